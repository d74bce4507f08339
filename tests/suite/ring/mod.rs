//! Integration tests of the snubber ring (`jeffcott::ring`) and its certified onset search,
//! one module per file: `cargo test --test suite ring::`, or one module:
//! `cargo test --test suite ring::ring_locate::`.

mod onset_bruteforce;
mod onset_linear;
mod ring_boundaries;
mod ring_element;
mod ring_friction;
mod ring_locate;
mod ring_relax;
mod ring_sensitivity;
mod rub_closed_forms;
mod rub_drive;
pub(crate) mod rub_energy;
mod rub_simulation;
mod rub_smoothed;
