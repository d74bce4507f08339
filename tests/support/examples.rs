//! The built example programs, for the tests of their command-line contracts.

use std::path::PathBuf;
use std::process::{Command, Output};

/// Path of example `name`, built by `cargo build --example name` with the profile the test
/// itself was built with (a no-op after a plain `cargo test`, which builds the examples), so
/// that the test never runs a stale binary. Panics, failing the test, if the example cannot be
/// built: a test of an example that does not build must fail, not pass as skipped.
pub fn example_exe(name: &str) -> PathBuf {
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
