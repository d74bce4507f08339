//! The run-up of a finite-element rotor on the ring, in SI units: the speed a table of (time,
//! speed) points, linear between them (the crate's `rotor::SpeedProfile::piecewise` and
//! `rotor::ProfiledLinearRotor`), or driven by a motor through the polar inertia (the non-ideal
//! drive, `rotor::DrivenLinearRotor`).

use std::f64::consts::TAU;

use jeffcott::hybrid::{SimOptions, SimStats, Trajectory};
use jeffcott::nalgebra::{DMatrix, DVector, Dyn};
use jeffcott::rotor::{
    BearingTable, DrivenLinearRotor, LinearRotor, ProfiledLinearRotor, RingedRotor, RubbingRotor,
    Segment, SmoothRotor, SpeedProfile,
};
use numpy::{AllowTypeChange, PyArrayLike1};
use pyo3::prelude::*;

use crate::bearings::{Bearings, Stack};
use crate::errors::value_error;
use crate::fe::{
    default_method, lateral_matrices, rotor_of, system_at, ArrayLike, Margin, Modes, ModesArg,
    Probes, Reduction, RingAt,
};
use crate::fe_run::{fe_run, FeRun, RunFacts, RunModel};
use crate::motor::Motor;
use crate::options::{coulomb, sim_options};
use crate::paper::dense_output;
use crate::runs::{self, Output};

/// A 1-D array-like of numbers, as float64.
type Column<'py> = PyArrayLike1<'py, f64, AllowTypeChange>;

/// The profile through the table's points: from `times[0]` = 0 at `speeds[0]`, a ramp (or a
/// hold, where two speeds are equal) to each next point; after the last, its speed held.
fn profile_of(times: &Column<'_>, speeds: &Column<'_>) -> PyResult<SpeedProfile> {
    let (t, w) = (times.as_array(), speeds.as_array());
    if t.len() != w.len() || t.is_empty() {
        return Err(value_error(format!(
            "times and speeds must be as long as each other and not empty, got {} and {}",
            t.len(),
            w.len()
        )));
    }
    if t[0] != 0.0 {
        return Err(value_error(format!("times[0] = {} must be 0", t[0])));
    }
    let mut segments = Vec::with_capacity(t.len() - 1);
    for i in 1..t.len() {
        let duration = t[i] - t[i - 1];
        if !(duration > 0.0 && duration.is_finite()) {
            return Err(value_error(format!(
                "times must increase: times[{i}] = {} after {}",
                t[i],
                t[i - 1]
            )));
        }
        segments.push(if w[i] == w[i - 1] {
            Segment::Hold { duration }
        } else {
            Segment::Ramp {
                to: w[i],
                rate: (w[i] - w[i - 1]) / duration,
            }
        });
    }
    SpeedProfile::piecewise(w[0], &segments).map_err(value_error)
}

/// The speeds where a reduction's error is measured: 33 equally spaced from the slowest of
/// `speeds` (at least 1/32 of the fastest) to the fastest, which is the last.
fn speed_grid(speeds: &[f64]) -> Vec<f64> {
    let top = speeds.iter().copied().fold(0.0, f64::max);
    let low = speeds.iter().copied().fold(top, f64::min).max(top / 32.0);
    (0..=32)
        .map(|i| low + (top - low) * i as f64 / 32.0)
        .collect()
}

/// How the speed goes: a table's profile, or a motor's drive.
enum Law {
    Profile(SpeedProfile),
    Drive {
        motor: Motor,
        inertia: f64,
        speed0: f64,
    },
}

impl Law {
    /// From the keywords: ``times`` and ``speeds``, or ``motor``, ``inertia`` and ``speed0``.
    fn new(
        table: (Option<Column<'_>>, Option<Column<'_>>),
        drive: (Option<Motor>, Option<f64>, Option<f64>),
    ) -> PyResult<Self> {
        match (table, drive) {
            ((Some(times), Some(speeds)), (None, None, None)) => {
                Ok(Law::Profile(profile_of(&times, &speeds)?))
            }
            ((None, None), (Some(motor), Some(inertia), Some(speed0))) => {
                if !(speed0.is_finite() && speed0 >= 0.0) {
                    return Err(value_error(format!(
                        "speed0 = {speed0} must be finite and >= 0"
                    )));
                }
                Ok(Law::Drive {
                    motor,
                    inertia,
                    speed0,
                })
            }
            ((None, None), _) => Err(value_error(
                "a drive needs motor, inertia and speed0 (or give times and speeds)",
            )),
            ((Some(_), Some(_)), _) => Err(value_error(
                "give times and speeds (a speed profile) or motor, inertia and speed0 (a \
                 drive), not both",
            )),
            _ => Err(value_error("times and speeds go together")),
        }
    }

