//! A finite-element rotor through its first critical speed (`--fe`): by default ROSS's
//! 204-DOF `rotor_example_with_damping` (the shared rotors' `.mat`, first critical about
//! 182 rad/s) with case S1's ring at node 12 (gap 79.5 µm, 1.1e6 N/m, the out-of-balance
//! 2e-3 kg m at node 12), reduced to node 12's x, y and 24 Craig-Bampton modes; any ROSS
//! export (`--fe-mat`), ring (`--fe-ring-node`, `--fe-gap`, `--fe-ring-stiffness`,
//! `--fe-ring-damping`), out-of-balance (`--fe-unbalance NODE,ME,PHASE`) and mode count
//! (`--fe-modes`). The speed ([`Law`]): up from `--fe-from` to `--fe-to` rad/s at `--fe-rate`
//! rad/s² and back down; or through the user's table `--fe-profile FILE`; or driven by the DC
//! motor `--fe-motor T0,OMEGA0,J` from `--fe-from` for `--fe-duration` s
//! (`rotor::ProfiledLinearRotor`, `rotor::DrivenLinearRotor`: the damping $C + \Omega G$, the
//! force $m e(\Omega^2\cos\varphi + \Omega^\prime\sin\varphi, \ldots)$). The bearings as the
//! export has them, or following the speed (`--fe-bearing-mat SPEED:FILE`, one export per
//! speed: `rotor::BearingTable`). With and without the ring. Prints a line per run and leg, and
//! writes `fe_envelope.png` (with `fe_envelope.csv`): the largest radius of the ring's node in
//! each revolution against its mean speed; with `--fe-rub-map`, over the rotor's rub map
//! ([`super::rub_map`]).

use std::path::{Path, PathBuf};
use std::time::Instant;

use jeffcott::analysis::{per_revolution, Revolution};
use jeffcott::hybrid::{
    simulate, DenseSampling, OutputPlan, RotorModel, SimOptions, StrobeRange, Trajectory,
};
use jeffcott::nalgebra::{DMatrix, DVector, Dyn};
use jeffcott::ode::Method;
use jeffcott::ring::{Kinematics, SnubberRing};
use jeffcott::rotor::{
    BearingTable, CraigBampton, LinearRotor, LinearSystem, ModeSelection, MotorTorque,
    RotorMatrices, Segment, SmoothRotor, SpeedProfile,
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
    /// Bearings that follow the speed: ROSS exports at these speeds (rad/s), their lateral
    /// stiffness and damping linear between them and held beyond them.
    pub bearings: Vec<(f64, PathBuf)>,
    /// Whether to draw the rub map of the same rotor over a sweep's envelope
    /// ([`super::rub_map`]).
    pub rub_map: bool,
}

/// Strobes a revolution of a prescribed speed (the envelope's resolution; a driven rotor's
/// strobes are its shaft's turns, one a revolution).
const SAMPLES: u32 = 16;

/// How the speed goes.
pub enum Law {
    /// Up from `from` to `to` (rad/s) at `rate` (rad/s²) and back down.
    Sweep { from: f64, to: f64, rate: f64 },
    /// Through the points (time s, speed rad/s) of a table, linear between them, held after.
    Table(Vec<(f64, f64)>),
    /// Driven by the DC motor $T = T_0(1 - \Omega/\Omega_0)$ (N m) through the polar inertia
    /// $J$ (kg m²) from `from` (rad/s) for `duration` (s).
    Motor {
        stall: f64,
        no_load: f64,
        inertia: f64,
        from: f64,
        duration: f64,
    },
}

impl Law {
    /// The reference speed (the state's scale, the samples' spacing): the largest the law
    /// prescribes, or the larger of the drive's start and its motor's no-load speed.
    fn reference(&self) -> f64 {
        match self {
            Law::Sweep { from, to, .. } => from.max(*to),
            Law::Table(points) => points.iter().map(|p| p.1).fold(0.0, f64::max),
            Law::Motor { no_load, from, .. } => no_load.max(*from),
        }
    }

    /// How long the run lasts (s).
    fn duration(&self) -> f64 {
        match self {
            Law::Sweep { from, to, rate } => 2.0 * (to - from) / rate,
            Law::Table(points) => points.last().map_or(0.0, |p| p.0),
            Law::Motor { duration, .. } => *duration,
        }
    }

    /// The prescribed profile (a drive has none).
    fn profile(&self) -> Result<SpeedProfile, String> {
        let err = |e: jeffcott::rotor::RotorError| e.to_string();
        let (start, segments) = match self {
            Law::Sweep { from, to, rate } => (
                *from,
                vec![
                    Segment::Ramp {
                        to: *to,
                        rate: *rate,
                    },
                    Segment::Ramp {
                        to: *from,
                        rate: -rate,
                    },
                ],
            ),
            Law::Table(points) => (points[0].1, table_segments(points)?),
            Law::Motor { .. } => return Err("a drive's speed is not prescribed".into()),
        };
        SpeedProfile::piecewise(start, &segments).map_err(err)
    }

