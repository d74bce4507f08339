//! `Etd4`'s dense output is as accurate as its steps (issue 31, class L1 of the linear-rotor
//! fuzzer): on a rotor whirling against a ring (a contact force in the rest $N$), the error
//! at points inside the steps is within a small factor of the error at the steps' ends, at
//! every tolerance. The truth is DOP853 at `rtol = atol = 1e-13` landing on each point.

use jeffcott::nalgebra::{Complex, SVector, U2};
use jeffcott::ode::{
    BlockForcing, DiagonalLinearPart, Dop853, Etd4, Integrator, OdeSystem, Options,
};

type V2 = SVector<f64, 2>;
type C = Complex<f64>;

/// A Jeffcott rotor in complex form, $u = x + iy$, pressed against a ring of stiffness $k$ and
/// radius $g$ all along the run: $u^\prime = \lambda u + A e^{i\omega t} + N(u)$ with the
/// unbalance $A e^{i\omega t}$ declared in the linear part and the contact force
/// $N(u) = -k(|u| - g)\thinspace u/|u|$ the rest (smooth while $|u| > g$; the test checks it
/// is). $\lambda = -0.02 + i$, $\omega = 1.9$ (above the natural frequency, as in the
/// fuzzer's minimal case), $A = \omega^2$, $k = 0.15$, $g = 0.4$.
struct Whirl {
    lambda: C,
    omega: f64,
    amplitude: f64,
    k: f64,
    gap: f64,
    lp: DiagonalLinearPart,
}

impl Whirl {
    fn new() -> Self {
        let (lambda, omega) = (C::new(-0.02, 1.0), 1.9);
        let amplitude = omega * omega;
        let unbalance = BlockForcing {
            cos: C::new(amplitude, 0.0),
            sin: C::new(0.0, amplitude),
            constant: C::new(0.0, 0.0),
        };
        let lp = DiagonalLinearPart::new(2, &[], &[(0, lambda)])
            .unwrap()
            .with_forcing(omega, &[(0, unbalance)])
            .unwrap();
        Self {
            lambda,
            omega,
            amplitude,
            k: 0.15,
            gap: 0.4,
            lp,
        }
    }
}

impl OdeSystem<U2> for Whirl {
    fn rhs(&self, t: f64, y: &V2, dy: &mut V2) {
        let u = C::new(y[0], y[1]);
        let r = u.norm();
        let contact = -self.k * (r - self.gap) / r * u;
        let forcing = self.amplitude * C::new(0.0, self.omega * t).exp();
        let d = self.lambda * u + forcing + contact;
        dy[0] = d.re;
        dy[1] = d.im;
    }
    fn linear_part(&self) -> Option<&DiagonalLinearPart> {
        Some(&self.lp)
    }
}

/// The largest errors of ETD4 at `tol` over $[0, 30]$ from $u(0) = 1.5$: at the steps' ends
/// and at 7 points inside each step (its eighths), against DOP853 at 1e-13; and the smallest
/// $|u|$ seen (the contact must hold).
fn errors(sys: &Whirl, tol: f64) -> (f64, f64, f64) {
    let (y0, t_end) = (V2::new(1.5, 0.0), 30.0);
    let mut etd = Etd4::new(Options::default().with_rtol(tol).with_atol(tol)).unwrap();
    let fine = Options::default().with_rtol(1e-13).with_atol(1e-13);
    let mut truth = Dop853::new(fine).unwrap();
    etd.reset(sys, 0.0, &y0, false).unwrap();
    truth.reset(sys, 0.0, &y0, false).unwrap();
    let (mut at_ends, mut inside, mut r_min, mut out) =
        (0.0f64, 0.0f64, f64::INFINITY, V2::zeros());
    let mut truth_at = |t: f64| {
        while truth.t() < t {
            truth.step(sys, t).unwrap();
        }
        *truth.y()
    };
    while etd.t() < t_end {
        etd.step(sys, t_end).unwrap();
        let (t0, t1) = (etd.t_prev(), etd.t());
        for k in 1..8 {
            let t = t0 + (k as f64 / 8.0) * (t1 - t0);
            etd.dense(sys, t, &mut out);
            let want = truth_at(t);
            inside = inside.max((out - want).norm());
            r_min = r_min.min(want.norm());
        }
        let want = truth_at(t1);
        at_ends = at_ends.max((etd.y() - want).norm());
        r_min = r_min.min(want.norm());
    }
    (at_ends, inside, r_min)
}

