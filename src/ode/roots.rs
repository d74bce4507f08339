//! The crate's bracketing root finder: the Illinois method.
//!
//! One root finder for every layer: the event detector locates event roots
//! and grazing extrema with it, and any other code that has a bracket of a
//! continuous scalar function should call [`illinois`] rather than write its
//! own.
//!
//! # The method
//!
//! Given $a < b$ with $g(a) \ne 0$ and $g(b)$ of the opposite sign (or zero),
//! each iteration takes the secant (regula falsi) point
//! $$c = b - g_b\thinspace\frac{b - a}{g_b - g_a}$$
//! and replaces the end of the same sign as $g(c)$. When the same end is kept
//! twice in a row, its stored function value is halved (the Illinois
//! modification), which restores superlinear convergence (order
//! $\approx 1.44$) where plain regula falsi stalls on one side. The iteration
//! falls back to bisection when the secant point is not strictly inside the
//! bracket, and on every fourth iteration in a row that did not halve the
//! bracket, so it never needs more than about four times the iterations of
//! bisection. A point is never taken closer than `tol / 2` to an end of the
//! bracket: once an end sits on the root to rounding (the secant point of a
//! nearly linear function does so at once), the next point falls half a
//! tolerance beyond it and closes the bracket, where the far end would
//! otherwise creep in over many iterations.
//!
//! # Guarantee
//!
//! If $g$ is continuous on $[a, b]$ the returned bracket always contains a
//! root, with $g(\text{lo})$ of the sign of $g(a)$ and $g(\text{hi})$ of the
//! opposite sign or zero: a sign change is never lost, whatever $g$ does
//! (round-off included), as long as it returns numbers: a NaN from $g$ stops the
//! search, not converged ([`Bracket::nan_at`]). The search stops when $\text{hi} - \text{lo} \le$
//! `tol`, when $g(\text{hi}) = 0$, when the ends are adjacent floats, or after
//! `max_iter` evaluations.
//!
//! ```
//! use jeffcott::ode::roots::illinois;
//!
//! // The root of cos on [1, 2] (pi / 2) to 4 ulp.
//! let tol = 4.0 * f64::EPSILON * 2.0;
//! let r = illinois(1.0, 1f64.cos(), 2.0, 2f64.cos(), tol, 100, f64::cos);
//! assert!(r.converged && r.hi - r.lo <= tol);
//! assert!(r.g_lo > 0.0 && r.g_hi <= 0.0);
//! assert!((r.hi - std::f64::consts::FRAC_PI_2).abs() <= tol);
//! assert!(r.evaluations < 15);
//! ```

/// The result of [`illinois`]: the final bracket and how it was obtained.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bracket {
    /// End on the side of the initial `a`: $g(\text{lo})$ has the sign of the
    /// initial `fa`.
    pub lo: f64,
    /// $g(\text{lo})$ (the initial `fa` if `lo` never moved).
    pub g_lo: f64,
    /// End on the other side: $g(\text{hi})$ has the opposite sign or is 0.
    pub hi: f64,
    /// $g(\text{hi})$ (the initial `fb` if `hi` never moved).
    pub g_hi: f64,
    /// Evaluations of $g$ made.
    pub evaluations: usize,
    /// Whether the search ended by its tolerance ($\text{hi} - \text{lo} \le$
    /// `tol`, $g(\text{hi}) = 0$ or adjacent floats). `false` when `max_iter`
    /// was reached, when `g` returned NaN ([`Bracket::nan_at`]) or the input was
    /// not a bracket (then `lo`, `hi` are the inputs).
    pub converged: bool,
    /// `Some(t)` when `g(t)` returned NaN inside the bracket: the search stopped
    /// there, not converged (NaN has no sign, so the side of the root is
    /// unknown), and `lo`, `hi`, `g_lo`, `g_hi` are the last bracket with
    /// numbers at both ends. `None` otherwise (NaN in the initial `fa`, `fb` is
    /// reported as not a bracket, with `None` here).
    pub nan_at: Option<f64>,
}

/// Illinois (modified regula falsi) on the bracket $[a, b]$ with `fa` $=
/// g(a) \ne 0$ and `fb` $= g(b)$ of the opposite sign or zero; see the
/// [module docs](self) for the method and its guarantee.
///
/// `tol` is an absolute width in the units of $t$ (use
/// $\max(\text{tol}, 4\varepsilon|t|)$ to ask for "a few ulp"); at most
/// `max_iter` evaluations of `g` are made. Input that is not a bracket (`fa`
/// zero or NaN, `fb` NaN or of the sign of `fa`) returns at once with
/// `converged == false`. A NaN returned by `g` during the search stops it with
/// `converged == false` and [`Bracket::nan_at`] set. Never panics.
pub fn illinois(
    a: f64,
    fa: f64,
    b: f64,
    fb: f64,
    tol: f64,
    max_iter: usize,
    mut g: impl FnMut(f64) -> f64,
) -> Bracket {
    let mut out = Bracket {
        lo: a,
        g_lo: fa,
        hi: b,
        g_hi: fb,
        evaluations: 0,
        converged: false,
        nan_at: None,
    };
    let pos_a = fa > 0.0;
    let is_bracket =
        fa != 0.0 && !fa.is_nan() && !fb.is_nan() && (fb == 0.0 || (fb > 0.0) != pos_a);
    if !is_bracket {
        return out;
    }
    // The working values fa, fb are the Illinois-scaled ones.
    let (mut a, mut fa, mut b, mut fb) = (a, fa, b, fb);
    let mut side = 0i8;
    let mut width = b - a;
    let mut slow = 0u32;
    loop {
        if fb == 0.0 || b - a <= tol {
            out.converged = true;
            break;
        }
        if out.evaluations >= max_iter {
            break;
        }
        let mut c = if slow >= 3 {
            slow = 0;
            0.5 * (a + b)
        } else {
            b - fb * (b - a) / (fb - fa)
        };
        // Never closer than half the tolerance to an end (b - a > tol here): once an end sits
        // on the root to rounding (the secant point may then round onto it), the next point
        // lands half a tolerance beyond it and closes the bracket, instead of bisecting from
        // the far end.
        let half = 0.5 * tol;
        if !c.is_nan() && b - a > 2.0 * half {
            c = c.max(a + half).min(b - half);
        }
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
            if !(c > a && c < b) {
                out.converged = true; // adjacent floats
                break;
            }
        }
        let fc = g(c);
        out.evaluations += 1;
        if fc.is_nan() {
            // No sign: the side of the root is unknown. Stop, not converged.
            out.nan_at = Some(c);
            break;
        }
        if fc == 0.0 || (fc > 0.0) != pos_a {
            b = c;
            fb = fc;
            out.hi = c;
            out.g_hi = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        } else {
            a = c;
            fa = fc;
            out.lo = c;
            out.g_lo = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        }
        if b - a > 0.5 * width {
            slow += 1;
        } else {
            slow = 0;
        }
        width = b - a;
    }
    out
}
