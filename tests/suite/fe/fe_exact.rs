//! Closed-form free flight of linear rotors (`rotor::LinearFreeFlight`) against independent
//! truths: the paper's own closed form (a second, independent derivation), a high-accuracy
//! integration, and a rotor run with integrated free flight; and refusal of near-defective
//! state matrices.

use crate::rng::Rng;
use std::sync::Arc;

use jeffcott::hybrid::{OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::{Complex, DMatrix, DVector, Dyn, OVector, Vector2};
use jeffcott::ode::{Dop853, Integrator, Options, Tolerance};
use jeffcott::paper::FreeOscillator;
use jeffcott::params::{Params, Preset};
use jeffcott::ring::onset::RotorMotion;
use jeffcott::ring::{Kinematics, SnubberRing};
use jeffcott::rotor::{
    LinearFreeFlight, LinearSystem, RingedRotor, RotorError, RotorMatrices, SmoothRotor,
};

fn data(name: &str) -> String {
    format!("{}/tests/data/rotors/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// The S1 rotor's free flight (ROSS's 204-DOF example at 1200 rpm, lateral DOFs, ring at node
/// 12, the unbalance 0.002 kg m at phase -pi/2 at node 12: the case's sidecar JSON).
pub fn s1_free_flight() -> LinearFreeFlight {
    ross_free_flight("rotor_example_with_damping_1200rpm.mat", 1200.0, 12)
}

/// A ROSS export's lateral free flight at `rpm` with the ring and an unbalance of 0.002 kg m
/// (phase -pi/2) at `node`.
fn ross_free_flight(file: &str, rpm: f64, node: usize) -> LinearFreeFlight {
    let full = RotorMatrices::from_ross_mat(data(file)).unwrap();
    let lat = full.lateral().unwrap();
    let w = rpm * std::f64::consts::TAU / 60.0;
    let n = lat.dofs();
    let ix = lat.x_dof(node).unwrap();
    let d = lat.damping() + lat.gyroscopic() * w;
    let mut f = DVector::from_element(n, Complex::new(0.0, 0.0));
    // F = me W^2 (cos(W t + phase), sin(W t + phase)) = Re(me W^2 e^{i phase} (1, -i) e^{i W t}).
    let ph = Complex::from_polar(0.002 * w * w, -std::f64::consts::FRAC_PI_2);
    f[ix] = ph;
    f[ix + 1] = ph * Complex::new(0.0, -1.0);
    LinearFreeFlight::new(
        LinearSystem::from_parts(
            lat.mass().clone(),
            d,
            lat.stiffness().clone(),
            w,
            f,
            DVector::zeros(n),
        )
        .unwrap(),
        [ix, ix + 1],
        Vector2::zeros(),
    )
}

#[test]
fn ross_rotors_closed_forms_are_accepted_and_well_conditioned() {
    for (file, rpm, node, dofs) in [
        ("rotor_example_with_damping_1200rpm.mat", 1200.0, 12, 136),
        ("rotor_example_1500rpm.mat", 1500.0, 3, 28),
    ] {
        let t = std::time::Instant::now();
        let form = ross_free_flight(file, rpm, node).prepare().unwrap();
        let ev = form.eigenvalues();
        let max_re = ev.iter().map(|l| l.re).fold(f64::NEG_INFINITY, f64::max);
        let max_abs = ev.iter().map(|l| l.norm()).fold(0.0, f64::max);
        eprintln!(
            "{file}: n {} condition {:.3e} residual {:.3e} max Re(lambda) {max_re:.3e} max |lambda| {max_abs:.3e}, prepared in {:?}",
            form.dofs(),
            form.condition(),
            form.residual(),
            t.elapsed()
        );
        assert_eq!(form.dofs(), dofs);
        // The 42-DOF rotor has no damping: its eigenvalues are imaginary, their real parts
        // rounding (either sign; the onset search's windowed bounds take the positive ones).
        assert!(max_re < 1e-12 * max_abs);
        assert!(form.condition() < 1e6 && form.residual() < 1e-10);
    }
}

/// The paper's Jeffcott rotor (MODEL.md) as matrices: $M = I$, $D = 2\nu_1 I$, $K = I$, rest
/// position $e$ (static force $e$), unbalance $\beta\eta^2 e^{i(\varphi_0 + \eta t)}$.
fn jeffcott_as_matrices(p: &Params) -> LinearFreeFlight {
    let b = Complex::from_polar(p.forcing_amplitude(), p.phi0);
    LinearFreeFlight::new(
        LinearSystem::from_parts(
            DMatrix::identity(2, 2),
            DMatrix::identity(2, 2) * (2.0 * p.nu1),
            DMatrix::identity(2, 2),
            p.eta,
            DVector::from_vec(vec![b, b * Complex::new(0.0, -1.0)]),
            DVector::from_vec(vec![p.ex, p.ey]),
        )
        .unwrap(),
        [0, 1],
        Vector2::zeros(),
    )
}

#[test]
fn jeffcott_rotor_as_matrices_matches_the_paper_closed_form() {
    // Two independent closed forms of the same motion: the paper's (complex amplitude Z,
    // damped oscillator per axis, its hyperbolic form when over-damped) and the modal one.
    let mut worst = 0.0f64;
    for nu1 in [0.125, 0.0, 0.6, 1.0 + 1e-6, 2.5] {
        let p = Params {
            eta: 2.3,
            nu1,
            ex: 0.3,
            ey: -0.2,
            ..Preset::Fig8a.params()
        };
        let osc = FreeOscillator::new(&p);
        let form = Arc::new(jeffcott_as_matrices(&p).prepare().unwrap());
        let (t0, y0) = (1.7, [0.4, -0.9, 1.3, 0.2]);
        let paper = osc.segment(t0, &y0);
        let ours = form.segment(t0, &y0);
        let (mut x, mut dx) = ([0.0; 4], [0.0; 4]);
        for i in 0..=400 {
            let t = t0 + 0.05 * i as f64;
            let (yp, ap) = paper.state_accel(t);
            ours.state(t, &mut x, &mut dx);
            let (r, v, a) = ours.kinematics(t);
            let scale = 1.0 + yp.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for k in 0..4 {
                worst = worst.max((x[k] - yp[k]).abs() / scale);
            }
            for (got, want) in [(r.x, yp[0]), (r.y, yp[1]), (v.x, yp[2]), (v.y, yp[3])] {
                worst = worst.max((got - want).abs() / scale);
            }
            for (got, want) in [(dx[2], ap[0]), (dx[3], ap[1]), (a.x, ap[0]), (a.y, ap[1])] {
                worst = worst.max((got - want).abs() / scale);
            }
            // The state-transition matrices: the paper's per-axis closed form.
            let (phi, want) = (form.transition_matrix(t - t0), paper.transition_matrix(t));
            for i in 0..4 {
                for j in 0..4 {
                    worst = worst.max((phi[(i, j)] - want[(i, j)]).abs());
                }
            }
        }
    }
    eprintln!(
        "Jeffcott as matrices vs the paper's closed form: worst relative difference {worst:.2e}"
    );
    assert!(worst < 1e-12, "{worst:e}");
}

#[test]
fn critically_damped_jeffcott_rotor_is_refused_as_defective() {
    // nu1 = 1: each axis has the double eigenvalue -1 with one eigenvector (a Jordan block).
    let p = Params {
        nu1: 1.0,
        ..Preset::Fig8a.params()
    };
    let err = jeffcott_as_matrices(&p).prepare().unwrap_err();
    eprintln!("critical damping: {err}");
    assert!(
        matches!(
            err,
            RotorError::IllConditionedModes { .. }
                | RotorError::Eigen(jeffcott::numeric::NumericError::SingularEigenvectors { .. })
        ),
        "{err:?}"
    );
    // Near critical damping, nu1 = 1 + delta, the eigenvalues -nu1 +- sqrt(2 delta) have nearly
    // parallel eigenvectors (condition about 1/sqrt(2 delta)): refused 1e-14 away.
    let p = Params {
        nu1: 1.0 + 1e-14,
        ..Preset::Fig8a.params()
    };
    assert!(matches!(
        jeffcott_as_matrices(&p).prepare(),
        Err(RotorError::IllConditionedModes { .. } | RotorError::Eigen(_))
    ));
}

/// A random stable rotor of `n` coordinates: SPD mass and stiffness, light proportional-plus-
/// random damping, a skew gyroscopic part times the speed; random forces.
fn random_rotor(n: usize, seed: u64) -> LinearFreeFlight {
    let mut rng = Rng(seed);
    let spd = |diag: f64, rng: &mut Rng| {
        let a = DMatrix::from_fn(n, n, |_, _| rng.sym());
        &a * a.transpose() * 0.3 + DMatrix::identity(n, n) * diag
    };
    let m = spd(1.0, &mut rng);
    let k = spd(4.0, &mut rng) * 5.0;
    let c = spd(0.2, &mut rng) * 0.05;
    let g = DMatrix::from_fn(n, n, |i, j| {
        if i < j {
            0.1 * ((i + 2 * j) as f64).sin()
        } else {
            0.0
        }
    });
    let speed = 2.7;
    let d = &c + (&g - g.transpose()) * speed;
    let f = DVector::from_fn(n, |_, _| Complex::new(rng.sym(), rng.sym()));
    let f0 = DVector::from_fn(n, |_, _| 0.3 * rng.sym());
    LinearFreeFlight::new(
        LinearSystem::from_parts(m, d, k, speed, f, f0).unwrap(),
        [0, 1],
        Vector2::new(0.1, -0.05),
    )
}

/// The matrices' vector field $x^\prime = (q^\prime, M^{-1}(f_0 + \mathrm{Re}(\hat F
/// e^{i\Omega t}) - D q^\prime - K q))$, written directly (with $M^{-1}$ from nalgebra's
/// inverse, not the closed form's factorisation).
struct MatrixField {
    lf: LinearFreeFlight,
    minv: DMatrix<f64>,
    minv_k: DMatrix<f64>,
    minv_d: DMatrix<f64>,
    minv_f0: DVector<f64>,
    minv_fhat: DVector<Complex<f64>>,
}

impl MatrixField {
    fn new(lf: LinearFreeFlight) -> Self {
        let minv = lf.system.mass().clone().try_inverse().unwrap();
        let minv_c = minv.map(|v| Complex::new(v, 0.0));
        Self {
            minv_k: &minv * lf.system.stiffness(),
            minv_d: &minv * lf.system.damping(),
            minv_f0: &minv * lf.system.constant_force(),
            minv_fhat: minv_c * lf.system.harmonic_force(),
            minv,
            lf,
        }
    }
    fn accel(&self, t: f64, q: &[f64], v: &[f64], out: &mut [f64]) {
        let n = self.lf.dofs();
        let (s, c) = (self.lf.system.speed() * t).sin_cos();
        let ph = Complex::new(c, s);
        for i in 0..n {
            out[i] = self.minv_f0[i] + (self.minv_fhat[i] * ph).re;
        }
        for j in 0..n {
            let (kc, dc) = (self.minv_k.column(j), self.minv_d.column(j));
            let (qj, vj) = (q[j], v[j]);
            for i in 0..n {
                out[i] -= kc[i] * qj + dc[i] * vj;
            }
        }
    }
}

#[test]
fn random_stable_rotor_matches_a_high_accuracy_integration() {
    let n = 10;
    let field = MatrixField::new(random_rotor(n, 7));
    let form = Arc::new(field.lf.prepare().unwrap());
    let sys = |t: f64, y: &OVector<f64, Dyn>, dy: &mut OVector<f64, Dyn>| {
        let (q, v) = y.as_slice().split_at(n);
        dy.as_mut_slice()[..n].copy_from_slice(v);
        let mut a = vec![0.0; n];
        field.accel(t, q, v, &mut a);
        dy.as_mut_slice()[n..].copy_from_slice(&a);
    };
    let mut rng = Rng(99);
    let x0: Vec<f64> = (0..2 * n).map(|_| rng.sym()).collect();
    let t0 = 0.3;
    let seg = form.segment(t0, &x0);
    let opts = Options::default()
        .with_rtol(Tolerance::Scalar(1e-13))
        .with_atol(Tolerance::Scalar(1e-15));
    let mut integ = Dop853::with_dim(Dyn(2 * n), opts).unwrap();
    let y0 = DVector::from_vec(x0.clone());
    integ.reset(&sys, t0, &y0, false).unwrap();
    let (mut x, mut dx) = (vec![0.0; 2 * n], vec![0.0; 2 * n]);
    let mut worst = 0.0f64;
    let mut steps = 0;
    for k in 1..=40 {
        let t = t0 + 0.25 * k as f64;
        while integ.t() < t {
            integ.step(&sys, t).unwrap();
            steps += 1;
        }
        seg.state(t, &mut x, &mut dx);
        let y = integ.y();
        let scale = y.amax().max(1.0);
        for i in 0..2 * n {
            worst = worst.max((x[i] - y[i]).abs() / scale);
        }
        let (r, v, _) = seg.kinematics(t);
        worst = worst.max((r.x - (y[0] - 0.1)).abs() / scale);
        worst = worst.max((v.y - y[n + 1]).abs() / scale);
    }
    eprintln!(
        "random rotor (20 states, condition {:.2e}): closed form vs DOP853 rtol 1e-13 over 10 time units ({steps} steps): worst relative difference {worst:.2e}",
        form.condition()
    );
    assert!(worst < 1e-10, "{worst:e}");
}

/// A linear rotor written from its matrices as a [`SmoothRotor`] (state `[q, q', x_s, y_s]`),
/// with or without its closed form.
struct MatrixRotor {
    field: MatrixField,
    /// What `linear_free_flight` gives (its own matrices, or another's to test the check).
    closed: Option<LinearFreeFlight>,
}

impl SmoothRotor for MatrixRotor {
    type Dim = Dyn;
    fn dim(&self) -> Dyn {
        Dyn(2 * self.field.lf.dofs() + 2)
    }
    fn rhs(&self, t: f64, y: &OVector<f64, Dyn>, dy: &mut OVector<f64, Dyn>) {
        let n = self.field.lf.dofs();
        let (q, v) = y.as_slice()[..2 * n].split_at(n);
        let (dq, dv) = dy.as_mut_slice()[..2 * n].split_at_mut(n);
        dq.copy_from_slice(v);
        self.field.accel(t, q, v, dv);
    }
    fn station(&self, y: &OVector<f64, Dyn>) -> Kinematics {
        let (n, [ix, iy], o) = (
            self.field.lf.dofs(),
            self.field.lf.station,
            self.field.lf.offset,
        );
        Kinematics::new([y[ix] - o.x, y[iy] - o.y], [y[n + ix], y[n + iy]])
    }
    fn add_station_force(
        &self,
        _y: &OVector<f64, Dyn>,
        f: &Vector2<f64>,
        dy: &mut OVector<f64, Dyn>,
    ) {
        let (n, [ix, iy]) = (self.field.lf.dofs(), self.field.lf.station);
        for i in 0..n {
            dy[n + i] += self.field.minv[(i, ix)] * f.x + self.field.minv[(i, iy)] * f.y;
        }
    }
    fn ring_slots(&self) -> [usize; 2] {
        let n = self.field.lf.dofs();
        [2 * n, 2 * n + 1]
    }
    fn forcing_period(&self) -> f64 {
        std::f64::consts::TAU / self.field.lf.system.speed()
    }
    fn linear_free_flight(&self) -> Option<LinearFreeFlight> {
        self.closed.clone()
    }
}

/// Two lumped nodes, gyroscopic coupling, unbalance at node 0 where the ring sits (gap 1):
/// a rotor that hits the ring several times a period.
fn two_node_rotor(exact: bool) -> MatrixRotor {
    two_node_rotor_forced(exact, 0.9)
}

fn two_node_rotor_forced(exact: bool, amplitude: f64) -> MatrixRotor {
    let n = 4;
    let m = DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 1.0, 0.5, 0.5]));
    let k2 = [[2.0, -1.0], [-1.0, 1.5]];
    let k = DMatrix::from_fn(n, n, |i, j| {
        if i % 2 == j % 2 {
            k2[i / 2][j / 2]
        } else {
            0.0
        }
    });
    let speed = 1.4;
    let g = DMatrix::from_fn(n, n, |i, j| match (i % 2, j % 2, i / 2 == j / 2) {
        (0, 1, true) => 0.2,
        (1, 0, true) => -0.2,
        _ => 0.0,
    });
    let d = &k * 0.04 + g * speed;
    let b = Complex::from_polar(amplitude, 0.3);
    let mut f = DVector::from_element(n, Complex::new(0.0, 0.0));
    f[0] = b;
    f[1] = b * Complex::new(0.0, -1.0);
    let lf = LinearFreeFlight::new(
        LinearSystem::from_parts(m, d, k, speed, f, DVector::zeros(n)).unwrap(),
        [0, 1],
        Vector2::new(0.05, -0.1),
    );
    MatrixRotor {
        closed: exact.then(|| lf.clone()),
        field: MatrixField::new(lf),
    }
}

