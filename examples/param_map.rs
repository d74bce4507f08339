//! Two-parameter maps: η against the preload D and η against the eccentricity eₓ, each run from
//! rest (the paper's zero initial conditions), coloured by the detected period, and a second
//! map by contacts per forcing period (and a third by the fraction of time in contact).
//!
//! `cargo run --release --example param_map` (no flags) draws both maps about the paper's
//! Fig. 8 values on 121 × 41 grids (η ∈ [2, 5]; D ∈ [0, 0.2]; eₓ ∈ [0.5, 1.1]) into
//! `target/figures/param_map/<map>/`: `period.png`, `contacts.png`, `contact_time.png` with
//! their CSV, and the sweep's records (`manifest.json`, `records-*.jsonl`). Killed part-way,
//! the same command resumes where it stopped. With `--features mpi` under `mpirun` or `srun`
//! the grid is split across the ranks; see `docs/global.md`. Without MPI, `--shard I/N` runs
//! one of N parts into the same folder (e.g. a task of a job array); the same command without
//! `--shard` then reads every point and draws.

#[path = "common/mod.rs"]
mod common;

use std::path::PathBuf;
use std::time::Instant;

use clap::Parser;
use common::cli::{f64_in, fail, parse, usize_in};
use common::plot::{self, Category, CategoryGrid, Figure, Grid};
use common::ranks::Ranks;
use common::{SweepRunFlags, Tolerances};
use jeffcott::analysis::StderrProgress;
use jeffcott::global::{AttractorOptions, Grid2, Manifest};
use jeffcott::hybrid::SimOptions;
use jeffcott::paper::{ParamPlane, SweepParameter};
use jeffcott::params::Params;
use jeffcott::params::Preset;
use jeffcott::stability::{continue_orbit, Branch, ContinuationOptions, SpecialKind};
use jeffcott::JeffcottModel;
use plotters::style::RGBColor;

/// The period classes of the map, with their colours.
fn period_classes() -> Vec<Category> {
    let c = |label: &str, (r, g, b): (u8, u8, u8)| Category {
        label: label.to_string(),
        colour: RGBColor(r, g, b),
    };
    vec![
        c("period 1", (31, 119, 180)),
        c("period 2", (44, 160, 44)),
        c("period 3", (255, 127, 14)),
        c("period 4", (148, 103, 189)),
        c("period 5", (140, 86, 75)),
        c("period 6", (188, 189, 34)),
        c("period 8", (23, 190, 207)),
        c("period 7 or 9-16", (227, 119, 194)),
        c("not periodic (up to 16)", (30, 30, 30)),
        c("failed", (214, 39, 40)),
    ]
}

/// The index in [`period_classes`] of a detected period (`Some(0)`: not periodic, `None`:
/// failed).
fn class_of(period: Option<usize>) -> usize {
    match period {
        Some(0) => 8,
        Some(p @ 1..=6) => p - 1,
        Some(8) => 6,
        Some(_) => 7,
        None => 9,
    }
}

