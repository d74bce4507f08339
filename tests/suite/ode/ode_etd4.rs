//! The exponential integrator `Etd4` against closed forms: exact for the linear part and a
//! constant force whatever the stiffness, fourth order with a harmonic force and with a
//! state-dependent rest, dense output, events, and its refusals. Every truth is a closed form
//! of a scalar or complex linear equation (written out in each test).

use jeffcott::nalgebra::{Complex, SVector, U2};
use jeffcott::numeric::Direction;
use jeffcott::ode::{
    find_first_event, phi_functions, phi_functions_to, DiagonalLinearPart, Etd4, EventFns,
    EventOptions, EventState, Integrator, OdeError, OdeSystem, Options,
};

type V2 = SVector<f64, 2>;
type C = Complex<f64>;

/// $u^\prime = \lambda u + a + b e^{i\omega t} + \mu u$ for $u = y_0 + i y_1$, split as
/// $L = \lambda$ (a complex block) and $N = a + b e^{i\omega t} + \mu u$.
struct Pair {
    lambda: C,
    a: C,
    b: C,
    omega: f64,
    mu: C,
    lp: DiagonalLinearPart,
}

impl Pair {
    fn new(lambda: C, a: C, b: C, omega: f64, mu: C) -> Self {
        let lp = DiagonalLinearPart::new(2, &[], &[(0, lambda)]).unwrap();
        Self {
            lambda,
            a,
            b,
            omega,
            mu,
            lp,
        }
    }

    /// The closed form from $u(0) = u_0$: with $\kappa = \lambda + \mu$,
    /// $u = e^{\kappa t}u_0 + a(e^{\kappa t} - 1)/\kappa + b(e^{i\omega t} - e^{\kappa t})/(i\omega - \kappa)$.
    fn exact(&self, t: f64, u0: C) -> C {
        let k = self.lambda + self.mu;
        let e = (k * t).exp();
        let iw = C::new(0.0, self.omega);
        e * u0 + self.a * (e - 1.0) / k + self.b * ((iw * t).exp() - e) / (iw - k)
    }
}

impl OdeSystem<U2> for Pair {
    fn rhs(&self, t: f64, y: &V2, dy: &mut V2) {
        let u = C::new(y[0], y[1]);
        let d = (self.lambda + self.mu) * u + self.a + self.b * C::new(0.0, self.omega * t).exp();
        dy[0] = d.re;
        dy[1] = d.im;
    }
    fn linear_part(&self) -> Option<&DiagonalLinearPart> {
        Some(&self.lp)
    }
}

fn at(integ: &Etd4<U2>) -> C {
    C::new(integ.y()[0], integ.y()[1])
}

/// Runs to `t_end`; returns the integrator.
fn run(sys: &Pair, u0: C, t_end: f64, opts: Options<U2>) -> Etd4<U2> {
    let mut integ = Etd4::new(opts).unwrap();
    integ
        .reset(sys, 0.0, &V2::new(u0.re, u0.im), false)
        .unwrap();
    while integ.t() < t_end {
        integ.step(sys, t_end).unwrap();
    }
    integ
}

/// A stiff mode ($\lambda = -10^6 + 3\cdot 10^5 i$, $|\lambda h| \sim 10^5$) under a constant
/// force: exact to rounding in a handful of steps, at every step's end and dense point (an
/// explicit method would need $10^6$ steps; Lawson's method is off by $O(1)$ at such steps).
#[test]
fn a_stiff_mode_under_a_constant_force_is_exact_in_a_few_steps() {
    let sys = Pair::new(
        C::new(-1e6, 3e5),
        C::new(2.0, 1.0),
        C::new(0.0, 0.0),
        1.0,
        C::new(0.0, 0.0),
    );
    let u0 = C::new(1.0, -1.0);
    let mut integ = run(&sys, u0, 1.0, Options::with_tol(1e-8, 1e-10));
    let exact = sys.exact(1.0, u0);
    assert!(
        (at(&integ) - exact).norm() <= 1e-14 * exact.norm(),
        "{}",
        (at(&integ) - exact).norm()
    );
    assert!(integ.stats().steps <= 40, "{} steps", integ.stats().steps);
    let (t0, t1) = (integ.t_prev(), integ.t());
    let mut out = V2::zeros();
    for theta in [0.1, 0.5, 0.77] {
        let t = t0 + theta * (t1 - t0);
        integ.dense(&sys, t, &mut out);
        let e = sys.exact(t, u0);
        assert!((C::new(out[0], out[1]) - e).norm() <= 1e-14 * e.norm());
    }
}

/// Error at $t = 1$ with steps of `h` (every step accepted: huge tolerances, `h_max = h`).
fn error_with_step(sys: &Pair, u0: C, h: f64) -> f64 {
    let opts = Options::with_tol(1e6, 1e6).with_h_init(h).with_h_max(h);
    let integ = run(sys, u0, 1.0, opts);
    (at(&integ) - sys.exact(1.0, u0)).norm()
}

