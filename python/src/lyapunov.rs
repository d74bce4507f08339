//! Lyapunov exponents of the paper's stroboscopic map, from Python.

use jeffcott::stability::{
    lyapunov_exponents_with_progress, LyapunovOptions, LyapunovSpectrum, StabilityError,
};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::arrays::{array, table};
use crate::errors::{simulation_error, value_error};
use crate::interrupt::CtrlC;
use crate::paper::run_setup;
use crate::params::PyParams;
use crate::runs;

/// Lyapunov exponents of the stroboscopic map (the crate's ``stability::lyapunov_exponents``).
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct Lyapunov {
    /// The exponents per forcing period (QR method), largest first, float64, shape (p,).
    pub exponents: Py<PyArray1<f64>>,
    /// Their batch-means standard errors per forcing period (NaN with fewer than two
    /// batches), float64, shape (p,).
    pub stderr: Py<PyArray1<f64>>,
    /// The exponents per unit of non-dimensional time tau (per period / forcing period),
    /// float64, shape (p,).
    pub per_time: Py<PyArray1<f64>>,
    /// Their standard errors per unit tau, float64, shape (p,).
    pub per_time_stderr: Py<PyArray1<f64>>,
    /// The running estimate after each complete batch, float64, shape (batches, p).
    pub running: Py<PyArray2<f64>>,
    /// Complete batches of ``batch`` periods.
    pub batches: usize,
    /// The forcing period 2 pi / eta (non-dimensional time).
    pub forcing_period: f64,
    /// The largest exponent per period by the two-trajectory method (plain simulation), or
    /// None when ``separation`` is None.
    pub two_trajectory: Option<f64>,
    /// Its batch-means standard error, or None.
    pub two_trajectory_stderr: Option<f64>,
    /// Events crossed at a grazing margin in the recorded periods.
    pub grazing_events: usize,
    /// The smallest event margin met in the recorded periods (1 without events).
    pub min_margin: f64,
    /// Recorded sections where the map on [x, y, x', y'] was not closed.
    pub open_sections: usize,
    /// The state [x, y, x', y', x_s, y_s] at the end, float64, shape (6,).
    pub end: Py<PyArray1<f64>>,
}

fn lyapunov(py: Python<'_>, l: &LyapunovSpectrum) -> PyResult<Lyapunov> {
    let e = &l.per_period;
    let values = |v: &[f64]| array(py, v.iter().copied());
    let running = e.running.iter().map(|r| r.iter().copied());
    let two = l.two_trajectory.as_ref();
    Ok(Lyapunov {
        exponents: values(&e.mean),
        stderr: values(&e.stderr),
        per_time: values(&l.per_time),
        per_time_stderr: values(&l.per_time_stderr),
        running: table(py, running, e.mean.len())?,
        batches: e.batches,
        forcing_period: l.forcing_period,
        two_trajectory: two.map(|t| t.lambda),
        two_trajectory_stderr: two.map(|t| t.stderr),
        grazing_events: l.grazing_events,
        min_margin: l.min_margin,
        open_sections: l.open_sections,
        end: values(&l.end),
    })
}

/// A stability error as a Python exception: ``ValueError`` for a bad option, else
/// ``SimulationError`` (``partial`` None).
pub fn stability_error(py: Python<'_>, e: StabilityError) -> PyErr {
    match e {
        StabilityError::InvalidOption { .. } => value_error(e),
        _ => simulation_error(py, e.to_string(), py.None()),
    }
}

/// Lyapunov exponents of the stroboscopic map along the trajectory from ``state0`` (default
/// rest): ``transient`` forcing periods run first, ``align`` periods of QR to align the frame,
/// then ``periods`` recorded in batches of ``batch`` (batch means give the standard errors;
/// use at least 20 batches). ``exponents``: how many, the largest first (None: all four).
/// ``separation`` (default 1e-8): the initial distance of the two-trajectory estimate of the
/// largest exponent, Euclidean in [x, y, x', y'] (gaps, gaps per 1/omega_n; None skips it).
/// Exponents are per forcing period (``per_time``: per unit tau). Options as ``simulate``.
///
/// Runs with the GIL released; Ctrl-C stops the transient (as ``simulate``) and is
/// looked for between periods (``KeyboardInterrupt``).
/// ``ValueError`` for bad input (e.g. ``batch > periods``); ``SimulationError`` if a run fails.
#[pyfunction]
#[pyo3(
    signature = (params, *, transient=300, align=100, periods=2000, batch=100, separation=Some(1e-8), exponents=None, state0=None, rtol=None, atol=None, method=None),
    // Written out: pyo3 shows the `Some(..)` default as `...` (Python's Ellipsis) in help().
    text_signature = "(params, *, transient=300, align=100, periods=2000, batch=100, separation=1e-08, exponents=None, state0=None, rtol=None, atol=None, method=None)"
)]
#[allow(clippy::too_many_arguments)] // Python keywords
pub fn lyapunov_exponents(
    py: Python<'_>,
    params: PyRef<'_, PyParams>,
    transient: u64,
    align: u64,
    periods: u64,
    batch: u64,
    separation: Option<f64>,
    exponents: Option<usize>,
    state0: Option<Vec<f64>>,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
) -> PyResult<Lyapunov> {
    let (model, y0, sim) = run_setup(&params, state0, rtol, atol, method)?;
    let mut opts = LyapunovOptions::default()
        .with_transient(0)
        .with_align(align)
        .with_periods(periods)
        .with_batch(batch)
        .with_separation(separation)
        .with_sim(sim);
    if let Some(n) = exponents {
        if !(1..=4).contains(&n) {
            return Err(value_error(format!("exponents = {n} must be 1..=4")));
        }
        opts = opts.with_exponents(n);
    }
    let start = runs::settle(py, &model, y0, transient, &opts.sim)?;
    let ctrl_c = CtrlC::new();
    let found = py.detach(|| lyapunov_exponents_with_progress(&model, &start, &opts, &ctrl_c));
    ctrl_c.raised()?;
    match found {
        Ok(l) => lyapunov(py, &l),
        Err(e) => Err(stability_error(py, e)),
    }
}
