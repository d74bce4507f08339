//! Nothing but a home for comparisons with other ODE crates, kept out of `jeffcott`'s
//! dev-dependencies so that a user's first build of an example or a test does not compile a
//! second nalgebra (or diffsol):
//! * `benches/compare_ode_solvers.rs`: the crate `jeffcott` against the generic `ode_solvers`
//!   crate; run it with `cargo bench -p bench-compare`; docs/performance.md gives its tables;
//! * `examples/stiff_jumps.rs`: the stiff problem with 100 jumps (issue 19) with diffsol's
//!   ESDIRK34, TR-BDF2 and BDF; run it with
//!   `cargo run -p bench-compare --features diffsol --release --example stiff_jumps`.
