//! A finite-element rotor through its first critical speed (`--fe`): by default ROSS's
//! 204-DOF `rotor_example_with_damping` (the shared rotors' `.mat`, first critical about
//! 182 rad/s) with case S1's ring at node 12 (gap 79.5 µm, 1.1e6 N/m, the out-of-balance
//! 2e-3 kg m at node 12), reduced to node 12's x, y and 24 Craig-Bampton modes; any ROSS
//! export (`--fe-mat`), ring (`--fe-ring-node`, `--fe-gap`, `--fe-ring-stiffness`,
//! `--fe-ring-damping`), out-of-balance (`--fe-unbalance NODE,ME,PHASE`) and mode count
//! (`--fe-modes`). Run up from `--fe-from` to `--fe-to` rad/s at `--fe-rate` rad/s² and back
//! down (`rotor::ProfiledLinearRotor`: the
//! damping $C + \Omega(t)G$, the force $m e(\Omega^2\cos\varphi + \Omega^\prime\sin\varphi,
//! \ldots)$), with and without the ring. Prints a line per run and leg, and writes
//! `fe_envelope.png` (with `fe_envelope.csv`): the largest radius of the ring's node in each
//! revolution against its mean speed.

use std::path::{Path, PathBuf};
use std::time::Instant;

use jeffcott::analysis::{per_revolution, Revolution};
use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::Dyn;
use jeffcott::ode::Method;
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{
    CraigBampton, LinearRotor, LinearSystem, ModeSelection, RingedRotor, RotorMatrices, Segment,
    SmoothRotor, SpeedProfile,
};

use crate::common::plot::{self, Figure, Series};

/// The rotor's file in the repository (a copy of `../shared/rotors/`, as the tests read it).
pub fn default_mat() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/rotors/rotor_example_with_damping_1200rpm.mat")
}

/// The ring, the out-of-balance and the reduction (the defaults: case S1's,
/// `tests/data/rotors/S1_reference.json`, and 24 modes).
pub struct Setup {
    /// The ring's node.
    pub ring_node: usize,
    /// The ring's radial gap, m.
    pub gap: f64,
    /// The ring's unit stiffness, N/m.
    pub ring_stiffness: f64,
    /// The ring's unit damping, N s/m.
    pub ring_damping: f64,
    /// The out-of-balance: node, m e (kg m), phase (rad).
    pub unbalance: (usize, f64, f64),
    /// The Craig-Bampton modes kept.
    pub modes: usize,
}
/// Strobes a revolution (the envelope's resolution).
const SAMPLES: u32 = 16;

/// The sweep: speeds (rad/s) and rate (rad/s²).
pub struct Sweep {
    pub from: f64,
    pub to: f64,
    pub rate: f64,
}

/// The reduced rotor at the sweep's profile, on the ring or without it (a gap of 1 m).
fn model(
    mat: &Path,
    (sweep, setup): (&Sweep, &Setup),
    ring: bool,
) -> Result<RingedRotor<jeffcott::rotor::ProfiledLinearRotor>, String> {
    let err = |e: jeffcott::rotor::RotorError| e.to_string();
    let lateral = RotorMatrices::from_ross_mat(mat)
        .and_then(|m| m.lateral())
        .map_err(|e| format!("{}: {e}", mat.display()))?;
    let x = lateral.x_dof(setup.ring_node).map_err(err)?;
    let (node, me, phase) = setup.unbalance;
    // The reference speed is the top one: it sets the state's scale.
    let system = LinearSystem::from_matrices(&lateral, sweep.from.max(sweep.to))
        .and_then(|s| s.with_unbalance(lateral.layout(), node, me, phase))
        .map_err(err)?;
    let cb = CraigBampton::from_rotor(&lateral, &[x, x + 1], ModeSelection::Count(setup.modes))
        .map_err(err)?;
    let g = cb.project(lateral.gyroscopic()).map_err(err)?;
    let legs = [
        Segment::Ramp {
            to: sweep.to,
            rate: sweep.rate,
        },
        Segment::Ramp {
            to: sweep.from,
            rate: -sweep.rate,
        },
    ];
    let profile = SpeedProfile::piecewise(sweep.from, &legs).map_err(err)?;
    let gap = if ring { setup.gap } else { 1.0 };
    let ring = SnubberRing::from_units(setup.ring_stiffness, setup.ring_damping, [0.0; 2], gap)
        .map_err(|e| e.to_string())?;
    LinearRotor::new(cb.reduce(&system).map_err(err)?, [0, 1], [0.0; 2])
        .and_then(|r| r.with_speed_profile(&g, profile))
        .and_then(|r| r.with_strobes_per_revolution(SAMPLES))
        .and_then(|r| r.ringed(ring))
        .map_err(err)
}

