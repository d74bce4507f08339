use super::core::zeros;
use super::events::{find_first_event, EventHit, EventOptions, EventSet, EventState};
use super::{Integrator, OdeError, OdeSystem, Stats};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};
use thiserror::Error;

/// Receives the results of [`solve`]. Every method has a no-op default.
///
/// Order of calls inside one step: outputs with times up to an event, the
/// event, further outputs/events, then `on_step` with the step's end point.
pub trait Observer<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Called with the initial point and after every accepted step (for a
    /// terminal event: with the truncated end point).
    fn on_step(&mut self, t: f64, y: &OVector<f64, D>) {
        let _ = (t, y);
    }
    /// Called for every event hit (terminal or not).
    fn on_event(&mut self, hit: &EventHit<D>) {
        let _ = hit;
    }
    /// The next requested output time. Called once at the start and after
    /// every `on_output`; times must be non-decreasing. Times before `t0` are
    /// skipped, times after the end of the integration are never reached.
    /// `None` = no (more) outputs.
    fn next_output(&mut self) -> Option<f64> {
        None
    }
    /// The state at a requested output time (dense output; the exact state
    /// at a step end).
    fn on_output(&mut self, t: f64, y: &OVector<f64, D>) {
        let _ = (t, y);
    }
}

/// An observer that ignores everything.
impl<D: Dim> Observer<D> for () where DefaultAllocator: Allocator<D> {}

/// An observer that records outputs on a given time grid, the accepted
/// steps (optional) and the events. Allocates only when it records.
#[derive(Debug, Clone)]
pub struct Recorder<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Requested output times (non-decreasing).
    pub grid: Vec<f64>,
    /// Whether to record every accepted step in `steps`.
    pub record_steps: bool,
    /// Recorded outputs `(t, y)`.
    pub outputs: Vec<(f64, OVector<f64, D>)>,
    /// Recorded steps `(t, y)` (if `record_steps`).
    pub steps: Vec<(f64, OVector<f64, D>)>,
    /// Recorded events.
    pub events: Vec<EventHit<D>>,
    next: usize,
}

impl<D: Dim> Default for Recorder<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn default() -> Self {
        Recorder {
            grid: Vec::new(),
            record_steps: false,
            outputs: Vec::new(),
            steps: Vec::new(),
            events: Vec::new(),
            next: 0,
        }
    }
}

impl<D: Dim> Recorder<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// A recorder with output times `grid` that does not record steps.
    pub fn with_grid(grid: Vec<f64>) -> Self {
        Recorder {
            grid,
            ..Default::default()
        }
    }
}

impl<D: Dim> Observer<D> for Recorder<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn on_step(&mut self, t: f64, y: &OVector<f64, D>) {
        if self.record_steps {
            self.steps.push((t, y.clone()));
        }
    }
    fn on_event(&mut self, hit: &EventHit<D>) {
        self.events.push(hit.clone());
    }
    fn next_output(&mut self) -> Option<f64> {
        let t = self.grid.get(self.next).copied();
        self.next += 1;
        t
    }
    fn on_output(&mut self, t: f64, y: &OVector<f64, D>) {
        self.outputs.push((t, y.clone()));
    }
}

/// Why [`solve`] stopped.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Stopped {
    /// `t_end` was reached.
    Reached,
    /// A terminal event `(index, t)` fired.
    Event(usize, f64),
}

/// Result of a successful [`solve`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct SolveReport<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Why the integration stopped.
    pub stopped: Stopped,
    /// Final time.
    pub t: f64,
    /// Final state.
    pub y: OVector<f64, D>,
    /// Work counters of the integrator (cumulative over its lifetime).
    pub stats: Stats,
}

impl<D: Dim> Copy for SolveReport<D>
where
    DefaultAllocator: Allocator<D>,
    OVector<f64, D>: Copy,
{
}

/// A failure part-way through [`solve`]: the error, the last good point and
/// the work counters.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("integration failed at t = {t}: {error}")]
pub struct SolveError<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// The underlying error.
    #[source]
    pub error: OdeError,
    /// Last good (accepted) time.
    pub t: f64,
    /// Last good state.
    pub y: OVector<f64, D>,
    /// Work counters at the failure.
    pub stats: Stats,
}

impl<D: Dim> Copy for SolveError<D>
where
    DefaultAllocator: Allocator<D>,
    OVector<f64, D>: Copy,
{
}

/// The observer's requested output times not yet reported, and the scratch the dense output
/// is written into.
struct Outputs<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// The next requested time (`None`: no more).
    pending: Option<f64>,
    y: OVector<f64, D>,
}

