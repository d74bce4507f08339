//! Continuation of periodic orbits in one parameter, with their stability, bifurcations and
//! grazings; and coexistence diagrams: the continued branches over the brute-force diagram.
//!
//! Two modes:
//!
//! * **one branch** (default): `--param P --from A --to B --period N` finds the period-N orbit
//!   at P = A (after `--transient` periods from the scene's initial state, then Newton), follows
//!   it towards B by pseudo-arclength (`stability::continue_orbit`) and prints **each special
//!   point as one JSON object a line** on standard output:
//!
//!   ```text
//!   {"kind": "grazing", "param": "eta", "value": 0.684768854, "multipliers": [[re, im], ...], "period": 1, "bracket": [a, b], "converged": true, "unconverged": null, "contacts": [0, 1]}
//!   ```
//!
//!   `kind` is `grazing`, `flip`, `fold` or `neimark-sacker`; the multipliers are those at the
//!   near end of the final bracket, largest modulus first; `"converged": false` (with the
//!   reason in `unconverged`) for a point detected but not located: its value is only
//!   somewhere in the bracket. With `--switch` the period-2N branch
//!   is followed from each flip (its special points are printed too, with their period). The
//!   branch is drawn into `--out` (`branch.png`: x of the orbit's points against P, stable
//!   solid, unstable dashed, special points marked; `branch.csv`);
//! * **`--coexistence`**: for the paper's Fig. 8 values with D = 0 and D = 0.1, the brute-force
//!   diagram from rest over η ∈ [2, 5] and, over it, every periodic orbit found from a few
//!   starts at a few η, continued both ways (and from their flips): which orbits coexist, and
//!   which are stable. Writes `coexistence_fig8a.png`, `coexistence_fig8b.png` into `--out`
//!   and prints the special points found.
//!
//! The scene flags are those of `simulate` (`--preset`, parameter overrides, `--rtol`,
//! `--atol`, `--method`, the initial state `--x0 --y0 --vx0 --vy0`).
//!
//! ```text
//! cargo run --release --example continuation -- --param eta --from 0.4 --to 0.8 --period 1
//! cargo run --release --example continuation -- --param eta --from 2 --to 2.3 --period 1 --switch
//! cargo run --release --example continuation -- --coexistence
//! ```

#[path = "common/mod.rs"]
mod common;

use std::path::{Path, PathBuf};

use clap::Parser;
use common::cli::{f64_in, fail, finite, num, parse, usize_in};
use common::or_exit;
use common::plot::{self, BranchCurve, Figure};
use common::scene::SceneFlags;
use jeffcott::analysis::{linspace, BifurcationOptions};
use jeffcott::global::{find_attractor, AttractorOptions};
use jeffcott::paper::{JeffcottModel, ParamSweep, SweepParameter};
use jeffcott::params::{Params, Preset};
use jeffcott::stability::{
    continue_orbit, switch_at_flip, Branch, ContinuationOptions, SpecialPoint,
};
use serde_json::json;

/// The parameters `--param` accepts.
const PARAMS: [(&str, SweepParameter); 10] = [
    ("eta", SweepParameter::Eta),
    ("preload", SweepParameter::Preload),
    ("delta-x", SweepParameter::PreloadX),
    ("k", SweepParameter::Stiffness),
    ("nu1", SweepParameter::Nu1),
    ("nu2", SweepParameter::Nu2),
    ("beta", SweepParameter::Beta),
    ("ex", SweepParameter::Ex),
    ("ey", SweepParameter::Ey),
    ("phi0", SweepParameter::Phi0),
];

fn special_json(s: &SpecialPoint, param: &str, period: u64) -> String {
    let m: Vec<_> = s.multipliers.iter().map(|m| json!([m.re, m.im])).collect();
    json!({
        "kind": s.kind.name(),
        "param": param,
        "value": s.parameter,
        "multipliers": m,
        "period": period,
        "bracket": [s.bracket.0, s.bracket.1],
        "converged": s.converged,
        "unconverged": s.unconverged.as_ref().map(|e| e.to_string()),
        "contacts": [s.contacts.0, s.contacts.1],
    })
    .to_string()
}