/// Runs the sweep up and back with and without the ring, prints a line per run and leg and
/// draws `fe_envelope.png` in `out`.
pub fn run(mat: &Path, (sweep, setup): (&Sweep, &Setup), out: &Path) -> Result<(), String> {
    let turn = (sweep.to - sweep.from) / sweep.rate;
    let mut legs = Vec::new();
    for ring in [true, false] {
        let model = model(mat, (sweep, setup), ring)?;
        let start = Instant::now();
        let mut plan = OutputPlan::every_strobe(2.0 * turn);
        // Dense samples 256 a revolution at the top speed: knots of the per-revolution peak.
        plan.dense = Some(DenseSampling {
            t_start: 0.0,
            dt: std::f64::consts::TAU / sweep.from.max(sweep.to) / 256.0,
        });
        let opts = SimOptions::default()
            .with_method(Method::Dop853)
            .with_rtol(1e-9)
            .with_atol(1e-9);
        let mut traj = Trajectory::<Dyn>::default();
        let y0 = model.rotor().rotor().rest_state();
        simulate(&model, 0.0, &y0, &plan, &opts, &mut traj).map_err(|e| e.to_string())?;
        let revs = per_revolution(&traj, SAMPLES as usize, |y| model.rotor().station(y))
            .map_err(|e| e.to_string())?;
        let (up, down): (Vec<Revolution>, Vec<Revolution>) =
            revs.into_iter().partition(|r| r.t_start < turn);
        let name = if ring {
            "on the ring"
        } else {
            "without the ring"
        };
        for (leg, revs) in [("up", &up), ("down", &down)] {
            let seconds = start.elapsed().as_secs_f64();
            summary((name, leg), revs, &traj, (setup.gap, seconds));
        }
        legs.push((format!("{name}, up"), up));
        legs.push((format!("{name}, down"), down));
    }
    draw(out, (sweep, setup), &legs)
}

/// One line: the leg's peak radius, its speed, and the revolutions that touched.
fn summary(
    (name, leg): (&str, &str),
    revs: &[Revolution],
    traj: &Trajectory<Dyn>,
    (gap, seconds): (f64, f64),
) {
    let peak = revs
        .iter()
        .max_by(|a, b| a.max_radius.total_cmp(&b.max_radius));
    let touched = revs.iter().filter(|r| r.touched()).count();
    if let Some(p) = peak {
        println!(
            "fe {name}, {leg}: peak radius {:.4} µm ({:.3} gaps) at {:.1} rad/s; {touched} of {} revolutions touched; {} events in the run, {seconds:.1} s",
            p.max_radius * 1e6,
            p.max_radius / gap,
            p.speed,
            revs.len(),
            traj.events.len()
        );
    }
}

fn draw(
    out: &Path,
    (sweep, setup): (&Sweep, &Setup),
    legs: &[(String, Vec<Revolution>)],
) -> Result<(), String> {
    let title = format!(
        "ROSS rotor ({} modes), ring at node {}: {} ↔ {} rad/s at {} rad/s²",
        setup.modes, setup.ring_node, sweep.from, sweep.to, sweep.rate
    );
    let fig = Figure::new(&title, "Ω (rad/s)", "largest |r| per revolution (µm)")
        .with_columns("omega_rad_s", "radius_um")
        .with_log(false, true)
        .with_note(&format!("the ring's gap: {:.1} µm", setup.gap * 1e6));
    let series: Vec<Series> = legs
        .iter()
        .map(|(label, revs)| {
            Series::new(
                label,
                revs.iter().map(|r| (r.speed, r.max_radius * 1e6)).collect(),
            )
        })
        .collect();
    plot::lines(out.join("fe_envelope.png"), &fig, &series).map_err(|e| e.to_string())
}