    /// The legs a run is cut into for the summary and the envelope: up and down for a sweep,
    /// one otherwise.
    fn legs(&self) -> Vec<(&'static str, f64)> {
        match self {
            Law::Sweep { from, to, rate } => vec![("up", (to - from) / rate), ("down", f64::MAX)],
            Law::Table(_) => vec![("table", f64::MAX)],
            Law::Motor { .. } => vec![("driven", f64::MAX)],
        }
    }
}

/// The table's segments: a ramp (or a hold, where two speeds are equal) to each next point;
/// the first point's time must be 0 and the times increasing.
fn table_segments(points: &[(f64, f64)]) -> Result<Vec<Segment>, String> {
    if points.first().is_none_or(|p| p.0 != 0.0) {
        return Err("--fe-profile: the first time must be 0".into());
    }
    points
        .windows(2)
        .map(|w| {
            let duration = w[1].0 - w[0].0;
            if !(duration > 0.0 && duration.is_finite()) {
                return Err(format!(
                    "--fe-profile: the times must increase ({} after {})",
                    w[1].0, w[0].0
                ));
            }
            Ok(if w[1].1 == w[0].1 {
                Segment::Hold { duration }
            } else {
                Segment::Ramp {
                    to: w[1].1,
                    rate: (w[1].1 - w[0].1) / duration,
                }
            })
        })
        .collect()
}

/// Reads a table of `time,speed` rows (s, rad/s): blank lines, `#` comments and a first line
/// that is not two numbers (a header) skipped; the first time 0, the times increasing.
pub fn read_table(path: &Path) -> Result<Vec<(f64, f64)>, String> {
    let text = std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut points = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let line = line.split('#').next().unwrap_or("").trim();
        if line.is_empty() {
            continue;
        }
        let numbers: Vec<Result<f64, _>> = line.split(',').map(|v| v.trim().parse()).collect();
        match numbers.as_slice() {
            [Ok(t), Ok(w)] => points.push((*t, *w)),
            _ if points.is_empty() && i == 0 => {} // a header
            _ => {
                return Err(format!(
                    "{}:{}: not `time,speed`: {line}",
                    path.display(),
                    i + 1
                ));
            }
        }
    }
    if points.len() < 2 {
        return Err(format!("{}: fewer than 2 points", path.display()));
    }
    table_segments(&points)?;
    Ok(points)
}

/// The lateral matrices of a ROSS export.
fn lateral_of(mat: &Path) -> Result<RotorMatrices, String> {
    RotorMatrices::from_ross_mat(mat)
        .and_then(|m| m.lateral())
        .map_err(|e| format!("{}: {e}", mat.display()))
}

/// The bearings' table from the exports at their speeds, or none.
fn bearing_table(setup: &Setup, dofs: usize) -> Result<Option<BearingTable>, String> {
    if setup.bearings.is_empty() {
        return Ok(None);
    }
    let mut points: Vec<(f64, DMatrix<f64>, DMatrix<f64>)> = Vec::new();
    for (speed, path) in &setup.bearings {
        let lateral = lateral_of(path)?;
        if lateral.dofs() != dofs {
            return Err(format!(
                "{}: {} lateral DOFs, the rotor has {dofs}",
                path.display(),
                lateral.dofs()
            ));
        }
        points.push((
            *speed,
            lateral.stiffness().clone(),
            lateral.damping().clone(),
        ));
    }
    points.sort_by(|a, b| a.0.total_cmp(&b.0));
    let speeds = points.iter().map(|p| p.0).collect();
    let (ks, cs) = points.into_iter().map(|p| (p.1, p.2)).unzip();
    BearingTable::new(speeds, ks, cs)
        .map(Some)
        .map_err(|e| format!("--fe-bearing-mat: {e}"))
}

/// Checks the rotor's and the bearings' exports before a run: each readable, the bearings' of
/// the rotor's size and at increasing, finite speeds.
pub fn check(mat: &Path, setup: &Setup) -> Result<(), String> {
    bearing_table(setup, lateral_of(mat)?.dofs()).map(|_| ())
}

/// The reduced rotor at the reference speed, its gyroscopic matrix and bearing table in the
/// reduced coordinates, and the ring (a gap of 1 m without it).
struct Reduced {
    rotor: LinearRotor,
    g: DMatrix<f64>,
    table: Option<BearingTable>,
    ring: SnubberRing,
}

