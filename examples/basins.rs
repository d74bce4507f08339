//! Basins of attraction: which attractor the rotor settles on from each initial state of a
//! grid, the attractors matched across the grid and drawn in colour with a legend.
//!
//! `cargo run --release --example basins` (no flags) draws the three multistable scenes of
//! `docs/global.md` on 100 × 100 grids of (x₀, x₀′), y₀ = y₀′ = 0:
//!
//! * `fig8a-eta2.2`: the paper's Fig. 8 values without preload at η = 2.2 (period 1 and the
//!   period-3 orbit born in a fold at η = 2.126);
//! * `fig8b-eta2.2`: the same with preload D = 0.1;
//! * `fig10a-eta2.5`: the Fig. 10a values (η = 2.5).
//!
//! Each scene's folder under `--out` (default `target/figures/basins`) holds the sweep's records
//! (`manifest.json`, `records-*.jsonl`: one JSON object per grid point, written as it finishes),
//! the picture `basins.png`, its data `basins.csv` (x, y, attractor) and `attractors.csv` (one
//! line per attractor: period, canonical point, basin size, contacts per period). **Killed
//! part-way, the same command resumes**: the points already in the folder are not run again
//! (delete the folder to start over). Built with `--features mpi` and started by `mpirun` or
//! `srun`, the grid is split across the ranks (rank 0 draws); see `docs/global.md`. Without
//! MPI, `--shard I/N` runs one of N parts into the same folder (e.g. a task of a job array);
//! the same command without `--shard` then reads every point and draws.

#[path = "common/mod.rs"]
mod common;

use std::path::PathBuf;
use std::time::Instant;

use clap::Parser;
use common::cli::{f64_in, fail, num, parse, usize_in};
use common::csv::{fmt_f64, CsvWriter};
use common::plot::{self, Category, CategoryGrid, Figure};
use common::ranks::Ranks;
use common::{SweepRunFlags, Tolerances};
use jeffcott::analysis::{PeriodTest, StderrProgress};
use jeffcott::global::{attractor_at, AttractorOptions, Grid2, Manifest, MatchOptions, PointLabel};
use jeffcott::hybrid::SimOptions;
use jeffcott::paper::{BasinPlane, StartPlane};
use jeffcott::params::{Params, Preset};

/// A named scene: preset and its default eta.
const SCENES: [(&str, Preset, f64); 3] = [
    ("fig8a", Preset::Fig8a, 2.2),
    ("fig8b", Preset::Fig8b, 2.2),
    ("fig10a", Preset::Fig10a, 2.5),
];

/// Basins of attraction of the rotor on a grid of initial states, attractors matched and drawn
/// in colour.
#[derive(Parser)]
#[command(name = "basins")]
struct Flags {
    /// Output folder
    #[arg(long, value_name = "DIR", default_value = "target/figures/basins")]
    out: PathBuf,
    /// Parameter set: the paper's Fig. 8a (D = 0), Fig. 8b (D = 0.1) or Fig. 10a values
    #[arg(long, default_value = "all", value_parser = ["all", "fig8a", "fig8b", "fig10a"])]
    scene: String,
    /// Frequency ratio (default: 2.2 for fig8a/fig8b, 2.5 for fig10a); needs one --scene
    /// [range: 0.01..=100]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(0.01, 100.0))]
    eta: Option<f64>,
    /// Preload D = Dx = Dy (default: the scene's); needs one --scene [range: 0..=10]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(0.0, 10.0))]
    preload: Option<f64>,
    /// Initial states varied: x0 against x0' (y0 = y0' = 0), x0 against y0 (at rest), or the
    /// phase phi0 against x0 (at rest)
    #[arg(long, default_value = "x-vx", value_parser = ["x-vx", "x-y", "phi-x"])]
    plane: String,
    /// Horizontal axis: lowest value (default: -1; 0 for phi-x) [range: -100..=100]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(-100.0, 100.0))]
    h_min: Option<f64>,
    /// Horizontal axis: highest value (default: 1; 2 pi for phi-x) [range: -100..=100]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(-100.0, 100.0))]
    h_max: Option<f64>,
    /// Vertical axis: lowest value (default: -1.5 for x-vx, -1 otherwise) [range: -100..=100]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(-100.0, 100.0))]
    v_min: Option<f64>,
    /// Vertical axis: highest value (default: 1.5 for x-vx, 1 otherwise) [range: -100..=100]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(-100.0, 100.0))]
    v_max: Option<f64>,
    /// Grid points along the horizontal axis [range: 1..=100000]
    #[arg(long, value_name = "COUNT", default_value = "100", value_parser = usize_in(1, 100_000))]
    n: usize,
    /// Grid points along the vertical axis (default: --n) [range: 1..=100000]
    #[arg(long, value_name = "COUNT", value_parser = usize_in(1, 100_000))]
    nv: Option<usize>,
    /// Forcing periods discarded before each recording [range: 1..=10000000]
    #[arg(long, value_name = "COUNT", value_parser = usize_in(1, 10_000_000),
          default_value = AttractorOptions::default().transient.to_string())]
    transient: usize,
    /// Stroboscopic points recorded and tested for a period (periods up to 16)
    /// [range: 32..=1000000]
    #[arg(long, value_name = "COUNT", value_parser = usize_in(32, 1_000_000),
          default_value = AttractorOptions::default().record.to_string())]
    record: usize,
    /// A run with no period goes on until its transients add up to this
    /// [range: 1..=100000000]
    #[arg(long, value_name = "COUNT", value_parser = usize_in(1, 100_000_000),
          default_value = AttractorOptions::default().max_transient.to_string())]
    max_transient: usize,
    /// Periodic attractors match when their cycle points agree to this (every component)
    /// [range: 1e-12..=1]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(1e-12, 1.0),
          default_value = num(MatchOptions::default().state))]
    match_tol: f64,
    #[command(flatten)]
    tol: Tolerances,
    #[command(flatten)]
    run: SweepRunFlags,
}

