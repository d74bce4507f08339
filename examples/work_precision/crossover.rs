//! `--suite crossover`: RADAU5 against DOP853, error against work, on the scenes of issue 19:
//! the paper's model (Fig. 8a, $\eta = 2$), the same with a stiff ring ($K = 10^4$ and
//! $10^6$), the flexible shaft with contacts in 8, 16, 32 and 64 modes, and the stiff test set.
//!
//! * Rotor scenes run from rest over `periods` forcing periods at `rtol = atol = tol`; the
//!   error is the largest component of the end state's error (the paper's model, in gaps and
//!   gaps times $\omega_n$) or the distance of the ring station at the end (the shaft, in
//!   gaps), against DOP853 at `rtol = atol = 1e-12` (the shaft: with the state's scale as its
//!   error weights, the stricter ones, so the reference does not rest on the modal choice).
//! * The stiff set runs at `rtol = tol` with each problem's usual atol; the error is
//!   $10^{-\mathrm{scd}}$ against the published end values (E5: the mixed scd). DOP853 gets
//!   200 000 step attempts.
//!
//! Work: wall time (the minimum of `repeat` runs) and right-hand-side evaluations (RADAU5's
//! counted as the method counts them: one per Newton iteration and stage, plus the
//! finite-difference Jacobians when a model gives none).

use std::path::Path;
use std::time::Instant;

use crate::common::{self, csv::CsvWriter, plot};
use crate::problems::{self, Problem};
use crate::shaft::{self, Layout};
use jeffcott::hybrid::{simulate, OutputPlan, RotorModel, SimOptions, SimStats, Trajectory};
use jeffcott::nalgebra::{allocator::Allocator, DefaultAllocator, Dyn, OVector, U6};
use jeffcott::ode::Method;
use jeffcott::paper::JeffcottModel;
use jeffcott::params::Preset;

/// The tolerances of the crossover: $10^{-4}$ to $10^{-10}$.
const TOLS: [f64; 4] = [1e-4, 1e-6, 1e-8, 1e-10];
/// The two methods compared.
const METHODS: [Method; 2] = [Method::Dop853, Method::Radau5];

/// One point of the diagram.
struct Point {
    error: f64,
    seconds: f64,
    rhs: u64,
    steps: u64,
    /// The run's mode transitions and the reference's (0 for the stiff set).
    transitions: [u64; 2],
}

/// The scenes' names, in the order they are run.
pub const SCENES: [&str; 12] = [
    "paper", "ring1e4", "ring1e6", "shaft8", "shaft16", "shaft32", "shaft64", "vdpol", "rober",
    "orego", "hires", "e5",
];

/// Runs the crossover on the scenes `only` selects (`"all"` or one name), writes
/// `crossover_results.csv`, a figure per scene (`xo_<scene>.png`, error against time) and
/// `crossover.png` (RADAU5's time over DOP853's against the tolerance, one line per scene) to
/// `out`.
pub fn run(out: &Path, only: &str, repeat: usize) {
    common::or_exit(std::fs::create_dir_all(out));
    let mut csv = common::or_exit(CsvWriter::create(
        out.join("crossover_results.csv"),
        &[
            "scene",
            "method",
            "tol",
            "error",
            "seconds",
            "rhs_evals",
            "steps",
            "transitions",
            "reference_transitions",
        ],
    ));
    let mut ratios = Vec::new();
    for scene in SCENES.iter().filter(|s| only == "all" || only == **s) {
        let mut by_time = Vec::new();
        let mut seconds = [[f64::NAN; TOLS.len()]; 2];
        for (m, method) in METHODS.into_iter().enumerate() {
            let mut pts = Vec::new();
            for (k, tol) in TOLS.into_iter().enumerate() {
                let result = measure(scene, method, tol, repeat);
                common::or_exit(csv.record(&report(scene, method, tol, &result)));
                if let Ok(p) = result {
                    pts.push((p.seconds, p.error.max(1e-16)));
                    seconds[m][k] = p.seconds;
                }
            }
            by_time.push(plot::Series::new(method.name(), pts));
        }
        crate::figure(
            out,
            &format!("xo_{scene}.png"),
            &format!("RADAU5 against DOP853: {scene}"),
            "wall time per run [s]",
            &by_time,
        );
        let ratio: Vec<(f64, f64)> = TOLS
            .iter()
            .zip(seconds[1].iter().zip(&seconds[0]))
            .map(|(&t, (r, d))| (t, r / d))
            .filter(|p| p.1.is_finite())
            .collect();
        if !ratio.is_empty() {
            ratios.push(plot::Series::new(scene, ratio));
        }
    }
    common::or_exit(csv.finish());
    let fig = plot::Figure::new(
        "RADAU5's time over DOP853's (below 1: RADAU5 wins; DOP853 failures left out)",
        "rtol",
        "time ratio RADAU5 / DOP853",
    )
    .with_columns("rtol", "ratio")
    .with_size(900, 600)
    .with_log(true, true)
    .with_markers()
    .with_legend(plot::LegendPosition::UpperRight);
    common::or_exit(plot::lines(out.join("crossover.png"), &fig, &ratios));
}

