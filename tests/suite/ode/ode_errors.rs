//! Typed errors: step-size underflow, non-finite right-hand sides, invalid
//! options, misuse of the stepping API.

use jeffcott::numeric::Direction;
use jeffcott::ode::{
    find_first_event, solve, solve_with, AnyIntegrator, DiagonalLinearPart, Dop853, Dopri5, Etd4,
    EventOptions, EventSet, EventState, Integrator, Method, NoEvents, OdeError, OdeSystem, Options,
    Radau5, Rk4, SolveError, Tolerance, MAX_SAMPLES,
};
use nalgebra::{Complex, Const, SVector, U2};

type V1 = SVector<f64, 1>;
type V2 = SVector<f64, 2>;

/// $y' = y^2$, $y(0) = 1$: $y = 1/(1-t)$ blows up at $t = 1$.
fn blowup(_t: f64, y: &V1, dy: &mut V1) {
    dy[0] = y[0] * y[0];
}

/// Harmonic oscillator $x'' = -x$.
fn osc(_t: f64, y: &V2, dy: &mut V2) {
    dy[0] = y[1];
    dy[1] = -y[0];
}

/// The error of a `solve` without events or observer from `(t0, y0)` to `t_end` that must fail.
#[track_caller]
fn solve_error<const N: usize>(
    integ: &mut impl Integrator<Const<N>>,
    sys: &impl OdeSystem<Const<N>>,
    t0: f64,
    y0: SVector<f64, N>,
    t_end: f64,
) -> SolveError<Const<N>> {
    solve(integ, sys, t0, &y0, t_end, &NoEvents, &mut ()).unwrap_err()
}

/// The error of a `solve_with` of [`osc`] from $(1, 0)$ over $[0, 1]$ with `events` and the
/// event options `bad`, which must fail.
#[track_caller]
fn event_options_error(
    integ: &mut impl Integrator<U2>,
    events: &impl EventSet<U2>,
    bad: &EventOptions,
) -> OdeError {
    solve_with(
        integ,
        &osc,
        0.0,
        &V2::new(1.0, 0.0),
        1.0,
        events,
        bad,
        &mut (),
    )
    .unwrap_err()
    .error
}

#[test]
fn finite_time_blow_up_gives_step_size_underflow_with_last_good_state() {
    for method in [Method::Dop853, Method::Dopri5] {
        let mut integ = AnyIntegrator::new(method, Options::with_tol(1e-8, 1e-8)).unwrap();
        let err = solve_error(&mut integ, &blowup, 0.0, V1::new(1.0), 2.0);
        println!("{}: {err}", method.name());
        match err.error {
            OdeError::StepSizeUnderflow { t, h, h_min } => {
                // the numerical blow-up time differs from 1 by the global error
                assert!((t - 1.0).abs() < 1e-6, "t = {t}");
                assert!(h < h_min);
            }
            e => panic!("{}: expected StepSizeUnderflow, got {e:?}", method.name()),
        }

        assert_eq!(err.t, integ.t());
        assert_eq!(err.y, *integ.y());
        // last good state: finite and huge (the solution blows up)
        assert!(err.y[0].is_finite() && err.y[0] > 1e6, "{}", err.y[0]);
        assert!(err.stats.steps > 10);
        assert_eq!(err.stats, *integ.stats());
        let msg = err.to_string();
        assert!(msg.contains("underflow") && msg.contains("event"), "{msg}");
    }
    // A user-set h_min triggers earlier.
    let opts = Options::with_tol(1e-8, 1e-8).with_h_min(1e-6);
    let mut integ = Dop853::new(opts).unwrap();
    let err = solve_error(&mut integ, &blowup, 0.0, V1::new(1.0), 2.0);
    assert!(matches!(err.error, OdeError::StepSizeUnderflow { h_min, .. } if h_min == 1e-6));
    assert!(err.t < 1.0 - 1e-6);
}

