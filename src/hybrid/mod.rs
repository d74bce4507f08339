//! Piecewise-smooth rotor models and the driver that runs them through modes and events.
//!
//! A piecewise-smooth model is a set of **modes** (free flight, contact on one branch of a
//! force law, ...). In each mode the state $y \in \mathbb{R}^N$ follows a smooth vector field,
//! either integrated numerically ([`Flow::Integrated`]) or known in closed form
//! ([`Flow::Exact`]). **Guards** $g_i(t, y)$ end a mode when they cross zero in their
//! direction; the model's **transition** map then gives the next mode and may reset the state.
//!
//! The [`RotorModel`] trait is that interface: a larger rotordynamics code (a 4-DOF rotor, a
//! reduced finite-element rotor with the same snubber ring element) implements it and reuses
//! [`simulate`], the event machinery of [`crate::ode`] and the analyses of
//! [`crate::analysis`]. [`crate::paper::JeffcottModel`] is the paper's model.
//!
//! Rules the driver relies on:
//! * inside a mode the vector field must be smooth (extend each branch's formula beyond its
//!   boundary rather than switching formulas inside a mode), so no step straddles a kink;
//! * guards of integrated modes are located on the dense output (with grazing detection when
//!   [`RotorModel::guard_derivative`] is given); exact modes find their own guards
//!   ([`ExactSegment::next_guard`]), as only the model knows the bounds that make that safe;
//! * a guard that is zero at the start of a mode does not fire again at once.

mod driver;
mod record;

pub use driver::{simulate, SimError, SimErrorKind, SimOptions, SimStats};
pub use record::{
    DenseSampling, EventRecord, HybridObserver, OutputPlan, Sample, StrobePoint, StrobeRange,
    Trajectory,
};

use std::fmt::Debug;

use nalgebra::SVector;

use crate::ode::Direction;

/// How a mode is advanced in time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Flow {
    /// Integrated numerically by the driver's [`crate::ode::Integrator`].
    Integrated,
    /// Known in closed form: the model supplies an [`ExactSegment`].
    Exact,
}

/// Why a model rejected a state or a transition.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ModelError {
    /// The state is not allowed by the model (e.g. the rotor beyond the ring).
    #[error("invalid state at t = {t}: {reason}")]
    InvalidState {
        /// Time.
        t: f64,
        /// What is wrong and what to try.
        reason: String,
    },
    /// A transition could not be computed.
    #[error("transition failed at t = {t}: {reason}")]
    Transition {
        /// Time.
        t: f64,
        /// What went wrong.
        reason: String,
    },
}

/// The first guard crossing an [`ExactSegment`] finds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuardCrossing {
    /// Index of the guard that fires.
    pub guard: usize,
    /// Time of the crossing.
    pub t: f64,
}

/// The closed-form motion of an exact mode, from the state it was started with.
pub trait ExactSegment<const N: usize> {
    /// State and its time derivative at time `t` (not before the segment's start).
    fn eval(&self, t: f64, y: &mut SVector<f64, N>, dy: &mut SVector<f64, N>);
    /// Searches $(t_\text{from}, t_\text{to}]$ for the first guard crossing; returns it, or
    /// `None` if none occurs up to `t_to`. Must not miss a crossing (document how) and must
    /// not fire a guard that is zero at the segment's start unless it is moving into its
    /// crossing direction.
    fn next_guard(&mut self, t_from: f64, t_to: f64) -> Option<GuardCrossing>;
    /// Closed-form evaluations made so far (for statistics).
    fn evaluations(&self) -> u64;
}

/// The [`RotorModel::Segment`] of a model without exact modes: never started by the
/// driver when every mode is [`Flow::Integrated`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NoExactModes;

impl<const N: usize> ExactSegment<N> for NoExactModes {
    fn eval(&self, _t: f64, y: &mut SVector<f64, N>, dy: &mut SVector<f64, N>) {
        y.fill(f64::NAN);
        dy.fill(f64::NAN);
    }
    fn next_guard(&mut self, _t_from: f64, t_to: f64) -> Option<GuardCrossing> {
        let _ = t_to;
        None
    }
    fn evaluations(&self) -> u64 {
        0
    }
}

