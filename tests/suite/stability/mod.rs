//! Integration tests of the stability tools (`jeffcott::stability`): Jacobians, saltation,
//! periodic orbits and multipliers, Lyapunov exponents; one module per file:
//! `cargo test --test suite stability::`, or one module:
//! `cargo test --test suite stability::stability_orbits::`.

mod stability_friction;
mod stability_honesty;
mod stability_jacobian;
mod stability_lyapunov;
mod stability_models;
mod stability_orbits;
mod stability_progress;
mod stability_rub_fold;
mod stability_rub_map;
mod stability_saltation;