impl<D: Dim> Outputs<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Skips the requested times before `t0` (and NaN) and reports those at `t0` with `y0`.
    fn start<O: Observer<D> + ?Sized>(out: &mut O, t0: f64, y0: &OVector<f64, D>, dim: D) -> Self {
        let mut pending = out.next_output();
        while let Some(to) = pending {
            if to < t0 || to.is_nan() {
                pending = out.next_output();
            } else {
                break;
            }
        }
        while pending == Some(t0) {
            out.on_output(t0, y0);
            pending = out.next_output();
        }
        Outputs {
            pending,
            y: zeros(dim),
        }
    }

    /// Reports every pending output time `<= upto` on the last step.
    fn emit<S, I, O>(&mut self, integ: &mut I, sys: &S, upto: f64, out: &mut O)
    where
        S: OdeSystem<D>,
        I: Integrator<D>,
        O: Observer<D> + ?Sized,
    {
        while let Some(to) = self.pending {
            if to > upto {
                break;
            }
            if to == integ.t() {
                self.y.copy_from(integ.y());
            } else {
                integ.dense(sys, to, &mut self.y);
            }
            out.on_output(to, &self.y);
            self.pending = out.next_output();
        }
    }
}

/// [`solve_with`] with default [`EventOptions`].
pub fn solve<D, S, I, E>(
    integ: &mut I,
    sys: &S,
    t0: f64,
    y0: &OVector<f64, D>,
    t_end: f64,
    events: &E,
    out: &mut impl Observer<D>,
) -> Result<SolveReport<D>, SolveError<D>>
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
    E: EventSet<D> + ?Sized,
{
    solve_with(
        integ,
        sys,
        t0,
        y0,
        t_end,
        events,
        &EventOptions::default(),
        out,
    )
}

/// Integrates from `(t0, y0)` to `t_end` (>= `t0`): resets `integ` (automatic
/// or `h_init` initial step), steps towards `t_end`, reports outputs at the
/// observer's requested times from the dense output, looks for events on
/// every step (several non-terminal events per step are reported in time
/// order) and stops at the first terminal event, truncating the integrator
/// there. Events at `t0` itself do not fire (re-arming rule of
/// [events](crate::ode#events)).
///
/// Errors carry the last good `(t, y)` and the stats.
#[allow(clippy::too_many_arguments)]
pub fn solve_with<D, S, I, E>(
    integ: &mut I,
    sys: &S,
    t0: f64,
    y0: &OVector<f64, D>,
    t_end: f64,
    events: &E,
    event_opts: &EventOptions,
    out: &mut impl Observer<D>,
) -> Result<SolveReport<D>, SolveError<D>>
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
    E: EventSet<D> + ?Sized,
{
    let stats0 = *integ.stats();
    let fail0 = |error: OdeError| SolveError {
        error,
        t: t0,
        y: y0.clone(),
        stats: stats0,
    };
    event_opts.validate().map_err(fail0)?;
    if !(t_end.is_finite() && t0.is_finite() && t_end >= t0) {
        return Err(fail0(OdeError::InvalidBound {
            t: t0,
            t_bound: t_end,
        }));
    }
    integ.reset(sys, t0, y0, false).map_err(fail0)?;
    let mut state = EventState::with_dim(integ.dim());
    let mut outputs = Outputs::start(out, t0, y0, integ.dim());
    out.on_step(t0, y0);
    while integ.t() < t_end {
        integ.step(sys, t_end).map_err(|e| failure(integ, e))?;
        let scan = (events, event_opts, &mut state);
        if let Some(stop) =
            events_in_step(integ, sys, scan, &mut outputs, out).map_err(|e| failure(integ, e))?
        {
            return Ok(report(integ, stop));
        }
        let t_now = integ.t();
        outputs.emit(integ, sys, t_now, out);
        out.on_step(integ.t(), integ.y());
    }
    Ok(report(integ, Stopped::Reached))
}

/// The events of the step just taken, in time order, with the outputs before each; at a
/// terminal event the integrator is truncated there and the stop returned.
fn events_in_step<D, S, I, E>(
    integ: &mut I,
    sys: &S,
    (events, event_opts, state): (&E, &EventOptions, &mut EventState<D>),
    outputs: &mut Outputs<D>,
    out: &mut impl Observer<D>,
) -> Result<Option<Stopped>, OdeError>
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
    E: EventSet<D> + ?Sized,
{
    while let Some(hit) = find_first_event(integ, sys, events, event_opts, state)? {
        outputs.emit(integ, sys, hit.t, out);
        out.on_event(hit);
        if events.terminal(hit.index) {
            let (index, t_hit) = (hit.index, hit.t);
            integ.truncate(sys, t_hit)?;
            out.on_step(integ.t(), integ.y());
            return Ok(Some(Stopped::Event(index, t_hit)));
        }
    }
    Ok(None)
}

/// The integrator's current point and counters as a [`SolveReport`].
fn report<D: Dim, I: Integrator<D>>(integ: &I, stopped: Stopped) -> SolveReport<D>
where
    DefaultAllocator: Allocator<D>,
{
    SolveReport {
        stopped,
        t: integ.t(),
        y: integ.y().clone(),
        stats: *integ.stats(),
    }
}

/// A failure at the integrator's last good point.
fn failure<D: Dim, I: Integrator<D>>(integ: &I, error: OdeError) -> SolveError<D>
where
    DefaultAllocator: Allocator<D>,
{
    SolveError {
        error,
        t: integ.t(),
        y: integ.y().clone(),
        stats: *integ.stats(),
    }
}
