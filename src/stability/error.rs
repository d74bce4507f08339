//! The errors of the stability analyses.

use thiserror::Error;

use super::floquet::FloquetError;
use crate::hybrid::SimErrorKind;

/// Why a stability computation failed.
#[derive(Debug, Clone, PartialEq, Error)]
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
    /// The multipliers could not be computed.
    #[error(transparent)]
    Floquet(#[from] FloquetError),
    /// An option or argument is invalid.
    #[error("invalid `{field}` = {value}: {hint}")]
    InvalidOption {
        /// The option.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What to use.
        hint: &'static str,
    },
}
