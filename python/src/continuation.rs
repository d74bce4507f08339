//! The pseudo-arclength continuation of periodic orbits of the paper's model along one
//! parameter, with its special points (fold, flip, Neimark-Sacker, grazing), from Python.

use jeffcott::paper::{JeffcottModel, ParamSweep};
use jeffcott::stability::{
    continue_orbit_with_progress, Branch, BranchEnd, ContinuationOptions, SpecialPoint,
};
use numpy::{Complex64, PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::arrays::{array, complex, table};
use crate::errors::value_error;
use crate::interrupt::CtrlC;
use crate::lyapunov::stability_error;
use crate::options::{positive, sim_options};
use crate::paper::{start_state, swept};
use crate::params::PyParams;
use crate::runs;

/// A special point of a continued branch.
#[pyclass(name = "SpecialPoint", module = "jeffcott", frozen, get_all)]
pub struct SpecialPointPy {
    /// "fold", "flip", "neimark-sacker" or "grazing".
    pub kind: String,
    /// The parameter where it is (the final bracket's midpoint; meaningful if ``converged``).
    pub parameter: f64,
    /// The final bracket's parameters (near end, far end).
    pub bracket: (f64, f64),
    /// Whether the bracket narrowed to ``bracket_width``; if not, ``unconverged`` says why.
    pub converged: bool,
    /// Why the location stopped early, or None.
    pub unconverged: Option<String>,
    /// The periodic point [x, y, x', y'] at the bracket's near end, float64, shape (4,).
    pub point: Py<PyArray1<f64>>,
    /// The multipliers at the near end, largest modulus first, complex128, shape (4,).
    pub multipliers: Py<PyArray1<Complex64>>,
    /// Contact onsets per orbit before and after.
    pub contacts: (usize, usize),
    /// Index in the branch's points of the point before it.
    pub after_point: usize,
}

/// A continued branch of period-``period`` orbits, points in order of arclength.
#[pyclass(name = "Branch", module = "jeffcott", frozen, get_all)]
pub struct ContinuedBranch {
    /// The swept parameter's name.
    pub parameter_name: String,
    /// The period in forcing periods.
    pub period: u64,
    /// The parameter at each point, float64, shape (N,).
    pub parameters: Py<PyArray1<f64>>,
    /// The periodic points [x, y, x', y'] (gaps, gaps per 1/omega_n), float64, shape (N, 4).
    pub points: Py<PyArray2<f64>>,
    /// The full states [x, y, x', y', x_s, y_s] at the section, float64, shape (N, 6).
    pub states: Py<PyArray2<f64>>,
    /// The Floquet multipliers, largest modulus first, complex128, shape (N, 4).
    pub multipliers: Py<PyArray2<Complex64>>,
    /// Whether every multiplier is inside the unit circle, bool, shape (N,).
    pub stable: Py<PyArray1<bool>>,
    /// Whether an event is crossed at a grazing margin, bool, shape (N,).
    pub grazing: Py<PyArray1<bool>>,
    /// Contact onsets per orbit, int64, shape (N,).
    pub contacts: Py<PyArray1<i64>>,
    /// Arclength from the first point (scaled coordinates), float64, shape (N,).
    pub arclength: Py<PyArray1<f64>>,
    /// The special points, in order of arclength.
    pub specials: Vec<Py<SpecialPointPy>>,
    /// How the branch ended: "reached", "max-points" or "stalled".
    pub end: String,
    /// For a stalled branch, the last parameter and the corrector's last failure; else None.
    pub end_reason: Option<(f64, String)>,
}

fn special(py: Python<'_>, s: &SpecialPoint) -> PyResult<Py<SpecialPointPy>> {
    let point = SpecialPointPy {
        kind: s.kind.name().to_string(),
        parameter: s.parameter,
        bracket: s.bracket,
        converged: s.converged,
        unconverged: s.unconverged.as_ref().map(ToString::to_string),
        point: array(py, s.point.iter().copied()),
        multipliers: array(py, complex(&s.multipliers)),
        contacts: s.contacts,
        after_point: s.after_point,
    };
    Py::new(py, point)
}

/// How a branch ended, as Python reads it: "reached", "max-points", "stopped" or "stalled"
/// (with the last parameter and the corrector's last failure).
pub fn branch_end(end: &BranchEnd) -> (&'static str, Option<(f64, String)>) {
    match end {
        BranchEnd::Reached => ("reached", None),
        BranchEnd::MaxPoints => ("max-points", None),
        BranchEnd::Stopped { .. } => ("stopped", None),
        BranchEnd::Stalled { parameter, reason } => {
            ("stalled", Some((*parameter, reason.to_string())))
        }
        _ => ("other", None),
    }
}

fn branch(py: Python<'_>, name: &str, b: &Branch) -> PyResult<ContinuedBranch> {
    let p = &b.points;
    let (end, end_reason) = branch_end(&b.end);
    Ok(ContinuedBranch {
        parameter_name: name.to_string(),
        period: b.period,
        parameters: array(py, p.iter().map(|q| q.parameter)),
        points: table(py, p.iter().map(|q| q.point.iter().copied()), 4)?,
        states: table(py, p.iter().map(|q| q.state.iter().copied()), 6)?,
        multipliers: table(py, p.iter().map(|q| complex(&q.multipliers)), 4)?,
        stable: array(py, p.iter().map(|q| q.stable)),
        grazing: array(py, p.iter().map(|q| q.grazing)),
        contacts: array(py, p.iter().map(|q| q.contacts as i64)),
        arclength: array(py, p.iter().map(|q| q.arclength)),
        specials: b
            .specials
            .iter()
            .map(|s| special(py, s))
            .collect::<PyResult<_>>()?,
        end: end.to_string(),
        end_reason,
    })
}

/// The continuation's options from the Python keywords (None keeps `base`'s).
pub fn options(
    base: ContinuationOptions,
    ds: Option<f64>,
    ds_max: Option<f64>,
    max_points: Option<usize>,
    bracket_width: Option<f64>,
) -> PyResult<ContinuationOptions> {
    let mut o = base;
    if let Some(v) = ds {
        o = o.with_ds(positive("ds", v)?);
    }
    if let Some(v) = ds_max {
        o = o.with_ds_max(positive("ds_max", v)?);
    }
    if let Some(n) = max_points {
        o = o.with_max_points(n);
    }
    if let Some(v) = bracket_width {
        o = o.with_bracket_width(positive("bracket_width", v)?);
    }
    Ok(o)
}

/// Continues the period-``period`` orbit of the paper's model in ``parameter`` (eta, D, Dx, K,
/// nu1, nu2, beta, ex, ey, phi0; the others from ``params``) from ``start`` towards ``stop``
/// by pseudo-arclength (the crate's ``stability::continue_orbit``: through folds, with folds,
/// flips, Neimark-Sacker points and grazings located to ``bracket_width``, default 1e-8).
///
/// The first orbit is sought near the state reached after ``transient`` forcing periods
/// from ``state0`` (default rest) at ``start``. ``ds`` (default 0.01), ``ds_max`` (0.02):
/// arclength steps in scaled coordinates; ``max_points`` (5000). Options as ``simulate``.
///
/// Runs with the GIL released; Ctrl-C stops the transient (as ``simulate``), and the
/// continuation looks for it between its steps (``KeyboardInterrupt``, within about one step
/// or bisection step).
/// ``ValueError`` for bad input; ``SimulationError`` if no orbit is found at ``start`` or a
/// run fails.
#[pyfunction]
#[pyo3(signature = (params, start, stop, *, parameter="eta", period=1, transient=300, state0=None, ds=None, ds_max=None, max_points=None, bracket_width=None, rtol=None, atol=None, method=None))]
#[allow(clippy::too_many_arguments)] // Python keywords
pub fn continue_orbit(
    py: Python<'_>,
    params: PyRef<'_, PyParams>,
    start: f64,
    stop: f64,
    parameter: &str,
    period: u64,
    transient: u64,
    state0: Option<Vec<f64>>,
    ds: Option<f64>,
    ds_max: Option<f64>,
    max_points: Option<usize>,
    bracket_width: Option<f64>,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
) -> PyResult<ContinuedBranch> {
    let family = ParamSweep::new(params.checked()?, swept(parameter)?);
    let model: JeffcottModel = family.model(start).map_err(value_error)?;
    let y0 = start_state(state0)?;
    let sim = sim_options(rtol, atol, method)?;
    let opts = options(
        ContinuationOptions::default(),
        ds,
        ds_max,
        max_points,
        bracket_width,
    )?
    .with_sim(sim);
    let guess = runs::settle(py, &model, y0, transient, &sim)?;
    let build = |value: f64| family.model(value);
    let ctrl_c = CtrlC::new();
    let found = py.detach(|| {
        continue_orbit_with_progress(build, start, stop, &guess, period, &opts, &ctrl_c)
    });
    ctrl_c.raised()?;
    match found {
        Ok(b) => branch(py, parameter, &b),
        Err(e) => Err(stability_error(py, e)),
    }
}
