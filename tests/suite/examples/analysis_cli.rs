//! The examples' command line (clap, through `examples/common/cli.rs`): the exit status and the
//! one-line message of a real example on bad input.

use crate::support as examples;

/// Runs the built `common_demo` example (built by the test if needed; a build failure fails
/// the test): every bad command line exits with status 2 and one `error: ...` line naming the
/// offending flag, before anything is computed or written.
#[test]
fn example_exits_with_status_2_on_bad_input() {
    let demo = examples::example_exe("common_demo");
    let dir = std::env::temp_dir().join(format!("jeffcott-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (args, names) in [
        (vec!["--r-min", "abc"], "--r-min"),
        (vec!["--r-min", "NaN"], "--r-min"),
        (vec!["--r-min", "inf"], "--r-min"),
        (vec!["--r-min", "5"], "--r-min"),
        (vec!["--values", "1"], "--values"),
        (vec!["--values", "1.5"], "--values"),
        (vec!["--values"], "--values"),
        (vec!["--mode", "fast"], "--mode"),
        (vec!["--bogus", "1"], "--bogus"),
        (vec!["stray"], "stray"),
        (vec!["--r-min", "3.5", "--r-max", "3.0"], "--r-min"),
    ] {
        let out = std::process::Command::new(&demo)
            .args(&args)
            .current_dir(&dir)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
        assert!(err.starts_with("error: "), "{args:?}: {err}");
        assert!(err.contains(names), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(out.stdout.is_empty(), "{args:?}");
    }
    // An out-of-range value names the range.
    let out = std::process::Command::new(&demo)
        .args(["--r-min", "5"])
        .output()
        .unwrap();
    assert!(String::from_utf8_lossy(&out.stderr).contains("0..=4"));
    assert_eq!(
        std::fs::read_dir(&dir).unwrap().count(),
        0,
        "a bad command line wrote something"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
