use nalgebra::{DMatrix, DVector};
use thiserror::Error;

/// Options of [`newton_fixed_point`]: `Default`, then the builder methods.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct NewtonOptions {
    /// Absolute residual tolerance, in units of each component's scale (module docs). Default
    /// `1e-11`; it must be above the noise of the map's evaluation (a few `1e-15` for the
    /// paper's stroboscopic map), or no step can reach it.
    pub atol: f64,
    /// Relative residual tolerance (module docs). Default 0: the absolute test alone, as the
    /// map's noise on the paper's orbits (of size 1) is far below `atol`.
    pub rtol: f64,
    /// Largest number of Newton iterations (evaluations of the Jacobian). Default 30.
    pub max_iterations: u32,
    /// Largest number of step halvings per iteration. Default 12.
    pub max_halvings: u32,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            atol: 1e-11,
            rtol: 0.0,
            max_iterations: 30,
            max_halvings: 12,
        }
    }
}

impl NewtonOptions {
    /// With the absolute residual tolerance [`atol`](Self::atol).
    pub fn with_atol(mut self, atol: f64) -> Self {
        self.atol = atol;
        self
    }
    /// With the relative residual tolerance [`rtol`](Self::rtol).
    pub fn with_rtol(mut self, rtol: f64) -> Self {
        self.rtol = rtol;
        self
    }
    /// With at most `n` iterations.
    pub fn with_max_iterations(mut self, n: u32) -> Self {
        self.max_iterations = n;
        self
    }
    /// With at most `n` halvings per iteration.
    pub fn with_max_halvings(mut self, n: u32) -> Self {
        self.max_halvings = n;
        self
    }
}

/// The map evaluated at a point.
#[derive(Debug, Clone, PartialEq)]
pub struct MapValue<X> {
    /// $P(z)$.
    pub value: DVector<f64>,
    /// $DP(z)$.
    pub jacobian: DMatrix<f64>,
    /// Whatever else the map reports with it (event log, margins).
    pub extra: X,
}

/// A converged fixed point.
#[derive(Debug, Clone, PartialEq)]
pub struct FixedPoint<X> {
    /// The point $z^{\ast}$.
    pub point: DVector<f64>,
    /// The map there, with its Jacobian (the monodromy matrix).
    pub map: MapValue<X>,
    /// $\lVert P(z^{\ast}) - z^{\ast}\rVert_\infty$.
    pub residual: f64,
    /// Newton iterations made (Jacobians evaluated, the last one included).
    pub iterations: u32,
    /// Evaluations of the map (with the halvings).
    pub evaluations: u32,
}

/// Why Newton's method stopped without a fixed point.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum NewtonError<E> {
    /// No convergence within the iteration limit, or no step lowered the residual: `last` is
    /// the best iterate found and `residual` its $\lVert G\rVert_\infty$. Try a better guess
    /// (a point of a longer transient), a larger tolerance (above the map's noise), or check
    /// that the orbit has this period.
    #[error("Newton did not converge after {iterations} iterations: residual {residual:e} (tolerance {tolerance:e}); {reason}")]
    NotConverged {
        /// The best iterate.
        last: DVector<f64>,
        /// Its residual.
        residual: f64,
        /// The absolute tolerance asked for.
        tolerance: f64,
        /// Iterations made.
        iterations: u32,
        /// Why it stopped.
        reason: &'static str,
    },
    /// The Newton matrix ($DP - I$ for a fixed point) is singular to working precision at
    /// `at` (a multiplier at 1: a fold, or a degenerate map).
    #[error("DP - I is singular (a multiplier is 1 to working precision)")]
    Singular {
        /// The iterate.
        at: DVector<f64>,
        /// Its residual.
        residual: f64,
    },
    /// The map could not be evaluated at `at`.
    #[error("the map failed at an iterate: {error}")]
    Map {
        /// The point.
        at: DVector<f64>,
        /// The map's error.
        error: E,
    },
    /// The options are invalid.
    #[error("invalid Newton option `{field}` = {value}: {hint}")]
    InvalidOption {
        /// The option.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What to use.
        hint: &'static str,
    },
}

