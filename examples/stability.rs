//! Stability of the rotor's orbits: periodic orbits and their Floquet multipliers, Lyapunov
//! exponents, and where a periodic orbit loses stability along η. Prints exactly one JSON
//! object on standard output, for scripts; `pictures` draws figures instead.
//!
//! Modes (subcommands, one of them; `stability MODE --help` lists its flags):
//!
//! * `orbit --period N [--transient T]`: runs T forcing periods from the initial state, then
//!   finds the period-N orbit by Newton's method on P^N(z) - z with the Jacobian of the
//!   variational equations:
//!   `{"period": N, "point": [x, y, vx, vy], "residual": r, "multipliers": [[re, im], ...],
//!   "contacts": c, "min_depth": d, "grazing_margin": g, ...}`, multipliers sorted by
//!   modulus, largest first; `min_depth` the smallest contact depth and `grazing_margin` the
//!   closest free-flight approach to contact (`null` when there is none); with
//!   `--friction MU --shaft-radius A` (A in gaps) the rotor with Coulomb friction at the ring
//!   (`paper::rub::rubbing_model`), whose section must fall in free flight (the slip's sense
//!   and the roll's direction are the contact's history; `--phi0` moves the section);
//! * `lyapunov --transient T --periods P`: the Lyapunov spectrum per forcing period by the
//!   QR method, its batch-means standard error, and the largest exponent by the
//!   two-trajectory method: `{"lambda": [l1, l2, l3, l4], "stderr": [...],
//!   "lambda1_two_trajectory": v, "stderr_two_trajectory": e, ...}`;
//! * `locate-loss --from A --to B --period N`: finds the period-N orbit at η = A (after
//!   the transient), continues it towards η = B and prints the first loss of stability:
//!   `{"eta": value, "kind": "flip" | "fold" | "neimark-sacker" | "grazing",
//!   "multipliers": [...], "bracket": [a, b], ...}` (`"eta": null` if it stays stable; if
//!   the continuation stops on an error, `"eta": null` with `"failure"`, the error,
//!   `"failed_at"` and `"last_eta"`, the last orbit's parameter);
//! * `pictures [--out DIR]`: the largest multiplier modulus of the period-1 orbit against
//!   η up to its loss of stability (both preloads), and the largest Lyapunov exponent against
//!   η over [2, 5] drawn above the bifurcation diagram from the same runs, for D = 0 and
//!   D = 0.1 (`--values`, `--periods`, `--transient` set the resolution).
//!
//! Every mode takes the scene flags of `simulate` (`--preset`, parameter overrides, `--rtol`,
//! `--atol`, `--method`, the initial state `--x0 --y0 --vx0 --vy0`). Exit status: 0 on success;
//! 2 with one `error: ...` line on standard error for bad input; 1 with one line if the
//! computation fails (e.g. Newton does not converge: the line gives the last residual).
//!
//! ```text
//! cargo run --release --example stability -- orbit --period 1 --eta 2
//! cargo run --release --example stability -- lyapunov --eta 2.442 --transient 500 --periods 5000
//! cargo run --release --example stability -- locate-loss --from 2 --to 2.3 --period 1 --preset fig8b
//! cargo run --release --example stability -- pictures
//! ```

#[path = "common/mod.rs"]
mod common;

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand};
use common::cli::{f64_in, fail, parse, usize_in};
use common::or_exit;
use common::plot::{self, Figure, Series};
use common::scene::{Scene, SceneFlags};
use jeffcott::analysis::{linspace, sweep, SweepOptions};
use jeffcott::hybrid::VariationalAlloc;
use jeffcott::nalgebra::DVector;
use jeffcott::paper::rub::rubbing_model;
use jeffcott::paper::{JeffcottModel, State};
use jeffcott::params::Params;
use jeffcott::stability::{
    locate_loss, lyapunov_exponents, periodic_orbit, LossOptions, LyapunovOptions, Multiplier,
    OrbitOptions, PeriodicOrbit, StroboscopicMap,
};
use serde_json::{json, Value};

fn multipliers_json(m: &[Multiplier]) -> Value {
    Value::Array(m.iter().map(|m| json!([m.re, m.im])).collect())
}

