//! Work-precision diagrams of the hybrid simulation: DOP853, DOPRI5, RADAU5 and RK4 on four fixed scenes.
//!
//! For each scene the run goes from rest (all states 0) to the end of the horizon; the error is
//! the largest component of the state error at the end against a reference, and the largest
//! error of the contact onset / loss times against the reference's event log. The reference is
//! DOP853 at `rtol = 1e-13, atol = 1e-15`, confirmed by DOPRI5 at the same tolerance and, for
//! the Fig. 8 scenes, by the committed independent references in `tests/data` (SciPy DOP853 at
//! rtol 1e-13); the confirmation numbers are printed and written to `reference.csv`.
//!
//! Scenes: `fig8a` (the paper's Fig. 8 values at η = 2.0, a period-1 orbit with contact),
//! `fig8b` (the same with preload 0.1), `stiff` (Fig. 8a values with K = 1000), `chaos`
//! (η = 2.442, chaotic, over 10 periods only so that the reference is reproducible).
//!
//! Work is the wall time (minimum over `--repeat` runs) and the number of right-hand-side
//! evaluations (integrated contact phases; the exact free flight is not counted there but in
//! `exact_evals`, also written to the CSV).
//!
//! ```text
//! cargo run --release --example work_precision -- --out target/figures/work_precision
//! ```
//!
//! `--suite crossover` draws RADAU5 against DOP853 on the scenes of issue 19 instead
//! (`crossover.rs`: `crossover_results.csv`, `xo_<scene>.png`, `crossover.png`).
//!
//! Writes `results.csv`, `reference.csv` and per scene `wp_<scene>_time.png` and
//! `wp_<scene>_rhs.png` (with the CSV of each figure beside it) to `--out`.

#[path = "../common/mod.rs"]
mod common;
mod crossover;
// The shaft's other items serve its example and tests (problems.rs allows its own).
#[path = "../stiff_set/problems.rs"]
mod problems;
#[allow(dead_code)]
#[path = "../flexible_shaft/shaft.rs"]
mod shaft;

use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::Parser;
use common::cli::{parse, usize_in};
use common::csv::CsvWriter;
use common::plot::{self, Figure, LegendPosition, Series};
use jeffcott::hybrid::{EventRecord, OutputPlan, SimOptions, SimStats, StrobeRange};
use jeffcott::nalgebra::U6;
use jeffcott::ode::Method;
use jeffcott::paper::{guard, JeffcottModel, State};
use jeffcott::params::{Params, Preset};

/// A fixed test scene.
struct Scene {
    name: &'static str,
    title: &'static str,
    params: Params,
    periods: u64,
    /// Independent reference file in tests/data (stroboscopic rows), if any.
    data: Option<&'static str>,
}

fn scenes() -> Vec<Scene> {
    let fig8 = Preset::Fig8a.params();
    vec![
        Scene {
            name: "fig8a",
            title: "periodic orbit, Fig. 8 values, η = 2.0, D = 0, 50 periods",
            params: fig8,
            periods: 50,
            data: Some("fig8a_eta2.0.csv"),
        },
        Scene {
            name: "fig8b",
            title: "periodic orbit, Fig. 8 values, η = 2.0, D = 0.1, 50 periods",
            params: fig8.with_preload(0.1),
            periods: 50,
            data: Some("fig8b_eta2.0.csv"),
        },
        Scene {
            name: "stiff",
            title: "stiff ring K = 1000, Fig. 8 values, η = 2.0, 50 periods",
            params: fig8.with_stiffness(1000.0),
            periods: 50,
            data: None,
        },
        Scene {
            name: "chaos",
            title: "chaotic scene, Fig. 8 values, η = 2.442, D = 0, 10 periods",
            params: fig8.with_eta(2.442),
            periods: 10,
            data: None,
        },
    ]
}

/// One run's outcome.
struct RunResult {
    end: State,
    events: Vec<EventRecord<U6>>,
    stats: SimStats,
    seconds: f64,
}