/// Prints one point and returns its CSV record.
fn report(scene: &str, method: Method, tol: f64, result: &Result<Point, String>) -> Vec<String> {
    let mut record = vec![scene.to_string(), method.name().into(), format!("{tol:e}")];
    match result {
        Ok(p) => {
            println!(
                "{scene:8} {:7} {tol:.0e}: error {:9.2e}, {:9.4} s, {:9} rhs, {:8} steps, \
                 {} transitions (reference {})",
                method.name(),
                p.error,
                p.seconds,
                p.rhs,
                p.steps,
                p.transitions[0],
                p.transitions[1]
            );
            record.extend([p.error, p.seconds].map(|v| format!("{v:e}")));
            record.extend(
                [p.rhs, p.steps, p.transitions[0], p.transitions[1]].map(|n| n.to_string()),
            );
        }
        Err(e) => {
            println!("{scene:8} {:7} {tol:.0e}: failed: {e}", method.name());
            record.extend(["NaN", "NaN", "0", "0", "0", "0"].map(String::from));
        }
    }
    record
}

/// One run of `scene` with `method` at `tol` against the scene's reference.
fn measure(scene: &str, method: Method, tol: f64, repeat: usize) -> Result<Point, String> {
    if let Some(problem) = Problem::from_name(scene) {
        return stiff(problem, method, tol, repeat);
    }
    if let Some(modes) = scene.strip_prefix("shaft") {
        let modes: usize = modes.parse().map_err(|_| format!("scene {scene}"))?;
        return shaft_scene(modes, method, tol, repeat);
    }
    let params = match scene {
        "paper" => Preset::Fig8a.params(),
        "ring1e4" => Preset::Fig8a.params().with_stiffness(1e4),
        "ring1e6" => Preset::Fig8a.params().with_stiffness(1e6),
        _ => return Err(format!("unknown scene {scene}")),
    };
    let model = JeffcottModel::new(params).map_err(|e| e.to_string())?;
    let y0 = OVector::zeros_generic(model.dim(), jeffcott::nalgebra::U1);
    let distance = |a: &OVector<f64, U6>, b: &OVector<f64, U6>| (a - b).amax();
    against_reference(&model, &y0, 20, method, tol, repeat, distance)
}

/// The shaft with contacts in `modes` modes (ring at station 3 of 8, out-of-balance at 2,
/// $\eta = 1.1$) over 10 periods from its consistent rest.
fn shaft_scene(modes: usize, method: Method, tol: f64, repeat: usize) -> Result<Point, String> {
    let params = Preset::Fig8a.params().with_eta(1.1);
    let layout = Layout {
        modes,
        stations: 8,
        unbalance: 2,
        ring: 3,
    };
    let model = shaft::on_ring(params, layout).map_err(|e| e.to_string())?;
    let mut y0 = OVector::zeros_generic(model.dim(), jeffcott::nalgebra::U1);
    model.make_consistent(&mut y0).map_err(|e| e.to_string())?;
    let s = model.rotor();
    let distance = |a: &OVector<f64, Dyn>, b: &OVector<f64, Dyn>| {
        (s.ring_kinematics(a.as_slice()).r - s.ring_kinematics(b.as_slice()).r).norm()
    };
    // The reference with the state's scale as error weights (the stricter ones).
    let strict = shaft::on_ring_with_weights(params, layout, false).map_err(|e| e.to_string())?;
    let reference_opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-12);
    let (reference, ref_stats) = end_state(&strict, &y0, 10, &reference_opts)?;
    let opts = SimOptions::default()
        .with_method(method)
        .with_rtol(tol)
        .with_atol(tol);
    timed(repeat, || end_state(&model, &y0, 10, &opts))
        .map(|(y, stats, seconds)| point(distance(&y, &reference), stats, ref_stats, seconds))
}

