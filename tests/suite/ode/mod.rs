//! Integration tests of the ODE layer (`jeffcott::ode`), one module per file:
//! `cargo test --test suite ode::`, or one module: `cargo test --test suite ode::ode_events::`.
//! The allocation counts are apart, in `tests/ode_alloc.rs` (a counting global allocator).

mod ode_adaptive;
mod ode_convergence;
mod ode_dense_tangent;
mod ode_determinism;
mod ode_dyn;
mod ode_errors;
mod ode_etd4;
mod ode_etd4_dense;
mod ode_etd4_forcing;
mod ode_etd4_shaft;
mod ode_events;
mod ode_honesty;
mod ode_radau;
mod ode_radau_contacts;
mod ode_radau_dense;
mod ode_stiff_jumps;
mod ode_stiff_set;