/// A finite number, or `null`.
fn num(v: Option<f64>) -> Value {
    v.filter(|v| v.is_finite())
        .map_or(Value::Null, |v| json!(v))
}

/// The state after `transient` periods from the scene's initial state.
fn after_transient(model: &JeffcottModel, scene: &Scene, transient: u64) -> State {
    let [x, y, vx, vy] = scene.start;
    let start = model
        .state_at([x, y], [vx, vy])
        .unwrap_or_else(|e| fail(format!("initial state: {e}")));
    if transient == 0 {
        return start;
    }
    let map = or_exit(StroboscopicMap::new(model, transient, scene.opts));
    or_exit(map.advance(&start)).y
}

/// Stability of the rotor's orbits, printed as one JSON object (pictures: figures).
#[derive(Parser)]
#[command(name = "stability", arg_required_else_help = false)]
struct Flags {
    #[command(subcommand)]
    mode: Mode,
}

/// `--transient`, shared by every mode.
#[derive(Args)]
struct Transient {
    /// Periods run from the initial state before anything [range: 0..=100000000]
    #[arg(long, value_name = "COUNT", default_value = "300", value_parser = usize_in(0, 100_000_000))]
    transient: usize,
}

/// `--friction` and `--shaft-radius`: Coulomb friction at the ring.
#[derive(Args)]
struct Friction {
    /// Coulomb friction coefficient between ring and shaft (0: the paper's frictionless
    /// model) [range: 0..=1000]
    #[arg(long, value_name = "NUMBER", default_value = "0", value_parser = f64_in(0.0, 1e3))]
    friction: f64,
    /// Shaft radius at the ring, in gaps (required with --friction > 0) [range: 0..=1000]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(0.0, 1e3))]
    shaft_radius: Option<f64>,
}

/// `--period`, the period of the orbit.
#[derive(Args)]
struct Period {
    /// Period N of the orbit (forcing periods) [range: 1..=10000]
    #[arg(long, value_name = "COUNT", default_value = "1", value_parser = usize_in(1, 10_000))]
    period: usize,
}

/// `--periods`, the recorded periods of the Lyapunov exponents.
#[derive(Args)]
struct Periods {
    /// Periods recorded for the Lyapunov exponents [range: 1..=100000000]
    #[arg(long, value_name = "COUNT", default_value = "2000", value_parser = usize_in(1, 100_000_000))]
    periods: usize,
}

/// `--step`, the continuation step in eta.
#[derive(Args)]
struct Step {
    /// Continuation step in eta [range: 1e-9..=1]
    #[arg(long, value_name = "NUMBER", default_value = "0.005", value_parser = f64_in(1e-9, 1.0))]
    step: f64,
}

#[derive(Subcommand)]
enum Mode {
    /// The period-N orbit (Newton on P^N(z) - z after the transient) and its Floquet
    /// multipliers
    Orbit {
        #[command(flatten)]
        scene: SceneFlags,
        #[command(flatten)]
        period: Period,
        #[command(flatten)]
        transient: Transient,
        #[command(flatten)]
        friction: Friction,
    },
    /// The Lyapunov spectrum per forcing period (QR method) with its batch-means standard
    /// error, and the largest exponent by two trajectories
    Lyapunov {
        #[command(flatten)]
        scene: SceneFlags,
        #[command(flatten)]
        transient: Transient,
        #[command(flatten)]
        periods: Periods,
        /// Batch length of the standard error (0: periods/20) [range: 0..=100000000]
        #[arg(long, value_name = "COUNT", default_value = "0", value_parser = usize_in(0, 100_000_000))]
        batch: usize,
    },
    /// The first loss of stability of the period-N orbit continued in eta from --from towards
    /// --to
    LocateLoss {
        #[command(flatten)]
        scene: SceneFlags,
        #[command(flatten)]
        period: Period,
        #[command(flatten)]
        transient: Transient,
        /// Starting eta [range: 0.01..=100]
        #[arg(long, value_name = "NUMBER", required = true, value_parser = f64_in(0.01, 100.0))]
        from: f64,
        /// Eta to continue towards [range: 0.01..=100]
        #[arg(long, value_name = "NUMBER", required = true, value_parser = f64_in(0.01, 100.0))]
        to: f64,
        #[command(flatten)]
        step: Step,
        /// Width of the final bracket in eta [range: 1e-14..=0.01]
        #[arg(long, value_name = "NUMBER", default_value = "1e-8", value_parser = f64_in(1e-14, 1e-2))]
        tolerance: f64,
    },
    /// Figures: the largest multiplier modulus of the period-1 orbit against eta up to its
    /// loss of stability, and the largest Lyapunov exponent against eta over [2, 5] above
    /// the bifurcation diagram, for D = 0 and D = 0.1
    Pictures {
        #[command(flatten)]
        scene: SceneFlags,
        /// Output folder
        #[arg(long, value_name = "DIR", default_value = "target/figures/stability")]
        out: PathBuf,
        /// Eta values over [2, 5] [range: 2..=100000]
        #[arg(long, value_name = "COUNT", default_value = "151", value_parser = usize_in(2, 100_000))]
        values: usize,
        #[command(flatten)]
        transient: Transient,
        #[command(flatten)]
        periods: Periods,
        #[command(flatten)]
        step: Step,
    },
}

