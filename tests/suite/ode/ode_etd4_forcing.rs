//! `Etd4` with a forcing declared in the linear part (`DiagonalLinearPart::with_forcing`,
//! issue 31 finding 2): the forcing is carried exactly, whatever its frequency against the
//! steps, at resonance too, so only the rest $N$ sets the steps; a forcing left in $N$ must be
//! resolved by the steps (the limitation, pinned); the declaration's checks. Every truth is the
//! closed form of a scalar or complex linear equation, written out in each test.

use jeffcott::nalgebra::{Complex, SVector, U2, U5};
use jeffcott::ode::{
    BlockForcing, DiagonalLinearPart, Etd4, Integrator, OdeError, OdeSystem, Options,
};

type C = Complex<f64>;
type V2 = SVector<f64, 2>;
type V5 = SVector<f64, 5>;

const I: C = C::new(0.0, 1.0);

/// Issue 31's probe: $u^\prime = (\lambda + \mu) u + e^{i\omega t}$ for $u = y_0 + i y_1$,
/// $\lambda = -0.1 + i$, with $L = \lambda$ and the forcing $e^{i\omega t}$ ($a = 1$, $b = i$)
/// declared or not; the rest is $N = \mu u$.
struct Probe {
    lambda: C,
    mu: C,
    omega: f64,
    lp: DiagonalLinearPart,
}

impl Probe {
    fn new(omega: f64, mu: C, declared: bool) -> Self {
        let lambda = C::new(-0.1, 1.0);
        let lp = DiagonalLinearPart::new(2, &[], &[(0, lambda)]).unwrap();
        let rotating = BlockForcing {
            cos: C::new(1.0, 0.0),
            sin: I,
            constant: C::new(0.0, 0.0),
        };
        let lp = match declared {
            true => lp.with_forcing(omega, &[(0, rotating)]).unwrap(),
            false => lp,
        };
        Self {
            lambda,
            mu,
            omega,
            lp,
        }
    }

    /// The closed form from $u(0) = u_0$: with $\kappa = \lambda + \mu$ and
    /// $c = 1/(i\omega - \kappa)$, $u(t) = e^{\kappa t}(u_0 - c) + c\thinspace e^{i\omega t}$.
    fn exact(&self, t: f64, u0: C) -> C {
        let k = self.lambda + self.mu;
        let c = 1.0 / (I * self.omega - k);
        (k * t).exp() * (u0 - c) + c * (I * self.omega * t).exp()
    }
}

impl OdeSystem<U2> for Probe {
    fn rhs(&self, t: f64, y: &V2, dy: &mut V2) {
        let u = C::new(y[0], y[1]);
        let d = (self.lambda + self.mu) * u + (I * self.omega * t).exp();
        dy[0] = d.re;
        dy[1] = d.im;
    }
    fn linear_part(&self) -> Option<&DiagonalLinearPart> {
        Some(&self.lp)
    }
}

/// The largest error of a run of `sys` from $u(0) = 0.5$ over $[0, 20]$ at rtol = atol = `tol`,
/// at every step's end and at two dense points inside every step, against the closed form,
/// over the solution's size there (at least $|u_0|$); and the accepted steps.
fn probe_error(sys: &Probe, tol: f64, opts: Options<U2>) -> (f64, u64) {
    let (u0, t_end) = (C::new(0.5, 0.0), 20.0);
    let mut integ = Etd4::new(opts.with_rtol(tol).with_atol(tol)).unwrap();
    integ
        .reset(sys, 0.0, &V2::new(u0.re, u0.im), false)
        .unwrap();
    let (mut worst, mut size, mut out) = (0.0f64, u0.norm(), V2::zeros());
    while integ.t() < t_end {
        integ.step(sys, t_end).unwrap();
        let (t0, t1) = (integ.t_prev(), integ.t());
        for theta in [0.37, 0.81] {
            let t = t0 + theta * (t1 - t0);
            integ.dense(sys, t, &mut out);
            worst = worst.max((C::new(out[0], out[1]) - sys.exact(t, u0)).norm());
            size = size.max(sys.exact(t, u0).norm());
        }
        let y = integ.y();
        worst = worst.max((C::new(y[0], y[1]) - sys.exact(t1, u0)).norm());
    }
    (worst / size, integ.stats().steps)
}

