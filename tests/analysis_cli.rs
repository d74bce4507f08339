//! The examples' flag parser (`examples/common/cli.rs`), tested through its `try_` methods, and
//! the exit status of a real example on bad input.

#[allow(dead_code)]
#[path = "../examples/common/cli.rs"]
mod cli;

#[path = "support/examples.rs"]
mod examples;

use cli::{Cli, Finish};

fn cli(args: &[&str]) -> Cli {
    Cli::from_args("demo", "A demo.", args.iter().copied())
}

#[test]
fn typed_values_and_defaults() {
    let mut c = cli(&["--eta", "2.5", "--n=7", "--mode", "reset", "--out", "dir/x"]);
    assert_eq!(c.try_f64_in("eta", 2.0, 0.0, 10.0, "frequency"), Ok(2.5));
    assert_eq!(c.try_usize("n", 3, "count"), Ok(7));
    assert_eq!(
        c.try_choice("mode", "carry", &["carry", "reset"], "mode"),
        Ok("reset".into())
    );
    assert_eq!(c.try_string("out", "o", "folder"), Ok("dir/x".into()));
    assert_eq!(c.try_f64("beta", 0.119, "forcing"), Ok(0.119));
    assert_eq!(c.try_opt_usize_in("threads", 1, 64, "threads"), Ok(None));
    assert_eq!(c.try_f64("neg", -1.0, "negative default"), Ok(-1.0));
    assert_eq!(c.try_finish(), Ok(Finish::Run));
    let mut c = cli(&["--x", "-0.5", "--threads", "2"]);
    assert_eq!(c.try_f64("x", 0.0, ""), Ok(-0.5));
    assert_eq!(c.try_opt_usize_in("threads", 1, 64, ""), Ok(Some(2)));
    assert_eq!(c.try_finish(), Ok(Finish::Run));
}

#[test]
fn bad_input_gives_one_clear_message() {
    let e = cli(&["--eta", "abc"]).try_f64("eta", 1.0, "").unwrap_err();
    assert_eq!(e, "--eta expects a finite number, got \"abc\"");
    for bad in ["NaN", "inf", "-inf", "1e999", ""] {
        let e = cli(&["--eta", bad]).try_f64("eta", 1.0, "").unwrap_err();
        assert!(e.starts_with("--eta expects a finite number"), "{bad}: {e}");
    }
    let e = cli(&["--eta", "12"])
        .try_f64_in("eta", 1.0, 0.0, 10.0, "")
        .unwrap_err();
    assert_eq!(e, "--eta must be in [0, 10], got 12");
    let e = cli(&["--n", "1.5"]).try_usize("n", 1, "").unwrap_err();
    assert_eq!(e, "--n expects a whole number >= 0, got \"1.5\"");
    let e = cli(&["--n", "-3"]).try_usize("n", 1, "").unwrap_err();
    assert!(e.contains("whole number"), "{e}");
    let e = cli(&["--n", "0"])
        .try_usize_in("n", 1, 1, 9, "")
        .unwrap_err();
    assert_eq!(e, "--n must be between 1 and 9, got 0");
    let e = cli(&["--mode", "fast"])
        .try_choice("mode", "a", &["a", "b"], "")
        .unwrap_err();
    assert_eq!(e, "--mode expects one of a, b, got \"fast\"");
    let e = cli(&["--out", ""]).try_string("out", "o", "").unwrap_err();
    assert!(e.contains("non-empty"), "{e}");
}

#[test]
fn structural_errors() {
    // Missing value at the end, and before another flag.
    let mut c = cli(&["--eta"]);
    assert_eq!(
        c.try_f64("eta", 1.0, ""),
        Err("--eta expects a value".to_string())
    );
    let mut c = cli(&["--eta", "--n", "3"]);
    assert_eq!(
        c.try_usize("n", 1, ""),
        Err("--eta expects a value".to_string())
    );
    // Unknown flag, reported at the end with the known ones.
    let mut c = cli(&["--etaa", "3"]);
    c.try_f64("eta", 1.0, "").unwrap();
    let e = c.try_finish().unwrap_err();
    assert_eq!(e, "unknown flag --etaa (known: --eta; see --help)");
    // A stray word and a repeated flag.
    let e = cli(&["3.0"]).try_finish().unwrap_err();
    assert!(e.starts_with("unexpected argument \"3.0\""), "{e}");
    let e = cli(&["--eta", "1", "--eta", "2"]).try_finish().unwrap_err();
    assert_eq!(e, "--eta is given twice");
}

#[test]
fn help_lists_every_flag_and_skips_validation() {
    let mut c = cli(&["--eta", "abc", "--help"]);
    assert_eq!(
        c.try_f64_in("eta", 2.0, 0.0, 10.0, "forcing frequency"),
        Ok(2.0)
    );
    assert_eq!(
        c.try_choice(
            "mode",
            "carry",
            &["carry", "reset"],
            "how values are linked"
        ),
        Ok("carry".into())
    );
    match c.try_finish() {
        Ok(Finish::Help(text)) => {
            assert!(text.starts_with("A demo."), "{text}");
            assert!(text.contains("--eta <number>"), "{text}");
            assert!(
                text.contains("forcing frequency (range [0, 10]) [default: 2]"),
                "{text}"
            );
            assert!(text.contains("one of: carry, reset"), "{text}");
            assert!(text.contains("--help"), "{text}");
        }
        other => panic!("expected help, got {other:?}"),
    }
    assert!(matches!(cli(&["-h"]).try_finish(), Ok(Finish::Help(_))));
}

/// Runs the built `common_demo` example (built by the test if needed; a build failure fails
/// the test).
#[test]
fn example_exits_with_status_2_on_bad_input() {
    let demo = examples::example_exe("common_demo");
    for args in [
        vec!["--r-min", "abc"],
        vec!["--r-min", "NaN"],
        vec!["--r-min", "5"],
        vec!["--values"],
        vec!["--mode", "fast"],
        vec!["--bogus", "1"],
        vec!["--r-min", "3.5", "--r-max", "3.0"],
    ] {
        let out = std::process::Command::new(&demo)
            .args(&args)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(
            err.starts_with("error: --") || err.starts_with("error: unknown flag"),
            "{err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
    let out = std::process::Command::new(&demo)
        .arg("--help")
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(0));
    assert!(String::from_utf8_lossy(&out.stdout).contains("--r-min"));
}
