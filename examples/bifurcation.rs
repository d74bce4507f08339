//! The paper's Fig. 8: bifurcation diagrams of the rotor's x_r(τ = 2πk/η) against η, without
//! (a) and with (b) preload, with the paper's reported bifurcation points marked.
//!
//! `cargo run --release --example bifurcation` (no flags) draws both diagrams over η ∈ [2, 5]
//! with 601 values, 300 discarded and 150 recorded forcing periods, every value from rest (zero
//! initial conditions; `--mode carry` carries the state from one value to the next instead, in
//! `--chunks` contiguous chunks that each start from rest), into
//! `target/figures/bifurcation`: `fig8a.png`, `fig8b.png`, the points behind them
//! (`fig8a.csv`, `fig8b.csv`: eta, x) and the detected period per value
//! (`fig8a_periods.csv`, ...). Run with `--help` for the flags.
//!
//! With `--friction MU --shaft-radius A` (A in gaps) the rotor meets its ring with Coulomb
//! friction (`paper::rub::rubbing_model`, docs/friction.md): the same diagrams, of the rotor with
//! friction, each η from rest or carried as above (not with `--locate-from`).

#[path = "common/mod.rs"]
mod common;

use std::path::PathBuf;
use std::time::Instant;

use clap::Parser;
use common::cli::{f64_in, fail, parse, usize_in};
use common::csv::{fmt_f64, CsvWriter};
use common::plot::{self, Figure};
use common::Tolerances;
use jeffcott::analysis::{
    bifurcation, linspace, start_from, Bifurcation, BifurcationOptions, LocatorOptions,
    StderrProgress, SweepOptions,
};
use jeffcott::hybrid::SimOptions;
use jeffcott::nalgebra::allocator::Allocator;
use jeffcott::nalgebra::{DVector, DefaultAllocator, Dim};
use jeffcott::paper::rub::rubbing_model;
use jeffcott::paper::{ParamSweep, SweepParameter};
use jeffcott::params::{Params, Preset};

/// The paper's reported points: (diagram, eta, label).
const PAPER_MARKS: [(&str, f64, &str); 9] = [
    ("a", 2.165, "2.165"),
    ("a", 2.717, "2.717"),
    ("a", 3.803, "3.803"),
    ("b", 2.213, "2.213"),
    ("b", 2.824, "2.824"),
    ("b", 3.107, "3.107"),
    ("b", 3.893, "3.893"),
    ("b", 4.211, "4.211"),
    ("b", 4.484, "4.484"),
];

/// Bifurcation diagrams of x_r against eta (paper Fig. 8a: D = 0, Fig. 8b: D = 0.1).
#[derive(Parser)]
#[command(name = "bifurcation")]
struct Flags {
    /// Output folder
    #[arg(long, value_name = "DIR", default_value = "target/figures/bifurcation")]
    out: PathBuf,
    /// Lowest eta [range: 0.01..=100]
    #[arg(long, value_name = "NUMBER", default_value = "2", value_parser = f64_in(0.01, 100.0))]
    eta_min: f64,
    /// Highest eta [range: 0.01..=100]
    #[arg(long, value_name = "NUMBER", default_value = "5", value_parser = f64_in(0.01, 100.0))]
    eta_max: f64,
    /// Number of eta values [range: 1..=1000000]
    #[arg(long, value_name = "COUNT", default_value = "601", value_parser = usize_in(1, 1_000_000))]
    steps: usize,
    /// Periods discarded [range: 0..=10000000]
    #[arg(long, value_name = "COUNT", default_value = "300", value_parser = usize_in(0, 10_000_000))]
    transient: usize,
    /// Periods recorded [range: 2..=1000000]
    #[arg(long, value_name = "COUNT", default_value = "150", value_parser = usize_in(2, 1_000_000))]
    record: usize,
    /// Which diagram
    #[arg(long, default_value = "both", value_parser = ["a", "b", "both"])]
    diagram: String,
    /// Preload D = Dx = Dy for a single diagram (default: the paper's 0 for a, 0.1 for b)
    /// [range: 0..=10]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(0.0, 10.0))]
    preload: Option<f64>,
    /// State carried over from the previous eta, or every eta from rest
    #[arg(long, default_value = "reset", value_parser = ["carry", "reset"])]
    mode: String,
    /// Carry mode: contiguous chunks, each starting from rest (1 = one serial chain)
    /// [range: 1..=1000000]
    #[arg(long, value_name = "COUNT", default_value = "8", value_parser = usize_in(1, 1_000_000))]
    chunks: usize,
    /// Worker threads, unset = all cores [range: 1..=1024]
    #[arg(long, value_name = "COUNT", value_parser = usize_in(1, 1024))]
    threads: Option<usize>,
    #[command(flatten)]
    tol: Tolerances,
    /// Relative tolerance of the period test [range: 0..=1]
    #[arg(long, value_name = "NUMBER", default_value = "1e-6", value_parser = f64_in(0.0, 1.0))]
    period_tol: f64,
    /// With --locate-to and --diagram a|b: locate by bisection (each run from rest) where the
    /// period detected at this eta ends towards --locate-to, print it and exit
    /// [range: 0.01..=100]
    #[arg(long = "locate-from", value_name = "NUMBER", value_parser = f64_in(0.01, 100.0))]
    locate_lo: Option<f64>,
    /// Other end for --locate-from (above or below it) [range: 0.01..=100]
    #[arg(long = "locate-to", value_name = "NUMBER", value_parser = f64_in(0.01, 100.0))]
    locate_hi: Option<f64>,
    /// Periods discarded at each bisection step [range: 0..=10000000]
    #[arg(long, value_name = "COUNT", default_value = "2000", value_parser = usize_in(0, 10_000_000))]
    locate_transient: usize,
    /// Periods recorded at each bisection step [range: 2..=1000000]
    #[arg(long, value_name = "COUNT", default_value = "200", value_parser = usize_in(2, 1_000_000))]
    locate_record: usize,
    /// Coulomb friction coefficient between ring and shaft (0: the paper's frictionless
    /// model) [range: 0..=1000]
    #[arg(long, value_name = "NUMBER", default_value = "0", value_parser = f64_in(0.0, 1e3))]
    friction: f64,
    /// Shaft radius at the ring, in gaps (required with --friction > 0) [range: 0..=1000]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(0.0, 1e3))]
    shaft_radius: Option<f64>,
}

