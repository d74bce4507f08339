//! The in-process fuzzer (module `fuzz`) and the regression tests of the defects it found
//! (module `fuzz_findings`): `cargo test --test fuzz`; the fuzzer alone:
//! `cargo test --test fuzz fuzz::`, the findings alone: `cargo test --test fuzz fuzz_findings::`.

/// `examples/custom_rotor`'s rotor, one of the fuzzed models.
#[allow(dead_code)] // the example uses what the tests do not
#[path = "../../examples/custom_rotor/rotor.rs"]
mod rotor;

mod fuzz;
mod fuzz_findings;
