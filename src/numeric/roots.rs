//! The bracketing root finder: the Illinois method.

use super::NumericError;

/// Stopping rule and safeguard of [`illinois`]: `RootOptions::default().with_tol(1e-12)`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct RootOptions {
    /// Stop when the bracket is at most this wide: an absolute width in the units of $t$ (use
    /// $\max(\text{tol}, 4\varepsilon|t|)$ to ask for "a few ulp"). Default 0: down to
    /// adjacent floats.
    pub tol: f64,
    /// Most evaluations of $g$. Default 200 (enough for four times the 52 halvings of bisection
    /// to one ulp of a bracket of one binade).
    pub max_evaluations: usize,
    /// Bisect on every fourth iteration in a row that did not halve the bracket (the worst
    /// case then is about four times bisection's iterations). Default `true`; `false` keeps the
    /// plain Illinois steps (bisecting only when the secant point leaves the bracket), which
    /// the contact-onset search uses on its convex cubics.
    pub bisect_when_slow: bool,
}

impl Default for RootOptions {
    fn default() -> Self {
        RootOptions {
            tol: 0.0,
            max_evaluations: 200,
            bisect_when_slow: true,
        }
    }
}

impl RootOptions {
    /// With this bracket width ([`RootOptions::tol`]).
    #[must_use]
    pub fn with_tol(mut self, tol: f64) -> Self {
        self.tol = tol;
        self
    }

    /// With at most this many evaluations ([`RootOptions::max_evaluations`]).
    #[must_use]
    pub fn with_max_evaluations(mut self, max_evaluations: usize) -> Self {
        self.max_evaluations = max_evaluations;
        self
    }

    /// With or without the bisection of slow steps ([`RootOptions::bisect_when_slow`]).
    #[must_use]
    pub fn with_bisect_when_slow(mut self, on: bool) -> Self {
        self.bisect_when_slow = on;
        self
    }
}

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
    /// `tol`, $g(\text{hi}) = 0$ or adjacent floats). `false` when
    /// [`RootOptions::max_evaluations`] was reached or `g` returned NaN
    /// ([`Bracket::nan_at`]).
    pub converged: bool,
    /// `Some(t)` when `g(t)` returned NaN inside the bracket: the search stopped
    /// there, not converged (NaN has no sign, so the side of the root is
    /// unknown), and `lo`, `hi`, `g_lo`, `g_hi` are the last bracket with
    /// numbers at both ends. `None` otherwise (NaN in the initial `fa`, `fb` is
    /// [`NumericError::NotABracket`]).
    pub nan_at: Option<f64>,
}

/// Illinois (modified regula falsi) on the bracket $[a, b]$ given as `(a, fa)`, `(b, fb)` with
/// `fa` $= g(a) \ne 0$ and `fb` $= g(b)$ of the opposite sign or zero; see the
/// method and its guarantee below, [`RootOptions`] for the stopping rule.
///
/// A NaN returned by `g` during the search stops it with `converged == false` and
/// [`Bracket::nan_at`] set; running out of evaluations gives `converged == false`. Never
/// panics.
///
/// # Errors
/// [`NumericError::NotABracket`] when the input is not a bracket (`fa` zero or NaN, `fb` NaN or
/// of the sign of `fa`); no evaluation of `g` is made.
///
/// # The method
///
/// Given $a < b$ with $g(a) \ne 0$ and $g(b)$ of the opposite sign (or zero),
/// each iteration takes the secant (regula falsi) point
/// $$c = b - g_b\thinspace\frac{b - a}{g_b - g_a}$$
/// and replaces the end of the same sign as $g(c)$. When the same end is kept
/// twice in a row, its stored function value is halved (the Illinois
/// modification), which restores superlinear convergence (order
/// $\approx 1.44$) where plain regula falsi stalls on one side. The iteration
/// falls back to bisection when the secant point is not strictly inside the
/// bracket, and (unless [`RootOptions::bisect_when_slow`] is off) on every fourth
/// iteration in a row that did not halve the bracket, so it never needs more than
/// about four times the iterations of bisection. A point is never taken closer
/// than `tol / 2` to an end of the bracket: once an end sits on the root to
/// rounding (the secant point of a nearly linear function does so at once), the
/// next point falls half a tolerance beyond it and closes the bracket, where the
/// far end would otherwise creep in over many iterations.
///
/// # Guarantee
///
/// If $g$ is continuous on $[a, b]$ the returned bracket always contains a
/// root, with $g(\text{lo})$ of the sign of $g(a)$ and $g(\text{hi})$ of the
/// opposite sign or zero: a sign change is never lost, whatever $g$ does
/// (round-off included), as long as it returns numbers: a NaN from $g$ stops the
/// search, not converged ([`Bracket::nan_at`]). The search stops when $\text{hi} - \text{lo} \le$
/// `tol`, when $g(\text{hi}) = 0$, when the ends are adjacent floats, or after
/// `max_evaluations` evaluations.
///
/// ```
/// use jeffcott::numeric::{illinois, RootOptions};
///
/// // The root of cos on [1, 2] (pi / 2) to 4 ulp.
/// let tol = 4.0 * f64::EPSILON * 2.0;
/// let opts = RootOptions::default().with_tol(tol).with_max_evaluations(100);
/// let r = illinois((1.0, 1f64.cos()), (2.0, 2f64.cos()), &opts, f64::cos)?;
/// assert!(r.converged && r.hi - r.lo <= tol);
/// assert!(r.g_lo > 0.0 && r.g_hi <= 0.0);
/// assert!((r.hi - std::f64::consts::FRAC_PI_2).abs() <= tol);
/// assert!(r.evaluations < 15);
/// # Ok::<(), jeffcott::numeric::NumericError>(())
/// ```
pub fn illinois(
    (a, fa): (f64, f64),
    (b, fb): (f64, f64),
    opts: &RootOptions,
    mut g: impl FnMut(f64) -> f64,
) -> Result<Bracket, NumericError> {
    let mut out = Bracket {
        lo: a,
        g_lo: fa,
        hi: b,
        g_hi: fb,
        evaluations: 0,
        converged: false,
        nan_at: None,
    };
    let is_bracket =
        fa != 0.0 && !fa.is_nan() && !fb.is_nan() && (fb == 0.0 || (fb > 0.0) != (fa > 0.0));
    if !is_bracket {
        return Err(NumericError::NotABracket { a, fa, b, fb });
    }
    let mut search = Search::new((a, fa), (b, fb));
    loop {
        if search.fb == 0.0 || search.b - search.a <= opts.tol {
            out.converged = true;
            break;
        }
        if out.evaluations >= opts.max_evaluations {
            break;
        }
        let Some(c) = search.next_point(opts) else {
            out.converged = true; // adjacent floats
            break;
        };
        let fc = g(c);
        out.evaluations += 1;
        if fc.is_nan() {
            // No sign: the side of the root is unknown. Stop, not converged.
            out.nan_at = Some(c);
            break;
        }
        search.take(c, fc, &mut out);
    }
    Ok(out)
}