/// The branch as curves of the first component of each of its orbit's points.
fn curves(branch: &Branch, label: &str, colour: plotters::style::RGBColor) -> Vec<BranchCurve> {
    let n = branch.period as usize;
    let mut out = Vec::new();
    for j in 0..n {
        let mut pieces: Vec<(Vec<(f64, f64)>, bool)> = Vec::new();
        for p in &branch.points {
            let pt = (p.parameter, p.cycle.get(j).map_or(f64::NAN, |y| y[0]));
            match pieces.last_mut() {
                Some((v, s)) if *s == p.stable => v.push(pt),
                Some((v, _)) => {
                    let joint = *v.last().unwrap_or(&pt);
                    pieces.push((vec![joint, pt], p.stable));
                }
                None => pieces.push((vec![pt], p.stable)),
            }
        }
        out.push(BranchCurve {
            label: if j == 0 {
                label.to_string()
            } else {
                String::new()
            },
            colour,
            pieces,
        });
    }
    out
}

fn marks(branch: &Branch) -> Vec<(f64, f64, String)> {
    branch
        .specials
        .iter()
        .map(|s| {
            let short = match s.kind.name() {
                "neimark-sacker" => "NS",
                k => k,
            };
            (
                s.parameter,
                s.state[0],
                format!("{short} {:.4}", s.parameter),
            )
        })
        .collect()
}

/// Continuation of periodic orbits: special points as JSON lines on stdout, the branch drawn.
#[derive(Parser)]
#[command(name = "continuation")]
struct Flags {
    #[command(flatten)]
    scene: SceneFlags,
    /// The parameter continued
    #[arg(long, default_value = "eta", value_parser = PARAMS.map(|p| p.0))]
    param: String,
    /// Starting value of the parameter (needed unless --coexistence)
    #[arg(long, value_name = "NUMBER", value_parser = finite,
          required_unless_present = "coexistence")]
    from: Option<f64>,
    /// Value to continue towards (needed unless --coexistence; not --from)
    #[arg(long, value_name = "NUMBER", value_parser = finite,
          required_unless_present = "coexistence")]
    to: Option<f64>,
    /// Period N of the orbit (forcing periods) [range: 1..=1000]
    #[arg(long, value_name = "COUNT", default_value = "1", value_parser = usize_in(1, 1000))]
    period: usize,
    /// Periods run from the initial state before Newton [range: 0..=100000000]
    #[arg(long, value_name = "COUNT", default_value = "300", value_parser = usize_in(0, 100_000_000))]
    transient: usize,
    /// Largest arclength step [range: 1e-6..=1]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(1e-6, 1.0),
          default_value = num(ContinuationOptions::default().ds_max))]
    ds_max: f64,
    /// Output folder
    #[arg(
        long,
        value_name = "DIR",
        default_value = "target/figures/continuation"
    )]
    out: PathBuf,
    /// Also follow the period-doubled branch from each flip
    #[arg(long)]
    switch: bool,
    /// Instead of one branch: the continued branches over the brute-force diagrams of Fig. 8
    /// (D = 0 and D = 0.1; uses only --out, --ds-max and the integration flags)
    #[arg(long, conflicts_with_all = ["from", "to", "switch"])]
    coexistence: bool,
}

