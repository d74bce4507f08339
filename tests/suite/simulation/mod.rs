//! Integration tests of the hybrid simulation (`jeffcott::hybrid`, `jeffcott::rotor`): the
//! paper's model, the reference trajectories, hard cases, contact loss and models of the user's
//! own; one module per file: `cargo test --test suite simulation::`, or one module:
//! `cargo test --test suite simulation::hard_cases::`.

mod contact_loss;
mod custom_model;
mod custom_rotor;
mod drive;
mod drive_energy;
mod dyn_models;
mod flexible_shaft;
mod hard_cases;
mod phase_strobes;
mod reference;
mod rotor_checks;
mod run_up;
mod run_up_passage;
mod run_up_profiles;
mod run_up_quasi_static;
mod si_units;
#[allow(clippy::module_inception)] // the paper's runs, in their area: `simulation::simulation::`
mod simulation;
mod stop;