#[test]
fn nan_in_rhs_gives_typed_error() {
    // NaN for t > 0.5
    let nan_late = |t: f64, y: &V1, dy: &mut V1| {
        dy[0] = if t > 0.5 { f64::NAN } else { -y[0] };
    };
    for method in [Method::Dop853, Method::Dopri5] {
        let mut integ = AnyIntegrator::new(method, Options::with_tol(1e-8, 1e-8)).unwrap();
        let err = solve_error(&mut integ, &nan_late, 0.0, V1::new(1.0), 2.0);
        println!("{}: {err}", method.name());
        assert!(
            matches!(err.error, OdeError::NonFiniteRhs { .. }),
            "{err:?}"
        );
        assert!(err.t <= 0.5 && err.y[0].is_finite());
        assert!((err.y[0] - (-err.t).exp()).abs() < 1e-6);
    }
    // Fixed steps cannot shrink: immediate error.
    let mut integ = Rk4::new(Options::fixed(0.3)).unwrap();
    let err = solve_error(&mut integ, &nan_late, 0.0, V1::new(1.0), 2.0);
    assert!(matches!(err.error, OdeError::NonFiniteRhs { t, .. } if t == 0.3));
    // NaN already at the initial point.
    let nan_always = |_t: f64, _y: &V1, dy: &mut V1| dy[0] = f64::NAN;
    let mut integ = Dop853::new(Options::default()).unwrap();
    assert!(matches!(
        integ.reset(&nan_always, 0.0, &V1::new(1.0), false),
        Err(OdeError::NonFiniteRhs { .. })
    ));
    // Non-finite initial data.
    assert!(matches!(
        integ.reset(&blowup, 0.0, &V1::new(f64::INFINITY), false),
        Err(OdeError::NonFiniteInitial { component: 0, .. })
    ));
    assert!(matches!(
        integ.reset(&blowup, f64::NAN, &V1::new(1.0), false),
        Err(OdeError::NonFiniteInitial { .. })
    ));
}

fn field_of(e: OdeError) -> &'static str {
    match e {
        OdeError::InvalidOption { field, .. } => field,
        other => panic!("expected InvalidOption, got {other:?}"),
    }
}

#[test]
fn invalid_options_name_the_field() {
    let d = Options::<U2>::default();
    let cases: Vec<(Options<U2>, &str)> = vec![
        (d.with_rtol(Tolerance::Scalar(-1.0)), "rtol"),
        (d.with_rtol(Tolerance::Scalar(f64::NAN)), "rtol"),
        (
            d.with_atol(Tolerance::PerComponent(V2::new(1e-9, f64::NAN))),
            "atol",
        ),
        (
            d.with_rtol(Tolerance::Scalar(0.0))
                .with_atol(Tolerance::Scalar(0.0)),
            "atol",
        ),
        (d.with_h_init(Some(0.0)), "h_init"),
        (d.with_h_init(Some(f64::NAN)), "h_init"),
        (d.with_h_max(0.0), "h_max"),
        (d.with_h_max(f64::NAN), "h_max"),
        (d.with_h_min(-1.0), "h_min"),
        (d.with_h_min(2.0).with_h_max(1.0), "h_min"),
        (d.with_max_steps(0), "max_steps"),
        (d.with_h_init(Some(1e-9)).with_h_min(1e-6), "h_init"),
        (d.with_safety(1.5), "safety"),
        (d.with_safety(0.0), "safety"),
        (d.with_fac_min(0.0), "fac_min"),
        (d.with_fac_max(0.5), "fac_max"),
        (d.with_fac_max(f64::INFINITY), "fac_max"),
        (d.with_beta(Some(0.5)), "beta"),
        (d.with_fixed_step(Some(-0.1)), "fixed_step"),
    ];
    for (opts, field) in cases {
        for method in Method::ALL {
            let opts = if method == Method::Rk4 && opts.fixed_step.is_none() {
                opts.with_fixed_step(Some(0.1))
            } else {
                opts
            };
            let e = AnyIntegrator::new(method, opts).unwrap_err();
            assert_eq!(field_of(e), field, "{} {opts:?}", method.name());
            assert!(e.to_string().contains(field));
        }
        assert_eq!(field_of(opts.validate().unwrap_err()), field);
    }
    // RK4 needs a fixed step.
    let e = Rk4::<U2>::new(Options::default()).unwrap_err();
    assert_eq!(field_of(e), "fixed_step");
    assert!(e.to_string().contains("fixed_step"));
    // Valid defaults.
    assert!(Dop853::<U2>::new(Options::default()).is_ok());
    assert!(Dopri5::<U2>::new(Options::default()).is_ok());
}

