//! The run-up of a finite-element rotor on the ring: the speed a table of (time, speed)
//! points, linear between them (the crate's `rotor::SpeedProfile::piecewise` and
//! `rotor::ProfiledLinearRotor`), in SI units.

use std::f64::consts::TAU;

use jeffcott::hybrid::{SimOptions, SimStats, Trajectory};
use jeffcott::nalgebra::{DVector, Dyn};
use jeffcott::rotor::{ProfiledLinearRotor, RubbingRotor, Segment, SmoothRotor, SpeedProfile};
use numpy::{AllowTypeChange, PyArrayLike1};
use pyo3::prelude::*;

use crate::bearings::{Bearings, Stack};
use crate::errors::value_error;
use crate::fe::{
    default_method, lateral_matrices, rotor_of, system_at, ArrayLike, Margin, Modes, ModesArg,
    Probes, Reduction, RingAt,
};
use crate::fe_run::{fe_run, FeRun, RunFacts, RunModel};
use crate::options::sim_options;
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

/// The speeds where a reduction's error is measured: 33 equally spaced from the table's
/// slowest (at least 1/32 of its fastest) to its fastest, which is the last.
fn speed_grid(speeds: &Column<'_>) -> Vec<f64> {
    let w = speeds.as_array();
    let top = w.iter().copied().fold(0.0, f64::max);
    let low = w.iter().copied().fold(top, f64::min).max(top / 32.0);
    (0..=32)
        .map(|i| low + (top - low) * i as f64 / 32.0)
        .collect()
}