/// A piecewise-smooth rotor model with state dimension `N`.
///
/// See the [module docs](self) for the contract. Methods take `&self`: a model is immutable
/// and can be shared across threads; per-run scratch (warm starts of inner solvers) lives in
/// [`RotorModel::Cache`], created by the driver for each run.
pub trait RotorModel<const N: usize> {
    /// The model's modes.
    type Mode: Copy + PartialEq + Debug;
    /// Closed-form motion of exact modes.
    type Segment: ExactSegment<N>;
    /// Per-run scratch, e.g. `Cell`s holding warm starts.
    type Cache: Default;

    /// The mode of an initial state.
    ///
    /// # Errors
    /// [`ModelError::InvalidState`] when the state is not allowed.
    fn initial_mode(&self, t: f64, y: &SVector<f64, N>) -> Result<Self::Mode, ModelError>;

    /// How `mode` is advanced.
    fn flow(&self, mode: Self::Mode) -> Flow;

    /// Vector field of an integrated mode (smooth within the mode).
    fn rhs(
        &self,
        mode: Self::Mode,
        t: f64,
        y: &SVector<f64, N>,
        dy: &mut SVector<f64, N>,
        cache: &Self::Cache,
    );

    /// Number of guards of an integrated mode.
    fn guard_count(&self, mode: Self::Mode) -> usize;

    /// Crossing direction of guard `i` that ends `mode`.
    fn guard_direction(&self, mode: Self::Mode, i: usize) -> Direction;

    /// Value of guard `i` of an integrated mode.
    fn guard_value(
        &self,
        mode: Self::Mode,
        i: usize,
        t: f64,
        y: &SVector<f64, N>,
        cache: &Self::Cache,
    ) -> f64;

    /// Time derivative of guard `i` along the flow (enables grazing detection).
    fn guard_derivative(
        &self,
        mode: Self::Mode,
        i: usize,
        t: f64,
        y: &SVector<f64, N>,
        dy: &SVector<f64, N>,
        cache: &Self::Cache,
    ) -> Option<f64> {
        let _ = (mode, i, t, y, dy, cache);
        None
    }

    /// Whether [`RotorModel::guard_derivative`] reads its `dy` argument; `false` saves a
    /// right-hand side evaluation per event sample (see
    /// [`crate::ode::EventSet::derivative_needs_rhs`]).
    fn guard_derivative_needs_rhs(&self) -> bool {
        true
    }

    /// Short name of guard `i` of `mode`, for event logs.
    fn guard_label(&self, mode: Self::Mode, i: usize) -> &'static str;

    /// Transition map: the mode after guard `guard` of `mode` fired at `(t, y)`; may reset
    /// `y` (e.g. place an algebraic component).
    ///
    /// # Errors
    /// [`ModelError`] when no successor mode exists.
    fn transition(
        &self,
        mode: Self::Mode,
        guard: usize,
        t: f64,
        y: &mut SVector<f64, N>,
    ) -> Result<Self::Mode, ModelError>;

    /// Starts the closed-form motion of an exact mode at `(t, y)`.
    fn start_segment(&self, mode: Self::Mode, t: f64, y: &SVector<f64, N>) -> Self::Segment;

    /// Makes algebraic components consistent (called at outputs and before transitions).
    fn project(&self, mode: Self::Mode, t: f64, y: &mut SVector<f64, N>, cache: &Self::Cache) {
        let _ = (mode, t, y, cache);
    }

    /// A small number labelling the mode in outputs (the paper's regime number for the
    /// Jeffcott model).
    fn mode_label(&self, mode: Self::Mode) -> u8;

    /// Period of the excitation (stroboscopic sampling and the chattering bound use it).
    fn forcing_period(&self) -> f64;
}
