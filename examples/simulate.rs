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
//! With `--friction MU` (> 0) Coulomb friction acts between the ring and a shaft of radius
//! `--shaft-radius A` (in gaps; required then) spinning counter-clockwise
//! (`paper::rub::rubbing_model`, docs/friction.md): `regime` is then 6, 7 or 8 while the shaft
//! slips forward, slips backward or rolls on the ring, 1 in free flight. Without it (or with
//! `--friction 0`) the run is the paper's model, as before.
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
//! cargo run --release --example simulate -- --preset fig8a --eta 2.5 --friction 0.3 --shaft-radius 0.05 --periods 20
//! ```

#[path = "common/mod.rs"]
mod common;

use std::io::{self, BufWriter, Write};

use clap::Parser;
use common::cli::{fail, finite, parse, usize_in};
use common::csv::write_f64;
use common::scene::{Scene, SceneFlags};
use jeffcott::hybrid::{simulate, OutputPlan, SimError, StrobePoint, Trajectory};
use jeffcott::nalgebra::{allocator::Allocator, DVector, DefaultAllocator, Dim};
use jeffcott::paper::rub::rubbing_model;
use jeffcott::JeffcottModel;

/// The CSV rows of `strobe` (row `k` counted from `transient`).
fn rows<D: Dim>(strobe: &[StrobePoint<D>], transient: u64) -> String
where
    DefaultAllocator: Allocator<D>,
{
    let mut text = Vec::new();
    write_rows(&mut text, strobe, transient).expect("writing to memory");
    String::from_utf8(text).expect("ASCII")
}

fn write_rows<D: Dim>(
    out: &mut impl Write,
    strobe: &[StrobePoint<D>],
    transient: u64,
) -> io::Result<()>
where
    DefaultAllocator: Allocator<D>,
{
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
    /// Coulomb friction coefficient between ring and shaft (>= 0; 0: the paper's frictionless model)
    #[arg(long, value_name = "NUMBER", value_parser = finite, default_value = "0")]
    friction: f64,
    /// Shaft radius at the ring, in gaps (> 0; required with --friction > 0)
    #[arg(long, value_name = "NUMBER", value_parser = finite)]
    shaft_radius: Option<f64>,
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
    let (t, n) = (transient as u64, periods as u64);
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let header = "k,tau,x,y,vx,vy,xs,ys,regime";
    let (strobe, failure) = if flags.friction == 0.0 {
        let model = JeffcottModel::new(params).unwrap_or_else(|e| fail(e));
        let state = model
            .state_at([x0, y0], [vx0, vy0])
            .unwrap_or_else(|e| fail(format!("initial state: {e}")));
        match model.strobe_range(&state, t, t.saturating_add(n), &opts) {
            Ok((traj, _)) => (rows(&traj.strobe, t), None),
            Err(f) => (rows(&f.partial.strobe, t), Some(f.error.to_string())),
        }
    } else {
        let radius = flags.shaft_radius.unwrap_or_else(|| {
            fail("--friction needs --shaft-radius (the shaft's radius at the ring, in gaps)")
        });
        let model = rubbing_model(&params, flags.friction, radius).unwrap_or_else(|e| fail(e));
        // The ring's slots at the centre: the model places the ring where the rotor starts
        // (the onset rule's location if it starts beyond the gap).
        let y = DVector::from_vec(vec![x0, y0, vx0, vy0, 0.0, 0.0]);
        let plan = OutputPlan::strobe(std::f64::consts::TAU / params.eta, t, t.saturating_add(n));
        let mut traj = Trajectory::default();
        let result: Result<_, SimError<_>> = simulate(&model, 0.0, &y, &plan, &opts, &mut traj);
        (rows(&traj.strobe, t), result.err().map(|e| e.to_string()))
    };
    let written = writeln!(out, "{header}")
        .and_then(|_| out.write_all(strobe.as_bytes()))
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
