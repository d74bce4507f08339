//! Adaptive step-size control: tolerance proportionality on problems with
//! known solutions, work counters, bounds, h_max, reset and truncate.

// Reference values are written with all their published/computed digits.
#![allow(clippy::excessive_precision)]

use jeffcott::ode::{
    solve, AnyIntegrator, Dop853, Dopri5, Integrator, Method, NoEvents, OdeError, OdeSystem,
    Options, Recorder, Rk4, Stopped, Tolerance,
};
use nalgebra::{Const, SVector, U4};

use crate::models;
use models::{slope, Kepler, V4};

/// Restricted three-body problem (Arenstorf orbit), period known to 30
/// digits: the solution returns to its initial value after one period.
struct Arenstorf;
const MU: f64 = 0.012277471;
const T_ARENSTORF: f64 = 17.065_216_560_157_962_558_891_720_624_9;

impl OdeSystem<U4> for Arenstorf {
    fn rhs(&self, _t: f64, y: &V4, dy: &mut V4) {
        let mu1 = 1.0 - MU;
        let d1 = ((y[0] + MU).powi(2) + y[1] * y[1]).powf(1.5);
        let d2 = ((y[0] - mu1).powi(2) + y[1] * y[1]).powf(1.5);
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = y[0] + 2.0 * y[3] - mu1 * (y[0] + MU) / d1 - MU * (y[0] - mu1) / d2;
        dy[3] = y[1] - 2.0 * y[2] - mu1 * y[1] / d1 - MU * y[1] / d2;
    }
}

fn arenstorf_y0() -> V4 {
    V4::new(0.994, 0.0, 0.0, -2.001_585_106_379_082_522_405_378_622_24)
}

fn run_to<const N: usize, S: OdeSystem<Const<N>>>(
    method: Method,
    opts: Options<Const<N>>,
    sys: &S,
    y0: SVector<f64, N>,
    t_end: f64,
) -> (SVector<f64, N>, jeffcott::ode::Stats) {
    let mut integ = AnyIntegrator::new(method, opts).unwrap();
    let rep = solve(&mut integ, sys, 0.0, &y0, t_end, &NoEvents, &mut ()).unwrap();
    assert_eq!(rep.stopped, Stopped::Reached);
    assert_eq!(rep.t, t_end);
    (rep.y, rep.stats)
}

fn sci(v: &[f64]) -> Vec<String> {
    v.iter().map(|e| format!("{e:.2e}")).collect()
}

/// Tolerances 1e-6 ... 1e-12 in half decades.
fn tolerances() -> Vec<f64> {
    (12..=24).map(|k| 10f64.powf(-(k as f64) / 2.0)).collect()
}

#[test]
fn arenstorf_error_decreases_with_tolerance() {
    for method in [Method::Dop853, Method::Dopri5] {
        let tols = tolerances();
        let mut errs = vec![];
        let mut steps = vec![];
        for &tol in &tols {
            let (y, st) = run_to(
                method,
                Options::with_tol(tol, tol),
                &Arenstorf,
                arenstorf_y0(),
                T_ARENSTORF,
            );
            errs.push((y - arenstorf_y0()).amax());
            steps.push(st.steps);
        }
        let p = slope(&tols, &errs);
        println!(
            "{} Arenstorf: errors {:?}, steps {steps:?}, slope {p:.3}",
            method.name(),
            sci(&errs)
        );
        // Tighter tolerance: more steps, and a smaller error at every decade.
        assert!(steps.windows(2).all(|w| w[1] >= w[0]), "{steps:?}");
        // Two decades tighter: smaller (single samples of the global error
        // can be lucky through cancellation; the rate is checked by the fit).
        for i in 0..tols.len() - 4 {
            assert!(errs[i + 4] < errs[i], "{}: {errs:?}", method.name());
        }
        assert!((p - 1.0).abs() < 0.3, "{}: error ~ tol^{p}", method.name());
        assert!(*errs.last().unwrap() < 1e-7);
    }
}