/// A rotor scene against DOP853 at `rtol = atol = 1e-12` over `periods` periods.
fn against_reference<M: RotorModel>(
    model: &M,
    y0: &OVector<f64, M::Dim>,
    periods: u64,
    method: Method,
    tol: f64,
    repeat: usize,
    distance: impl Fn(&OVector<f64, M::Dim>, &OVector<f64, M::Dim>) -> f64,
) -> Result<Point, String>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    let reference_opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-12);
    let (reference, ref_stats) = end_state(model, y0, periods, &reference_opts)?;
    let opts = SimOptions::default()
        .with_method(method)
        .with_rtol(tol)
        .with_atol(tol);
    timed(repeat, || end_state(model, y0, periods, &opts))
        .map(|(y, stats, seconds)| point(distance(&y, &reference), stats, ref_stats, seconds))
}

fn point(error: f64, stats: SimStats, reference: SimStats, seconds: f64) -> Point {
    Point {
        error,
        seconds,
        rhs: stats.rhs_evals,
        steps: stats.steps,
        transitions: [stats.transitions, reference.transitions],
    }
}

/// The least wall time of `repeat` runs of `f`, with the last run's result.
fn timed<T, S>(
    repeat: usize,
    f: impl Fn() -> Result<(T, S), String>,
) -> Result<(T, S, f64), String> {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..repeat.max(1) {
        let clock = Instant::now();
        let r = f()?;
        best = best.min(clock.elapsed().as_secs_f64());
        last = Some(r);
    }
    let (y, stats) = last.ok_or("no run")?;
    Ok((y, stats, best))
}

/// The state after `periods` forcing periods from `y0` at `t = 0`.
fn end_state<M: RotorModel>(
    model: &M,
    y0: &OVector<f64, M::Dim>,
    periods: u64,
    opts: &SimOptions,
) -> Result<(OVector<f64, M::Dim>, SimStats), String>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    let plan = OutputPlan::strobe(model.forcing_period(), periods, periods);
    let mut traj = Trajectory::default();
    let stats = simulate(model, 0.0, y0, &plan, opts, &mut traj).map_err(|e| e.to_string())?;
    let end = traj.strobe.pop().ok_or("no stroboscopic output")?.y;
    Ok((end, stats))
}

/// A problem of the stiff set at `rtol = tol`, its usual atol; error $10^{-\mathrm{scd}}$.
fn stiff(problem: Problem, method: Method, tol: f64, repeat: usize) -> Result<Point, String> {
    let atol = problem.usual_atol(tol);
    let budget = if method == Method::Radau5 {
        1_000_000
    } else {
        200_000
    };
    let (r, (), seconds) = timed(repeat, || {
        problems::run(problem, method, tol, atol, budget)
            .map(|r| (r, ()))
            .map_err(|e| e.to_string())
    })?;
    // E5's components are below its atol: its relative scd is atol's, the mixed one is what
    // the tolerances control (as `tests/suite/ode/ode_stiff_set.rs` asserts).
    let scd = if problem == Problem::E5 {
        problems::mescd(r.y.as_slice(), problem.reference(), tol, atol)
    } else {
        r.scd()
    };
    Ok(Point {
        error: 10f64.powf(-scd),
        seconds,
        rhs: r.stats.rhs_evals,
        steps: r.stats.steps,
        transitions: [0, 0],
    })
}
