//! Integration tests of the stability tools (`jeffcott::stability`): Jacobians, saltation,
//! periodic orbits and multipliers, Lyapunov exponents; one module per file:
//! `cargo test --test stability`, or one module: `cargo test --test stability stability_orbits::`.

/// `examples/custom_rotor`'s rotor, tested as a user's model.
#[allow(dead_code)] // the example uses what the tests do not
#[path = "../../examples/custom_rotor/rotor.rs"]
mod rotor;

mod stability_honesty;
mod stability_jacobian;
mod stability_lyapunov;
mod stability_models;
mod stability_orbits;
mod stability_progress;
mod stability_saltation;