#[test]
fn kepler_tolerance_proportionality() {
    let sys = Kepler { e: 0.5 };
    let t_end = 3.0 * 2.0 * std::f64::consts::PI;
    for method in [Method::Dop853, Method::Dopri5] {
        let tols = tolerances();
        let errs: Vec<f64> = tols
            .iter()
            .map(|&tol| {
                let (y, _) = run_to(
                    method,
                    Options::with_tol(tol, tol),
                    &sys,
                    sys.exact(0.0),
                    t_end,
                );
                (y - sys.exact(t_end)).amax()
            })
            .collect();
        let p = slope(&tols, &errs);
        println!(
            "{} Kepler e=0.5: errors {:?}, slope {p:.3}",
            method.name(),
            sci(&errs)
        );
        assert!((p - 1.0).abs() < 0.25, "{}: error ~ tol^{p}", method.name());
        // Two decades tighter: smaller (single samples of the global error
        // can be lucky through cancellation; the rate is checked by the fit).
        for i in 0..tols.len() - 4 {
            assert!(errs[i + 4] < errs[i], "{}: {errs:?}", method.name());
        }
        // Error per unit tolerance stays within a band (tolerance proportionality).
        let ratios: Vec<f64> = errs.iter().zip(&tols).map(|(e, t)| e / t).collect();
        let (lo, hi) = ratios
            .iter()
            .fold((f64::MAX, 0.0f64), |(a, b), &r| (a.min(r), b.max(r)));
        assert!(
            hi / lo < 100.0 && hi < 1e4,
            "{}: err/tol ratios {ratios:?}",
            method.name()
        );
    }
}

#[test]
fn stats_count_rhs_evaluations_exactly() {
    let sys = Kepler { e: 0.3 };
    let y0 = sys.exact(0.0);
    // DOP853: 1 (reset) + 1 (initial step guess) + 12 per accepted + 11 per rejected.
    let mut d = Dop853::new(Options::with_tol(1e-9, 1e-9)).unwrap();
    d.reset(&sys, 0.0, &y0, false).unwrap();
    while d.t() < 20.0 {
        d.step(&sys, 20.0).unwrap();
    }
    let s = *d.stats();
    assert!(s.steps > 10);
    assert_eq!(s.rhs_evals, 2 + 12 * s.steps + 11 * s.rejected, "{s:?}");
    // Dense output on the last step costs 3 more, once.
    let mut out = V4::zeros();
    d.dense(&sys, d.t() - 1e-3, &mut out);
    d.dense(&sys, d.t() - 2e-3, &mut out);
    assert_eq!(d.stats().rhs_evals, s.rhs_evals + 3);

    // DOPRI5: 1 + 1 + 6 per attempt (FSAL).
    let mut p = Dopri5::new(Options::with_tol(1e-7, 1e-7)).unwrap();
    p.reset(&sys, 0.0, &y0, false).unwrap();
    while p.t() < 20.0 {
        p.step(&sys, 20.0).unwrap();
    }
    let s = *p.stats();
    assert_eq!(s.rhs_evals, 2 + 6 * (s.steps + s.rejected), "{s:?}");

    // RK4: 1 + 4 per step, no rejections.
    let mut r = Rk4::new(Options::fixed(0.01)).unwrap();
    r.reset(&sys, 0.0, &y0, false).unwrap();
    while r.t() < 1.0 {
        r.step(&sys, 1.0).unwrap();
    }
    let s = *r.stats();
    assert_eq!(s.steps, 100);
    assert_eq!(s.rejected, 0);
    assert_eq!(s.rhs_evals, 1 + 4 * s.steps);
}

#[test]
fn steps_respect_h_max_and_land_on_bound() {
    let sys = Kepler { e: 0.3 };
    let opts = Options::with_tol(1e-6, 1e-6).with_h_max(0.05);
    for method in [Method::Dop853, Method::Dopri5] {
        let mut integ = AnyIntegrator::new(method, opts).unwrap();
        integ.reset(&sys, 0.0, &sys.exact(0.0), false).unwrap();
        let t_end = 1.234_567;
        while integ.t() < t_end {
            integ.step(&sys, t_end).unwrap();
            assert!(integ.t() - integ.t_prev() <= 0.05 * 1.01 + 1e-15);
            assert!(integ.t() <= t_end);
        }
        assert_eq!(integ.t(), t_end);
        // step at the bound is a no-op; a bound behind is an error
        let steps = integ.stats().steps;
        integ.step(&sys, t_end).unwrap();
        assert_eq!(integ.stats().steps, steps);
        assert!(matches!(
            integ.step(&sys, 1.0),
            Err(OdeError::InvalidBound { .. })
        ));
    }
}