/// What the outputs of one diagram are named and titled by.
struct Diagram<'a> {
    /// "a" or "b".
    d: &'a str,
    label: String,
    base: Params,
    /// (mu, a) with friction.
    friction: Option<(f64, f64)>,
    out: &'a std::path::Path,
    tol: f64,
    periods: (usize, usize),
    mode_text: &'a str,
    eta_range: (f64, f64),
    /// The paper's marks drawn (its own preloads, no friction).
    marks: bool,
}

fn main() {
    let Flags {
        out,
        eta_min,
        eta_max,
        steps,
        transient,
        record,
        diagram,
        preload,
        mode,
        chunks,
        threads,
        tol: tolerances,
        period_tol: tol,
        locate_lo,
        locate_hi,
        locate_transient,
        locate_record,
        friction,
        shaft_radius,
    } = parse();
    let (rtol, atol) = tolerances.get();
    // Unset values as NaN below.
    let preload = preload.unwrap_or(f64::NAN);
    let (locate_lo, locate_hi) = (locate_lo.unwrap_or(f64::NAN), locate_hi.unwrap_or(f64::NAN));
    if locate_lo.is_nan() != locate_hi.is_nan() {
        fail("--locate-from and --locate-to go together");
    }
    if eta_min > eta_max || (eta_min == eta_max && steps > 1) {
        fail(format!(
            "--eta-min ({eta_min}) must be below --eta-max ({eta_max})"
        ));
    }
    if !preload.is_nan() && diagram == "both" {
        fail("--preload needs --diagram a or --diagram b");
    }

    let friction = (friction > 0.0).then(|| {
        let a = shaft_radius.unwrap_or_else(|| {
            fail("--friction needs --shaft-radius (the shaft's radius at the ring, in gaps)")
        });
        (friction, a)
    });
    if !locate_lo.is_nan() {
        if friction.is_some() {
            fail("--locate-from is not available with --friction");
        }
        if diagram == "both" {
            fail("--locate-from needs --diagram a or --diagram b");
        }
        if locate_lo == locate_hi {
            fail(format!(
                "--locate-from ({locate_lo}) must differ from --locate-to ({locate_hi})"
            ));
        }
        let base = if diagram == "a" {
            Preset::Fig8a.params()
        } else {
            Preset::Fig8b.params()
        };
        let base = if preload.is_nan() {
            base
        } else {
            base.with_preload(preload)
        };
        let mut lc = LocatorOptions::default()
            .with_transient(locate_transient as u64)
            .with_record(locate_record as u64)
            .with_opts(SimOptions::default().with_rtol(rtol).with_atol(atol));
        lc.period_test.tol = tol;
        let t0 = Instant::now();
        let family = ParamSweep::new(base, SweepParameter::Eta);
        let c = common::or_exit(family.locate_period_change(locate_lo, locate_hi, &lc));
        println!(
            "fig8{diagram} (D = {}): {} (at {:.5}) -> {} (at {:.5}): eta = {:.3} ({} runs of {}+{} periods from rest, {:.1} s)",
            base.dx,
            c.bracket.at_from,
            c.bracket.from,
            c.bracket.at_to,
            c.bracket.to,
            c.value(),
            c.evaluations,
            locate_transient,
            locate_record,
            t0.elapsed().as_secs_f64()
        );
        return;
    }

    let etas = common::or_exit(linspace(eta_min, eta_max, steps));
    let mut config = BifurcationOptions::default()
        .with_transient(transient as u64)
        .with_record(record as u64)
        .with_opts(SimOptions::default().with_rtol(rtol).with_atol(atol));
    config.period_test.tol = tol;
    config.sweep = match mode.as_str() {
        "carry" => SweepOptions::carry_over(chunks),
        _ => SweepOptions::reset(),
    };
    if let Some(n) = threads {
        config.sweep = config.sweep.with_threads(n);
    }
    let mode_text = if mode == "carry" {
        format!("carried over ({chunks} chunks)")
    } else {
        "each η from rest".to_string()
    };

    let which: Vec<&str> = match diagram.as_str() {
        "both" => vec!["a", "b"],
        d => vec![d],
    };
    let start_all = Instant::now();
    let mut total_periods = 0.0;
    for d in which {
        let base = if d == "a" {
            Preset::Fig8a.params()
        } else {
            Preset::Fig8b.params()
        };
        let base = if preload.is_nan() {
            base
        } else {
            base.with_preload(preload)
        };
        let label = format!("fig8{d}");
        let progress = StderrProgress::new(format!("{label} (D = {})", base.dx));
        let t0 = Instant::now();
        let diagram = Diagram {
            d,
            label: label.clone(),
            base,
            friction,
            out: &out,
            tol,
            periods: (transient, record),
            mode_text: &mode_text,
            eta_range: (eta_min, eta_max),
            marks: preload.is_nan() && friction.is_none(),
        };
        let periods = (steps * (transient + record)) as f64;
        total_periods += periods;
        match friction {
            None => {
                let family = ParamSweep::new(base, SweepParameter::Eta);
                let result = common::or_exit(family.bifurcation(&etas, &config, Some(&progress)));
                write_outputs(&diagram, &result, t0.elapsed().as_secs_f64())
            }
            Some((mu, a)) => {
                let build = |eta: f64| rubbing_model(&base.with_eta(eta), mu, a);
                let start = start_from(DVector::zeros(6));
                let result =
                    common::or_exit(bifurcation(&etas, build, start, &config, Some(&progress)));
                write_outputs(&diagram, &result, t0.elapsed().as_secs_f64())
            }
        }
    }
    let secs = start_all.elapsed().as_secs_f64();
    eprintln!(
        "total {secs:.2} s, {:.1} µs per forcing period (wall); figures and CSV in {}",
        secs / total_periods * 1e6,
        out.display()
    );
}

