//! The example programs as a user runs them: their command line, `--help`, exit statuses and
//! outputs, and the examples' shared CSV and figure helpers; one module per file:
//! `cargo test --test suite examples::`, or one module:
//! `cargo test --test suite examples::examples_help::`. Each test builds the example it runs,
//! once a process (`tests/support/examples.rs`).

mod analysis_cli;
mod analysis_plot;
mod examples_help;
mod figures_simulate;
mod global_examples;
mod ross_rotor_cli;
mod rub_cli;
mod run_up_cli;
mod stability_cli;
