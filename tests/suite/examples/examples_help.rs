//! `--help` of every example (listed from the `examples/` folder, so that a new example cannot
//! be forgotten) and of each of its subcommands: exit status 0, nothing written, no `NaN`, every
//! flag the example's own documentation mentions is in it, and every advertised range
//! `[range: lo..=hi]` is the one the parser enforces.

use crate::support;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The examples: `examples/NAME.rs` and `examples/NAME/main.rs`, with their source text (the
/// header documentation of the main file).
fn examples() -> Vec<(String, String)> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples");
    let mut list = Vec::new();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let (name, main) = if path.is_dir() {
            let main = path.join("main.rs");
            if !main.exists() {
                continue; // examples/common: shared code
            }
            (
                path.file_name().unwrap().to_string_lossy().into_owned(),
                main,
            )
        } else if path.extension().is_some_and(|e| e == "rs") {
            (
                path.file_stem().unwrap().to_string_lossy().into_owned(),
                path,
            )
        } else {
            continue;
        };
        list.push((name, std::fs::read_to_string(main).unwrap()));
    }
    list.sort();
    assert!(list.len() >= 14, "examples found: {list:?}");
    list
}

/// A fresh empty working directory.
fn empty_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("jeffcott-help-{}-{tag}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run(exe: &Path, dir: &Path, args: &[&str]) -> Output {
    Command::new(exe)
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run the example")
}

/// The subcommands listed by a help text (section `Commands:`), without `help`.
fn subcommands(help: &str) -> Vec<String> {
    help.lines()
        .skip_while(|l| !l.starts_with("Commands:"))
        .skip(1)
        .take_while(|l| l.starts_with("  "))
        .filter_map(|l| l.split_whitespace().next())
        .filter(|c| *c != "help")
        .map(str::to_string)
        .collect()
}

/// `(flag, range)` for each option of a help text with `[range: lo..=hi]` in its description.
fn ranges(help: &str) -> Vec<(String, String, String)> {
    let mut out = Vec::new();
    let mut flag: Option<String> = None;
    let mut text = String::new();
    let mut flush = |flag: &Option<String>, text: &str| {
        if let (Some(f), Some(i)) = (flag, text.find("[range: ")) {
            let r = &text[i + 8..];
            let r = &r[..r.find([']', ';']).unwrap()];
            let (lo, hi) = r.split_once("..").unwrap();
            out.push((
                f.clone(),
                lo.to_string(),
                hi.trim_start_matches('=').to_string(),
            ));
        }
    };
    for line in help.lines() {
        let t = line.trim_start();
        if t.starts_with("--") || t.starts_with("-h,") {
            flush(&flag, &text);
            flag = t.split_whitespace().next().map(str::to_string);
            text.clear();
        }
        text.push_str(line);
        text.push(' ');
    }
    flush(&flag, &text);
    out
}

/// A value just outside `bound` (above `hi` or below `lo`), written as the user would.
fn outside(bound: &str, above: bool) -> Option<String> {
    if let Ok(n) = bound.parse::<usize>() {
        return if above {
            n.checked_add(1).map(|n| n.to_string())
        } else {
            n.checked_sub(1).map(|n| n.to_string())
        };
    }
    let x: f64 = bound
        .parse()
        .unwrap_or_else(|_| panic!("range bound {bound}"));
    let d = x.abs().max(1e-300) * 1e-6;
    Some(format!("{:e}", if above { x + d } else { x - d }))
}

/// Checks one help page (of an example or one of its subcommands) and returns its text.
fn check_help(name: &str, exe: &Path, prefix: &[&str]) -> String {
    let dir = empty_dir(name);
    let mut args = prefix.to_vec();
    args.push("--help");
    let out = run(exe, &dir, &args);
    let help = String::from_utf8(out.stdout).unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(0), "{name} {args:?}: {err}");
    assert!(err.is_empty(), "{name} {args:?}: {err}");
    assert!(help.contains("Usage:"), "{name} {args:?}: {help}");
    assert!(!help.contains("NaN"), "{name} {args:?}: {help}");
    assert!(
        !help.contains("0.0000"),
        "{name} {args:?}: unreadable number in {help}"
    );
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "{name} {args:?} wrote into its working directory"
    );
    // The ranges are the parser's: each bound accepted, a value just outside it refused with
    // status 2 and a message naming the flag (the parser stops before `--help` is reached).
    for (flag, lo, hi) in ranges(&help) {
        for (bound, above) in [(&lo, false), (&hi, true)] {
            if bound.is_empty() {
                continue; // open range `lo..`
            }
            let mut ok = prefix.to_vec();
            ok.extend([flag.as_str(), bound.as_str(), "--help"]);
            let out = run(exe, &dir, &ok);
            assert_eq!(out.status.code(), Some(0), "{name} {ok:?}");
            let Some(v) = outside(bound, above) else {
                continue;
            };
            let mut bad = prefix.to_vec();
            bad.extend([flag.as_str(), v.as_str(), "--help"]);
            let out = run(exe, &dir, &bad);
            let err = String::from_utf8_lossy(&out.stderr);
            assert_eq!(out.status.code(), Some(2), "{name} {bad:?}: {err}");
            assert!(err.contains(&flag), "{name} {bad:?}: {err}");
            assert_eq!(err.lines().count(), 1, "{name} {bad:?}: {err}");
        }
    }
    assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "{name}");
    let _ = std::fs::remove_dir_all(&dir);
    help
}

/// Flags the example's header documentation (`//!`) mentions, without cargo's own.
fn documented_flags(source: &str) -> Vec<String> {
    const CARGO: [&str; 5] = ["--example", "--release", "--features", "--help", "--bin"];
    let mut flags: Vec<String> = Vec::new();
    for line in source.lines().filter(|l| l.starts_with("//!")) {
        let mut rest = line;
        while let Some(i) = rest.find("--") {
            rest = &rest[i + 2..];
            let word: String = rest
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '-')
                .collect();
            if word.starts_with(|c: char| c.is_ascii_lowercase()) {
                let flag = format!("--{word}");
                if !CARGO.contains(&flag.as_str()) && !flags.contains(&flag) {
                    flags.push(flag);
                }
            }
        }
    }
    flags
}

#[test]
fn help_of_every_example_is_safe_and_truthful() {
    for (name, source) in examples() {
        let exe = support::example_exe(&name);
        let top = check_help(&name, &exe, &[]);
        let mut all = top.clone();
        for sub in subcommands(&top) {
            all.push_str(&check_help(&name, &exe, &[sub.as_str()]));
        }
        for flag in documented_flags(&source) {
            assert!(
                all.contains(&format!("{flag} ")) || all.contains(&format!("{flag}\n")),
                "{name}: its documentation mentions {flag}, its help does not"
            );
        }
    }
}

#[test]
fn a_positional_output_folder_never_takes_a_flag() {
    for name in ["fig6_regions", "fig7_restoring_force"] {
        let exe = support::example_exe(name);
        let dir = empty_dir(name);
        for args in [&["--help"][..], &["-h"], &["out", "--help"]] {
            let out = run(&exe, &dir, args);
            let written: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
            assert!(written.is_empty(), "{name} {args:?} wrote {written:?}");
            assert_eq!(out.status.code(), Some(0), "{name} {args:?}");
        }
        let out = run(&exe, &dir, &["--bogus"]);
        assert_eq!(out.status.code(), Some(2), "{name}");
        assert!(!dir.join("--help").exists() && !dir.join("-h").exists());
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 0, "{name}");
        let _ = std::fs::remove_dir_all(&dir);
    }
}