fn run_ringed(rotor: MatrixRotor, periods: u64) -> (Trajectory<Dyn>, jeffcott::hybrid::SimStats) {
    let ring = SnubberRing::isotropic(30.0, 0.05, 0.01).unwrap();
    let period = rotor.forcing_period();
    let model = RingedRotor::new(rotor, ring).unwrap();
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-14);
    let plan = OutputPlan {
        events: true,
        ..OutputPlan::strobe(period, 0, periods)
    };
    let mut traj = Trajectory::default();
    let y0 = DVector::zeros(10);
    let stats = jeffcott::hybrid::simulate(&model, 0.0, &y0, &plan, &opts, &mut traj).unwrap();
    (traj, stats)
}

#[test]
fn a_closed_form_that_disagrees_with_its_rotor_is_an_error() {
    // The gyroscopic sign flipped (D = C - W G instead of C + W G), or the unbalance's phase
    // off by a quarter turn: RingedRotor::new names the mismatch.
    let ring = SnubberRing::isotropic(30.0, 0.05, 0.01).unwrap();
    let mut rotor = two_node_rotor(true);
    let mut wrong = rotor.field.lf.clone();
    let s = &wrong.system;
    let w = s.speed();
    let mut d = s.damping().clone();
    for (i, j) in [(0, 1), (2, 3)] {
        d[(i, j)] -= 0.4 * w;
        d[(j, i)] += 0.4 * w;
    }
    let (m, k, f, f0) = (
        s.mass(),
        s.stiffness(),
        s.harmonic_force(),
        s.constant_force(),
    );
    let system = LinearSystem::from_parts(m.clone(), d, k.clone(), w, f.clone(), f0.clone());
    wrong.system = system.unwrap();
    rotor.closed = Some(wrong);
    let Err(err) = RingedRotor::new(rotor, ring) else {
        panic!("accepted");
    };
    eprintln!("{err}");
    assert!(
        matches!(err, RotorError::LinearMismatch { method: "rhs", .. }),
        "{err:?}"
    );
    let mut rotor = two_node_rotor(true);
    let mut wrong = rotor.field.lf.clone();
    let s = &wrong.system;
    let f = s.harmonic_force() * Complex::new(0.0, 1.0);
    let (m, d, k) = (s.mass().clone(), s.damping().clone(), s.stiffness().clone());
    let system = LinearSystem::from_parts(m, d, k, s.speed(), f, s.constant_force().clone());
    wrong.system = system.unwrap();
    rotor.closed = Some(wrong);
    let Err(err) = RingedRotor::new(rotor, ring) else {
        panic!("accepted");
    };
    assert!(
        matches!(err, RotorError::LinearMismatch { method: "rhs", .. }),
        "{err:?}"
    );
    // The same rotor with its own matrices is accepted.
    assert!(RingedRotor::new(two_node_rotor(true), ring).is_ok());
}

