//! The rub map (`stability::rub_map`) of a 2-DOF linear rotor with anisotropic supports on the
//! ring, continued in speed from below the first contact. Truths computed here, not by the
//! crate: the grazing speed from the closed-form linear response (its ellipse's semi-major
//! axis reaching the gap, by bisection in the test), the no-contact amplitude on the same
//! closed form, and one rub-branch orbit checked by a long run to its attractor and by the
//! growth of a perturbation.

use jeffcott::hybrid::{simulate, OutputPlan, RotorModel, SimOptions, Trajectory};
use jeffcott::nalgebra::Complex;
use jeffcott::nalgebra::{DMatrix, DVector};
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{LinearRotor, LinearSystem, RingedRotor, SmoothRotor};
use jeffcott::stability::{rub_map, RingReading, RubMap, RubMapOptions, SpecialKind};

// Unit mass per axis, natural frequencies 1 (x) and 1.2 (y), damping 0.05, out-of-balance
// 0.05 (kg m), gap 0.5, ring stiffness 20 per unit and damping 0.05.
pub(super) const ME: f64 = 0.05;
pub(super) const GAP: f64 = 0.5;
const KXY: [f64; 2] = [1.0, 1.44];
pub(super) const C: f64 = 0.05;
const RING_STIFFNESS: f64 = 20.0;
pub(super) const RING_DAMPING: f64 = 0.05;

fn model(speed: f64) -> Result<RingedRotor<LinearRotor>, String> {
    rotor_with(KXY, RING_STIFFNESS, speed)
}

/// The rotor with isotropic supports of stiffness `k`.
fn isotropic(k: f64, speed: f64) -> Result<RingedRotor<LinearRotor>, String> {
    rotor_with([k, k], RING_STIFFNESS, speed)
}

/// The rotor with supports of stiffness `stiffness` (x, y) on a ring of stiffness
/// `ring_stiffness` per unit, at `speed`.
pub(super) fn rotor_with(
    stiffness: [f64; 2],
    ring_stiffness: f64,
    speed: f64,
) -> Result<RingedRotor<LinearRotor>, String> {
    let m = DMatrix::identity(2, 2);
    let k = DMatrix::from_diagonal(&DVector::from_row_slice(&stiffness));
    let c = DMatrix::identity(2, 2) * C;
    let f = ME * speed * speed;
    let system = LinearSystem::new(m, c, k, speed)
        .and_then(|s| s.with_harmonic_force(0, Complex::new(f, 0.0)))
        .and_then(|s| s.with_harmonic_force(1, Complex::new(0.0, -f)))
        .map_err(|e| e.to_string())?;
    let ring = SnubberRing::from_units(ring_stiffness, RING_DAMPING, [0.0, 0.0], GAP)
        .map_err(|e| e.to_string())?;
    LinearRotor::new(system, [0, 1], [0.0, 0.0])
        .and_then(|r| r.ringed(ring))
        .map_err(|e| e.to_string())
}

/// The closed form off the ring: per axis $X_j = \hat F_j/(k_j - \Omega^2 + i c\Omega)$; the
/// orbit $\operatorname{Re}(Z e^{i\theta})$ is an ellipse of semi-major axis
/// $\sqrt{(|Z|^2 + |Z\cdot Z|)/2}$ ($Z\cdot Z$ without conjugation).
fn free_amplitude(speed: f64) -> f64 {
    let f = ME * speed * speed;
    let axis = |k: f64, force: Complex<f64>| force / Complex::new(k - speed * speed, C * speed);
    let (x, y) = (
        axis(KXY[0], Complex::new(f, 0.0)),
        axis(KXY[1], Complex::new(0.0, -f)),
    );
    ((x.norm_sqr() + y.norm_sqr() + (x * x + y * y).norm()) / 2.0).sqrt()
}

pub(super) fn read(
    m: &RingedRotor<LinearRotor>,
    y: &DVector<f64>,
    c: bool,
) -> Result<RingReading, String> {
    Ok(RingReading {
        station: m.rotor().station(y),
        normal_force: m.normal_force(y, c).map_err(|e| e.to_string())?,
    })
}