fn observed_orders(sys: &Pair, u0: C, h0: f64) -> Vec<f64> {
    let errs: Vec<f64> = (0..4)
        .map(|k| error_with_step(sys, u0, h0 / 2f64.powi(k)))
        .collect();
    errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

/// A harmonic force on a lightly damped fast mode ($\lambda = -2 + 30i$, $\omega = 5$): at
/// least fifth order (the error falls 32-fold or more per halved step). The step keeps the
/// local extrapolation of its two half steps (order 5; issue 31, class L1); measured 7.3,
/// 6.2, 6.05 (then 6.0 and 5.5 at two more halvings, near rounding). Before, fourth order.
#[test]
fn a_harmonic_force_is_integrated_at_fifth_order() {
    let sys = Pair::new(
        C::new(-2.0, 30.0),
        C::new(0.0, 0.0),
        C::new(1.0, 0.5),
        5.0,
        C::new(0.0, 0.0),
    );
    let orders = observed_orders(&sys, C::new(0.3, 0.0), 0.2);
    println!("orders {orders:?}");
    for p in &orders {
        assert!((4.6..=7.5).contains(p), "orders {orders:?}");
    }
}

/// A rest that depends on the state ($N = \mu u$, $\mu = 3 - 2i$) beside a stiff linear part
/// ($\lambda = -50$): fifth order, the truth $e^{(\lambda + \mu)t}u_0$. Measured 6.2, 5.1,
/// 4.70 (then 4.83 and 4.92 at two more halvings: tending to 5 as $h\lambda$ shrinks).
/// Before the local extrapolation (issue 31, class L1), fourth order.
#[test]
fn a_state_dependent_rest_is_integrated_at_fifth_order() {
    let sys = Pair::new(
        C::new(-50.0, 0.0),
        C::new(0.0, 0.0),
        C::new(0.0, 0.0),
        1.0,
        C::new(3.0, -2.0),
    );
    let orders = observed_orders(&sys, C::new(1.0, 0.5), 0.05);
    println!("orders {orders:?}");
    for p in &orders {
        assert!((4.6..=7.5).contains(p), "orders {orders:?}");
    }
}

/// With error control: each accepted step's local error is within the tolerance (here
/// $\mathrm{atol} + \mathrm{rtol}|y| < 2\,\mathrm{tol}$, $|y| < 1$), and the problem contracts
/// ($\operatorname{Re}(\lambda + \mu) = -1.5$), so the global error is at most the sum of the
/// local ones, $2\,\mathrm{tol}$ times the steps; tighter tolerances give smaller errors.
#[test]
fn the_step_control_meets_its_tolerance() {
    let sys = Pair::new(
        C::new(-2.0, 30.0),
        C::new(0.1, 0.0),
        C::new(1.0, 0.5),
        5.0,
        C::new(0.5, 0.0),
    );
    let u0 = C::new(0.3, 0.0);
    let mut last = f64::INFINITY;
    for tol in [1e-6, 1e-8, 1e-10] {
        let integ = run(&sys, u0, 1.0, Options::with_tol(tol, tol));
        let err = (at(&integ) - sys.exact(1.0, u0)).norm();
        println!("tol {tol:e}: error {err:e}, {} steps", integ.stats().steps);
        let steps = integ.stats().steps as f64;
        assert!(err <= 2.0 * steps * tol, "tol {tol:e}: error {err:e}");
        assert!(err < last);
        last = err;
    }
}

/// $y^\prime = -y + 2$ from 0 (a real block, $\lambda = -1$): $y = 2(1 - e^{-t})$ crosses 1 at
/// $\ln 2$; the event is found there (the dense output is exact for a constant force).
#[test]
fn an_event_is_located_on_the_dense_output() {
    struct Relax(DiagonalLinearPart);
    impl OdeSystem<U2> for Relax {
        fn rhs(&self, _t: f64, y: &V2, dy: &mut V2) {
            dy[0] = -y[0] + 2.0;
            dy[1] = 0.0;
        }
        fn linear_part(&self) -> Option<&DiagonalLinearPart> {
            Some(&self.0)
        }
    }
    let sys = Relax(DiagonalLinearPart::new(2, &[(0, -1.0)], &[]).unwrap());
    let events = EventFns::new(vec![Direction::Rising], |_i, _t, y: &V2| y[0] - 1.0);
    let mut integ = Etd4::new(Options::with_tol(1e-6, 1e-6)).unwrap();
    integ.reset(&sys, 0.0, &V2::zeros(), false).unwrap();
    let mut state = EventState::new();
    let hit = loop {
        integ.step(&sys, 10.0).unwrap();
        if let Some(hit) = find_first_event(
            &mut integ,
            &sys,
            &events,
            &EventOptions::default(),
            &mut state,
        )
        .unwrap()
        {
            break hit;
        }
        assert!(integ.t() < 10.0, "no event");
    };
    assert!((hit.t - 2f64.ln()).abs() < 1e-12, "{}", hit.t - 2f64.ln());
    integ.truncate(&sys, hit.t).unwrap();
    assert!((integ.y()[0] - 1.0).abs() < 1e-12);
}

/// A system without a linear part, or with one of another size, is refused with a typed
/// error; so are fixed steps and an invalid linear part.
#[test]
fn refusals_are_typed() {
    let plain = |_t: f64, y: &V2, dy: &mut V2| {
        dy[0] = y[1];
        dy[1] = -y[0];
    };
    let mut integ = Etd4::<U2>::new(Options::default()).unwrap();
    assert_eq!(
        integ.reset(&plain, 0.0, &V2::zeros(), false),
        Err(OdeError::NoLinearPart)
    );
    struct Wrong(DiagonalLinearPart);
    impl OdeSystem<U2> for Wrong {
        fn rhs(&self, _t: f64, _y: &V2, dy: &mut V2) {
            dy.fill(0.0);
        }
        fn linear_part(&self) -> Option<&DiagonalLinearPart> {
            Some(&self.0)
        }
    }
    let wrong = Wrong(DiagonalLinearPart::new(3, &[], &[]).unwrap());
    assert!(matches!(
        integ.reset(&wrong, 0.0, &V2::zeros(), false),
        Err(OdeError::DimensionMismatch {
            field: "linear_part",
            expected: 2,
            found: 3
        })
    ));
    assert!(matches!(
        Etd4::<U2>::new(Options::default().with_fixed_step(0.1)),
        Err(OdeError::InvalidOption {
            field: "fixed_step",
            ..
        })
    ));
    for (real, complex) in [
        (vec![(2, -1.0)], vec![]),
        (vec![(0, -1.0)], vec![(0, C::new(-1.0, 1.0))]),
        (vec![], vec![(1, C::new(-1.0, 1.0))]),
        (vec![(0, f64::NAN)], vec![]),
    ] {
        assert!(matches!(
            DiagonalLinearPart::new(2, &real, &complex),
            Err(OdeError::InvalidLinearPart { .. })
        ));
    }
}

/// $\varphi_k(z) = \sum_j z^j/(j + k)!$ summed term by term (60 terms): exact to rounding for
/// real positive $z$ up to 10, where no term cancels.
fn phi_series(z: f64, k: usize) -> f64 {
    let mut term: f64 = (1..=k).map(|j| 1.0 / j as f64).product();
    let mut sum = 0.0;
    for j in 0..60 {
        sum += term;
        term *= z / (j + k + 1) as f64;
    }
    sum
}

/// $\varphi_k(z)$ on both sides of the switch from the series to the recurrence ($|z| = 1$)
/// and of the series' shorter forms (11 terms below $|z| = 1/8$, 15 below $1/2$; issue 32),
/// against the series summed term by term for real positive $z$ (no cancellation there) and
/// against the defining relation $\varphi_{k}(z) = z\varphi_{k+1}(z) + 1/k!$.
#[test]
fn phi_functions_are_accurate_across_their_switch() {
    let bands = [0.01, 0.124_999, 0.125_001, 0.3, 0.499_999, 0.500_001];
    for z in bands.into_iter().chain([0.999_999, 1.000_001, 2.5, 10.0]) {
        let p = phi_functions(C::new(z, 0.0));
        for k in 0..4 {
            let want = phi_series(z, k);
            assert!((p[k].re - want).abs() <= 1e-14 * want, "z {z}, k {k}");
        }
    }
    for z in [
        C::new(0.06, -0.1),
        C::new(-0.3, 0.35),
        C::new(-0.7, 0.6),
        C::new(-3.0, 40.0),
        C::new(-1e5, 2e3),
        C::new(0.0, 1.0),
    ] {
        let p = phi_functions(z);
        let fact = [1.0, 1.0, 0.5];
        for k in 0..3 {
            let rebuilt = z * p[k + 1] + fact[k];
            assert!(
                (rebuilt - p[k]).norm() <= 1e-14 * p[k].norm().max(1.0),
                "z {z}, k {k}"
            );
        }
    }
}

/// $\varphi_4$ and $\varphi_5$ of `phi_functions_to::<6>` (ETD4's dense output) on both sides
/// of the switch, against the series as above, and the first four equal to `phi_functions`'
/// (the same code). The recurrence downwards loses more near $|z| = 1$ for higher $k$: the
/// largest relative error is printed (measured 3.7e-14) and bounded by `5e-14`.
#[test]
fn higher_phi_functions_are_accurate_across_their_switch() {
    let mut worst = 0.0f64;
    for z in [0.1, 0.3, 0.999_999, 1.000_001, 2.5, 10.0] {
        let p = phi_functions_to::<6>(C::new(z, 0.0));
        assert_eq!(p[..4], phi_functions(C::new(z, 0.0)));
        for (k, pk) in p.iter().enumerate() {
            let want = phi_series(z, k);
            worst = worst.max((pk.re - want).abs() / want);
        }
    }
    println!("largest relative error {worst:.1e}");
    assert!(worst <= 5e-14, "{worst:e}");
}