#[test]
fn ringed_rotor_with_exact_free_flight_matches_integrated_free_flight() {
    let exact_model = RingedRotor::new(
        two_node_rotor(true),
        SnubberRing::isotropic(30.0, 0.05, 0.01).unwrap(),
    )
    .unwrap();
    assert!(matches!(exact_model.closed_form(), Some(Ok(_))));
    let periods = 60;
    let t = std::time::Instant::now();
    let (exact, se) = run_ringed(two_node_rotor(true), periods);
    let te = t.elapsed();
    let t = std::time::Instant::now();
    let (integrated, si) = run_ringed(two_node_rotor(false), periods);
    let ti = t.elapsed();
    let kinds = |t: &Trajectory<Dyn>| t.events.iter().map(|e| e.kind).collect::<Vec<_>>();
    let onsets = exact
        .events
        .iter()
        .filter(|e| e.kind == "contact onset")
        .count();
    let worst_strobe = exact
        .strobe
        .iter()
        .zip(&integrated.strobe)
        .map(|(a, b)| (a.y.rows(0, 8) - b.y.rows(0, 8)).amax())
        .fold(0.0f64, f64::max);
    let worst_event = exact
        .events
        .iter()
        .zip(&integrated.events)
        .map(|(a, b)| (a.t - b.t).abs())
        .fold(0.0f64, f64::max);
    eprintln!(
        "two-node rotor, {periods} periods: {onsets} contact onsets, {} events; max strobe difference {worst_strobe:.2e}, max event time difference {worst_event:.2e}; exact: {te:?} ({} steps, {} closed-form evaluations), integrated: {ti:?} ({} steps)",
        exact.events.len(),
        se.steps,
        se.exact_evals,
        si.steps
    );
    assert_eq!(kinds(&exact), kinds(&integrated));
    assert!(onsets >= 20, "{onsets}");
    assert!(se.exact_evals > 0 && si.exact_evals == 0);
    assert!(worst_strobe < 1e-9, "{worst_strobe:e}");
    assert!(worst_event < 1e-9, "{worst_event:e}");
}

