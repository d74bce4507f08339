//! A finite-element rotor on the snubber ring from numpy matrices, as a ROSS user has them
//! (``rotor.M()``, ``rotor.K(w)``, ``rotor.C(w)``, ``rotor.G()``): the transient from rest at
//! the ring node, in SI units.

use std::ffi::CString;

use jeffcott::hybrid::{SimStats, Trajectory};
use jeffcott::nalgebra::{DMatrix, DVector, Dyn};
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{
    CraigBampton, DofLayout, LinearRotor, LinearSystem, ModeSelection, RingedRotor, RotorMatrices,
};
use numpy::{AllowTypeChange, PyArray1, PyArrayLike2};
use pyo3::exceptions::PyRuntimeWarning;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::array;
use crate::chunks;
use crate::errors::value_error;
use crate::options::sim_options;
use crate::paper::dense_output;

/// A transient of a finite-element rotor on the ring: the ring node's displacement at uniform
/// samples, and the contact events.
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct FeTransient {
    /// Sample times t_i = i dt (s), float64, shape (N+1,).
    pub t: Py<PyArray1<f64>>,
    /// The ring node's x from its undeflected position (m), float64, shape (N+1,).
    pub x: Py<PyArray1<f64>>,
    /// The ring node's y (m), float64, shape (N+1,).
    pub y: Py<PyArray1<f64>>,
    /// Regime at the samples (1: no contact, 2..=5 contact), uint8, shape (N+1,).
    pub regimes: Py<PyArray1<u8>>,
    /// Times of the contact onsets (s), float64.
    pub onsets: Py<PyArray1<f64>>,
    /// Times of the contact losses (s), float64.
    pub losses: Py<PyArray1<f64>>,
    /// Degrees of freedom integrated (after dropping z, theta and any reduction).
    pub dofs: usize,
    /// The least damping ratio of the integrated rotor's modes without contact,
    /// min -Re(lambda)/|lambda| over its nonzero eigenvalues (NaN if the eigen-decomposition
    /// was refused as ill-conditioned).
    pub least_damping_ratio: f64,
    /// Whether a mode grows without contact (``least_damping_ratio < 0``): the rotor is
    /// linearly unstable, its free response grows whatever the ring does (a RuntimeWarning
    /// says so when the run starts).
    pub linearly_unstable: bool,
    /// The work done (steps, rejected, rhs_evals, ..., jacobians, lu_decompositions).
    pub stats: Py<PyDict>,
}

/// A matrix from any array-like that numpy reads as 2-D numbers (arrays of any float or int
/// type, any memory order, nested lists), as float64.
type ArrayLike<'py> = PyArrayLike2<'py, f64, AllowTypeChange>;

fn matrix(name: &str, a: &ArrayLike<'_>) -> PyResult<DMatrix<f64>> {
    let v = a.as_array();
    let (r, c) = v.dim();
    if r != c {
        return Err(value_error(format!(
            "{name} must be square, got shape ({r}, {c})"
        )));
    }
    Ok(DMatrix::from_fn(r, c, |i, j| v[(i, j)]))
}

fn layout(name: &str) -> PyResult<DofLayout> {
    match name {
        "ross6" => Ok(DofLayout::Ross6),
        "lateral4" => Ok(DofLayout::Lateral4),
        other => Err(value_error(format!(
            "layout '{other}' is not ross6 or lateral4"
        ))),
    }
}

/// The ring and where it sits: node, gap (m), unit stiffness (N/m), unit damping (N s/m),
/// preloads and rest-centre offset (m).
struct RingAt {
    node: usize,
    ring: SnubberRing,
    offset: [f64; 2],
}

/// The rotor on the ring, full or reduced to `modes` Craig-Bampton modes.
fn build(
    lateral: &RotorMatrices,
    system: LinearSystem,
    at: RingAt,
    modes: usize,
) -> PyResult<RingedRotor<LinearRotor>> {
    let rotor = if modes == 0 {
        let x = lateral.x_dof(at.node).map_err(value_error)?;
        LinearRotor::new(system, [x, x + 1], at.offset)
    } else {
        let cb = CraigBampton::at_node(lateral, at.node, ModeSelection::Count(modes))
            .map_err(value_error)?;
        // The reduced coordinates 0 and 1 are the ring node's x and y.
        LinearRotor::new(cb.reduce(&system).map_err(value_error)?, [0, 1], at.offset)
    };
    rotor
        .map_err(value_error)?
        .ringed(at.ring)
        .map_err(value_error)
}

/// The least damping ratio of the integrated rotor without contact, from the eigenvalues of
/// its free flight's closed form (NaN where that was refused as ill-conditioned).
fn least_damping_ratio(model: &RingedRotor<LinearRotor>) -> f64 {
    match model.closed_form() {
        Some(Ok(form)) => form.least_damping_ratio(),
        _ => f64::NAN,
    }
}

/// A RuntimeWarning that the rotor is linearly unstable (`zeta` < 0).
fn warn_if_unstable(py: Python<'_>, zeta: f64) -> PyResult<()> {
    if zeta >= 0.0 || zeta.is_nan() {
        return Ok(());
    }
    let message = format!(
        "the rotor is linearly unstable without contact (least damping ratio {:.3} %): its \
         free response grows whatever the ring does; check the bearings' cross-coupling",
        100.0 * zeta
    );
    let message = CString::new(message).map_err(value_error)?;
    PyErr::warn(py, &py.get_type::<PyRuntimeWarning>(), &message, 1)
}