/// The probe with its forcing declared, at $\omega = 1$, $10^2$, $10^4$ (issue 31's case:
/// with the forcing in $N$ the run was up to 1.19 off a solution of size 0.5) and $10^6$:
/// within 10 tol of the solution's size at every step's end and dense point. The rest is 0,
/// so every step is exact and the error is rounding (measured: at most 9e-15 of the size, in
/// 4 or 5 steps).
#[test]
fn a_declared_forcing_is_exact_whatever_its_frequency() {
    let tol = 1e-4;
    for omega in [1.0, 1e2, 1e4, 1e6] {
        let sys = Probe::new(omega, C::new(0.0, 0.0), true);
        let (err, steps) = probe_error(&sys, tol, Options::default());
        println!("declared, omega {omega:e}: error {err:.2e} of the size, {steps} steps");
        assert!(err <= 10.0 * tol, "omega {omega:e}: error {err:e}");
    }
}

/// A rest beside the declared forcing, $N = \mu u$ with $\mu = -0.3 + 0.2i$ (contracting,
/// $\operatorname{Re}(\lambda + \mu) = -0.4$, so that local errors do not grow): $u$ carries
/// the forced response $e^{i\omega t}/(i\omega - \lambda - \mu)$, so $N$ oscillates at
/// $\omega$ too, with the amplitude $|\mu|/\omega$. Where the steps the tolerance asks for
/// resolve it ($\omega = 1$), or when they are capped at a quarter of its period
/// ($\omega = 10^2$, $10^3$, $10^4$), the error is within 10 tol. Without the cap at
/// $\omega = 10^2$ it is not (the limitation of `Etd4`'s "Error and step size", pinned:
/// measured 1.2e-2 of the size, 119 tol, in 32 steps; 9.7e-3 in 33 before issue 32's
/// reordered rounding flipped one step's acceptance, 8.5e-3 in 30 before the local
/// extrapolation of issue 31, class L1): the rest's oscillation is left to the
/// steps, and the step doubling does not see a step that skips it.
#[test]
fn a_rest_that_inherits_the_forcing_must_be_resolved_by_the_steps() {
    let (tol, mu) = (1e-4, C::new(-0.3, 0.2));
    for (omega, cap) in [(1.0, false), (1e2, true), (1e3, true), (1e4, true)] {
        let sys = Probe::new(omega, mu, true);
        let opts = match cap {
            true => Options::default().with_h_max(0.25 * std::f64::consts::TAU / omega),
            false => Options::default(),
        };
        let (err, steps) = probe_error(&sys, tol, opts);
        println!("rest, omega {omega:e}, cap {cap}: error {err:.2e} of the size, {steps} steps");
        assert!(err <= 10.0 * tol, "omega {omega:e}: error {err:e}");
    }
    let sys = Probe::new(1e2, mu, true);
    let (err, steps) = probe_error(&sys, tol, Options::default());
    println!("rest, omega 1e2, no cap: error {err:.2e} of the size, {steps} steps");
    assert!(
        err > 10.0 * tol,
        "error {err:e}: the limitation is gone, update the docs"
    );
}

/// The same probe with the forcing left in $N$ (not declared) and the steps capped at a
/// quarter of its period (`h_max`, as `hybrid::simulate` caps them): the steps resolve the
/// forcing and the error is within 10 tol, at $\omega$ up to $10^4$ ($10^6$ would take
/// $10^7$ steps).
#[test]
fn an_undeclared_forcing_is_met_when_the_steps_resolve_it() {
    let tol = 1e-4;
    for omega in [1.0, 1e2, 1e4] {
        let sys = Probe::new(omega, C::new(0.0, 0.0), false);
        let quarter = 0.25 * std::f64::consts::TAU / omega;
        let (err, steps) = probe_error(&sys, tol, Options::default().with_h_max(quarter));
        println!("omega {omega:e}, h_max a quarter period: error {err:.2e}, {steps} steps");
        assert!(err <= 10.0 * tol, "omega {omega:e}: error {err:e}");
    }
}

