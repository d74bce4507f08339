//! The dominant Floquet multipliers without the dense monodromy matrix
//! ([`dominant_multipliers`]).

use nalgebra::{DMatrix, DVector, DefaultAllocator, OVector};

use super::error::StabilityError;
use super::floquet::Multiplier;
use super::map::StroboscopicMap;
use crate::hybrid::{SimOptions, Variational, VariationalAlloc};
use crate::numeric::{arnoldi, ArnoldiOptions};

/// The multipliers of largest modulus of [`dominant_multipliers`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DominantMultipliers {
    /// The multipliers, largest modulus first (a complex pair as $\lambda, \bar\lambda$ when
    /// both are among them).
    pub multipliers: Vec<Multiplier>,
    /// Each one's Ritz residual $|DP^n x - \mu x|$ ($|x| = 1$), relative to the largest
    /// modulus: the error of the multiplier is about this for a well-conditioned one.
    pub residuals: Vec<f64>,
    /// Jacobian-vector products taken (each one run of the map with one variational column).
    pub actions: usize,
    /// Whether every residual is within the tolerance asked for.
    pub converged: bool,
}

/// The `opts.count` Floquet multipliers of largest modulus of the `periods`-period map of
/// `model` at the full state `y` (a periodic orbit's point; at any other state, the dominant
/// eigenvalues of $DP^n$ there), matrix-free: the Arnoldi iteration ([`arnoldi`]) on the
/// Jacobian-vector products $q \mapsto DP^n q$ ([`StroboscopicMap::linearize_along`], one
/// variational column a run, through every event's saltation), never the $k \times k$
/// monodromy matrix of the map's $k$ components.
///
/// Each action is a run of the map with one column, so the cost is about `actions` runs
/// against the dense path's one run with $k$ columns
/// ([`StroboscopicMap::linearize`], then [`multipliers`](super::multipliers)): it pays where
/// a right-hand side costs far more than a column of the variational equations times the
/// actions needed (hundreds of coordinates), and the dense path stays the one for small
/// models. A damped orbit's spectrum is a few multipliers near the unit circle and many near
/// zero, which Arnoldi finds in a few dozen actions. The start vector is fixed (the result is
/// deterministic).
///
/// # Errors
/// [`StabilityError::InvalidOption`] for `periods = 0`; the runs' errors
/// ([`StabilityError::Simulation`]); [`StabilityError::Numeric`] for options out of range or a
/// failed eigenvalue problem of the Krylov space.
pub fn dominant_multipliers<M>(
    model: &M,
    y: &OVector<f64, M::Dim>,
    periods: u64,
    sim: SimOptions,
    opts: &ArnoldiOptions,
) -> Result<DominantMultipliers, StabilityError>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let map = StroboscopicMap::new(model, periods, sim)?;
    let k = map.components().len();
    // A fixed start with every component present.
    let start = DVector::from_fn(k, |i, _| 1.0 + 0.5 * (1.7 * i as f64 + 0.3).sin());
    let mut actions = 0;
    let apply = |q: &DVector<f64>| {
        actions += 1;
        let column = DMatrix::from_column_slice(k, 1, q.as_slice());
        Ok::<_, StabilityError>(
            map.linearize_along(y, &column)?
                .jacobian
                .column(0)
                .into_owned(),
        )
    };
    let ritz = arnoldi(&start, apply, opts)?;
    Ok(DominantMultipliers {
        multipliers: ritz
            .values
            .iter()
            .map(|c| Multiplier { re: c.re, im: c.im })
            .collect(),
        residuals: ritz.residuals,
        actions,
        converged: ritz.converged,
    })
}