/// Reports the time `secs` that `result` took, writes the periods' CSV, prints the period
/// changes and draws the diagram.
fn write_outputs<D: Dim, E: std::fmt::Display>(
    g: &Diagram<'_>,
    result: &Bifurcation<D, E>,
    secs: f64,
) where
    DefaultAllocator: Allocator<D>,
{
    let (label, base, tol) = (&g.label, &g.base, g.tol);
    let (transient, record) = g.periods;
    let periods = (result.values.len() * (transient + record)) as f64;
    eprintln!(
        "{label}: {} values x {} periods in {secs:.2} s on {} threads = {:.1} µs per forcing period (wall)",
        result.values.len(),
        transient + record,
        result.threads,
        secs / periods * 1e6
    );
    for f in result.failures() {
        eprintln!("warning: {label}: eta = {} failed: {}", f.value, f.error);
    }
    let path = g.out.join(format!("{label}_periods.csv"));
    let mut w = common::or_exit(CsvWriter::create(
        &path,
        &["eta", "period", "from_reset", "error"],
    ));
    for (v, c) in result.values.iter().zip(&result.columns) {
        let fields = match c {
            Ok(col) => [
                fmt_f64(*v),
                col.periodicity
                    .period()
                    .map_or("0".into(), |p| p.to_string()),
                col.from_reset.to_string(),
                String::new(),
            ],
            Err(e) => [fmt_f64(*v), String::new(), String::new(), e.to_string()],
        };
        common::or_exit(w.record(&fields));
    }
    common::or_exit(w.finish());
    let friction = g.friction.map_or(String::new(), |(mu, a)| {
        format!(", friction {mu}, shaft radius {a}")
    });
    println!(
        "{label} (D = {}{friction}): changes of the detected period (tol {tol}):",
        base.dx
    );
    for c in result.period_changes() {
        println!(
            "  between eta = {:.4} and {:.4}: {} -> {}",
            c.from, c.to, c.at_from, c.at_to
        );
    }
    let pts = result.points(0);
    let (eta_min, eta_max) = g.eta_range;
    let mut fig = Figure::new(
        &format!(
            "Fig. 8{}: x(2πk/η), D = {}, ν₁ = {}, ν₂ = {}, K = {}, β = {}, eₓ = {}, φ₀ = {}{friction}; {transient}+{record} periods, {}",
            g.d, base.dx, base.nu1, base.nu2, base.kx, base.beta, base.ex, base.phi0, g.mode_text
        ),
        "η = Ω/ωₙ",
        "x (rotor, units of the gap γ)",
    )
    .with_columns("eta", "x")
    .with_size(1600, 1000)
    .with_x_range(eta_min, eta_max.max(eta_min + 1e-9));
    if g.marks {
        for &(_, v, l) in PAPER_MARKS.iter().filter(|m| m.0 == g.d) {
            if (eta_min..=eta_max).contains(&v) {
                fig = fig.with_mark(v, &format!("paper {l}"));
            }
        }
    }
    let png = g.out.join(format!("{label}.png"));
    common::or_exit(plot::bifurcation(&png, &fig, &pts));
    eprintln!("wrote {} ({} points)", png.display(), pts.len());
}
