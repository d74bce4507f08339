//! The Poincaré section of the paper's model at the forcing phase: the stroboscopic points
//! after a transient, and their period.

use jeffcott::analysis::PeriodTest;
use jeffcott::hybrid::{RotorModel, Trajectory};
use jeffcott::paper::State;
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::arrays::array;
use crate::errors::{run_error, value_error};
use crate::paper::{run_setup, states};
use crate::params::PyParams;
use crate::runs::{self, Output};

/// Recorded stroboscopic points k = transient + 1 ..= transient + record and their period.
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct Section {
    /// Period indices k, int64, shape (record,).
    pub k: Py<PyArray1<i64>>,
    /// States [x, y, x', y', x_s, y_s] (gaps, gaps per 1/omega_n), float64, (record, 6).
    pub points: Py<PyArray2<f64>>,
    /// Regimes 1..=5 at the points, uint8, shape (record,).
    pub regimes: Py<PyArray1<u8>>,
    /// The detected period (the crate's default ``PeriodTest``), or -1: not periodic or
    /// not converged.
    pub period: i64,
}

/// The Poincaré section (stroboscopic points at t_k = 2 pi k / eta) from ``state0`` (default
/// rest): ``transient`` periods discarded, ``record`` kept, their period detected as the
/// crate's ``analysis::PeriodTest`` does (relative to the model's state scale). Options,
/// Ctrl-C and errors as ``simulate`` (``partial`` a ``Section`` of the points so far).
#[pyfunction]
#[pyo3(signature = (params, *, transient=300, record=150, state0=None, rtol=None, atol=None, method=None))]
#[allow(clippy::too_many_arguments)] // Python keywords
pub fn poincare(
    py: Python<'_>,
    params: PyRef<'_, PyParams>,
    transient: u64,
    record: u64,
    state0: Option<Vec<f64>>,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
) -> PyResult<Section> {
    if record < 2 {
        return Err(value_error("record must be at least 2"));
    }
    let (model, y0, opts) = run_setup(&params, state0, rtol, atol, method)?;
    let last = transient.saturating_add(record);
    let output = Output::Strobe { last };
    let mut traj = Trajectory::default();
    let outcome = runs::run(py, &model, &y0, output, &opts, &mut traj)?;
    let kept: Vec<_> = traj.strobe.iter().filter(|p| p.k > transient).collect();
    let period = match &outcome {
        Ok(_) => {
            let states: Vec<State> = kept.iter().map(|p| p.y).collect();
            PeriodTest::default()
                .detect_scaled(&states, &model.state_scale())
                .map_err(value_error)?
                .period()
                .map_or(-1, |p| p as i64)
        }
        Err(_) => -1,
    };
    let section = Section {
        k: array(py, kept.iter().map(|p| p.k as i64)),
        points: states(py, kept.iter().map(|p| &p.y))?,
        regimes: array(py, kept.iter().map(|p| p.label)),
        period,
    };
    match outcome {
        Ok(_) => Ok(section),
        Err(e) => Err(run_error(py, e, Py::new(py, section)?.into_any())),
    }
}