/// Cost of the closed form against DOP853 on the S1 rotor's free flight (timings printed;
/// `cargo test --test suite free_flight_cost -- --ignored --nocapture`).
#[test]
#[ignore = "timing report"]
fn free_flight_cost_on_the_s1_rotor() {
    use jeffcott::ring::onset::{find_onset, OnsetStats};
    use jeffcott::ring::Relaxation;
    let lf = s1_free_flight();
    let t = std::time::Instant::now();
    let form = Arc::new(lf.prepare().unwrap());
    let prepare = t.elapsed();
    let n = form.dofs();
    let mut rng = Rng(5);
    let x0: Vec<f64> = (0..2 * n)
        .map(|i| if i < n { 1e-5 } else { 1e-3 } * rng.sym())
        .collect();
    let reps = 2000;
    let t = std::time::Instant::now();
    let mut seg = form.segment(0.0, &x0);
    for _ in 1..reps {
        seg = form.segment(0.0, &x0);
    }
    let start = t.elapsed() / reps;
    let t = std::time::Instant::now();
    let mut acc = 0.0;
    for i in 0..reps {
        acc += seg.kinematics(1e-4 * i as f64).0.x;
    }
    let kin = t.elapsed() / reps;
    let t = std::time::Instant::now();
    for i in 0..reps {
        acc += seg.bounds_on(1e-4 * i as f64, 1.0).jerk;
    }
    let bounds = t.elapsed() / reps;
    let (mut x, mut dx) = (vec![0.0; 2 * n], vec![0.0; 2 * n]);
    let t = std::time::Instant::now();
    for i in 0..reps / 10 {
        seg.state(1e-4 * i as f64, &mut x, &mut dx);
        acc += x[0];
    }
    let full = t.elapsed() / (reps / 10);
    // The certified search over one revolution (0.05 s) against a ring far away.
    let ring = SnubberRing {
        gap: 1e-2,
        ..SnubberRing::isotropic(1.1e6, 0.0, 0.005).unwrap()
    };
    let mut stats = OnsetStats::default();
    let t = std::time::Instant::now();
    let onset = find_onset(
        &seg,
        &Relaxation::at_rest(0.0),
        &ring,
        (0.0, 0.05),
        false,
        &mut stats,
    );
    let search = t.elapsed();
    // DOP853 on the same free flight, 1 ms (1/50 of a revolution), rtol 1e-10.
    let field = MatrixField::new(s1_free_flight());
    let sys = |t: f64, y: &OVector<f64, Dyn>, dy: &mut OVector<f64, Dyn>| {
        let (q, v) = y.as_slice().split_at(n);
        dy.as_mut_slice()[..n].copy_from_slice(v);
        let mut a = vec![0.0; n];
        field.accel(t, q, v, &mut a);
        dy.as_mut_slice()[n..].copy_from_slice(&a);
    };
    let opts = Options::default()
        .with_rtol(Tolerance::Scalar(1e-10))
        .with_atol(Tolerance::Scalar(1e-16));
    let mut integ = Dop853::with_dim(Dyn(2 * n), opts).unwrap();
    let t = std::time::Instant::now();
    integ
        .reset(&sys, 0.0, &DVector::from_vec(x0.clone()), false)
        .unwrap();
    let mut steps = 0;
    while integ.t() < 1e-3 {
        integ.step(&sys, 1e-3).unwrap();
        steps += 1;
    }
    let dop = t.elapsed();
    seg.state(1e-3, &mut x, &mut dx);
    let diff = (0..n)
        .map(|i| (x[i] - integ.y()[i]).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "S1 rotor (n = {n}): prepare {prepare:?}; segment start {start:?}; station r, r', r'' {kin:?}; bounds {bounds:?}; full state {full:?}; certified search over one revolution: {onset:?}, {} evaluations, {search:?}; DOP853 rtol 1e-10 over 1 ms: {steps} steps, {dop:?} (x 50 = one revolution), max |q| difference at 1 ms {diff:.2e} m ({acc:.1e})",
        stats.evaluations
    );
}

