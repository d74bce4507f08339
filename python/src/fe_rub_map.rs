//! The rub map of a finite-element rotor on the ring: its branch of periodic orbits continued
//! in speed (the crate's `stability::rub_map`), from numpy matrices as a ROSS user has them.

use jeffcott::nalgebra::DVector;
use jeffcott::rotor::{LinearRotor, RingedRotor, SmoothRotor};
use jeffcott::stability::{rub_map, RingReading, RubMap, RubMapOptions, SpecialPoint};
use numpy::{AllowTypeChange, PyArray1, PyArrayLike1};
use pyo3::prelude::*;

use crate::arrays::array;
use crate::bearings::{Bearings, Stack};
use crate::continuation::{branch_end, options};
use crate::errors::value_error;
use crate::fe::{
    default_method, lateral_matrices, rotor_of, system_at, system_of, ArrayLike, Modes, ModesArg,
    RingAt,
};
use crate::interrupt::CtrlC;
use crate::lyapunov::stability_error;
use crate::options::sim_options;
use crate::runs;

/// A special point of a rub map.
#[pyclass(name = "RubSpecialPoint", module = "jeffcott", frozen, get_all)]
pub struct RubSpecialPoint {
    /// "fold", "flip", "neimark-sacker" or "grazing".
    pub kind: String,
    /// The speed (rad/s) where it is (the final bracket's midpoint; meaningful if
    /// ``converged``).
    pub speed: f64,
    /// The final bracket's speeds (near end, far end).
    pub bracket: (f64, f64),
    /// Whether the bracket narrowed to ``bracket_width``; if not, ``unconverged`` says why.
    pub converged: bool,
    /// Why the location stopped early, or None.
    pub unconverged: Option<String>,
    /// The largest Floquet multiplier's modulus at the near end.
    pub spectral_radius: f64,
    /// Contact onsets per orbit before and after.
    pub contacts: (usize, usize),
}

/// The rub map of a finite-element rotor: one continued branch of period-1 orbits, each
/// measured at the ring node, points in order of arclength (the speed goes back at a fold).
#[pyclass(name = "RubMap", module = "jeffcott", frozen, get_all)]
pub struct FeRubMap {
    /// The speed (rad/s) of each orbit, float64, shape (N,).
    pub speed: Py<PyArray1<f64>>,
    /// The ring node's largest radius from the ring's centre over the orbit (m), located
    /// between the samples, float64, shape (N,).
    pub amplitude: Py<PyArray1<f64>>,
    /// The fraction of the period in contact (1: a full annular rub), float64, shape (N,).
    pub contact_fraction: Py<PyArray1<f64>>,
    /// The largest normal contact force over the orbit's samples (N), float64, shape (N,).
    pub peak_force: Py<PyArray1<f64>>,
    /// Whether every Floquet multiplier is inside the unit circle, bool, shape (N,).
    pub stable: Py<PyArray1<bool>>,
    /// The largest multiplier's modulus, float64, shape (N,).
    pub spectral_radius: Py<PyArray1<f64>>,
    /// Contact onsets per orbit (0 in a full annular rub: no onset), int64, shape (N,).
    pub contacts: Py<PyArray1<i64>>,
    /// The special points, in order of arclength.
    pub specials: Vec<Py<RubSpecialPoint>>,
    /// How the branch ended: "reached", "max-points", "stalled" or "stopped".
    pub end: String,
    /// For a stalled branch, the last speed and the corrector's last failure; else None.
    pub end_reason: Option<(f64, String)>,
    /// Points whose measuring run failed (their measures NaN): (index, message).
    pub failures: Vec<(usize, String)>,
    /// Craig-Bampton modes kept (0: the full model).
    pub modes: usize,
    /// The reduction's worst relative error on the steady unbalance response at the ring node
    /// at the two ends of the range (0 for the full model).
    pub mode_error: f64,
}

fn special(py: Python<'_>, s: &SpecialPoint) -> PyResult<Py<RubSpecialPoint>> {
    let point = RubSpecialPoint {
        kind: s.kind.name().to_string(),
        speed: s.parameter,
        bracket: s.bracket,
        converged: s.converged,
        unconverged: s.unconverged.as_ref().map(ToString::to_string),
        spectral_radius: s.multipliers.first().map_or(f64::NAN, |m| m.modulus()),
        contacts: s.contacts,
    };
    Py::new(py, point)
}

