//! Nothing but a home for `benches/compare_ode_solvers.rs`: the crate `jeffcott` against the
//! generic `ode_solvers` crate, kept out of `jeffcott`'s dev-dependencies so that a user's first
//! build of an example or a test does not compile a second nalgebra. Run it with
//! `cargo bench -p bench-compare`; docs/performance.md gives its tables.
