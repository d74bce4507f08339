//! The in-process fuzzer (module `fuzz`), the regression tests of the defects it found
//! (module `fuzz_findings`) and the linear-rotor fuzzer (module `fuzz_linear`), over one
//! harness (module `harness`): `cargo test --test suite fuzz::`; the fuzzer alone:
//! `cargo test --test suite fuzz::fuzz::`, the findings alone:
//! `cargo test --test suite fuzz::fuzz_findings::`, the linear rotors alone:
//! `cargo test --test suite fuzz::fuzz_linear::`.

#[allow(clippy::module_inception)] // the fuzzer itself, in its area: `fuzz::fuzz::`
mod fuzz;
mod fuzz_findings;
mod fuzz_friction;
mod fuzz_linear;
mod harness;