/// At `rtol = atol` from 1e-5 to 1e-10 the error is within 3 tol inside the steps and 1 tol
/// at their ends, not growing as the tolerance tightens. Before issue 31's fix (class L1) it
/// was 26 to 250 tol inside the steps and 8.9 to 85 at their ends, growing like
/// $\mathrm{tol}^{-1/5}$: the steps kept the two half steps' result (local error of the size
/// of the estimate, so the global error grew with the number of steps) and the dense output
/// interpolated $N$ by the quadratic through one half step's stages (local error $O(h^4)$, one
/// order below the steps', about 3 times their error here).
#[test]
fn the_errors_follow_the_tolerance_in_contact() {
    let sys = Whirl::new();
    for tol in [1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10] {
        let (at_ends, inside, r_min) = errors(&sys, tol);
        println!(
            "tol {tol:.0e}: steps' ends {:.3} tol, inside {:.3} tol, |u| >= {r_min:.3}",
            at_ends / tol,
            inside / tol,
        );
        assert!(r_min > sys.gap, "contact lost: |u| = {r_min}");
        assert!(
            inside <= 3.0 * tol && at_ends <= tol,
            "tol {tol:e}: inside the steps {inside:e}, at their ends {at_ends:e}"
        );
    }
}

/// [`Whirl`] with a right-hand side that is not finite past `t_fail`: every step that reaches
/// past it is refused, until the step size underflows.
struct Failing {
    whirl: Whirl,
    t_fail: f64,
}

impl OdeSystem<U2> for Failing {
    fn rhs(&self, t: f64, y: &V2, dy: &mut V2) {
        self.whirl.rhs(t, y, dy);
        if t > self.t_fail {
            dy.fill(f64::NAN);
        }
    }
    fn linear_part(&self) -> Option<&DiagonalLinearPart> {
        Some(&self.whirl.lp)
    }
}

/// The dense output reuses the accepted trial's $\varphi$-functions and forcing increments
/// (issue 32), which a later trial overwrites: after a step that fails (its trials refused
/// until the step size underflows), the dense output on the last accepted step is the one it
/// gave before that step, bit for bit, at each eighth of the step. The truth is a clone of
/// the integrator taken before the failing step.
#[test]
fn a_failed_step_leaves_the_dense_output_of_the_accepted_one() {
    let sys = Failing {
        whirl: Whirl::new(),
        t_fail: 2.0,
    };
    let mut etd = Etd4::new(Options::default().with_rtol(1e-8).with_atol(1e-8)).unwrap();
    etd.reset(&sys, 0.0, &V2::new(1.5, 0.0), false).unwrap();
    let mut before = etd.clone();
    let mut steps = 0;
    while etd.step(&sys, 10.0).is_ok() {
        before = etd.clone();
        steps += 1;
        assert!(steps < 100_000, "the failing step never came");
    }
    assert!(steps > 0 && etd.t() <= sys.t_fail);
    let (t0, t1) = (etd.t_prev(), etd.t());
    let (mut want, mut got) = (V2::zeros(), V2::zeros());
    for k in 1..8 {
        let t = t0 + (k as f64 / 8.0) * (t1 - t0);
        before.dense(&sys, t, &mut want);
        etd.dense(&sys, t, &mut got);
        assert_eq!(got, want, "at t = {t}");
    }
}