pub(super) fn tight() -> SimOptions {
    SimOptions::default().with_rtol(1e-11).with_atol(1e-11)
}

/// The maps' options: runs at 1e-11, steps up to 0.05, at most `max_points` orbits.
pub(super) fn options(max_points: usize) -> RubMapOptions {
    let base = RubMapOptions::default();
    base.with_continuation(
        base.continuation
            .with_sim(tight())
            .with_ds_max(0.05)
            .with_max_points(max_points),
    )
}

fn map(from: f64, to: f64) -> RubMap {
    let guess = model(from).unwrap().rotor().steady_state().unwrap();
    rub_map(model, (from, to), &guess, 1, &options(400), read, &()).unwrap()
}

/// An isotropic rotor's free circle of radius $m e\Omega^2/|k - \Omega^2 + i c\Omega|$ reaches
/// the gap below and above its critical speed: $|X| = g$ is
/// $(m^2e^2 - g^2)u^2 + g^2(2k - c^2)u - g^2k^2 = 0$, a quadratic in $u = \Omega^2$ whose roots
/// are both positive ($m e < g$). The two speeds, smaller first.
pub(super) fn isotropic_grazings(k: f64) -> [f64; 2] {
    let (a, b, c0) = (
        ME * ME - GAP * GAP,
        GAP * GAP * (2.0 * k - C * C),
        -GAP * GAP * k * k,
    );
    let root = (b * b - 4.0 * a * c0).sqrt();
    // a < 0: the root with +sqrt is the smaller.
    [
        ((-b + root) / (2.0 * a)).sqrt(),
        ((-b - root) / (2.0 * a)).sqrt(),
    ]
}

/// The first grazing is where the free orbit's ellipse reaches the gap: located to 1e-8 in
/// speed against the closed form's bisection here; off the ring the amplitudes are the closed
/// form's, and the contact fraction and the normal force are zero.
#[test]
fn the_first_contact_is_where_the_linear_response_reaches_the_gap() {
    let (mut lo, mut hi) = (0.8, 1.0);
    assert!(free_amplitude(lo) < GAP && free_amplitude(hi) > GAP);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if free_amplitude(mid) < GAP {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let graze = 0.5 * (lo + hi);
    let rub = map(0.8, 1.3);
    let first = rub
        .branch
        .specials
        .iter()
        .find(|s| s.kind == SpecialKind::Grazing)
        .expect("a grazing");
    println!(
        "grazing {:.12} (closed form {graze:.12}), converged {}",
        first.parameter, first.converged
    );
    assert!(first.converged, "{:?}", first.unconverged);
    assert!((first.parameter - graze).abs() <= 1e-8);
    let mut free = 0;
    for p in rub
        .points
        .iter()
        .filter(|p| p.contacts == 0 && p.parameter < graze)
    {
        let err = (p.amplitude - free_amplitude(p.parameter)).abs() / GAP;
        assert!(err <= 1e-8, "{err:e} of the gap at speed {}", p.parameter);
        assert_eq!((p.contact_fraction, p.peak_force), (0.0, 0.0));
        free += 1;
    }
    assert!(free >= 3, "{free} free orbits");
    assert!(rub.failures.is_empty(), "{:?}", rub.failures);
}

/// The strobes $k = 1..=K$ of a run from `y` (the ring placed consistently first).
fn strobes(model: &RingedRotor<LinearRotor>, y: &DVector<f64>, periods: u64) -> Vec<DVector<f64>> {
    let mut y = y.clone();
    model.make_consistent(&mut y).unwrap();
    let plan = OutputPlan::strobe(model.forcing_period(), 1, periods);
    let mut traj = Trajectory::default();
    simulate(model, 0.0, &y, &plan, &tight(), &mut traj).unwrap();
    traj.strobe.into_iter().map(|p| p.y).collect()
}

/// The rotor's part of a state in gaps (and gaps per unit time), without the ring's slots.
fn distance(a: &DVector<f64>, b: &DVector<f64>) -> f64 {
    (0..4).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max) / GAP
}

