//! `examples/stability`: one JSON object on standard output with the keys, in every
//! mode (`orbit`, `lyapunov`, `locate-loss`, `pictures`); status 2 with one line on standard
//! error for bad input.

use crate::support;

use std::process::{Command, Output};

use serde_json::Value;

fn run(args: &[&str]) -> Output {
    Command::new(support::example_exe("stability"))
        .args(args)
        .output()
        .expect("run the example")
}

/// The single JSON object printed by a successful run.
fn json(args: &[&str]) -> Value {
    let out = support::run_ok(Command::new(support::example_exe("stability")).args(args));
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert_eq!(stdout.lines().count(), 1, "one line of JSON: {stdout}");
    serde_json::from_str(&stdout).expect("valid JSON")
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

#[test]
fn orbit_mode_prints_the_check_value() {
    let v = json(&["orbit", "--period", "1", "--eta", "2"]);
    assert_eq!(v["period"], 1);
    let point: Vec<f64> = v["point"].as_array().unwrap().iter().map(f).collect();
    let check = [0.5781094858, -0.0232587983, 0.0944197873, -0.3099208533];
    for (a, b) in point.iter().zip(check) {
        assert!((a - b).abs() < 2e-10, "{a} vs {b}");
    }
    assert!(f(&v["residual"]) <= 1e-11);
    let m = v["multipliers"].as_array().unwrap();
    assert_eq!(m.len(), 4);
    let modulus: Vec<f64> = m.iter().map(|p| f(&p[0]).hypot(f(&p[1]))).collect();
    for (a, b) in modulus
        .iter()
        .zip([0.73114935, 0.67460586, 0.67460586, 0.62356301])
    {
        assert!((a - b).abs() < 1e-8, "{a} vs {b}");
    }
    // Sorted by modulus, largest first; the pair as lambda, conj(lambda).
    assert!(modulus.windows(2).all(|w| w[0] >= w[1]));
    assert!(f(&m[1][1]) > 0.0 && f(&m[2][1]) < 0.0);
    assert_eq!(v["contacts"], 1);
    // tests/data/stability_reference.csv: 0.0388609869820 (the located maximum; the crate's
    // sampled depth is 3.7e-9 below it).
    let depth = f(&v["min_depth"]);
    eprintln!("depth {:.1e} from the reference's", depth - 0.0388609869820);
    assert!(depth <= 0.0388609869820 && depth > 0.0388609869820 - 1e-8);
    assert!(v["grazing_margin"].is_null());
}

#[test]
fn lyapunov_mode_prints_the_spectrum_and_its_errors() {
    let v = json(&[
        "lyapunov",
        "--eta",
        "2",
        "--transient",
        "100",
        "--periods",
        "200",
    ]);
    let lambda: Vec<f64> = v["lambda"].as_array().unwrap().iter().map(f).collect();
    assert_eq!(lambda.len(), 4);
    // A stable fixed point: the logs of its multipliers' moduli (the reference's 0.7311493468).
    let two = f(&v["lambda1_two_trajectory"]);
    eprintln!(
        "lambda_1 {:.1e} from ln|multiplier|, two-trajectory {:.1e} from QR",
        lambda[0] - 0.7311493468f64.ln(),
        two - lambda[0]
    );
    assert!(
        (lambda[0] - 0.7311493468f64.ln()).abs() < 1e-5,
        "{lambda:?}"
    );
    assert_eq!(v["stderr"].as_array().unwrap().len(), 4);
    // Measured -6.4e-6 and 6.5e-6 (200 periods).
    assert!((two - lambda[0]).abs() < 2e-5);
    assert!(f(&v["stderr_two_trajectory"]) >= 0.0);
    assert_eq!(v["batch_length"], 10);
    assert_eq!(v["batches"], 20);
}

#[test]
fn locate_loss_mode_prints_the_flip() {
    // A short continuation near the reference's 2.2348432765533 (+- 2e-11,
    // tests/data/stability_reference.csv).
    let v = json(&[
        "locate-loss",
        "--from",
        "2.22",
        "--to",
        "2.24",
        "--period",
        "1",
        "--step",
        "0.005",
    ]);
    eprintln!(
        "eta* {:.1e} from the reference's",
        f(&v["eta"]) - 2.2348432765533
    );
    // Measured 4.2e-12.
    assert!((f(&v["eta"]) - 2.2348432765533).abs() < 5e-11, "{v}");
    assert_eq!(v["kind"], "flip");
    let m = v["multipliers"].as_array().unwrap();
    assert!((f(&m[0][0]) + 1.0).abs() < 1e-5);
    // Stable all the way: eta null.
    let v = json(&[
        "locate-loss",
        "--from",
        "2.0",
        "--to",
        "2.02",
        "--period",
        "1",
    ]);
    assert!(v["eta"].is_null() && v["kind"].is_null());
}

#[test]
fn bad_input_exits_with_status_2_and_one_line() {
    for args in [
        vec!["--period", "1"],
        vec![],
        vec!["orbit", "lyapunov"],
        vec!["--orbit"],
        vec!["lyapunov", "--from", "2"],
        vec!["orbit", "--period", "0"],
        vec!["locate-loss", "--from", "2"],
        vec!["orbit", "--eta", "abc"],
        vec!["lyapunov", "--periods", "10", "--batch", "20"],
        vec!["orbit", "--bogus", "1"],
    ] {
        let out = run(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(out.stdout.is_empty(), "{args:?}");
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{err}");
    }
}

#[test]
fn a_failed_computation_exits_with_status_1() {
    // Past the flip the period-1 orbit is unstable: there is nothing to continue.
    let out = run(&[
        "locate-loss",
        "--from",
        "2.3",
        "--to",
        "2.4",
        "--period",
        "1",
    ]);
    assert_eq!(out.status.code(), Some(1));
    assert!(out.stdout.is_empty());
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(err.lines().count(), 1, "{err}");
    assert!(err.contains("stable") || err.contains("residual"), "{err}");
}

#[test]
fn pictures_mode_writes_its_figures() {
    let dir = std::env::temp_dir().join(format!("jeffcott-stability-{}", std::process::id()));
    let v = json(&[
        "pictures",
        "--out",
        dir.to_str().unwrap(),
        "--values",
        "3",
        "--transient",
        "20",
        "--periods",
        "40",
        "--step",
        "0.05",
    ]);
    assert_eq!(v["figures"], dir.to_str().unwrap());
    for name in [
        "multipliers_period1.png",
        "multipliers_period1.csv",
        "lyapunov_fig8a.png",
        "lyapunov_fig8a_top.csv",
        "lyapunov_fig8a_bottom.csv",
        "lyapunov_fig8b.png",
    ] {
        assert!(dir.join(name).exists(), "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `orbit --friction MU --shaft-radius A`: the period-2 rub orbit of the Fig. 8 rotor on an
/// isotropic ring at eta 2.5 (onsets into slip and into rolling, ends of rolling). Its point is
/// checked by plain simulation, not by Newton: two forcing periods of `rubbing_model` from it
/// return to it to 1e-9. A section that falls in a contact (eta 3 after 101 periods) is
/// status 1 naming `--phi0`; friction without a radius is status 2.
#[test]
fn orbit_mode_with_friction_finds_the_rub_orbit() {
    use jeffcott::hybrid::SimOptions;
    use jeffcott::nalgebra::DVector;
    use jeffcott::paper::rub::rubbing_model;
    use jeffcott::params::Preset;
    use jeffcott::stability::StroboscopicMap;

    let scene = [
        "--nu1",
        "0.125",
        "--k",
        "30",
        "--ex",
        "0.9",
        "--ey",
        "0.1",
        "--friction",
        "0.3",
        "--shaft-radius",
        "0.05",
        "--period",
        "2",
    ];
    let mut args = vec!["orbit", "--eta", "2.5", "--transient", "100"];
    args.extend_from_slice(&scene);
    let v = json(&args);
    assert_eq!(v["period"], 2);
    assert!(f(&v["spectral_radius"]) < 1.0);
    let point: Vec<f64> = v["point"].as_array().unwrap().iter().map(f).collect();
    let p = Preset::Fig8a.params().with_eta(2.5);
    let p = jeffcott::params::Params {
        nu1: 0.125,
        kx: 30.0,
        ky: 30.0,
        ex: 0.9,
        ey: 0.1,
        ..p
    };
    let model = rubbing_model(&p, 0.3, 0.05).unwrap();
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-13);
    let map = StroboscopicMap::new(&model, 2, opts).unwrap();
    let y0 = DVector::from_vec(vec![point[0], point[1], point[2], point[3], 0.0, 0.0]);
    let back = map.advance(&y0).unwrap();
    let off = (0..4)
        .map(|i| (back.y[i] - point[i]).abs())
        .fold(0.0, f64::max);
    eprintln!("the rub orbit's point comes back to {off:.1e}");
    assert!(off < 1e-9, "{off:e}");
    let mut contact = vec!["orbit", "--eta", "3", "--transient", "101"];
    contact.extend_from_slice(&scene);
    let out = run(&contact);
    let err = String::from_utf8(out.stderr).unwrap();
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("--phi0") && err.lines().count() == 1, "{err}");
    let out = run(&["orbit", "--friction", "0.3"]);
    assert_eq!(out.status.code(), Some(2));
}
