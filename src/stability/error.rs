//! The errors of the stability analyses.

use nalgebra::DVector;
use thiserror::Error;

use super::floquet::FloquetError;
use super::lyapunov::LyapunovSpectrum;
use crate::hybrid::SimErrorKind;

/// Why a stability computation failed.
#[derive(Debug, Clone, PartialEq, Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum StabilityError {
    /// A run of the model (with or without its variational equations) failed.
    #[error("simulation failed at t = {t}: {kind}")]
    Simulation {
        /// What went wrong (a model error, e.g. a transition the linearisation cannot cross,
        /// names the event).
        kind: SimErrorKind,
        /// Time of the failure.
        t: f64,
    },
    /// Newton's method did not converge: `last` is its best iterate (the non-algebraic
    /// components at the section) and `residual` its $\lVert P^n(z) - z\rVert_\infty$. Try a
    /// better guess (a longer transient), another period, or a tolerance above the map's noise.
    #[error("no periodic orbit: Newton stopped after {iterations} iterations at residual {residual:e} ({reason})")]
    NotConverged {
        /// The best iterate.
        last: DVector<f64>,
        /// Its residual.
        residual: f64,
        /// Iterations made.
        iterations: u32,
        /// Why it stopped.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        reason: crate::StaticStr,
    },
    /// $DP^n - I$ is singular at `at`: a multiplier is 1 to working precision (a fold).
    #[error("DP - I is singular at the iterate (residual {residual:e}): a multiplier is 1")]
    Singular {
        /// The iterate.
        at: DVector<f64>,
        /// Its residual.
        residual: f64,
    },
    /// The model could not be built at a parameter value.
    #[error("no model at parameter {parameter}: {reason}")]
    Model {
        /// The parameter value.
        parameter: f64,
        /// The builder's error.
        reason: String,
    },
    /// The orbit a continuation starts from is not stable.
    #[error("the orbit at parameter {parameter} is not stable (spectral radius {spectral_radius}): start the continuation where it is")]
    Unstable {
        /// The parameter value.
        parameter: f64,
        /// Its largest multiplier modulus.
        spectral_radius: f64,
    },
    /// Newton converged, but to another orbit than the one followed: its correction from the
    /// prediction exceeds the largest accepted one, or its minimal period differs.
    #[error("Newton left the branch at parameter {parameter}: correction {correction:e} (largest accepted {max_correction:e}), minimal period {minimal_period} (followed {expected_period})")]
    LeftBranch {
        /// The parameter value.
        parameter: f64,
        /// $\lVert z^{\ast} - z_{\rm predicted}\rVert_\infty$.
        correction: f64,
        /// The largest correction accepted.
        max_correction: f64,
        /// The minimal period of the orbit found.
        minimal_period: u64,
        /// The minimal period of the orbit followed.
        expected_period: u64,
    },
    /// A computation ran out of its budget before it was done (what it computed is returned
    /// with this error).
    #[error(
        "`{field}` = {limit} exhausted at parameter {parameter}: allow more, or a larger step"
    )]
    Budget {
        /// The option that set the budget.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// Its value.
        limit: f64,
        /// Where the computation stopped.
        parameter: f64,
    },
    /// No orbit of the period near the guess at the start of a continuation: the corrector
    /// failed there with `source`.
    #[error("no period-{period} orbit near the guess at parameter {parameter}: {source}; try a longer transient, another period or a better guess")]
    NoStart {
        /// The period.
        period: u64,
        /// The parameter.
        parameter: f64,
        /// Why.
        source: Box<StabilityError>,
    },
    /// Branch switching found no orbit of the doubled period next to a flip: `source` is the
    /// failure at the largest amplitude tried.
    #[error("no period-{period} orbit branches off the flip at {parameter}: {source}")]
    NoSwitch {
        /// The doubled period.
        period: u64,
        /// The flip's parameter.
        parameter: f64,
        /// Why, at the last amplitude tried.
        source: Box<StabilityError>,
    },
    /// Branch switching converged back to the orbit of the flip's own period.
    #[error("at amplitude {amplitude} the corrector found the period-{period} orbit again")]
    SamePeriod {
        /// The flip's period.
        period: u64,
        /// The amplitude along the flip's eigenvector.
        amplitude: f64,
    },
    /// The multipliers could not be computed.
    #[error(transparent)]
    Floquet(#[from] FloquetError),
    /// A numeric tool failed or was given options out of range (the Krylov eigensolver of
    /// [`dominant_multipliers`](super::dominant_multipliers)).
    #[error(transparent)]
    Numeric(#[from] crate::numeric::NumericError),
    /// A run of the map ended without its stroboscopic point (the driver returned without
    /// reaching the section): a condition of the run, not of an option.
    #[error("the run of {periods} forcing periods produced no stroboscopic point")]
    NoStroboscopicPoint {
        /// The map's number of forcing periods.
        periods: u64,
    },
    /// The caller's [`Progress`](crate::analysis::Progress) observer asked the computation to
    /// stop ([`Progress::should_stop`](crate::analysis::Progress::should_stop)) after `done` of
    /// `total` units of work (periods of Lyapunov exponents, points of a branch).
    #[error("stopped by the caller after {done} of {total} units of work")]
    Stopped {
        /// Units finished.
        done: u64,
        /// Units planned.
        total: u64,
        /// What was computed by then: the Lyapunov exponents of the periods recorded so far
        /// (`None` before the first recorded period, and for a branch, which comes back
        /// whole with [`BranchEnd::Stopped`](crate::stability::BranchEnd::Stopped)).
        partial: Option<Box<LyapunovSpectrum>>,
    },
    /// An option or an argument breaks its documented rule.
    #[error("invalid `{field}` = {value}: {hint}")]
    InvalidOption {
        /// The option.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// Its value.
        value: f64,
        /// What to use.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        hint: crate::StaticStr,
    },
}
