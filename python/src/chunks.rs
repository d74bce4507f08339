//! Long runs in chunks: each chunk runs with the GIL released, and Ctrl-C is checked between
//! chunks (a `KeyboardInterrupt` stops the run). Each chunk starts from the state the
//! previous one ended at (its last output, at its end time exactly).

use jeffcott::hybrid::{
    simulate, DenseSampling, OutputPlan, RotorModel, SimError, SimOptions, SimStats, StrobeRange,
    Trajectory,
};
use jeffcott::nalgebra::allocator::Allocator;
use jeffcott::nalgebra::{DefaultAllocator, OVector};
use pyo3::prelude::*;
use pyo3::pyclass_init::PyClassInitializer;
use pyo3::PyClass;

use crate::errors::run_error;

/// A finished or failed chunked run: everything recorded is in the caller's trajectory.
pub type Outcome<D> = Result<SimStats, SimError<D>>;

/// Which outputs a chunked run records: the last one of each chunk is the next chunk's start.
#[derive(Debug, Clone, Copy)]
pub enum Output {
    /// Stroboscopic points `k = 0..=last` (the model's strobe times), `per_chunk` a chunk.
    Strobe { last: u64, per_chunk: u64 },
    /// `count` samples at `t0 + i dt`, `per_chunk` a chunk, with the event log, and the
    /// stroboscopic points up to the last sample if `strobes`.
    Dense {
        dt: f64,
        count: u64,
        per_chunk: u64,
        strobes: bool,
    },
}

impl Output {
    /// The same output with the stroboscopic points too (dense outputs only).
    pub fn with_strobes(self) -> Self {
        match self {
            Output::Dense {
                dt,
                count,
                per_chunk,
                ..
            } => Output::Dense {
                dt,
                count,
                per_chunk,
                strobes: true,
            },
            strobe => strobe,
        }
    }
}

/// The plan of chunk `j` starting at `t` (the previous chunk's end), or `None` past the end;
/// `strobes_done` stroboscopic points were recorded before it.
fn plan_of<M: RotorModel>(
    model: &M,
    output: Output,
    (j, t): (u64, f64),
    strobes_done: u64,
) -> Option<OutputPlan>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    // Later chunks skip the output at their start: the previous chunk recorded it.
    let skip = u64::from(j > 0);
    match output {
        Output::Strobe { last, per_chunk } => {
            let first = (j * per_chunk + skip).min(last + 1);
            let end = ((j + 1) * per_chunk).min(last);
            (j == 0 || first <= end).then(|| OutputPlan {
                t_end: model.strobe_time(end),
                strobe: Some(StrobeRange { first, last: end }),
                dense: None,
                events: false,
            })
        }
        Output::Dense {
            dt,
            count,
            per_chunk,
            strobes,
        } => {
            let first = j * per_chunk + skip;
            let end = ((j + 1) * per_chunk).min(count.saturating_sub(1));
            let t_start = if j == 0 { t } else { t + dt };
            // The driver's sample times are `t_start + dt i`: the last one is `t_end` exactly.
            (j == 0 || first <= end).then(|| OutputPlan {
                t_end: t_start + dt * (end - first) as f64,
                // The strobes after those recorded, up to the chunk's end.
                strobe: strobes.then_some(StrobeRange {
                    first: strobes_done,
                    last: u64::MAX - 1,
                }),
                dense: Some(DenseSampling { t_start, dt }),
                events: true,
            })
        }
    }
}

/// The state at the end of a chunk: its last output.
fn last_state<D: jeffcott::nalgebra::Dim>(
    traj: &Trajectory<D>,
    output: Output,
) -> Option<OVector<f64, D>>
where
    DefaultAllocator: Allocator<D>,
{
    match output {
        Output::Strobe { .. } => traj.strobe.last().map(|p| p.y.clone()),
        Output::Dense { .. } => traj.samples.last().map(|s| s.y.clone()),
    }
}