/// One orbit of the rub branch checked without the continuation: a run from it, its velocity
/// kicked by 1e-3 gap per unit time, falls back onto it to 1e-9 of the gap (the attractor
/// found by a different method), at the rate of its largest multiplier (measured from the
/// perturbation's decay over the run's last periods, within 2 %); an unstable orbit of the
/// branch, kicked by 1e-9, leaves it at its largest multiplier's rate.
#[test]
fn a_rub_orbit_is_the_attractor_and_its_multipliers_are_the_perturbations_rate() {
    let rub = map(0.8, 1.3);
    let pick = |stable: bool| {
        rub.branch
            .points
            .iter()
            .filter(|p| p.contacts > 0 && p.stable == stable && p.min_margin > 0.05)
            .min_by(|a, b| {
                let r = |p: &jeffcott::stability::BranchPoint| p.multipliers[0].modulus();
                let key = |p| if stable { r(p) } else { -r(p) };
                key(a).total_cmp(&key(b))
            })
            .expect("an orbit in contact")
    };
    for (stable, kick, periods) in [(true, 1e-3, 400), (false, 1e-9, 60)] {
        let p = pick(stable);
        let model = model(p.parameter).unwrap();
        let point = DVector::from_column_slice(&p.state);
        let mut start = point.clone();
        start[2] += kick * GAP;
        let path = strobes(&model, &start, periods);
        let d: Vec<f64> = path.iter().map(|y| distance(y, &point)).collect();
        let mu = p.multipliers[0].modulus();
        // The rate where the perturbation is linear and above the runs' noise: from where it
        // is 1e-5 of the gap down to 1e-9 (stable), from 1e-8 up to 1e-4 (unstable).
        let first = |pred: &dyn Fn(f64) -> bool| d.iter().position(|&x| pred(x)).unwrap();
        let (a, b) = if stable {
            (first(&|x| x < 1e-5), first(&|x| x < 1e-9))
        } else {
            (first(&|x| x > 1e-8), first(&|x| x > 1e-4))
        };
        assert!(b > a + 5, "too short a window: {a}..{b}");
        let rate = (d[b] / d[a]).powf(1.0 / (b - a) as f64);
        println!(
            "speed {:.6} stable {stable}: |mu| {mu:.6}, perturbation's rate {rate:.6}, last distance {:.2e}",
            p.parameter,
            d.last().unwrap()
        );
        assert!(
            (rate / mu - 1.0).abs() <= 0.02,
            "rate {rate} against |mu| {mu}"
        );
        if stable {
            assert!(
                *d.last().unwrap() <= 1e-9,
                "{:e} of the gap",
                d.last().unwrap()
            );
        } else {
            assert!(mu > 1.0);
        }
    }
}

/// With isotropic supports the free orbit is a circle: the rub starts as a permanent contact
/// (a full annular rub, no onset event), a grazing all the same, located where the circle's
/// radius $|X| = m e\Omega^2/|k - \Omega^2 + i c\Omega|$ reaches the gap (closed form, solved
/// here for $\Omega$ in closed form: a quadratic in $\Omega^2$), to 1e-8 in speed; beyond it
/// the orbit is in contact all the period.
#[test]
fn an_isotropic_rotors_full_annular_rub_starts_at_a_located_grazing() {
    let k = 1.0;
    let build = |speed: f64| isotropic(k, speed);
    let graze = isotropic_grazings(k)[0];
    let guess = build(0.8).unwrap().rotor().steady_state().unwrap();
    let rub = rub_map(build, (0.8, 1.0), &guess, 1, &options(60), read, &()).unwrap();
    let first = rub.branch.specials.first().expect("a special point");
    println!("grazing {:.12} (closed form {graze:.12})", first.parameter);
    assert_eq!(first.kind, SpecialKind::Grazing);
    assert!(first.converged, "{:?}", first.unconverged);
    assert!((first.parameter - graze).abs() <= 1e-8);
    let beyond = rub.points.iter().filter(|p| p.parameter > graze + 1e-6);
    assert!(beyond.clone().count() >= 3);
    for p in beyond {
        assert_eq!((p.contact_fraction, p.contacts), (1.0, 0));
        assert!(p.amplitude > GAP && p.peak_force > 0.0);
    }
}
