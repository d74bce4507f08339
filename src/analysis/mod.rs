//! Analyses of simulations: period detection, stroboscopic orbits, phase portraits and
//! Poincaré sections, parallel parameter sweeps, bifurcation diagrams and a bifurcation
//! locator.
//!
//! Nothing here knows about a particular model: the sample-level tools work on plain `f64`
//! data and user closures, and the simulation-level tools work on any
//! [`RotorModel`](crate::hybrid::RotorModel), a swept parameter being a closure that builds
//! the model at each value (see [`bifurcation`](mod@bifurcation)). The paper's model has
//! ready-made families over its parameters in [`crate::paper::ParamSweep`].
//!
//! * [`period`]: is a sampled orbit periodic, and with which period ([`PeriodTest`] for
//!   state vectors)? How many distinct values does a bifurcation-diagram column hold?
//! * [`orbit`]: stroboscopic orbits of a model after a transient ([`strobe_orbit`]).
//! * [`portrait`]: dense samples with the event log, split into smooth pieces, and Poincaré
//!   sections through them ([`phase_portrait`]).
//! * [`poincare`]: where a densely sampled trajectory crosses a section.
//! * [`sweep`](mod@sweep): run a computation over a list of parameter values in parallel, with
//!   independent values or with the state carried from one value to the next, with results
//!   that are bitwise independent of the number of threads.
//! * [`bifurcation`](mod@bifurcation): bifurcation diagrams of a model family.
//! * [`locate`]: where the detected period changes along a parameter, by bisection.

pub mod bifurcation;
mod error;
pub mod locate;
pub mod orbit;
pub mod period;
pub mod poincare;
pub mod portrait;
pub mod sweep;

pub use bifurcation::{bifurcation, start_from, Bifurcation, BifurcationConfig, Column, Failure};
pub use error::{AnalysisError, OrbitError};
pub use locate::{locate_period_change, LocatedChange, LocatorConfig, PeriodChange};
pub use orbit::{strobe_orbit, PoincareMap, StrobeOrbit};
pub use period::{
    count_distinct, detect_period, detect_period_scalar, detect_period_scaled, distinct_values,
    recurrence_residual, window_residuals, LagResiduals, PeriodTest, Periodicity,
};
pub use poincare::{section_crossings, section_crossings_hermite, Crossing};
pub use portrait::{phase_portrait, PhasePortrait};
pub(crate) use sweep::on_pool;
pub use sweep::{
    chunk_ranges, linspace, sweep, Progress, StderrProgress, SweepConfig, SweepMode, SweepResult,
};