fn main() {
    let Flags { mode } = parse();
    match mode {
        Mode::Orbit {
            scene,
            period,
            transient,
            friction,
        } => orbit(
            &scene.scene(),
            period.period as u64,
            transient.transient as u64,
            &friction,
        ),
        Mode::Lyapunov {
            scene,
            transient,
            periods,
            batch,
        } => {
            let scene = scene.scene();
            let periods = periods.periods;
            let batch = if batch == 0 {
                (periods / 20).max(1)
            } else {
                batch
            };
            if batch > periods {
                fail(format!(
                    "--batch ({batch}) cannot exceed --periods ({periods})"
                ));
            }
            lyapunov(
                &scene,
                transient.transient as u64,
                periods as u64,
                batch as u64,
            )
        }
        Mode::LocateLoss {
            scene,
            period,
            transient,
            from,
            to,
            step,
            tolerance,
        } => {
            let scene = scene.scene();
            let opts = LossOptions::default()
                .with_step(step.step)
                .with_bracket_width(tolerance)
                .with_orbit((LossOptions::default().orbit).with_sim(scene.opts));
            locate(
                &scene,
                from,
                to,
                period.period as u64,
                transient.transient as u64,
                &opts,
            )
        }
        Mode::Pictures {
            scene,
            out,
            values,
            transient,
            periods,
            step,
        } => pictures(
            &scene.scene(),
            &out,
            values,
            transient.transient as u64,
            periods.periods as u64,
            step.step,
        ),
    }
}

fn print(v: Value) {
    println!("{v}");
}

fn orbit(scene: &Scene, period: u64, transient: u64, friction: &Friction) {
    let opts = OrbitOptions::default().with_sim(scene.opts);
    if friction.friction > 0.0 {
        let radius = friction.shaft_radius.unwrap_or_else(|| {
            fail("--friction needs --shaft-radius (the shaft's radius at the ring, in gaps)")
        });
        let model = rubbing_model(&scene.params, friction.friction, radius)
            .unwrap_or_else(|e| fail(format!("--friction: {e}")));
        let [x, y, vx, vy] = scene.start;
        let start = DVector::from_vec(vec![x, y, vx, vy, 0.0, 0.0]);
        let map = or_exit(StroboscopicMap::new(&model, transient.max(1), scene.opts));
        let section = or_exit(map.advance(&start));
        if section.label != 1 {
            eprintln!(
                "error: the section after the transient falls in a contact (regime {}): with friction the contact's history is not in the rotor's state; move the section with --phi0",
                section.label
            );
            std::process::exit(1);
        }
        let o = or_exit(periodic_orbit(&model, &section.y, period, &opts));
        return print(orbit_json(&o));
    }
    let model = or_exit(JeffcottModel::new(scene.params));
    let guess = after_transient(&model, scene, transient);
    let o = or_exit(periodic_orbit(&model, &guess, period, &opts));
    print(orbit_json(&o));
}