fn run(scene: &Scene, opts: &SimOptions, repeat: usize) -> Result<RunResult, String> {
    let model = JeffcottModel::new(scene.params).map_err(|e| e.to_string())?;
    let t_end = scene.params.forcing_period() * scene.periods as f64;
    let plan = OutputPlan {
        t_end,
        strobe: Some(StrobeRange {
            first: scene.periods,
            last: scene.periods,
        }),
        dense: None,
        events: true,
    };
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..repeat.max(1) {
        let t0 = Instant::now();
        let r = model.run(0.0, &State::zeros(), &plan, opts);
        best = best.min(t0.elapsed().as_secs_f64());
        let (traj, stats) = r.map_err(|f| f.error.to_string())?;
        let end = traj
            .strobe
            .last()
            .ok_or_else(|| "no stroboscopic output".to_string())?
            .y;
        out = Some((end, traj.events, stats));
    }
    let (end, events, stats) = out.expect("at least one run");
    Ok(RunResult {
        end,
        events,
        stats,
        seconds: best,
    })
}

fn max_abs_diff(a: &State, b: &State) -> f64 {
    (a - b).iter().fold(0.0f64, |m, d| m.max(d.abs()))
}

/// Largest error of the onset / loss times: each reference event is matched to the nearest
/// event of the same kind. Returns `(max error, number of onset/loss events in the run minus
/// in the reference)`.
fn event_time_error(run: &[EventRecord<U6>], reference: &[EventRecord<U6>]) -> (f64, i64) {
    let is_contact = |e: &&EventRecord<U6>| e.kind == guard::ONSET || e.kind == guard::LOSS;
    let mine: Vec<&EventRecord<U6>> = run.iter().filter(is_contact).collect();
    let refs: Vec<&EventRecord<U6>> = reference.iter().filter(is_contact).collect();
    let mut worst = 0.0f64;
    for r in &refs {
        let d = mine
            .iter()
            .filter(|e| e.kind == r.kind)
            .map(|e| (e.t - r.t).abs())
            .fold(f64::INFINITY, f64::min);
        worst = worst.max(d);
    }
    (worst, mine.len() as i64 - refs.len() as i64)
}

/// The state at stroboscopic index `k` in an independent reference file of tests/data.
fn data_row(name: &str, k: u64) -> Option<State> {
    let path = format!("{}/tests/data/{name}", env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(path).ok()?;
    text.lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('k') && !l.is_empty())
        .find_map(|l| {
            let f: Vec<f64> = l.split(',').filter_map(|x| x.parse().ok()).collect();
            (f.len() >= 7 && f[0] as u64 == k).then(|| State::from_column_slice(&f[1..7]))
        })
}

fn opts_for(method: Method, tol: f64, steps: u32) -> SimOptions {
    SimOptions::default()
        .with_method(method)
        .with_rtol(tol)
        .with_atol(tol)
        .with_steps_per_period(steps)
}

/// Work-precision diagrams (error against wall time and right-hand-side evaluations) of
/// DOP853, DOPRI5, RADAU5 and RK4 on four fixed scenes of the Jeffcott rotor with snubber ring.
#[derive(Parser)]
#[command(name = "work_precision")]
struct Flags {
    /// Output folder
    #[arg(
        long,
        value_name = "DIR",
        default_value = "target/figures/work_precision"
    )]
    out: PathBuf,
    /// Runs per point; the minimum time is kept [range: 1..=1000]
    #[arg(long, value_name = "COUNT", default_value = "5", value_parser = usize_in(1, 1000))]
    repeat: usize,
    /// Which diagrams: `methods` (the four methods on the four scenes above) or `crossover`
    /// (RADAU5 against DOP853 on the paper's model, stiff rings, the flexible shaft in 8 to 64
    /// modes and the stiff set: `crossover.rs`)
    #[arg(long, default_value = "methods", value_parser = ["methods", "crossover"])]
    suite: String,
    /// One scene or all (methods: fig8a, fig8b, stiff, chaos; crossover: paper, ring1e4,
    /// ring1e6, shaft8, shaft16, shaft32, shaft64, vdpol, rober, orego, hires, e5)
    #[arg(long = "scene", default_value = "all", value_parser = scene_name)]
    only: String,
    /// Run once with METHOD:SETTING (dop853:1e-10, dopri5:1e-8, radau5:1e-8, rk4:400) and print the work
    /// done; no reference, no files (for instruction counts under valgrind)
    #[arg(long, value_name = "METHOD:SETTING")]
    single: Option<String>,
}

