//! A convenience driver: integrate from `t0` to `t_end` with outputs at
//! requested times (from the dense output) and events.

use super::events::{check_event_set, find_first_event, EventHit, EventOptions, EventSet, EventState};
use super::{Integrator, OdeError, OdeSystem, Stats};
use nalgebra::SVector;
use thiserror::Error;

/// Receives the results of [`solve`]. Every method has a no-op default.
///
/// Order of calls inside one step: outputs with times up to an event, the
/// event, further outputs/events, then `on_step` with the step's end point.
pub trait Observer<const N: usize> {
    /// Called with the initial point and after every accepted step (for a
    /// terminal event: with the truncated end point).
    fn on_step(&mut self, t: f64, y: &SVector<f64, N>) {
        let _ = (t, y);
    }
    /// Called for every event hit (terminal or not).
    fn on_event(&mut self, hit: &EventHit<N>) {
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
    fn on_output(&mut self, t: f64, y: &SVector<f64, N>) {
        let _ = (t, y);
    }
}

/// An observer that ignores everything.
impl<const N: usize> Observer<N> for () {}

/// An observer that records outputs on a given time grid, the accepted
/// steps (optional) and the events. Allocates only when it records.
#[derive(Debug, Clone, Default)]
pub struct Recorder<const N: usize> {
    /// Requested output times (non-decreasing).
    pub grid: Vec<f64>,
    /// Whether to record every accepted step in `steps`.
    pub record_steps: bool,
    /// Recorded outputs `(t, y)`.
    pub outputs: Vec<(f64, SVector<f64, N>)>,
    /// Recorded steps `(t, y)` (if `record_steps`).
    pub steps: Vec<(f64, SVector<f64, N>)>,
    /// Recorded events.
    pub events: Vec<EventHit<N>>,
    next: usize,
}

impl<const N: usize> Recorder<N> {
    /// A recorder with output times `grid` that does not record steps.
    pub fn with_grid(grid: Vec<f64>) -> Self {
        Recorder {
            grid,
            ..Default::default()
        }
    }
}

impl<const N: usize> Observer<N> for Recorder<N> {
    fn on_step(&mut self, t: f64, y: &SVector<f64, N>) {
        if self.record_steps {
            self.steps.push((t, *y));
        }
    }
    fn on_event(&mut self, hit: &EventHit<N>) {
        self.events.push(*hit);
    }
    fn next_output(&mut self) -> Option<f64> {
        let t = self.grid.get(self.next).copied();
        self.next += 1;
        t
    }
    fn on_output(&mut self, t: f64, y: &SVector<f64, N>) {
        self.outputs.push((t, *y));
    }
}

/// Why [`solve`] stopped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Stopped {
    /// `t_end` was reached.
    Reached,
    /// A terminal event `(index, t)` fired.
    Event(usize, f64),
}

/// Result of a successful [`solve`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveReport<const N: usize> {
    /// Why the integration stopped.
    pub stopped: Stopped,
    /// Final time.
    pub t: f64,
    /// Final state.
    pub y: SVector<f64, N>,
    /// Work counters of the integrator (cumulative over its lifetime).
    pub stats: Stats,
}

/// A failure part-way through [`solve`]: the error, the last good point and
/// the work counters.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[error("integration failed at t = {t}: {error}")]
pub struct SolveError<const N: usize> {
    /// The underlying error.
    #[source]
    pub error: OdeError,
    /// Last good (accepted) time.
    pub t: f64,
    /// Last good state.
    pub y: SVector<f64, N>,
    /// Work counters at the failure.
    pub stats: Stats,
}

/// Reports every pending output time `<= upto` on the last step.
fn emit_outputs<const N: usize, S, I, O>(
    integ: &mut I,
    sys: &S,
    upto: f64,
    pending: &mut Option<f64>,
    out: &mut O,
    y_out: &mut SVector<f64, N>,
) where
    S: OdeSystem<N>,
    I: Integrator<N>,
    O: Observer<N> + ?Sized,
{
    while let Some(to) = *pending {
        if to > upto {
            break;
        }
        if to == integ.t() {
            *y_out = *integ.y();
        } else {
            integ.dense(sys, to, y_out);
        }
        out.on_output(to, y_out);
        *pending = out.next_output();
    }
}

