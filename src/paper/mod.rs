//! The paper's model: the Jeffcott rotor with a preloaded snubber ring, as a
//! [`RotorModel`](crate::hybrid::RotorModel), and the analyses of [`crate::analysis`] over its
//! parameters ([`ParamSweep`]) and on the grids of [`crate::global`] ([`BasinPlane`],
//! [`ParamPlane`]).
pub mod free_flight;
mod linearization;
mod model;
mod planes;
mod sweep;

pub use model::{guard, Cache, FreeSegment, JeffcottModel, Mode, RunFailure, State};
pub use planes::{BasinPlane, ParamPlane, StartPlane};
pub use sweep::{poincare_map, ParamSweep, RotorStart, SweepParameter};
