//! Every simulation-level analysis on models of the user's own, built by closures: stroboscopic
//! orbits, bifurcation diagrams (reset and carried state), phase portraits with Poincaré
//! sections, and the period-change locator, each checked against a closed form.

use std::f64::consts::{PI, TAU};

use jeffcott::analysis::{
    bifurcation, locate_period_change, phase_portrait, start_from, strobe_orbit,
    BifurcationOptions, LocatorOptions, OrbitError, PeriodTest, Periodicity, SweepOptions,
};
use jeffcott::hybrid::{Flow, ModelError, NoExactModes, RotorModel, SimErrorKind, SimOptions};
use jeffcott::nalgebra::{SVector, U2};
use jeffcott::numeric::Direction;

type S = SVector<f64, 2>;

/// $x'' + 2\zeta x' + x + k (x - 1)_+ = A \cos\omega t$: a forced oscillator meeting a spring
/// stop at $x = 1$.
struct ForcedStop {
    amp: f64,
    omega: f64,
    zeta: f64,
    k: f64,
}

impl ForcedStop {
    fn new(amp: f64) -> Result<Self, String> {
        if !(amp.is_finite() && amp >= 0.0) {
            return Err(format!("amplitude {amp}: must be finite and >= 0"));
        }
        Ok(Self {
            amp,
            omega: 0.8,
            zeta: 0.1,
            k: 20.0,
        })
    }

    /// Steady state of the linear (no contact) motion at the stroboscopic times $t_k = kP$.
    fn linear_strobe_state(&self) -> S {
        let (w, z) = (self.omega, self.zeta);
        let x = self.amp / ((1.0 - w * w).powi(2) + (2.0 * z * w).powi(2)).sqrt();
        let delta = (2.0 * z * w).atan2(1.0 - w * w);
        S::new(x * delta.cos(), x * w * delta.sin())
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Mode {
    Free,
    Stop,
}

impl RotorModel for ForcedStop {
    type Dim = U2;
    type Mode = Mode;
    type Segment = NoExactModes;
    type Cache = ();

    fn dim(&self) -> U2 {
        U2
    }
    fn new_cache(&self) {}

    fn initial_mode(&self, _t: f64, y: &S) -> Result<Mode, ModelError> {
        Ok(if y[0] < 1.0 { Mode::Free } else { Mode::Stop })
    }
    fn flow(&self, _mode: Mode) -> Flow {
        Flow::Integrated
    }
    fn rhs(&self, mode: Mode, t: f64, y: &S, dy: &mut S, _cache: &()) {
        let stop = if mode == Mode::Stop {
            self.k * (y[0] - 1.0)
        } else {
            0.0
        };
        let f = self.amp * (self.omega * t).cos();
        *dy = S::new(y[1], f - 2.0 * self.zeta * y[1] - y[0] - stop);
    }
    fn guard_count(&self, _mode: Mode) -> usize {
        1
    }
    fn guard_direction(&self, mode: Mode, _i: usize) -> Direction {
        match mode {
            Mode::Free => Direction::Rising,
            Mode::Stop => Direction::Falling,
        }
    }
    fn guard_value(&self, _mode: Mode, _i: usize, _t: f64, y: &S, _cache: &()) -> f64 {
        y[0] - 1.0
    }
    fn guard_label(&self, mode: Mode, _i: usize) -> &'static str {
        match mode {
            Mode::Free => "hit",
            Mode::Stop => "leave",
        }
    }
    fn transition(&self, mode: Mode, _g: usize, _t: f64, _y: &mut S) -> Result<Mode, ModelError> {
        Ok(match mode {
            Mode::Free => Mode::Stop,
            Mode::Stop => Mode::Free,
        })
    }
    fn start_segment(&self, _mode: Mode, _t: f64, _y: &S) -> NoExactModes {
        NoExactModes
    }
    fn mode_label(&self, mode: Mode) -> u8 {
        match mode {
            Mode::Free => 1,
            Mode::Stop => 2,
        }
    }
    fn forcing_period(&self) -> f64 {
        TAU / self.omega
    }
}

/// The unforced undamped oscillator $x'' = -x$ sampled every `period`: the stroboscopic map is
/// a rotation by the angle `period`, of period `q` exactly when `period = 2 pi p / q`.
struct Rotation {
    period: f64,
}

impl RotorModel for Rotation {
    type Dim = U2;
    type Mode = ();
    type Segment = NoExactModes;
    type Cache = ();

    fn dim(&self) -> U2 {
        U2
    }
    fn new_cache(&self) {}