fn result(py: Python<'_>, map: &RubMap, reduction: crate::fe::Reduction) -> PyResult<FeRubMap> {
    let p = &map.points;
    let (end, end_reason) = branch_end(&map.branch.end);
    let radius = map
        .branch
        .points
        .iter()
        .map(|q| q.multipliers.first().map_or(0.0, |m| m.modulus()));
    Ok(FeRubMap {
        speed: array(py, p.iter().map(|q| q.parameter)),
        amplitude: array(py, p.iter().map(|q| q.amplitude)),
        contact_fraction: array(py, p.iter().map(|q| q.contact_fraction)),
        peak_force: array(py, p.iter().map(|q| q.peak_force)),
        stable: array(py, p.iter().map(|q| q.stable)),
        spectral_radius: array(py, radius),
        contacts: array(py, p.iter().map(|q| q.contacts as i64)),
        specials: map
            .branch
            .specials
            .iter()
            .map(|s| special(py, s))
            .collect::<PyResult<_>>()?,
        end: end.to_string(),
        end_reason,
        failures: map
            .failures
            .iter()
            .map(|(i, e)| (*i, e.to_string()))
            .collect(),
        modes: reduction.modes,
        mode_error: reduction.error,
    })
}

/// What the rub map reads at a state: the ring node and the normal force.
fn read(
    m: &RingedRotor<LinearRotor>,
    y: &DVector<f64>,
    in_contact: bool,
) -> Result<RingReading, jeffcott::hybrid::ModelError> {
    Ok(RingReading {
        station: m.rotor().station(y),
        normal_force: m.normal_force(y, in_contact)?,
    })
}

