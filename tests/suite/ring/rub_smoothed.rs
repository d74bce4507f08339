//! Friction at the ring against an independent implementation written here: the same rotor
//! and ring with Coulomb's law smoothed, $F_t = \mu N\psi(v/\varepsilon)$,
//! $\psi(x) = x/\sqrt{1 + x^2}$, integrated by an adaptive Dormand-Prince 5(4) written in this
//! file, for shrinking $\varepsilon$. Nothing of the crate's friction is used: no location
//! solver (the contact direction $\theta$ is a state, $\theta^\prime = v - \eta a$ with $v$
//! from the smoothed law), no modes, no events (the contact lasts throughout the run), the
//! ring's force law written out below. As $\varepsilon \to 0$ its trajectory tends to the
//! crate's, which locates every slip reversal, roll and preload crossing as an event.

use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::{Complex, DMatrix, DVector, Vector2};
use jeffcott::ring::{RingAxis, SnubberRing};
use jeffcott::rotor::{LinearRotor, LinearSystem, RubbingRotor};

/// A preloaded anisotropic ring pressed on by an eccentric rotor (its rest 1.30 gaps from the
/// ring's centre, the gap 1): contact throughout, slipping both ways, rolling and preload
/// crossings of both axes while the out-of-balance turns. The paper's units: rotor mass,
/// stiffness and gap 1.
struct Scene {
    mu: f64,
    /// Shaft radius a (gaps).
    a: f64,
    eta: f64,
    beta: f64,
    nu1: f64,
    nu2: f64,
    k: [f64; 2],
    preload: [f64; 2],
    /// Rest position of the rotor relative to the ring's centre.
    e: [f64; 2],
    /// Initial rotor displacement from its rest (toward the ring's centre).
    q0: [f64; 2],
}

const SCENE: Scene = Scene {
    mu: 0.3,
    a: 0.005,
    eta: 2.5,
    beta: 0.02,
    nu1: 0.1,
    nu2: 0.002,
    k: [30.0, 20.0],
    preload: [0.005, 0.003],
    e: [1.3, 0.1],
    q0: [-0.289, -0.0222],
};

const T_END: f64 = 10.0;
const DT: f64 = 0.01;

impl Scene {
    /// Elastic force of one axis at ring coordinate s: 2Ks inside the preload, K(s + D sign s)
    /// beyond it (MODEL.md); and its damping coefficient, 4 nu2 inside, 2 nu2 beyond.
    fn axis(&self, i: usize, s: f64) -> (f64, f64) {
        let (k, d) = (self.k[i], self.preload[i]);
        if s.abs() <= d {
            (2.0 * k * s, 4.0 * self.nu2)
        } else {
            (k * (s + d.copysign(s)), 2.0 * self.nu2)
        }
    }

    fn unbalance(&self, t: f64) -> Vector2<f64> {
        let f = self.beta * self.eta * self.eta;
        Vector2::new((self.eta * t).cos(), (self.eta * t).sin()) * f
    }

    /// The ring at s = r - n(theta) for the rotor's station r: the unit normal and tangent,
    /// the elastic force g(s), the dampers C(s), and F_t/(mu N) (t . g over mu n . g).
    fn ring_at(&self, r: Vector2<f64>, theta: f64) -> Ring {
        let (sin, cos) = theta.sin_cos();
        let (n, tan) = (Vector2::new(cos, sin), Vector2::new(-sin, cos));
        let s = r - n;
        let ((gx, cx), (gy, cy)) = (self.axis(0, s.x), self.axis(1, s.y));
        let g = Vector2::new(gx, gy);
        Ring {
            n,
            tan,
            g,
            c: Vector2::new(cx, cy),
            ratio: tan.dot(&g) / (self.mu * n.dot(&g)),
        }
    }