/// Two-parameter maps of the rotor from rest: eta against the preload and against the
/// eccentricity, coloured by period and by contacts per period.
#[derive(Parser)]
#[command(name = "param_map")]
struct Flags {
    /// Output folder
    #[arg(long, value_name = "DIR", default_value = "target/figures/param_map")]
    out: PathBuf,
    /// Which map
    #[arg(long = "map", default_value = "both", value_parser = ["both", "preload", "ecc"])]
    which: String,
    /// Lowest eta [range: 0.01..=100]
    #[arg(long, value_name = "NUMBER", default_value = "2", value_parser = f64_in(0.01, 100.0))]
    eta_min: f64,
    /// Highest eta [range: 0.01..=100]
    #[arg(long, value_name = "NUMBER", default_value = "5", value_parser = f64_in(0.01, 100.0))]
    eta_max: f64,
    /// Number of eta values [range: 1..=1000000]
    #[arg(long, value_name = "COUNT", default_value = "121", value_parser = usize_in(1, 1_000_000))]
    n_eta: usize,
    /// Preload map: highest D (from 0) [range: 0..=10]
    #[arg(long = "preload-max", value_name = "NUMBER", default_value = "0.2", value_parser = f64_in(0.0, 10.0))]
    d_max: f64,
    /// Eccentricity map: lowest e_x [range: -10..=10]
    #[arg(long = "ecc-min", value_name = "NUMBER", default_value = "0.5", value_parser = f64_in(-10.0, 10.0))]
    e_min: f64,
    /// Eccentricity map: highest e_x [range: -10..=10]
    #[arg(long = "ecc-max", value_name = "NUMBER", default_value = "1.1", value_parser = f64_in(-10.0, 10.0))]
    e_max: f64,
    /// Number of values of D or e_x [range: 1..=1000000]
    #[arg(long, value_name = "COUNT", default_value = "41", value_parser = usize_in(1, 1_000_000))]
    n_y: usize,
    /// Forcing periods discarded [range: 1..=10000000]
    #[arg(long, value_name = "COUNT", default_value = "500", value_parser = usize_in(1, 10_000_000))]
    transient: usize,
    /// Stroboscopic points tested [range: 32..=1000000]
    #[arg(long, value_name = "COUNT", default_value = "64", value_parser = usize_in(32, 1_000_000))]
    record: usize,
    /// A run with no period goes on until its transients add up to this
    /// [range: 1..=100000000]
    #[arg(long, value_name = "COUNT", default_value = "1500", value_parser = usize_in(1, 100_000_000))]
    max_transient: usize,
    #[command(flatten)]
    tol: Tolerances,
    #[command(flatten)]
    run: SweepRunFlags,
    /// Draw the continuation's bifurcation curves over the period map
    #[arg(long, default_value = "yes", value_parser = ["yes", "no"])]
    overlay: String,
}