/// A system $G(u) = 0$ evaluated at a point: $G$, the Newton matrix $\partial G/\partial u$,
/// and what else the evaluation reports.
pub(crate) struct System<X> {
    /// $G(u)$.
    pub(crate) residual: DVector<f64>,
    /// $\partial G/\partial u$.
    pub(crate) matrix: DMatrix<f64>,
    /// The rest.
    pub(crate) extra: X,
}

/// A converged zero of a [`System`].
pub(crate) struct Zero<X> {
    pub(crate) u: DVector<f64>,
    pub(crate) system: System<X>,
    pub(crate) residual: f64,
    pub(crate) iterations: u32,
    pub(crate) evaluations: u32,
    /// The evaluations of the full [`System`] among them.
    pub(crate) full_evaluations: u32,
}

/// How [`solve`] steps and stops.
pub(crate) struct Rule<'a> {
    pub(crate) opts: &'a NewtonOptions,
    /// The scale $s_i$ of each component of $G$ (module docs).
    pub(crate) scale: &'a DVector<f64>,
    /// `Some(factor)`: the last component is a constraint row, converged at `factor * atol`
    /// (its scale 1, no relative part); `None`: no constraint.
    pub(crate) constraint: Option<f64>,
    /// Halve a step that does not lower the residual (`false`: always take the full step,
    /// as a pseudo-arclength corrector does, whose constraint may need the residual to grow).
    pub(crate) line_search: bool,
}

impl Rule<'_> {
    /// The scaled residual: the largest $|G_i|/(\text{atol}\thinspace s_i + \text{rtol}|u_i|)$, below 1
    /// when converged.
    fn scaled(&self, g: &DVector<f64>, u: &DVector<f64>) -> f64 {
        let n = g.len();
        g.iter()
            .enumerate()
            .map(|(i, gi)| {
                let tol = match self.constraint {
                    Some(factor) if i + 1 == n => factor * self.opts.atol,
                    _ => {
                        let s = self.scale.get(i).copied().unwrap_or(1.0);
                        self.opts.atol * s + self.opts.rtol * u.get(i).map_or(0.0, |v| v.abs())
                    }
                };
                if gi.is_nan() {
                    f64::INFINITY
                } else {
                    gi.abs() / tol
                }
            })
            .fold(0.0, f64::max)
    }
}

fn check<E>(opts: &NewtonOptions) -> Result<(), NewtonError<E>> {
    let bad = |field, value: f64| NewtonError::InvalidOption {
        field,
        value,
        hint: "use a finite tolerance >= 0 above the map's noise (atol > 0, e.g. 1e-11)",
    };
    if !(opts.atol.is_finite() && opts.atol > 0.0) {
        return Err(bad("atol", opts.atol));
    }
    if !(opts.rtol.is_finite() && opts.rtol >= 0.0) {
        return Err(bad("rtol", opts.rtol));
    }
    Ok(())
}

/// The one Newton: $G(u) = 0$ from `u0` (module docs); `eval(u)` returns the [`System`] at
/// `u`. Used by [`newton_fixed_point`] and the continuation's corrector.
pub(crate) fn solve<X, E>(
    u0: &DVector<f64>,
    eval: impl FnMut(&DVector<f64>) -> Result<System<X>, E>,
    rule: &Rule<'_>,
) -> Result<Zero<X>, NewtonError<E>> {
    solve_held(
        u0,
        eval,
        None::<Held<fn(&DVector<f64>) -> Result<DVector<f64>, E>>>,
        rule,
    )
}

/// A Newton matrix held over the steps ([`solve_held`]): the simplified (chord) Newton.
pub(crate) struct Held<R> {
    /// The matrix to start from: $\partial G/\partial u$ at a point near `u0` (a branch's
    /// previous point).
    pub(crate) matrix: DMatrix<f64>,
    /// $G(u)$ alone: far cheaper than the [`System`] where the matrix is the variational
    /// equations' (one run instead of one with a column per component).
    pub(crate) residual: R,
}

/// Whether a held matrix still serves: the scaled residual of a chord step must fall at least
/// by this factor, or the matrix is refreshed where the step landed (as Hairer's RADAU5 does
/// with its contraction estimate).
const CHORD_CONTRACTION: f64 = 0.5;