fn main() {
    let Flags {
        scene,
        param,
        from,
        to,
        period,
        transient,
        ds_max,
        out,
        switch,
        coexistence,
    } = parse();
    let scene = scene.scene();
    let d = ContinuationOptions::default();
    let config = d
        .with_ds(d.ds.min(ds_max))
        .with_ds_max(ds_max)
        .with_sim(scene.opts);
    if coexistence {
        run_coexistence(&out, &config);
        return;
    }
    let (Some(from), Some(to)) = (from, to) else {
        fail("--from and --to are needed (or use --coexistence)");
    };
    if from == to {
        fail("--to must differ from --from");
    }
    let sp = PARAMS
        .iter()
        .find(|p| p.0 == param)
        .map_or(SweepParameter::Eta, |p| p.1);
    let base = scene.params;
    let build = |v: f64| JeffcottModel::new(sp.apply(&base, v));
    let model = build(from).unwrap_or_else(|e| fail(format!("--from: {e}")));
    let [x, y, vx, vy] = scene.start;
    let start = model
        .state_at([x, y], [vx, vy])
        .unwrap_or_else(|e| fail(format!("initial state: {e}")));
    let guess = if transient > 0 {
        let (traj, _) =
            or_exit(model.strobe_range(&start, transient as u64, transient as u64, &scene.opts));
        traj.strobe.last().map_or(start, |p| p.y)
    } else {
        start
    };
    let branch = or_exit(continue_orbit(
        build,
        from,
        to,
        &guess,
        period as u64,
        &config,
    ));
    let mut all = vec![(branch, format!("period {period}"))];
    if switch {
        let flips: Vec<SpecialPoint> = all[0]
            .0
            .specials
            .iter()
            .filter(|s| s.kind.name() == "flip")
            .cloned()
            .collect();
        for f in &flips {
            match switch_at_flip(build, f, to, period as u64, &config) {
                Ok(b) => all.push((
                    b,
                    format!("period {} from the flip at {:.4}", 2 * period, f.parameter),
                )),
                Err(e) => eprintln!("warning: {e}"),
            }
        }
    }
    let mut curves_all = Vec::new();
    let mut marks_all = Vec::new();
    for (i, (b, label)) in all.iter().enumerate() {
        for s in &b.specials {
            println!("{}", special_json(s, &param, b.period));
        }
        eprintln!(
            "{label}: {} points, {} special points, {:?}",
            b.points.len(),
            b.specials.len(),
            b.end
        );
        curves_all.extend(curves(b, label, plot::series_colour(i)));
        marks_all.extend(marks(b));
    }
    let fig = Figure::new(
        &format!(
            "Continuation in {} from {from} towards {to}: stable solid, unstable dashed",
            plot::symbol(&param)
        ),
        plot::symbol(&param),
        "x at the section (rotor, units of the gap γ)",
    )
    .with_columns(&param, "x")
    .with_size(1500, 950);
    let png = out.join("branch.png");
    or_exit(plot::branches(&png, &fig, &[], &curves_all, &marks_all));
    eprintln!("wrote {}", png.display());
}

/// The distinct periodic attractors reached at `eta` from a few starts: (period, state).
fn seeds(base: &Params, eta: f64) -> Vec<(u64, jeffcott::State)> {
    let model = or_exit(JeffcottModel::new(base.with_eta(eta)));
    let config = AttractorOptions::default()
        .with_transient(600)
        .with_max_transient(3000);
    let mut found: Vec<jeffcott::global::Attractor> = Vec::new();
    for x0 in [-0.6, 0.0, 0.6] {
        for v0 in [-1.2, 0.0, 0.4, 1.2] {
            let Ok(y0) = model.state_at([x0, 0.0], [v0, 0.0]) else {
                continue;
            };
            let Ok(a) = find_attractor(&model, &y0, &config) else {
                continue;
            };
            let tol = jeffcott::global::MatchOptions::default();
            if a.period().is_some_and(|p| p <= 8) && !found.iter().any(|f| f.matches(&a, &tol)) {
                found.push(a);
            }
        }
    }
    // A slowly converging orbit can pass the period test only at a multiple of its period:
    // continue it at its period at the matching tolerance.
    found
        .into_iter()
        .filter_map(|a| {
            let cycle = a.reduced_cycle(1e-3);
            let z = cycle.first()?.clone();
            let y = model.state_at([z[0], z[1]], [z[2], z[3]]).ok()?;
            Some((cycle.len() as u64, y))
        })
        .collect()
}

/// Whether the orbit through `y` at `eta` is already on one of the branches.
fn known(branches: &[Branch], period: u64, eta: f64, y: &jeffcott::State) -> bool {
    branches.iter().filter(|b| b.period == period).any(|b| {
        b.points.iter().any(|p| {
            (p.parameter - eta).abs() < 0.03
                && p.cycle
                    .iter()
                    .any(|c| (0..4).all(|i| (c[i] - y[i]).abs() < 0.02))
        })
    })
}