/// Case S1's first free flight, from rest to the first contact: the closed form and the
/// certified search against the shared reference (an independent implementation, DOP853 and
/// LSODA at rtol 1e-12, event times agreeing to 8e-11 s): its samples before the onset and
/// its first onset time.
#[test]
fn s1_first_free_flight_matches_the_reference() {
    use jeffcott::ring::onset::{find_onset, Onset, OnsetStats};
    use jeffcott::ring::{Relaxation, RingAxis};
    let form = Arc::new(s1_free_flight().prepare().unwrap());
    let n = form.dofs();
    let seg = form.segment(0.0, &vec![0.0; 2 * n]);
    let gap = 7.95e-5;
    // k_s = 1.1e6 N/m, c_s = 0.01 N s/m, no preload: the ring's K = k_s, nu2 = c_s / 2.
    let axis = RingAxis::new(1.1e6, 0.0);
    let ring = SnubberRing::new(axis, axis, 0.005, gap).unwrap();
    let mut stats = OnsetStats::default();
    let Onset::At(t_on) = find_onset(
        &seg,
        &Relaxation::at_rest(0.0),
        &ring,
        (0.0, 0.05),
        false,
        &mut stats,
    ) else {
        panic!("no contact found");
    };
    let reference_onset = 0.0048176775848062375;
    let csv = std::fs::read_to_string(data("S1_reference.csv")).unwrap();
    let mut worst = 0.0f64;
    for line in csv.lines().skip(1) {
        let v: Vec<f64> = line.split(',').map(|s| s.parse().unwrap()).collect();
        if v[0] >= t_on {
            break;
        }
        let (r, _, _) = seg.kinematics(v[0]);
        worst = worst.max((r.x - v[1]).abs().max((r.y - v[2]).abs()) / gap);
    }
    eprintln!(
        "S1 first free flight: onset at {t_on} s (reference {reference_onset}, difference {:.1e} s, {} evaluations); samples before it within {worst:.1e} of the gap",
        t_on - reference_onset,
        stats.evaluations
    );
    assert!((t_on - reference_onset).abs() < 1e-9, "{t_on}");
    assert!(worst < 1e-8, "{worst:e}");
}

