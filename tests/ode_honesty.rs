//! Honest answers of the ODE layer and the hybrid driver (issue 16): a root finder that meets
//! NaN says so, the driver's event screen is off by default, outputs never change the
//! trajectory, and a guard that cannot be evaluated stops the run with a typed error.

use jeffcott::ode::roots::illinois;

/// NaN at an end of the initial bracket: not a bracket, not converged (the input is returned).
#[test]
fn illinois_nan_at_a_bracket_end_is_not_converged() {
    for (fa, fb) in [(f64::NAN, 1.0), (-1.0, f64::NAN)] {
        let r = illinois(0.0, fa, 1.0, fb, 1e-12, 100, |t| t - 0.5);
        assert!(!r.converged, "fa = {fa}, fb = {fb}: {r:?}");
        assert_eq!(r.evaluations, 0);
    }
}

/// NaN in the middle of the search: $g(t) = t - 1/2$ except NaN on $(0.45, 0.55)$, bracket
/// $[0, 1]$. The first secant point is $1/2$, where $g$ is NaN: the search cannot tell which
/// side the root is on, so it must stop there, not converged, with the NaN time reported and
/// the last bracket of numbers. (Before the fix the NaN was taken as a sign, the search went
/// on with NaN as an end value and reported convergence.)
#[test]
fn illinois_nan_mid_iteration_is_not_converged() {
    let g = |t: f64| {
        if t > 0.45 && t < 0.55 {
            f64::NAN
        } else {
            t - 0.5
        }
    };
    let r = illinois(0.0, g(0.0), 1.0, g(1.0), 1e-12, 100, g);
    assert!(!r.converged, "{r:?}");
    assert_eq!(r.nan_at, Some(0.5), "{r:?}");
    assert!(!r.g_lo.is_nan() && !r.g_hi.is_nan(), "{r:?}");
    assert!(r.g_lo < 0.0 && r.g_hi > 0.0, "{r:?}");
}
