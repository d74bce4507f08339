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
pub mod layout;
pub mod plot;
pub mod ranks;

use std::fmt::Display;

/// The `--rtol` and `--atol` flags of the simulation examples, with the crate's defaults (one
/// declaration for every example: `#[command(flatten)]`).
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct Tolerances {
    /// Relative tolerance of the integrator [range: 0..=0.01]
    #[arg(long, value_name = "NUMBER", value_parser = cli::f64_in(0.0, 1e-2),
          default_value = cli::num(jeffcott::hybrid::SimOptions::default().rtol))]
    pub rtol: f64,
    /// Absolute tolerance of the integrator [range: 0..=0.01; not 0 with --rtol 0]
    #[arg(long, value_name = "NUMBER", value_parser = cli::f64_in(0.0, 1e-2),
          default_value = cli::num(jeffcott::hybrid::SimOptions::default().atol))]
    pub atol: f64,
}

impl Tolerances {
    /// `(rtol, atol)`, or exits with status 2 if both are 0.
    pub fn get(&self) -> (f64, f64) {
        if self.rtol + self.atol <= 0.0 {
            cli::fail("--rtol and --atol cannot both be 0");
        }
        (self.rtol, self.atol)
    }
}

/// The `--threads`, `--max-new-points` and `--shard` flags of the resumable sweeps.
#[derive(clap::Args, Debug, Clone, Copy)]
pub struct SweepRunFlags {
    /// Run only shard I of N (0 <= I < N: the points I, I + N, I + 2N, ...) into its own file
    /// of the folder, e.g. one task of a job array (--shard $SLURM_ARRAY_TASK_ID/8); nothing
    /// is drawn. When every shard has finished, the same command without --shard reads all
    /// points and draws
    #[arg(long, value_name = "I/N", value_parser = shard)]
    pub shard: Option<jeffcott::global::Shard>,
    /// Worker threads per process, unset = all cores [range: 1..=1024]
    #[arg(long, value_name = "COUNT", value_parser = cli::usize_in(1, 1024))]
    pub threads: Option<usize>,
    /// Run at most this many new points, then stop (a later run resumes); unset = all
    /// [range: 1..]
    #[arg(long, value_name = "COUNT", value_parser = cli::usize_in(1, usize::MAX))]
    pub max_new_points: Option<usize>,
}

impl SweepRunFlags {
    /// The run configuration these flags describe.
    pub fn config(&self) -> jeffcott::global::RunOptions {
        let mut run = jeffcott::global::RunOptions::default();
        if let Some(t) = self.threads {
            run = run.with_threads(t);
        }
        if let Some(m) = self.max_new_points {
            run = run.with_max_new_points(m);
        }
        if let Some(s) = self.shard {
            run = run.with_shard(s);
        }
        run
    }
}

/// A value parser: a shard `I/N` ([`jeffcott::global::Shard`]).
fn shard(s: &str) -> Result<jeffcott::global::Shard, String> {
    s.parse()
        .map_err(|e: jeffcott::global::StoreError| e.to_string())
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