/// The JSON of a periodic orbit (the module docs list its keys).
fn orbit_json<D: jeffcott::nalgebra::Dim>(o: &PeriodicOrbit<D>) -> Value
where
    jeffcott::nalgebra::DefaultAllocator: VariationalAlloc<D>,
{
    let period = o.period;
    json!({
        "period": period,
        "point": o.point.as_slice(),
        "residual": o.residual,
        "multipliers": multipliers_json(&o.multipliers),
        "contacts": o.margins.contacts,
        "min_depth": num(o.margins.min_depth),
        "grazing_margin": num(o.margins.clearance),
        "spectral_radius": o.spectral_radius(),
        "minimal_period": o.minimal_period,
        "min_event_margin": o.margins.min_event_margin,
        "iterations": o.iterations,
    })
}

fn lyapunov(scene: &Scene, transient: u64, periods: u64, batch: u64) {
    let model = or_exit(JeffcottModel::new(scene.params));
    let [x, y, vx, vy] = scene.start;
    let y0 = model
        .state_at([x, y], [vx, vy])
        .unwrap_or_else(|e| fail(format!("initial state: {e}")));
    let opts = LyapunovOptions::default()
        .with_transient(transient)
        .with_periods(periods)
        .with_batch(batch)
        .with_sim(scene.opts);
    let l = or_exit(lyapunov_exponents(&model, &y0, &opts));
    let two = l.two_trajectory.as_ref();
    print(json!({
        "lambda": l.per_period.mean,
        "stderr": l.per_period.stderr.iter().map(|&s| num(Some(s))).collect::<Vec<_>>(),
        "lambda1_two_trajectory": num(two.map(|t| t.lambda)),
        "stderr_two_trajectory": num(two.map(|t| t.stderr)),
        "lambda_per_tau": l.per_time,
        "batch_length": l.per_period.batch_length,
        "batches": l.per_period.batches,
        "sum": l.sum(),
        "grazing_events": l.grazing_events,
    }));
}

fn locate(scene: &Scene, from: f64, to: f64, period: u64, transient: u64, opts: &LossOptions) {
    let at = |eta: f64| {
        JeffcottModel::new(Params {
            eta,
            ..scene.params
        })
    };
    let model = or_exit(at(from));
    let guess = after_transient(&model, scene, transient);
    let c = or_exit(locate_loss(at, from, to, &guess, period, opts));
    match c.loss {
        Some(loss) => print(json!({
            "eta": loss.parameter,
            "kind": loss.kind.name(),
            "multipliers": multipliers_json(&loss.orbit.multipliers),
            "bracket": [loss.bracket.0, loss.bracket.1],
            "tolerance": opts.bracket_width,
            "period": period,
            "steps": c.path.len(),
        })),
        None => match c.failure {
            // The branch ended by an error: no bifurcation located, the error said.
            Some(f) => print(json!({
                "eta": null,
                "kind": null,
                "failure": f.error.to_string(),
                "failed_at": f.parameter,
                "last_eta": f.last_parameter,
                "multipliers": multipliers_json(&f.last_orbit.multipliers),
                "period": period,
                "steps": c.path.len(),
            })),
            None => print(json!({
                "eta": null,
                "kind": null,
                "multipliers": [],
                "period": period,
                "steps": c.path.len(),
            })),
        },
    }
}