/// The working state of [`illinois`]: the bracket with its Illinois-scaled values.
struct Search {
    a: f64,
    /// $g(a)$, halved each time `a` is kept twice in a row.
    fa: f64,
    b: f64,
    /// $g(b)$, halved each time `b` is kept twice in a row.
    fb: f64,
    /// Whether the initial $g(a)$ is positive: the side of `a`.
    pos_a: bool,
    /// The end replaced last: 1 for `b`, -1 for `a`, 0 before the first.
    side: i8,
    /// The bracket's width before the last step.
    width: f64,
    /// Steps in a row that did not halve the bracket.
    slow: u32,
}

impl Search {
    fn new((a, fa): (f64, f64), (b, fb): (f64, f64)) -> Self {
        Search {
            a,
            fa,
            b,
            fb,
            pos_a: fa > 0.0,
            side: 0,
            width: b - a,
            slow: 0,
        }
    }

    /// The next point strictly inside the bracket (`b - a > tol` here): the secant point, or
    /// the midpoint after slow steps or when the secant leaves the bracket; `None` when the
    /// ends are adjacent floats.
    fn next_point(&mut self, opts: &RootOptions) -> Option<f64> {
        let (a, b) = (self.a, self.b);
        let mut c = if opts.bisect_when_slow && self.slow >= 3 {
            self.slow = 0;
            0.5 * (a + b)
        } else {
            b - self.fb * (b - a) / (self.fb - self.fa)
        };
        // Never closer than half the tolerance to an end (b - a > tol here): once an end sits
        // on the root to rounding (the secant point may then round onto it), the next point
        // lands half a tolerance beyond it and closes the bracket, instead of bisecting from
        // the far end.
        let half = 0.5 * opts.tol;
        if !c.is_nan() && b - a > 2.0 * half {
            c = c.max(a + half).min(b - half);
        }
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
            if !(c > a && c < b) {
                return None;
            }
        }
        Some(c)
    }

    /// Replaces the end of the sign of `fc` by `c` (recorded in `out`), halving the value
    /// kept twice in a row (the Illinois modification), and counts the slow steps.
    fn take(&mut self, c: f64, fc: f64, out: &mut Bracket) {
        if fc == 0.0 || (fc > 0.0) != self.pos_a {
            self.b = c;
            self.fb = fc;
            out.hi = c;
            out.g_hi = fc;
            if self.side == 1 {
                self.fa *= 0.5;
            }
            self.side = 1;
        } else {
            self.a = c;
            self.fa = fc;
            out.lo = c;
            out.g_lo = fc;
            if self.side == -1 {
                self.fb *= 0.5;
            }
            self.side = -1;
        }
        if self.b - self.a > 0.5 * self.width {
            self.slow += 1;
        } else {
            self.slow = 0;
        }
        self.width = self.b - self.a;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn solve(g: impl Fn(f64) -> f64 + Copy, a: f64, b: f64, tol: f64) -> Bracket {
        illinois(
            (a, g(a)),
            (b, g(b)),
            &RootOptions::default().with_tol(tol),
            g,
        )
        .unwrap()
    }

    /// Roots of functions known in closed form, to the asked width, with the sign invariant.
    #[test]
    fn roots_of_known_functions() {
        // (g, a, b, the root in closed form)
        type Case = (fn(f64) -> f64, f64, f64, f64);
        let cases: [Case; 5] = [
            (|x| x * x - 2.0, 1.0, 2.0, 2f64.sqrt()),
            (|x| x * x * x - 2.0, 0.0, 3.0, 2f64.cbrt()),
            (|x| x.exp() - 3.0, 0.0, 2.0, 3f64.ln()),
            (|x| 0.5 - x.sin(), 0.0, 1.5, std::f64::consts::FRAC_PI_6),
            (|x| (x - 1.0).powi(9) - 1e-9, 0.0, 3.0, 1.0 + 0.1),
        ];
        for (g, a, b, root) in cases {
            for tol in [1e-6, 1e-12, 0.0] {
                let r = solve(g, a, b, tol);
                assert!(r.converged, "{r:?}");
                // Stopped by the width, or by an exact zero at `hi` (then `hi` is the root).
                let width = tol.max(4.0 * f64::EPSILON * root);
                assert!(r.hi - r.lo <= width || r.g_hi == 0.0, "{r:?}");
                assert!(
                    (r.g_lo > 0.0) == (g(a) > 0.0)
                        && (r.g_hi == 0.0 || (r.g_hi > 0.0) != (g(a) > 0.0))
                );
                assert!(
                    r.lo - 4.0 * f64::EPSILON * root <= root
                        && root <= r.hi + 4.0 * f64::EPSILON * root,
                    "{r:?} vs {root}"
                );
                // At most about four times bisection's evaluations (52 halvings per binade).
                assert!(r.evaluations <= 4 * 60, "{r:?}");
                assert_eq!(r.nan_at, None);
            }
        }
    }

    /// A linear function: the first secant point is the root (to rounding), and the next
    /// point, half a tolerance beyond, closes the bracket.
    #[test]
    fn linear_function_closes_in_two_evaluations() {
        let r = solve(|x| 3.0 * x - 1.0, 0.0, 1.0, 1e-9);
        assert!(r.converged);
        assert!(r.evaluations <= 2, "{r:?}");
        assert!(r.lo <= 1.0 / 3.0 && 1.0 / 3.0 <= r.hi);
    }

    #[test]
    fn a_bracket_without_a_sign_change_is_an_error() {
        let g = |x: f64| x * x + 1.0;
        for (fa, fb) in [
            (g(-1.0), g(1.0)),
            (0.0, 1.0),
            (f64::NAN, -1.0),
            (1.0, f64::NAN),
        ] {
            let mut calls = 0;
            let r = illinois((-1.0, fa), (1.0, fb), &RootOptions::default(), |x| {
                calls += 1;
                g(x)
            });
            assert!(matches!(r, Err(NumericError::NotABracket { .. })), "{r:?}");
            assert_eq!(calls, 0);
        }
        // A zero at the second end is a bracket, converged at once.
        let r = illinois((0.0, -1.0), (1.0, 0.0), &RootOptions::default(), |x| {
            x - 1.0
        })
        .unwrap();
        assert!(r.converged && r.evaluations == 0 && r.hi == 1.0);
    }

    #[test]
    fn capped_search_is_not_converged() {
        let g = |x: f64| x.exp() - 3.0;
        let opts = RootOptions::default()
            .with_tol(1e-15)
            .with_max_evaluations(3);
        let r = illinois((0.0, g(0.0)), (2.0, g(2.0)), &opts, g).unwrap();
        assert!(!r.converged);
        assert_eq!(r.evaluations, 3);
        assert!(r.lo < 3f64.ln() && 3f64.ln() < r.hi);
    }

    #[test]
    fn nan_inside_stops_not_converged() {
        let g = |x: f64| {
            if x > 0.4 && x < 0.6 {
                f64::NAN
            } else {
                x - 0.5
            }
        };
        let r = illinois(
            (0.0, -0.5),
            (1.0, 0.5),
            &RootOptions::default().with_tol(1e-12),
            g,
        )
        .unwrap();
        assert!(!r.converged);
        assert!(r.nan_at.is_some_and(|t| t > 0.4 && t < 0.6));
        assert!(r.g_lo < 0.0 && r.g_hi > 0.0);
    }

    /// On a function where regula falsi keeps one end, the bisection safeguard bounds the
    /// evaluations; without it the search still converges (the Illinois halving) but may
    /// take other steps.
    #[test]
    fn slow_steps_are_bisected() {
        let g = |x: f64| x.powi(15) - 0.5;
        let root = 0.5f64.powf(1.0 / 15.0);
        for slow in [true, false] {
            let opts = RootOptions::default()
                .with_tol(1e-13)
                .with_bisect_when_slow(slow);
            let r = illinois((0.0, g(0.0)), (1.2, g(1.2)), &opts, g).unwrap();
            assert!(r.converged, "{slow}: {r:?}");
            assert!(r.lo - 1e-13 <= root && root <= r.hi + 1e-13);
            if slow {
                assert!(r.evaluations <= 4 * 44, "{r:?}");
            }
        }
    }
}