/// Run-up (or run-down, or any speed history) of a finite-element rotor on the snubber ring,
/// from rest (q = q' = 0, the ring at its centre) at t = 0 to ``t_end`` (s; default the
/// table's last time), sampled every ``dt`` (s; default 1/128 of a revolution at the largest
/// speed).
///
/// The speed Omega(t) (rad/s) goes through the points (``times[i]``, ``speeds[i]``), linear
/// between them (constant acceleration; ``times[0]`` = 0, increasing), held at the last speed
/// after the last point: two points make a ramp, three a ramp up and back down. The equations
/// are M q'' + (C + Omega G) q' + K q = F(t): ``C`` and ``K`` as given, for all speeds, or
/// following the speed: ``bearing_K[i]`` and ``bearing_C[i]`` (each like ``K``, ``C``: shape
/// (S, N, N)) at ``bearing_speeds[i]`` (rad/s, increasing), linear in Omega between them and
/// held beyond them (sample ROSS's ``rotor.K(w)``, ``rotor.C(w)`` on a grid fine enough for
/// that rule; ``jeffcott.ross.FeRotor.run_up`` does). The out-of-balance m e pushes with
/// m e (Omega^2 cos phi + Omega' sin phi, Omega^2 sin phi - Omega' cos phi), phi = phase + the integral of Omega (the radial and the
/// tangential force of the accelerating mass). The rotor, the ring, ``modes``, ``rtol``,
/// ``atol``, ``method``, ``probe_nodes``, ``friction``, ``shaft_radius`` (Coulomb friction at
/// the ring, the shaft's surface speed following the profile) and ``layout`` as in
/// ``fe_transient``, the
/// reduction's error measured
/// at 33 speeds from the table's slowest (at least 1/32 of its fastest) to its fastest; ``ring=False`` runs without
/// the ring (its gap 1 m). Runs with the GIL released; Ctrl-C stops it. Memory: each sample keeps the state and
/// its derivative until the run ends (2 (2 n + 2) floats, n the DOFs integrated).
/// ``ValueError`` for bad input (the crate's message), ``SimulationError`` (``partial``: an
/// ``FeRun``) for a failed run. Returns an ``FeRun`` (its ``speed`` the profile's at the
/// samples, its least damping ratio at the largest speed).
#[pyfunction]
#[pyo3(
    signature = (M, K, C, G, times, speeds, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, ring=true, t_end=None, dt=None, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=ModesArg::Count(0), mode_tolerance=1e-3, probe_nodes=vec![], bearing_speeds=None, bearing_K=None, bearing_C=None, friction=0.0, shaft_radius=None, rtol=1e-8, atol=None, method=None, layout="ross6"),
    // Written out: pyo3 shows a tuple default as `...` (Python's Ellipsis) in help().
    text_signature = "(M, K, C, G, times, speeds, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, ring=True, t_end=None, dt=None, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=0, mode_tolerance=0.001, probe_nodes=[], bearing_speeds=None, bearing_K=None, bearing_C=None, friction=0.0, shaft_radius=None, rtol=1e-08, atol=None, method=None, layout='ross6')"
)]
#[allow(clippy::too_many_arguments, non_snake_case)] // Python keywords, ROSS's names
pub fn fe_run_up(
    py: Python<'_>,
    M: ArrayLike<'_>,
    K: ArrayLike<'_>,
    C: ArrayLike<'_>,
    G: ArrayLike<'_>,
    times: Column<'_>,
    speeds: Column<'_>,
    ring_node: usize,
    gap: f64,
    ring_stiffness: f64,
    ring_damping: f64,
    unbalance: Vec<(usize, f64, f64)>,
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
    if !(friction.is_finite() && friction >= 0.0) {
        return Err(value_error(format!(
            "friction must be finite and >= 0, got {friction}"
        )));
    }
    let profile = profile_of(&times, &speeds)?;
    let top = profile.eta_max();
    if top.is_nan() || top <= 0.0 {
        return Err(value_error("the speeds must not all be zero"));
    }
    let t_end = match t_end {
        Some(t) => t,
        None if profile.ramp_time() > 0.0 => profile.ramp_time(),
        None => return Err(value_error("a constant speed needs t_end")),
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
    let grid = speed_grid(&speeds);
    let (model, reduction, margin, probes) = py.detach(|| {
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
        let profiled = rotor
            .with_speed_profile(&g, profile.clone())
            .and_then(|r| match &table {
                Some(table) => r.with_bearing_table(table),
                None => Ok(r),
            })
            .and_then(|r| r.ringed(ring))
            .map_err(value_error)?;
        PyResult::Ok((profiled, reduction, margin, probes))
    })?;
    margin.warn(py)?;
    let opts = sim_options(
        Some(rtol),
        Some(atol.unwrap_or(rtol)),
        Some(method.unwrap_or(default_method(modes))),
    )?
    .with_max_events_per_period(u32::MAX);
    let period = TAU / top;
    let dt = dt.unwrap_or(period / 128.0);
    let output = dense_output(t_end, dt)?.with_strobes();
    let mut y0 = model.rotor().rotor().rest_state();
    model.make_consistent(&mut y0).map_err(value_error)?;
    let run = Run {
        y0,
        output,
        opts,
        profile: &profile,
        reduction,
        margin,
        probes: (&probe_nodes, &probes),
    };
    match (friction, shaft_radius) {
        (0.0, _) => run.of(py, &model),
        (mu, Some(radius)) => {
            let model = RubbingRotor::new(model, mu, radius).map_err(value_error)?;
            run.of(py, &model)
        }
        (_, None) => Err(value_error(
            "friction needs shaft_radius: the shaft's radius at the ring node (m)",
        )),
    }
}

/// A run-up's plan besides its model.
struct Run<'a> {
    y0: DVector<f64>,
    output: Output,
    opts: SimOptions,
    profile: &'a SpeedProfile,
    reduction: Reduction,
    margin: Margin,
    probes: (&'a [usize], &'a Probes),
}

impl Run<'_> {
    /// Runs `model` (with or without friction at the ring) as an ``FeRun``.
    fn of<M: RunModel<Rotor = ProfiledLinearRotor>>(
        self,
        py: Python<'_>,
        model: &M,
    ) -> PyResult<FeRun> {
        let displacement = |y: &DVector<f64>| model.smooth().rotor().station_displacement(y);
        let speed = |t: f64| self.profile.eta(t);
        let phase = |t: f64| self.profile.phase(t);
        let facts = RunFacts {
            model,
            displacement: &displacement,
            speed: &speed,
            phase: &phase,
            dofs: model.smooth().rotor().system().dofs(),
            reduction: self.reduction,
            margin: self.margin,
            probes: self.probes,
        };
        let result = |py: Python<'_>, traj: &Trajectory<Dyn>, stats: &SimStats| {
            fe_run(py, &facts, traj, stats)
        };
        runs::run_into(py, model, self.y0, self.output, &self.opts, result)
    }
}