fn main() {
    let ranks = Ranks::init();
    let Flags {
        out,
        which,
        eta_min,
        eta_max,
        n_eta,
        d_max,
        e_min,
        e_max,
        n_y,
        transient,
        record,
        max_transient,
        tol,
        run,
        overlay,
    } = parse();
    let (rtol, atol) = tol.get();
    let shard = run.shard;
    if shard.is_some() && ranks.size > 1 {
        fail("--shard splits a sweep into independent processes: run it without mpirun/srun -n, or run the whole sweep with MPI");
    }
    let run = run.config();
    let overlay = overlay == "yes";
    if eta_min >= eta_max || e_min >= e_max {
        fail("each axis needs its lowest value below its highest");
    }
    if max_transient < transient {
        fail("--max-transient must be at least --transient");
    }
    let config = AttractorOptions::default()
        .with_transient(transient as u64)
        .with_record(record as u64)
        .with_max_transient(max_transient as u64)
        .with_opts(SimOptions::default().with_rtol(rtol).with_atol(atol));
    let base = Preset::Fig8a.params();
    let maps = [
        (
            "preload",
            SweepParameter::Preload,
            (0.0, d_max),
            "D (preload)",
        ),
        (
            "ecc",
            SweepParameter::Ex,
            (e_min, e_max),
            "eₓ (eccentricity)",
        ),
    ];
    for (name, param, (lo, hi), y_label) in
        maps.into_iter().filter(|m| which == "both" || m.0 == which)
    {
        let grid = common::or_exit(Grid2::linspace((eta_min, eta_max, n_eta), (lo, hi, n_y)));
        let plane = ParamPlane::new(base, SweepParameter::Eta, param);
        let dir = out.join(name);
        // The folder records the grid and every setting of `config`; the description, the
        // plane, adds the model's parameters.
        let manifest = common::or_exit(Manifest::scan("param_map", &plane, &grid, &config));
        let store = common::or_exit(ranks.open_store(&dir, manifest));
        let progress = StderrProgress::new(format!("map eta x {}", param.symbol()));
        let t0 = Instant::now();
        let scan = common::or_exit(ranks.scan_grid(
            &grid,
            plane.setup(),
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
                "{name}: shard {shard}: {} points computed, {} recorded in all, {} to go in {}; when every shard has finished, run again without --shard to draw",
                r.computed,
                r.results.len() - r.missing(),
                r.missing(),
                dir.display(),
            );
            continue;
        }
        let secs = t0.elapsed().as_secs_f64();
        let r = &scan.results;
        eprintln!(
            "{name}: {} points computed, {} reused, {} missing; {secs:.1} s wall on {} rank(s) x {} thread(s)",
            r.computed,
            r.reused,
            r.missing(),
            ranks.size,
            r.threads
        );
        for (i, e) in r.failures().take(5) {
            eprintln!(
                "warning: {name}: point {i} {:?} failed: {e}",
                scan.grid.point(i)
            );
        }
        let classes = period_classes();
        let cells: Vec<Option<usize>> = scan
            .periods()
            .iter()
            .zip(&r.results)
            .map(|(p, slot)| slot.as_ref().map(|_| class_of(*p)))
            .collect();
        let mut counts = vec![0usize; classes.len()];
        for c in cells.iter().flatten() {
            counts[*c] += 1;
        }
        let legend: Vec<Category> = classes
            .into_iter()
            .zip(&counts)
            .filter(|&(_, &n)| n > 0)
            .map(|(c, n)| Category {
                label: format!("{} ({n})", c.label),
                ..c
            })
            .collect();
        // Re-index the cells to the legend's kept classes.
        let kept: Vec<usize> = (0..counts.len()).filter(|&k| counts[k] > 0).collect();
        let cells: Vec<Option<usize>> = cells
            .iter()
            .map(|c| c.and_then(|k| kept.iter().position(|&j| j == k)))
            .collect();
        println!(
            "{name}: {} points; {}",
            cells.len(),
            legend
                .iter()
                .map(|c| c.label.clone())
                .collect::<Vec<_>>()
                .join(", ")
        );
        let title = |what: &str| {
            format!(
                "{what}, from rest: Fig. 8 values (ν₁ = {}, K = {}, β = {}, {}), {transient}+{record} periods (up to {max_transient})",
                base.nu1,
                base.kx,
                base.beta,
                if name == "preload" { format!("eₓ = {}", base.ex) } else { "D = 0".to_string() },
            )
        };
        let curves = if overlay {
            overlays(name, &base, &scan.grid)
        } else {
            Vec::new()
        };
        let fig = |what: &str| {
            let mut f = Figure::new(&title(what), "η = Ω/ωₙ", y_label)
                .with_columns("eta", param.symbol())
                .with_size(1600, 900);
            for (label, pts) in &curves {
                f = f.with_overlay(label, pts.clone());
            }
            f
        };
        let png = dir.join("period.png");
        common::or_exit(plot::category_map(
            &png,
            &fig("Detected period"),
            &CategoryGrid {
                xs: scan.grid.x.clone(),
                ys: scan.grid.y.clone(),
                cells,
            },
            &legend,
        ));
        for (file, what, values, bar) in [
            (
                "contacts.png",
                "Contacts per forcing period",
                scan.contacts_per_period(),
                "contacts per period",
            ),
            (
                "contact_time.png",
                "Fraction of time in contact",
                scan.stat(|a| a.stats.contact_fraction),
                "time in contact",
            ),
        ] {
            common::or_exit(plot::heatmap(
                dir.join(file),
                &fig(what),
                &Grid {
                    xs: scan.grid.x.clone(),
                    ys: scan.grid.y.clone(),
                    values,
                    z_range: None,
                },
                bar,
            ));
        }
        eprintln!(
            "wrote {} (and contacts.png, contact_time.png)",
            png.display()
        );
    }
}

