//! `examples/rub`: the three scenes against the closed forms of `paper::rub` (which the suite
//! checks against the equation of motion, `ring::rub_closed_forms`), and its pictures.

use crate::support;

use std::process::Command;

use jeffcott::paper::rub::{dry_whip, synchronous_rub};
use jeffcott::params::Params;

/// The number after `key ` in `line`.
fn after(line: &str, key: &str) -> f64 {
    let rest = &line[line.find(key).unwrap_or_else(|| panic!("{key} in {line}")) + key.len()..];
    let word = rest
        .split([' ', ',', ';', '('])
        .find(|w| !w.is_empty())
        .unwrap();
    word.parse()
        .unwrap_or_else(|_| panic!("a number after {key}: {line}"))
}

#[test]
fn rub_reaches_the_closed_forms_and_draws_its_pictures() {
    let out = std::env::temp_dir().join(format!("jeffcott-rub-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let run = support::run_ok(Command::new(support::example_exe("rub")).args([
        "--periods",
        "150",
        "--mu-steps",
        "2",
        "--strobes",
        "2",
        "--out",
        out.to_str().unwrap(),
    ]));
    let stdout = String::from_utf8(run.stdout).unwrap();
    let lines: Vec<&str> = stdout.lines().collect();
    assert_eq!(lines.len(), 4, "{stdout}");
    let p = Params {
        eta: 1.2,
        nu1: 0.05,
        nu2: 0.002,
        kx: 30.0,
        ky: 30.0,
        beta: 0.5,
        dx: 0.0,
        dy: 0.0,
        ex: 0.0,
        ey: 0.0,
        phi0: 0.0,
    };
    // 1. Settling on the synchronous rub (the larger radius), whirling with the spin.
    let rub = synchronous_rub(&p, 0.05).unwrap();
    let radius = rub.iter().map(|r| r.radius).fold(0.0, f64::max);
    assert!(
        (after(lines[0], "radius") - radius).abs() < 1e-3,
        "{}",
        lines[0]
    );
    assert!(
        (after(lines[0], "whirl ratio") - 1.0).abs() < 1e-4,
        "{}",
        lines[0]
    );
    // 2. Turned into a backward whirl near the whip's frequency.
    let whips = dry_whip(&Params { beta: 0.0, ..p }, 0.2).unwrap();
    let whip = whips
        .iter()
        .max_by(|a, b| a.radius.total_cmp(&b.radius))
        .unwrap();
    let ratio = after(lines[1], "whirl ratio");
    assert!(
        (-ratio * p.eta / whip.frequency - 1.0).abs() < 1e-3,
        "{}",
        lines[1]
    );
    // 3. On the dry whip itself.
    assert!(
        (after(lines[2], "radius") - whip.radius).abs() < 1e-7,
        "{}",
        lines[2]
    );
    assert!(
        (after(lines[2], "frequency") - whip.frequency).abs() < 1e-7,
        "{}",
        lines[2]
    );
    for name in [
        "orbit_rub",
        "orbit_whip",
        "whirl",
        "slip_velocity",
        "friction_bifurcation",
    ] {
        for ext in ["png", "csv"] {
            let file = out.join(format!("{name}.{ext}"));
            assert!(
                std::fs::metadata(&file).is_ok_and(|m| m.len() > 0),
                "{file:?}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// `bifurcation --friction MU --shaft-radius A`: Fig. 8a's diagram with friction. Below contact
/// (eta 0.5: the free orbit stays inside the gap) its points are the frictionless diagram's
/// (the paper's `JeffcottModel` there, `rubbing_model`'s `LinearRotor` with its free flight in
/// closed form here: two implementations) to 1e-12; where the rotor rubs (eta 2.5) they are
/// not. Friction without a radius, or with `--locate-from`, is status 2.
#[test]
fn bifurcation_with_friction_draws_the_diagram_of_the_rubbing_rotor() {
    let read = |dir: &std::path::Path| -> Vec<(f64, f64)> {
        let text = std::fs::read_to_string(dir.join("fig8a.csv")).unwrap();
        text.lines()
            .skip(1)
            .map(|l| {
                let (e, x) = l.split_once(',').unwrap();
                (e.parse().unwrap(), x.parse().unwrap())
            })
            .collect()
    };
    let base = std::env::temp_dir().join(format!("jeffcott-bif-rub-{}", std::process::id()));
    let run = |extra: &[&str], name: &str| {
        let dir = base.join(name);
        let mut args = vec![
            "--diagram",
            "a",
            "--eta-min",
            "0.5",
            "--eta-max",
            "2.5",
            "--steps",
            "2",
            "--transient",
            "100",
            "--record",
            "20",
            "--out",
        ];
        args.push(dir.to_str().unwrap());
        args.extend_from_slice(extra);
        let out = support::run_ok(Command::new(support::example_exe("bifurcation")).args(&args));
        let text = String::from_utf8(out.stdout).unwrap();
        assert!(dir.join("fig8a.png").is_file());
        (read(&dir), text)
    };
    let (dry, _) = run(&[], "dry");
    let (rub, text) = run(&["--friction", "0.3", "--shaft-radius", "0.05"], "rub");
    assert!(text.contains("friction 0.3, shaft radius 0.05"), "{text}");
    assert_eq!(dry.len(), 40);
    assert_eq!(rub.len(), 40);
    let below = |pts: &[(f64, f64)]| {
        pts.iter()
            .filter(|p| p.0 == 0.5)
            .map(|p| p.1)
            .collect::<Vec<_>>()
    };
    for (a, b) in below(&dry).iter().zip(below(&rub)) {
        assert!((a - b).abs() <= 1e-12, "{a} and {b}");
        assert!(*a < 1.0, "the free orbit stays inside the gap: {a}");
    }
    let rubbing = |pts: &[(f64, f64)]| {
        pts.iter()
            .filter(|p| p.0 == 2.5)
            .map(|p| p.1)
            .collect::<Vec<_>>()
    };
    let gap = rubbing(&dry)
        .iter()
        .zip(rubbing(&rub))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f64, f64::max);
    assert!(gap > 1e-3, "friction must change the rubbing orbit: {gap}");
    for bad in [
        &["--friction", "0.3"][..],
        &[
            "--friction",
            "0.3",
            "--shaft-radius",
            "1",
            "--locate-from",
            "2",
            "--locate-to",
            "2.2",
        ],
    ] {
        let mut args = vec!["--diagram", "a", "--steps", "2"];
        args.extend_from_slice(bad);
        let out = Command::new(support::example_exe("bifurcation"))
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8(out.stderr).unwrap();
        assert_eq!(out.status.code(), Some(2), "{bad:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{bad:?}: {err}");
    }
    let _ = std::fs::remove_dir_all(&base);
}