/// A `--scene` value: one of either suite's scenes, or `all`.
fn scene_name(s: &str) -> Result<String, String> {
    let methods = ["fig8a", "fig8b", "stiff", "chaos", "all"];
    if methods.contains(&s) || crossover::SCENES.contains(&s) {
        Ok(s.to_string())
    } else {
        Err(format!(
            "expected all, one of {} (--suite methods) or one of {} (--suite crossover)",
            methods[..4].join(", "),
            crossover::SCENES.join(", ")
        ))
    }
}

fn main() {
    let Flags {
        out,
        repeat,
        suite,
        only,
        single,
    } = parse();
    let crossover_scene = crossover::SCENES.contains(&only.as_str());
    if only != "all" && crossover_scene != (suite == "crossover") {
        common::cli::fail(format!("--scene {only} is not a scene of --suite {suite}"));
    }
    if suite == "crossover" {
        crossover::run(&out, &only, repeat);
        return;
    }
    if let Some(single) = single {
        run_single(&only, &single);
        return;
    }
    common::or_exit(std::fs::create_dir_all(&out));

    let tols: Vec<f64> = (3..=12).map(|e| 10f64.powi(-e)).collect();
    let rk4_steps: Vec<u32> = (0..10).map(|i| 50u32 << i).collect();

    let mut csv = common::or_exit(CsvWriter::create(
        out.join("results.csv"),
        &[
            "scene",
            "method",
            "tol_or_steps",
            "state_error",
            "event_error",
            "event_count_diff",
            "seconds",
            "rhs_evals",
            "exact_evals",
            "steps",
            "rejected",
            "transitions",
        ],
    ));
    let mut refcsv = common::or_exit(CsvWriter::create(
        out.join("reference.csv"),
        &[
            "scene",
            "dop853_vs_dopri5_state",
            "dop853_vs_dopri5_events",
            "dop853_vs_tests_data",
            "contact_events",
        ],
    ));

    for scene in scenes() {
        if only != "all" && only != scene.name {
            continue;
        }
        let ref_opts = opts_for(Method::Dop853, 1e-13, 1).with_atol(1e-15);
        let reference = common::or_exit(run(&scene, &ref_opts, 1));
        let check = common::or_exit(run(
            &scene,
            &opts_for(Method::Dopri5, 1e-13, 1).with_atol(1e-15),
            1,
        ));
        let dd = max_abs_diff(&reference.end, &check.end);
        let (de, dn) = event_time_error(&check.events, &reference.events);
        let data = scene
            .data
            .and_then(|d| data_row(d, scene.periods))
            .map_or(f64::NAN, |y| max_abs_diff(&reference.end, &y));
        let n_contact = reference
            .events
            .iter()
            .filter(|e| e.kind == guard::ONSET || e.kind == guard::LOSS)
            .count();
        println!(
            "{}: reference DOP853 1e-13 vs DOPRI5 1e-13: state {dd:.2e}, event times {de:.2e} \
             (count diff {dn}); vs tests/data: {data:.2e}; {n_contact} onset/loss events",
            scene.name
        );
        common::or_exit(refcsv.record(&[
            scene.name.to_string(),
            format!("{dd:e}"),
            format!("{de:e}"),
            format!("{data:e}"),
            n_contact.to_string(),
        ]));

        let mut by_time: Vec<Series> = Vec::new();
        let mut by_rhs: Vec<Series> = Vec::new();
        for method in Method::ALL {
            let settings: Vec<(f64, SimOptions)> = if method == Method::Rk4 {
                rk4_steps
                    .iter()
                    .map(|&n| (f64::from(n), opts_for(method, 1e-6, n)))
                    .collect()
            } else {
                tols.iter().map(|&t| (t, opts_for(method, t, 1))).collect()
            };
            let mut pts_time = Vec::new();
            let mut pts_rhs = Vec::new();
            for (setting, opts) in settings {
                match run(&scene, &opts, repeat) {
                    Ok(r) => {
                        let err = max_abs_diff(&r.end, &reference.end);
                        let (ev, dn) = event_time_error(&r.events, &reference.events);
                        println!(
                            "  {:7} {:>8} err {:9.2e} ev {:9.2e} ({:+}) {:9.3} ms rhs {:8} exact {:8}",
                            method.name(),
                            label(method, setting),
                            err,
                            ev,
                            dn,
                            r.seconds * 1e3,
                            r.stats.rhs_evals,
                            r.stats.exact_evals
                        );
                        common::or_exit(csv.record(&[
                            scene.name.to_string(),
                            method.name().to_string(),
                            format!("{setting:e}"),
                            format!("{err:e}"),
                            format!("{ev:e}"),
                            dn.to_string(),
                            format!("{:e}", r.seconds),
                            r.stats.rhs_evals.to_string(),
                            r.stats.exact_evals.to_string(),
                            r.stats.steps.to_string(),
                            r.stats.rejected.to_string(),
                            r.stats.transitions.to_string(),
                        ]));
                        // Errors below 1e-15 are plotted at 1e-15 (log axis).
                        let e = err.max(1e-15);
                        pts_time.push((r.seconds, e));
                        pts_rhs.push((r.stats.rhs_evals as f64, e));
                    }
                    Err(e) => {
                        println!(
                            "  {:7} {:>8} failed: {e}",
                            method.name(),
                            label(method, setting)
                        );
                        common::or_exit(csv.record(&[
                            scene.name.to_string(),
                            method.name().to_string(),
                            format!("{setting:e}"),
                            "NaN".into(),
                            "NaN".into(),
                            "0".into(),
                            "NaN".into(),
                            "0".into(),
                            "0".into(),
                            "0".into(),
                            "0".into(),
                            "0".into(),
                        ]));
                    }
                }
            }
            by_time.push(Series::new(method.name(), pts_time));
            by_rhs.push(Series::new(method.name(), pts_rhs));
        }
        figure(
            &out,
            &format!("wp_{}_time.png", scene.name),
            scene.title,
            "wall time per run [s]",
            &by_time,
        );
        figure(
            &out,
            &format!("wp_{}_rhs.png", scene.name),
            scene.title,
            "right-hand-side evaluations",
            &by_rhs,
        );
    }
    common::or_exit(csv.finish());
    common::or_exit(refcsv.finish());
}

