//! The paper's model from Python: stroboscopic and dense runs, bifurcation diagrams, where
//! the ring sits and in which regime. Non-dimensional units throughout: time in $1/\omega_n$
//! (one forcing period is $2\pi/\eta$), lengths in gaps, velocities in gaps times $\omega_n$.

use jeffcott::analysis::{BifurcationOptions, SweepOptions};
use jeffcott::hybrid::{SimOptions, SimStats, Trajectory};
use jeffcott::nalgebra::{allocator::Allocator, DVector, DefaultAllocator, Dim, OVector, Vector2};
use jeffcott::paper::rub::rubbing_model;
use jeffcott::paper::{JeffcottModel, ParamSweep, State, SweepParameter};
use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{array, table};
use crate::errors::value_error;
use crate::options::{coulomb, positive, sim_options};
use crate::params::PyParams;
use crate::runs::{self, Output};

/// Stroboscopic states of a run, one row per forcing period k = 0..=N (the first is the start).
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct StrobeRun {
    /// Period indices k, int64, shape (N+1,).
    pub k: Py<PyArray1<i64>>,
    /// Times t_k = 2 pi k / eta (non-dimensional), float64, shape (N+1,).
    pub t: Py<PyArray1<f64>>,
    /// States [x, y, x', y', x_s, y_s] (gaps, gaps per 1/omega_n), float64, shape (N+1, 6).
    pub states: Py<PyArray2<f64>>,
    /// Regimes 1..=5 (I..V; 1 is free flight); with friction 6, 7, 8 (slipping forward,
    /// slipping backward, rolling), uint8, shape (N+1,).
    pub regimes: Py<PyArray1<u8>>,
    /// The work done: steps, rejected, rhs_evals, exact_evals, transitions, jacobians,
    /// lu_decompositions.
    pub stats: Py<PyDict>,
}

/// Dense samples of a run on a uniform grid t_i = i dt, and its events.
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct DenseRun {
    /// Sample times (non-dimensional), float64, shape (N,).
    pub t: Py<PyArray1<f64>>,
    /// States [x, y, x', y', x_s, y_s] at the samples, float64, shape (N, 6).
    pub states: Py<PyArray2<f64>>,
    /// Their time derivatives (the ring's velocity included), float64, shape (N, 6).
    pub derivatives: Py<PyArray2<f64>>,
    /// Regimes 1..=5 at the samples (with friction 6, 7, 8: slipping forward, backward,
    /// rolling), uint8, shape (N,).
    pub regimes: Py<PyArray1<u8>>,
    /// Event times, float64, shape (E,).
    pub event_t: Py<PyArray1<f64>>,
    /// Event kinds (guard names: onset, loss, ...), a list of E str.
    pub event_kind: Vec<String>,
    /// Regime after each event, uint8, shape (E,).
    pub event_regime: Py<PyArray1<u8>>,
    /// The work done (as ``StrobeRun.stats``).
    pub stats: Py<PyDict>,
}

/// A bifurcation diagram: for each parameter value, the recorded stroboscopic states.
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct Diagram {
    /// The parameter values, float64, shape (V,).
    pub values: Py<PyArray1<f64>>,
    /// Recorded states, float64, shape (V, record, 6); NaN rows where the run failed.
    pub points: Py<PyArray3<f64>>,
    /// Detected period of each column (-1: not periodic, not converged or failed), int64, (V,).
    pub periods: Py<PyArray1<i64>>,
    /// The crate's message for each failed column, else None: a list of V entries.
    pub errors: Vec<Option<String>>,
}

pub fn model_of(params: &PyParams) -> PyResult<JeffcottModel> {
    JeffcottModel::new(params.checked()?).map_err(value_error)
}

pub fn start_state(state0: Option<Vec<f64>>) -> PyResult<State> {
    match state0 {
        None => Ok(State::zeros()),
        Some(v) if v.len() == 6 && v.iter().all(|x| x.is_finite()) => {
            Ok(State::from_column_slice(&v))
        }
        Some(v) => Err(value_error(format!(
            "state0 must hold 6 finite values [x, y, x', y', x_s, y_s], got {v:?}"
        ))),
    }
}

