//! The built example programs, for the tests of their command-line contracts.

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::process::{Command, Output};
use std::sync::Mutex;

/// The examples this test process has built (or found fresh), by name.
static BUILT: Mutex<BTreeMap<String, PathBuf>> = Mutex::new(BTreeMap::new());

/// Path of example `name`, built by `cargo build --example name` with the profile the test
/// itself was built with (a no-op after a plain `cargo test`, which builds the examples), so
/// that the test never runs a stale binary. Each example is built once a process: a no-op
/// `cargo build` still costs a third of a second of CPU, and the tests that ask for the same
/// example wait for one build instead of queueing on Cargo's lock. Panics, failing the test, if
/// the example cannot be built: a test of an example that does not build must fail, not pass
/// as skipped.
pub fn example_exe(name: &str) -> PathBuf {
    // A test that panicked while holding the lock left the map as it was: still valid.
    let mut built = BUILT.lock().unwrap_or_else(|e| e.into_inner());
    if let Some(bin) = built.get(name) {
        return bin.clone();
    }
    let bin = build_example(name);
    built.insert(name.to_owned(), bin.clone());
    bin
}

/// Builds example `name` (see [`example_exe`]) and returns its path.
fn build_example(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("the test's own path");
    // target/<profile>/deps/<test> -> target/<profile>
    let profile_dir = exe
        .parent()
        .and_then(|d| d.parent())
        .expect("target/<profile>/deps")
        .to_path_buf();
    let bin = profile_dir
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let mut cmd = Command::new(cargo);
    cmd.args(["build", "--quiet", "--example", name])
        .arg("--manifest-path")
        .arg(concat!(env!("CARGO_MANIFEST_DIR"), "/Cargo.toml"));
    if profile_dir.file_name().is_some_and(|n| n == "release") {
        cmd.arg("--release");
    } else {
        cmd.args(["--profile", "test"]);
    }
    let status = cmd.status().expect("run cargo to build the example");
    assert!(
        status.success(),
        "building the example `{name}` failed: {status}"
    );
    assert!(
        bin.exists(),
        "example `{name}` not found at {}",
        bin.display()
    );
    bin
}

/// Runs `cmd` to completion and returns its output, failing the test with the command's
/// standard error if it does not exit successfully.
#[allow(dead_code)] // included by tests that only check failures too
pub fn run_ok(cmd: &mut Command) -> Output {
    let out = cmd.output().expect("run the example");
    assert!(
        out.status.success(),
        "{:?}: {}\n{}",
        cmd,
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    out
}
