//! The paper's Fig. 10: phase portraits (x_s, x_s') of the snubber ring, with the lines broken
//! where the ring's velocity jumps (contact onset and loss, preload crossings).
//!
//! (a) D = 0 and (b) D = 0.05 with ν₁ = 0.06, ν₂ = 0.002, η = 2.5, K = 30, e_x = 0.4,
//! e_y = 0.5, β = 70 · 0.00289; (c) D = 0 and (d) D = 0.03 with the Fig. 8 values at η = 3
//! (presets `fig10a` .. `fig10d`). From rest, a transient is discarded, then the state is
//! sampled densely for a few forcing periods; the event log of the run splits the curve into
//! smooth pieces.
//!
//! `cargo run --release --example ring_phase` writes `fig10a.png` .. `fig10d.png`, the rotor's
//! phase portraits `fig10a_rotor.png` ..., the CSV behind them and the event log
//! (`fig10a_events.csv`) into `target/figures/ring_phase`. Run with `--help` for the flags.

#[path = "common/mod.rs"]
mod common;

use std::f64::consts::TAU;
use std::path::PathBuf;

use clap::Parser;
use common::cli::{parse, usize_in};
use common::csv::{fmt_f64, CsvWriter};
use common::plot::{self, Figure, Series};
use common::Tolerances;
use jeffcott::analysis::phase_portrait;
use jeffcott::hybrid::SimOptions;
use jeffcott::paper::JeffcottModel;
use jeffcott::params::Preset;

/// Ring phase portraits (x_s, x_s') of the paper's Fig. 10a-d.
#[derive(Parser)]
#[command(name = "ring_phase")]
struct Flags {
    /// Output folder
    #[arg(long, value_name = "DIR", default_value = "target/figures/ring_phase")]
    out: PathBuf,
    /// Which panel of Fig. 10
    #[arg(long, default_value = "all", value_parser = ["a", "b", "c", "d", "all"])]
    figure: String,
    /// Periods discarded [range: 0..=100000000]
    #[arg(long, value_name = "COUNT", default_value = "300", value_parser = usize_in(0, 100_000_000))]
    transient: usize,
    /// Periods drawn [range: 1..=10000]
    #[arg(long, value_name = "COUNT", default_value = "8", value_parser = usize_in(1, 10_000))]
    periods: usize,
    /// Dense samples per forcing period [range: 10..=1000000]
    #[arg(long = "samples", value_name = "COUNT", default_value = "4000", value_parser = usize_in(10, 1_000_000))]
    per_period: usize,
    #[command(flatten)]
    tol: Tolerances,
}

fn main() {
    let Flags {
        out,
        figure,
        transient,
        periods,
        per_period,
        tol,
    } = parse();
    let (rtol, atol) = tol.get();

    let panels: Vec<(&str, Preset)> = [
        ("a", Preset::Fig10a),
        ("b", Preset::Fig10b),
        ("c", Preset::Fig10c),
        ("d", Preset::Fig10d),
    ]
    .into_iter()
    .filter(|(n, _)| figure == "all" || figure == *n)
    .collect();
    let opts = SimOptions::default().with_rtol(rtol).with_atol(atol);
    for (name, preset) in panels {
        let params = preset.params();
        let model = common::or_exit(JeffcottModel::new(params));
        let y0 = common::or_exit(model.state_at([0.0; 2], [0.0; 2]));
        let period = TAU / params.eta;
        let t_start = period * transient as f64;
        let t_end = period * (transient + periods) as f64;
        let dt = period / per_period as f64;
        let pp = common::or_exit(phase_portrait(&model, &y0, t_start, t_end, dt, &opts));
        let events: Vec<_> = pp.events.iter().filter(|e| e.t >= t_start).collect();
        let ring = pp.broken_curve(|s| (s.y[4], s.dy[4]));
        let ring_y = pp.broken_curve(|s| (s.y[5], s.dy[5]));
        let params_text = format!(
            "η = {}, D = {}, ν₁ = {}, e = ({}, {}), φ₀ = {}; τ/P = {transient}..{}",
            params.eta,
            params.dx,
            params.nu1,
            params.ex,
            params.ey,
            params.phi0,
            transient + periods
        );
        let fig = Figure::new(
            &format!("Fig. 10{name}: ring phase portrait, {params_text}"),
            "xₛ (ring, units of the gap γ)",
            "xₛ′ = dxₛ/dτ",
        )
        .with_columns("xs", "vxs")
        .with_size(1200, 1000);
        let path = out.join(format!("fig10{name}.png"));
        common::or_exit(plot::lines(&path, &fig, &[Series::new("", ring)]));
        let fig = Figure::new(
            &format!("Fig. 10{name} (y axis): ring phase portrait, {params_text}"),
            "yₛ (ring, units of the gap γ)",
            "yₛ′ = dyₛ/dτ",
        )
        .with_columns("ys", "vys")
        .with_size(1200, 1000);
        common::or_exit(plot::lines(
            out.join(format!("fig10{name}_y.png")),
            &fig,
            &[Series::new("", ring_y)],
        ));
        let rotor: Vec<(f64, f64)> = pp.samples.iter().map(|s| (s.y[0], s.y[2])).collect();
        let fig = Figure::new(
            &format!("Fig. 10{name} rotor: phase portrait, {params_text}"),
            "x (rotor, units of the gap γ)",
            "x′ = dx/dτ",
        )
        .with_columns("x", "vx")
        .with_size(1200, 1000);
        common::or_exit(plot::lines(
            out.join(format!("fig10{name}_rotor.png")),
            &fig,
            &[Series::new("", rotor)],
        ));
        let mut w = common::or_exit(CsvWriter::create(
            out.join(format!("fig10{name}_events.csv")),
            &["t", "kind", "from", "to", "x", "y", "xs", "ys"],
        ));
        for e in &events {
            common::or_exit(w.record(&[
                fmt_f64(e.t),
                e.kind.to_string(),
                e.from.to_string(),
                e.to.to_string(),
                fmt_f64(e.after[0]),
                fmt_f64(e.after[1]),
                fmt_f64(e.after[4]),
                fmt_f64(e.after[5]),
            ]));
        }
        common::or_exit(w.finish());
        let (lo, hi) = pp
            .samples
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), s| {
                (l.min(s.y[4]), h.max(s.y[4]))
            });
        println!(
            "fig10{name}: {} samples, {} events ({} smooth pieces) in the drawn window; x_s in [{lo:.4}, {hi:.4}]; wrote {}",
            pp.samples.len(),
            events.len(),
            pp.pieces().len(),
            path.display()
        );
    }
}