    /// The contact direction at which F_t/(mu N) is `ratio` for the station r, by bisection
    /// within 0.05 rad of r's direction (F_t/N falls as theta grows: F_t' = -N - t.G't).
    fn direction_with_ratio(&self, r: Vector2<f64>, ratio: f64) -> f64 {
        let (mut lo, mut hi) = (r.y.atan2(r.x) - 0.05, r.y.atan2(r.x) + 0.05);
        assert!(self.ring_at(r, lo).ratio > ratio && self.ring_at(r, hi).ratio < ratio);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if self.ring_at(r, mid).ratio > ratio {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// The smoothed model's field, state z = (q, q', theta): the ring at s = r - n(theta),
    /// r = q + e. Also returns the normal part of the ring's force n . f (contact needs it
    /// positive). NaN where the smoothed law has no slip velocity (|F_t| >= mu N).
    fn smoothed(&self, t: f64, z: &[f64; 5], eps: f64) -> ([f64; 5], f64) {
        let q = Vector2::new(z[0], z[1]);
        let q_dot = Vector2::new(z[2], z[3]);
        let r = q + Vector2::new(self.e[0], self.e[1]);
        let Ring {
            n,
            tan,
            g,
            c,
            ratio,
        } = self.ring_at(r, z[4]);
        // psi(v/eps) = ratio  <=>  v = eps ratio / sqrt(1 - ratio^2).
        let v = eps * ratio / ((1.0 - ratio) * (1.0 + ratio)).sqrt();
        let theta_dot = v - self.eta * self.a;
        let s_dot = q_dot - tan * theta_dot;
        let f = g + c.component_mul(&s_dot);
        let acc = self.unbalance(t) - q_dot * (2.0 * self.nu1) - q - f;
        ([q_dot.x, q_dot.y, acc.x, acc.y, theta_dot], n.dot(&f))
    }
}

/// The ring in contact at a contact direction ([`Scene::ring_at`]).
struct Ring {
    n: Vector2<f64>,
    tan: Vector2<f64>,
    g: Vector2<f64>,
    c: Vector2<f64>,
    ratio: f64,
}

/// Dormand-Prince 5(4): the nodes, the stage coefficients, the fifth-order weights (the last
/// stage's row) and the fourth-order ones.
const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A: [[f64; 6]; 7] = [
    [0.0; 6],
    [0.2, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0],
    [
        19372.0 / 6561.0,
        -25360.0 / 2187.0,
        64448.0 / 6561.0,
        -212.0 / 729.0,
        0.0,
        0.0,
    ],
    [
        9017.0 / 3168.0,
        -355.0 / 33.0,
        46732.0 / 5247.0,
        49.0 / 176.0,
        -5103.0 / 18656.0,
        0.0,
    ],
    [
        35.0 / 384.0,
        0.0,
        500.0 / 1113.0,
        125.0 / 192.0,
        -2187.0 / 6784.0,
        11.0 / 84.0,
    ],
];
const B4: [f64; 7] = [
    5179.0 / 57600.0,
    0.0,
    7571.0 / 16695.0,
    393.0 / 640.0,
    -92097.0 / 339200.0,
    187.0 / 2100.0,
    1.0 / 40.0,
];

/// The smoothed model from `z0` at the sample times k DT up to T_END, adaptive steps that land
/// on each sample, error per step below `tol` (mixed: absolute and relative to the state).
/// Returns the rotor's station r at each sample, and the least n . f met at a step's end.
fn integrate_smoothed(scene: &Scene, z0: [f64; 5], eps: f64, tol: f64) -> (Vec<Vector2<f64>>, f64) {
    let field = |t: f64, z: &[f64; 5]| scene.smoothed(t, z, eps);
    let station = |z: &[f64; 5]| Vector2::new(z[0] + scene.e[0], z[1] + scene.e[1]);
    let (mut t, mut z, mut h) = (0.0, z0, 1e-6);
    let mut out = vec![station(&z)];
    let mut least_normal = f64::INFINITY;
    let samples = (T_END / DT).round() as usize;
    for k in 1..=samples {
        let target = k as f64 * DT;
        while t < target {
            let last = h >= target - t;
            let step = if last { target - t } else { h };
            let mut stages = [[0.0; 5]; 7];
            for i in 0..7 {
                let mut zi = z;
                for (j, stage) in stages.iter().enumerate().take(i) {
                    for (zm, km) in zi.iter_mut().zip(stage) {
                        *zm += step * A[i][j] * km;
                    }
                }
                stages[i] = field(t + C[i] * step, &zi).0;
            }
            let mut next = z;
            let mut err = 0f64;
            for m in 0..5 {
                let high: f64 = (0..6).map(|i| A[6][i] * stages[i][m]).sum();
                let low: f64 = (0..7).map(|i| B4[i] * stages[i][m]).sum();
                next[m] += step * high;
                let scale = tol * (1.0 + z[m].abs().max(next[m].abs()));
                err = err.max((step * (high - low) / scale).abs());
            }
            // A stage without a slip velocity (|F_t| >= mu N) rejects the step (`f64::max`
            // above passes over NaN).
            let finite = stages.iter().flatten().all(|k| k.is_finite());
            if !finite || err > 1.0 {
                h = 0.5 * step.min(h);
                assert!(h > 1e-14, "the smoothed run stalls at t = {t}");
                continue;
            }
            let (_, normal) = field(t + step, &next);
            least_normal = least_normal.min(normal);
            (t, z) = (if last { target } else { t + step }, next);
            // The usual controller: the fifth root of the error, safety 0.9, growth at most 5x.
            let grow = (0.9 * err.max(1e-10).powf(-0.2)).min(5.0);
            if !last {
                h = step * grow;
            }
        }
        out.push(station(&z));
    }
    (out, least_normal)
}

/// The crate's run of the scene: `RubbingRotor` on the paper's rotor written as a
/// `LinearRotor`, DOP853 at rtol 1e-12, samples every DT.
fn crate_run(scene: &Scene) -> Trajectory<jeffcott::nalgebra::Dyn> {
    let eye = DMatrix::<f64>::identity(2, 2);
    let f = Complex::new(scene.beta * scene.eta * scene.eta, 0.0);
    let system = LinearSystem::new(eye.clone(), &eye * (2.0 * scene.nu1), eye, scene.eta)
        .unwrap()
        .with_harmonic_force(0, f)
        .unwrap()
        .with_harmonic_force(1, f * Complex::new(0.0, -1.0))
        .unwrap();
    let axis = |i: usize| RingAxis::new(scene.k[i], scene.preload[i]);
    let ring = SnubberRing::new(axis(0), axis(1), scene.nu2, 1.0).unwrap();
    let rotor = LinearRotor::new(system, [0, 1], [-scene.e[0], -scene.e[1]])
        .unwrap()
        .ringed(ring)
        .unwrap();
    let model = RubbingRotor::new(rotor, scene.mu, scene.a).unwrap();
    let y0 = DVector::from_vec(vec![scene.q0[0], scene.q0[1], 0.0, 0.0, 0.0, 0.0]);
    let plan = OutputPlan {
        t_end: T_END,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: DT,
        }),
        events: true,
    };
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-13);
    let mut traj = Trajectory::default();
    simulate(&model, 0.0, &y0, &plan, &opts, &mut traj).unwrap();
    traj
}

