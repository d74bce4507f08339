//! The paper's model: the Jeffcott rotor with a preloaded snubber ring.
pub mod free_flight;
pub mod onset;