fn run_coexistence(out: &Path, config: &ContinuationOptions) {
    let (lo, hi) = (2.0, 5.0);
    let seed_etas = [2.0, 2.17, 2.2, 2.6, 2.75, 3.0, 3.5, 3.9, 4.3, 4.6];
    for (name, preset) in [("fig8a", Preset::Fig8a), ("fig8b", Preset::Fig8b)] {
        let base = preset.params();
        // The brute-force diagram from rest.
        let etas = or_exit(linspace(lo, hi, 601));
        let bconf = BifurcationOptions::default()
            .with_transient(300)
            .with_record(60);
        let progress =
            jeffcott::analysis::StderrProgress::new(format!("{name}: diagram from rest"));
        let diagram = or_exit(ParamSweep::new(base, SweepParameter::Eta).bifurcation(
            &etas,
            &bconf,
            Some(&progress),
        ));
        let background = diagram.points(0);
        // Branches from every distinct periodic attractor at the seed etas, both ways.
        let mut branches: Vec<Branch> = Vec::new();
        let build = |eta: f64| JeffcottModel::new(base.with_eta(eta));
        let cfg = config.with_max_points(600);
        for &eta in &seed_etas {
            eprintln!("{name}: periodic attractors at eta = {eta}...");
            for (period, y) in seeds(&base, eta) {
                if known(&branches, period, eta, &y) {
                    continue;
                }
                for to in [lo, hi] {
                    match continue_orbit(build, eta, to, &y, period, &cfg) {
                        Ok(b) => {
                            eprintln!(
                                "{name}: period {period} from eta = {eta} towards {to}: {} points to {:.4}, {} special points",
                                b.points.len(),
                                b.points.last().map_or(eta, |p| p.parameter),
                                b.specials.len()
                            );
                            branches.push(b);
                        }
                        Err(e) => eprintln!("{name}: period {period} at eta = {eta}: {e}"),
                    }
                }
            }
        }
        // The period-doubled branches from the flips of periods 1 and 2.
        let mut doubled = Vec::new();
        for b in branches.iter().filter(|b| b.period <= 2) {
            for f in b.specials.iter().filter(|s| s.kind.name() == "flip") {
                let to = if b.points.last().map_or(hi, |p| p.parameter) > f.parameter {
                    hi
                } else {
                    lo
                };
                match switch_at_flip(build, f, to, b.period, &cfg) {
                    Ok(d) if !known(&doubled, d.period, f.parameter, &first_state(&d)) => {
                        doubled.push(d)
                    }
                    Ok(_) => {}
                    Err(e) => eprintln!("{name}: {e}"),
                }
            }
        }
        branches.extend(doubled);
        let mut curves_all = Vec::new();
        let mut marks_all = Vec::new();
        for b in &branches {
            for s in &b.specials {
                println!(
                    "{{\"diagram\": \"{name}\", {}",
                    &special_json(s, "eta", b.period)[1..]
                );
            }
            let colour = plot::series_colour(b.period as usize - 1);
            curves_all.extend(curves(b, "", colour));
            // Labelled: the bifurcations of periods 1 to 3 (the rest would bury the picture).
            marks_all.extend(
                marks(b)
                    .into_iter()
                    .zip(&b.specials)
                    .filter(|(_, s)| s.kind.name() != "grazing" && b.period <= 3)
                    .map(|(m, _)| m),
            );
        }
        // One legend entry per period.
        let mut periods: Vec<u64> = branches.iter().map(|b| b.period).collect();
        periods.sort_unstable();
        periods.dedup();
        for p in periods {
            curves_all.push(BranchCurve {
                label: format!("period {p}"),
                colour: plot::series_colour(p as usize - 1),
                pieces: Vec::new(),
            });
        }
        let fig = Figure::new(
            &format!(
                "Fig. 8{}: continued periodic orbits (stable solid, unstable dashed) over the diagram from rest (grey), D = {}",
                &name[4..],
                base.dx
            ),
            "η = Ω/ωₙ",
            "x at the section (rotor, units of the gap γ)",
        )
        .with_columns("eta", "x")
        .with_size(1800, 1000)
        .with_x_range(lo, hi);
        let png = out.join(format!("coexistence_{name}.png"));
        or_exit(plot::branches(
            &png,
            &fig,
            &background,
            &curves_all,
            &marks_all,
        ));
        eprintln!("wrote {}", png.display());
    }
}

/// The first point of a branch as a state (for [`known`]).
fn first_state(b: &Branch) -> jeffcott::State {
    let s = b.points.first().map_or(vec![0.0; 6], |p| p.state.clone());
    jeffcott::State::from_iterator(s.into_iter().chain(std::iter::repeat(0.0)).take(6))
}
