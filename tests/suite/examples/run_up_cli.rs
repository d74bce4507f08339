//! `examples/run_up`'s one-run interface (issue 21 item 5): CSV `tau,eta,x,y` at S phases per
//! revolution of the out-of-balance, checked against the phase's closed form and, without the
//! ring, against the Duhamel integral; status 2 with one line on standard error for bad input.

use std::f64::consts::TAU;
use std::process::{Command, Output};

use crate::duhamel::{duhamel, ramp_force};
use crate::support;

fn run(args: &[&str]) -> Output {
    Command::new(support::example_exe("run_up"))
        .args(args)
        .output()
        .expect("run the example")
}

/// The rows of a successful `--csv` run.
fn rows(args: &[&str]) -> Vec<[f64; 4]> {
    let out = support::run_ok(Command::new(support::example_exe("run_up")).args(args));
    let text = String::from_utf8(out.stdout).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("tau,eta,x,y"));
    lines
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            [v[0], v[1], v[2], v[3]]
        })
        .collect()
}

#[test]
fn rows_fall_on_the_phases_up_and_down() {
    for (from, to, rate) in [("0.3", "3", "0.02"), ("3", "0.3", "-0.02")] {
        let args = [
            "--preset",
            "fig8a",
            "--eta-from",
            from,
            "--eta-to",
            to,
            "--rate",
            rate,
            "--samples-per-period",
            "8",
            "--csv",
        ];
        let rows = rows(&args);
        let (a, b, r): (f64, f64, f64) = (
            from.parse().unwrap(),
            to.parse().unwrap(),
            rate.parse().unwrap(),
        );
        let end = (b - a) / r;
        // Revolutions over the ramp: the mean speed times its duration, over 2 pi.
        let turns = 0.5 * (a + b) * end / TAU;
        assert_eq!(rows.len() as f64, (8.0 * turns).floor() + 1.0);
        assert_eq!(rows[0], [0.0, a, 0.0, 0.0]);
        for (k, [tau, eta, ..]) in rows.iter().enumerate() {
            let phase = a * tau + 0.5 * r * tau * tau;
            let want = TAU * k as f64 / 8.0;
            assert!(
                (phase - want).abs() <= 1e-12 * want.max(1.0),
                "row {k}: {phase} vs {want}"
            );
            assert!((eta - (a + r * tau)).abs() <= 1e-13 * b.max(a));
            assert!(*tau <= end);
        }
    }
}

#[test]
fn without_the_ring_it_is_the_duhamel_integral() {
    let args = [
        "--preset",
        "fig8a",
        "--no-ring",
        "--ex",
        "0",
        "--ey",
        "0",
        "--nu1",
        "0.05",
        "--phi0",
        "0.3",
        "--rtol",
        "1e-12",
        "--atol",
        "1e-13",
        "--eta-from",
        "0.3",
        "--eta-to",
        "2",
        "--rate",
        "0.02",
        "--samples-per-period",
        "16",
        "--csv",
    ];
    let rows = rows(&args);
    let radius = |r: &[f64; 4]| r[2].hypot(r[3]);
    let peak = (0..rows.len())
        .max_by(|&i, &j| radius(&rows[i]).total_cmp(&radius(&rows[j])))
        .unwrap();
    let amplitude = radius(&rows[peak]);
    let beta = jeffcott::params::Preset::Fig8a.params().beta;
    let mut worst = 0.0f64;
    for i in [peak - 7, peak, peak + 7] {
        let tau = rows[i][0];
        let panels = (tau * 100.0).ceil() as usize;
        for c in 0..2 {
            let f = |u: f64| ramp_force(beta, 0.3, 0.3, 0.02, u, true)[c];
            worst = worst.max((rows[i][2 + c] - duhamel(0.05, f, tau, panels)).abs());
        }
    }
    eprintln!(
        "peak {amplitude:.6} at eta {:.4}: worst {:.2e} of it",
        rows[peak][1],
        worst / amplitude
    );
    assert!(worst <= 1e-9 * amplitude);
}

