//! The same analyses on the paper's model in its non-dimensional units (gap 1, time
//! $\tau = \omega_n t$) and on the same physical rig in SI units (metres, seconds, a
//! [`SmoothRotor`] Jeffcott rotor of 10 kg on 1e6 N/m with a ring gap of 0.1 mm, on a
//! [`RingedRotor`]): the orbits agree after scaling, the multipliers and the periods are the
//! same. The conversion is that of docs/model.md: lengths $\gamma x$, velocities
//! $\gamma\omega_n x^\prime$, time $\tau/\omega_n$, ring unit stiffness $K k_r$, damping
//! $2\nu\sqrt{k_r M}$, preload $D\gamma$, unbalance acceleration $\beta\gamma\Omega^2$.
//!
//! The non-dimensional side is the paper's [`JeffcottModel`] (closed-form free flight,
//! analytic Jacobians); the SI side integrates its free flight and differences its field, so
//! the two agree to the integration's and the differences' errors, not bitwise.
//!
//! Special points: the flip of Fig. 8b's period-1 orbit and the grazing of its period-2 orbit
//! by `stability::locate_loss`, at the same parameter on both sides.
//! TODO(issue 17): the pseudo-arclength continuation's special points (folds) on both sides.

use jeffcott::analysis::{bifurcation, start_from, strobe_orbit, BifurcationOptions, PeriodTest};
use jeffcott::global::{find_attractor, Attractor, AttractorOptions, MatchOptions};
use jeffcott::hybrid::SimOptions;
use jeffcott::nalgebra::{SVector, Vector2, U6};
use jeffcott::paper::{JeffcottModel, State};
use jeffcott::params::{Params, Preset};
use jeffcott::ring::{Kinematics, RingAxis, SnubberRing};
use jeffcott::rotor::{RingedRotor, SmoothRotor};
use jeffcott::stability::{
    locate_loss, periodic_orbit, LossOptions, Multiplier, OrbitOptions, PeriodicOrbit, SpecialKind,
    StroboscopicMap,
};

/// Rotor mass, kg.
const MASS: f64 = 10.0;
/// Rotor stiffness, N/m.
const STIFFNESS: f64 = 1e6;
/// Radial clearance, m.
const GAP: f64 = 1e-4;

fn omega_n() -> f64 {
    (STIFFNESS / MASS).sqrt()
}

/// The SI state of a non-dimensional one: `[x, y, x', y', x_s, y_s]` in m and m/s.
fn to_si(y: &[f64]) -> SVector<f64, 6> {
    let w = omega_n();
    SVector::from_fn(|i, _| y[i] * if i == 2 || i == 3 { GAP * w } else { GAP })
}

/// The non-dimensional state of an SI one.
fn to_nd(y: &[f64]) -> Vec<f64> {
    let w = omega_n();
    y.iter()
        .enumerate()
        .map(|(i, v)| v / if i == 2 || i == 3 { GAP * w } else { GAP })
        .collect()
}

/// A Jeffcott rotor in SI units: `[x, y, x', y', x_s, y_s]`.
struct SiRotor {
    /// Damping, N s/m.
    damping: f64,
    /// Rest position relative to the ring's centre, m.
    rest: [f64; 2],
    /// Unbalance `m rho / M`, m.
    unbalance: f64,
    /// Spin speed, rad/s.
    spin: f64,
    /// Initial phase, rad.
    phase: f64,
    /// The state's scale if the rotor gives it (else `RingedRotor` derives it).
    scale: Option<SVector<f64, 6>>,
}

impl SmoothRotor for SiRotor {
    type Dim = U6;
    fn dim(&self) -> U6 {
        U6
    }
    fn rhs(&self, t: f64, y: &SVector<f64, 6>, dy: &mut SVector<f64, 6>) {
        let b = self.unbalance * self.spin * self.spin;
        let (sin, cos) = (self.phase + self.spin * t).sin_cos();
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = b * cos - (self.damping * y[2] + STIFFNESS * (y[0] - self.rest[0])) / MASS;
        dy[3] = b * sin - (self.damping * y[3] + STIFFNESS * (y[1] - self.rest[1])) / MASS;
    }
    fn station(&self, y: &SVector<f64, 6>) -> Kinematics {
        Kinematics::new([y[0], y[1]], [y[2], y[3]])
    }
    fn add_station_force(&self, _y: &SVector<f64, 6>, f: &Vector2<f64>, dy: &mut SVector<f64, 6>) {
        dy[2] += f.x / MASS;
        dy[3] += f.y / MASS;
    }
    fn ring_slots(&self) -> [usize; 2] {
        [4, 5]
    }
    fn forcing_period(&self) -> f64 {
        std::f64::consts::TAU / self.spin
    }
    fn state_scale(&self) -> Option<SVector<f64, 6>> {
        self.scale
    }
}

