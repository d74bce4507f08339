//! Stability of non-smooth orbits: linearisation of the hybrid flow through its events.
//!
//! Smooth variational equations are wrong across a contact: a perturbation that moves an event
//! in time picks up the jump of the vector field there. This module collects the pieces that
//! carry a perturbation through a piecewise-smooth trajectory:
//!
//! * [`saltation()`]: the saltation matrix of one event, for any state dimension (fixed or
//!   dynamic), with a typed grazing flag;
//! * the model-side derivatives it is built from live with the models: the ring's in
//!   [`crate::ring`] (`ContactHessian`, `ForceJacobian`, `GuardGradient`, the relaxation's
//!   sensitivities), the paper's free flight in
//!   [`crate::paper::free_flight::FreeOscillator::transition_matrix`].

pub mod saltation;

pub use saltation::{saltation, EventLinearization, Saltation, SaltationError, GRAZING_MARGIN};
pub mod floquet;
pub mod newton;
pub mod statistics;

pub use floquet::{multipliers, CrossingKind, FloquetError, Multiplier};
pub use newton::{newton_fixed_point, FixedPoint, MapValue, NewtonError, NewtonOptions};
pub use statistics::{qr_step, BatchEstimate, BatchMeans};
mod augmented;
mod error;
pub mod variational;

pub use augmented::LinearEvent;
pub use error::StabilityError;
pub use variational::{Variational, VariationalAlloc, Workspace};
pub mod map;
mod ring_models;

pub use map::{Advanced, Linearization, StroboscopicMap};
pub mod orbit;

pub use orbit::{periodic_orbit, OrbitMargins, OrbitOptions, PeriodicOrbit};
pub mod lyapunov;

pub use lyapunov::{lyapunov_exponents, LyapunovOptions, LyapunovSpectrum, TwoTrajectory};
pub mod continuation;

pub use continuation::{
    locate_loss, Continuation, ContinuationOptions, ContinuationPoint, LossKind, StabilityLoss,
};