/// Case S1 in full (0.5 s, 7 contacts) with exact free flight on the matrices' rotor above
/// (DOP853 at rtol 1e-10 in contact), against the shared reference: samples and contact
/// count. `cargo test --test suite s1_full -- --ignored --nocapture` (minutes: contact phases
/// are integrated at the stability limit of the 7.3e6 rad/s mode).
#[test]
#[ignore = "minutes"]
fn s1_full_run_with_exact_free_flight() {
    use jeffcott::ring::RingAxis;
    let exact = std::env::var("S1_INTEGRATED").is_err();
    let rotor = MatrixRotor {
        field: MatrixField::new(s1_free_flight()),
        closed: exact.then(s1_free_flight),
    };
    let gap = 7.95e-5;
    let axis = RingAxis::new(1.1e6, 0.0);
    let ring = SnubberRing::new(axis, axis, 0.005, gap).unwrap();
    let model = RingedRotor::new(rotor, ring).unwrap();
    let opts = SimOptions::default().with_rtol(1e-10);
    let plan = OutputPlan {
        t_end: 0.5,
        strobe: None,
        dense: Some(jeffcott::hybrid::DenseSampling {
            t_start: 0.0,
            dt: 0.0005,
        }),
        events: true,
    };
    let mut traj = Trajectory::default();
    let n = 136;
    let t = std::time::Instant::now();
    let stats = jeffcott::hybrid::simulate(
        &model,
        0.0,
        &DVector::zeros(2 * n + 2),
        &plan,
        &opts,
        &mut traj,
    )
    .unwrap();
    let wall = t.elapsed();
    let csv = std::fs::read_to_string(data("S1_reference.csv")).unwrap();
    let reference: Vec<Vec<f64>> = csv
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|s| s.parse().unwrap()).collect())
        .collect();
    let ix = 48;
    let mut worst = 0.0f64;
    for (s, r) in traj.samples.iter().zip(&reference) {
        assert!((s.t - r[0]).abs() < 1e-12);
        worst = worst.max((s.y[ix] - r[1]).abs().max((s.y[ix + 1] - r[2]).abs()) / gap);
    }
    let onsets: Vec<f64> = traj
        .events
        .iter()
        .filter(|e| e.kind == "contact onset")
        .map(|e| e.t)
        .collect();
    eprintln!(
        "S1 ({} free flight): {} samples, max |error| / gap {worst:.2e}, {} contacts at {onsets:?}; {wall:?}, {} steps, {} closed-form evaluations",
        if exact { "exact" } else { "integrated" },
        traj.samples.len(),
        onsets.len(),
        stats.steps,
        stats.exact_evals
    );
    assert_eq!(traj.samples.len(), reference.len());
    assert_eq!(onsets.len(), 7);
    assert!(worst < 1e-6, "{worst:e}");
}