/// `--single`: one run per selected scene, printing the end state and the work done.
fn run_single(only: &str, spec: &str) {
    let (m, v) = spec
        .split_once(':')
        .unwrap_or_else(|| common::cli::fail(format!("--single {spec}: expected METHOD:SETTING")));
    let v: f64 = v
        .parse()
        .unwrap_or_else(|_| common::cli::fail(format!("--single {spec}: bad setting")));
    let opts = match m {
        "dop853" => opts_for(Method::Dop853, v, 1),
        "dopri5" => opts_for(Method::Dopri5, v, 1),
        "radau5" => opts_for(Method::Radau5, v, 1),
        "rk4" if (1.0..=1e7).contains(&v) => opts_for(Method::Rk4, 1e-6, v as u32),
        _ => common::cli::fail(format!("--single {spec}: unknown method or bad setting")),
    };
    for scene in scenes() {
        if only != "all" && only != scene.name {
            continue;
        }
        let r = common::or_exit(run(&scene, &opts, 1));
        println!(
            "{} {spec}: end x = {:.15e}, {:?}, {:.3} ms",
            scene.name,
            r.end[0],
            r.stats,
            r.seconds * 1e3
        );
    }
}

/// The setting as printed: a tolerance, or RK4's steps per period.
fn label(method: Method, setting: f64) -> String {
    if method == Method::Rk4 {
        format!("{setting}")
    } else {
        format!("{setting:.0e}")
    }
}

fn figure(out: &Path, file: &str, title: &str, x_label: &str, series: &[Series]) {
    let fig = Figure::new(
        &format!("Work-precision: {title}"),
        x_label,
        "max state error at the end",
    )
    .with_columns("work", "error")
    .with_size(900, 600)
    .with_log(true, true)
    .with_markers()
    .with_legend(LegendPosition::UpperRight);
    common::or_exit(plot::lines(out.join(file), &fig, series));
}