#[test]
fn per_component_tolerance_and_outputs() {
    let sys = Kepler { e: 0.4 };
    let opts = Options::default()
        .with_rtol(Tolerance::PerComponent(V4::new(1e-10, 1e-10, 1e-9, 1e-9)))
        .with_atol(Tolerance::Scalar(1e-12));
    let mut integ = Dop853::new(opts).unwrap();
    let grid: Vec<f64> = (0..=50).map(|i| i as f64 * 0.2).collect();
    let mut rec = Recorder::with_grid(grid.clone());
    solve(
        &mut integ,
        &sys,
        0.0,
        &sys.exact(0.0),
        10.0,
        &NoEvents,
        &mut rec,
    )
    .unwrap();
    assert_eq!(rec.outputs.len(), grid.len());
    for ((t, y), tg) in rec.outputs.iter().zip(&grid) {
        assert_eq!(t, tg);
        assert!((y - sys.exact(*t)).amax() < 1e-7, "t = {t}");
    }
}

#[test]
fn reset_keep_step_and_truncate() {
    let sys = Kepler { e: 0.3 };
    let mut integ = Dop853::new(Options::with_tol(1e-10, 1e-10)).unwrap();
    integ.reset(&sys, 0.0, &sys.exact(0.0), false).unwrap();
    for _ in 0..5 {
        integ.step(&sys, 100.0).unwrap();
    }
    let h = integ.h_next();
    let (tp, t) = (integ.t_prev(), integ.t());
    let tm = 0.5 * (tp + t);
    let mut ym = V4::zeros();
    integ.dense(&sys, tm, &mut ym);
    integ.truncate(&sys, tm).unwrap();
    assert_eq!(integ.t(), tm);
    assert_eq!(*integ.y(), ym);
    assert_eq!(integ.t_prev(), tp);
    assert_eq!(integ.h_next(), h);
    // dense output still valid on [t_prev, t_new]
    let mut y2 = V4::zeros();
    integ.dense(&sys, 0.5 * (tp + tm), &mut y2);
    assert!((y2 - sys.exact(0.5 * (tp + tm))).amax() < 1e-8);
    // out of range
    assert!(matches!(
        integ.truncate(&sys, tm + 1.0),
        Err(OdeError::TruncateOutOfRange { .. })
    ));
    assert!(matches!(
        integ.truncate(&sys, tp),
        Err(OdeError::TruncateOutOfRange { .. })
    ));
    // continue from the truncated point
    integ.step(&sys, 100.0).unwrap();
    assert_eq!(integ.t_prev(), tm);
    assert!((integ.y() - sys.exact(integ.t())).amax() < 1e-8);
    // reset with keep_step keeps the suggestion
    let h = integ.h_next();
    let (t1, y1) = (integ.t(), *integ.y());
    integ.reset(&sys, t1, &y1, true).unwrap();
    assert_eq!(integ.h_next(), h);
    assert_eq!(integ.t_prev(), integ.t());
    let mut yd = V4::zeros();
    integ.dense(&sys, t1 + 1.0, &mut yd);
    assert_eq!(yd, y1);
}

#[test]
fn fixed_step_mode_of_adaptive_methods_takes_exact_steps() {
    let sys = Kepler { e: 0.1 };
    for method in Method::ALL {
        let mut integ = AnyIntegrator::new(method, Options::fixed(0.1)).unwrap();
        integ.reset(&sys, 0.0, &sys.exact(0.0), false).unwrap();
        integ.step(&sys, 10.0).unwrap();
        assert_eq!(integ.t(), 0.1, "{}", integ.name());
        assert_eq!(integ.stats().rejected, 0);
    }
}