/// The rig of the non-dimensional `p` in SI units: its ring's force in newtons (unit stiffness
/// `K k_r`, a unit's damping force `c_s s'` with `c_s = 2 nu2 sqrt(k_r M)`, i.e. the ring's
/// `damping` is `c_s / 2`), lengths in metres.
fn si_model(p: &Params) -> RingedRotor<SiRotor> {
    si_model_with(p, None)
}

/// [`si_model`] with the scale of the paper's units (the gap, the gap times `omega_n`) given by
/// the rotor.
fn si_model_in_paper_scale(p: &Params) -> RingedRotor<SiRotor> {
    si_model_with(p, Some(to_si(&[1.0; 6])))
}

fn si_model_with(p: &Params, scale: Option<SVector<f64, 6>>) -> RingedRotor<SiRotor> {
    let crit = 2.0 * (STIFFNESS * MASS).sqrt();
    let rotor = SiRotor {
        damping: p.nu1 * crit,
        rest: [p.ex * GAP, p.ey * GAP],
        unbalance: p.beta * GAP,
        spin: p.eta * omega_n(),
        phase: p.phi0,
        scale,
    };
    let ring = SnubberRing::new(
        RingAxis::new(p.kx * STIFFNESS, p.dx * GAP),
        RingAxis::new(p.ky * STIFFNESS, p.dy * GAP),
        0.5 * p.nu2 * crit,
        GAP,
    )
    .unwrap();
    RingedRotor::new(rotor, ring).unwrap()
}

/// The non-dimensional state after `n` forcing periods from rest.
fn settled(model: &JeffcottModel, n: u64) -> State {
    StroboscopicMap::new(model, n, SimOptions::default())
        .unwrap()
        .advance(&State::zeros())
        .unwrap()
        .y
}

/// Largest difference, in units of the gap (velocities of `gap * omega_n`), between a
/// non-dimensional state and an SI one.
fn state_gap(nd: &[f64], si: &[f64]) -> f64 {
    nd.iter()
        .zip(to_nd(si))
        .fold(0.0, |m, (a, b)| f64::max(m, (a - b).abs()))
}

fn multiplier_gap(a: &[Multiplier], b: &[Multiplier]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).fold(0.0, |m, (u, v)| {
        f64::max(m, (u.re - v.re).hypot(u.im - v.im))
    })
}

#[test]
fn periodic_orbits_and_multipliers_agree() {
    // Fig. 8b (preload 0.1): the period-1 orbit at eta = 2 and the period-2 orbit at eta = 3.
    for (eta, period) in [(2.0, 1), (3.0, 2)] {
        let p = Preset::Fig8b.params().with_eta(eta);
        let nd = JeffcottModel::new(p).unwrap();
        let si = si_model(&p);
        let start = settled(&nd, 30);
        let opts = OrbitOptions::default();
        let a = periodic_orbit(&nd, &start, period, &opts).unwrap();
        let b = periodic_orbit(&si, &to_si(start.as_slice()), period, &opts).unwrap();
        let (dz, dm) = (
            state_gap(a.point.as_slice(), b.point.as_slice()),
            multiplier_gap(&a.multipliers, &b.multipliers),
        );
        eprintln!(
            "eta {eta}: point {dz:.1e} gap, multipliers {dm:.1e} (|m| = {:.4}), \
             {} / {} Newton iterations, minimal periods {} / {}",
            a.spectral_radius(),
            a.iterations,
            b.iterations,
            a.minimal_period,
            b.minimal_period,
        );
        assert!(dz < 1e-8, "eta {eta}: points differ by {dz:e} gap");
        assert!(dm < 1e-8, "eta {eta}: multipliers differ by {dm:e}");
        assert_eq!(a.minimal_period, period);
        assert_eq!(b.minimal_period, period);
        assert_eq!(a.margins.structure, b.margins.structure);
        // The crossing margins are measured in units of the scale: with the derived scale
        // (velocities in units of the gap times the forcing frequency, not omega_n) they are
        // close to the paper's, with the paper's scale given by the rotor they are the same.
        let c = periodic_orbit(
            &si_model_in_paper_scale(&p),
            &to_si(start.as_slice()),
            period,
            &opts,
        )
        .unwrap();
        let margins = |o: &PeriodicOrbit<_>| o.events.iter().map(|e| e.margin).collect::<Vec<_>>();
        let (ma, mb, mc) = (margins(&a), margins(&b), margins(&c));
        eprintln!("eta {eta}: margins {ma:.4?} / derived scale {mb:.4?} / paper's scale {mc:.4?}");
        assert_eq!(a.grazing, b.grazing);
        for ((x, y), z) in ma.iter().zip(&mb).zip(&mc) {
            assert!(
                (x - z).abs() < 1e-6 && y / x < 2.0 && x / y < 2.0,
                "{x} {y} {z}"
            );
        }
    }
}

