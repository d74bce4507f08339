//! Basins of attraction of the paper's model (the crate's global layer): a grid of initial
//! states, the attractor each reaches, and the table of distinct attractors.

use jeffcott::global::{
    scan_grid, Attractor, AttractorOptions, Catalogue, Grid2, MatchOptions, PointFailure,
    PointLabel, RunOptions,
};
use jeffcott::paper::{BasinPlane, StartPlane};
use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::arrays::{array, table};
use crate::errors::value_error;
use crate::options::{positive, sim_options};
use crate::params::PyParams;

/// One distinct attractor of a basin scan.
#[pyclass(name = "BasinAttractor", module = "jeffcott", frozen, get_all)]
pub struct BasinAttractor {
    /// Its period in forcing periods, 0 if not periodic (or not converged).
    pub period: usize,
    /// Periodic: the cycle's stroboscopic states [x, y, x', y', x_s, y_s] from its canonical
    /// (lexicographically smallest) point, float64, shape (period, 6); else (0, 6).
    pub cycle: Py<PyArray2<f64>>,
    /// Grid points that reached it.
    pub count: usize,
    /// Flat index (x fastest) of the first grid point that reached it.
    pub first: usize,
    /// Contact onsets per forcing period over the recorded window.
    pub contacts_per_period: f64,
    /// Fraction of the window's time in contact.
    pub contact_fraction: f64,
    /// The crate's one-line description.
    pub description: String,
}

/// A basin scan: labels on the grid and the attractor table.
#[pyclass(name = "Basins", module = "jeffcott", frozen, get_all)]
pub struct Basins {
    /// The horizontal coordinate's values, float64, shape (nx,).
    pub x: Py<PyArray1<f64>>,
    /// The vertical coordinate's values, float64, shape (ny,).
    pub y: Py<PyArray1<f64>>,
    /// The coordinates' names, e.g. ("x0", "vx0").
    pub names: (String, String),
    /// ``labels[j, i]``: the index in ``attractors`` reached from (x[i], y[j]), -1 if the
    /// point's run failed, int64, shape (ny, nx).
    pub labels: Py<PyArray2<i64>>,
    /// The distinct attractors, in order of first appearance (x fastest, then y).
    pub attractors: Vec<Py<BasinAttractor>>,
    /// The failed points: (flat index, the crate's message).
    pub failures: Vec<(usize, String)>,
}

fn plane(name: &str) -> PyResult<StartPlane> {
    match name {
        "x-vx" => Ok(StartPlane::XVx),
        "x-y" => Ok(StartPlane::XY),
        "phi0-x" => Ok(StartPlane::PhaseX),
        other => Err(value_error(format!(
            "plane '{other}' is not one of x-vx, x-y, phi0-x"
        ))),
    }
}

fn attractor(
    py: Python<'_>,
    a: &Attractor,
    count: usize,
    first: usize,
) -> PyResult<BasinAttractor> {
    let width = a.cycle.first().map_or(6, Vec::len);
    Ok(BasinAttractor {
        period: a.period().unwrap_or(0),
        cycle: table(py, a.cycle.iter().map(|y| y.iter().copied()), width)?,
        count,
        first,
        contacts_per_period: a.stats.contacts_per_period,
        contact_fraction: a.stats.contact_fraction,
        description: a.describe(),
    })
}

/// The scan's options from the Python keywords.
fn attractor_options(
    transient: u64,
    record: u64,
    max_transient: u64,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
) -> PyResult<AttractorOptions> {
    if record < 2 {
        return Err(value_error("record must be at least 2"));
    }
    Ok(AttractorOptions::default()
        .with_transient(transient)
        .with_record(record)
        .with_max_transient(max_transient.max(transient))
        .with_opts(sim_options(rtol, atol, method)?))
}

/// Basins of attraction of the paper's model at ``params``: from each start of the grid
/// ``x`` by ``y`` in ``plane`` ("x-vx": x0 against x0'; "x-y": x0 against y0; "phi0-x": the
/// forcing phase phi0 in rad against x0; the other coordinates zero, the ring placed
/// consistently; gaps and gaps per 1/omega_n), the run discards ``transient`` forcing periods,
/// records ``record`` and tests them for a period, going on up to ``max_transient`` periods
/// if none is found (the crate's ``global::find_attractor``). Attractors are matched within
/// ``match_state`` gaps (the crate's ``MatchOptions``, default 1e-3) in order of the points.
///
/// The points run on the crate's threads (``threads``: None for all cores) with the GIL
/// released, a row of ``y`` at a time, Ctrl-C checked between rows. ``ValueError`` for bad
/// input; a point whose run fails is labelled -1 with its message in ``failures``.
#[pyfunction]
#[pyo3(signature = (params, x, y, *, plane="x-vx", transient=500, record=64, max_transient=4000, match_state=1e-3, rtol=None, atol=None, method=None, threads=None))]
#[allow(clippy::too_many_arguments)] // Python keywords
pub fn basins(
    py: Python<'_>,
    params: PyRef<'_, PyParams>,
    x: Vec<f64>,
    y: Vec<f64>,
    plane: &str,
    transient: u64,
    record: u64,
    max_transient: u64,
    match_state: f64,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
    threads: Option<usize>,
) -> PyResult<Basins> {
    let grid = Grid2::new(x.clone(), y.clone()).map_err(value_error)?;
    let start = BasinPlane::new(params.checked()?, self::plane(plane)?);
    let config = attractor_options(transient, record, max_transient, rtol, atol, method)?;
    let tol = MatchOptions::default().with_state(positive("match_state", match_state)?);
    let run = match threads {
        Some(0) => return Err(value_error("threads must be at least 1")),
        Some(n) => RunOptions::default().with_threads(n),
        None => RunOptions::default(),
    };
    let mut results: Vec<Option<Result<Attractor, PointFailure>>> = Vec::new();
    for &row in &grid.y {
        let line = Grid2::new(grid.x.clone(), vec![row]).map_err(value_error)?;
        let scan = py
            .detach(|| scan_grid(&line, start.setup(), &config, None, &run, None))
            .map_err(value_error)?;
        results.extend(scan.results.results);
        py.check_signals()?;
    }
    let catalogue = Catalogue::new(&results, &tol);
    basins_of(py, &grid, start.plane.names(), &catalogue, &results)
}

fn basins_of(
    py: Python<'_>,
    grid: &Grid2,
    (h, v): (&str, &str),
    catalogue: &Catalogue,
    results: &[Option<Result<Attractor, PointFailure>>],
) -> PyResult<Basins> {
    let labels: Vec<i64> = catalogue
        .labels
        .iter()
        .map(|l| match l {
            PointLabel::Attractor(k) => *k as i64,
            _ => -1,
        })
        .collect();
    let labels =
        Array2::from_shape_vec((grid.y.len(), grid.x.len()), labels).map_err(value_error)?;
    let attractors = catalogue
        .entries
        .iter()
        .map(|e| Py::new(py, attractor(py, &e.attractor, e.count, e.first)?))
        .collect::<PyResult<_>>()?;
    let failures = results
        .iter()
        .enumerate()
        .filter_map(|(i, r)| match r {
            Some(Err(e)) => Some((i, e.to_string())),
            _ => None,
        })
        .collect();
    Ok(Basins {
        x: array(py, grid.x.iter().copied()),
        y: array(py, grid.y.iter().copied()),
        names: (h.to_string(), v.to_string()),
        labels: labels.into_pyarray(py).unbind(),
        attractors,
        failures,
    })
}
