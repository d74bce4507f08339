//! Issue 16, item 2: a converging orbit is not a long cycle.
//!
//! The model: the paper's rotor out of contact (no eccentricity, an out-of-balance too small to
//! reach the ring), i.e. the linear damped oscillator `x'' + 2 nu1 x' + x = beta eta^2 cos(eta t)`
//! (and the same in `y` with `sin`). Its stroboscopic map has, in closed form, the multipliers
//! `exp((-nu1 ± i sqrt(1 - nu1^2)) T)` with `T = 2 pi / eta` (each a double pair, one per axis),
//! and its only attractor is the harmonic steady state, a fixed point of the map (period 1).
//! `nu1` and `eta` are chosen so that the multipliers have modulus 0.98 and sit at 3/8 of a turn:
//! a stable period-1 orbit just before a Neimark-Sacker point at a 3/8 resonance. Its transient
//! is a spiral that turns 3 times in 8 periods, so the lag-8 difference of the stroboscopic
//! points is about (1 - 0.98^8) / |0.98 e^{3i pi/4} - 1| ~ 1/12 of the lag-1 difference.

use jeffcott::analysis::MAX_WINDOWS;
use jeffcott::analysis::{
    bifurcation, detect_period, start_from, strobe_orbit, window_residuals, BifurcationOptions,
    PeriodTest, Periodicity,
};
use jeffcott::analysis::{section_crossings, section_crossings_hermite};
use jeffcott::global::{find_attractor, Attractor, AttractorOptions};
use jeffcott::hybrid::SimOptions;
use jeffcott::numeric::Direction;
use jeffcott::params::{Params, Preset};
use jeffcott::{JeffcottModel, State};

use std::f64::consts::TAU;

/// `(eta, nu1)` with multipliers `modulus · exp(± i 2 pi turn)`: `sqrt(1 - nu1^2) T = 2 pi turn`,
/// `nu1 T = -ln(modulus)`, `T = 2 pi / eta`.
fn resonant(modulus: f64, turn: f64) -> (f64, f64) {
    let a = -modulus.ln() / TAU; // nu1 / eta
    let eta = 1.0 / (turn * turn + a * a).sqrt();
    (eta, a * eta)
}

fn linear_params(modulus: f64, turn: f64, beta: f64) -> Params {
    let (eta, nu1) = resonant(modulus, turn);
    Params {
        eta,
        nu1,
        beta,
        ex: 0.0,
        ey: 0.0,
        ..Params::default()
    }
}

/// The harmonic steady state at the stroboscopic phase (t = 2 pi k / eta, phi0 = 0):
/// `x + i y = Z`, `x' + i y' = i eta Z`, `Z = beta eta^2 / (1 - eta^2 + 2 i nu1 eta)`.
fn steady_state(p: &Params) -> [f64; 4] {
    let b = p.beta * p.eta * p.eta;
    let (re, im) = (1.0 - p.eta * p.eta, 2.0 * p.nu1 * p.eta);
    let n = re * re + im * im;
    let (zr, zi) = (b * re / n, -b * im / n);
    [zr, zi, -p.eta * zi, p.eta * zr]
}

/// Betas for which the default `find_attractor` window (500 periods discarded, 64 recorded,
/// from rest) sees the spiral with amplitude between the lag-1 and the lag-p tolerance for
/// some p > 1 (before the fix it reported periods 2, 3, 8 and 8).
const BETAS: [f64; 4] = [0.005, 0.01, 0.02, 0.05];

#[test]
fn find_attractor_reports_the_fixed_point_not_a_long_cycle() {
    for beta in BETAS {
        let p = linear_params(0.98, 3.0 / 8.0, beta);
        let model = JeffcottModel::new(p).unwrap();
        let a = find_attractor(&model, &State::zeros(), &AttractorOptions::default()).unwrap();
        assert_eq!(a.period(), Some(1), "beta {beta}: {}", a.describe());
        assert!(a.describe().starts_with("period 1 "), "{}", a.describe());
        // The cycle point is the closed-form harmonic steady state (to within the test's
        // tolerance 1e-6: the lag-1 residual passed, so the spiral's radius is below 1e-6/1.8).
        let z = a.canonical().unwrap();
        for (c, want) in steady_state(&p).iter().enumerate() {
            assert!(
                (z[c] - want).abs() < 1e-6,
                "beta {beta}, component {c}: {} vs {want}",
                z[c]
            );
        }
        // The ring never moves: no contact.
        assert_eq!(a.stats.contacts_per_period, 0.0);
        // The first window (500 + 64 periods) is the one that passed a lag p > 1 with lag 1
        // failing; one more window shrinks the spiral by 0.98^564 ~ 1e-5, and lag 1 passes.
        assert_eq!(a.stats.periods_run, 2 * 564, "beta {beta}");
    }
}