#[test]
fn bad_input_is_status_2_with_one_line() {
    let base = ["--eta-to", "3", "--csv"];
    let cases: [&[&str]; 7] = [
        &[
            "--eta-from",
            "0.3",
            "--rate",
            "-0.01",
            "--samples-per-period",
            "8",
        ],
        &[
            "--eta-from",
            "0.3",
            "--rate",
            "0",
            "--samples-per-period",
            "8",
        ],
        &[
            "--eta-from",
            "0.3",
            "--rate",
            "nan",
            "--samples-per-period",
            "8",
        ],
        &[
            "--eta-from",
            "-1",
            "--rate",
            "0.01",
            "--samples-per-period",
            "8",
        ],
        &[
            "--eta-from",
            "0.3",
            "--rate",
            "0.01",
            "--samples-per-period",
            "0",
        ],
        &[
            "--eta-from",
            "3",
            "--rate",
            "0.01",
            "--samples-per-period",
            "8",
        ],
        &[
            "--eta-from",
            "0.3",
            "--rate",
            "0.01",
            "--samples-per-period",
            "8",
            "--preset",
            "nope",
        ],
    ];
    for extra in cases {
        let mut args: Vec<&str> = base.to_vec();
        args.extend_from_slice(extra);
        let out = run(&args);
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2), "{extra:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{extra:?}: {err}");
        assert!(err.starts_with("error"), "{err}");
        assert!(out.stdout.is_empty());
    }
    let out = run(&[
        "--eta-from",
        "0.3",
        "--eta-to",
        "3",
        "--samples-per-period",
        "8",
    ]);
    assert_eq!(out.status.code(), Some(2), "--rate is required");
}