    /// The reference speed (the state's scale, the forcing period of the step bound and the
    /// margin's): the profile's largest; the drive's start or its motor's no-load speed,
    /// whichever is larger.
    fn reference(&self) -> f64 {
        match self {
            Law::Profile(p) => p.eta_max(),
            Law::Drive { motor, speed0, .. } => motor.no_load_speed().max(*speed0),
        }
    }

    /// The speeds the run is expected to pass: the profile's points, or the drive's start and
    /// reference.
    fn speeds(&self, table: &[f64]) -> Vec<f64> {
        match self {
            Law::Profile(_) => table.to_vec(),
            Law::Drive { speed0, .. } => vec![*speed0, self.reference()],
        }
    }
}

/// Run-up (or run-down, or any speed history) of a finite-element rotor on the snubber ring,
/// from rest (q = q' = 0, the ring at its centre) at t = 0 to ``t_end`` (s; default the
/// table's last time), sampled every ``dt`` (s; default 1/128 of a revolution at the reference
/// speed: the largest of the table, or of a drive's ``speed0`` and its motor's no-load speed).
///
/// The speed Omega(t) (rad/s), either prescribed or driven:
///
/// * prescribed: through the points (``times[i]``, ``speeds[i]``), linear between them
///   (constant acceleration; ``times[0]`` = 0, increasing), held at the last speed after the
///   last point: two points make a ramp, three a ramp up and back down;
/// * driven (the non-ideal drive: give ``motor``, ``inertia`` and ``speed0`` instead of
///   ``times`` and ``speeds``, and ``t_end``): J Omega' = T(Omega) minus the out-of-balance's
///   reaction torque (and, with ``friction``, the rub torque), from Omega = ``speed0`` (rad/s)
///   and the shaft's angle 0; ``motor`` a ``jeffcott.Motor`` (T in N m), ``inertia`` J the
///   polar inertia of everything that spins (kg m^2, the out-of-balance's included; above
///   the out-of-balance's own share, which any physical rotor is). The revolutions are the
///   shaft's turns, located where its angle reaches 2 pi k.
///
/// The equations are M q'' + (C + Omega G) q' + K q = F(t): ``C`` and ``K`` as given, for all
/// speeds, or following the speed: ``bearing_K[i]`` and ``bearing_C[i]`` (each like ``K``,
/// ``C``: shape (S, N, N)) at ``bearing_speeds[i]`` (rad/s, increasing), linear in Omega
/// between them and held beyond them (sample ROSS's ``rotor.K(w)``, ``rotor.C(w)`` on a grid
/// fine enough for that rule; ``jeffcott.ross.FeRotor.run_up`` does). The out-of-balance m e
/// pushes with m e (Omega^2 cos phi + Omega' sin phi, Omega^2 sin phi - Omega' cos phi), phi =
/// phase + the shaft's angle (the radial and the tangential force of the accelerating mass).
/// The rotor, the ring, ``modes``, ``rtol``, ``atol``, ``method``, ``probe_nodes``,
/// ``friction``, ``shaft_radius`` (Coulomb friction at the ring, the shaft's surface speed
/// following the speed) and ``layout`` as in ``fe_transient``, the reduction's error measured
/// at 33 speeds from the slowest of the run (at least 1/32 of the reference) to the reference;
/// ``ring=False`` runs without the ring (its gap 1 m). Runs with the GIL released; Ctrl-C stops
/// it. Memory: each sample keeps the state and its derivative until the run ends (2 (2 n + 4)
/// floats, n the DOFs integrated). ``ValueError`` for bad input (the crate's message),
/// ``SimulationError`` (``partial``: an ``FeRun``) for a failed run. Returns an ``FeRun`` (its
/// ``speed`` and ``phase`` the profile's or the drive's at the samples, its least damping
/// ratio at the reference speed).
#[pyfunction]
#[pyo3(
    signature = (M, K, C, G, times=None, speeds=None, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, motor=None, inertia=None, speed0=None, ring=true, t_end=None, dt=None, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=ModesArg::Count(0), mode_tolerance=1e-3, probe_nodes=vec![], bearing_speeds=None, bearing_K=None, bearing_C=None, friction=0.0, shaft_radius=None, rtol=1e-8, atol=None, method=None, layout="ross6"),
    // Written out: pyo3 shows a tuple default as `...` (Python's Ellipsis) in help().
    text_signature = "(M, K, C, G, times=None, speeds=None, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, motor=None, inertia=None, speed0=None, ring=True, t_end=None, dt=None, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=0, mode_tolerance=0.001, probe_nodes=[], bearing_speeds=None, bearing_K=None, bearing_C=None, friction=0.0, shaft_radius=None, rtol=1e-08, atol=None, method=None, layout='ross6')"
)]
#[allow(clippy::too_many_arguments, non_snake_case)] // Python keywords, ROSS's names
pub fn fe_run_up(
    py: Python<'_>,
    M: ArrayLike<'_>,
    K: ArrayLike<'_>,
    C: ArrayLike<'_>,
    G: ArrayLike<'_>,
    times: Option<Column<'_>>,
    speeds: Option<Column<'_>>,
    ring_node: usize,
    gap: f64,
    ring_stiffness: f64,
    ring_damping: f64,
    unbalance: Vec<(usize, f64, f64)>,
    motor: Option<PyRef<'_, Motor>>,
    inertia: Option<f64>,
    speed0: Option<f64>,
    ring: bool,
    t_end: Option<f64>,
    dt: Option<f64>,
    preload: (f64, f64),
    ring_offset: (f64, f64),
    modes: ModesArg,
    mode_tolerance: f64,
    probe_nodes: Vec<usize>,
    bearing_speeds: Option<Column<'_>>,
    bearing_K: Option<Stack<'_>>,
    bearing_C: Option<Stack<'_>>,
    friction: f64,
    shaft_radius: Option<f64>,
    rtol: f64,
    atol: Option<f64>,
    method: Option<&str>,
    layout: &str,
) -> PyResult<FeRun> {
    let modes = Modes::new(modes, mode_tolerance)?;
    let friction = coulomb(friction, shaft_radius, "in m")?;
    let table: Vec<f64> = speeds
        .as_ref()
        .map_or(Vec::new(), |s| s.as_array().to_vec());
    let motor = motor.map(|m| (*m).clone());
    let law = Law::new((times, speeds), (motor, inertia, speed0))?;
    let top = law.reference();
    if top.is_nan() || top <= 0.0 {
        return Err(value_error("the speeds must not all be zero"));
    }
    let t_end = match (&law, t_end) {
        (_, Some(t)) => t,
        (Law::Profile(p), None) if p.ramp_time() > 0.0 => p.ramp_time(),
        (Law::Profile(_), None) => return Err(value_error("a constant speed needs t_end")),
        (Law::Drive { .. }, None) => return Err(value_error("a drive needs t_end")),
    };
    let mut lateral = lateral_matrices([&M, &K, &C, &G], layout)?;
    let bearings = Bearings::from_args(
        (&M, &G),
        layout,
        (bearing_speeds, bearing_K.as_ref(), bearing_C.as_ref()),
    )?;
    if let Some(b) = &bearings {
        // The bearings at the reference speed: the reduction's modes and the margin's.
        lateral = b.lateral_at(&lateral, top)?;
    }
    // The reference speed is the top one: it sets the state's scale.
    let system = system_at(&lateral, top, &unbalance)?;
    let gap = if ring { gap } else { 1.0 };
    let at = RingAt::new(
        ring_node,
        [gap, ring_stiffness, ring_damping],
        preload,
        ring_offset,
    )?;
    let ring = at.ring;
    let grid = speed_grid(&law.speeds(&table));
    let built = py.detach(|| {
        let (rotor, cb, reduction) = rotor_of(&lateral, system, &at, (modes, &grid))?;
        let probes = Probes::new(&lateral, cb.as_ref(), &probe_nodes)?;
        let g = match &cb {
            Some(cb) => cb.project(lateral.gyroscopic()).map_err(value_error)?,
            None => lateral.gyroscopic().clone(),
        };
        let form = rotor.linear_free_flight().map(|f| f.prepare());
        let margin = Margin::of(form.as_ref().map(|f| f.as_ref()));
        let table = bearings
            .as_ref()
            .map(|b| b.in_run(cb.as_ref()))
            .transpose()?;
        PyResult::Ok(Built {
            rotor,
            g,
            table,
            reduction,
            margin,
            probes,
        })
    })?;
    built.margin.warn(py)?;
    let method = method.unwrap_or(default_method(modes));
    let opts = sim_options(Some(rtol), Some(atol.unwrap_or(rtol)), Some(method))?
        .with_max_events_per_period(u32::MAX);
    let dt = dt.unwrap_or(TAU / top / 128.0);
    let output = dense_output(t_end, dt)?.with_strobes();
    let plan = Plan {
        output,
        opts,
        method,
        reduction: built.reduction,
        margin: built.margin,
        probes: (&probe_nodes, &built.probes),
        friction,
    };
    match &law {
        Law::Profile(profile) => {
            let profiled = built
                .rotor
                .with_speed_profile(&built.g, profile.clone())
                .and_then(|r| match &built.table {
                    Some(table) => r.with_bearing_table(table),
                    None => Ok(r),
                })
                .and_then(|r| r.ringed(ring))
                .map_err(value_error)?;
            let y0 = profiled.rotor().rotor().rest_state();
            let speed = |t: f64, _: &DVector<f64>| profile.eta(t);
            let phase = |t: f64, _: &DVector<f64>| profile.phase(t);
            plan.run(py, profiled, y0, (&speed, &phase))
        }
        Law::Drive {
            motor,
            inertia,
            speed0,
        } => {
            let driven = built
                .rotor
                .with_drive(&built.g, *inertia, motor.torque.clone())
                .and_then(|r| match &built.table {
                    Some(table) => r.with_bearing_table(table),
                    None => Ok(r),
                })
                .and_then(|r| r.ringed(ring))
                .map_err(value_error)?;
            let y0 = driven.rotor().rest_state(*speed0);
            let (si, pi) = (driven.rotor().speed_index(), driven.rotor().phase_index());
            let speed = move |_: f64, y: &DVector<f64>| y[si];
            let phase = move |_: f64, y: &DVector<f64>| y[pi];
            plan.run(py, driven, y0, (&speed, &phase))
        }
    }
}