#[test]
fn the_period_test_does_not_call_a_converging_spiral_a_cycle() {
    for beta in BETAS {
        let p = linear_params(0.98, 3.0 / 8.0, beta);
        let model = JeffcottModel::new(p).unwrap();
        let o = strobe_orbit(&model, &State::zeros(), 500, 64, &SimOptions::default()).unwrap();
        let got = o.period(&PeriodTest::default()).unwrap();
        assert!(got.period().is_none(), "beta {beta}: {got}");
    }
}

/// A synthetic spiral `x_i = A m^i (cos i phi, sin i phi)` about `c`, `phi = 2 pi turn`.
fn spiral(n: usize, a: f64, m: f64, turn: f64, c: [f64; 2]) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let r = a * m.powi(i as i32);
            let phi = TAU * turn * i as f64;
            [c[0] + r * phi.cos(), c[1] + r * phi.sin()]
        })
        .collect()
}

#[test]
fn synthetic_spirals_near_rational_angles_are_not_cycles() {
    let tol = 1e-6;
    // Moduli 0.97..0.99 at 3/8, 1/3, 2/5 and 1/2 of a turn (a flip), amplitudes spread over
    // the range where a lag p > 1 passes the tolerance before lag 1 does.
    for m in [0.97, 0.98, 0.99] {
        for turn in [3.0 / 8.0, 1.0 / 3.0, 2.0 / 5.0, 0.5] {
            for k in 0..40 {
                let a = tol * 10f64.powf(-1.5 + 0.05 * k as f64);
                for n in [32, 64, 150] {
                    let o = spiral(n, a, m, turn, [0.3, -0.2]);
                    let got = detect_period(&o, 16, tol).unwrap();
                    assert!(
                        got.period().is_none_or(|p| p == 1),
                        "m {m}, turn {turn}, A {a:e}, n {n}: {got}"
                    );
                }
            }
        }
    }
}
#[test]
fn the_not_converged_outcome_says_what_was_seen() {
    let p = linear_params(0.98, 3.0 / 8.0, 0.02);
    let model = JeffcottModel::new(p).unwrap();
    let o = strobe_orbit(&model, &State::zeros(), 500, 64, &SimOptions::default()).unwrap();
    let got = o.period(&PeriodTest::default()).unwrap();
    let Periodicity::NotConverged { passed, shrinking } = got else {
        panic!("expected not converged, got {got}");
    };
    // Lag 8 (3 turns of the spiral) passes, lag 1 shrinks by 0.98 per period.
    assert_eq!((passed.lag, shrinking.lag), (8, 1), "{got}");
    assert_eq!(passed.per_window().len(), MAX_WINDOWS);
    assert!(passed.per_window().iter().all(|&r| r <= 1e-6), "{got}");
    let w = shrinking.per_window();
    assert!(w.windows(2).all(|p| p[1] < p[0]), "{got}");
    // The windows start 47/3 periods apart on average (comparisons 1..64 cut at 16, 32, 48),
    // and the spiral shrinks by 0.98 per period.
    let per_window = (w[3] / w[0]).powf(1.0 / 3.0);
    let want = 0.98f64.powf(47.0 / 3.0);
    assert!((per_window - want).abs() < 0.03, "{per_window} vs {want}");
    assert!(got.to_string().starts_with("not converged: lag 8"), "{got}");
    assert!(
        got.to_string().contains("lag 1 (residual per window"),
        "{got}"
    );
    // The residuals are those of window_residuals on the same points.
    let states = o.states();
    assert_eq!(window_residuals(&states, 8).unwrap(), passed);
    assert_eq!(window_residuals(&states, 1).unwrap(), shrinking);
}

/// `n` samples cycling through `base` plus `a m^i` along (1, 1) (a transient decaying by `m`
/// per sample towards the cycle).
fn converging_cycle(base: &[[f64; 2]], n: usize, a: f64, m: f64) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let b = base[i % base.len()];
            let e = a * m.powi(i as i32);
            [b[0] + e, b[1] + e]
        })
        .collect()
}

#[test]
fn genuine_cycles_are_still_reported() {
    let tol = 1e-6;
    // An exact rotation by 3/8 of a turn: a genuine period-8 cycle.
    let o = spiral(64, 0.7, 1.0, 3.0 / 8.0, [0.0, 0.0]);
    assert_eq!(detect_period(&o, 16, tol).unwrap(), Periodicity::Period(8));
    // The same cycle with a fast-decaying transient of 0.5e-6 (multiplier 0.5): lag 8 passes
    // and shrinks, but the points have less than 1e-6 left to move; lags 1, 2, 4 are the
    // distances between cycle points, stationary.
    let base: Vec<[f64; 2]> = o[..8].to_vec();
    let o = converging_cycle(&base, 64, 0.5e-6, 0.5);
    assert_eq!(detect_period(&o, 16, tol).unwrap(), Periodicity::Period(8));
    // A period-2 cycle converging with multiplier 0.9 per sample, lag-2 residual 0.9 tol at
    // first: the remaining drift is (closed form) below 1e-7.
    let two = [[0.5, 0.1], [-0.4, 0.2]];
    let a = 0.9 * tol / (1.0 - 0.81);
    let o = converging_cycle(&two, 150, a, 0.9);
    assert_eq!(detect_period(&o, 16, tol).unwrap(), Periodicity::Period(2));
}

