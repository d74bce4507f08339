//! Bisection on a yes/no test.

/// Which end of the bracket a probed point is like (the answer of the test given to
/// [`bisect`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Side {
    /// Like the `near` end: the point becomes the new `near` end.
    Near,
    /// Like the `far` end (or undecidable): the point becomes the new `far` end.
    Far,
}

/// The result of [`bisect`]: the final bracket and how it was obtained.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bisection {
    /// The end like the initial `near` end (the initial one if no probe answered
    /// [`Side::Near`]).
    pub near: f64,
    /// The end like the initial `far` end (the initial one if no probe answered [`Side::Far`]).
    pub far: f64,
    /// Probes made (calls of the test).
    pub evaluations: usize,
    /// Whether the search ended by its tolerance ($|\text{far} - \text{near}| \le$ `tol`, or the
    /// ends adjacent floats). `false` when `max_evaluations` was reached or an end is not finite
    /// (then no probe is made).
    pub converged: bool,
}

impl Bisection {
    /// The midpoint of the final bracket.
    pub fn midpoint(&self) -> f64 {
        0.5 * (self.near + self.far)
    }
}

/// Bisects the bracket between `near` and `far` (either may be the larger) on a test: the
/// midpoint is probed and replaces the end it is like, until the bracket is at most `tol`
/// wide (or its ends are adjacent floats), or after `max_evaluations` probes.
///
/// The test `probe(x)` answers [`Side::Near`] or [`Side::Far`], or fails with the caller's
/// error, which stops the search and is returned as is. When the test changes its answer only
/// once between the ends, the final bracket holds that change; otherwise it holds one of the
/// changes (not necessarily the nearest). The ends' own answers are not asked for: the caller
/// knows them. Non-finite ends or a NaN `tol` return at once, not converged. Never panics.
///
/// # Errors
/// The first error of `probe`.
pub fn bisect<E>(
    near: f64,
    far: f64,
    tol: f64,
    max_evaluations: usize,
    mut probe: impl FnMut(f64) -> Result<Side, E>,
) -> Result<Bisection, E> {
    let mut out = Bisection {
        near,
        far,
        evaluations: 0,
        converged: false,
    };
    if !(near.is_finite() && far.is_finite()) || tol.is_nan() {
        return Ok(out);
    }
    while (out.far - out.near).abs() > tol {
        if out.evaluations >= max_evaluations {
            return Ok(out);
        }
        let mid = 0.5 * (out.near + out.far);
        if mid == out.near || mid == out.far {
            break; // adjacent floats
        }
        out.evaluations += 1;
        match probe(mid)? {
            Side::Near => out.near = mid,
            Side::Far => out.far = mid,
        }
    }
    out.converged = true;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The test "x is below the threshold", whose change is at `threshold` exactly.
    fn below(threshold: f64) -> impl FnMut(f64) -> Result<Side, ()> {
        move |x| Ok(if x < threshold { Side::Near } else { Side::Far })
    }

    #[test]
    fn finds_a_threshold_from_either_side() {
        for (near, far) in [(0.0, 1.0), (1.0, 0.0)] {
            let t = 0.3;
            let probe = move |x: f64| {
                Ok::<_, ()>(if (x < t) == (near < t) {
                    Side::Near
                } else {
                    Side::Far
                })
            };
            let b = bisect(near, far, 1e-10, 100, probe).unwrap();
            assert!(b.converged);
            assert!((b.far - b.near).abs() <= 1e-10);
            assert!((b.near < t) == (near < t) && (b.far < t) != (near < t));
            // Bisection: the width halves per probe, so 34 probes from width 1 to 1e-10.
            assert_eq!(b.evaluations, 34);
            assert!((b.midpoint() - t).abs() <= 1e-10);
        }
    }

    #[test]
    fn zero_tolerance_stops_at_adjacent_floats() {
        let b = bisect(1.0, 2.0, 0.0, 1000, below(1.5f64.next_up())).unwrap();
        assert!(b.converged);
        assert_eq!(b.near, 1.5);
        assert_eq!(b.far, 1.5f64.next_up());
    }

    #[test]
    fn capped_search_is_not_converged() {
        let b = bisect(0.0, 1.0, 1e-12, 5, below(0.3)).unwrap();
        assert!(!b.converged);
        assert_eq!(b.evaluations, 5);
        assert!((b.far - b.near - 1.0 / 32.0).abs() < 1e-15);
        assert!(b.near < 0.3 && b.far >= 0.3);
    }

    #[test]
    fn probe_error_is_returned() {
        let mut calls = 0;
        let r = bisect(0.0, 1.0, 1e-12, 100, |x| {
            calls += 1;
            if calls == 3 {
                Err(x)
            } else {
                Ok(Side::Near)
            }
        });
        assert_eq!(r, Err(0.875));
    }

    #[test]
    fn non_finite_input_is_not_converged() {
        for (a, b, tol) in [
            (f64::NAN, 1.0, 1e-3),
            (0.0, f64::INFINITY, 1e-3),
            (0.0, 1.0, f64::NAN),
        ] {
            let r = bisect(a, b, tol, 100, below(0.5)).unwrap();
            assert!(!r.converged);
            assert_eq!(r.evaluations, 0);
        }
    }
}
