//! The integration tests, one binary: an area a module, a file a module inside it.
//!
//! `cargo test --test suite` runs them all; one area: `cargo test --test suite ring::`; one
//! file: `cargo test --test suite ring::onset_bruteforce::`. One binary links the library and
//! instantiates its generic code once, and its tests share both cores (one binary per area ran
//! each area's slowest test alone). The allocation counts are apart (`tests/ode_alloc.rs`: a
//! counting global allocator), and so are the tests of the `serde` and `mpi` features.

// The helpers the areas share (`tests/support/`, and code of the examples tested as a user's).
/// The examples' shared CLI, CSV and figure helpers (`examples/common/`).
#[path = "../../examples/common/mod.rs"]
mod common;
/// The Duhamel integral of the linear rotor by Gauss-Legendre quadrature.
#[path = "../support/duhamel.rs"]
mod duhamel;
/// Energy-balance helpers (simulation and finite-element rotors).
#[path = "../support/energy.rs"]
mod energy;
/// Test models with known solutions (the integrator tests).
#[path = "../support/models.rs"]
mod models;
/// A small deterministic random number generator.
#[path = "../support/rng.rs"]
mod rng;
/// `examples/custom_rotor`'s rotor, tested and fuzzed as a user's model.
#[allow(dead_code)] // the example uses what the tests do not
#[path = "../../examples/custom_rotor/rotor.rs"]
mod rotor;
/// `examples/flexible_shaft`'s modal shaft (a hybrid model with many contact events).
#[allow(dead_code)] // the example uses what the tests do not
#[path = "../../examples/flexible_shaft/shaft.rs"]
mod shaft;
/// The built example programs.
#[path = "../support/examples.rs"]
mod support;

// The areas.
mod analysis;
mod examples;
mod fe;
mod fuzz;
mod global;
/// No module of `src/` imports from a higher layer.
mod layers;
mod ode;
mod ring;
mod simulation;
mod stability;