/// What a run of the paper's model starts from: the model of `params`, the state `state0`
/// (default rest) and the integration options (`None` keeps the crate's default), checked in
/// that order.
pub fn run_setup(
    params: &PyParams,
    state0: Option<Vec<f64>>,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
) -> PyResult<(JeffcottModel, State, SimOptions)> {
    Ok((
        model_of(params)?,
        start_state(state0)?,
        sim_options(rtol, atol, method)?,
    ))
}

/// The states as the rows of an (N, 6) numpy array.
pub fn states<'a, D: Dim>(
    py: Python<'_>,
    states: impl ExactSizeIterator<Item = &'a OVector<f64, D>>,
) -> PyResult<Py<PyArray2<f64>>>
where
    DefaultAllocator: Allocator<D>,
{
    // The rotor's and the ring's six (a driven rotor's speed and phase follow).
    table(py, states.map(|y| y.iter().copied().take(6)), 6)
}

fn strobe_run<D: Dim>(py: Python<'_>, traj: &Trajectory<D>, stats: &SimStats) -> PyResult<StrobeRun>
where
    DefaultAllocator: Allocator<D>,
{
    let s = &traj.strobe;
    Ok(StrobeRun {
        k: array(py, s.iter().map(|p| p.k as i64)),
        t: array(py, s.iter().map(|p| p.t)),
        states: states(py, s.iter().map(|p| &p.y))?,
        regimes: array(py, s.iter().map(|p| p.label)),
        stats: runs::stats_dict(py, stats)?.unbind(),
    })
}

fn dense_run<D: Dim>(py: Python<'_>, traj: &Trajectory<D>, stats: &SimStats) -> PyResult<DenseRun>
where
    DefaultAllocator: Allocator<D>,
{
    let s = &traj.samples;
    let e = &traj.events;
    Ok(DenseRun {
        t: array(py, s.iter().map(|p| p.t)),
        states: states(py, s.iter().map(|p| &p.y))?,
        derivatives: states(py, s.iter().map(|p| &p.dy))?,
        regimes: array(py, s.iter().map(|p| p.label)),
        event_t: array(py, e.iter().map(|v| v.t)),
        event_kind: e.iter().map(|v| v.kind.to_string()).collect(),
        event_regime: array(py, e.iter().map(|v| v.to)),
        stats: runs::stats_dict(py, stats)?.unbind(),
    })
}

/// Stroboscopic run of the paper's model: the states at t_k = 2 pi k / eta, k = 0..=periods,
/// from ``state0`` (default: rest, [0]*6) at t = 0.
///
/// ``friction`` > 0: Coulomb friction between the ring and a shaft of radius ``shaft_radius``
/// (in gaps, required then) spinning counter-clockwise (the crate's
/// ``paper::rub::rubbing_model``; docs/friction.md); ``regimes`` 6, 7, 8 are slipping forward,
/// slipping backward and rolling. A ``state0`` beyond the gap starts in contact by the onset
/// rule, the ring placed for it.
///
/// Tolerances and method as the crate's ``SimOptions`` (defaults rtol 1e-10, atol 1e-12,
/// dop853; also dopri5, radau5); ``max_steps`` bounds the run's step attempts. The run
/// releases the GIL; Ctrl-C stops it (``KeyboardInterrupt``).
///
/// Raises ``ValueError`` for bad parameters or input, ``SimulationError`` (with ``partial``,
/// a ``StrobeRun`` of the points before the failure) for a failed run.
#[pyfunction]
#[pyo3(signature = (params, periods, *, state0=None, rtol=None, atol=None, method=None, max_steps=None, friction=0.0, shaft_radius=None))]
#[allow(clippy::too_many_arguments)] // Python keywords
pub fn simulate(
    py: Python<'_>,
    params: PyRef<'_, PyParams>,
    periods: u64,
    state0: Option<Vec<f64>>,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
    max_steps: Option<u64>,
    friction: f64,
    shaft_radius: Option<f64>,
) -> PyResult<StrobeRun> {
    let (model, y0, opts) = run_setup(&params, state0, rtol, atol, method)?;
    let opts = with_max_steps(opts, max_steps);
    let output = Output::Strobe { last: periods };
    match rub_of(&params, friction, shaft_radius)? {
        None => runs::run_into(py, &model, y0, output, &opts, strobe_run),
        Some(rub) => runs::run_into(py, &rub, dyn_state(&y0), output, &opts, strobe_run),
    }
}

/// The paper's rotor with friction ([`rubbing_model`]) for `friction` > 0, `None` for 0.
fn rub_of(
    params: &PyParams,
    friction: f64,
    shaft_radius: Option<f64>,
) -> PyResult<Option<jeffcott::rotor::RubbingRotor<jeffcott::rotor::LinearRotor>>> {
    let Some((mu, radius)) = coulomb(friction, shaft_radius, "in gaps")? else {
        return Ok(None);
    };
    rubbing_model(&params.checked()?, mu, radius)
        .map(Some)
        .map_err(value_error)
}

/// The paper's state as the friction model's (the same layout).
fn dyn_state(y: &State) -> DVector<f64> {
    DVector::from_column_slice(y.as_slice())
}

/// Dense run of the paper's model: samples at t_i = i dt for t_i <= t_end (non-dimensional
/// time), from ``state0`` (default rest) at t = 0, with the event log. Options, friction,
/// Ctrl-C and errors as ``simulate`` (``partial`` a ``DenseRun``).
#[pyfunction]
#[pyo3(signature = (params, t_end, dt, *, state0=None, rtol=None, atol=None, method=None, max_steps=None, friction=0.0, shaft_radius=None))]
#[allow(clippy::too_many_arguments)] // Python keywords
pub fn simulate_dense(
    py: Python<'_>,
    params: PyRef<'_, PyParams>,
    t_end: f64,
    dt: f64,
    state0: Option<Vec<f64>>,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
    max_steps: Option<u64>,
    friction: f64,
    shaft_radius: Option<f64>,
) -> PyResult<DenseRun> {
    let (model, y0, opts) = run_setup(&params, state0, rtol, atol, method)?;
    let opts = with_max_steps(opts, max_steps);
    let output = dense_output(t_end, dt)?;
    match rub_of(&params, friction, shaft_radius)? {
        None => runs::run_into(py, &model, y0, output, &opts, dense_run),
        Some(rub) => runs::run_into(py, &rub, dyn_state(&y0), output, &opts, dense_run),
    }
}

/// The options with a bound on the run's step attempts, if given.
fn with_max_steps(opts: SimOptions, max_steps: Option<u64>) -> SimOptions {
    match max_steps {
        Some(n) => opts.with_max_steps(n),
        None => opts,
    }
}

/// Samples `i dt <= t_end` (to a relative 1e-12).
pub fn dense_output(t_end: f64, dt: f64) -> PyResult<Output> {
    let dt = positive("dt", dt)?;
    if !(t_end.is_finite() && t_end >= 0.0) {
        return Err(value_error(format!(
            "t_end = {t_end} must be finite and >= 0"
        )));
    }
    let count = (t_end / dt * (1.0 + 1e-12)).floor() as u64 + 1;
    Ok(Output::Dense {
        dt,
        count,
        strobes: false,
    })
}

/// The swept parameters by their names.
const SWEPT: [SweepParameter; 10] = [
    SweepParameter::Eta,
    SweepParameter::Preload,
    SweepParameter::PreloadX,
    SweepParameter::Stiffness,
    SweepParameter::Nu1,
    SweepParameter::Nu2,
    SweepParameter::Beta,
    SweepParameter::Ex,
    SweepParameter::Ey,
    SweepParameter::Phi0,
];

pub fn swept(name: &str) -> PyResult<SweepParameter> {
    SWEPT
        .into_iter()
        .find(|p| p.symbol() == name)
        .ok_or_else(|| {
            let names: Vec<_> = SWEPT.iter().map(|p| p.symbol()).collect();
            value_error(format!(
                "parameter '{name}' is not one of {}",
                names.join(", ")
            ))
        })
}

/// Bifurcation diagram (the crate's ``analysis::bifurcation``, every value from ``params``'
/// rest state): for each of ``values`` of ``parameter`` (eta, D, Dx, K, nu1, nu2, beta, ex,
/// ey, phi0), ``transient`` forcing periods discarded, ``record`` stroboscopic states kept
/// and their period detected. The values run on the crate's threads (``threads``: None for
/// all cores) with the GIL released, a group at a time, Ctrl-C checked between groups.
/// A failed value is a NaN column with its message in ``errors``; bad input is ``ValueError``.
#[pyfunction]
#[pyo3(signature = (params, values, *, parameter="eta", transient=300, record=150, rtol=None, atol=None, method=None, threads=None))]
#[allow(clippy::too_many_arguments)] // Python keywords
pub fn bifurcation(
    py: Python<'_>,
    params: PyRef<'_, PyParams>,
    values: Vec<f64>,
    parameter: &str,
    transient: u64,
    record: u64,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
    threads: Option<usize>,
) -> PyResult<Diagram> {
    if record == 0 {
        return Err(value_error("record must be at least 1"));
    }
    let family = ParamSweep::new(params.checked()?, swept(parameter)?);
    let config = bifurcation_options(transient, record, sim_options(rtol, atol, method)?, threads);
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let group = 2 * threads.unwrap_or(cores).max(1);
    let mut points = Array3::<f64>::from_elem((values.len(), record as usize, 6), f64::NAN);
    let (mut periods, mut errors) = (Vec::new(), Vec::new());
    for (g, part) in values.chunks(group).enumerate() {
        let diagram = py
            .detach(|| family.bifurcation(part, &config, None))
            .map_err(value_error)?;
        for (i, column) in diagram.columns.iter().enumerate() {
            match column {
                Ok(c) => {
                    for (r, y) in c.orbit.points.iter().enumerate() {
                        for (j, v) in y.y.iter().enumerate() {
                            points[(g * group + i, r, j)] = *v;
                        }
                    }
                    periods.push(c.periodicity.period().map_or(-1, |p| p as i64));
                    errors.push(None);
                }
                Err(e) => {
                    periods.push(-1);
                    errors.push(Some(e.to_string()));
                }
            }
        }
        py.check_signals()?;
    }
    Ok(Diagram {
        values: array(py, values),
        points: points.into_pyarray(py).unbind(),
        periods: array(py, periods),
        errors,
    })
}

fn bifurcation_options(
    transient: u64,
    record: u64,
    opts: SimOptions,
    threads: Option<usize>,
) -> BifurcationOptions {
    let mut sweep = SweepOptions::default();
    sweep.threads = threads;
    BifurcationOptions::default()
        .with_transient(transient)
        .with_record(record)
        .with_opts(opts)
        .with_sweep(sweep)
}

/// Where the ring sits when nothing moves it, for the rotor at (x, y) (gaps): its centre
/// (0, 0) inside the gap, the minimiser of its energy beyond (the crate's
/// ``SnubberRing::consistent_position``). Returns (x_s, y_s) in gaps; ``ValueError`` for bad
/// parameters or a non-finite position.
#[pyfunction]
pub fn ring_position(params: PyRef<'_, PyParams>, x: f64, y: f64) -> PyResult<(f64, f64)> {
    let model = model_of(&params)?;
    let s = model
        .ring()
        .consistent_position(&Vector2::new(x, y))
        .map_err(value_error)?;
    Ok((s.x, s.y))
}

/// The regime of the rotor at (x, y) (gaps): 1 (I, no contact) when inside the gap, else
/// 2..=5 (II..V: which axes of the ring are beyond their preload). ``ValueError`` as
/// ``ring_position``.
#[pyfunction]
pub fn regime(params: PyRef<'_, PyParams>, x: f64, y: f64) -> PyResult<u8> {
    let model = model_of(&params)?;
    let r = model
        .ring()
        .regime(&Vector2::new(x, y))
        .map_err(value_error)?;
    Ok(r.number())
}
