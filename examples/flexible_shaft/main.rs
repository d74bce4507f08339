//! A flexible shaft on the snubber ring: a pinned-pinned Euler-Bernoulli shaft in its first
//! `--modes` bending modes (the state size is read at run time: `4 modes + 2`, a `Dyn`
//! state), the out-of-balance at station `--unbalance` and the ring at station `--ring` of
//! `--stations` evenly spaced stations (model and scaling: `shaft.rs`). The paper's ring,
//! damping and forcing values (`--preset`); `eta` is the forcing over the first natural
//! frequency, so that with one mode at midspan this is the paper's rotor.
//!
//! Writes to `--out` (default `target/figures/flexible_shaft`):
//! * `orbit.png`: the orbits of the ring's and the out-of-balance's stations over `--periods`
//!   forcing periods after `--transient`, as deflections from the shaft's rest line, with the
//!   ring's gap circle (centred at $-e$, the ring's centre seen from the rest line);
//! * `bifurcation.png`: $x$ of the ring's station (relative to the ring's centre, as the
//!   paper's $x_r$) at the stroboscopic points against `eta`, every value from rest, from the
//!   crate's generic bifurcation sweep;
//!
//! each with the CSV behind it, and prints a summary.
//!
//! ```text
//! cargo run --release --example flexible_shaft -- --modes 6 --ring 4 --eta 3.5
//! ```

#[path = "../common/mod.rs"]
mod common;
// `Layout::jeffcott` and `FlexibleShaft::energy` serve the tests
// (tests/suite/simulation/flexible_shaft.rs).
#[allow(dead_code)]
mod shaft;

use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

use clap::Parser;
use common::cli::{f64_in, fail, parse, usize_in};
use common::plot::{self, Figure, Series};
use common::scene::MethodFlag;
use common::{or_exit, Tolerances};
use jeffcott::analysis::{
    bifurcation, linspace, phase_portrait, start_from, strobe_orbit, BifurcationOptions,
    PeriodTest, Periodicity, SweepOptions,
};
use jeffcott::hybrid::SimOptions;
use jeffcott::nalgebra::DVector;
use jeffcott::params::Preset;
use shaft::Layout;

/// A pinned-pinned flexible shaft in its first bending modes on the snubber ring: orbit and
/// bifurcation diagram.
#[derive(Parser)]
#[command(name = "flexible_shaft")]
struct Flags {
    /// Output folder
    #[arg(
        long,
        value_name = "DIR",
        default_value = "target/figures/flexible_shaft"
    )]
    out: PathBuf,
    /// Bending modes kept (state size 4 modes + 2) [range: 1..=64]
    #[arg(long, value_name = "COUNT", default_value = "4", value_parser = usize_in(1, 64))]
    modes: usize,
    /// Evenly spaced stations (default: as many as modes) [range: 1..=64]
    #[arg(long, value_name = "COUNT", value_parser = usize_in(1, 64))]
    stations: Option<usize>,
    /// Station of the out-of-balance [range: 1..=64]
    #[arg(long, value_name = "STATION", default_value = "2", value_parser = usize_in(1, 64))]
    unbalance: usize,
    /// Station of the snubber ring [range: 1..=64]
    #[arg(long, value_name = "STATION", default_value = "3", value_parser = usize_in(1, 64))]
    ring: usize,
    /// Ring, damping and forcing values of the paper's Fig. 8a (D = 0) or 8b (D = 0.1)
    #[arg(long, default_value = "fig8a", value_parser = ["fig8a", "fig8b"])]
    preset: String,
    /// Eta = forcing frequency / first natural frequency [range: 0.001..=100]
    #[arg(long, value_name = "NUMBER", default_value = "3", value_parser = f64_in(1e-3, 100.0))]
    eta: f64,
    /// Modal damping ratio of every mode (default: the preset's nu1) [range: 0..=10]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(0.0, 10.0))]
    zeta: Option<f64>,
    /// Orbit: forcing periods discarded [range: 0..=1000000]
    #[arg(long, value_name = "COUNT", default_value = "300", value_parser = usize_in(0, 1_000_000))]
    transient: usize,
    /// Orbit: forcing periods drawn [range: 1..=100000]
    #[arg(long, value_name = "COUNT", default_value = "20", value_parser = usize_in(1, 100_000))]
    periods: usize,
    /// Bifurcation: lowest eta [range: 0.001..=100]
    #[arg(long, value_name = "NUMBER", default_value = "2", value_parser = f64_in(1e-3, 100.0))]
    eta_min: f64,
    /// Bifurcation: highest eta [range: 0.001..=100]
    #[arg(long, value_name = "NUMBER", default_value = "5", value_parser = f64_in(1e-3, 100.0))]
    eta_max: f64,
    /// Bifurcation: eta values [range: 1..=100000]
    #[arg(long, value_name = "COUNT", default_value = "121", value_parser = usize_in(1, 100_000))]
    steps: usize,
    /// Bifurcation: forcing periods discarded [range: 0..=1000000]
    #[arg(long, value_name = "COUNT", default_value = "200", value_parser = usize_in(0, 1_000_000))]
    bif_transient: usize,
    /// Bifurcation: forcing periods recorded [range: 2..=100000]
    #[arg(long, value_name = "COUNT", default_value = "40", value_parser = usize_in(2, 100_000))]
    record: usize,
    #[command(flatten)]
    tol: Tolerances,
    /// Integration method (rk4 takes 400 fixed steps per forcing period)
    #[arg(long, value_enum, default_value = "dop853")]
    method: MethodFlag,
    /// RADAU5's error weights: `modal` (a mode's velocity counted by the displacement it
    /// stands for, `FlexibleShaft::error_scale_vector`) or `state` (the state's scale, as
    /// before; the explicit methods always use it)
    #[arg(long, default_value = "modal", value_parser = ["modal", "state"])]
    error_weight: String,
    /// RADAU5's Newton solves: `woodbury` (the shaft declares its diagonal springs, the
    /// contact couples the modes with rank 2: O(N) a solve) or `dense` (the LU of the
    /// condensed matrix, as before)
    #[arg(long, default_value = "woodbury", value_parser = ["woodbury", "dense"])]
    newton_solve: String,
}