    fn initial_mode(&self, _t: f64, _y: &S) -> Result<(), ModelError> {
        Ok(())
    }
    fn flow(&self, _mode: ()) -> Flow {
        Flow::Integrated
    }
    fn rhs(&self, _mode: (), _t: f64, y: &S, dy: &mut S, _cache: &()) {
        *dy = S::new(y[1], -y[0]);
    }
    fn guard_count(&self, _mode: ()) -> usize {
        0
    }
    fn guard_direction(&self, _mode: (), _i: usize) -> Direction {
        Direction::Either
    }
    fn guard_value(&self, _mode: (), _i: usize, _t: f64, _y: &S, _cache: &()) -> f64 {
        1.0
    }
    fn guard_label(&self, _mode: (), _i: usize) -> &'static str {
        "none"
    }
    fn transition(&self, _mode: (), _g: usize, _t: f64, _y: &mut S) -> Result<(), ModelError> {
        Ok(())
    }
    fn start_segment(&self, _mode: (), _t: f64, _y: &S) -> NoExactModes {
        NoExactModes
    }
    fn mode_label(&self, _mode: ()) -> u8 {
        1
    }
    fn forcing_period(&self) -> f64 {
        self.period
    }
}

fn tight() -> SimOptions {
    SimOptions::default().with_rtol(1e-12).with_atol(1e-14)
}

#[test]
fn bifurcation_of_a_user_model_matches_the_linear_steady_state_below_contact() {
    // Amplitudes whose steady amplitude A / |1 - w^2 + 2i zeta w| stays below the stop at 1.
    let amps = [0.1, 0.2, 0.3];
    let config = BifurcationOptions::default()
        .with_transient(60)
        .with_record(6)
        .with_opts(tight());
    let diagram = bifurcation(
        &amps,
        ForcedStop::new,
        start_from(S::zeros()),
        &config,
        None,
    )
    .unwrap();
    for (a, col) in amps.iter().zip(&diagram.columns) {
        let col = col.as_ref().unwrap();
        assert_eq!(col.value, *a);
        assert_eq!(col.periodicity, Periodicity::Period(1));
        assert_eq!(col.orbit.stats.transitions, 0);
        let expected = ForcedStop::new(*a).unwrap().linear_strobe_state();
        for p in &col.orbit.points {
            // The transient decays like exp(-zeta t) = exp(-0.1 * 60 * 7.85) ~ 1e-21.
            assert!(
                (p.y - expected).norm() < 1e-9,
                "A = {a}: {} vs {expected}",
                p.y
            );
        }
    }
}

#[test]
fn a_user_model_sweep_carries_state_fails_per_value_and_is_thread_independent() {
    // Amplitudes with contact (steady amplitude above 1) and an invalid one.
    let amps = [0.5, 0.6, -1.0, 0.7, 0.8];
    let run = |sweep: SweepOptions| {
        let config = BifurcationOptions::default()
            .with_transient(40)
            .with_record(8)
            .with_sweep(sweep);
        bifurcation(
            &amps,
            ForcedStop::new,
            start_from(S::zeros()),
            &config,
            None,
        )
        .unwrap()
    };
    let bits = |b: &jeffcott::analysis::Bifurcation<U2, String>| -> Vec<Vec<u64>> {
        b.columns
            .iter()
            .map(|c| match c {
                Ok(col) => col
                    .orbit
                    .points
                    .iter()
                    .flat_map(|p| p.y.iter().map(|v| v.to_bits()))
                    .collect(),
                Err(_) => vec![u64::MAX],
            })
            .collect()
    };
    for mode in [SweepOptions::reset(), SweepOptions::carry_over(1)] {
        let one = run(mode.with_threads(1));
        let two = run(mode.with_threads(2));
        assert_eq!(bits(&one), bits(&two), "{mode:?}");
        let failures = one.failures();
        assert_eq!(failures.len(), 1);
        assert_eq!(failures[0].value, -1.0);
        assert!(matches!(failures[0].error, OrbitError::Build(m) if m.contains("amplitude")));
        let col = |i: usize| one.columns[i].as_ref().unwrap();
        assert!(col(0).orbit.stats.transitions > 0, "contact expected");
        // Carried state: value 1 starts where value 0 ended; after the failure, from reset.
        let carried = mode != SweepOptions::reset();
        assert_eq!(col(1).from_reset, !carried);
        assert!(col(3).from_reset);
        if carried {
            let model = ForcedStop::new(0.6).unwrap();
            let direct = strobe_orbit(&model, &col(0).orbit.last, 40, 8, &config_opts()).unwrap();
            assert_eq!(direct.points, col(1).orbit.points);
        }
    }
}

fn config_opts() -> SimOptions {
    BifurcationOptions::default().opts
}

