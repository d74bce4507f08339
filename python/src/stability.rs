//! Periodic orbits of the paper's model and their Floquet multipliers, from Python.

use jeffcott::nalgebra::U6;
use jeffcott::stability::{OrbitOptions, PeriodicOrbit};
use numpy::{Complex64, PyArray1};
use pyo3::prelude::*;

use crate::arrays::{array, complex};
use crate::errors::simulation_error;
use crate::paper::run_setup;
use crate::params::PyParams;
use crate::runs;

/// A periodic orbit of the stroboscopic map and its stability (non-dimensional units).
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct Orbit {
    /// Its period n in forcing periods (as asked; see ``minimal_period``).
    pub period: u64,
    /// The full state [x, y, x', y', x_s, y_s] at the periodic point (t = 0), float64, (6,).
    pub state: Py<PyArray1<f64>>,
    /// The periodic point z* = [x, y, x', y'], float64, shape (4,).
    pub point: Py<PyArray1<f64>>,
    /// The Floquet multipliers (eigenvalues of the monodromy matrix), largest modulus
    /// first, complex128, shape (4,).
    pub multipliers: Py<PyArray1<Complex64>>,
    /// The largest multiplier modulus: the orbit is stable below 1.
    pub spectral_radius: f64,
    /// max |P^n(z*) - z*| at the end of Newton's iteration.
    pub residual: f64,
    /// Newton iterations.
    pub iterations: u32,
    /// The smallest m dividing the period with P^m(z*) = z* (to 1e-8).
    pub minimal_period: u64,
    /// Whether an event of the orbit is grazing (the multipliers are then one side's).
    pub grazing: bool,
}

fn orbit(py: Python<'_>, o: &PeriodicOrbit<U6>) -> Orbit {
    Orbit {
        period: o.period,
        state: array(py, o.state.iter().copied()),
        point: array(py, o.point.iter().copied()),
        multipliers: array(py, complex(&o.multipliers)),
        spectral_radius: o.spectral_radius(),
        residual: o.residual,
        iterations: o.iterations,
        minimal_period: o.minimal_period,
        grazing: o.grazing,
    }
}

/// The period-``period`` orbit near the state reached after ``transient`` forcing periods
/// from ``state0`` (default rest): Newton's method on P^n(z) - z (the crate's
/// ``stability::periodic_orbit``, monodromy by the variational equations with saltation
/// matrices at the events), with its Floquet multipliers. Options as ``simulate``.
/// ``ValueError`` for bad input; ``SimulationError`` if the run or Newton fails
/// (``partial`` is None).
#[pyfunction]
#[pyo3(signature = (params, period=1, *, transient=300, state0=None, rtol=None, atol=None, method=None))]
#[allow(clippy::too_many_arguments)] // Python keywords
pub fn periodic_orbit(
    py: Python<'_>,
    params: PyRef<'_, PyParams>,
    period: u64,
    transient: u64,
    state0: Option<Vec<f64>>,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
) -> PyResult<Orbit> {
    let (model, y0, sim) = run_setup(&params, state0, rtol, atol, method)?;
    let guess = runs::settle(py, &model, y0, transient, &sim)?;
    let opts = OrbitOptions::default().with_sim(sim);
    let found = py.detach(|| jeffcott::stability::periodic_orbit(&model, &guess, period, &opts));
    match found {
        Ok(o) => Ok(orbit(py, &o)),
        Err(e) => Err(simulation_error(py, e.to_string(), py.None())),
    }
}