fn main() {
    let Flags {
        out,
        modes,
        stations,
        unbalance,
        ring,
        preset,
        eta,
        zeta,
        transient,
        periods,
        eta_min,
        eta_max,
        steps,
        bif_transient,
        record,
        tol,
        method,
        error_weight,
        newton_solve,
    } = parse();
    let frequency_weights = error_weight == "modal";
    let springs = newton_solve == "woodbury";
    let (rtol, atol) = tol.get();
    if eta_max < eta_min {
        fail(format!("--eta-max {eta_max} is below --eta-min {eta_min}"));
    }

    let mut params = if preset == "fig8a" {
        Preset::Fig8a
    } else {
        Preset::Fig8b
    }
    .params()
    .with_eta(eta);
    if let Some(zeta) = zeta {
        params.nu1 = zeta;
    }
    let layout = Layout {
        modes,
        stations: stations.unwrap_or(modes),
        unbalance,
        ring,
    };
    let opts = SimOptions::default()
        .with_method(method.method())
        .with_rtol(rtol)
        .with_atol(atol);
    let model = or_exit(shaft::on_ring_with(
        params,
        layout,
        frequency_weights,
        springs,
    ));
    let s = model.rotor();
    // From rest on the shaft's line (the ring placed if the rest point is beyond the gap).
    let mut y0 = DVector::zeros(s.state_len());
    or_exit(model.make_consistent(&mut y0));

    let xi = |i: usize| s.station_position(i);
    let list = |v: Vec<f64>| {
        v.iter()
            .map(|x| format!("{x:.3}"))
            .collect::<Vec<_>>()
            .join(" ")
    };
    println!(
        "flexible shaft: {modes} modes (state size {}), {} stations at xi = {}",
        s.state_len(),
        layout.stations,
        list((1..=layout.stations).map(xi).collect())
    );
    println!(
        "  out-of-balance at station {unbalance} (xi = {:.3}), ring at station {ring} (xi = {:.3}), modal damping {}",
        xi(unbalance),
        xi(ring),
        params.nu1
    );
    println!(
        "  omega_j / omega_1 = {}; mode shapes at the ring {}",
        list((1..=modes).map(shaft::natural_frequency).collect()),
        list(
            (1..=modes)
                .map(|j| shaft::mode_shape(j, xi(ring)))
                .collect()
        )
    );
    let clearance = 1.0 - params.ex.hypot(params.ey);
    let whirl = s.free_whirl_radius(ring);
    println!(
        "eta = {eta}: without the ring the ring's station would whirl with radius {whirl:.3} (clearance {clearance:.3}: {})",
        if whirl > clearance { "contact" } else { "no contact" }
    );

    // The orbit after the transient.
    let clock = Instant::now();
    let period = params.forcing_period();
    let t0 = period * transient as f64;
    let orbit = or_exit(strobe_orbit(
        &model,
        &y0,
        transient as u64,
        periods as u64,
        &opts,
    ));
    let portrait = or_exit(phase_portrait(
        &model,
        &y0,
        t0,
        t0 + period * periods as f64,
        period / 400.0,
        &opts,
    ));
    let contacts = portrait
        .events
        .iter()
        .filter(|e| e.t >= t0 && e.kind == "contact onset")
        .count();
    let reach = portrait
        .samples
        .iter()
        .map(|x| s.ring_kinematics(x.y.as_slice()).r.norm())
        .fold(0.0, f64::max);
    let periodicity = or_exit(orbit.period(&PeriodTest::default()));
    println!(
        "orbit: {}, {contacts} contact onsets in {periods} periods, largest |r| at the ring {reach:.4}, {} steps ({} rejected, {} rhs evaluations, {} Jacobians, {} LU), {:.2} s",
        describe(&periodicity),
        orbit.stats.steps + portrait.stats.steps,
        orbit.stats.rejected + portrait.stats.rejected,
        orbit.stats.rhs_evals + portrait.stats.rhs_evals,
        orbit.stats.jacobians + portrait.stats.jacobians,
        orbit.stats.lu_decompositions + portrait.stats.lu_decompositions,
        clock.elapsed().as_secs_f64()
    );

    let deflection = |station: usize| {
        portrait.broken_curve(|x| {
            let (w, _) = s.station_motion(station, x.y.as_slice());
            (w[0], w[1])
        })
    };
    let circle: Vec<(f64, f64)> = (0..=360)
        .map(|i| (i as f64).to_radians())
        .map(|a| (a.cos() - params.ex, a.sin() - params.ey))
        .collect();
    let series = [
        Series::new(&format!("ring station {ring}"), deflection(ring)),
        Series::new(
            &format!("out-of-balance station {unbalance}"),
            deflection(unbalance),
        ),
        Series::new("ring's gap", circle),
    ];
    let (lo, hi) = square_range(&series);
    let fig = Figure::new(
        &format!("flexible shaft, {modes} modes, eta = {eta}: deflection from the rest line"),
        "w_x / gap",
        "w_y / gap",
    )
    .with_x_range(lo.0, hi.0)
    .with_y_range(lo.1, hi.1)
    .with_size(800, 800);
    let path = out.join("orbit.png");
    or_exit(plot::lines(&path, &fig, &series));
    println!("wrote {}", path.display());

    // The bifurcation diagram from the crate's generic sweep: the closure builds the model.
    let clock = Instant::now();
    let etas = or_exit(linspace(eta_min, eta_max, steps));
    let config = BifurcationOptions::default()
        .with_transient(bif_transient as u64)
        .with_record(record as u64)
        .with_sweep(SweepOptions::reset())
        .with_opts(opts);
    let build =
        |eta: f64| shaft::on_ring_with(params.with_eta(eta), layout, frequency_weights, springs);
    let diagram = or_exit(bifurcation(
        &etas,
        build,
        start_from(y0.clone()),
        &config,
        None,
    ));
    let mut points = Vec::new();
    let mut census: BTreeMap<String, usize> = BTreeMap::new();
    for col in diagram.columns.iter().flatten() {
        points.extend(
            col.orbit
                .points
                .iter()
                .map(|p| (col.value, s.ring_kinematics(p.y.as_slice()).r.x)),
        );
        *census.entry(describe(&col.periodicity)).or_default() += 1;
    }
    for f in diagram.failures() {
        eprintln!("eta = {}: {}", f.value, f.error);
    }
    let census: Vec<String> = census.iter().map(|(k, n)| format!("{n} {k}")).collect();
    println!(
        "bifurcation: {} values of eta in [{eta_min}, {eta_max}] ({}), {} failed, {:.2} s on {} threads",
        etas.len(),
        census.join(", "),
        diagram.failures().len(),
        clock.elapsed().as_secs_f64(),
        diagram.threads
    );
    let fig = Figure::new(
        &format!("flexible shaft, {modes} modes: x at the ring's station {ring}"),
        "eta",
        "x_r / gap",
    )
    .with_columns("eta", "x_r");
    let path = out.join("bifurcation.png");
    or_exit(plot::bifurcation(&path, &fig, &points));
    println!("wrote {}", path.display());
}

fn describe(p: &Periodicity) -> String {
    match p {
        Periodicity::Period(n) => format!("period {n}"),
        Periodicity::NotConverged { .. } => "not converged".to_string(),
        _ => "not periodic".to_string(),
    }
}

/// A square window holding every finite point, with a margin.
fn square_range(series: &[Series]) -> ((f64, f64), (f64, f64)) {
    let pts = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0.is_finite() && p.1.is_finite());
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    let half = 0.55 * (x1 - x0).max(y1 - y0);
    let (cx, cy) = (0.5 * (x0 + x1), 0.5 * (y0 + y1));
    ((cx - half, cy - half), (cx + half, cy + half))
}
