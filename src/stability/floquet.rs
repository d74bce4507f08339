use nalgebra::DMatrix;
use thiserror::Error;

/// A Floquet multiplier, a complex number $\lambda = $ `re` $+ i\thinspace$`im`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Multiplier {
    /// Real part.
    pub re: f64,
    /// Imaginary part.
    pub im: f64,
}

impl Multiplier {
    /// $|\lambda|$.
    pub fn modulus(&self) -> f64 {
        self.re.hypot(self.im)
    }

    /// $\arg\lambda \in (-\pi, \pi]$ ($\pi$ for a negative real multiplier).
    pub fn argument(&self) -> f64 {
        self.im.atan2(self.re)
    }

    /// Whether the multiplier is real: $|\operatorname{Im}\lambda| \le$ `tol`
    /// $\cdot\thinspace|\lambda|$.
    pub fn is_real(&self, tol: f64) -> bool {
        self.im.abs() <= tol * self.modulus()
    }
}

/// How a multiplier crosses (or is closest to) the unit circle.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum CrossingKind {
    /// A real multiplier at $-1$: period doubling.
    Flip,
    /// A real multiplier at $+1$: saddle node (or a symmetry-breaking / transcritical
    /// bifurcation).
    Fold,
    /// A complex pair on the unit circle: a torus (quasi-periodic motion) is born or dies.
    NeimarkSacker,
}

impl CrossingKind {
    /// The name used in outputs: `"flip"`, `"fold"`, `"neimark-sacker"`.
    pub fn name(self) -> &'static str {
        match self {
            CrossingKind::Flip => "flip",
            CrossingKind::Fold => "fold",
            CrossingKind::NeimarkSacker => "neimark-sacker",
        }
    }

    /// The kind of a critical multiplier: real (relative imaginary part below `tol`) and
    /// negative is a flip, real and positive a fold, otherwise Neimark–Sacker.
    pub fn of(m: &Multiplier, tol: f64) -> Self {
        if m.is_real(tol) {
            if m.re < 0.0 {
                CrossingKind::Flip
            } else {
                CrossingKind::Fold
            }
        } else {
            CrossingKind::NeimarkSacker
        }
    }
}

/// Why multipliers could not be computed.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum FloquetError {
    /// The matrix is not square.
    #[error("monodromy matrix is {rows} x {cols}: it must be square")]
    NotSquare {
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
    },
    /// The matrix holds NaN or infinity.
    #[error("monodromy matrix has a non-finite entry at ({row}, {col})")]
    NonFinite {
        /// Row.
        row: usize,
        /// Column.
        col: usize,
    },
    /// The Schur iteration did not converge (not expected for finite input).
    #[error("eigenvalue iteration did not converge for a {size} x {size} matrix")]
    NotConverged {
        /// The matrix size.
        size: usize,
    },
}

/// The eigenvalues of `monodromy`, sorted by modulus, largest first (ties: larger real part
/// first, then positive imaginary part first, so that a complex pair is listed as
/// $\lambda, \bar\lambda$).
///
/// # Errors
/// [`FloquetError`] for a non-square or non-finite matrix.
///
/// ```
/// use jeffcott::nalgebra::DMatrix;
/// use jeffcott::stability::multipliers;
///
/// // Block diagonal: a rotation by a quarter turn scaled by 0.5 (eigenvalues +-0.5i) and -2.
/// let m = DMatrix::from_row_slice(3, 3, &[0.0, -0.5, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, -2.0]);
/// let mu = multipliers(&m)?;
/// assert!((mu[0].re + 2.0).abs() < 1e-15 && mu[0].im == 0.0); // largest modulus first
/// assert!((mu[1].im - 0.5).abs() < 1e-15 && (mu[2].im + 0.5).abs() < 1e-15); // pair: +i first
/// assert!(mu[1..].iter().all(|m| (m.modulus() - 0.5).abs() < 1e-15));
/// # Ok::<(), jeffcott::stability::FloquetError>(())
/// ```
pub fn multipliers(monodromy: &DMatrix<f64>) -> Result<Vec<Multiplier>, FloquetError> {
    let (rows, cols) = monodromy.shape();
    if rows != cols {
        return Err(FloquetError::NotSquare { rows, cols });
    }
    for j in 0..cols {
        for i in 0..rows {
            if !monodromy[(i, j)].is_finite() {
                return Err(FloquetError::NonFinite { row: i, col: j });
            }
        }
    }
    if rows == 0 {
        return Ok(Vec::new());
    }
    let schur = monodromy
        .clone()
        .try_schur(f64::EPSILON, 100 * rows.max(10))
        .ok_or(FloquetError::NotConverged { size: rows })?;
    let mut out: Vec<Multiplier> = schur
        .complex_eigenvalues()
        .iter()
        .map(|c| Multiplier { re: c.re, im: c.im })
        .collect();
    sort_by_modulus(&mut out);
    Ok(out)
}

/// Sorts multipliers by modulus, largest first (ties as in [`multipliers`]).
pub(crate) fn sort_by_modulus(m: &mut [Multiplier]) {
    m.sort_by(|a, b| {
        b.modulus()
            .total_cmp(&a.modulus())
            .then(b.re.total_cmp(&a.re))
            .then(b.im.total_cmp(&a.im))
    });
}

/// The largest modulus of a set of multipliers (0 for none): the spectral radius.
pub(crate) fn spectral_radius(m: &[Multiplier]) -> f64 {
    m.iter().map(Multiplier::modulus).fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigenvalues_of_a_block_diagonal_matrix_are_sorted_and_classified() {
        // Blocks: rotation by 1.2 scaled 0.9, -0.95, 0.3.
        let (r, a) = (0.9, 1.2f64);
        let m = DMatrix::from_row_slice(
            4,
            4,
            &[
                r * a.cos(),
                -r * a.sin(),
                0.0,
                0.0,
                r * a.sin(),
                r * a.cos(),
                0.0,
                0.0,
                0.0,
                0.0,
                -0.95,
                0.0,
                0.0,
                0.0,
                0.0,
                0.3,
            ],
        );
        let mult = multipliers(&m).unwrap();
        assert!((mult[0].re + 0.95).abs() < 1e-14 && mult[0].im == 0.0);
        assert_eq!(CrossingKind::of(&mult[0], 1e-9), CrossingKind::Flip);
        assert!((mult[1].modulus() - 0.9).abs() < 1e-14);
        assert!((mult[1].argument() - 1.2).abs() < 1e-14);
        assert!((mult[2].argument() + 1.2).abs() < 1e-14);
        assert_eq!(
            CrossingKind::of(&mult[1], 1e-9),
            CrossingKind::NeimarkSacker
        );
        assert!((mult[3].re - 0.3).abs() < 1e-14);
        assert_eq!(CrossingKind::of(&mult[3], 1e-9), CrossingKind::Fold);
        assert!((spectral_radius(&mult) - 0.95).abs() < 1e-14);
    }

    #[test]
    fn bad_matrices_are_typed_errors() {
        assert_eq!(
            multipliers(&DMatrix::zeros(2, 3)),
            Err(FloquetError::NotSquare { rows: 2, cols: 3 })
        );
        let mut m = DMatrix::identity(3, 3);
        m[(1, 2)] = f64::NAN;
        assert_eq!(
            multipliers(&m),
            Err(FloquetError::NonFinite { row: 1, col: 2 })
        );
        assert!(multipliers(&DMatrix::zeros(0, 0)).unwrap().is_empty());
    }
}
