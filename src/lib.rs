//! Jeffcott rotor with a preloaded snubber ring (crate docs are written in the integration step).
#![forbid(unsafe_code)]
#![deny(missing_docs)]

pub mod analysis;
pub mod hybrid;
pub mod jeffcott;
pub mod ode;
pub mod params;
pub mod ring;
