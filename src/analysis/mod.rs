//! Generic analysis tools: period detection, parallel parameter sweeps, section crossings.
//!
//! Nothing here knows about rotors: the tools work on plain `f64` samples and on user-supplied
//! closures, so they can be tested on synthetic data and reused for any simulation.
//!
//! * [`period`]: is a stroboscopic orbit periodic, and with which period? How many distinct
//!   values does a bifurcation-diagram column hold?
//! * [`sweep`](mod@sweep): run a simulation over a list of parameter values in parallel, with
//!   independent values or with the state carried from one value to the next, with results
//!   that are bitwise independent of the number of threads.
//! * [`poincare`]: where a densely sampled trajectory crosses a section.

mod error;
pub mod jeffcott;
pub mod period;
pub mod poincare;
pub mod sweep;

pub use error::AnalysisError;
pub use jeffcott::{
    bifurcation, linspace, locate_period_change, phase_portrait, poincare_map, strobe_orbit,
    Bifurcation, BifurcationConfig, Column, LocatorConfig, OrbitError, PeriodChange, PeriodTest,
    PhasePortrait, StrobeOrbit, StrobePoint, SweepParameter,
};
pub use period::{
    count_distinct, detect_period, detect_period_scalar, distinct_values, recurrence_residual,
    Periodicity,
};
pub use poincare::{section_crossings, section_crossings_hermite, Crossing, Direction};
pub use sweep::{
    chunk_ranges, sweep, Progress, StderrProgress, SweepConfig, SweepMode, SweepResult,
};