#[test]
fn a_cycle_still_drifting_by_more_than_the_tolerance_is_not_converged() {
    let tol = 1e-6;
    // Period 2 converging with multiplier 0.99 per sample: the lag-2 residual starts at
    // 0.9 tol (so lag 2 passes), but the last point is still a m^149 = 1e-5 (closed form) from
    // the cycle, ten tolerances.
    let two = [[0.5, 0.1], [-0.4, 0.2]];
    let a = 0.9 * tol / (1.0 - 0.99f64.powi(2));
    assert!(a * 0.99f64.powi(149) > 5.0 * tol);
    let o = converging_cycle(&two, 150, a, 0.99);
    let got = detect_period(&o, 16, tol).unwrap();
    match got {
        Periodicity::NotConverged { passed, shrinking } => {
            assert_eq!((passed.lag, shrinking.lag), (2, 2), "{got}");
            // The extrapolated drift is of the order of the true remaining distance.
            let drift = shrinking.extrapolated_drift();
            assert!(drift > 3.0 * tol && drift < 30.0 * tol, "{drift:e}");
        }
        other => panic!("expected not converged, got {other}"),
    }
}

#[test]
fn bifurcation_columns_and_changes_never_show_the_spurious_cycle() {
    let (eta0, _) = resonant(0.98, 3.0 / 8.0);
    let base = linear_params(0.98, 3.0 / 8.0, 0.02);
    let values = [eta0 - 2e-3, eta0 - 1e-3, eta0, eta0 + 1e-3, eta0 + 2e-3];
    let build = |eta: f64| JeffcottModel::new(Params { eta, ..base });
    let config = BifurcationOptions::default()
        .with_transient(500)
        .with_record(64);
    let d = bifurcation(&values, build, start_from(State::zeros()), &config, None).unwrap();
    for col in d.columns.iter().flatten() {
        assert!(
            col.periodicity.period().is_none_or(|p| p == 1),
            "eta {}: {}",
            col.value,
            col.periodicity
        );
    }
    for change in d.period_changes() {
        assert!(
            change.at_from.period().is_none_or(|p| p == 1)
                && change.at_to.period().is_none_or(|p| p == 1),
            "{change:?}"
        );
    }
}

#[test]
fn a_not_converged_attractor_round_trips_through_its_record() {
    let p = linear_params(0.98, 3.0 / 8.0, 0.02);
    let model = JeffcottModel::new(p).unwrap();
    // One window only: the run stops not converged.
    let config = AttractorOptions::default().with_max_transient(500);
    let a = find_attractor(&model, &State::zeros(), &config).unwrap();
    assert!(
        matches!(a.periodicity, Periodicity::NotConverged { .. }),
        "{}",
        a.describe()
    );
    assert!(a.cycle.is_empty());
    assert!(
        a.describe().starts_with("not converged: lag 8"),
        "{}",
        a.describe()
    );
    let json = serde_json::to_value(&a).unwrap();
    assert!(json["periodicity"].get("NotConverged").is_some(), "{json}");
    let back: Attractor = serde_json::from_str(&json.to_string()).unwrap();
    assert_eq!(back, a);
    assert!(back.periodicity.agrees_with(&a.periodicity));
}

/// The paper's model (Fig. 8a set, no preload) just below the Neimark-Sacker point of its
/// period-3 orbit at eta = 4.8567 (docs/global.md, from the continuation's Floquet
/// multipliers): from rest, after a bifurcation diagram's default 300 + 150 periods, the
/// period-3 orbit is still converging and its transient nearly closes after 5 turns of the
/// period-3 map, so lag 15 passed while lag 3 did not (before the fix: `period 15`).
#[test]
fn the_papers_period_3_orbit_near_its_neimark_sacker_point_is_not_period_15() {
    let model = JeffcottModel::new(Preset::Fig8a.params().with_eta(4.853)).unwrap();
    let y0 = model.state_at([0.0, 0.0], [0.0, 0.0]).unwrap();
    let config = BifurcationOptions::default();
    let o = strobe_orbit(&model, &y0, config.transient, config.record, &config.opts).unwrap();
    let got = o.period(&config.period_test).unwrap();
    assert!(got.period().is_none_or(|p| p == 3), "{got}");
    // Given the time, the run settles on the period-3 orbit.
    let a = find_attractor(&model, &y0, &AttractorOptions::default()).unwrap();
    assert_eq!(a.period(), Some(3), "{}", a.describe());
}