/// [`solve`], with the Newton matrix `held` over the steps when given (the simplified Newton:
/// each step one evaluation of $G$ alone), refreshed by `eval` where a step does not contract
/// by [`CHORD_CONTRACTION`] or the held matrix is singular, and `eval` taken once more at the
/// zero (its [`System`] is returned). Without `held`, every step evaluates the [`System`]:
/// Newton itself.
pub(crate) fn solve_held<X, E, R>(
    u0: &DVector<f64>,
    mut eval: impl FnMut(&DVector<f64>) -> Result<System<X>, E>,
    held: Option<Held<R>>,
    rule: &Rule<'_>,
) -> Result<Zero<X>, NewtonError<E>>
where
    R: FnMut(&DVector<f64>) -> Result<DVector<f64>, E>,
{
    check(rule.opts)?;
    let opts = rule.opts;
    let (mut evaluations, mut full_evaluations) = (0u32, 0u32);
    let chord = held.is_some();
    let (mut residual_of, held_matrix) = match held {
        Some(h) => (Some(h.residual), Some(h.matrix)),
        None => (None, None),
    };
    // One evaluation at `u`: the full System (`full`), or G alone with the held matrix.
    let mut at = |u: &DVector<f64>, full: bool, evaluations: &mut u32| {
        *evaluations += 1;
        full_evaluations += u32::from(full || residual_of.is_none());
        let map_error = |error| NewtonError::Map {
            at: u.clone(),
            error,
        };
        match residual_of.as_mut() {
            Some(residual) if !full => residual(u).map(Point::Residual).map_err(map_error),
            _ => eval(u).map(Point::Full).map_err(map_error),
        }
    };
    let not_converged = |last, residual, iterations, reason| NewtonError::NotConverged {
        last,
        residual,
        tolerance: opts.atol,
        iterations,
        reason,
    };
    let mut u = u0.clone();
    let mut current = at(&u, held_matrix.is_none(), &mut evaluations)?;
    let mut matrix = match &current {
        Point::Full(s) => s.matrix.clone(),
        Point::Residual(_) => held_matrix.unwrap_or_default(),
    };
    let mut lu = matrix.clone().lu();
    let mut scaled = rule.scaled(current.residual(), &u);
    let (mut iterations, mut rising) = (1u32, 0u32);
    loop {
        let residual = current.residual().amax();
        if scaled <= 1.0 {
            let system = match current {
                Point::Full(s) => s,
                Point::Residual(_) => match at(&u, true, &mut evaluations)? {
                    Point::Full(s) => s,
                    Point::Residual(_) => unreachable!("a full evaluation asked"),
                },
            };
            return Ok(Zero {
                u,
                system,
                residual,
                iterations,
                evaluations,
                full_evaluations,
            });
        }
        if !residual.is_finite() {
            return Err(not_converged(
                u,
                residual,
                iterations,
                "non-finite residual",
            ));
        }
        if iterations >= opts.max_iterations {
            return Err(not_converged(
                u,
                residual,
                iterations,
                "iteration limit reached",
            ));
        }
        let fresh = matches!(current, Point::Full(_));
        let solved = lu.solve(&(-current.residual()));
        let step = solved.filter(|s| !rule.line_search || s.iter().all(|v| v.is_finite()));
        let Some(step) = step else {
            if fresh {
                return Err(NewtonError::Singular { at: u, residual });
            }
            // A held matrix singular here: the one at this iterate instead.
            current = at(&u, true, &mut evaluations)?;
            if let Point::Full(s) = &current {
                matrix.copy_from(&s.matrix);
                lu = matrix.clone().lu();
            }
            continue;
        };
        let trial = |factor: f64| {
            let trial = &u + &step * factor;
            let value = at(&trial, !chord, &mut evaluations)?;
            let st = rule.scaled(value.residual(), &trial);
            Ok((trial, value, st))
        };
        let Some((ut, value, st)) = halve(trial, rule, scaled)? else {
            let reason =
                "no step lowers the residual (it is at the map's noise, or the guess is poor)";
            return Err(not_converged(u, residual, iterations, reason));
        };
        // Held, a corrector is one of many tried (a smaller step follows): where even the
        // Jacobian at the iterate raises the residual twice there is no zero near, and the
        // steps left would each cost a full evaluation.
        rising += u32::from(chord && fresh && st >= scaled);
        if rising >= 2 {
            let reason = "the residual rose twice under the Jacobian at the iterate";
            return Err(not_converged(u, residual, iterations, reason));
        }
        let stale = chord && st > CHORD_CONTRACTION * scaled;
        if chord && !stale {
            broyden(
                &mut matrix,
                &(&ut - &u),
                &(value.residual() - current.residual()),
            );
        }
        (u, current, scaled) = (ut, value, st);
        if stale && scaled > 1.0 {
            current = at(&u, true, &mut evaluations)?;
        }
        if let Point::Full(s) = &current {
            matrix.copy_from(&s.matrix);
        }
        lu = matrix.clone().lu();
        iterations += 1;
    }
}

