//! Infrastructure shared by the examples: command-line flags, CSV output, figures.
//!
//! Each example includes this folder with
//!
//! ```ignore
//! #[path = "common/mod.rs"]
//! mod common;
//! ```
//!
//! Not every example uses every helper, hence the `dead_code` allowance.
#![allow(dead_code)]

pub mod cli;
pub mod csv;
pub mod plot;
pub mod ranks;

use std::fmt::Display;

/// The `--rtol` and `--atol` flags of the simulation examples, with the crate's defaults.
pub fn tolerance_flags(cli: &mut cli::Cli) -> (f64, f64) {
    let d = jeffcott::hybrid::SimOptions::default();
    let rtol = cli.f64_in("rtol", d.rtol, 1e-15, 1e-2, "relative tolerance");
    let atol = cli.f64_in("atol", d.atol, 1e-18, 1e-2, "absolute tolerance");
    (rtol, atol)
}

/// The `--threads` and `--max-new-points` flags of the resumable sweeps, as their run
/// configuration.
pub fn sweep_run_flags(cli: &mut cli::Cli) -> jeffcott::global::RunConfig {
    let threads = cli.opt_usize_in(
        "threads",
        1,
        1024,
        "worker threads per process, unset = all cores",
    );
    let max_new = cli.opt_usize_in(
        "max-new-points",
        1,
        usize::MAX,
        "run at most this many new points, then stop (a later run resumes)",
    );
    let mut run = jeffcott::global::RunConfig::default();
    if let Some(t) = threads {
        run = run.with_threads(t);
    }
    if let Some(m) = max_new {
        run = run.with_max_new_points(m);
    }
    run
}

/// Unwraps `r`, or prints `error: {e}` on stderr and exits with status 1 (a failure while
/// running, as opposed to a bad command line, which exits with status 2).
pub fn or_exit<T, E: Display>(r: Result<T, E>) -> T {
    r.unwrap_or_else(|e| {
        eprintln!("error: {e}");
        std::process::exit(1)
    })
}
pub mod scene;
