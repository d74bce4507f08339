//! A flexible shaft on the snubber ring (prototype on the const-generic API: 4 modes).

#[path = "../common/mod.rs"]
mod common;
mod shaft;

use std::time::Instant;

use common::cli::Cli;
use common::plot::{self, Figure, Series};
use common::{or_exit, tolerance_flags};
use jeffcott::analysis::{phase_portrait, strobe_orbit, sweep, PeriodTest, SweepConfig};
use jeffcott::hybrid::SimOptions;
use jeffcott::nalgebra::SVector;
use jeffcott::params::Preset;
use shaft::Layout;

const N: usize = 18;

fn main() {
    let mut cli = Cli::new("A pinned-pinned flexible shaft in its first bending modes on the snubber ring.");
    let preset = cli.choice("preset", "fig8a", &["fig8a", "fig8b"], "ring, damping and forcing values");
    let eta = cli.f64_in("eta", 3.0, 1e-3, 100.0, "frequency ratio eta (forcing over the first natural frequency)");
    let unbalance = cli.usize("unbalance", 2, "station of the out-of-balance");
    let ring = cli.usize("ring", 3, "station of the snubber ring");
    let transient = cli.usize_in("transient", 300, 0, 1_000_000, "periods discarded");
    let periods = cli.usize_in("periods", 20, 1, 1_000_000, "periods drawn");
    let eta_min = cli.f64("eta-min", 2.0, "bifurcation diagram: first eta");
    let eta_max = cli.f64("eta-max", 5.0, "bifurcation diagram: last eta");
    let steps = cli.usize_in("steps", 61, 2, 100_000, "bifurcation diagram: eta values");
    let bif_transient = cli.usize_in("bif-transient", 200, 0, 1_000_000, "bifurcation diagram: periods discarded");
    let bif_record = cli.usize_in("bif-record", 40, 1, 1_000_000, "bifurcation diagram: periods recorded");
    let (rtol, atol) = tolerance_flags(&mut cli);
    cli.finish();

    let params = if preset == "fig8a" { Preset::Fig8a } else { Preset::Fig8b }.params().with_eta(eta);
    let layout = Layout { modes: 4, stations: 4, unbalance, ring };
    let opts = SimOptions { rtol, atol, ..SimOptions::default() };
    let model = or_exit(shaft::on_ring::<N>(params, layout));
    let s = model.rotor();
    let y0 = SVector::<f64, N>::zeros();

    let clock = Instant::now();
    let orbit = or_exit(strobe_orbit(&model, &y0, transient as u64, periods as u64, &opts));
    let period = params.forcing_period();
    let t0 = period * transient as f64;
    let portrait = or_exit(phase_portrait(&model, &y0, t0, t0 + period * periods as f64, period / 200.0, &opts));
    let contacts = portrait.events.iter().filter(|e| e.kind == "contact onset").count();
    println!(
        "orbit: {:?}, {contacts} contacts in {periods} periods, {:.2} s",
        orbit.period(&PeriodTest::default()),
        clock.elapsed().as_secs_f64()
    );

    let circle = (0..=360)
        .map(|i| (i as f64).to_radians())
        .map(|a| (a.cos() - params.ex, a.sin() - params.ey))
        .collect();
    let fig = Figure::new(&format!("flexible shaft, eta = {eta}"), "w_x", "w_y")
        .with_x_range(-1.4, 1.4)
        .with_y_range(-1.4, 1.4)
        .with_size(700, 700);
    let path = "target/figures/flexible_shaft/orbit.png";
    or_exit(plot::lines(
        path,
        &fig,
        &[
            Series::new("ring station", portrait.broken_curve(|x| { let (w, _) = s.station_motion(ring, x.y.as_slice()); (w[0], w[1]) })),
            Series::new("unbalance station", portrait.broken_curve(|x| { let (w, _) = s.station_motion(unbalance, x.y.as_slice()); (w[0], w[1]) })),
            Series::new("ring gap", circle),
        ],
    ));

    let clock = Instant::now();
    let etas: Vec<f64> = (0..steps).map(|i| eta_min + (eta_max - eta_min) * i as f64 / (steps - 1) as f64).collect();
    let result = or_exit(sweep(
        &etas,
        &SweepConfig::reset(),
        |&e, _: Option<()>| {
            let m = shaft::on_ring::<N>(params.with_eta(e), layout).map_err(|e| e.to_string())?;
            let o = strobe_orbit(&m, &y0, bif_transient as u64, bif_record as u64, &opts).map_err(|e| e.to_string())?;
            let pts: Vec<(f64, f64)> = o.points.iter().map(|p| (e, m.rotor().ring_kinematics(p.y.as_slice()).r.x)).collect();
            Ok::<_, String>((pts, ()))
        },
        None,
    ));
    let pts: Vec<(f64, f64)> = result.results.iter().filter_map(|r| r.as_ref().ok()).flatten().copied().collect();
    println!("bifurcation: {} values, {:.2} s", etas.len(), clock.elapsed().as_secs_f64());
    let fig = Figure::new("flexible shaft: x at the ring station", "eta", "x_r");
    or_exit(plot::bifurcation("target/figures/flexible_shaft/bifurcation.png", &fig, &pts));
}
