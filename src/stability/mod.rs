//! Stability of non-smooth orbits: linearisation of the hybrid flow through its events,
//! periodic orbits and their Floquet multipliers, Lyapunov exponents, and where an orbit loses
//! stability along a parameter.
//!
//! Smooth variational equations are wrong across a contact: a perturbation that moves an event
//! in time picks up the jump of the vector field there, the **saltation matrix**
//! ([`saltation()`]). Integrated with the state through every event, the variational
//! equations give the Jacobian of the stroboscopic map exactly where the map is smooth, and
//! say where it is not (grazing, with its margin).
//!
//! What a model supplies for its linearisation is the trait [`Variational`](crate::hybrid::Variational) of
//! [`crate::hybrid`] (field and reset Jacobians, guard gradients, the closed form's Jacobian,
//! its algebraic components, with finite-difference defaults), implemented with each model:
//! analytic for [`crate::paper::JeffcottModel`], the ring's parts analytic for
//! [`crate::rotor::RingedRotor`]. This module uses the trait only and names no model. The
//! layers, bottom up:
//!
//! | item | role |
//! |---|---|
//! | [`saltation()`] | the saltation matrix of one event, any dimension, typed grazing flag |
//! | [`StroboscopicMap`] | $P^n$ on the non-algebraic components and its Jacobian $DP^n$ (or $DP^n Q$) |
//! | [`periodic_orbit`] | Newton on $P^n(z) - z$: point, residual, multipliers, grazing margins |
//! | [`lyapunov_exponents`] | QR (Benettin) spectrum with batch-means errors, two-trajectory check |
//! | [`continue_orbit`], [`switch_at_flip`] | the continuation core: pseudo-arclength along a parameter (a closure builds the model) through folds, with fold, flip, Neimark–Sacker and grazing located, and branch switching at a flip |
//! | [`locate_loss`] | its natural-parameter case: where a stable orbit loses stability (flip, fold, Neimark–Sacker, grazing), or a failure with its error |
//! | [`floquet`], [`newton`], [`statistics`] | the numerics underneath, on plain matrices and closures |
//!
//! The ring's own derivatives are in [`crate::ring::sensitivity`], the paper's free flight's
//! transition matrix in [`crate::paper::free_flight::FreeOscillator::transition_matrix`]. The
//! method, every saltation matrix of the model written out, the cross-checks and the results
//! are in [stability.md](https://docs.rs/crate/jeffcott/latest/source/docs/stability.md).

mod augmented;
pub mod continuation;
mod error;
pub mod floquet;
pub mod lyapunov;
pub mod map;
pub mod newton;
pub mod orbit;
pub mod saltation;
pub mod statistics;

pub use augmented::LinearEvent;
pub use continuation::{
    continue_orbit, locate_loss, switch_at_flip, Branch, BranchEnd, BranchFailure, BranchPoint,
    Continuation, ContinuationOptions, ContinuationPoint, LossOptions, SpecialKind, SpecialPoint,
    StabilityLoss,
};
pub use error::StabilityError;
pub use floquet::{multipliers, CrossingKind, FloquetError, Multiplier};
pub use lyapunov::{lyapunov_exponents, LyapunovOptions, LyapunovSpectrum, TwoTrajectory};
pub use map::{Advanced, Linearization, StroboscopicMap};
pub use newton::{newton_fixed_point, FixedPoint, MapValue, NewtonError, NewtonOptions};
pub use orbit::{periodic_orbit, OrbitMargins, OrbitOptions, PeriodicOrbit};
pub use saltation::{saltation, EventLinearization, Saltation, SaltationError, GRAZING_MARGIN};
pub use statistics::{qr_step, BatchEstimate, BatchMeans};