/// The rub map of a finite-element rotor on the snubber ring: its branch of period-1 orbits
/// (one per revolution) continued in speed from ``speed_from`` towards ``speed_to`` (rad/s) by
/// pseudo-arclength (through folds; grazings, folds, flips and Neimark-Sacker points located
/// to ``bracket_width`` in speed, default 1e-8), each orbit measured at the ring node: its
/// largest radius, the fraction of the period in contact, the largest normal force, its
/// stability (the crate's ``stability::rub_map``).
///
/// The rotor, the ring and the out-of-balance as ``fe_transient`` takes them (speeds in rad/s;
/// the speed enters ``speed * G`` and the out-of-balance), the bearings as given or following
/// the speed as ``fe_run_up`` takes them (``bearing_speeds``, ``bearing_K``, ``bearing_C``;
/// the reduction made with the bearings at the higher end of the range). The branch starts at the rotor's linear steady orbit at ``speed_from``
/// (exact there when it clears the ring), or, with ``transient`` > 0, where a run from it
/// settles after that many revolutions (a start in contact). ``modes`` > 0 (or "auto")
/// reduces the rotor (Craig-Bampton, the ring node kept physical): the Jacobian is the dense
/// monodromy matrix, whose cost grows as the square of the coordinates, so tens of modes run
/// in seconds and the full 200-DOF model takes minutes. ``ds`` (default 0.01), ``ds_max``
/// (0.2): arclength steps in coordinates scaled by the gap; ``max_points`` (2000);
/// ``samples``: dense samples an orbit for its measures (256). ``rtol`` (1e-9), ``atol``
/// (``rtol``), ``method``: the runs' (dop853 for a reduced rotor, radau5 for the full one);
/// the orbits are converged to 10 ``rtol`` (relative to the gap), above the runs' noise.
///
/// Runs with the GIL released; Ctrl-C stops it between steps (``KeyboardInterrupt``).
/// ``ValueError`` for bad input; ``SimulationError`` if no orbit is found at the start.
/// Returns a ``RubMap``.
#[pyfunction]
#[pyo3(
    signature = (M, K, C, G, speed_from, speed_to, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=ModesArg::Count(0), mode_tolerance=1e-3, bearing_speeds=None, bearing_K=None, bearing_C=None, transient=0, ds=None, ds_max=0.2, max_points=2000, bracket_width=None, samples=256, rtol=1e-9, atol=None, method=None, layout="ross6"),
    text_signature = "(M, K, C, G, speed_from, speed_to, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=0, mode_tolerance=0.001, bearing_speeds=None, bearing_K=None, bearing_C=None, transient=0, ds=None, ds_max=0.2, max_points=2000, bracket_width=None, samples=256, rtol=1e-09, atol=None, method=None, layout='ross6')"
)]
#[allow(clippy::too_many_arguments, non_snake_case)] // Python keywords, ROSS's names
pub fn fe_rub_map(
    py: Python<'_>,
    M: ArrayLike<'_>,
    K: ArrayLike<'_>,
    C: ArrayLike<'_>,
    G: ArrayLike<'_>,
    speed_from: f64,
    speed_to: f64,
    ring_node: usize,
    gap: f64,
    ring_stiffness: f64,
    ring_damping: f64,
    unbalance: Vec<(usize, f64, f64)>,
    preload: (f64, f64),
    ring_offset: (f64, f64),
    modes: ModesArg,
    mode_tolerance: f64,
    bearing_speeds: Option<PyArrayLike1<'_, f64, AllowTypeChange>>,
    bearing_K: Option<Stack<'_>>,
    bearing_C: Option<Stack<'_>>,
    transient: u64,
    ds: Option<f64>,
    ds_max: f64,
    max_points: usize,
    bracket_width: Option<f64>,
    samples: usize,
    rtol: f64,
    atol: Option<f64>,
    method: Option<&str>,
    layout: &str,
) -> PyResult<FeRubMap> {
    let modes = Modes::new(modes, mode_tolerance)?;
    let method = method.unwrap_or(default_method(modes));
    let sim = sim_options(Some(rtol), Some(atol.unwrap_or(rtol)), Some(method))?;
    let base = RubMapOptions::default();
    let continuation = options(
        base.continuation,
        ds,
        Some(ds_max),
        Some(max_points),
        bracket_width,
    )?;
    // The corrector's tolerance above the runs' noise (a map integrated at rtol is no more
    // exact than that).
    let continuation = continuation
        .with_sim(sim)
        .with_atol((10.0 * rtol).max(1e-10));
    let opts = base.with_continuation(continuation).with_samples(samples);
    let exported = lateral_matrices([&M, &K, &C, &G], layout)?;
    let bearings = Bearings::from_args(
        (&M, &G),
        layout,
        (bearing_speeds, bearing_K.as_ref(), bearing_C.as_ref()),
    )?;
    let table = bearings.as_ref().map(Bearings::table);
    // The matrices at a speed: the bearings there where they follow it.
    let at_speed = |speed: f64| match table {
        Some(t) => t.matrices_at(&exported, speed),
        None => Ok(exported.clone()),
    };
    // The reduction's modes with the bearings at the higher end of the range.
    let lateral = at_speed(speed_from.max(speed_to)).map_err(value_error)?;
    let at = RingAt::new(
        ring_node,
        [gap, ring_stiffness, ring_damping],
        preload,
        ring_offset,
    )?;
    let speeds = [speed_from, speed_to];
    let first = system_at(&lateral, speed_from, &unbalance)?;
    let (_, cb, reduction) = py.detach(|| rotor_of(&lateral, first, &at, (modes, &speeds)))?;
    let x = lateral.x_dof(ring_node).map_err(value_error)?;
    let build = |speed: f64| -> Result<RingedRotor<LinearRotor>, String> {
        let system = at_speed(speed)
            .and_then(|l| system_of(&l, speed, &unbalance))
            .map_err(|e| e.to_string())?;
        let rotor = match &cb {
            Some(cb) => {
                let reduced = cb.reduce(&system).map_err(|e| e.to_string())?;
                LinearRotor::new(reduced, [0, 1], at.offset)
            }
            None => LinearRotor::new(system, [x, x + 1], at.offset),
        };
        rotor
            .and_then(|r| r.ringed(at.ring))
            .map_err(|e| e.to_string())
    };
    let start = build(speed_from).map_err(value_error)?;
    let steady = start.rotor().steady_state().map_err(value_error)?;
    let guess = match transient {
        0 => steady,
        periods => runs::settle(py, &start, steady, periods, &sim)?,
    };
    let ctrl_c = CtrlC::new();
    let found = py.detach(|| {
        rub_map(
            build,
            (speed_from, speed_to),
            &guess,
            1,
            &opts,
            read,
            &ctrl_c,
        )
    });
    ctrl_c.raised()?;
    match found {
        Ok(map) => result(py, &map, reduction),
        Err(e) => Err(stability_error(py, e)),
    }
}
