//! The paper's model: the Jeffcott rotor with a preloaded snubber ring.
pub mod free_flight;
mod model;
pub mod onset;

pub use model::{guard, Cache, FreeSegment, JeffcottModel, Mode, RunFailure, State};