/// The figures (module docs).
fn pictures(
    scene: &Scene,
    out: &std::path::Path,
    values: usize,
    transient: u64,
    periods: u64,
    step: f64,
) {
    let presets = [(0.0, "D = 0"), (0.1, "D = 0.1")];
    // 1. max |multiplier| of the period-1 orbit against eta, up to its loss of stability.
    let mut series = Vec::new();
    let mut fig = Figure::new(
        "Period-1 orbit from η = 2: largest multiplier modulus up to its loss of stability",
        "η = Ω/ωₙ",
        "max |λ| (Floquet multipliers)",
    )
    .with_columns("eta", "max_modulus")
    .with_markers();
    for (d, label) in &presets {
        eprintln!("{label}: continuing the period-1 orbit from η = 2...");
        let base = scene.params.with_preload(*d);
        let at = |eta: f64| JeffcottModel::new(Params { eta, ..base });
        let model = or_exit(at(2.0));
        let guess = after_transient(
            &model,
            &Scene {
                params: base.with_eta(2.0),
                opts: scene.opts,
                start: scene.start,
            },
            transient,
        );
        let opts = LossOptions::default()
            .with_step(step)
            .with_orbit((LossOptions::default().orbit).with_sim(scene.opts));
        let c = or_exit(locate_loss(at, 2.0, 3.0, &guess, 1, &opts));
        let mut points: Vec<(f64, f64)> = c
            .path
            .iter()
            .map(|p| (p.parameter, p.multipliers[0].modulus()))
            .collect();
        if let Some(loss) = &c.loss {
            points.push((loss.parameter, 1.0));
            fig = fig.with_mark(
                loss.parameter,
                &format!("{label}: η = {:.6}", loss.parameter),
            );
            eprintln!(
                "{label}: period 1 loses stability at eta = {:.9} ({})",
                loss.parameter,
                loss.kind.name()
            );
        }
        if let Some(f) = &c.failure {
            eprintln!(
                "{label}: the continuation stopped at eta = {:.9}: {}",
                f.parameter, f.error
            );
        }
        series.push(Series::new(label, points));
    }
    or_exit(plot::lines(
        out.join("multipliers_period1.png"),
        &fig,
        &series,
    ));

    // 2. The largest Lyapunov exponent over the bifurcation diagram, from the same runs.
    let etas = or_exit(linspace(2.0, 5.0, values));
    for (d, label) in presets {
        let base = scene.params.with_preload(d);
        let opts = LyapunovOptions::default()
            .with_transient(transient)
            .with_periods(periods.max(20))
            .with_batch((periods / 20).max(1))
            .with_separation(None)
            .with_exponents(1)
            .with_keep(150)
            .with_sim(scene.opts);
        let start = scene.start;
        let runner = |eta: &f64, _: Option<()>| {
            let model = JeffcottModel::new(base.with_eta(*eta)).map_err(|e| e.to_string())?;
            let y0 = model
                .state_at([start[0], start[1]], [start[2], start[3]])
                .map_err(|e| e.to_string())?;
            lyapunov_exponents(&model, &y0, &opts)
                .map(|l| {
                    (
                        (l.per_period.mean[0], l.per_period.stderr[0], l.sections),
                        (),
                    )
                })
                .map_err(|e| e.to_string())
        };
        let progress =
            jeffcott::analysis::StderrProgress::new(format!("Lyapunov exponents, {label}"));
        let result = or_exit(sweep(
            &etas,
            &SweepOptions::reset(),
            runner,
            Some(&progress),
        ));
        let mut lambda = Vec::new();
        let mut diagram = Vec::new();
        for (eta, r) in etas.iter().zip(&result.results) {
            match r {
                Ok((l, _, sections)) => {
                    lambda.push((*eta, *l));
                    diagram.extend(sections.iter().map(|z| (*eta, z[0])));
                }
                Err(e) => eprintln!("eta = {eta}: {e}"),
            }
        }
        let top = Figure::new(
            &format!("Largest Lyapunov exponent per forcing period, {label}"),
            "η = Ω/ωₙ",
            "λ₁ (per period)",
        )
        .with_columns("eta", "lambda1")
        .with_size(1200, 400);
        let bottom = Figure::new(
            &format!("Bifurcation diagram, {label}"),
            "η = Ω/ωₙ",
            "x (rotor, units of the gap γ)",
        )
        .with_columns("eta", "x")
        .with_size(1200, 600);
        let name = if d == 0.0 {
            "lyapunov_fig8a.png"
        } else {
            "lyapunov_fig8b.png"
        };
        or_exit(plot::lines_over_points(
            out.join(name),
            &top,
            &[Series::new("", lambda)],
            &bottom,
            &diagram,
        ));
    }
    print(json!({ "figures": out.display().to_string() }));
}
