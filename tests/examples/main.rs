//! The example programs as a user runs them: their command line, `--help`, exit statuses and
//! outputs, and the examples' shared CSV and figure helpers; one module per file:
//! `cargo test --test examples`, or one module: `cargo test --test examples examples_help::`.
//! Each test builds the example it runs (`tests/support/examples.rs`).

/// The examples' shared CLI, CSV and figure helpers (`examples/common/`).
#[path = "../../examples/common/mod.rs"]
mod common;
/// The Duhamel integral of the linear rotor by Gauss-Legendre quadrature.
#[path = "../support/duhamel.rs"]
mod duhamel;
/// The built example programs.
#[path = "../support/examples.rs"]
mod support;

mod analysis_cli;
mod analysis_plot;
mod examples_help;
mod figures_simulate;
mod global_examples;
mod ross_rotor_cli;
mod run_up_cli;
mod stability_cli;