fn transient(
    py: Python<'_>,
    model: &RingedRotor<LinearRotor>,
    zeta: f64,
    traj: &Trajectory<Dyn>,
    stats: &SimStats,
) -> PyResult<FeTransient> {
    let at = |y: &DVector<f64>| model.rotor().station_displacement(y);
    let s = &traj.samples;
    let changes = |onset: bool| {
        let e = traj
            .events
            .iter()
            .filter(|e| e.from != e.to && (e.from == 1) == onset);
        array(py, e.map(|e| e.t))
    };
    Ok(FeTransient {
        t: array(py, s.iter().map(|p| p.t)),
        x: array(py, s.iter().map(|p| at(&p.y)[0])),
        y: array(py, s.iter().map(|p| at(&p.y)[1])),
        regimes: array(py, s.iter().map(|p| p.label)),
        onsets: changes(true),
        losses: changes(false),
        dofs: model.rotor().system().dofs(),
        least_damping_ratio: zeta,
        linearly_unstable: zeta < 0.0,
        stats: chunks::stats_dict(py, stats)?.unbind(),
    })
}

/// Transient of a finite-element rotor on the snubber ring, from rest (q = q' = 0, the ring at
/// its centre) at t = 0 to ``t_end`` (s), sampled ``samples`` + 1 times (every t_end/samples).
///
/// ``M, K, C, G``: square float64 arrays in SI units as ROSS gives them (``rotor.M(w)``,
/// ``rotor.K(w)``, ``rotor.C(w)``, ``rotor.G()``) for M q'' + (C + speed G) q' + K q = F,
/// layout ``"ross6"`` (6 DOFs a node: x, y, z, alpha, beta, theta; z and theta are dropped
/// after checking they are uncoupled) or ``"lateral4"``. ``speed`` in rad/s. ``unbalance``:
/// a list of (node, m e in kg m, phase in rad). The ring at ``ring_node`` (0-based): radial
/// ``gap`` (m), unit stiffness ``ring_stiffness`` (N/m), unit damping ``ring_damping``
/// (N s/m), ``preload`` (Delta_x, Delta_y) (m), rest centre at ``ring_offset`` (m) from the
/// undeflected node. ``modes`` > 0 reduces the rotor to that many Craig-Bampton modes (the
/// ring node's x, y kept physical). Method: radau5 for the full model, dop853 for a reduced
/// one, unless given; ``atol`` defaults to ``rtol``. Runs ``chunk`` samples at a time with
/// the GIL released, Ctrl-C checked between chunks. ``ValueError`` for bad input (the
/// crate's message), ``SimulationError`` (``partial``: an ``FeTransient``) for a failed run.
#[pyfunction]
#[pyo3(
    signature = (M, K, C, G, speed, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, t_end, samples, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=0, rtol=1e-8, atol=None, method=None, layout="ross6", chunk=50),
    // Written out: pyo3 shows a tuple default as `...` (Python's Ellipsis) in help().
    text_signature = "(M, K, C, G, speed, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, t_end, samples, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=0, rtol=1e-08, atol=None, method=None, layout='ross6', chunk=50)"
)]
#[allow(clippy::too_many_arguments, non_snake_case)] // Python keywords, ROSS's names
pub fn fe_transient(
    py: Python<'_>,
    M: ArrayLike<'_>,
    K: ArrayLike<'_>,
    C: ArrayLike<'_>,
    G: ArrayLike<'_>,
    speed: f64,
    ring_node: usize,
    gap: f64,
    ring_stiffness: f64,
    ring_damping: f64,
    unbalance: Vec<(usize, f64, f64)>,
    t_end: f64,
    samples: u64,
    preload: (f64, f64),
    ring_offset: (f64, f64),
    modes: usize,
    rtol: f64,
    atol: Option<f64>,
    method: Option<&str>,
    layout: &str,
    chunk: u64,
) -> PyResult<FeTransient> {
    let (m, k, c, g) = (
        matrix("M", &M)?,
        matrix("K", &K)?,
        matrix("C", &C)?,
        matrix("G", &G)?,
    );
    let full = RotorMatrices::new(m, c, g, k, self::layout(layout)?).map_err(value_error)?;
    let lateral = full.lateral().map_err(value_error)?;
    let mut system = LinearSystem::from_matrices(&lateral, speed).map_err(value_error)?;
    for (node, me, phase) in unbalance {
        system = system
            .with_unbalance(lateral.layout(), node, me, phase)
            .map_err(value_error)?;
    }
    let ring = SnubberRing::from_units(ring_stiffness, ring_damping, [preload.0, preload.1], gap)
        .map_err(value_error)?;
    let at = RingAt {
        node: ring_node,
        ring,
        offset: [ring_offset.0, ring_offset.1],
    };
    let model = py.detach(|| build(&lateral, system, at, modes))?;
    let zeta = least_damping_ratio(&model);
    warn_if_unstable(py, zeta)?;
    let default_method = if modes == 0 { "radau5" } else { "dop853" };
    let opts = sim_options(
        Some(rtol),
        Some(atol.unwrap_or(rtol)),
        Some(method.unwrap_or(default_method)),
    )?
    .with_max_events_per_period(u32::MAX);
    if samples == 0 {
        return Err(value_error("samples must be at least 1"));
    }
    let dt = t_end / samples as f64;
    let output = dense_output(t_end, dt, chunk.max(1) as f64 * dt)?;
    let mut y0 = model.rotor().rest_state();
    model.make_consistent(&mut y0).map_err(value_error)?;
    let result = |py: Python<'_>, traj: &Trajectory<_>, stats: &SimStats| {
        transient(py, &model, zeta, traj, stats)
    };
    chunks::run_into(py, &model, y0, output, &opts, result)
}
