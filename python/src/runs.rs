//! Long runs from Python: one run of the crate's driver with the GIL released, its outputs
//! recorded by an observer that the driver asks after every step whether to stop
//! (`HybridObserver::should_stop`); the observer runs Python's signal handlers at most every
//! 50 ms ([`CtrlC`]), so a Ctrl-C stops the run and raises its `KeyboardInterrupt`. The run is
//! never cut or restarted: it is bit for bit the same run as from Rust.

use jeffcott::hybrid::{
    simulate, DenseSampling, EventRecord, HybridObserver, OutputPlan, RotorModel, Sample, SimError,
    SimOptions, SimStats, StrobePoint, StrobeRange, Trajectory,
};
use jeffcott::nalgebra::allocator::Allocator;
use jeffcott::nalgebra::{DefaultAllocator, Dim, OVector};
use pyo3::prelude::*;
use pyo3::pyclass_init::PyClassInitializer;
use pyo3::PyClass;

use crate::errors::run_error;
use crate::interrupt::CtrlC;

/// A finished or failed run: everything recorded is in the caller's trajectory.
pub type Outcome<D> = Result<SimStats, SimError<D>>;

/// Which outputs a run records.
#[derive(Debug, Clone, Copy)]
pub enum Output {
    /// Stroboscopic points `k = 0..=last` (the model's strobe times).
    Strobe { last: u64 },
    /// `count` samples at `i dt`, with the event log, and the stroboscopic points up to the
    /// last sample if `strobes`.
    Dense { dt: f64, count: u64, strobes: bool },
}

impl Output {
    /// The same output with the stroboscopic points too (dense outputs only).
    pub fn with_strobes(self) -> Self {
        match self {
            Output::Dense { dt, count, .. } => Output::Dense {
                dt,
                count,
                strobes: true,
            },
            strobe => strobe,
        }
    }

    /// The driver's plan of a run from t = 0.
    fn plan<M: RotorModel>(self, model: &M) -> OutputPlan
    where
        DefaultAllocator: Allocator<M::Dim>,
    {
        match self {
            Output::Strobe { last } => OutputPlan {
                t_end: model.strobe_time(last),
                strobe: Some(StrobeRange { first: 0, last }),
                dense: None,
                events: false,
            },
            Output::Dense { dt, count, strobes } => OutputPlan {
                // The driver's sample times are `i dt`: the last one is `t_end` exactly.
                t_end: dt * count.saturating_sub(1) as f64,
                strobe: strobes.then_some(StrobeRange {
                    first: 0,
                    last: u64::MAX - 1,
                }),
                dense: Some(DenseSampling { t_start: 0.0, dt }),
                events: true,
            },
        }
    }
}

/// Records a run's outputs and stops it on Ctrl-C.
struct Recorder<'a, D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    traj: &'a mut Trajectory<D>,
    ctrl_c: &'a CtrlC,
    /// The driver's questions so far (one a step).
    steps: u32,
}

impl<D: Dim> HybridObserver<D> for Recorder<'_, D>
where
    DefaultAllocator: Allocator<D>,
{
    fn on_strobe(&mut self, point: &StrobePoint<D>) {
        self.traj.on_strobe(point);
    }
    fn on_sample(&mut self, sample: &Sample<D>) {
        self.traj.on_sample(sample);
    }
    fn on_event(&mut self, event: &EventRecord<D>) {
        self.traj.on_event(event);
    }
    fn should_stop(&mut self) -> bool {
        // The clock and the locks every 16 steps: a few nanoseconds a step, where a step of
        // the paper's model takes about a microsecond.
        self.steps = self.steps.wrapping_add(1);
        self.steps.is_multiple_of(16) && jeffcott::analysis::Progress::should_stop(self.ctrl_c)
    }
}

/// Runs `model` from `y0` at t = 0 into `total`; `Err` only for Ctrl-C (`KeyboardInterrupt`),
/// a failed run is `Ok(Err(_))` with its outputs in `total`.
pub fn run<M>(
    py: Python<'_>,
    model: &M,
    y0: &OVector<f64, M::Dim>,
    output: Output,
    opts: &SimOptions,
    total: &mut Trajectory<M::Dim>,
) -> PyResult<Outcome<M::Dim>>
where
    M: RotorModel + Sync,
    DefaultAllocator: Allocator<M::Dim>,
    OVector<f64, M::Dim>: Send + Sync,
{
    let plan = output.plan(model);
    let ctrl_c = CtrlC::new();
    let outcome = py.detach(|| {
        let mut recorder = Recorder {
            traj: &mut *total,
            ctrl_c: &ctrl_c,
            steps: 0,
        };
        simulate(model, 0.0, y0, &plan, opts, &mut recorder)
    });
    // The run stops only for a raised handler: then that (the KeyboardInterrupt) is the
    // answer, not the driver's `Stopped`.
    ctrl_c.raised()?;
    Ok(outcome)
}

/// Runs `model` from `y0` at t = 0 ([`run`]) and makes `result` of what was recorded and the
/// work done: the result, or a failed run's error ([`run_error`]) whose `partial` is the
/// result of what was recorded before the failure.
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
    match run(py, model, &y0, output, opts, &mut traj)? {
        Ok(stats) => result(py, &traj, &stats),
        Err(e) => {
            let partial = Py::new(py, result(py, &traj, &e.stats)?)?.into_any();
            Err(run_error(py, e, partial))
        }
    }
}

/// The state after `periods` forcing periods from `y0` at t = 0 (Ctrl-C stops it): where the
/// analyses that seek an attractor start. A failed run is a `SimulationError` (`partial`
/// None).
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
    let output = Output::Strobe { last: periods };
    let mut traj = Trajectory::default();
    if let Err(e) = run(py, model, &y0, output, opts, &mut traj)? {
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