#[test]
fn multipliers_with_exact_free_flight_match_integrated_free_flight() {
    use jeffcott::stability::{periodic_orbit, OrbitOptions};
    let ring = SnubberRing::isotropic(30.0, 0.05, 0.01).unwrap();
    // Unbalance 1.2: a period-1 orbit with several impacts a period (free flights between).
    let (settled, _) = run_ringed(two_node_rotor_forced(false, 1.2), 200);
    let start = settled.strobe.last().unwrap().y.clone();
    let opts = OrbitOptions::default();
    let mut results = Vec::new();
    for exact in [true, false] {
        let model = RingedRotor::new(two_node_rotor_forced(exact, 1.2), ring).unwrap();
        let t = std::time::Instant::now();
        let orbit = periodic_orbit(&model, &start, 1, &opts).unwrap();
        let onsets = orbit
            .events
            .iter()
            .filter(|e| e.kind == "contact onset")
            .count();
        eprintln!(
            "exact free flight {exact}: spectral radius {:.6}, {} events ({onsets} onsets), {} Newton iterations, {:?}",
            orbit.spectral_radius(),
            orbit.events.len(),
            orbit.iterations,
            t.elapsed()
        );
        results.push(orbit);
    }
    let (a, b) = (&results[0], &results[1]);
    let dz = (&a.point - &b.point).amax();
    let dm = a
        .multipliers
        .iter()
        .zip(&b.multipliers)
        .map(|(u, v)| (u.re - v.re).hypot(u.im - v.im))
        .fold(0.0, f64::max);
    eprintln!("periodic orbit: points differ by {dz:.1e}, multipliers by {dm:.1e}");
    assert!(a.events.iter().any(|e| e.kind == "contact onset"));
    assert!(dz < 1e-8 && dm < 1e-6, "{dz:e} {dm:e}");
}

/// Case S1 on `LinearRotor` with exact and with integrated free flight (Radau5, rtol = atol =
/// 1e-8 in contact, as `fe_s1`), against the shared reference: samples, event times, cost.
/// `S1_T_END` (s, default 0.5). `cargo test --test suite s1_linear_rotor -- --ignored --nocapture`.
#[test]
#[ignore = "about a minute (two runs of S1)"]
fn s1_linear_rotor_exact_and_integrated_free_flight() {
    use crate::fe::fe_s1::{event_error, reference, Run};
    use jeffcott::hybrid::DenseSampling;
    use jeffcott::ode::Method;
    use jeffcott::rotor::{LinearRotor, LinearSystem};
    let t_end: f64 = std::env::var("S1_T_END").map_or(0.5, |v| v.parse().unwrap());
    let gap = 7.95e-5;
    let lateral = RotorMatrices::from_ross_mat(data("rotor_example_with_damping_1200rpm.mat"))
        .unwrap()
        .lateral()
        .unwrap();
    let w = 1200.0 * std::f64::consts::TAU / 60.0;
    let x = lateral.x_dof(12).unwrap();
    let system = LinearSystem::from_matrices(&lateral, w)
        .unwrap()
        .with_unbalance(lateral.layout(), 12, 0.002, -std::f64::consts::FRAC_PI_2)
        .unwrap();
    let ring = SnubberRing::from_units(1.1e6, 0.01, [0.0, 0.0], gap).unwrap();
    let opts = SimOptions::default()
        .with_method(Method::Radau5)
        .with_rtol(1e-8)
        .with_atol(1e-8);
    let plan = OutputPlan {
        t_end,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: 0.0005,
        }),
        events: true,
    };
    let reference = reference(t_end);
    let mut runs = Vec::new();
    for exact in [true, false] {
        let t = std::time::Instant::now();
        let rotor = LinearRotor::new(system.clone(), [x, x + 1], [0.0, 0.0])
            .unwrap()
            .with_exact_free_flight(exact);
        let model = rotor.ringed(ring).unwrap();
        let build = t.elapsed().as_secs_f64();
        assert_eq!(model.closed_form().is_some(), exact);
        let mut trajectory = Trajectory::default();
        let t = std::time::Instant::now();
        let y0 = model.rotor().rest_state();
        let stats =
            jeffcott::hybrid::simulate(&model, 0.0, &y0, &plan, &opts, &mut trajectory).unwrap();
        let run = Run {
            trajectory,
            stats,
            seconds: t.elapsed().as_secs_f64(),
        };
        let worst = run
            .trajectory
            .samples
            .iter()
            .zip(&reference)
            .map(|(s, r)| (s.y[x] - r[1]).hypot(s.y[x + 1] - r[2]) / gap)
            .fold(0.0, f64::max);
        let dt_event = event_error(&run, t_end);
        eprintln!(
            "S1 to {t_end} s, Radau5 rtol 1e-8, {} free flight: build {build:.2} s, run {:.2} s, {} steps, {} rhs, {} closed-form evaluations, {} transitions; max error {worst:.2e} gap, events within {dt_event:.1e} s",
            if exact { "exact" } else { "integrated" },
            run.seconds,
            run.stats.steps,
            run.stats.rhs_evals,
            run.stats.exact_evals,
            run.stats.transitions
        );
        assert_eq!(run.trajectory.samples.len(), reference.len());
        assert!(worst <= 1e-6, "{worst:e}");
        runs.push(run);
    }
    let diff = runs[0]
        .trajectory
        .samples
        .iter()
        .zip(&runs[1].trajectory.samples)
        .map(|(a, b)| (a.y[x] - b.y[x]).hypot(a.y[x + 1] - b.y[x + 1]) / gap)
        .fold(0.0, f64::max);
    eprintln!("exact against integrated free flight: max difference {diff:.2e} gap");
}