/// Issue 16, item 5 (Poincaré part). The section `h = -1` below `x = 0.3`, `h = 1e-10` from
/// there on (a threshold with very unequal sides) along `x = t`, sampled at `t = 0, 1`: the one
/// crossing is at `t = 0.3` exactly. The old private Illinois copy (60 steps, no bisection
/// fallback) stalled near `t = 1` and returned its smallest-|h| point there as located.
#[test]
fn hermite_crossing_of_a_lopsided_threshold_is_where_h_changes_sign() {
    let times = [0.0, 1.0];
    let states = [[0.0], [1.0]];
    let derivs = [[1.0], [1.0]];
    let h = |_: f64, x: &[f64]| if x[0] < 0.3 { -1.0 } else { 1e-10 };
    let c = section_crossings_hermite(&times, &states, &derivs, h, Direction::Rising).unwrap();
    assert_eq!(c.len(), 1);
    assert!((c[0].t - 0.3).abs() < 1e-12, "{:?}", c[0]);
    assert!((c[0].state[0] - 0.3).abs() < 1e-12, "{:?}", c[0]);
    // The crossing carries its bracket, which holds the located time, and is converged.
    let (lo, hi) = c[0].bracket;
    assert!(c[0].converged, "{:?}", c[0]);
    assert!(
        lo <= c[0].t && c[0].t <= hi && hi - lo <= 1e-13,
        "{:?}",
        c[0]
    );
    assert!(lo < 0.3 && hi >= 0.3, "{:?}", c[0]);
}

/// A section function that is NaN on the interpolant between the samples (finite at both):
/// the search cannot locate the crossing, which is reported flagged, with its bracket.
#[test]
fn an_unlocatable_crossing_is_flagged_not_located() {
    let times = [0.0, 1.0];
    let states = [[-1.0], [1.0]];
    let derivs = [[2.0], [2.0]];
    let h = |_: f64, x: &[f64]| if x[0].abs() < 0.9 { f64::NAN } else { x[0] };
    let c = section_crossings_hermite(&times, &states, &derivs, h, Direction::Rising).unwrap();
    assert_eq!(c.len(), 1);
    assert!(!c[0].converged, "{:?}", c[0]);
    let (lo, hi) = c[0].bracket;
    assert!(
        0.0 <= lo && lo <= c[0].t && c[0].t <= hi && hi <= 1.0,
        "{:?}",
        c[0]
    );
    // A smooth section is located and converged: x = t - 0.5 crosses 0 at t = 0.5 exactly.
    let h = |_: f64, x: &[f64]| x[0];
    let c = section_crossings_hermite(&times, &states, &derivs, h, Direction::Rising).unwrap();
    assert!(c[0].converged && (c[0].t - 0.5).abs() < 1e-14, "{:?}", c[0]);
    let lin = section_crossings(&times, &states, h, Direction::Rising).unwrap();
    assert!(
        lin[0].converged && lin[0].bracket == (lin[0].t, lin[0].t),
        "{:?}",
        lin[0]
    );
}

/// A small deterministic generator of noise in [-1, 1] (fixed seeds).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// Converged cycles with noise up to 0.4 tol per component (lag differences up to 0.8 tol,
/// stationary): the convergence checks must not mistake the noise for a trend, over many
/// seeds and record lengths.
#[test]
fn noisy_converged_cycles_stay_periodic() {
    let tol = 1e-6;
    let bases: [&[[f64; 2]]; 4] = [
        &[[0.3, -0.2]],
        &[[0.5, 0.1], [-0.4, 0.2]],
        &[[0.1, 0.0], [0.7, 0.3], [0.4, -0.6]],
        &[
            [0.9, 0.0],
            [0.2, 0.1],
            [0.8, 0.05],
            [0.25, 0.1],
            [0.6, 0.6],
            [0.0, 0.3],
        ],
    ];
    for base in bases {
        for n in [32, 64, 150] {
            for seed in 0..300u64 {
                let mut rng = Lcg(seed * 7919 + n as u64);
                let o: Vec<[f64; 2]> = (0..n)
                    .map(|i| {
                        let b = base[i % base.len()];
                        [b[0] + 0.4 * tol * rng.next(), b[1] + 0.4 * tol * rng.next()]
                    })
                    .collect();
                let got = detect_period(&o, 16, tol).unwrap();
                assert_eq!(
                    got,
                    Periodicity::Period(base.len()),
                    "n {n}, seed {seed}: {got}"
                );
            }
        }
    }
}
