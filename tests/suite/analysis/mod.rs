//! Integration tests of the analyses (`jeffcott::analysis`): period detection, Poincaré
//! sections, sweeps and the analyses behind the figures; one module per file:
//! `cargo test --test suite analysis::`, or one module:
//! `cargo test --test suite analysis::analysis_sweep::`.

mod analysis_honesty;
mod analysis_models;
mod analysis_period;
mod analysis_poincare;
mod analysis_sweep;
mod figures_analysis;
mod order;
mod revolutions;