/// Bifurcation curves from the continuation, over the map: for the preload map the flips of
/// the period-1 orbit (followed in η from 2) and of the period-2 orbit (from 3), at each of
/// 11 preloads; for the eccentricity map the grazing of the orbit without contact (followed
/// in eₓ from 0.5 at each of 13 η) next to its analytic curve eₓ = 1 − A(η).
fn overlays(map: &str, base: &Params, grid: &Grid2) -> Vec<(String, Vec<(f64, f64)>)> {
    let config = ContinuationOptions::default();
    let first = |b: &Branch, kind| {
        // A located point only: an unconverged bracket is not a point of the curve.
        b.specials
            .iter()
            .find(|s| s.kind == kind && s.converged)
            .map(|s| s.parameter)
    };
    let (y0, y1) = (grid.y[0], grid.y[grid.y.len() - 1]);
    if map == "preload" {
        let mut flip1 = Vec::new();
        let mut flip2 = Vec::new();
        for i in 0..11 {
            let d = y0 + (y1 - y0) * i as f64 / 10.0;
            let p = base.with_preload(d);
            let build = |eta: f64| JeffcottModel::new(p.with_eta(eta));
            for (eta0, to, period, out) in [(2.0, 2.5, 1, &mut flip1), (3.0, 4.5, 2, &mut flip2)] {
                let Ok(model) = build(eta0) else { continue };
                let Ok(y) = model.state_at([0.0; 2], [0.0; 2]) else {
                    continue;
                };
                let Ok((traj, _)) = model.strobe_range(&y, 600, 600, &config.sim) else {
                    continue;
                };
                let Some(guess) = traj.strobe.last().map(|s| s.y) else {
                    continue;
                };
                if let Ok(b) = continue_orbit(build, eta0, to, &guess, period, &config)
                    && let Some(e) = first(&b, SpecialKind::Flip)
                {
                    out.push((e, d));
                }
            }
        }
        vec![
            ("flip of period 1".to_string(), flip1),
            ("flip of period 2".to_string(), flip2),
        ]
    } else {
        let (x0, x1) = (grid.x[0], grid.x[grid.x.len() - 1]);
        let analytic: Vec<(f64, f64)> = (0..=60)
            .map(|i| {
                let eta = x0 + (x1 - x0) * i as f64 / 60.0;
                let (re, im) = (1.0 - eta * eta, 2.0 * base.nu1 * eta);
                (eta, 1.0 - base.beta * eta * eta / re.hypot(im))
            })
            .collect();
        let mut graze = Vec::new();
        for i in 0..13 {
            let eta = x0 + (x1 - x0) * i as f64 / 12.0;
            let p = base.with_eta(eta);
            let build = |ex: f64| {
                let mut q = p;
                q.ex = ex;
                JeffcottModel::new(q)
            };
            let Ok(model) = build(y0) else { continue };
            let Ok(y) = model.state_at([y0, 0.0], [0.0; 2]) else {
                continue;
            };
            let Ok((traj, _)) = model.strobe_range(&y, 600, 600, &config.sim) else {
                continue;
            };
            let Some(guess) = traj.strobe.last().map(|s| s.y) else {
                continue;
            };
            if let Ok(b) = continue_orbit(build, y0, y1, &guess, 1, &config)
                && let Some(e) = first(&b, SpecialKind::Grazing)
            {
                graze.push((eta, e));
            }
        }
        println!("ecc: grazing of the orbit without contact, continuation vs 1 - A(eta):");
        for &(eta, e) in &graze {
            let (re, im) = (1.0 - eta * eta, 2.0 * base.nu1 * eta);
            let a = base.beta * eta * eta / re.hypot(im);
            println!(
                "  eta = {eta:.3}: e_x = {e:.9} (analytic {:.9}, difference {:.1e})",
                1.0 - a,
                e - (1.0 - a)
            );
        }
        vec![
            ("grazing, e + A(η) = 1".to_string(), analytic),
            ("grazing (continuation)".to_string(), graze),
        ]
    }
}