/// [`solve_with`] with default [`EventOptions`].
pub fn solve<const N: usize, S, I, E>(
    integ: &mut I,
    sys: &S,
    t0: f64,
    y0: &SVector<f64, N>,
    t_end: f64,
    events: &E,
    out: &mut impl Observer<N>,
) -> Result<SolveReport<N>, SolveError<N>>
where
    S: OdeSystem<N>,
    I: Integrator<N>,
    E: EventSet<N> + ?Sized,
{
    solve_with(integ, sys, t0, y0, t_end, events, &EventOptions::default(), out)
}

/// Integrates from `(t0, y0)` to `t_end` (>= `t0`): resets `integ` (automatic
/// or `h_init` initial step), steps towards `t_end`, reports outputs at the
/// observer's requested times from the dense output, looks for events on
/// every step (several non-terminal events per step are reported in time
/// order) and stops at the first terminal event, truncating the integrator
/// there. Events at `t0` itself do not fire (re-arming rule of
/// [`events`](super::events)).
///
/// Errors carry the last good `(t, y)` and the stats.
#[allow(clippy::too_many_arguments)]
pub fn solve_with<const N: usize, S, I, E>(
    integ: &mut I,
    sys: &S,
    t0: f64,
    y0: &SVector<f64, N>,
    t_end: f64,
    events: &E,
    event_opts: &EventOptions,
    out: &mut impl Observer<N>,
) -> Result<SolveReport<N>, SolveError<N>>
where
    S: OdeSystem<N>,
    I: Integrator<N>,
    E: EventSet<N> + ?Sized,
{
    let fail = |integ: &I, error: OdeError| SolveError {
        error,
        t: integ.t(),
        y: *integ.y(),
        stats: *integ.stats(),
    };
    let stats0 = *integ.stats();
    let fail0 = |error: OdeError| SolveError {
        error,
        t: t0,
        y: *y0,
        stats: stats0,
    };
    check_event_set(events).map_err(fail0)?;
    event_opts.validate().map_err(fail0)?;
    if !(t_end.is_finite() && t0.is_finite() && t_end >= t0) {
        return Err(fail0(OdeError::InvalidBound { t: t0, t_bound: t_end }));
    }
    integ.reset(sys, t0, y0, false).map_err(fail0)?;
    let mut state = EventState::<N>::new();

    let mut pending = out.next_output();
    while let Some(to) = pending {
        if to < t0 || to.is_nan() {
            pending = out.next_output();
        } else {
            break;
        }
    }
    if pending == Some(t0) {
        out.on_output(t0, y0);
        pending = out.next_output();
        while pending == Some(t0) {
            out.on_output(t0, y0);
            pending = out.next_output();
        }
    }
    out.on_step(t0, y0);

    let mut y_out = SVector::<f64, N>::zeros();
    while integ.t() < t_end {
        integ.step(sys, t_end).map_err(|e| fail(integ, e))?;
        loop {
            match find_first_event(integ, sys, events, event_opts, &mut state) {
                Some(hit) => {
                    emit_outputs(integ, sys, hit.t, &mut pending, out, &mut y_out);
                    out.on_event(&hit);
                    if events.terminal(hit.index) {
                        integ.truncate(sys, hit.t).map_err(|e| fail(integ, e))?;
                        out.on_step(integ.t(), integ.y());
                        return Ok(SolveReport {
                            stopped: Stopped::Event(hit.index, hit.t),
                            t: integ.t(),
                            y: *integ.y(),
                            stats: *integ.stats(),
                        });
                    }
                }
                None => break,
            }
        }
        let t_now = integ.t();
        emit_outputs(integ, sys, t_now, &mut pending, out, &mut y_out);
        out.on_step(integ.t(), integ.y());
    }
    Ok(SolveReport {
        stopped: Stopped::Reached,
        t: integ.t(),
        y: *integ.y(),
        stats: *integ.stats(),
    })
}