#[test]
fn out_draws_the_envelope_of_both_legs_and_the_orders() {
    let dir = std::env::temp_dir().join(format!("run_up_cli_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = support::run_ok(
        Command::new(support::example_exe("run_up"))
            .args([
                "--preset",
                "fig8a",
                "--x0",
                "0.9",
                "--eta-from",
                "0.5",
                "--eta-to",
                "2",
                "--rate",
                "0.05",
                "--samples-per-period",
                "8",
                "--out",
            ])
            .arg(&dir),
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(
        text.lines().count(),
        2,
        "a summary line for each sweep: {text}"
    );
    assert!(text.lines().all(|l| l.starts_with("peak radius")), "{text}");
    assert!(dir.join("envelope.png").is_file());
    let csv = std::fs::read_to_string(dir.join("envelope.csv")).unwrap();
    let series: std::collections::BTreeSet<&str> = csv
        .lines()
        .skip(1)
        .filter_map(|l| l.split(',').next())
        .collect();
    assert_eq!(series.len(), 2, "up and down: {series:?}");
    // One row a whole revolution of the run up and back: the phase's closed form, the mean
    // speed 1.25 times the duration 2 x 30, over 2 pi.
    let revolutions = (1.25 * 60.0 / TAU).floor();
    assert_eq!(csv.lines().count() as f64 - 1.0, revolutions);
    for file in ["orders.png", "waterfall.png", "revolutions.csv"] {
        assert!(dir.join(file).is_file(), "{file}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--motor`: the weak motor of `tests/suite/simulation/drive.rs` without the ring (rest at the
/// centre) is captured where its line meets the closed-form load, 0.931146 (computed there);
/// a motor of two numbers, or with `--eta-to`, is status 2.
#[test]
fn motor_runs_the_non_ideal_drive() {
    let args = [
        "--preset",
        "fig8a",
        "--no-ring",
        "--eta-from",
        "0.1",
        "--samples-per-period",
        "8",
        "--motor",
        "0.05,3,10",
        "--duration",
        "900",
    ];
    let out = support::run_ok(Command::new(support::example_exe("run_up")).args(args));
    let text = String::from_utf8(out.stdout).unwrap();
    let last = text.lines().last().unwrap();
    let mean: f64 = last
        .strip_prefix("last third: mean eta ")
        .and_then(|r| r.split(',').next())
        .unwrap()
        .parse()
        .unwrap();
    assert!((mean - 0.931146).abs() < 1e-4, "{last}");
    for bad in [
        &["--motor", "1,2"][..],
        &["--motor", "1,2,3", "--eta-to", "2"],
    ] {
        let mut a = vec![
            "--preset",
            "fig8a",
            "--eta-from",
            "0.1",
            "--samples-per-period",
            "8",
        ];
        a.extend_from_slice(bad);
        let out = run(&a);
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2), "{bad:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{bad:?}: {err}");
    }
}

/// `--motor` with `--friction`: the rub torque brakes the drive. Fig. 8a's rotor driven from
/// 2.5 by $t = 3(1 - \eta/2.7)$, $j = 2$, rubs the ring slipping forward (shaft radius 0.5
/// gaps, no slip stops), so the torque $-\mu_f N a$ only brakes: the mean speed of the last
/// third falls below the frictionless run's (measured 2.6633 against 2.6791; the torque's work
/// is checked by the energy balance of `ring::rub_energy`). Friction without `--motor` or
/// without `--shaft-radius` is status 2.
#[test]
fn motor_with_friction_is_braked_by_the_rub_torque() {
    let base = [
        "--preset",
        "fig8a",
        "--eta-from",
        "2.5",
        "--samples-per-period",
        "16",
        "--motor",
        "3,2.7,2",
        "--duration",
        "200",
    ];
    let last_line = |extra: &[&str]| {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        let out = support::run_ok(Command::new(support::example_exe("run_up")).args(args));
        String::from_utf8(out.stdout)
            .unwrap()
            .lines()
            .last()
            .unwrap()
            .to_string()
    };
    let mean = |line: &str| -> f64 {
        let rest = line.strip_prefix("last third: mean eta ").unwrap();
        rest.split(',').next().unwrap().parse().unwrap()
    };
    let dry = last_line(&[]);
    let rub = last_line(&["--friction", "0.3", "--shaft-radius", "0.5"]);
    assert!(
        rub.contains("slip stops") && rub.contains("ends of rolling"),
        "{rub}"
    );
    assert!(!dry.contains("slip stops"), "{dry}");
    assert!(mean(&rub) < mean(&dry) - 0.005, "{rub} against {dry}");
    for bad in [&base[..6], &base[..]] {
        let mut a = bad.to_vec();
        if a.len() == 6 {
            a.extend_from_slice(&[
                "--eta-to",
                "3",
                "--rate",
                "0.1",
                "--friction",
                "0.3",
                "--shaft-radius",
                "1",
            ]);
        } else {
            a.extend_from_slice(&["--friction", "0.3"]);
        }
        let out = run(&a);
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2), "{a:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{a:?}: {err}");
    }
}

/// `--fe`: ROSS's 204-DOF rotor (24 modes) up and back with and without the ring, fast
/// (1000 rad/s²): a line per run and leg, `fe_envelope.png`, and one CSV row a whole
/// revolution of each run (the phase's closed form: $2 \cdot 180 \cdot 0.16$ rad over
/// $2\pi$, floored); `--fe-to` below `--fe-from` is status 2.
#[test]
fn fe_draws_the_envelope_of_a_finite_element_rotor() {
    let dir = std::env::temp_dir().join(format!("run_up_fe_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let out = support::run_ok(
        Command::new(support::example_exe("run_up"))
            .args(["--fe", "--fe-rate", "1000", "--out"])
            .arg(&dir),
    );
    let text = String::from_utf8(out.stdout).unwrap();
    assert_eq!(text.lines().count(), 4, "{text}");
    assert!(text.lines().all(|l| l.starts_with("fe ")), "{text}");
    assert!(dir.join("fe_envelope.png").is_file());
    let csv = std::fs::read_to_string(dir.join("fe_envelope.csv")).unwrap();
    let revolutions = (2.0 * 180.0 * 0.16 / TAU).floor();
    assert_eq!(csv.lines().count() as f64 - 1.0, 2.0 * revolutions, "{csv}");
    let _ = std::fs::remove_dir_all(&dir);
    let out = run(&["--fe", "--fe-from", "300", "--fe-to", "200"]);
    assert_eq!(out.status.code(), Some(2));
}

/// `--fe` with a ring of the user's: a gap of 1 m puts it out of reach, so the run "on the
/// ring" is the run without it (the same peak line, no revolution touched), where the default
/// ring is touched; a malformed `--fe-unbalance` is status 2.
#[test]
fn fe_takes_the_users_ring() {
    let dir = std::env::temp_dir().join(format!("run_up_fe_ring_{}", std::process::id()));
    let lines = |extra: &[&str]| {
        let out = support::run_ok(
            Command::new(support::example_exe("run_up"))
                .args(["--fe", "--fe-rate", "1000", "--fe-modes", "8"])
                .args(extra)
                .arg("--out")
                .arg(&dir),
        );
        let text = String::from_utf8(out.stdout).unwrap();
        let up = |name: &str| {
            let line = text
                .lines()
                .find(|l| l.starts_with(name))
                .unwrap()
                .to_string();
            let peak = line.split(" µm").next().unwrap().to_string();
            let touched = line
                .split("; ")
                .nth(1)
                .unwrap()
                .split(' ')
                .next()
                .unwrap()
                .to_string();
            (peak.replace(name, ""), touched)
        };
        (up("fe on the ring, up"), up("fe without the ring, up"))
    };
    let (ring, free) = lines(&[]);
    assert_ne!(ring.1, "0", "the default ring is touched");
    let (far, free_again) = lines(&["--fe-gap", "1"]);
    assert_eq!(far, (free.0.clone(), "0".to_string()));
    assert_eq!(free_again, free);
    let _ = std::fs::remove_dir_all(&dir);
    let out = run(&["--fe", "--fe-unbalance", "12,2e-3"]);
    assert_eq!(out.status.code(), Some(2));
}

/// The `--fe` runs' summary lines (one per run and leg) of `run_up --fe` with `args`, each
/// without its run time (the text after the last comma).
fn fe_lines(args: &[&str]) -> Vec<String> {
    let dir = std::env::temp_dir().join(format!("run_up_fe_laws_{}", std::process::id()));
    let out = support::run_ok(
        Command::new(support::example_exe("run_up"))
            .arg("--fe")
            .args(args)
            .arg("--out")
            .arg(&dir),
    );
    let _ = std::fs::remove_dir_all(&dir);
    let text = String::from_utf8(out.stdout).unwrap();
    text.lines()
        .map(|l| l.rsplit_once(", ").map_or(l, |p| p.0).to_string())
        .collect()
}

/// A file of the repository's `tests/data`.
fn data_path(relative: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(relative)
}

/// A file in the temporary folder with `text`.
fn temp_file(name: &str, text: &str) -> std::path::PathBuf {
    let path = std::env::temp_dir().join(format!("{}_{name}", std::process::id()));
    std::fs::write(&path, text).unwrap();
    path
}

/// `--fe-profile FILE` (the user's table) and `--fe-motor T0,OMEGA0,J` (the drive) against
/// runs they must reproduce: a table through the sweep's points is the sweep (its one leg's
/// peak the larger of the sweep's two, every revolution of both legs); a drive of huge inertia
/// whose motor holds 150 rad/s is the table holding 150 rad/s (the same peaks and contacts;
/// the speed moves by 1e-9 of itself). Bad tables are status 2.
#[test]
fn fe_takes_a_table_or_a_motor() {
    let sweep = fe_lines(&["--fe-rate", "1000", "--fe-modes", "8"]);
    let points = temp_file(
        "sweep.csv",
        "time_s,speed_rad_s\n0,100\n0.16,260\n0.32,100\n",
    );
    let table = fe_lines(&["--fe-profile", points.to_str().unwrap(), "--fe-modes", "8"]);
    assert_eq!(table.len(), 2, "{table:?}");
    let peak = |l: &str| {
        l.split(" rad/s;")
            .next()
            .unwrap()
            .split(": ")
            .nth(1)
            .unwrap()
            .to_string()
    };
    assert_eq!(peak(&table[0]), peak(&sweep[0]), "{table:?} {sweep:?}");
    assert!(table[0].contains("9 of 9 revolutions touched"), "{table:?}");
    assert!(
        sweep[0].contains("5 of 5") && sweep[1].contains("4 of 4"),
        "{sweep:?}"
    );

    let mat = data_path("rotors/rotor_example_bearings_150rads.mat");
    let hold = temp_file("hold.csv", "0,150\n0.3,150\n");
    let scene = [
        "--fe-mat",
        mat.to_str().unwrap(),
        "--fe-ring-node",
        "3",
        "--fe-gap",
        "4e-5",
        "--fe-unbalance",
        "2,1e-3,0",
        "--fe-modes",
        "12",
    ];
    let held = fe_lines(&[&scene[..], &["--fe-profile", hold.to_str().unwrap()]].concat());
    let motor = [
        "--fe-motor",
        "1e12,150,1e10",
        "--fe-from",
        "150",
        "--fe-duration",
        "0.3",
    ];
    let driven = fe_lines(&[&scene[..], &motor[..]].concat());
    assert_eq!(held.len(), 2);
    for (d, h) in driven.iter().zip(&held) {
        assert_eq!(d.replace("driven", "table"), *h);
    }
    assert!(held[0].contains("5 events"), "{held:?}");

    for bad in [
        "0,100\n",
        "1,100\n2,200\n",
        "0,100\n0,200\n",
        "0,100\nx,y\n",
    ] {
        let file = temp_file("bad.csv", bad);
        let out = run(&["--fe", "--fe-profile", file.to_str().unwrap()]);
        assert_eq!(out.status.code(), Some(2), "{bad:?}");
    }
    let out = run(&["--fe", "--fe-motor", "1,2"]);
    assert_eq!(out.status.code(), Some(2));
}

/// `--fe-bearing-mat SPEED:FILE`: ROSS's `rotor_example` with bearings that stiffen with the
/// speed, exported by ROSS at 100, 150 and 200 rad/s (`tests/data/rotors/export_bearing_rotors.py`).
/// Held at 150 rad/s, the rotor with the three exports as its bearing table is the rotor of the
/// export at 150 alone (the table's value at a grid point), and not the one at 100 (the
/// bearings matter). A table of another rotor's size, two equal speeds, or no `SPEED:` are
/// status 2.
#[test]
fn fe_bearings_follow_the_speed_from_exports_at_several_speeds() {
    let mat = |w: u32| data_path(&format!("rotors/rotor_example_bearings_{w}rads.mat"));
    let hold = temp_file("hold150.csv", "0,150\n0.3,150\n");
    let scene = |m: &std::path::Path| {
        vec![
            "--fe-mat".to_string(),
            m.to_str().unwrap().to_string(),
            "--fe-profile".into(),
            hold.to_str().unwrap().into(),
            "--fe-ring-node".into(),
            "3".into(),
            "--fe-gap".into(),
            "4e-5".into(),
            "--fe-unbalance".into(),
            "2,1e-3,0".into(),
            "--fe-modes".into(),
            "12".into(),
        ]
    };
    let table: Vec<String> = [100, 150, 200]
        .iter()
        .flat_map(|&w| {
            [
                "--fe-bearing-mat".to_string(),
                format!("{w}:{}", mat(w).display()),
            ]
        })
        .collect();
    let lines = |v: Vec<String>| fe_lines(&v.iter().map(String::as_str).collect::<Vec<_>>());
    let with_table = lines([scene(&mat(100)), table.clone()].concat());
    let at_150 = lines(scene(&mat(150)));
    let at_100 = lines(scene(&mat(100)));
    assert_eq!(with_table, at_150);
    assert_ne!(with_table[0], at_100[0], "the bearings must matter");

    let other = data_path("rotors/rotor_example_1500rpm.mat");
    for bad in [
        format!("100:{}", other.display()),
        format!("{}", mat(100).display()),
    ] {
        let out = run(&["--fe", "--fe-bearing-mat", &bad]);
        assert_eq!(out.status.code(), Some(2), "{bad}");
    }
    let same = format!("100:{}", mat(100).display());
    let out = run(&["--fe", "--fe-bearing-mat", &same, "--fe-bearing-mat", &same]);
    assert_eq!(out.status.code(), Some(2));
}