/// The limitation, pinned (`Etd4`'s "Error and step size"): a fast forcing left in $N$ without
/// a cap on the steps is not resolved and the step-doubling estimate does not see it (its
/// samples at $t + kh/4$ alias the forcing), so the run is wrong by far more than the
/// tolerance. Measured: up to 1.19 off a solution of size 0.5 (2.4 of its size), 1 035 steps
/// (813 rejected) with $\omega h$ up to 9 900; since the steps keep their local extrapolation
/// (issue 31, class L1), 0.40 of its size in 5 905 steps: still 4 000 tol, so the bound is
/// now a tenth of the size (1 000 tol; it was the size). If this starts to fail, the estimate
/// has learnt to see an unresolved forcing: update `Etd4`'s documentation and this test.
#[test]
fn an_undeclared_fast_forcing_without_a_step_cap_is_not_seen() {
    let sys = Probe::new(1e4, C::new(0.0, 0.0), false);
    let (err, steps) = probe_error(&sys, 1e-4, Options::default());
    println!("undeclared, omega 1e4, no cap: error {err:.2e} of the size, {steps} steps");
    assert!(
        err > 0.1,
        "error {err:e}: the limitation is gone, update the docs"
    );
}

/// Real blocks and resonance, rtol = atol = $10^{-6}$ over $[0, 10]$, $\omega = 50$, each
/// component's truth in closed form:
/// * $y_0^\prime = -2y_0 + \cos\omega t + 0.5\sin\omega t + 3$ (a real block):
///   $y_0 = e^{-2t}(y_0(0) - p(0)) + p(t)$, $p = P\cos\omega t + Q\sin\omega t + 3/2$,
///   $P = -(\lambda a + b\omega)/(\lambda^2 + \omega^2)$, $Q = (a\omega - \lambda b)/(\lambda^2 +
///   \omega^2)$;
/// * $y_1^\prime = 0.7$ (a real block with $\lambda = 0$, a constant: resonance):
///   $y_1 = y_1(0) + 0.7t$;
/// * $y_2^\prime = 2\cos\omega t - 1$ (outside every block, $L = 0$):
///   $y_2 = y_2(0) + 2\sin(\omega t)/\omega - t$;
/// * $u^\prime = i\omega u + (1 - 2i)e^{i\omega t}$, $u = y_3 + iy_4$ (undamped at the forcing
///   frequency, resonance): $u = e^{i\omega t}(u(0) + (1 - 2i)t)$.
#[test]
fn real_blocks_and_resonances_are_exact() {
    let omega = 50.0;
    struct Mixed(DiagonalLinearPart, f64);
    impl OdeSystem<U5> for Mixed {
        fn rhs(&self, t: f64, y: &V5, dy: &mut V5) {
            let (s, c) = (self.1 * t).sin_cos();
            dy[0] = -2.0 * y[0] + c + 0.5 * s + 3.0;
            dy[1] = 0.7;
            dy[2] = 2.0 * c - 1.0;
            let u = I * self.1 * C::new(y[3], y[4]) + C::new(1.0, -2.0) * C::new(c, s);
            dy[3] = u.re;
            dy[4] = u.im;
        }
        fn linear_part(&self) -> Option<&DiagonalLinearPart> {
            Some(&self.0)
        }
    }
    let real = |a: f64, b: f64, c: f64| BlockForcing {
        cos: C::new(a, 0.0),
        sin: C::new(b, 0.0),
        constant: C::new(c, 0.0),
    };
    let amp = C::new(1.0, -2.0);
    let rotating = BlockForcing {
        cos: amp,
        sin: I * amp,
        constant: C::new(0.0, 0.0),
    };
    let lp = DiagonalLinearPart::new(5, &[(0, -2.0), (1, 0.0)], &[(3, I * omega)])
        .unwrap()
        .with_forcing(
            omega,
            &[
                (0, real(1.0, 0.5, 3.0)),
                (1, real(0.0, 0.0, 0.7)),
                (2, real(2.0, 0.0, -1.0)),
                (3, rotating),
            ],
        )
        .unwrap();
    let sys = Mixed(lp, omega);
    let y0 = V5::new(0.2, -0.1, 0.4, 0.3, 0.1);
    let exact = |t: f64| {
        let (l, a, b) = (-2.0, 1.0, 0.5);
        let d = l * l + omega * omega;
        let (p, q) = (-(l * a + b * omega) / d, (a * omega - l * b) / d);
        let part = |t: f64| p * (omega * t).cos() + q * (omega * t).sin() + 1.5;
        let u = (I * omega * t).exp() * (C::new(y0[3], y0[4]) + amp * t);
        V5::new(
            (l * t).exp() * (y0[0] - part(0.0)) + part(t),
            y0[1] + 0.7 * t,
            y0[2] + 2.0 * (omega * t).sin() / omega - t,
            u.re,
            u.im,
        )
    };
    let tol = 1e-6;
    let mut integ = Etd4::new(Options::with_tol(tol, tol)).unwrap();
    integ.reset(&sys, 0.0, &y0, false).unwrap();
    let (mut worst, mut out) = (0.0f64, V5::zeros());
    while integ.t() < 10.0 {
        integ.step(&sys, 10.0).unwrap();
        let t = 0.5 * (integ.t_prev() + integ.t());
        integ.dense(&sys, t, &mut out);
        worst = worst.max((out - exact(t)).amax());
        worst = worst.max((integ.y() - exact(integ.t())).amax());
    }
    let size = exact(10.0).amax();
    println!(
        "real blocks and resonances: error {worst:.2e}, size {size:.1}, {} steps",
        integ.stats().steps
    );
    assert!(worst <= 10.0 * tol * size, "error {worst:e}");
}