/// What a run-up's rotor is built from, either law.
struct Built {
    rotor: LinearRotor,
    g: DMatrix<f64>,
    table: Option<BearingTable>,
    reduction: Reduction,
    margin: Margin,
    probes: Probes,
}

/// The ring node's displacement in a state of a run-up's rotor (m, from its undeflected
/// position).
trait Displaced: SmoothRotor<Dim = Dyn> + Sync {
    fn displacement(&self, y: &DVector<f64>) -> [f64; 2];
    /// The degrees of freedom integrated.
    fn dofs(&self) -> usize;
}

impl Displaced for ProfiledLinearRotor {
    fn displacement(&self, y: &DVector<f64>) -> [f64; 2] {
        self.rotor().station_displacement(y)
    }
    fn dofs(&self) -> usize {
        self.rotor().system().dofs()
    }
}

impl Displaced for DrivenLinearRotor {
    fn displacement(&self, y: &DVector<f64>) -> [f64; 2] {
        self.station_displacement(y)
    }
    fn dofs(&self) -> usize {
        self.rotor().system().dofs()
    }
}

/// The speed and the shaft's angle at a sample.
type SpeedAndPhase<'a> = (
    &'a dyn Fn(f64, &DVector<f64>) -> f64,
    &'a dyn Fn(f64, &DVector<f64>) -> f64,
);

