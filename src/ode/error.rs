//! The error type of the ODE layer.

use thiserror::Error;

/// Errors of the ODE layer. Every variant says where it happened and what to
/// try.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum OdeError {
    /// An option is invalid.
    #[error("invalid option `{field}` = {value}: {hint}")]
    InvalidOption {
        /// Name of the field of [`Options`](super::Options) (or [`EventOptions`](super::EventOptions)).
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// The offending value (`NaN` when the value is missing).
        value: f64,
        /// What to do instead.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        hint: crate::StaticStr,
    },
    /// The initial time or state given to [`Integrator::reset`](super::Integrator::reset) is not finite.
    #[error("non-finite initial value at t = {t}: component {component} = {value}; pass a finite time and state")]
    NonFiniteInitial {
        /// Initial time.
        t: f64,
        /// Offending component (`usize::MAX` for the time itself).
        component: usize,
        /// Offending value.
        value: f64,
    },
    /// The right-hand side produced non-finite values and reducing the step
    /// size did not help (or they occurred at an accepted point).
    #[error("right-hand side returned NaN/inf at t = {t} (step size h = {h}); check the model's domain, or stop before it with an event")]
    NonFiniteRhs {
        /// Last accepted time.
        t: f64,
        /// Step size of the failing attempt.
        h: f64,
    },
    /// The controller wants a step smaller than `h_min` or than the
    /// resolution of `t` (stiffness, a singularity or a discontinuity).
    #[error("step size underflow at t = {t}: h = {h} < h_min = {h_min}; the solution may blow up or be non-smooth here (locate the discontinuity with an event) or the tolerances are too tight")]
    StepSizeUnderflow {
        /// Last accepted time.
        t: f64,
        /// The rejected step size.
        h: f64,
        /// Effective minimum step (max of `h_min` and $10\varepsilon|t|$).
        h_min: f64,
    },
    /// The Newton iteration of the implicit method ([`Radau5`](super::Radau5)) did not
    /// converge with the fixed step of [`Options::fixed_step`](super::Options::fixed_step)
    /// (adaptive steps would have been reduced instead).
    #[error("the Newton iteration did not converge at t = {t} with the fixed step h = {h}; use a smaller fixed step, or adaptive steps (fixed_step: None)")]
    NewtonFailure {
        /// Last accepted time.
        t: f64,
        /// The fixed step size.
        h: f64,
    },
    /// More than `max_steps` attempts since the last reset.
    #[error("too many steps: {max_steps} attempts since the last reset, reached t = {t} with h = {h}; raise Options::max_steps or loosen the tolerances")]
    TooManySteps {
        /// Last accepted time.
        t: f64,
        /// Current step size.
        h: f64,
        /// The limit.
        max_steps: u64,
    },
    /// `step` or `truncate` was called before `reset`.
    #[error("integrator not initialised: call Integrator::reset(sys, t0, y0, false) first")]
    NotInitialized,
    /// The bound passed to `step` is not finite or lies behind the current
    /// time (integration is forward only).
    #[error("invalid bound t_bound = {t_bound} at t = {t}: the bound must be finite and >= t (forward integration only)")]
    InvalidBound {
        /// Current time.
        t: f64,
        /// The bound.
        t_bound: f64,
    },
    /// `truncate` was given a time outside `(t_prev, t]`.
    #[error("truncate at t_new = {t_new} outside the last step ({t_prev}, {t}]; truncate only inside the last accepted step")]
    TruncateOutOfRange {
        /// Requested time.
        t_new: f64,
        /// Left end of the last step.
        t_prev: f64,
        /// Right end of the last step.
        t: f64,
    },
    /// An event function returned NaN where the detector needed its sign (at the start of a
    /// scanned step, at a sample with no crossing of another event before it, or inside a
    /// root bracket): whether and where it crosses zero cannot be decided, so the detector
    /// stops rather than skip it.
    #[error("event {index} returned NaN at t = {t}: its crossings cannot be decided there; an event function must have a value wherever the integration may go (end the integration before it with another event)")]
    EventNotANumber {
        /// Index of the event in its set.
        index: usize,
        /// Time of the NaN.
        t: f64,
    },
    /// A vector (an initial state, a per-component tolerance) has the wrong
    /// number of components for the integrator's dimension (only possible
    /// with [`Dyn`](nalgebra::Dyn)).
    #[error("`{field}` has {found} components but the integrator was built for dimension {expected}; build it with the system's dimension (Dop853::with_dim(Dyn(n), ..)) or pass a vector of that length")]
    DimensionMismatch {
        /// What has the wrong length: `"y0"`, `"rtol"`, `"atol"`.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// The integrator's dimension.
        expected: usize,
        /// The length given.
        found: usize,
    },
    /// The exponential integrator ([`Etd4`](super::Etd4)) was given a system without a
    /// diagonal linear part ([`OdeSystem::linear_part`](super::OdeSystem::linear_part)).
    #[error("the system supplies no diagonal linear part (OdeSystem::linear_part): ETD4 needs one; use DOP853 or RADAU5, or a model in modal coordinates")]
    NoLinearPart,
    /// A [`DiagonalLinearPart`](super::DiagonalLinearPart) names a component out of range or
    /// twice, or has a non-finite eigenvalue.
    #[error("invalid linear part at component {component} (value {value}): each component in at most one block, within the dimension, with a finite eigenvalue")]
    InvalidLinearPart {
        /// The component.
        component: usize,
        /// The eigenvalue's part given for it.
        value: f64,
    },
    /// A forcing declared on a [`DiagonalLinearPart`](super::DiagonalLinearPart)
    /// ([`DiagonalLinearPart::with_forcing`](super::DiagonalLinearPart::with_forcing)) is
    /// invalid: a frequency or an amplitude not finite, a component that is not a block's
    /// first or is forced twice, an imaginary part on a real block.
    #[error("invalid forcing `{field}` = {value} (component {component:?}): {hint}")]
    InvalidForcing {
        /// `"frequency"`, `"component"`, or the amplitude: `"cos"`, `"sin"`, `"constant"`.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// The block's first component (`None` for the frequency).
        component: Option<usize>,
        /// The offending value (the component itself for `"component"`, the offending part
        /// of an amplitude).
        value: f64,
        /// What to do instead.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        hint: crate::StaticStr,
    },
}