/// Broyden's ("good") rank-one update of the Newton matrix `b` by a step `s` and the change
/// `y` of the residual it made: $B \leftarrow B + (y - Bs)\thinspace s^T / s^Ts$, the
/// least change of $B$ with $Bs = y$. It turns the held matrix's linear convergence superlinear, and
/// leaves exact rows (a linear constraint's) exact.
fn broyden(b: &mut DMatrix<f64>, s: &DVector<f64>, y: &DVector<f64>) {
    let ss = s.norm_squared();
    if ss > 0.0 && ss.is_finite() {
        let r = y - &*b * s;
        b.ger(1.0 / ss, &r, s, 1.0);
    }
}

/// One evaluation of [`solve_held`]: the full [`System`], or the residual alone.
enum Point<X> {
    Full(System<X>),
    Residual(DVector<f64>),
}

impl<X> Point<X> {
    fn residual(&self) -> &DVector<f64> {
        match self {
            Point::Full(s) => &s.residual,
            Point::Residual(g) => g,
        }
    }
}

/// A trial step of [`solve`]: the point, the system there and its scaled residual.
type Trial<X> = (DVector<f64>, Point<X>, f64);

/// The full step, halved (with the line search) until it lowers the scaled residual
/// `scaled`; `None` if no halving does.
fn halve<X, E>(
    mut trial: impl FnMut(f64) -> Result<Trial<X>, NewtonError<E>>,
    rule: &Rule<'_>,
    scaled: f64,
) -> Result<Option<Trial<X>>, NewtonError<E>> {
    let mut factor = 1.0;
    for _ in 0..=rule.opts.max_halvings {
        let t = trial(factor)?;
        if !rule.line_search || t.2 < scaled {
            return Ok(Some(t));
        }
        factor *= 0.5;
    }
    Ok(None)
}