/// The rotor's matrices as exported, its bearings' table (if any) and its reduction, made with
/// the bearings at the reference speed `top` (the modes and the state's scale there).
pub struct Rotor {
    pub lateral: RotorMatrices,
    pub table: Option<BearingTable>,
    pub cb: CraigBampton,
}

impl Rotor {
    pub fn new(mat: &Path, setup: &Setup, top: f64) -> Result<Self, String> {
        let lateral = lateral_of(mat)?;
        let table = bearing_table(setup, lateral.dofs())?;
        let at_top = at_speed(&lateral, table.as_ref(), top)?;
        let x = at_top.x_dof(setup.ring_node).map_err(|e| e.to_string())?;
        let modes = ModeSelection::Count(setup.modes);
        let cb =
            CraigBampton::from_rotor(&at_top, &[x, x + 1], modes).map_err(|e| e.to_string())?;
        Ok(Self { lateral, table, cb })
    }

    /// The reduced system at `speed` with the out-of-balance, the bearings at that speed.
    pub fn system(&self, setup: &Setup, speed: f64) -> Result<LinearSystem, String> {
        let err = |e: jeffcott::rotor::RotorError| e.to_string();
        let lateral = at_speed(&self.lateral, self.table.as_ref(), speed)?;
        let (node, me, phase) = setup.unbalance;
        let system = LinearSystem::from_matrices(&lateral, speed)
            .and_then(|s| s.with_unbalance(lateral.layout(), node, me, phase))
            .map_err(err)?;
        self.cb.reduce(&system).map_err(err)
    }
}

/// The matrices with the bearings of the table at `speed` (as exported without a table).
fn at_speed(
    lateral: &RotorMatrices,
    table: Option<&BearingTable>,
    speed: f64,
) -> Result<RotorMatrices, String> {
    match table {
        Some(t) => t.matrices_at(lateral, speed).map_err(|e| e.to_string()),
        None => Ok(lateral.clone()),
    }
}

/// The ring of the setup (a gap of 1 m without it).
pub fn ring_of(setup: &Setup, ring: bool) -> Result<SnubberRing, String> {
    let gap = if ring { setup.gap } else { 1.0 };
    SnubberRing::from_units(setup.ring_stiffness, setup.ring_damping, [0.0; 2], gap)
        .map_err(|e| e.to_string())
}

fn reduced(mat: &Path, (law, setup): (&Law, &Setup), ring: bool) -> Result<Reduced, String> {
    let err = |e: jeffcott::rotor::RotorError| e.to_string();
    let top = law.reference();
    let r = Rotor::new(mat, setup, top)?;
    Ok(Reduced {
        rotor: LinearRotor::new(r.system(setup, top)?, [0, 1], [0.0; 2]).map_err(err)?,
        g: r.cb.project(r.lateral.gyroscopic()).map_err(err)?,
        table: (r.table.as_ref())
            .map(|t| r.cb.project_table(t))
            .transpose()
            .map_err(err)?,
        ring: ring_of(setup, ring)?,
    })
}

/// One run of the law with or without the ring: its revolutions and its event count.
fn run_once(
    mat: &Path,
    (law, setup): (&Law, &Setup),
    ring: bool,
) -> Result<(Vec<Revolution>, usize), String> {
    let err = |e: jeffcott::rotor::RotorError| e.to_string();
    let r = reduced(mat, (law, setup), ring)?;
    if let Law::Motor {
        stall,
        no_load,
        inertia,
        from,
        ..
    } = law
    {
        let motor = MotorTorque::linear(*stall, *no_load).map_err(|e| e.to_string())?;
        let mut driven = r.rotor.with_drive(&r.g, *inertia, motor).map_err(err)?;
        if let Some(t) = &r.table {
            driven = driven.with_bearing_table(t).map_err(err)?;
        }
        let model = driven.ringed(r.ring).map_err(err)?;
        let y0 = model.rotor().rest_state(*from);
        let station = |y: &DVector<f64>| model.rotor().station(y);
        return simulate_law(&model, y0, law, (1, &station));
    }
    let mut profiled = r
        .rotor
        .with_speed_profile(&r.g, law.profile()?)
        .and_then(|p| p.with_strobes_per_revolution(SAMPLES))
        .map_err(err)?;
    if let Some(t) = &r.table {
        profiled = profiled.with_bearing_table(t).map_err(err)?;
    }
    let model = profiled.ringed(r.ring).map_err(err)?;
    let y0 = model.rotor().rotor().rest_state();
    let station = |y: &DVector<f64>| model.rotor().station(y);
    simulate_law(&model, y0, law, (SAMPLES as usize, &station))
}

/// The ring node's kinematics in a state.
type Station<'a> = dyn Fn(&DVector<f64>) -> Kinematics + 'a;

