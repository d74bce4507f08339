//! The in-process fuzzer (module `fuzz`) and the regression tests of the defects it found
//! (module `fuzz_findings`): `cargo test --test suite fuzz::`; the fuzzer alone:
//! `cargo test --test suite fuzz::fuzz::`, the findings alone:
//! `cargo test --test suite fuzz::fuzz_findings::`.

#[allow(clippy::module_inception)] // the fuzzer itself, in its area: `fuzz::fuzz::`
mod fuzz;
mod fuzz_findings;