/// The declaration's checks, each a typed error naming the field and the value; and what a
/// declaration reads back (`forcing_frequency`, `block_forcing`, `forcing_at`).
#[test]
fn a_forcing_declaration_is_checked() {
    let lp = || DiagonalLinearPart::new(4, &[(0, -1.0)], &[(1, C::new(-1.0, 2.0))]).unwrap();
    let unit = BlockForcing {
        cos: C::new(1.0, 0.0),
        ..BlockForcing::default()
    };
    let field_of = |frequency: f64, blocks: &[(usize, BlockForcing)]| match lp()
        .with_forcing(frequency, blocks)
    {
        Err(OdeError::InvalidForcing {
            field,
            component,
            value,
            ..
        }) => (field, component, value),
        other => panic!("accepted: {other:?}"),
    };
    let nan = f64::NAN;
    let (field, component, value) = field_of(nan, &[(0, unit)]);
    assert!(field == "frequency" && component.is_none() && value.is_nan());
    assert_eq!(field_of(1.0, &[(4, unit)]), ("component", Some(4), 4.0));
    assert_eq!(field_of(1.0, &[(2, unit)]), ("component", Some(2), 2.0));
    assert_eq!(
        field_of(1.0, &[(0, unit), (0, unit)]),
        ("component", Some(0), 0.0)
    );
    let imaginary = BlockForcing {
        sin: C::new(0.0, 0.5),
        ..unit
    };
    assert_eq!(field_of(1.0, &[(0, imaginary)]), ("sin", Some(0), 0.5));
    let infinite = BlockForcing {
        constant: C::new(1.0, f64::INFINITY),
        ..unit
    };
    assert_eq!(
        field_of(1.0, &[(1, infinite)]),
        ("constant", Some(1), f64::INFINITY)
    );
    // A complex block takes complex amplitudes, a component outside every block real ones.
    let forced = lp()
        .with_forcing(3.0, &[(1, imaginary), (3, unit)])
        .unwrap();
    assert_eq!(forced.forcing_frequency(), Some(3.0));
    assert_eq!(forced.block_forcing(1), Some(imaginary));
    assert_eq!(forced.block_forcing(0), None);
    assert_eq!(lp().forcing_frequency(), None);
    // A declaration equals its copy, at exact resonance too (lambda = 2i against omega = 2, and
    // omega = 0 on the component outside every block), where the detunings set up for the
    // exact response have no inverse (issue 32: they are stored as 0, not as NaN).
    let resonant = DiagonalLinearPart::new(4, &[], &[(1, C::new(0.0, 2.0))])
        .unwrap()
        .with_forcing(2.0, &[(1, imaginary), (3, unit)])
        .unwrap();
    assert_eq!(resonant, resonant.clone());
    let constant = lp().with_forcing(0.0, &[(3, unit)]).unwrap();
    assert_eq!(constant, constant.clone());
    // g(t) = a cos 3t + b sin 3t + c: the pair (1, 2) gets cos 3t + 0.5 i sin 3t, component 3
    // cos 3t, component 0 nothing.
    let mut g = [9.0; 4];
    forced.forcing_at(0.2, &mut g).unwrap();
    let (s, c) = (3.0f64 * 0.2).sin_cos();
    assert_eq!(g, [0.0, c, 0.5 * s, c]);
    assert!(matches!(
        forced.forcing_at(0.2, &mut [0.0; 3]),
        Err(OdeError::DimensionMismatch {
            field: "out",
            expected: 4,
            found: 3
        })
    ));
}
