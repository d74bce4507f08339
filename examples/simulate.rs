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

use common::cli::{fail, Cli};
use common::csv::write_f64;
use jeffcott::hybrid::{SimOptions, StrobePoint};
use jeffcott::nalgebra::U6;
use jeffcott::ode::Method;
use jeffcott::params::{Params, Preset};
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

fn main() {
    let mut cli = Cli::new(
        "One simulation of the Jeffcott rotor with a preloaded snubber ring: stroboscopic states\n\
         k,tau,x,y,vx,vy,xs,ys,regime as CSV on stdout, rows k = 0..=N at tau = 2 pi (T + k) / eta.",
    );
    let preset_name = cli.string(
        "preset",
        "fig8a",
        &format!("parameter preset ({})", Preset::NAMES.join(", ")),
    );
    // Without --help an unknown preset stops here; with --help the defaults shown are fig8a's.
    let preset: Preset = preset_name
        .parse()
        .unwrap_or_else(|e| fail(format!("--preset: {e}")));
    let p = preset.params();
    let eta = cli.f64("eta", p.eta, "frequency ratio eta = Omega/omega_n (> 0)");
    let nu1 = cli.f64("nu1", p.nu1, "rotor damping ratio (>= 0)");
    let nu2 = cli.f64("nu2", p.nu2, "ring damping ratio (>= 0)");
    let k = cli.f64("k", p.kx, "ring stiffness ratio K = Kx = Ky (>= 0)");
    let beta = cli.f64("beta", p.beta, "out-of-balance beta (>= 0)");
    let ex = cli.f64("ex", p.ex, "eccentricity e_x");
    let ey = cli.f64("ey", p.ey, "eccentricity e_y");
    let dx = cli.f64("delta-x", p.dx, "preload D_x (>= 0)");
    let dy = cli.f64("delta-y", p.dy, "preload D_y (>= 0)");
    let phi0 = cli.f64("phi0", p.phi0, "initial forcing phase phi0 (radians)");
    let periods = cli.usize_in("periods", 10, 0, 1_000_000_000, "printed periods N");
    let transient = cli.usize_in(
        "transient",
        0,
        0,
        1_000_000_000,
        "periods run before the first printed row",
    );
    let defaults = SimOptions::default();
    let rtol = cli.f64_in("rtol", defaults.rtol, 0.0, 1.0, "relative tolerance");
    let atol = cli.f64_in("atol", defaults.atol, 0.0, 1.0, "absolute tolerance");
    let method = cli.choice(
        "method",
        "dop853",
        &["dop853", "dopri5", "rk4"],
        "integration method of contact phases",
    );
    let steps = cli.usize_in(
        "steps-per-period",
        defaults.steps_per_period as usize,
        1,
        u32::MAX as usize,
        "fixed steps per forcing period (rk4)",
    );
    let x0 = cli.f64("x0", 0.0, "initial x");
    let y0 = cli.f64("y0", 0.0, "initial y");
    let vx0 = cli.f64("vx0", 0.0, "initial x' = dx/dtau");
    let vy0 = cli.f64("vy0", 0.0, "initial y' = dy/dtau");
    cli.finish();
    if rtol + atol <= 0.0 {
        fail("--rtol and --atol cannot both be 0");
    }

    let params = Params {
        eta,
        nu1,
        nu2,
        kx: k,
        ky: k,
        beta,
        dx,
        dy,
        ex,
        ey,
        phi0,
    };
    let model = JeffcottModel::new(params).unwrap_or_else(|e| fail(e));
    let state = model
        .state_at([x0, y0], [vx0, vy0])
        .unwrap_or_else(|e| fail(format!("initial state: {e}")));
    let opts = SimOptions {
        method: match method.as_str() {
            "dopri5" => Method::Dopri5,
            "rk4" => Method::Rk4,
            _ => Method::Dop853,
        },
        rtol,
        atol,
        steps_per_period: u32::try_from(steps).unwrap_or(u32::MAX),
        ..defaults
    };
    let (t, n) = (transient as u64, periods as u64);
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let header = "k,tau,x,y,vx,vy,xs,ys,regime";
    let result = model.stroboscopic(&state, t, t.saturating_add(n), &opts);
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