#[test]
fn invalid_event_options_and_too_many_events() {
    let mut integ = Dop853::new(Options::default()).unwrap();
    let bad = EventOptions::default().with_samples_per_step(0);
    let e = event_options_error(&mut integ, &NoEvents, &bad);
    assert_eq!(field_of(e), "samples_per_step");
    let bad = EventOptions::default().with_root_tol(-1.0);
    let e = event_options_error(&mut integ, &NoEvents, &bad);
    assert_eq!(field_of(e), "root_tol");

    // samples_per_step above MAX_SAMPLES and max_iter = 0 are errors too
    // (they used to be clamped silently).
    for (bad, field) in [
        (
            EventOptions::default().with_samples_per_step(MAX_SAMPLES + 1),
            "samples_per_step",
        ),
        (EventOptions::default().with_max_iter(0), "max_iter"),
    ] {
        let e = event_options_error(&mut integ, &X0, &bad);
        assert_eq!(field_of(e), field);
    }
}

/// $g = x$, crossing both ways.
struct X0;
impl EventSet<U2> for X0 {
    fn len(&self) -> usize {
        1
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Either
    }
    fn value(&self, _i: usize, _t: f64, y: &V2) -> f64 {
        y[0]
    }
}

/// Every entry point that takes `EventOptions` validates them: the detector
/// returns a typed error (naming the field) instead of clamping, and
/// evaluates nothing.
#[test]
fn find_first_event_validates_its_options() {
    let mut integ = Dop853::new(Options::fixed(2.0)).unwrap();
    integ.reset(&osc, 0.0, &V2::new(1.0, 0.0), false).unwrap();
    integ.step(&osc, 10.0).unwrap(); // x = cos t crosses 0 at pi/2 in [0, 2]
    let mut st = EventState::new();
    for (samples, ok) in [
        (0, false),
        (1, true),
        (MAX_SAMPLES, true),
        (MAX_SAMPLES + 1, false),
    ] {
        let opts = EventOptions::default().with_samples_per_step(samples);
        let before = *integ.stats();
        st.reset();
        let r = find_first_event(&mut integ, &osc, &X0, &opts, &mut st);
        if ok {
            let hit = r.unwrap().expect("crossing at pi/2");
            // One step of length 2: the root of the dense output, off by the
            // integration error (3e-4 here).
            let err = (hit.t - std::f64::consts::FRAC_PI_2).abs();
            assert!(err < 1e-3, "{}", hit.t);
        } else {
            match r {
                Err(e) => assert_eq!(field_of(e), "samples_per_step"),
                Ok(h) => panic!("samples_per_step = {samples} accepted: {h:?}"),
            }
            assert_eq!(*integ.stats(), before, "nothing evaluated");
        }
    }
    let bad = EventOptions::default().with_root_tol(f64::NAN);
    let e = find_first_event(&mut integ, &osc, &X0, &bad, &mut st).unwrap_err();
    assert_eq!(field_of(e), "root_tol");
}

#[test]
fn api_misuse_is_an_error_not_a_panic() {
    for method in Method::ALL {
        let mut integ = AnyIntegrator::new(method, Options::fixed(0.1)).unwrap();
        assert!(matches!(
            integ.step(&osc, 1.0),
            Err(OdeError::NotInitialized)
        ));
        assert!(matches!(
            integ.truncate(&osc, 1.0),
            Err(OdeError::NotInitialized)
        ));
        // dense before reset/step: no panic
        let mut out = V2::zeros();
        integ.dense(&osc, 0.5, &mut out);
        integ.reset(&osc, 0.0, &V2::new(1.0, 0.0), false).unwrap();
        assert!(matches!(
            integ.step(&osc, -1.0),
            Err(OdeError::InvalidBound { .. })
        ));
        assert!(matches!(
            integ.step(&osc, f64::NAN),
            Err(OdeError::InvalidBound { .. })
        ));
        assert!(matches!(
            integ.step(&osc, f64::INFINITY),
            Err(OdeError::InvalidBound { .. })
        ));
        // truncate without a step: (t_prev, t] is empty
        assert!(matches!(
            integ.truncate(&osc, 0.0),
            Err(OdeError::TruncateOutOfRange { .. })
        ));
    }
    // solve with t_end < t0
    let mut integ = Dop853::new(Options::default()).unwrap();
    let e = solve_error(&mut integ, &osc, 1.0, V2::new(1.0, 0.0), 0.0);
    assert!(matches!(e.error, OdeError::InvalidBound { .. }));
}

