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
