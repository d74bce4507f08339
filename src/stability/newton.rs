//! Newton's method for a fixed point of a map with a known Jacobian, $F(z) = P(z) - z = 0$.
//!
//! Each iteration solves $(DP(z_k) - I)\thinspace\delta = -(P(z_k) - z_k)$ by LU with partial
//! pivoting and takes the full step if it lowers the residual $\lVert F\rVert_\infty$; otherwise
//! it halves the step (up to [`NewtonOptions::max_halvings`] times), which keeps an iterate that
//! would leave the basin of the orbit from jumping to another one. It stops when
//! $\lVert F(z)\rVert_\infty \le$ [`NewtonOptions::tolerance`], and returns the point with the
//! map's value and Jacobian there (the monodromy matrix). A run that does not converge returns
//! its last iterate and residual inside the error.

use nalgebra::{DMatrix, DVector};
use thiserror::Error;

/// Options of [`newton_fixed_point`]. A plain struct with `Default`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct NewtonOptions {
    /// Convergence: $\lVert P(z) - z\rVert_\infty$ at most this. Default `1e-11`; it must be
    /// above the noise of the map's evaluation (a few `1e-15` for the paper's stroboscopic
    /// map), or no step can reach it.
    pub tolerance: f64,
    /// Largest number of Newton iterations (evaluations of the Jacobian). Default 30.
    pub max_iterations: u32,
    /// Largest number of step halvings per iteration. Default 12.
    pub max_halvings: u32,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-11,
            max_iterations: 30,
            max_halvings: 12,
        }
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
    /// the best iterate found and `residual` its $\lVert P(z) - z\rVert_\infty$. Try a better
    /// guess (a point of a longer transient), a larger tolerance (above the map's noise), or
    /// check that the orbit has this period.
    #[error("Newton did not converge after {iterations} iterations: residual {residual:e} (tolerance {tolerance:e}); {reason}")]
    NotConverged {
        /// The best iterate.
        last: DVector<f64>,
        /// Its residual.
        residual: f64,
        /// The tolerance asked for.
        tolerance: f64,
        /// Iterations made.
        iterations: u32,
        /// Why it stopped.
        reason: &'static str,
    },
    /// $DP - I$ is singular to working precision at `at` (a multiplier at 1: a fold, or a
    /// degenerate map).
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

fn sup_norm(v: &DVector<f64>) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

/// Newton's method for $P(z) = z$ from `guess` (module docs); `map(z)` returns $P(z)$ and
/// $DP(z)$.
///
/// # Errors
/// [`NewtonError`], carrying the last iterate and its residual when it did not converge.
pub fn newton_fixed_point<X, E>(
    guess: &DVector<f64>,
    mut map: impl FnMut(&DVector<f64>) -> Result<MapValue<X>, E>,
    opts: &NewtonOptions,
) -> Result<FixedPoint<X>, NewtonError<E>> {
    if !(opts.tolerance.is_finite() && opts.tolerance > 0.0) {
        return Err(NewtonError::InvalidOption {
            field: "tolerance",
            value: opts.tolerance,
            hint: "use a finite tolerance > 0 above the map's noise, e.g. 1e-11",
        });
    }
    let mut evaluations = 0u32;
    let mut eval = |z: &DVector<f64>, evaluations: &mut u32| {
        *evaluations += 1;
        map(z).map_err(|error| NewtonError::Map {
            at: z.clone(),
            error,
        })
    };
    let mut z = guess.clone();
    let mut current = eval(&z, &mut evaluations)?;
    let mut f = &current.value - &z;
    let mut residual = sup_norm(&f);
    let mut iterations = 1u32;
    loop {
        if residual <= opts.tolerance {
            return Ok(FixedPoint {
                point: z,
                map: current,
                residual,
                iterations,
                evaluations,
            });
        }
        if iterations >= opts.max_iterations {
            return Err(NewtonError::NotConverged {
                last: z,
                residual,
                tolerance: opts.tolerance,
                iterations,
                reason: "iteration limit reached",
            });
        }
        let n = z.len();
        let a = &current.jacobian - DMatrix::identity(n, n);
        let Some(step) = a.lu().solve(&(-&f)) else {
            return Err(NewtonError::Singular { at: z, residual });
        };
        if !step.iter().all(|s| s.is_finite()) {
            return Err(NewtonError::Singular { at: z, residual });
        }
        let mut scale = 1.0;
        let mut accepted = None;
        for _ in 0..=opts.max_halvings {
            let trial = &z + &step * scale;
            let value = eval(&trial, &mut evaluations)?;
            let ft = &value.value - &trial;
            let rt = sup_norm(&ft);
            if rt < residual {
                accepted = Some((trial, value, ft, rt));
                break;
            }
            scale *= 0.5;
        }
        let Some((zt, value, ft, rt)) = accepted else {
            return Err(NewtonError::NotConverged {
                last: z,
                residual,
                tolerance: opts.tolerance,
                iterations,
                reason:
                    "no step lowers the residual (it is at the map's noise, or the guess is poor)",
            });
        };
        z = zt;
        current = value;
        f = ft;
        residual = rt;
        iterations += 1;
    }
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
        let fp = newton_fixed_point(&guess, map, &NewtonOptions::default()).unwrap();
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
        match newton_fixed_point(&guess, shift, &NewtonOptions::default()) {
            Err(NewtonError::Singular { at, residual }) => {
                assert_eq!(at, guess);
                assert_eq!(residual, 1.0);
            }
            other => panic!("{other:?}"),
        }
        let opts = NewtonOptions {
            max_iterations: 2,
            tolerance: 1e-30,
            ..NewtonOptions::default()
        };
        match newton_fixed_point(&DVector::from_vec(vec![1.1, 1.9]), map, &opts) {
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
}