/// Simulates `model` from `y0` over the law's duration with strobes (`per_revolution` a
/// revolution) and dense samples 256 a revolution at the reference speed (knots of the
/// per-revolution peak); its revolutions and events.
fn simulate_law<M: RotorModel<Dim = Dyn>>(
    model: &M,
    y0: DVector<f64>,
    law: &Law,
    (per_turn, station): (usize, &Station<'_>),
) -> Result<(Vec<Revolution>, usize), String> {
    let plan = OutputPlan {
        t_end: law.duration(),
        strobe: Some(StrobeRange {
            first: 0,
            last: u64::MAX - 1,
        }),
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: std::f64::consts::TAU / law.reference() / 256.0,
        }),
        events: true,
    };
    let opts = SimOptions::default()
        .with_method(Method::Dop853)
        .with_rtol(1e-9)
        .with_atol(1e-9);
    let mut traj = Trajectory::<Dyn>::default();
    simulate(model, 0.0, &y0, &plan, &opts, &mut traj).map_err(|e| e.to_string())?;
    let revs = per_revolution(&traj, per_turn, station).map_err(|e| e.to_string())?;
    Ok((revs, traj.events.len()))
}

/// Runs the law with and without the ring, prints a line per run and leg and draws
/// `fe_envelope.png` in `out`.
pub fn run(mat: &Path, (law, setup): (&Law, &Setup), out: &Path) -> Result<(), String> {
    let mut legs = Vec::new();
    for ring in [true, false] {
        let start = Instant::now();
        let (revs, events) = run_once(mat, (law, setup), ring)?;
        let seconds = start.elapsed().as_secs_f64();
        let name = if ring {
            "on the ring"
        } else {
            "without the ring"
        };
        let mut from = 0.0;
        for (leg, until) in law.legs() {
            let part: Vec<Revolution> = revs
                .iter()
                .filter(|r| r.t_start >= from && r.t_start < until)
                .cloned()
                .collect();
            from = until;
            summary((name, leg), &part, events, (setup.gap, seconds));
            legs.push((format!("{name}, {leg}"), part));
        }
    }
    let map = match law {
        Law::Sweep { from, to, .. } if setup.rub_map => {
            Some(super::rub_map::compute(mat, setup, (*from, *to))?)
        }
        _ if setup.rub_map => {
            return Err("--fe-rub-map needs a sweep (not a table or a motor)".into())
        }
        _ => None,
    };
    draw(out, (law, setup), &legs, map.as_ref())
}

/// One line: the leg's peak radius, its speed, and the revolutions that touched.
fn summary(
    (name, leg): (&str, &str),
    revs: &[Revolution],
    events: usize,
    (gap, seconds): (f64, f64),
) {
    let peak = revs
        .iter()
        .max_by(|a, b| a.max_radius.total_cmp(&b.max_radius));
    let touched = revs.iter().filter(|r| r.touched()).count();
    if let Some(p) = peak {
        println!(
            "fe {name}, {leg}: peak radius {:.4} µm ({:.3} gaps) at {:.1} rad/s; {touched} of {} revolutions touched; {events} events in the run, {seconds:.1} s",
            p.max_radius * 1e6,
            p.max_radius / gap,
            p.speed,
            revs.len(),
        );
    }
}

fn draw(
    out: &Path,
    (law, setup): (&Law, &Setup),
    legs: &[(String, Vec<Revolution>)],
    map: Option<&jeffcott::stability::RubMap>,
) -> Result<(), String> {
    let how = match law {
        Law::Sweep { from, to, rate } => format!("{from} ↔ {to} rad/s at {rate} rad/s²"),
        Law::Table(points) => format!("a table of {} points", points.len()),
        Law::Motor {
            stall,
            no_load,
            inertia,
            from,
            ..
        } => format!(
            "motor T0 = {stall} N m, Ω0 = {no_load} rad/s, J = {inertia} kg m², from {from} rad/s"
        ),
    };
    let title = format!(
        "ROSS rotor ({} modes), ring at node {}: {how}",
        setup.modes, setup.ring_node
    );
    let fig = Figure::new(&title, "Ω (rad/s)", "largest |r| per revolution (µm)")
        .with_columns("omega_rad_s", "radius_um")
        .with_log(false, true)
        .with_note(&format!("the ring's gap: {:.1} µm", setup.gap * 1e6));
    let mut series: Vec<Series> = legs
        .iter()
        .map(|(label, revs)| {
            Series::new(
                label,
                revs.iter().map(|r| (r.speed, r.max_radius * 1e6)).collect(),
            )
        })
        .collect();
    series.extend(map.into_iter().flat_map(super::rub_map::series));
    plot::lines(out.join("fe_envelope.png"), &fig, &series).map_err(|e| e.to_string())
}
