//! Your own rotor on the crate's snubber ring, from the public API only: a Jeffcott rotor with
//! cross-coupled stiffness `q` and a cubic bearing term `k3` (`rotor.rs`, 60 lines), the ring's
//! contact rules from `RingedRotor`, and the crate's analyses. Prints the stroboscopic points
//! after the transient as CSV (`k,tau,x,y,vx,vy,xs,ys,regime`) and draws the orbit with the
//! gap circle.
//!
//! ```text
//! cargo run --release --example custom_rotor -- --q 0.05 --k3 0.5 --eta 2.2
//! ```

#[path = "../common/mod.rs"]
mod common;
mod rotor;

use clap::Parser;
use common::cli::{f64_in, finite, parse, usize_in};
use common::csv::fmt_f64;
use common::plot::{self, Figure, Series};
use common::scene::MethodFlag;
use common::{or_exit, Tolerances};
use jeffcott::analysis::phase_portrait;
use jeffcott::analysis::strobe_orbit;
use jeffcott::hybrid::SimOptions;
use jeffcott::params::Preset;

/// A Jeffcott rotor with cross-coupled stiffness and a cubic bearing on the snubber ring
/// (Fig. 8a values otherwise).
#[derive(Parser)]
#[command(name = "custom_rotor")]
struct Flags {
    /// Ring and rotor values
    #[arg(long, default_value = "fig8a", value_parser = ["fig8a", "fig8b"])]
    preset: String,
    /// Frequency ratio eta [range: 0.001..=100]
    #[arg(long, value_name = "NUMBER", default_value = "2", value_parser = f64_in(1e-3, 100.0))]
    eta: f64,
    /// Cross-coupled stiffness q
    #[arg(long, value_name = "NUMBER", default_value = "0.05", value_parser = finite)]
    q: f64,
    /// Cubic bearing stiffness k3
    #[arg(long, value_name = "NUMBER", default_value = "0.5", value_parser = finite)]
    k3: f64,
    /// Periods discarded [range: 0..=1000000]
    #[arg(long, value_name = "COUNT", default_value = "300", value_parser = usize_in(0, 1_000_000))]
    transient: usize,
    /// Periods printed [range: 1..=1000000]
    #[arg(long, value_name = "COUNT", default_value = "20", value_parser = usize_in(1, 1_000_000))]
    periods: usize,
    #[command(flatten)]
    tol: Tolerances,
    /// Integration method (rk4 takes 400 fixed steps per forcing period)
    #[arg(long, value_enum, default_value = "dop853")]
    method: MethodFlag,
}

fn main() {
    let Flags {
        preset,
        eta,
        q,
        k3,
        transient,
        periods,
        tol,
        method,
    } = parse();
    let (rtol, atol) = tol.get();

    let params = if preset == "fig8a" {
        Preset::Fig8a
    } else {
        Preset::Fig8b
    }
    .params();
    let model = or_exit(rotor::on_ring(params.with_eta(eta), q, k3));
    let y0 = jeffcott::State::zeros();
    let opts = SimOptions::default()
        .with_method(method.method())
        .with_rtol(rtol)
        .with_atol(atol);
    let orbit = or_exit(strobe_orbit(
        &model,
        &y0,
        transient as u64,
        periods as u64,
        &opts,
    ));
    println!("k,tau,x,y,vx,vy,xs,ys,regime");
    for p in &orbit.points {
        let ys: Vec<String> = p.y.iter().map(|v| fmt_f64(*v)).collect();
        println!("{},{},{},{}", p.k, fmt_f64(p.t), ys.join(","), p.label);
    }

    // The orbit over the printed periods, drawn from dense samples, with the gap circle.
    let period = params.with_eta(eta).forcing_period();
    let t0 = period * transient as f64;
    let portrait = or_exit(phase_portrait(
        &model,
        &y0,
        t0,
        t0 + period * periods as f64,
        period / 200.0,
        &opts,
    ));
    let circle = (0..=360)
        .map(|i| (i as f64).to_radians())
        .map(|a| (a.cos(), a.sin()))
        .collect();
    let fig = Figure::new(
        &format!("custom rotor: q = {q}, k3 = {k3}, eta = {eta}"),
        "x",
        "y",
    )
    .with_x_range(-1.4, 1.4)
    .with_y_range(-1.4, 1.4)
    .with_size(700, 700);
    let path = "target/figures/custom_rotor/orbit.png";
    or_exit(plot::lines(
        path,
        &fig,
        &[
            Series::new("orbit", portrait.broken_curve(|s| (s.y[0], s.y[1]))),
            Series::new("gap circle", circle),
        ],
    ));
    eprintln!("wrote {path}");
}
