//! [`PointFailure`]: why one point of a scan has no attractor, in a form that is recorded
//! and read back.

use std::fmt::Display;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim};
use thiserror::Error;

use crate::analysis::AnalysisError;
use crate::hybrid::{ModelError, SimError, SimErrorKind};

/// Why one point of a scan failed. Recorded in the sweep's folder and read back on restart,
/// so it holds text rather than the original error values; the variant and the simulation's
/// [`SimFailureKind`] stay typed.
#[derive(Debug, Clone, PartialEq, Error, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub enum PointFailure {
    /// The model could not be built at this point (e.g. invalid parameters).
    #[error("could not build the model: {message}")]
    Build {
        /// The builder's message.
        message: String,
    },
    /// The initial state was rejected.
    #[error("invalid initial state: {message}")]
    InitialState {
        /// The model's message.
        message: String,
    },
    /// The simulation failed.
    #[error("simulation failed at t = {t} ({kind}): {message}")]
    Simulation {
        /// Which [`SimErrorKind`] it was.
        kind: SimFailureKind,
        /// Last good time.
        t: f64,
        /// The driver's message.
        message: String,
    },
    /// A bad setting of the analysis.
    #[error("{message}")]
    Analysis {
        /// The message.
        message: String,
    },
}

/// The variant of a [`SimErrorKind`], for a recorded [`PointFailure::Simulation`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub enum SimFailureKind {
    /// [`SimErrorKind::Model`], or [`SimErrorKind::Guard`] (a guard of the model without a
    /// value).
    Model,
    /// [`SimErrorKind::Integrator`].
    Integrator,
    /// [`SimErrorKind::Chattering`].
    Chattering,
    /// [`SimErrorKind::Stalled`].
    Stalled,
    /// [`SimErrorKind::NonFinite`] (a diverged run).
    NonFinite,
    /// [`SimErrorKind::InvalidOption`].
    InvalidOption,
    /// [`SimErrorKind::DimensionMismatch`].
    DimensionMismatch,
    /// [`SimErrorKind::Stopped`] (the observer asked it to stop).
    Stopped,
}

impl SimFailureKind {
    const NAMES: [(SimFailureKind, &'static str); 8] = [
        (SimFailureKind::Model, "model"),
        (SimFailureKind::Integrator, "integrator"),
        (SimFailureKind::Chattering, "chattering"),
        (SimFailureKind::Stalled, "stalled"),
        (SimFailureKind::NonFinite, "non-finite"),
        (SimFailureKind::InvalidOption, "invalid-option"),
        (SimFailureKind::DimensionMismatch, "dimension-mismatch"),
        (SimFailureKind::Stopped, "stopped"),
    ];

    /// The kind of a driver error.
    pub fn of(kind: &SimErrorKind) -> Self {
        match kind {
            SimErrorKind::Model(_) | SimErrorKind::Guard { .. } => SimFailureKind::Model,
            // The run's step budget, as the integrator's own bound of a phase.
            SimErrorKind::Integrator(_) | SimErrorKind::TooManySteps { .. } => {
                SimFailureKind::Integrator
            }
            SimErrorKind::Chattering { .. } => SimFailureKind::Chattering,
            SimErrorKind::Stalled { .. } => SimFailureKind::Stalled,
            SimErrorKind::NonFinite => SimFailureKind::NonFinite,
            SimErrorKind::InvalidOption { .. } => SimFailureKind::InvalidOption,
            SimErrorKind::DimensionMismatch { .. } => SimFailureKind::DimensionMismatch,
            SimErrorKind::Stopped => SimFailureKind::Stopped,
        }
    }

    /// Its name (its `Display`): `"model"`, `"integrator"`, `"chattering"`, `"stalled"`,
    /// `"non-finite"`, `"invalid-option"`, `"dimension-mismatch"` or `"stopped"`.
    pub fn name(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(k, _)| *k == self)
            .map_or("unknown", |(_, n)| n)
    }
}

impl std::fmt::Display for SimFailureKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl PointFailure {
    /// A model that could not be built, with its builder's error.
    pub fn build(e: impl Display) -> Self {
        PointFailure::Build {
            message: e.to_string(),
        }
    }

    /// The variant's name: `"build"`, `"initial-state"`, `"simulation"`,
    /// `"analysis"`.
    pub fn kind_name(&self) -> &'static str {
        match self {
            PointFailure::Build { .. } => "build",
            PointFailure::InitialState { .. } => "initial-state",
            PointFailure::Simulation { .. } => "simulation",
            PointFailure::Analysis { .. } => "analysis",
        }
    }
}

impl From<ModelError> for PointFailure {
    fn from(e: ModelError) -> Self {
        PointFailure::InitialState {
            message: e.to_string(),
        }
    }
}

impl<D: Dim> From<SimError<D>> for PointFailure
where
    DefaultAllocator: Allocator<D>,
{
    fn from(e: SimError<D>) -> Self {
        PointFailure::Simulation {
            kind: SimFailureKind::of(&e.kind),
            t: e.t,
            message: e.kind.to_string(),
        }
    }
}

impl From<AnalysisError> for PointFailure {
    fn from(e: AnalysisError) -> Self {
        PointFailure::Analysis {
            message: e.to_string(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn failures_round_trip_through_their_records() {
        let all = [
            PointFailure::build("parameter `eta` must be > 0, got -1"),
            PointFailure::InitialState {
                message: "rotor beyond the ring".into(),
            },
            PointFailure::Analysis {
                message: "bad".into(),
            },
            PointFailure::Simulation {
                kind: SimFailureKind::Stalled,
                t: 12.5,
                message: "stalled".into(),
            },
        ];
        for f in all {
            let text = serde_json::to_string(&f).unwrap();
            let back: PointFailure = serde_json::from_str(&text).unwrap();
            assert_eq!(back, f);
        }
        for (k, n) in SimFailureKind::NAMES {
            assert_eq!(k.name(), n);
        }
    }
}