/// `atol = +inf` excludes a component from error control: a fast
/// exponential component ($y_2' = 40 y_2$, growing to $e^{40}$) that would
/// force small steps does not shrink them, and the oscillator components keep
/// their accuracy — in fact they get exactly the steps, and the bits, of the
/// oscillator integrated alone.
#[test]
fn infinite_atol_excludes_a_component_from_error_control() {
    type V3 = SVector<f64, 3>;
    let with_exp = |_t: f64, y: &V3, dy: &mut V3| {
        dy[0] = y[1];
        dy[1] = -y[0];
        dy[2] = 40.0 * y[2];
    };
    let alone = |_t: f64, y: &SVector<f64, 2>, dy: &mut SVector<f64, 2>| {
        dy[0] = y[1];
        dy[1] = -y[0];
    };
    let t_end = 1.0;
    let y0 = V3::new(1.0, 0.0, 1.0);
    for method in [Method::Dop853, Method::Dopri5] {
        let run3 = |atol2: f64| {
            let opts = Options::default()
                .with_rtol(Tolerance::Scalar(1e-10))
                .with_atol(Tolerance::PerComponent(V3::new(1e-12, 1e-12, atol2)));
            let mut rec = Recorder::default();
            rec.record_steps = true;
            let rep = solve(
                &mut AnyIntegrator::new(method, opts).unwrap(),
                &with_exp,
                0.0,
                &y0,
                t_end,
                &NoEvents,
                &mut rec,
            )
            .unwrap();
            (rep, rec.steps)
        };
        let (free, free_steps) = run3(f64::INFINITY);
        let (controlled, _) = run3(1e-12);
        let mut rec2 = Recorder::default();
        rec2.record_steps = true;
        let opts2 = Options::with_tol(1e-10, 1e-12);
        let rep2 = solve(
            &mut AnyIntegrator::new(method, opts2).unwrap(),
            &alone,
            0.0,
            &SVector::<f64, 2>::new(1.0, 0.0),
            t_end,
            &NoEvents,
            &mut rec2,
        )
        .unwrap();
        println!(
            "{}: steps with y2 free {}, controlled {}, oscillator alone {}",
            method.name(),
            free.stats.steps,
            controlled.stats.steps,
            rep2.stats.steps
        );
        // The excluded component does not shrink the steps ...
        assert_eq!(free.stats.steps, rep2.stats.steps, "{}", method.name());
        assert!(
            controlled.stats.steps >= 3 * free.stats.steps,
            "{}: {} vs {}",
            method.name(),
            controlled.stats.steps,
            free.stats.steps
        );
        // ... the others are integrated exactly as without it (same bits) ...
        assert_eq!(free_steps.len(), rec2.steps.len());
        for ((t3, y3), (t2, y2)) in free_steps.iter().zip(&rec2.steps) {
            assert_eq!(t3.to_bits(), t2.to_bits());
            assert_eq!(y3[0].to_bits(), y2[0].to_bits());
            assert_eq!(y3[1].to_bits(), y2[1].to_bits());
        }
        // ... and keep their accuracy.
        assert!((free.y[0] - t_end.cos()).abs() < 1e-9, "{}", free.y[0]);
        assert!((free.y[1] + t_end.sin()).abs() < 1e-9, "{}", free.y[1]);
        // The excluded component is still computed, with the accuracy of the
        // steps chosen for the others (here 40 h is about 7: a factor 3 low).
        let exact = (40.0 * t_end).exp();
        println!(
            "  y2 free {:e}, controlled {:e}, exact {exact:e}",
            free.y[2], controlled.y[2]
        );
        assert!(free.y[2].is_finite() && free.y[2] > exact / 10.0 && free.y[2] < exact * 10.0);
        assert!((controlled.y[2] / exact - 1.0).abs() < 1e-8);
    }
}

#[test]
fn atol_validation_allows_plus_infinity_only() {
    type V3 = SVector<f64, 3>;
    let per = |v: f64| Tolerance::PerComponent(V3::new(1e-12, v, 1e-12));
    for (atol, ok) in [
        (per(f64::INFINITY), true),
        (Tolerance::Scalar(f64::INFINITY), true),
        (per(f64::NEG_INFINITY), false),
        (per(f64::NAN), false),
        (per(-1e-12), false),
    ] {
        let opts = Options::default().with_atol(atol);
        match Dop853::new(opts) {
            Ok(_) => assert!(ok, "{atol:?} accepted"),
            Err(e) => {
                assert!(!ok, "{atol:?} rejected: {e}");
                assert!(matches!(e, OdeError::InvalidOption { field: "atol", .. }));
                assert!(e.to_string().contains("INFINITY"), "{e}");
            }
        }
    }
    // rtol stays finite.
    let opts = Options::<nalgebra::U3>::default().with_rtol(Tolerance::Scalar(f64::INFINITY));
    assert!(matches!(
        Dop853::new(opts),
        Err(OdeError::InvalidOption { field: "rtol", .. })
    ));
}