/// A run-up's plan besides its model.
struct Plan<'a> {
    output: Output,
    opts: SimOptions,
    /// The method's name, as asked for or picked.
    method: &'a str,
    reduction: Reduction,
    margin: Margin,
    probes: (&'a [usize], &'a Probes),
    /// Coulomb friction at the ring: (mu, the shaft's radius in m).
    friction: Option<(f64, f64)>,
}

impl Plan<'_> {
    /// Runs `model` from rest (its ring placed), with friction at the ring if asked for.
    fn run<R: Displaced>(
        self,
        py: Python<'_>,
        model: RingedRotor<R>,
        mut y0: DVector<f64>,
        law: SpeedAndPhase<'_>,
    ) -> PyResult<FeRun> {
        model.make_consistent(&mut y0).map_err(value_error)?;
        match self.friction {
            None => self.of(py, &model, y0, law),
            Some((mu, radius)) => {
                let model = RubbingRotor::new(model, mu, radius).map_err(value_error)?;
                self.of(py, &model, y0, law)
            }
        }
    }

    /// Runs `model` (with or without friction at the ring) as an ``FeRun``.
    fn of<M: RunModel>(
        self,
        py: Python<'_>,
        model: &M,
        y0: DVector<f64>,
        (speed, phase): SpeedAndPhase<'_>,
    ) -> PyResult<FeRun>
    where
        M::Rotor: Displaced,
    {
        let displacement = |y: &DVector<f64>| model.smooth().displacement(y);
        let facts = RunFacts {
            model,
            displacement: &displacement,
            speed,
            phase,
            dofs: model.smooth().dofs(),
            reduction: self.reduction,
            margin: self.margin,
            probes: self.probes,
            method: self.method,
        };
        let result = |py: Python<'_>, traj: &Trajectory<Dyn>, stats: &SimStats| {
            fe_run(py, &facts, traj, stats)
        };
        runs::run_into(py, model, y0, self.output, &self.opts, result)
    }
}
