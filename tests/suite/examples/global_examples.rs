//! The `basins` and `param_map` examples: they run on small grids and write their files, and
//! a `basins` run killed part-way (SIGKILL) and started again with the same folder finishes
//! with exactly the files of an uninterrupted run.

use crate::support;

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

fn out_dir(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let target = exe.parent().and_then(|d| d.parent()).unwrap().to_path_buf();
    let dir = target.join("global_examples_test").join(name);
    let _ = fs::remove_dir_all(&dir);
    dir
}

fn lines(path: &Path) -> usize {
    fs::read_to_string(path).map_or(0, |t| t.lines().count())
}

/// The record lines of a folder, sorted by text (the index comes first in each line).
fn sorted_records(dir: &Path) -> Vec<String> {
    let mut all: Vec<String> = fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "jsonl"))
        .flat_map(|p| {
            fs::read_to_string(p)
                .unwrap()
                .lines()
                .map(str::to_string)
                .collect::<Vec<_>>()
        })
        .collect();
    all.sort();
    all
}

const SMALL: [&str; 10] = [
    "--scene",
    "fig8b",
    "--n",
    "16",
    "--nv",
    "10",
    "--transient",
    "300",
    "--max-transient",
    "300",
];

#[test]
fn basins_killed_and_restarted_equals_an_uninterrupted_run() {
    let exe = support::example_exe("basins");
    let scene = "fig8b-eta2.2";
    let whole = out_dir("whole");
    let run = support::run_ok(
        Command::new(&exe)
            .args(SMALL)
            .args(["--threads", "2", "--out"])
            .arg(&whole),
    );
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert!(
        stdout.contains("attractor(s) on 16 x 10 points"),
        "{stdout}"
    );
    for f in [
        "manifest.json",
        "records-0.jsonl",
        "basins.png",
        "basins.csv",
        "attractors.csv",
    ] {
        assert!(whole.join(scene).join(f).exists(), "{f}");
    }
    assert_eq!(lines(&whole.join(scene).join("records-0.jsonl")), 160);

    // Killed after a few points (one thread, so that it is slow enough to catch), up to
    // three tries in case a run finishes before the kill lands.
    let parts = out_dir("parts");
    let records = parts.join(scene).join("records-0.jsonl");
    let mut killed_at = None;
    for _ in 0..3 {
        let _ = fs::remove_dir_all(&parts);
        let mut child = Command::new(&exe)
            .args(SMALL)
            .args(["--threads", "1", "--out"])
            .arg(&parts)
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        let t0 = Instant::now();
        while lines(&records) < 5 && t0.elapsed() < Duration::from_secs(60) {
            std::thread::sleep(Duration::from_millis(2));
        }
        child.kill().unwrap();
        child.wait().unwrap();
        let n = lines(&records);
        if (5..160).contains(&n) {
            killed_at = Some(n);
            break;
        }
    }
    let killed_at = killed_at.expect("the run was never caught part-way");
    assert!(!parts.join(scene).join("basins.png").exists());
    let rerun = support::run_ok(
        Command::new(&exe)
            .args(SMALL)
            .args(["--threads", "2", "--out"])
            .arg(&parts),
    );
    let err = String::from_utf8_lossy(&rerun.stderr);
    assert!(
        err.contains(&format!(
            "{} points computed, {killed_at} reused",
            160 - killed_at
        )),
        "{err}"
    );
    for f in ["basins.csv", "attractors.csv"] {
        assert_eq!(
            fs::read_to_string(parts.join(scene).join(f)).unwrap(),
            fs::read_to_string(whole.join(scene).join(f)).unwrap(),
            "{f}"
        );
    }
    assert_eq!(
        sorted_records(&parts.join(scene)),
        sorted_records(&whole.join(scene))
    );
}

#[test]
fn param_map_writes_both_maps() {
    let exe = support::example_exe("param_map");
    let out = out_dir("param_map");
    support::run_ok(
        Command::new(&exe)
            .args([
                "--n-eta",
                "3",
                "--n-y",
                "2",
                "--transient",
                "100",
                "--record",
                "32",
            ])
            .args(["--max-transient", "100", "--out"])
            .arg(&out),
    );
    for map in ["preload", "ecc"] {
        for f in [
            "period.png",
            "period.csv",
            "contacts.png",
            "contact_time.csv",
            "records-0.jsonl",
        ] {
            assert!(out.join(map).join(f).exists(), "{map}/{f}");
        }
        // 3 x 2 cells, plus the header.
        assert_eq!(lines(&out.join(map).join("period.csv")), 7);
    }
}

#[test]
fn bad_flags_exit_with_status_2() {
    let exe = support::example_exe("basins");
    for args in [
        vec!["--eta", "2.3"],
        vec!["--scene", "fig9"],
        vec!["--scene", "fig8a", "--h-min", "1", "--h-max", "0"],
        vec![
            "--scene",
            "fig8a",
            "--transient",
            "900",
            "--max-transient",
            "100",
        ],
    ] {
        let out = Command::new(&exe).args(&args).output().unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).starts_with("error: --")
                || String::from_utf8_lossy(&out.stderr).starts_with("error: ")
        );
    }
}
