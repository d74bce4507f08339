//! The command-line contract of `examples/simulate.rs`, tested on the built example.
//!
//! The example binary is built by `cargo build --example simulate` from this test (a no-op
//! when `cargo test` has already built it), so the test also runs under
//! `cargo test --test suite examples::figures_simulate::` and never uses a stale binary. If the
//! example does not build, every test here fails.

use crate::support as examples;

use std::f64::consts::TAU;
use std::path::PathBuf;
use std::process::{Command, Output};
use std::sync::OnceLock;

/// Path of the `simulate` example, built once per test run.
fn simulate_exe() -> PathBuf {
    static EXE: OnceLock<PathBuf> = OnceLock::new();
    EXE.get_or_init(|| examples::example_exe("simulate"))
        .clone()
}

fn run(args: &[&str]) -> Output {
    Command::new(simulate_exe())
        .args(args)
        .output()
        .expect("run simulate")
}

fn rows(out: &Output) -> Vec<Vec<String>> {
    String::from_utf8_lossy(&out.stdout)
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn header_rows_and_tau() {
    let out = run(&["--periods", "5"]);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(text.lines().next(), Some("k,tau,x,y,vx,vy,xs,ys,regime"));
    let rows = rows(&out);
    assert_eq!(rows.len(), 6);
    let eta = 2.0; // fig8a
    for (i, r) in rows.iter().enumerate() {
        assert_eq!(r.len(), 9, "{r:?}");
        assert_eq!(r[0], i.to_string());
        let tau: f64 = r[1].parse().unwrap();
        assert!(
            (tau - TAU * i as f64 / eta).abs() <= 1e-12 * (1.0 + tau),
            "{tau}"
        );
        for v in &r[2..8] {
            assert!(v.parse::<f64>().unwrap().is_finite(), "{v}");
        }
        let regime: u8 = r[8].parse().unwrap();
        assert!((1..=5).contains(&regime));
    }
    // Row 0 is the initial state (at rest at the origin, no contact).
    for v in &rows[0][2..8] {
        assert!(v.parse::<f64>().unwrap().abs() < 1e-15, "{v}");
    }
    assert_eq!(rows[0][8], "1");
}

#[test]
fn transient_shifts_tau_not_k_and_flags_override_the_preset() {
    let args = [
        "--preset",
        "fig8b",
        "--eta",
        "3",
        "--transient",
        "7",
        "--periods",
        "3",
    ];
    let out = run(&args);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let shifted = rows(&out);
    assert_eq!(shifted.len(), 4);
    for (i, r) in shifted.iter().enumerate() {
        assert_eq!(r[0], i.to_string());
        let tau: f64 = r[1].parse().unwrap();
        let expected = TAU * (7 + i) as f64 / 3.0;
        assert!(
            (tau - expected).abs() <= 1e-12 * expected,
            "{tau} vs {expected}"
        );
    }
    // The row k = 0 after 7 periods is the row k = 7 of a run without transient: same bits.
    let full = run(&["--preset", "fig8b", "--eta", "3", "--periods", "10"]);
    let full = rows(&full);
    assert_eq!(full[7][1..], shifted[0][1..]);
    // Full-precision output: every number reads back and prints the same.
    for v in &shifted[1][1..8] {
        let x: f64 = v.parse().unwrap();
        assert!(format!("{x}") == *v || format!("{x:e}") == *v, "{v}");
    }
}

#[test]
fn bad_input_exits_2_with_one_line() {
    let cases: [&[&str]; 12] = [
        &["--bogus", "1"],
        &["--eta"],
        &["--eta", "abc"],
        &["--eta", "NaN"],
        &["--eta", "-1"],
        &["--nu1", "-0.5"],
        &["--preset", "fig99"],
        &["--method", "euler"],
        &["--periods", "2.5"],
        &["--steps-per-period", "0"],
        &["--rtol", "2"],
        &["stray"],
    ];
    for args in cases {
        let out = run(args);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(out.stdout.is_empty(), "{args:?}");
    }
}

#[test]
fn simulation_failure_exits_1_with_one_line() {
    // An absurd tolerance: the step size underflows in the first contact phase.
    let out = run(&["--rtol", "0", "--atol", "1e-300", "--periods", "2"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.starts_with("error: "), "{err}");
    // The rows computed before the failure are printed (here: the initial state).
    let text = String::from_utf8_lossy(&out.stdout);
    assert_eq!(text.lines().next(), Some("k,tau,x,y,vx,vy,xs,ys,regime"));
}

#[test]
fn help_exits_0() {
    let out = run(&["--help"]);
    assert_eq!(out.status.code(), Some(0));
    let text = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--preset",
        "--eta",
        "--nu1",
        "--nu2",
        "--k",
        "--beta",
        "--ex",
        "--ey",
        "--delta-x",
        "--delta-y",
        "--phi0",
        "--periods",
        "--transient",
        "--rtol",
        "--atol",
        "--method",
        "--steps-per-period",
        "--x0",
        "--y0",
        "--vx0",
        "--vy0",
    ] {
        assert!(text.contains(&format!("{flag} <")), "{flag}");
    }
}
