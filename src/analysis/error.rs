//! The error types of the analysis layer: [`AnalysisError`] for bad input to an analysis,
//! [`OrbitError`] for an analysis of a model family that failed at one parameter value.

use thiserror::Error;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim};

use super::PeriodChange;
use crate::hybrid::{ModelError, SimError};

/// What went wrong in an analysis routine.
///
/// Every variant names the offending argument and carries its value, so the message alone says
/// what to fix. New variants may be added in minor releases.
#[derive(Debug, Clone, PartialEq, Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum AnalysisError {
    /// A real-valued argument is NaN, infinite or outside its allowed range.
    #[error("invalid {name} = {value}: expected {expected}")]
    InvalidValue {
        /// Name of the argument.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        name: crate::StaticStr,
        /// The value received.
        value: f64,
        /// What the argument must satisfy, in words.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        expected: crate::StaticStr,
    },
    /// A count argument (a period bound, a number of chunks or threads) is out of range.
    #[error("invalid {name} = {value}: expected {expected}")]
    InvalidCount {
        /// Name of the argument.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        name: crate::StaticStr,
        /// The value received.
        value: usize,
        /// What the argument must satisfy, in words.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        expected: crate::StaticStr,
    },
    /// A record resampled in the shaft's angle ([`AngleSamples::resample`]) too coarsely for a
    /// tracked order: the interpolation's error bound for that order
    /// ([`AngleSamples::interpolation_error`]) is above the tolerance
    /// ([`OrderTrackOptions::max_interpolation_error`]).
    ///
    /// [`AngleSamples::resample`]: super::AngleSamples::resample
    /// [`AngleSamples::interpolation_error`]: super::AngleSamples::interpolation_error
    /// [`OrderTrackOptions::max_interpolation_error`]: super::OrderTrackOptions::max_interpolation_error
    #[error("order {order} is resolved only to {bound:.1e} of its amplitude by the angle resampling (tolerance {tolerance:.1e}): record more samples a revolution (the bound falls as the phase step to the 6th power)")]
    OrderUnresolved {
        /// The highest order tracked.
        order: f64,
        /// Its relative interpolation error bound.
        bound: f64,
        /// The tolerance.
        tolerance: f64,
    },
    /// Too few samples to run the requested test.
    #[error("too few samples: got {got}, need at least {needed} ({why})")]
    TooFewSamples {
        /// Number of samples received.
        got: usize,
        /// Minimum number of samples needed.
        needed: usize,
        /// Why that many are needed.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        why: crate::StaticStr,
    },
    /// A sample (state vector) has a different length from the first one.
    #[error("sample {index} has {found} components, but sample 0 has {expected}")]
    DimensionMismatch {
        /// Index of the offending sample.
        index: usize,
        /// Length of sample 0.
        expected: usize,
        /// Length of the offending sample.
        found: usize,
    },
    /// A sample holds NaN or an infinity (a diverged trajectory, usually).
    #[error("sample {index}, component {component} is not finite ({value}); did the trajectory diverge?")]
    NonFiniteSample {
        /// Index of the offending sample.
        index: usize,
        /// Index of the offending component within the sample.
        component: usize,
        /// The value found.
        value: f64,
    },
    /// Two slices that must have the same length do not.
    #[error("{first} has {first_len} entries but {second} has {second_len}; they must match")]
    LengthMismatch {
        /// Name of the first slice.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        first: crate::StaticStr,
        /// Its length.
        first_len: usize,
        /// Name of the second slice.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        second: crate::StaticStr,
        /// Its length.
        second_len: usize,
    },
    /// Sample times are not strictly increasing.
    #[error("times must increase strictly, but times[{index}] = {time} follows {previous}")]
    TimesNotIncreasing {
        /// Index of the offending time.
        index: usize,
        /// The time before it.
        previous: f64,
        /// The offending time.
        time: f64,
    },
    /// Sample times that should be equally spaced are not (a spectrum needs a uniform record:
    /// resample it first, [`AngleSamples::resample`](super::AngleSamples::resample)).
    #[error("samples must be equally spaced, but step {index} is {step} where the mean step is {expected}")]
    NonUniformSamples {
        /// Index of the offending step (between samples `index` and `index + 1`).
        index: usize,
        /// Its length.
        step: f64,
        /// The mean step of the record.
        expected: f64,
    },
    /// Shaft angles (phases) that must increase strictly do not.
    #[error("phases must increase strictly, but phases[{index}] = {phase} follows {previous}")]
    PhaseNotIncreasing {
        /// Index of the offending phase.
        index: usize,
        /// The phase before it.
        previous: f64,
        /// The offending phase.
        phase: f64,
    },
    /// The worker thread pool for a sweep could not be built.
    #[error("could not build a pool of {threads} worker threads: {message}")]
    ThreadPool {
        /// Number of threads requested.
        threads: usize,
        /// The message of the underlying error.
        message: String,
    },
}

/// Why an analysis of a model family ([`bifurcation`](super::bifurcation()),
/// [`locate_period_change`](super::locate_period_change)) failed at one parameter value.
///
/// `E` is the error of the user's model builder (for the paper's model
/// [`ParamError`](crate::params::ParamError)).
#[derive(Debug, Clone, PartialEq, Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize, E: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>, E: serde::Deserialize<'de>"
    ))
)]
#[non_exhaustive]
pub enum OrbitError<D: Dim, E>
where
    DefaultAllocator: Allocator<D>,
{
    /// The model could not be built at this value (e.g. invalid parameters).
    #[error("could not build the model: {0}")]
    Build(E),
    /// The start rule rejected the initial state.
    #[error("invalid initial state: {0}")]
    State(ModelError),
    /// The simulation failed.
    #[error("{0}")]
    Simulation(Box<SimError<D>>),
    /// The analysis of the orbit failed (e.g. non-finite points, bad locator settings).
    #[error(transparent)]
    Analysis(AnalysisError),
    /// The locator's two ends have the same detected period
    /// ([`Periodicity::agrees_with`](super::Periodicity::agrees_with)): nothing to locate.
    /// Boxed: the two outcomes carry their residuals.
    #[error(
        "no change of period between {} ({}) and {} ({})",
        .0.from, .0.at_from, .0.to, .0.at_to
    )]
    NoChange(Box<PeriodChange>),
}

impl<D: Dim, E> From<SimError<D>> for OrbitError<D, E>
where
    DefaultAllocator: Allocator<D>,
{
    fn from(e: SimError<D>) -> Self {
        OrbitError::Simulation(Box::new(e))
    }
}

impl<D: Dim, E> From<AnalysisError> for OrbitError<D, E>
where
    DefaultAllocator: Allocator<D>,
{
    fn from(e: AnalysisError) -> Self {
        OrbitError::Analysis(e)
    }
}

impl<D: Dim, E> From<ModelError> for OrbitError<D, E>
where
    DefaultAllocator: Allocator<D>,
{
    fn from(e: ModelError) -> Self {
        OrbitError::State(e)
    }
}
