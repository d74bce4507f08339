//! The crate's scalar numerical tools, below every other layer (it imports nothing of the
//! crate): one bracketing root finder, one bisection helper, one non-symmetric
//! eigen-decomposition and one Krylov eigensolver, the cubic Hermite interpolant, and the
//! direction type of a sign change.
//!
//! * [`illinois`] — the bracketing root finder (Illinois-modified regula falsi with a bisection
//!   safeguard) for a continuous scalar function with a sign change on a bracket: the event
//!   detector of [`ode`](crate::ode) locates event roots and grazing extrema with it, the
//!   Poincaré sections of [`analysis`](crate::analysis) their crossings on an interpolant, the
//!   certified contact-onset search of [`ring::onset`](crate::ring::onset) the roots of its
//!   Taylor bounds. It returns a [`Bracket`] (both ends, their values, evaluations and a
//!   `converged` flag), or [`NumericError::NotABracket`] when the input has no sign change.
//! * [`bisect`] — bisection on a yes/no test (which end a probed point is like): for properties
//!   without a continuous value to interpolate, such as the detected period of a simulation
//!   ([`analysis::locate_period_change`](crate::analysis::locate_period_change)). It returns a
//!   [`Bisection`] (the final bracket, evaluations, `converged`).
//! * [`eigen_decomposition`] — eigenvalues, eigenvectors and their inverse for a real
//!   non-symmetric matrix (balancing, then faer's complex Schur form and back-substitution), with
//!   the eigenvector matrix's condition number and the backward error: the modal closed form of
//!   a linear rotor's free flight ([`crate::rotor::LinearClosedForm`]) rests on it.
//! * [`arnoldi`] — the eigenvalues of largest modulus of an operator known by its action
//!   (Krylov, matrix-free): the dominant Floquet multipliers of a large model
//!   ([`stability::dominant_multipliers`](crate::stability::dominant_multipliers)) without its
//!   dense monodromy matrix.
//! * [`hermite_weights`], [`hermite_slope_weights`] — the cubic Hermite interpolant of an
//!   interval from the values and slopes at its ends: Poincaré sections located between samples
//!   ([`analysis::section_crossings_hermite`](crate::analysis::section_crossings_hermite)) and
//!   the per-revolution peak radius ([`analysis::per_revolution`](crate::analysis::per_revolution)).
//! * [`Direction`] — the direction of a sign change (`Rising`, `Falling`, `Either`), used by
//!   event functions, the guards of hybrid models, the ring element and Poincaré sections.
//!
//! Any code with a bracket of a continuous scalar function should call [`illinois`], and any
//! code bisecting a parameter on a test should call [`bisect`], rather than write its own loop.
//!
//! ```
//! use jeffcott::numeric::{bisect, illinois, RootOptions, Side};
//!
//! // The root of x^2 - 2 on [1, 2]: sqrt(2) to 1e-12.
//! let g = |x: f64| x * x - 2.0;
//! let r = illinois((1.0, g(1.0)), (2.0, g(2.0)), &RootOptions::default().with_tol(1e-12), g)?;
//! assert!(r.converged && r.hi - r.lo <= 1e-12);
//! assert!((r.hi - 2f64.sqrt()).abs() <= 1e-12);
//!
//! // Where a test changes its answer: here at x = 0.3, to 1e-9.
//! let b = bisect(0.0, 1.0, 1e-9, 100, |x| Ok::<_, ()>(if x < 0.3 { Side::Near } else { Side::Far }))
//!     .unwrap();
//! assert!(b.converged && b.near < 0.3 && b.far >= 0.3 && b.far - b.near <= 1e-9);
//! # Ok::<(), jeffcott::numeric::NumericError>(())
//! ```

mod arnoldi;
mod bisect;
mod eigen;
mod hermite;
pub(crate) mod lu;
mod roots;

pub use arnoldi::{arnoldi, ArnoldiOptions, RitzValues};
pub use bisect::{bisect, Bisection, Side};
pub use eigen::{eigen_decomposition, EigenDecomposition};
pub use hermite::{hermite_slope_weights, hermite_weights};
pub use roots::{illinois, Bracket, RootOptions};

/// Errors of the numerical tools.
#[derive(Debug, Clone, Copy, PartialEq, thiserror::Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum NumericError {
    /// The root finder's input has no sign change: `fa` is zero or NaN, or `fb` is NaN or of the
    /// sign of `fa`.
    #[error(
        "no sign change on the bracket: g({a}) = {fa}, g({b}) = {fb} (need g(a) nonzero and \
         g(b) of the opposite sign or zero; sample more densely or widen the bracket)"
    )]
    NotABracket {
        /// The first end.
        a: f64,
        /// The value at the first end.
        fa: f64,
        /// The second end.
        b: f64,
        /// The value at the second end.
        fb: f64,
    },
    /// The matrix to decompose is not square (or empty).
    #[error(
        "the matrix is {rows} x {cols}: an eigen-decomposition needs a non-empty square matrix"
    )]
    NotSquare {
        /// Rows.
        rows: usize,
        /// Columns.
        cols: usize,
    },
    /// The matrix to decompose has a non-finite entry.
    #[error("the matrix has the non-finite entry {value}")]
    NonFiniteMatrix {
        /// The entry.
        value: f64,
    },
    /// The QR iteration of the Schur form did not converge.
    #[error("the QR iteration of the Schur form of the {size} x {size} matrix did not converge")]
    NoConvergence {
        /// The matrix's order.
        size: usize,
    },
    /// The eigenvectors are linearly dependent to working precision (a defective matrix).
    #[error("the eigenvector matrix is singular to working precision (zero pivot in column {column}): the matrix is defective or nearly so")]
    SingularEigenvectors {
        /// The column of the zero pivot.
        column: usize,
    },
    /// An input of [`arnoldi`] out of range.
    #[error("arnoldi: {field:?} = {value} is out of range (count in 1..=n, tol > 0, a non-zero finite start, actions of the start's size and finite)")]
    InvalidArnoldi {
        /// The input.
        field: ArnoldiInput,
        /// Its value.
        value: f64,
    },
}

/// The inputs of [`arnoldi`] that [`NumericError::InvalidArnoldi`] names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ArnoldiInput {
    /// [`ArnoldiOptions::count`]: 0, or above the operator's size (the value given).
    Count,
    /// [`ArnoldiOptions::tol`]: not positive and finite.
    Tol,
    /// The start vector: its norm zero or non-finite (the norm given).
    Start,
    /// An action: of another size than the start (its size given) or with a non-finite entry.
    Action,
}

/// Direction of a sign change of a scalar function $g$ (the crate's one direction type): which
/// crossings an event, a guard or a section counts.
///
/// ```
/// use jeffcott::numeric::Direction;
///
/// assert!(Direction::Either.allows(Direction::Rising));
/// assert!(!Direction::Falling.allows(Direction::Rising));
/// assert_eq!(Direction::Rising.opposite(), Direction::Falling);
/// ```
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Direction {
    /// $g$ goes from negative to non-negative.
    Rising,
    /// $g$ goes from positive to non-positive.
    Falling,
    /// Both.
    Either,
}

impl Direction {
    /// Whether a crossing in direction `d` (Rising or Falling) is allowed.
    pub fn allows(self, d: Direction) -> bool {
        matches!(self, Direction::Either) || self == d
    }

    /// The opposite direction (`Either` stays `Either`).
    pub fn opposite(self) -> Direction {
        match self {
            Direction::Rising => Direction::Falling,
            Direction::Falling => Direction::Rising,
            Direction::Either => Direction::Either,
        }
    }
}
