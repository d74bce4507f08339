//! Command-line helpers for the examples, which parse their flags with clap (derive): value
//! parsers for finite numbers and ranges, the numbers shown in the help, and the error exit for
//! checks that involve several flags.
//!
//! A range check is written `value_parser = f64_in(lo, hi)` and its help text says
//! `[range: lo..=hi]`; an out-of-range value is a clap error (status 2) naming the flag.

use std::fmt::Display;

/// A finite real number (no NaN, no infinity).
pub fn finite(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err("expected a finite number".to_string()),
    }
}

/// A value parser: a finite real number in `lo..=hi`.
pub fn f64_in(lo: f64, hi: f64) -> impl Fn(&str) -> Result<f64, String> + Clone + Send + Sync {
    move |s| {
        let x = finite(s)?;
        if (lo..=hi).contains(&x) {
            Ok(x)
        } else {
            Err(format!("not in {}..={}", num(lo), num(hi)))
        }
    }
}

/// A value parser: a whole number in `lo..=hi`.
pub fn usize_in(
    lo: usize,
    hi: usize,
) -> impl Fn(&str) -> Result<usize, String> + Clone + Send + Sync {
    move |s| {
        let x: usize = s
            .trim()
            .parse()
            .map_err(|_| "expected a whole number >= 0".to_string())?;
        if (lo..=hi).contains(&x) {
            Ok(x)
        } else {
            Err(format!("not in {lo}..={hi}"))
        }
    }
}

/// A number as the help shows it: the shorter of the plain and the scientific notation
/// (`1e-10`, not `0.0000000001`).
pub fn num(x: f64) -> String {
    let plain = x.to_string();
    let sci = format!("{x:e}");
    if sci.len() < plain.len() {
        sci
    } else {
        plain
    }
}

/// Prints `error: {msg}` on stderr and exits with status 2 (a bad command line that clap alone
/// cannot see, such as two flags that contradict each other).
pub fn fail(msg: impl Display) -> ! {
    eprintln!("error: {msg}");
    std::process::exit(2)
}

/// Parses the process's arguments into `T`. `--help` prints the help and exits with status 0
/// (writing nothing else); a bad command line prints clap's message as one `error: ...` line
/// on stderr (naming the flag) and exits with status 2. Negative numbers are values, not flags
/// (`--x0 -0.5`).
pub fn parse<T: clap::Parser>() -> T {
    let cmd = negative_numbers(T::command());
    cmd.try_get_matches()
        .and_then(|mut m| T::from_arg_matches_mut(&mut m))
        .unwrap_or_else(|e| {
            if !e.use_stderr() {
                e.exit(); // --help: status 0
            }
            let text = e.render().to_string();
            let lines: Vec<&str> = text
                .lines()
                .map(str::trim)
                .filter(|l| {
                    !l.is_empty()
                        && !l.starts_with("Usage:")
                        && !l.starts_with("For more information")
                })
                .collect();
            eprintln!("{}", lines.join(" "));
            std::process::exit(2)
        })
}

/// `cmd` and its subcommands with negative numbers taken as values.
fn negative_numbers(cmd: clap::Command) -> clap::Command {
    let names: Vec<String> = cmd
        .get_subcommands()
        .map(|s| s.get_name().to_string())
        .collect();
    let mut cmd = cmd.allow_negative_numbers(true);
    for n in names {
        cmd = cmd.mut_subcommand(n, negative_numbers);
    }
    cmd
}