#[test]
fn a_converging_orbit_is_not_a_cycle_in_si_units_either() {
    // Shortly after a start from rest the period-1 orbit at eta = 2 is still converging: in
    // the paper's units its points still move by more than the period test's 1e-6 gap, in SI
    // units by less than 1e-6 m (1e-2 gap), which an absolute tolerance would call a cycle.
    let p = Preset::Fig8b.params().with_eta(2.0);
    let nd = JeffcottModel::new(p).unwrap();
    let si = si_model(&p);
    let test = PeriodTest::default();
    let opts = SimOptions::default();
    for transient in [10, 20, 40, 300] {
        let a = strobe_orbit(&nd, &State::zeros(), transient, 32, &opts).unwrap();
        let b = strobe_orbit(&si, &SVector::zeros(), transient, 32, &opts).unwrap();
        let (pa, pb) = (a.period(&test).unwrap(), b.period(&test).unwrap());
        eprintln!("transient {transient}: {pa} / {pb}");
        assert!(pa.agrees_with(&pb), "transient {transient}: {pa} / {pb}");
        for (u, v) in a.points.iter().zip(&b.points) {
            assert!((u.t - v.t * omega_n()).abs() <= 1e-12 * u.t, "strobe times");
            let d = state_gap(u.y.as_slice(), v.y.as_slice());
            assert!(
                d < 1e-8,
                "transient {transient}: points differ by {d:e} gap"
            );
        }
    }
}

#[test]
fn attractors_agree() {
    // Period 1 (eta = 2), period 2 (eta = 3) of Fig. 8b, from rest.
    let config = AttractorOptions::default()
        .with_transient(100)
        .with_record(32);
    for (eta, period) in [(2.0, 1), (3.0, 2)] {
        let p = Preset::Fig8b.params().with_eta(eta);
        let nd = JeffcottModel::new(p).unwrap();
        let si = si_model(&p);
        let a = find_attractor(&nd, &State::zeros(), &config).unwrap();
        let b = find_attractor(&si, &SVector::zeros(), &config).unwrap();
        eprintln!("eta {eta}: {} / {}", a.describe(), b.describe());
        assert_eq!(a.period(), Some(period));
        assert_eq!(b.period(), Some(period));
        assert_eq!(a.stats.periods_run, b.stats.periods_run);
        let d = state_gap(a.canonical().unwrap(), b.canonical().unwrap());
        assert!(d < 1e-8, "eta {eta}: canonical points differ by {d:e} gap");
        assert_eq!(a.stats.contacts_per_period, b.stats.contacts_per_period);
        // The SI attractor keeps its model's scale through its record; the paper's (scale 1)
        // leaves it out.
        assert!(a.scale.is_empty() && b.scale.len() == 6);
        let back: Attractor = serde_json::from_str(&serde_json::to_string(&b).unwrap()).unwrap();
        assert_eq!(back, b);
        assert!(!serde_json::to_string(&a).unwrap().contains("scale"));
    }
}