#[test]
fn a_refused_closed_form_leaves_free_flight_integrated() {
    // The critically damped Jeffcott rotor as matrices: RingedRotor keeps the refusal and
    // integrates, and the run meets the ring as the paper's model does.
    use jeffcott::hybrid::{Flow, RotorModel};
    use jeffcott::ring::RingMode;
    let p = Params {
        nu1: 1.0,
        eta: 2.0,
        beta: 0.5,
        ..Preset::Fig8a.params()
    };
    let lf = jeffcott_as_matrices(&p);
    let rotor = MatrixRotor {
        closed: Some(lf.clone()),
        field: MatrixField::new(lf),
    };
    let ring = SnubberRing::isotropic(30.0, 0.0, 0.002).unwrap();
    let model = RingedRotor::new(rotor, ring).unwrap();
    assert!(matches!(
        model.closed_form(),
        Some(Err(RotorError::IllConditionedModes { .. }))
    ));
    let y0 = DVector::zeros(6);
    let free = model.initial_mode(0.0, &y0).unwrap();
    assert!(matches!(free, RingMode::Free { .. }));
    assert_eq!(model.flow(free), Flow::Integrated);
    let plan = OutputPlan {
        events: true,
        ..OutputPlan::strobe(std::f64::consts::TAU / p.eta, 0, 20)
    };
    let mut traj = Trajectory::default();
    let stats =
        jeffcott::hybrid::simulate(&model, 0.0, &y0, &plan, &SimOptions::default(), &mut traj)
            .unwrap();
    assert!(stats.transitions > 0 && stats.exact_evals == 0);
}

/// A two-DOF rotor (mass `m`, damping `c`, stiffness `k` per axis) with an unbalance force
/// `f` (N, forward at the speed) and a constant force `g` along y, the ring at both DOFs.
fn forced_pair(m: f64, c: f64, k: f64, speed: f64, f: f64, g: f64) -> jeffcott::rotor::LinearRotor {
    let eye = DMatrix::<f64>::identity(2, 2);
    let system = LinearSystem::from_parts(
        &eye * m,
        &eye * c,
        &eye * k,
        speed,
        DVector::from_vec(vec![Complex::new(f, 0.0), Complex::new(0.0, -f)]),
        DVector::from_vec(vec![0.0, g]),
    )
    .unwrap();
    jeffcott::rotor::LinearRotor::new(system, [0, 1], [0.0, 0.0]).unwrap()
}

/// Issue 31, finding 3: valid rotors whose forcing dwarfs a column of the state matrix are
/// accepted with their closed form (before: `LinearMismatch`, 2.8e-17 against a tolerance of
/// 1e-17, the column lost to cancellation against the forcing), as `ModalRotor` accepts them:
/// mass 10, stiffness 1e6 and damping 1e-8 and 1e-10 per axis with an unbalance of 1e-4 kg m
/// at 300 rad/s (9 N), gap 1e-4; and a stiffness of 1e-13 under a constant force, whose
/// closed form then passes the self-check but is refused for its rounding (a static deflection
/// of 2e12 gaps: `ClosedFormRounding`, free flight integrated).
#[test]
fn forcing_that_dwarfs_a_column_is_accepted() {
    let ring = SnubberRing::from_units(1e6, 10.0, [0.0, 0.0], 1e-4).unwrap();
    let light = |c: f64| forced_pair(10.0, c, 1e6, 300.0, 1e-4 * 300.0 * 300.0, 0.0);
    let soft = forced_pair(1.0, 0.5, 1e-13, 1.0, 0.1, 0.2);
    let soft_ring = SnubberRing::from_units(10.0, 0.1, [0.0, 0.0], 1.0).unwrap();
    for (name, rotor, ring, rounded) in [
        ("damping 1e-8", light(1e-8), ring, false),
        ("damping 1e-10", light(1e-10), ring, false),
        ("stiffness 1e-13", soft, soft_ring, true),
    ] {
        jeffcott::rotor::ModalRotor::new(&rotor)
            .unwrap_or_else(|e| panic!("{name}: modal form {e}"))
            .ringed(ring)
            .unwrap_or_else(|e| panic!("{name}: modal {e}"));
        let model = rotor.ringed(ring).unwrap_or_else(|e| panic!("{name}: {e}"));
        let form = model.closed_form();
        let ok = if rounded {
            matches!(form, Some(Err(RotorError::ClosedFormRounding { .. })))
        } else {
            matches!(form, Some(Ok(_)))
        };
        assert!(ok, "{name}: {:?}", form.map(|r| r.err()));
    }
}
