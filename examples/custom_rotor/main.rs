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

use common::cli::Cli;
use common::csv::fmt_f64;
use common::plot::{self, Figure, Series};
use common::{or_exit, tolerance_flags};
use jeffcott::analysis::orbit::strobe_orbit;
use jeffcott::analysis::portrait::phase_portrait;
use jeffcott::hybrid::SimOptions;
use jeffcott::params::Preset;

fn main() {
    let mut cli = Cli::new("A Jeffcott rotor with cross-coupled stiffness and a cubic bearing on the snubber ring (Fig. 8a values otherwise).");
    let preset = cli.choice(
        "preset",
        "fig8a",
        &["fig8a", "fig8b"],
        "ring and rotor values",
    );
    let eta = cli.f64_in("eta", 2.0, 1e-3, 100.0, "frequency ratio eta");
    let q = cli.f64("q", 0.05, "cross-coupled stiffness q");
    let k3 = cli.f64("k3", 0.5, "cubic bearing stiffness k3");
    let transient = cli.usize_in("transient", 300, 0, 1_000_000, "periods discarded");
    let periods = cli.usize_in("periods", 20, 1, 1_000_000, "periods printed");
    let (rtol, atol) = tolerance_flags(&mut cli);
    cli.finish();

    let params = if preset == "fig8a" {
        Preset::Fig8a
    } else {
        Preset::Fig8b
    }
    .params();
    let model = or_exit(rotor::on_ring(params.with_eta(eta), q, k3));
    let y0 = jeffcott::State::zeros();
    let opts = SimOptions {
        rtol,
        atol,
        ..SimOptions::default()
    };
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