#[test]
fn attractors_match_alike() {
    // The period-2 orbits at eta = 3 and 3.005 differ by about 7e-3 gap: distinct attractors
    // at the default matching tolerance (1e-3 of the state's scale), in both units; each
    // matches the same run's attractor.
    let config = AttractorOptions::default()
        .with_transient(100)
        .with_record(32);
    let tol = MatchOptions::default();
    let run = |eta: f64| {
        let p = Preset::Fig8b.params().with_eta(eta);
        let nd = JeffcottModel::new(p).unwrap();
        let a = find_attractor(&nd, &State::zeros(), &config).unwrap();
        let b = find_attractor(&si_model(&p), &SVector::zeros(), &config).unwrap();
        (a, b)
    };
    let (a1, b1) = run(3.0);
    let (a2, b2) = run(3.005);
    let (z1, z2) = (a1.canonical().unwrap(), a2.canonical().unwrap());
    let d = z1
        .iter()
        .zip(z2)
        .fold(0.0, |m, (u, v)| f64::max(m, (u - v).abs()));
    let (w1, w2) = (b1.canonical().unwrap(), b2.canonical().unwrap());
    let dsi = w1
        .iter()
        .zip(w2)
        .fold(0.0, |m, (u, v)| f64::max(m, (u - v).abs()));
    eprintln!("eta 3 and 3.005: canonical points {d:.1e} gap apart; SI {dsi:.1e}");
    assert!(!a1.matches(&a2, &tol), "non-dimensional");
    assert!(!b1.matches(&b2, &tol), "SI: distinct attractors matched");
    assert!(a1.matches(&a1.clone(), &tol) && b1.matches(&b1.clone(), &tol));
}

#[test]
fn a_bifurcation_slice_agrees() {
    let base = Preset::Fig8b.params();
    let values = [2.0, 2.5, 3.0, 3.5, 4.0, 4.6];
    let config = BifurcationOptions::default()
        .with_transient(300)
        .with_record(32);
    let nd = bifurcation(
        &values,
        |eta| JeffcottModel::new(base.with_eta(eta)),
        start_from(State::zeros()),
        &config,
        None,
    )
    .unwrap();
    let si = bifurcation(
        &values,
        |eta| Ok::<_, String>(si_model(&base.with_eta(eta))),
        start_from(SVector::zeros()),
        &config,
        None,
    )
    .unwrap();
    for (i, eta) in values.iter().enumerate() {
        let a = nd.columns[i].as_ref().unwrap();
        let b = si.columns[i].as_ref().unwrap();
        eprintln!("eta {eta}: {} / {}", a.periodicity, b.periodicity);
        assert!(
            a.periodicity.agrees_with(&b.periodicity),
            "eta {eta}: {} / {}",
            a.periodicity,
            b.periodicity
        );
        if a.periodicity.period().is_some() {
            for (u, v) in a.orbit.points.iter().zip(&b.orbit.points) {
                let d = state_gap(u.y.as_slice(), v.y.as_slice());
                assert!(d < 1e-8, "eta {eta}: points differ by {d:e} gap");
            }
        }
    }
}

#[test]
fn special_points_agree() {
    // The period-1 orbit of Fig. 8b flips near eta = 2.2; the period-2 orbit grazes the
    // preload near 3.1028. eta is the family's parameter on both sides.
    let base = Preset::Fig8b.params();
    let opts = LossOptions::default();
    for (from, to, period, kind) in [
        (2.0, 2.3, 1, SpecialKind::Flip),
        (3.0, 3.2, 2, SpecialKind::Grazing),
    ] {
        let start = settled(&JeffcottModel::new(base.with_eta(from)).unwrap(), 300);
        let a = locate_loss(
            |eta| JeffcottModel::new(base.with_eta(eta)),
            from,
            to,
            &start,
            period,
            &opts,
        )
        .unwrap();
        let b = locate_loss(
            |eta| Ok::<_, String>(si_model(&base.with_eta(eta))),
            from,
            to,
            &to_si(start.as_slice()),
            period,
            &opts,
        )
        .unwrap();
        let (la, lb) = (a.loss.expect("a loss"), b.loss.expect("a loss"));
        eprintln!(
            "{kind:?}: eta* {:.10} / {:.10} ({:.1e} apart), brackets {:?} / {:?}",
            la.parameter,
            lb.parameter,
            la.parameter - lb.parameter,
            la.bracket,
            lb.bracket
        );
        assert_eq!(la.kind, kind);
        assert_eq!(lb.kind, kind);
        // Both located to the bracket width (1e-8).
        assert!((la.parameter - lb.parameter).abs() < 2.0 * opts.bracket_width);
    }
}