/// Runs `model` from `(t0, y0)` chunk by chunk into `total`; `Err` only for Ctrl-C
/// (`KeyboardInterrupt`), a failed run is `Ok(Err(_))` with its outputs in `total`.
pub fn run<M>(
    py: Python<'_>,
    model: &M,
    (t0, y0): (f64, OVector<f64, M::Dim>),
    output: Output,
    opts: &SimOptions,
    total: &mut Trajectory<M::Dim>,
) -> PyResult<Outcome<M::Dim>>
where
    M: RotorModel + Sync,
    DefaultAllocator: Allocator<M::Dim>,
    OVector<f64, M::Dim>: Send + Sync,
{
    let (mut t, mut y, mut stats) = (t0, y0, SimStats::default());
    for j in 0.. {
        let Some(plan) = plan_of(model, output, (j, t), total.strobe.len() as u64) else {
            break;
        };
        let before = total.strobe.len() + total.samples.len();
        let result = py.detach(|| {
            let mut chunk = Trajectory::default();
            let r = simulate(model, t, &y, &plan, opts, &mut chunk);
            (r, chunk)
        });
        let (result, chunk) = result;
        let end = last_state(&chunk, output);
        total.strobe.extend(chunk.strobe);
        total.samples.extend(chunk.samples);
        total.events.extend(chunk.events);
        match result {
            Ok(s) => stats += s,
            Err(e) => return Ok(Err(e)),
        }
        match end {
            Some(e) if total.strobe.len() + total.samples.len() > before => {
                (t, y) = (plan.t_end, e);
            }
            _ => break,
        }
        py.check_signals()?;
    }
    Ok(Ok(stats))
}

/// Runs `model` from `y0` at t = 0 chunk by chunk ([`run`]) and makes `result` of what was
/// recorded and the work done: the result, or a failed run's error ([`run_error`]) whose
/// `partial` is the result of what was recorded before the failure.
pub fn run_into<M, T, F>(
    py: Python<'_>,
    model: &M,
    y0: OVector<f64, M::Dim>,
    output: Output,
    opts: &SimOptions,
    result: F,
) -> PyResult<T>
where
    M: RotorModel + Sync,
    DefaultAllocator: Allocator<M::Dim>,
    OVector<f64, M::Dim>: Send + Sync,
    T: PyClass + Into<PyClassInitializer<T>>,
    F: Fn(Python<'_>, &Trajectory<M::Dim>, &SimStats) -> PyResult<T>,
{
    let mut traj = Trajectory::default();
    match run(py, model, (0.0, y0), output, opts, &mut traj)? {
        Ok(stats) => result(py, &traj, &stats),
        Err(e) => {
            let partial = Py::new(py, result(py, &traj, &e.stats)?)?.into_any();
            Err(run_error(py, e, partial))
        }
    }
}

/// The state after `periods` forcing periods from `y0` at t = 0, run 100 periods a chunk
/// (Ctrl-C between them): where the analyses that seek an attractor start. A failed run is a
/// `SimulationError` (`partial` None).
pub fn settle<M>(
    py: Python<'_>,
    model: &M,
    y0: OVector<f64, M::Dim>,
    periods: u64,
    opts: &SimOptions,
) -> PyResult<OVector<f64, M::Dim>>
where
    M: RotorModel + Sync,
    DefaultAllocator: Allocator<M::Dim>,
    OVector<f64, M::Dim>: Send + Sync,
{
    let output = Output::Strobe {
        last: periods,
        per_chunk: 100,
    };
    let mut traj = Trajectory::default();
    if let Err(e) = run(py, model, (0.0, y0.clone()), output, opts, &mut traj)? {
        return Err(run_error(py, e, py.None()));
    }
    Ok(traj.strobe.pop().map_or(y0, |p| p.y))
}

/// The work of a run as a dict (steps, rejected, rhs_evals, exact_evals, transitions,
/// jacobians, lu_decompositions, woodbury_decompositions).
pub fn stats_dict<'py>(py: Python<'py>, s: &SimStats) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
    let d = pyo3::types::PyDict::new(py);
    d.set_item("steps", s.steps)?;
    d.set_item("rejected", s.rejected)?;
    d.set_item("rhs_evals", s.rhs_evals)?;
    d.set_item("exact_evals", s.exact_evals)?;
    d.set_item("transitions", s.transitions)?;
    d.set_item("jacobians", s.jacobians)?;
    d.set_item("lu_decompositions", s.lu_decompositions)?;
    d.set_item("woodbury_decompositions", s.woodbury_decompositions)?;
    Ok(d)
}
