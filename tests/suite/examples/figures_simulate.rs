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

/// `--friction MU --shaft-radius A`: the rows are `paper::rub::rubbing_model`'s stroboscopic
/// states, bit for bit (printed in round-trip form), with the friction's regimes 6 to 8 among
/// them when the contact is met at the strobe; bad friction input exits 2 naming the flag or
/// the field.
#[test]
fn friction_runs_the_papers_rotor_with_friction() {
    use jeffcott::hybrid::{simulate, OutputPlan, SimOptions, Trajectory};
    use jeffcott::nalgebra::DVector;
    use jeffcott::params::Preset;
    // Fig. 8a at eta 2.5 and phi0 = 1, started beyond the gap: it slips forward at the start,
    // and about half its strobes land in contact, rolling.
    let args = [
        "--preset",
        "fig8a",
        "--eta",
        "2.5",
        "--phi0",
        "1",
        "--friction",
        "0.3",
        "--shaft-radius",
        "0.05",
        "--x0",
        "1.1",
        "--periods",
        "40",
    ];
    let out = run(&args);
    assert_eq!(out.status.code(), Some(0), "{out:?}");
    let rows = rows(&out);
    assert_eq!(rows.len(), 41);
    let p = jeffcott::params::Params {
        eta: 2.5,
        phi0: 1.0,
        ..Preset::Fig8a.params()
    };
    let model = jeffcott::paper::rub::rubbing_model(&p, 0.3, 0.05).unwrap();
    let y0 = DVector::from_vec(vec![1.1, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let mut traj = Trajectory::default();
    let plan = OutputPlan::strobe(TAU / 2.5, 0, 40);
    simulate(&model, 0.0, &y0, &plan, &SimOptions::default(), &mut traj).unwrap();
    for (row, point) in rows.iter().zip(&traj.strobe) {
        for (text, value) in row[2..8].iter().zip(point.y.iter()) {
            assert_eq!(text.parse::<f64>().unwrap(), *value, "{row:?}");
        }
        assert_eq!(row[8], point.label.to_string());
    }
    assert_eq!(
        rows[0][8], "6",
        "starts beyond the gap, slipping forward: {:?}",
        rows[0]
    );
    assert!(
        rows.iter().filter(|r| r[8] == "8").count() > 10,
        "rolling at the strobes"
    );
    for (flags, word) in [
        (vec!["--friction", "0.3"], "--shaft-radius"),
        (vec!["--friction", "-1", "--shaft-radius", "1"], "friction"),
        (
            vec!["--friction", "0.3", "--shaft-radius", "0"],
            "shaft_radius",
        ),
        // Beyond 2 sqrt 2, the bound of a preloaded isotropic ring.
        (
            vec!["--friction", "3", "--shaft-radius", "1", "--delta-x", "0.1"],
            "friction",
        ),
    ] {
        let out = run(&flags);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{flags:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(err.contains(word), "{flags:?}: {err}");
    }
}
