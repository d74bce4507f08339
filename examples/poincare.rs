//! The paper's Fig. 9: stroboscopic Poincaré maps (x, x′) of the rotor at τ = 2πk/η.
//!
//! (a) η = 2.223, D = 0; (b) η = 2.181, D = 0.1; (c) η = 2.442, D = 0; (d) η = 2.442, D = 0.1
//! (presets `fig9a` .. `fig9d`; the other values are those of Fig. 8). From rest, a transient
//! is discarded, then many points are recorded and their period detected (shown in the title).
//!
//! The captions of (a) and (b) appear to have their η swapped (`docs/reproduction.md`): with the
//! captions' values both maps are period 1 (a single point), with the values swapped they show
//! what the paper's text describes (period 3 for D = 0, a closed curve for D = 0.1). So (a) and
//! (b) are drawn both ways: `fig9a.png` (the caption's η = 2.223) and `fig9a_eta2.181.png`,
//! `fig9b.png` (2.181) and `fig9b_eta2.223.png`, each with a note saying which it is.
//!
//! `cargo run --release --example poincare` writes these six pictures and the CSV behind them
//! into `target/figures/poincare`; `--eta` draws one panel at another η instead
//! (`fig9<panel>_eta<η>.png`). Run with `--help` for the flags.

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

/// Poincaré maps (x, x′) of the rotor: the paper's Fig. 9a-d (9a, 9b also with their η swapped).
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
    /// Draw the panel at this η only (default: the caption's, and for a and b the swapped
    /// one too) [range: 0.01..=100]
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
    let opts = SimOptions::default().with_rtol(rtol).with_atol(atol);
    let test = PeriodTest::default()
        .with_max_period(max_period)
        .with_tol(tol);
    let run = Run {
        out: &out,
        transient,
        record,
        opts: &opts,
        test: &test,
    };
    for (name, preset) in panels {
        let params = preset.params();
        // The η of the other panel of the swapped pair (a <-> b).
        let swapped = match name {
            "a" => Some(Preset::Fig9b.params().eta),
            "b" => Some(Preset::Fig9a.params().eta),
            _ => None,
        };
        match (eta, swapped) {
            (Some(eta), _) => run.panel(name, &params.with_eta(eta), Version::Other),
            (None, Some(other)) => {
                run.panel(name, &params, Version::Caption);
                run.panel(name, &params.with_eta(other), Version::Swapped);
            }
            (None, None) => run.panel(name, &params, Version::Plain),
        }
    }
}

/// Which η a panel is drawn at.
#[derive(Clone, Copy, PartialEq)]
enum Version {
    /// Panels c and d: the caption's η.
    Plain,
    /// Panels a and b at the caption's η (which looks swapped).
    Caption,
    /// Panels a and b at the other panel's η.
    Swapped,
    /// At the η of `--eta`.
    Other,
}

/// The settings shared by the panels.
struct Run<'a> {
    out: &'a std::path::Path,
    transient: usize,
    record: usize,
    opts: &'a SimOptions,
    test: &'a PeriodTest,
}

impl Run<'_> {
    /// Computes and draws one panel, and prints a line about it.
    fn panel(&self, name: &str, params: &jeffcott::params::Params, version: Version) {
        let (transient, record, tol) = (self.transient, self.record, self.test.tol);
        let started = std::time::Instant::now();
        let map = common::or_exit(poincare_map(
            params,
            RotorStart::at_rest(),
            transient as u64,
            record as u64,
            self.opts,
            self.test,
        ));
        let (orbit, per_text) = (map.orbit, map.periodicity.to_string());
        let pts = orbit.pairs(0, 2);
        let (xr, vr) = (
            padded_range(pts.iter().map(|p| p.0)),
            padded_range(pts.iter().map(|p| p.1)),
        );
        let (note, file) = match version {
            Version::Plain => (None, format!("fig9{name}.png")),
            Version::Caption => (
                Some(format!(
                    "At the caption's η = {}. The paper's text describes this panel\n\
                     at the other panel's η = {}: the captions of 9a and 9b look\n\
                     swapped (docs/reproduction.md); drawn so in fig9{name}_eta{}.png",
                    params.eta,
                    if name == "a" { "2.181" } else { "2.223" },
                    if name == "a" { "2.181" } else { "2.223" }
                )),
                format!("fig9{name}.png"),
            ),
            Version::Swapped => (
                Some(format!(
                    "Drawn at the other panel's η = {}, not the caption's:\n\
                     the captions of 9a and 9b look swapped (docs/reproduction.md)",
                    params.eta
                )),
                format!("fig9{name}_eta{}.png", params.eta),
            ),
            Version::Other => (None, format!("fig9{name}_eta{}.png", params.eta)),
        };
        let mut note = note.unwrap_or_default();
        if per_text == "period 1" {
            let n = pts.len();
            note = format!("{note}\nAll {n} points fall on this one dot (period 1).")
                .trim_start()
                .to_string();
        }
        let mut fig = Figure::new(
            &format!(
                "Fig. 9{name}{}: (x, x′) at τ = 2πk/η, η = {}, D = {}, φ₀ = {}; k = {}..{} from rest: {per_text}",
                match version {
                    Version::Caption => " as captioned",
                    Version::Swapped => " with the other panel's η",
                    _ => "",
                },
                params.eta,
                params.dx,
                params.phi0,
                transient + 1,
                transient + record
            ),
            "x (rotor, units of the gap γ)",
            "x′ = dx/dτ",
        )
        .with_columns("x", "vx")
        .with_size(1200, 1000)
        .with_x_range(xr.0, xr.1)
        .with_y_range(vr.0, vr.1);
        if !note.is_empty() {
            fig = fig.with_note(&note);
        }
        let path = self.out.join(file);
        common::or_exit(plot::scatter(&path, &fig, &[Series::new("", pts)]));
        println!(
            "fig9{name}: eta = {}, D = {}: {per_text} (tol {tol}; {} points, {} steps, {} transitions, {:.1} s); wrote {}",
            params.eta,
            params.dx,
            orbit.points.len(),
            orbit.stats.steps,
            orbit.stats.transitions,
            started.elapsed().as_secs_f64(),
            path.display()
        );
    }
}