/// The crate's trajectory against the smoothed law's for eps = 1e-3, 5e-4, 2.5e-4 (gaps per
/// unit time; the slip velocities here are 1e-2 to 1): the smoothed runs converge to the
/// crate's, as their own convergence predicts.
#[test]
fn coulomb_friction_is_the_limit_of_a_smoothed_law_integrated_independently() {
    converges_to_the_crates_run(&[1e-3, 5e-4, 2.5e-4]);
}

/// As above, down to eps = 6.25e-5 (half a minute).
#[test]
#[ignore = "long: half a minute"]
fn coulomb_friction_is_the_limit_of_a_smoothed_law_down_to_small_smoothing() {
    converges_to_the_crates_run(&[1e-3, 5e-4, 2.5e-4, 1.25e-4, 6.25e-5]);
}

/// Runs the crate and the smoothed law for each `eps` (halving) and checks: contact
/// throughout with slipping both ways, rolling and preload crossings of both axes; each
/// halving brings the smoothed run closer to the crate's; and the crate's run lies where the
/// smoothed runs head: their steps shrink geometrically (ratio rho, from the last two), so
/// the last run's distance to the limit is about rho/(1 - rho) times the last step, and its
/// distance to the crate's must not exceed that by more than a quarter.
fn converges_to_the_crates_run(epsilons: &[f64]) {
    let scene = SCENE;
    let traj = crate_run(&scene);
    let mut modes = std::collections::BTreeMap::new();
    for e in &traj.events {
        *modes.entry(e.kind).or_insert(0) += 1;
    }
    println!("crate's events: {modes:?}");
    for kind in ["slip velocity zero", "friction cone's edge"] {
        assert!(
            modes.get(kind).copied().unwrap_or(0) >= 5,
            "{kind}: {modes:?}"
        );
    }
    assert!(
        modes.keys().filter(|k| k.contains("preload")).count() == 4,
        "both axes cross their preloads both ways: {modes:?}"
    );
    assert!(!modes.contains_key("contact loss"), "contact throughout");
    let labels: std::collections::BTreeSet<u8> = traj.samples.iter().map(|s| s.label).collect();
    assert_eq!(labels, [6, 7, 8].into(), "slipping both ways and rolling");
    let reference: Vec<Vector2<f64>> = traj
        .samples
        .iter()
        .map(|s| Vector2::new(s.y[0] + scene.e[0], s.y[1] + scene.e[1]))
        .collect();
    assert_eq!(reference.len(), (T_END / DT).round() as usize + 1);
    // Both start with the rotor at q0 at rest, slipping forward (the onset rule: the forward
    // slip's velocity there is the surface speed eta a > 0): the smoothed run where its law
    // gives that slip velocity, psi(eta a/eps) = F_t/(mu N), found here by bisection.
    let distance = |a: &[Vector2<f64>], b: &[Vector2<f64>]| {
        a.iter()
            .zip(b)
            .map(|(p, q)| (p - q).norm())
            .fold(0.0, f64::max)
    };
    let mut runs = Vec::new();
    for &eps in epsilons {
        let x = scene.eta * scene.a / eps;
        let theta0 = scene.direction_with_ratio(reference[0], x / (1.0 + x * x).sqrt());
        let z0 = [scene.q0[0], scene.q0[1], 0.0, 0.0, theta0];
        let (r, least_normal) = integrate_smoothed(&scene, z0, eps, 1e-9);
        assert!(
            least_normal > 0.0,
            "the smoothed contact lasts: {least_normal}"
        );
        assert!(r.iter().all(|p| p.x.is_finite() && p.y.is_finite()));
        println!(
            "eps {eps:.3e}: {:.3e} from the crate's",
            distance(&r, &reference)
        );
        runs.push(r);
    }
    let off: Vec<f64> = runs.iter().map(|r| distance(r, &reference)).collect();
    // Each halving of eps brings the smoothed run closer to the crate's.
    for w in off.windows(2) {
        assert!(w[1] < 0.7 * w[0], "converging to the crate's run: {off:?}");
    }
    let n = runs.len();
    let steps: Vec<f64> = (1..n).map(|k| distance(&runs[k], &runs[k - 1])).collect();
    let rho = steps[n - 2] / steps[n - 3];
    let predicted = steps[n - 2] * rho / (1.0 - rho);
    println!(
        "steps between the smoothed runs {}, rho {rho:.3}: the last {predicted:.3e} from their limit, {:.3e} from the crate's",
        steps.iter().map(|d| format!("{d:.3e}")).collect::<Vec<_>>().join(", "),
        off[n - 1]
    );
    assert!(rho < 0.75, "the smoothed runs converge: {steps:?}");
    assert!(
        off[n - 1] <= 1.25 * predicted,
        "the crate's run is {:.3e} from the last smoothed run, which is {predicted:.3e} from their limit",
        off[n - 1]
    );
}