#[test]
fn too_many_steps() {
    let opts = Options::with_tol(1e-12, 1e-12).with_max_steps(10);
    let mut integ = Dop853::new(opts).unwrap();
    let e = solve_error(&mut integ, &osc, 0.0, V2::new(1.0, 0.0), 100.0);
    assert!(
        matches!(e.error, OdeError::TooManySteps { max_steps: 10, .. }),
        "{e:?}"
    );
    assert_eq!(e.stats.steps + e.stats.rejected, 10);
    assert!(e.to_string().contains("max_steps"));
    // The limit is per reset: a fresh solve can run again.
    let e2 = solve_error(&mut integ, &osc, 0.0, V2::new(1.0, 0.0), 100.0);
    assert!(matches!(e2.error, OdeError::TooManySteps { .. }));
}

/// $y'' = -y$ up to $t = 1$ (solution $\cos t$ from $(1, 0)$), then a violent forcing that
/// makes the next trial step fail.
fn calm_then_violent(t: f64, y: &V2, dy: &mut V2) {
    dy[0] = y[1];
    dy[1] = -y[0] + if t > 1.0 { 1e6 * (1e3 * t).sin() } else { 0.0 };
}

/// [`calm_then_violent`] with its linear part declared ($w = y_0 + iy_1$, $w^\prime = -iw + iF$:
/// a complex block $-i$), for ETD4.
struct CalmThenViolent(DiagonalLinearPart);

impl OdeSystem<U2> for CalmThenViolent {
    fn rhs(&self, t: f64, y: &V2, dy: &mut V2) {
        calm_then_violent(t, y, dy);
    }
    fn linear_part(&self) -> Option<&DiagonalLinearPart> {
        Some(&self.0)
    }
}

/// A step that fails after a rejected trial (here: the attempt budget runs out) leaves the last
/// accepted step's dense output as it was: the truth is $\cos t$ inside that step, and the same
/// integrator's dense output without the failed step. Every adaptive method. Before their
/// fixes DOP853 gave 36 400 where $\cos t = 0.64$, and ETD4 (its trials wrote the half steps the
/// dense output reads) 644 683 where $\cos t = 0.85$; RADAU5 keeps its polynomial apart from
/// its trials and passed as it was.
#[test]
fn dense_output_survives_a_failed_step() {
    fn check<I: Integrator<U2>>(sys: &impl OdeSystem<U2>, build: impl Fn(u64) -> I) {
        let y0 = V2::new(1.0, 0.0);
        let to_calm_end = |integ: &mut I| {
            integ.reset(sys, 0.0, &y0, false).unwrap();
            while integ.t() < 0.99 {
                integ.step(sys, 0.99).unwrap();
            }
        };
        let mut clean = build(1_000_000);
        to_calm_end(&mut clean);
        let attempts = clean.stats().steps + clean.stats().rejected;
        let mid = 0.5 * (clean.t_prev() + clean.t());
        let mut expected = V2::zeros();
        clean.dense(sys, mid, &mut expected);

        // One attempt more than the calm part needs: the first trial past t = 1 is rejected,
        // and the step ends with the budget spent.
        let mut failed = build(attempts + 1);
        to_calm_end(&mut failed);
        let r = failed.step(sys, 5.0);
        assert!(matches!(r, Err(OdeError::TooManySteps { .. })), "{r:?}");
        assert!(failed.stats().rejected > clean.stats().rejected);
        let mut out = V2::zeros();
        failed.dense(sys, mid, &mut out);
        let name = failed.name();
        assert!(
            (out[0] - mid.cos()).abs() < 1e-8,
            "{name}: {out:?} vs cos {}",
            mid.cos()
        );
        assert_eq!(out, expected, "{name}");
    }
    let opts = |m| Options::with_tol(1e-10, 1e-10).with_max_steps(m);
    let sys = calm_then_violent;
    check(&sys, |m| Dop853::<U2>::new(opts(m)).unwrap());
    check(&sys, |m| Dopri5::<U2>::new(opts(m)).unwrap());
    check(&sys, |m| Radau5::<U2>::new(opts(m)).unwrap());
    let lp = DiagonalLinearPart::new(2, &[], &[(0, Complex::new(0.0, -1.0))]).unwrap();
    check(&CalmThenViolent(lp), |m| Etd4::<U2>::new(opts(m)).unwrap());
}