#[test]
fn poincare_section_of_a_user_models_phase_portrait_finds_its_maxima() {
    // A contacting steady orbit: sample it densely and cut it at x' = 0 from above (the
    // maxima of x). The orbit has period 1, so the set of maxima repeats every period (a flip
    // mode of multiplier ~ -0.8 decays first: 200 periods bring it below 1e-14).
    let model = ForcedStop::new(0.6).unwrap();
    let p = model.forcing_period();
    let (n0, n1) = (200.0, 206.0);
    let pp = phase_portrait(&model, &S::zeros(), n0 * p, n1 * p, p / 400.0, &tight()).unwrap();
    let window: Vec<_> = pp.events.iter().filter(|e| e.t > n0 * p).collect();
    assert!(window.len() >= 6, "{} events", window.len());
    let maxima = pp.crossings(|_, y| y[1], Direction::Falling).unwrap();
    let per_period = maxima.len() / 6;
    assert!(per_period >= 1 && maxima.len() % 6 == 0, "{}", maxima.len());
    for c in &maxima {
        // On the section, and a maximum of the sampled x within the Hermite error.
        assert!(c.state[1].abs() < 1e-9, "{c:?}");
        let near = pp
            .samples
            .iter()
            .filter(|s| (s.t - c.t).abs() < p / 200.0)
            .map(|s| s.y[0])
            .fold(f64::NEG_INFINITY, f64::max);
        assert!(c.state[0] >= near - 1e-9, "{} < {near}", c.state[0]);
    }
    for w in maxima.windows(per_period + 1) {
        let (a, b) = (&w[0], &w[per_period]);
        // The samples repeat with the period too, so the interpolation error does as well.
        assert!((b.t - a.t - p).abs() < 1e-9, "{} vs {p}", b.t - a.t);
        assert!((b.state[0] - a.state[0]).abs() < 1e-9);
    }
}

#[test]
fn locator_finds_a_rational_rotation_of_a_user_model() {
    // Sampling x'' = -x every P rotates the phase by P: period 2 at P = pi exactly, not
    // periodic (up to 16) just below it. The change is at pi.
    let config = LocatorOptions::default()
        .with_transient(1)
        .with_record(40)
        .with_resolution(1e-4)
        .with_opts(tight())
        .with_period_test(PeriodTest::default());
    let build = |period: f64| -> Result<Rotation, String> { Ok(Rotation { period }) };
    let start = start_from(S::new(1.0, 0.0));
    let c = locate_period_change(PI, 2.5, build, start.clone(), &config).unwrap();
    assert_eq!(c.bracket.at_from, Periodicity::Period(2));
    assert_eq!(c.bracket.at_to, Periodicity::NotPeriodic { up_to: 16 });
    assert_eq!(c.bracket.from, PI);
    assert!((c.bracket.from - c.bracket.to).abs() <= 1e-4);
    assert!((c.value() - PI).abs() <= 1e-4, "{c:?}");
    // Same periodicity at both ends (both irrational rotations): nothing to locate.
    let e = locate_period_change(2.5, 2.6, build, start.clone(), &config).unwrap_err();
    assert!(matches!(e, OrbitError::NoChange { .. }), "{e}");
    // A builder error is reported as such.
    let failing = |_: f64| -> Result<Rotation, String> { Err("no model".into()) };
    let e = locate_period_change(PI, 2.5, failing, start, &config).unwrap_err();
    assert!(
        matches!(e, OrbitError::Build(ref m) if m == "no model"),
        "{e}"
    );
}

#[test]
fn strobe_orbit_rejects_empty_and_overflowing_ranges() {
    let model = Rotation { period: 1.0 };
    let y0 = S::new(1.0, 0.0);
    let opts = SimOptions::default();
    for (transient, record) in [(5, 0), (u64::MAX, 1), (1, u64::MAX)] {
        let e = strobe_orbit(&model, &y0, transient, record, &opts).unwrap_err();
        assert!(
            matches!(
                e.kind,
                SimErrorKind::InvalidOption {
                    field: "record",
                    ..
                }
            ),
            "{transient} {record}: {e}"
        );
    }
    let o = strobe_orbit(&model, &y0, 3, 2, &opts).unwrap();
    assert_eq!(o.points.iter().map(|p| p.k).collect::<Vec<_>>(), [4, 5]);
    assert_eq!(o.last, o.points[1].y);
}

/// The two strobe conventions name the same points: `strobe_range(y0, t + 1, t + r)` (the raw
/// index range) and `strobe_orbit(model, y0, t, r)` (the analyses' `(transient, record)`), as
/// `JeffcottModel::strobe_range` documents. Both are one run of the driver with the same plan,
/// so the points agree bitwise.
#[test]
fn strobe_range_and_strobe_orbit_name_the_same_points() {
    use jeffcott::paper::{JeffcottModel, State};
    use jeffcott::params::Preset;
    let model = JeffcottModel::new(Preset::Fig8b.params().with_eta(2.0)).unwrap();
    let (t, r) = (20, 5);
    let opts = SimOptions::default();
    let (range, _) = model
        .strobe_range(&State::zeros(), t + 1, t + r, &opts)
        .unwrap();
    let orbit = strobe_orbit(&model, &State::zeros(), t, r, &opts).unwrap();
    assert_eq!(range.strobe.len(), r as usize);
    assert_eq!(orbit.points.len(), r as usize);
    for (a, b) in range.strobe.iter().zip(&orbit.points) {
        assert_eq!(a.k, b.k);
        assert_eq!(a.t.to_bits(), b.t.to_bits());
        assert!(a
            .y
            .iter()
            .zip(b.y.iter())
            .all(|(u, v)| u.to_bits() == v.to_bits()));
    }
    assert_eq!(orbit.points[0].k, t + 1);
}
