//! The paper's Fig. 9: stroboscopic Poincaré maps (x_r, x_r') at τ = 2πk/η.
//!
//! (a) η = 2.223, D = 0; (b) η = 2.181, D = 0.1; (c) η = 2.442, D = 0; (d) η = 2.442, D = 0.1
//! (presets `fig9a` .. `fig9d`; the other values are those of Fig. 8). From rest, a transient
//! is discarded, then many points are recorded and their period detected (shown in the title).
//!
//! `cargo run --release --example poincare` writes `fig9a.png` .. `fig9d.png` and the CSV
//! behind them into `target/figures/poincare`. Run with `--help` for the flags.

#[path = "common/mod.rs"]
mod common;

use std::path::PathBuf;

use clap::Parser;
use common::cli::{f64_in, parse, usize_in};
use common::plot::{self, Figure, Series};
use common::Tolerances;
use jeffcott::analysis::PeriodTest;
use jeffcott::hybrid::SimOptions;
use jeffcott::paper::{poincare_map, RotorStart};
use jeffcott::params::Preset;

/// The range of the values padded by 5 %, and at least `MIN_SPAN` wide: a periodic orbit's
/// points coincide to the integration tolerance, and an automatic range would blow that
/// rounding noise up to fill the picture.
fn padded_range(values: impl Iterator<Item = f64>) -> (f64, f64) {
    const MIN_SPAN: f64 = 0.05;
    let (lo, hi) = values
        .filter(|v| v.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), v| {
            (l.min(v), h.max(v))
        });
    if lo > hi {
        return (-1.0, 1.0);
    }
    let mid = 0.5 * (lo + hi);
    let half = (0.5 * (hi - lo) * 1.05).max(0.5 * MIN_SPAN);
    (mid - half, mid + half)
}

/// Poincaré maps (x_r, x_r') of the paper's Fig. 9a-d.
#[derive(Parser)]
#[command(name = "poincare")]
struct Flags {
    /// Output folder
    #[arg(long, value_name = "DIR", default_value = "target/figures/poincare")]
    out: PathBuf,
    /// Which panel of Fig. 9
    #[arg(long, default_value = "all", value_parser = ["a", "b", "c", "d", "all"])]
    figure: String,
    /// Periods discarded [range: 0..=100000000]
    #[arg(long, value_name = "COUNT", default_value = "1000", value_parser = usize_in(0, 100_000_000))]
    transient: usize,
    /// Periods recorded [range: 2..=100000000]
    #[arg(long, value_name = "COUNT", default_value = "3000", value_parser = usize_in(2, 100_000_000))]
    record: usize,
    /// Override the panel's eta (default: the paper's) [range: 0.01..=100]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(0.01, 100.0))]
    eta: Option<f64>,
    #[command(flatten)]
    tol: Tolerances,
    /// Relative tolerance of the period test [range: 0..=1]
    #[arg(long, value_name = "NUMBER", default_value = "1e-6", value_parser = f64_in(0.0, 1.0))]
    period_tol: f64,
    /// Largest period tested [range: 1..=10000]
    #[arg(long, value_name = "COUNT", default_value = "16", value_parser = usize_in(1, 10_000))]
    max_period: usize,
}

fn main() {
    let Flags {
        out,
        figure,
        transient,
        record,
        eta,
        tol: tolerances,
        period_tol: tol,
        max_period,
    } = parse();
    let (rtol, atol) = tolerances.get();

    let panels: Vec<(&str, Preset)> = [
        ("a", Preset::Fig9a),
        ("b", Preset::Fig9b),
        ("c", Preset::Fig9c),
        ("d", Preset::Fig9d),
    ]
    .into_iter()
    .filter(|(n, _)| figure == "all" || figure == *n)
    .collect();
    let opts = SimOptions {
        rtol,
        atol,
        ..SimOptions::default()
    };
    let test = PeriodTest { max_period, tol };
    for (name, preset) in panels {
        let mut params = preset.params();
        if let Some(eta) = eta {
            params.eta = eta;
        }
        let map = common::or_exit(poincare_map(
            &params,
            RotorStart::at_rest(),
            transient as u64,
            record as u64,
            &opts,
            &test,
        ));
        let (orbit, per_text) = (map.orbit, map.periodicity.to_string());
        let pts = orbit.pairs(0, 2);
        let (xr, vr) = (
            padded_range(pts.iter().map(|p| p.0)),
            padded_range(pts.iter().map(|p| p.1)),
        );
        let fig = Figure::new(
            &format!(
                "Fig. 9{name}: (x_r, x_r′) at τ = 2πk/η, η = {}, D = {}, φ₀ = {}; k = {}..{} from rest: {per_text}",
                params.eta,
                params.dx,
                params.phi0,
                transient + 1,
                transient + record
            ),
            "x_r",
            "x_r′ = dx_r/dτ",
        )
        .with_columns("x", "vx")
        .with_size(1200, 1000)
        .with_x_range(xr.0, xr.1)
        .with_y_range(vr.0, vr.1);
        let path = out.join(format!("fig9{name}.png"));
        common::or_exit(plot::scatter(&path, &fig, &[Series::new("", pts)]));
        println!(
            "fig9{name}: eta = {}, D = {}: {per_text} (tol {tol}; {} points, {} steps, {} transitions); wrote {}",
            params.eta,
            params.dx,
            orbit.points.len(),
            orbit.stats.steps,
            orbit.stats.transitions,
            path.display()
        );
    }
}
