//! Integration tests of the hybrid simulation (`jeffcott::hybrid`, `jeffcott::rotor`): the
//! paper's model, the reference trajectories, hard cases, contact loss and models of the user's
//! own; one module per file: `cargo test --test simulation`, or one module:
//! `cargo test --test simulation hard_cases::`.

/// The Duhamel integral of the linear rotor by Gauss-Legendre quadrature.
#[path = "../support/duhamel.rs"]
mod duhamel;
/// Energy-balance helpers (with `tests/fe`).
#[path = "../support/energy.rs"]
mod energy;
/// `examples/custom_rotor`'s rotor, tested as a user's model.
#[allow(dead_code)] // the example uses what the tests do not
#[path = "../../examples/custom_rotor/rotor.rs"]
mod rotor;
/// `examples/flexible_shaft`'s modal shaft.
#[allow(dead_code)] // the example uses what the tests do not
#[path = "../../examples/flexible_shaft/shaft.rs"]
mod shaft;
/// The built example programs (`flexible_shaft` runs its example).
#[path = "../support/examples.rs"]
mod support;

mod contact_loss;
mod custom_model;
mod custom_rotor;
mod drive;
mod drive_energy;
mod dyn_models;
mod flexible_shaft;
mod hard_cases;
mod reference;
mod rotor_checks;
mod run_up;
mod run_up_passage;
mod run_up_profiles;
mod run_up_quasi_static;
mod si_units;
mod simulation;
