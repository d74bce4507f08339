//! One simulation, printed as stroboscopic states in CSV on standard output.
//!
//! ```text
//! k,tau,x,y,vx,vy,xs,ys,regime
//! ```
//!
//! Row `k` (for `k = 0..=N`, `N = --periods`) is the state at the absolute time
//! `tau = 2π (T + k) / η`, `T = --transient`: the first `T` forcing periods run unprinted, `k`
//! counts from there, and `tau` is still measured from the start of the run. Without
//! `--transient`, row 0 is the initial state at `tau = 0`. There are always `N + 1` rows.
//! `regime` is 1..5 for the paper's regimes I..V (I: no contact). Numbers are printed in Rust's
//! shortest round-trip form (they read back to the same `f64`).
//!
//! The parameters come from `--preset` (default `fig8a`); every other flag overrides the
//! preset's value. The initial rotor state is `--x0 --y0 --vx0 --vy0` (default at rest at the
//! origin); the ring starts at its centre, or at its minimum-energy position if the rotor starts
//! in contact (|r| > 1).
//!
//! Exit status: 0 on success; 2 with one `error: ...` line on standard error for bad input
//! (unknown flag or preset or method, missing value, not a number, NaN, out of range, invalid
//! parameters); 1 with one line on standard error if the simulation fails, after the rows
//! computed before the failure have been printed.
//!
//! ```text
//! cargo run --release --example simulate -- --preset fig8b --eta 3 --transient 300 --periods 4
//! ```

#[path = "common/mod.rs"]
mod common;

use std::io::{self, BufWriter, Write};

use clap::Parser;
use common::cli::{fail, parse, usize_in};
use common::csv::write_f64;
use common::scene::{Scene, SceneFlags};
use jeffcott::hybrid::StrobePoint;
use jeffcott::nalgebra::U6;
use jeffcott::JeffcottModel;

fn write_rows(out: &mut impl Write, strobe: &[StrobePoint<U6>], transient: u64) -> io::Result<()> {
    for p in strobe {
        write!(out, "{},", p.k - transient)?;
        write_f64(out, p.t)?;
        for v in p.y.iter() {
            out.write_all(b",")?;
            write_f64(out, *v)?;
        }
        writeln!(out, ",{}", p.label)?;
    }
    Ok(())
}

/// One simulation of the Jeffcott rotor with a preloaded snubber ring: stroboscopic states
/// k,tau,x,y,vx,vy,xs,ys,regime as CSV on stdout, rows k = 0..=N at tau = 2 pi (T + k) / eta.
#[derive(Parser)]
#[command(name = "simulate")]
struct Flags {
    #[command(flatten)]
    scene: SceneFlags,
    /// Printed periods N [range: 0..=1000000000]
    #[arg(long, value_name = "COUNT", default_value = "10", value_parser = usize_in(0, 1_000_000_000))]
    periods: usize,
    /// Periods T run before the first printed row [range: 0..=1000000000]
    #[arg(long, value_name = "COUNT", default_value = "0", value_parser = usize_in(0, 1_000_000_000))]
    transient: usize,
}

fn main() {
    let flags: Flags = parse();
    let (periods, transient) = (flags.periods, flags.transient);
    let scene = flags.scene.scene();
    let Scene {
        params,
        opts,
        start: [x0, y0, vx0, vy0],
    } = scene;
    let model = JeffcottModel::new(params).unwrap_or_else(|e| fail(e));
    let state = model
        .state_at([x0, y0], [vx0, vy0])
        .unwrap_or_else(|e| fail(format!("initial state: {e}")));
    let (t, n) = (transient as u64, periods as u64);
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let header = "k,tau,x,y,vx,vy,xs,ys,regime";
    let result = model.strobe_range(&state, t, t.saturating_add(n), &opts);
    let (strobe, failure) = match result {
        Ok((traj, _)) => (traj.strobe, None),
        Err(f) => (f.partial.strobe, Some(f.error)),
    };
    let written = writeln!(out, "{header}")
        .and_then(|_| write_rows(&mut out, &strobe, t))
        .and_then(|_| out.flush());
    if let Err(e) = written {
        // A closed pipe (e.g. `| head`) is not an error of the simulation.
        if e.kind() != io::ErrorKind::BrokenPipe {
            eprintln!("error: writing the output: {e}");
            std::process::exit(1);
        }
    }
    if let Some(e) = failure {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}