fn main() {
    let ranks = Ranks::init();
    let Flags {
        out,
        scene,
        eta,
        preload,
        plane,
        h_min,
        h_max,
        v_min,
        v_max,
        n,
        nv,
        transient,
        record,
        max_transient,
        match_tol,
        tol: tolerances,
        run,
    } = parse();
    let (rtol, atol) = tolerances.get();
    let shard = run.shard;
    if shard.is_some() && ranks.size > 1 {
        fail("--shard splits a sweep into independent processes: run it without mpirun/srun -n, or run the whole sweep with MPI");
    }
    let run = run.config();
    let (dh, dv) = match plane.as_str() {
        "x-y" => ((-1.0, 1.0), (-1.0, 1.0)),
        "phi-x" => ((0.0, std::f64::consts::TAU), (-1.0, 1.0)),
        _ => ((-1.0, 1.0), (-1.5, 1.5)),
    };
    let (h_min, h_max) = (h_min.unwrap_or(dh.0), h_max.unwrap_or(dh.1));
    let (v_min, v_max) = (v_min.unwrap_or(dv.0), v_max.unwrap_or(dv.1));
    // Unset values as NaN below.
    let (eta, preload) = (eta.unwrap_or(f64::NAN), preload.unwrap_or(f64::NAN));
    if scene == "all" && !(eta.is_nan() && preload.is_nan()) {
        fail("--eta and --preload need one --scene");
    }
    if h_min >= h_max || v_min >= v_max {
        fail("each axis needs its lowest value below its highest");
    }
    if max_transient < transient {
        fail("--max-transient must be at least --transient");
    }
    let start_plane = match plane.as_str() {
        "x-y" => StartPlane::XY,
        "phi-x" => StartPlane::PhaseX,
        _ => StartPlane::XVx,
    };
    let config = AttractorOptions::default()
        .with_transient(transient as u64)
        .with_record(record as u64)
        .with_max_transient(max_transient as u64)
        .with_opts(SimOptions::default().with_rtol(rtol).with_atol(atol))
        .with_period_test(PeriodTest::default());
    let tol = MatchOptions::default().with_state(match_tol);
    let grid = common::or_exit(Grid2::linspace(
        (h_min, h_max, n),
        (v_min, v_max, nv.unwrap_or(n)),
    ));

    for &(name, preset, default_eta) in SCENES.iter().filter(|s| scene == "all" || s.0 == scene) {
        let mut params: Params = preset.params();
        params.eta = if eta.is_nan() { default_eta } else { eta };
        if !preload.is_nan() {
            params = params.with_preload(preload);
        }
        let label = format!("{name}-eta{}", params.eta);
        let dir = out.join(&label);
        let basin = BasinPlane::new(params, start_plane);
        // The folder records the grid and every setting of `config`; the description, the
        // plane, adds the model's parameters.
        let manifest = common::or_exit(Manifest::scan("basins", &basin, &grid, &config));
        let store = common::or_exit(ranks.open_store(&dir, manifest));
        let progress = StderrProgress::new(if ranks.size > 1 {
            format!("{label} (rank 0 of {})", ranks.size)
        } else if let Some(s) = shard {
            format!("{label} (shard {s})")
        } else {
            label.clone()
        });
        let t0 = Instant::now();
        let scan = common::or_exit(ranks.scan_grid(
            &grid,
            basin.setup(),
            &config,
            Some(&store),
            &run,
            ranks.is_root().then_some(&progress as _),
        ));
        let Some(scan) = scan else { continue };
        if let Some(shard) = shard {
            // One part of the sweep: the figures wait for the whole (a run without --shard).
            let r = &scan.results;
            eprintln!(
                "{label}: shard {shard}: {} points computed, {} recorded in all, {} to go in {}; when every shard has finished, run again without --shard to draw",
                r.computed,
                r.results.len() - r.missing(),
                r.missing(),
                dir.display(),
            );
            continue;
        }
        let secs = t0.elapsed().as_secs_f64();
        let r = &scan.results;
        let periods: u64 = r.successes().map(|(_, a)| a.stats.periods_run).sum();
        eprintln!(
            "{label}: {} points computed, {} reused from {}, {} missing; {secs:.1} s wall on {} rank(s) x {} thread(s)",
            r.computed,
            r.reused,
            dir.display(),
            r.missing(),
            ranks.size,
            r.threads,
        );
        if r.computed == r.results.len() && periods > 0 {
            eprintln!(
                "{label}: {periods} forcing periods in all, {:.1} µs per period (wall)",
                secs / periods as f64 * 1e6
            );
        }
        for (i, e) in r.failures().take(5) {
            eprintln!(
                "warning: {label}: point {i} {:?} failed: {e}",
                scan.grid.point(i)
            );
        }
        let cat = scan.catalogue(&tol);
        let total = cat.labels.len() as f64;
        let (hn, vn) = start_plane.names();
        println!(
            "{label}: {} attractor(s) on {} x {} points of ({hn}, {vn}), match tolerance {match_tol}:",
            cat.entries.len(),
            scan.grid.x.len(),
            scan.grid.y.len()
        );
        // Where the paper's run from rest goes (the rest state need not be a grid point).
        let rest_point = match start_plane {
            StartPlane::PhaseX => [params.phi0, 0.0],
            _ => [0.0, 0.0],
        };
        let rest = attractor_at(&basin.setup(), &rest_point, &config);
        let rest_k = rest.as_ref().ok().and_then(|a| {
            cat.entries
                .iter()
                .position(|e| e.attractor.matches(a, &tol))
        });
        match (&rest, rest_k) {
            (Ok(_), Some(k)) => println!("  from rest: A{k}"),
            (Ok(a), None) => println!("  from rest: {} (not reached from the grid)", a.describe()),
            (Err(e), _) => println!("  from rest: failed: {e}"),
        }
        let mut legend: Vec<Category> = Vec::new();
        for (k, e) in cat.entries.iter().enumerate() {
            let pct = 100.0 * e.count as f64 / total;
            println!(
                "  A{k}: {} — {} points ({pct:.1} %)",
                e.attractor.describe(),
                e.count
            );
            let short = match (e.attractor.period(), e.attractor.canonical()) {
                (Some(p), Some(z)) => format!("P{p}, x = {:.4}, x′ = {:.4}", z[0], z[2]),
                _ => format!(
                    "not periodic, {:.2} contacts/T",
                    e.attractor.stats.contacts_per_period
                ),
            };
            let from_rest = if rest_k == Some(k) { ", from rest" } else { "" };
            legend.push(Category {
                label: format!("A{k}: {short} ({pct:.1} %{from_rest})"),
                colour: plot::series_colour(k),
            });
        }
        let failed = cat.failed();
        if failed > 0 {
            println!("  failed: {failed} points");
        }
        let failed_k = legend.len();
        legend.push(Category {
            label: format!("failed ({failed})"),
            colour: plotters_black(),
        });
        let cells: Vec<Option<usize>> = cat
            .labels
            .iter()
            .map(|l| match l {
                PointLabel::Attractor(k) => Some(*k),
                PointLabel::Failed => Some(failed_k),
                PointLabel::NotRun => None,
            })
            .collect();
        if failed == 0 {
            legend.pop();
        }
        let fig = Figure::new(
            &format!(
                "Basins, {name} values: η = {}, D = {}, e = ({}, {}), ν₁ = {}; {transient}+{record} periods (up to {max_transient})",
                params.eta, params.dx, params.ex, params.ey, params.nu1
            ),
            plot::symbol(hn),
            plot::symbol(vn),
        )
        .with_columns(hn, vn)
        .with_size(1500, 1000)
        .with_pin(rest_point[0], rest_point[1], "rest");
        let png = dir.join("basins.png");
        common::or_exit(plot::category_map(
            &png,
            &fig,
            &CategoryGrid {
                xs: scan.grid.x.clone(),
                ys: scan.grid.y.clone(),
                cells,
            },
            &legend,
        ));
        // One line per attractor.
        let mut w = common::or_exit(CsvWriter::create(
            dir.join("attractors.csv"),
            &[
                "attractor",
                "period",
                "points",
                "fraction",
                "contacts_per_period",
                "contact_fraction",
                "x",
                "y",
                "vx",
                "vy",
                "first_point",
            ],
        ));
        for (k, e) in cat.entries.iter().enumerate() {
            let a = &e.attractor;
            let z = a.canonical().map_or(vec![f64::NAN; 4], |z| z.to_vec());
            common::or_exit(w.record(&[
                format!("A{k}"),
                a.period().map_or("0".into(), |p| p.to_string()),
                e.count.to_string(),
                fmt_f64(e.count as f64 / total),
                fmt_f64(a.stats.contacts_per_period),
                fmt_f64(a.stats.contact_fraction),
                fmt_f64(z[0]),
                fmt_f64(z[1]),
                fmt_f64(z[2]),
                fmt_f64(z[3]),
                e.first.to_string(),
            ]));
        }
        common::or_exit(w.finish());
        eprintln!("wrote {}", png.display());
    }
}

fn plotters_black() -> plotters::style::RGBColor {
    plotters::style::RGBColor(30, 30, 30)
}