/// Newton's method for $P(z) = z$ from `guess` (module docs); `map(z)` returns $P(z)$ and
/// $DP(z)$; `scale` is the scale of each component of $z$ (`None`: 1 for every one).
///
/// # Errors
/// [`NewtonError`], carrying the last iterate and its residual when it did not converge.
///
/// ```
/// use jeffcott::nalgebra::{DMatrix, DVector};
/// use jeffcott::stability::{newton_fixed_point, MapValue, NewtonOptions};
///
/// // An affine map P(z) = A z + b: its fixed point is (I - A)^{-1} b = (2.5, 2.5).
/// let a = DMatrix::from_row_slice(2, 2, &[0.5, 0.1, 0.0, 0.2]);
/// let b = DVector::from_vec(vec![1.0, 2.0]);
/// let map = |z: &DVector<f64>| {
///     Ok::<_, std::convert::Infallible>(MapValue { value: &a * z + &b, jacobian: a.clone(), extra: () })
/// };
/// let fixed = newton_fixed_point(&DVector::zeros(2), map, None, &NewtonOptions::default())?;
/// assert!((fixed.point - DVector::from_vec(vec![2.5, 2.5])).amax() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn newton_fixed_point<X, E>(
    guess: &DVector<f64>,
    mut map: impl FnMut(&DVector<f64>) -> Result<MapValue<X>, E>,
    scale: Option<&DVector<f64>>,
    opts: &NewtonOptions,
) -> Result<FixedPoint<X>, NewtonError<E>> {
    let ones = DVector::from_element(guess.len(), 1.0);
    let rule = Rule {
        opts,
        scale: scale.unwrap_or(&ones),
        constraint: None,
        line_search: true,
    };
    let n = guess.len();
    let eval = |z: &DVector<f64>| {
        map(z).map(|m| System {
            residual: &m.value - z,
            matrix: &m.jacobian - DMatrix::identity(n, n),
            extra: m,
        })
    };
    let zero = solve(guess, eval, &rule)?;
    Ok(FixedPoint {
        point: zero.u,
        map: zero.system.extra,
        residual: zero.residual,
        iterations: zero.iterations,
        evaluations: zero.evaluations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A smooth map of the plane with a fixed point at (1, 2) and multipliers 0.5, -0.3.
    fn map(z: &DVector<f64>) -> Result<MapValue<()>, ()> {
        let (x, y) = (z[0] - 1.0, z[1] - 2.0);
        let value = DVector::from_vec(vec![1.0 + 0.5 * x + 0.2 * y * y, 2.0 - 0.3 * y + x * x]);
        let jacobian = DMatrix::from_row_slice(2, 2, &[0.5, 0.4 * y, 2.0 * x, -0.3]);
        Ok(MapValue {
            value,
            jacobian,
            extra: (),
        })
    }

    #[test]
    fn converges_quadratically_to_the_fixed_point() {
        let guess = DVector::from_vec(vec![1.1, 1.9]);
        let fp = newton_fixed_point(&guess, map, None, &NewtonOptions::default()).unwrap();
        assert!((fp.point[0] - 1.0).abs() < 1e-12 && (fp.point[1] - 2.0).abs() < 1e-12);
        assert!(fp.residual <= 1e-11);
        assert!(fp.iterations <= 7, "{}", fp.iterations);
        assert!((fp.map.jacobian[(0, 0)] - 0.5).abs() < 1e-11);
    }

    #[test]
    fn failure_returns_the_last_iterate_and_its_residual() {
        // A map with no fixed point: P(z) = z + 1.
        let shift = |z: &DVector<f64>| -> Result<MapValue<()>, ()> {
            Ok(MapValue {
                value: z.add_scalar(1.0),
                jacobian: DMatrix::identity(2, 2),
                extra: (),
            })
        };
        let guess = DVector::from_vec(vec![0.0, 0.0]);
        match newton_fixed_point(&guess, shift, None, &NewtonOptions::default()) {
            Err(NewtonError::Singular { at, residual }) => {
                assert_eq!(at, guess);
                assert_eq!(residual, 1.0);
            }
            other => panic!("{other:?}"),
        }
        let opts = NewtonOptions::default()
            .with_max_iterations(2)
            .with_atol(1e-30);
        match newton_fixed_point(&DVector::from_vec(vec![1.1, 1.9]), map, None, &opts) {
            Err(NewtonError::NotConverged {
                last,
                residual,
                iterations,
                ..
            }) => {
                assert_eq!(iterations, 2);
                assert!(residual < 0.1 && residual > 0.0);
                assert!((last[0] - 1.0).abs() < 0.1);
            }
            other => panic!("{other:?}"),
        }
    }

    /// Full steps, no constraint.
    fn full_steps<'a>(opts: &'a NewtonOptions, ones: &'a DVector<f64>) -> Rule<'a> {
        Rule {
            opts,
            scale: ones,
            constraint: None,
            line_search: false,
        }
    }

    /// [`map`]'s fixed-point system $G = P(z) - z$ and its residual alone.
    fn system(z: &DVector<f64>) -> Result<System<()>, ()> {
        let m = map(z)?;
        Ok(System {
            residual: &m.value - z,
            matrix: &m.jacobian - DMatrix::identity(2, 2),
            extra: (),
        })
    }

    fn held(matrix: DMatrix<f64>) -> Held<impl FnMut(&DVector<f64>) -> Result<DVector<f64>, ()>> {
        Held {
            matrix,
            residual: |z: &DVector<f64>| system(z).map(|s| s.residual),
        }
    }

    #[test]
    fn a_held_matrix_reaches_newtons_zero_and_returns_the_system_there() {
        let (opts, ones) = (NewtonOptions::default(), DVector::from_element(2, 1.0));
        let rule = full_steps(&opts, &ones);
        let guess = DVector::from_vec(vec![1.1, 1.9]);
        // The matrix of a point 0.05 away: near, not exact.
        let near = system(&DVector::from_vec(vec![1.05, 1.95])).unwrap().matrix;
        let newton = solve(&guess, system, &rule).unwrap();
        let chord = solve_held(&guess, system, Some(held(near)), &rule).unwrap();
        assert!((&chord.u - &newton.u).amax() < 1e-11);
        // One full evaluation, at the zero: its matrix is the map's there.
        assert_eq!(chord.full_evaluations, 1);
        let exact = system(&chord.u).unwrap().matrix;
        assert_eq!(chord.system.matrix, exact);
        assert_eq!(newton.full_evaluations, newton.evaluations);
    }

    #[test]
    fn a_held_matrix_that_does_not_contract_is_refreshed() {
        let (opts, ones) = (NewtonOptions::default(), DVector::from_element(2, 1.0));
        let rule = full_steps(&opts, &ones);
        let guess = DVector::from_vec(vec![1.1, 1.9]);
        // Three times the true matrix: each chord step a third of Newton's, the residual
        // falling by about 2/3 a step, too slowly.
        let wrong = system(&guess).unwrap().matrix * 3.0;
        let chord = solve_held(&guess, system, Some(held(wrong)), &rule).unwrap();
        assert!((chord.u[0] - 1.0).abs() < 1e-12 && (chord.u[1] - 2.0).abs() < 1e-12);
        assert!(chord.full_evaluations >= 2, "{}", chord.full_evaluations);
    }

    #[test]
    fn a_held_correction_without_a_zero_gives_up_when_newton_raises_the_residual_twice() {
        // G = (x^2 + 1, y): no zero; Newton's x wanders (x -> (x^2 - 1)/2x).
        let g = |u: &DVector<f64>| DVector::from_vec(vec![u[0] * u[0] + 1.0, u[1]]);
        let full = |u: &DVector<f64>| {
            Ok::<_, ()>(System {
                residual: g(u),
                matrix: DMatrix::from_row_slice(2, 2, &[2.0 * u[0], 0.0, 0.0, 1.0]),
                extra: (),
            })
        };
        let (opts, ones) = (NewtonOptions::default(), DVector::from_element(2, 1.0));
        let rule = full_steps(&opts, &ones);
        let start = DVector::from_vec(vec![0.7, 0.1]);
        let held = Held {
            matrix: full(&start).unwrap().matrix,
            residual: |u: &DVector<f64>| Ok::<_, ()>(g(u)),
        };
        match solve_held(&start, full, Some(held), &rule) {
            Err(NewtonError::NotConverged {
                iterations, reason, ..
            }) => {
                assert!(reason.contains("rose twice"), "{reason}");
                assert!(iterations < opts.max_iterations, "{iterations}");
            }
            other => panic!("{:?}", other.map(|z| z.u)),
        }
    }

    #[test]
    fn broydens_update_meets_the_secant_and_keeps_an_exact_row() {
        let mut b = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 3.0, 4.0]);
        let s = DVector::from_vec(vec![0.5, -1.0]);
        // The second row's change is exactly its row times s: that row must not move.
        let y = DVector::from_vec(vec![2.0, 3.0 * 0.5 - 4.0]);
        broyden(&mut b, &s, &y);
        assert!((&b * &s - &y).amax() < 1e-15);
        assert_eq!(b.row(1), DMatrix::from_row_slice(1, 2, &[3.0, 4.0]).row(0));
    }

    #[test]
    fn the_stopping_rule_follows_the_scale_of_the_state() {
        // The same map in units 1e-5 times smaller (an SI rotor in metres): with the scale
        // 1e-5 Newton takes the same iterations to the same relative accuracy; an absolute
        // test at 1e-11 would stop at a relative error near 1e-6.
        let unit = 1e-5;
        let si = |z: &DVector<f64>| -> Result<MapValue<()>, ()> {
            let m = map(&(z / unit))?;
            Ok(MapValue {
                value: m.value * unit,
                jacobian: m.jacobian,
                extra: (),
            })
        };
        let opts = NewtonOptions::default();
        let guess = DVector::from_vec(vec![1.1, 1.9]);
        let reference = newton_fixed_point(&guess, map, None, &opts).unwrap();
        let scale = DVector::from_element(2, unit);
        let scaled = newton_fixed_point(&(&guess * unit), si, Some(&scale), &opts).unwrap();
        assert_eq!(scaled.iterations, reference.iterations);
        for i in 0..2 {
            let relative = (scaled.point[i] / unit - reference.point[i]).abs();
            assert!(relative < 1e-12, "component {i}: {relative:e}");
        }
    }
}
