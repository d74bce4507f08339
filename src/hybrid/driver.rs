//! The hybrid driver: advances a [`RotorModel`] through its modes, locating guards and
//! applying transitions, and reports outputs to an observer.

use nalgebra::{Const, SVector};
use thiserror::Error;

use super::record::{EventRecord, HybridObserver, OutputPlan, Sample, StrobePoint};
use super::{ExactSegment, Flow, GuardCrossing, ModelError, RotorModel};
use crate::ode::events::MAX_SAMPLES;
use crate::ode::{
    find_first_event, AnyIntegrator, Direction, EventOptions, EventSet, EventState, Integrator,
    Method, OdeError, OdeSystem, Options, Tolerance,
};

/// Options of a hybrid run. A plain struct with `Default`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SimOptions {
    /// Integration method of integrated modes. Default [`Method::Dop853`].
    pub method: Method,
    /// Relative tolerance of adaptive methods. Default `1e-10`.
    pub rtol: f64,
    /// Absolute tolerance of adaptive methods. Default `1e-12`.
    pub atol: f64,
    /// Fixed steps per forcing period for [`Method::Rk4`] (>= 1). Default 400.
    pub steps_per_period: u32,
    /// Largest step as a fraction of the forcing period (> 0). Default 0.25.
    pub max_step_fraction: f64,
    /// Interior samples per step for guard detection on the dense output, in
    /// `1..=`[`MAX_SAMPLES`]. Default 4.
    pub event_samples: usize,
    /// Chattering bound: more transitions than this within one forcing period is an error
    /// ([`SimErrorKind::Chattering`]). Default 1000.
    pub max_events_per_period: u32,
    /// Step attempts allowed per integrated phase. Default 1e7.
    pub max_steps: u64,
}

impl Default for SimOptions {
    fn default() -> Self {
        Self {
            method: Method::Dop853,
            rtol: 1e-10,
            atol: 1e-12,
            steps_per_period: 400,
            max_step_fraction: 0.25,
            event_samples: 4,
            max_events_per_period: 1000,
            max_steps: 10_000_000,
        }
    }
}

/// Work done by a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct SimStats {
    /// Accepted integrator steps.
    pub steps: u64,
    /// Rejected integrator steps.
    pub rejected: u64,
    /// Right-hand-side evaluations (steps, dense output, events).
    pub rhs_evals: u64,
    /// Closed-form evaluations in exact modes.
    pub exact_evals: u64,
    /// Transitions (events that changed the mode).
    pub transitions: u64,
}

/// What went wrong in a run.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum SimErrorKind {
    /// The model rejected the initial state or a transition.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The integrator failed (step-size underflow, non-finite values, too many steps).
    #[error(transparent)]
    Integrator(#[from] OdeError),
    /// Transitions accumulate: chattering or Zeno behaviour.
    #[error("chattering: {count} transitions within one forcing period (bound {bound}); raise SimOptions::max_events_per_period if this is expected")]
    Chattering {
        /// Transitions counted in the window.
        count: u32,
        /// The bound.
        bound: u32,
    },
    /// The state became NaN or infinite.
    #[error("non-finite state")]
    NonFinite,
    /// An option is invalid.
    #[error("invalid option `{field}` = {value}: {hint}")]
    InvalidOption {
        /// Field of [`SimOptions`] or [`OutputPlan`].
        field: &'static str,
        /// Offending value.
        value: f64,
        /// What to do.
        hint: &'static str,
    },
}

/// A failed run: the error, where it happened, and the work done. Whatever the observer
/// recorded up to that point stays in the observer.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("simulation failed at t = {t}: {kind}")]
pub struct SimError<const N: usize> {
    /// What went wrong.
    pub kind: SimErrorKind,
    /// Last good time.
    pub t: f64,
    /// Last good state.
    pub y: SVector<f64, N>,
    /// Work done until then.
    pub stats: SimStats,
}

/// The model in one mode, as an [`OdeSystem`].
struct ModeSystem<'a, M: RotorModel<N>, const N: usize> {
    model: &'a M,
    mode: M::Mode,
    cache: &'a M::Cache,
}

impl<M: RotorModel<N>, const N: usize> OdeSystem<Const<N>> for ModeSystem<'_, M, N> {
    fn rhs(&self, t: f64, y: &SVector<f64, N>, dy: &mut SVector<f64, N>) {
        self.model.rhs(self.mode, t, y, dy, self.cache);
    }
}

impl<M: RotorModel<N>, const N: usize> EventSet<Const<N>> for ModeSystem<'_, M, N> {
    fn len(&self) -> usize {
        self.model.guard_count(self.mode)
    }
    fn direction(&self, i: usize) -> Direction {
        self.model.guard_direction(self.mode, i)
    }
    fn value(&self, i: usize, t: f64, y: &SVector<f64, N>) -> f64 {
        self.model.guard_value(self.mode, i, t, y, self.cache)
    }
    fn derivative(
        &self,
        i: usize,
        t: f64,
        y: &SVector<f64, N>,
        dy: &SVector<f64, N>,
    ) -> Option<f64> {
        self.model
            .guard_derivative(self.mode, i, t, y, dy, self.cache)
    }
    fn derivative_needs_rhs(&self) -> bool {
        self.model.guard_derivative_needs_rhs()
    }
}

/// Pending outputs, in time order.
struct Schedule {
    period: f64,
    strobe_next: u64,
    strobe_last: u64,
    has_strobe: bool,
    dense_t0: f64,
    dense_dt: f64,
    dense_next: u64,
    has_dense: bool,
    t_end: f64,
}

enum Due {
    Strobe(u64),
    Dense,
}

impl Schedule {
    fn new(plan: &OutputPlan, period: f64, t0: f64) -> Self {
        let (first, last) = plan.strobe.map_or((1, 0), |r| (r.first, r.last));
        let (d0, dt) = plan
            .dense
            .map_or((f64::INFINITY, 1.0), |d| (d.t_start, d.dt));
        let mut s = Self {
            period,
            strobe_next: first,
            strobe_last: last,
            has_strobe: plan.strobe.is_some() && first <= last,
            dense_t0: d0,
            dense_dt: dt,
            dense_next: 0,
            has_dense: plan.dense.is_some(),
            t_end: plan.t_end,
        };
        // Skip outputs before the start.
        while s.has_strobe && s.strobe_time() < t0 {
            s.advance_strobe();
        }
        while s.has_dense && s.dense_time() < t0 {
            s.advance_dense();
        }
        s
    }
    fn strobe_time(&self) -> f64 {
        self.period * self.strobe_next as f64
    }
    fn dense_time(&self) -> f64 {
        self.dense_t0 + self.dense_dt * self.dense_next as f64
    }
    fn advance_strobe(&mut self) {
        self.strobe_next += 1;
        if self.strobe_next > self.strobe_last {
            self.has_strobe = false;
        }
    }
    fn advance_dense(&mut self) {
        self.dense_next += 1;
        if self.dense_time() > self.t_end {
            self.has_dense = false;
        }
    }
    fn next_strobe(&self) -> f64 {
        if self.has_strobe {
            self.strobe_time()
        } else {
            f64::INFINITY
        }
    }
    fn next_time(&self) -> f64 {
        let d = if self.has_dense {
            self.dense_time()
        } else {
            f64::INFINITY
        };
        self.next_strobe().min(d)
    }
    /// The next output due at or before `t`, strobes first on ties.
    fn pop_due(&mut self, t: f64) -> Option<(f64, Due)> {
        let ts = self.next_strobe();
        let td = if self.has_dense {
            self.dense_time()
        } else {
            f64::INFINITY
        };
        if ts <= t && ts <= td {
            let k = self.strobe_next;
            self.advance_strobe();
            Some((ts, Due::Strobe(k)))
        } else if td <= t {
            self.advance_dense();
            Some((td, Due::Dense))
        } else {
            None
        }
    }
}

/// Counts transitions in windows of one forcing period.
struct ChatterGuard {
    window_start: f64,
    count: u32,
    bound: u32,
    period: f64,
}

impl ChatterGuard {
    fn record(&mut self, t: f64) -> Result<(), SimErrorKind> {
        if t - self.window_start > self.period {
            self.window_start = t;
            self.count = 0;
        }
        self.count += 1;
        if self.count > self.bound {
            return Err(SimErrorKind::Chattering {
                count: self.count,
                bound: self.bound,
            });
        }
        Ok(())
    }
}

fn check_options(opts: &SimOptions, plan: &OutputPlan, t0: f64) -> Result<(), SimErrorKind> {
    let bad = |field, value, hint| Err(SimErrorKind::InvalidOption { field, value, hint });
    if !(opts.rtol.is_finite() && opts.rtol >= 0.0) {
        return bad("rtol", opts.rtol, "use a finite rtol >= 0, e.g. 1e-10");
    }
    if !(opts.atol.is_finite() && opts.atol >= 0.0) || opts.rtol + opts.atol <= 0.0 {
        return bad("atol", opts.atol, "use a finite atol > 0, e.g. 1e-12");
    }
    if opts.steps_per_period == 0 {
        return bad("steps_per_period", 0.0, "use at least 1 step per period");
    }
    if !(opts.max_step_fraction.is_finite() && opts.max_step_fraction > 0.0) {
        return bad(
            "max_step_fraction",
            opts.max_step_fraction,
            "use a finite fraction > 0, e.g. 0.25",
        );
    }
    if !(plan.t_end.is_finite() && plan.t_end >= t0) {
        return bad(
            "t_end",
            plan.t_end,
            "t_end must be finite and not before the start",
        );
    }
    if opts.event_samples == 0 || opts.event_samples > MAX_SAMPLES {
        return bad(
            "event_samples",
            opts.event_samples as f64,
            "use 1..=ode::MAX_SAMPLES (64) interior samples per step, e.g. 4",
        );
    }
    if let Some(r) = plan.strobe {
        if r.first > r.last {
            return bad(
                "strobe.first",
                r.first as f64,
                "the stroboscopic range is reversed: first must not exceed last",
            );
        }
    }
    if let Some(d) = plan.dense {
        if !d.t_start.is_finite() {
            return bad(
                "dense.t_start",
                d.t_start,
                "the first dense sample time must be finite",
            );
        }
        if !(d.dt.is_finite() && d.dt > 0.0) {
            return bad(
                "dense.dt",
                d.dt,
                "the dense sampling interval must be finite and > 0",
            );
        }
    }
    Ok(())
}

/// Runs `model` from `(t0, y0)` to `plan.t_end`, reporting outputs to `obs`.
///
/// Stroboscopic outputs in integrated modes come from the dense output of the last step
/// (DOP853: 7th order) or, for DOPRI5 and RK4, from steps that land exactly on them; in
/// exact modes they are the closed form.
///
/// # Errors
/// [`SimError`] with the last good `(t, y)`; the observer keeps what was recorded.
pub fn simulate<const N: usize, M, O>(
    model: &M,
    t0: f64,
    y0: &SVector<f64, N>,
    plan: &OutputPlan,
    opts: &SimOptions,
    obs: &mut O,
) -> Result<SimStats, SimError<N>>
where
    M: RotorModel<N>,
    O: HybridObserver<N>,
{
    let mut stats = SimStats::default();
    let fail = |kind: SimErrorKind, t: f64, y: SVector<f64, N>, stats: SimStats| SimError {
        kind,
        t,
        y,
        stats,
    };
    if let Err(k) = check_options(opts, plan, t0) {
        return Err(fail(k, t0, *y0, stats));
    }
    if !(t0.is_finite() && y0.iter().all(|v| v.is_finite())) {
        return Err(fail(SimErrorKind::NonFinite, t0, *y0, stats));
    }
    let period = model.forcing_period();
    let cache = M::Cache::default();
    // Outputs use their own scratch so that asking for them never changes the trajectory
    // (warm starts and the like would otherwise differ at the rounding level).
    let out_cache = M::Cache::default();
    let mut mode = model
        .initial_mode(t0, y0)
        .map_err(|e| fail(e.into(), t0, *y0, stats))?;
    let mut integ = build_integrator::<N>(opts, period).map_err(|e| fail(e, t0, *y0, stats))?;
    let land_on_strobe = opts.method != Method::Dop853;
    let ev_opts = EventOptions {
        samples_per_step: opts.event_samples,
        ..EventOptions::default()
    };
    let mut sched = Schedule::new(plan, period, t0);
    let mut chatter = ChatterGuard {
        window_start: t0,
        count: 0,
        bound: opts.max_events_per_period,
        period,
    };
    let (mut t, mut y) = (t0, *y0);
    let mut keep_step = false;
    let mut dy = SVector::<f64, N>::zeros();

    'modes: loop {
        // Outputs due exactly at the current time (start, or an event time).
        let (guard, t_event) = match model.flow(mode) {
            Flow::Exact => {
                let mut seg = model.start_segment(mode, t, &y);
                let found = loop {
                    let target = sched.next_time().min(plan.t_end);
                    let hit = seg.next_guard(t, target);
                    let t_stop = hit.map_or(target, |h| h.t);
                    while let Some((to, due)) = sched.pop_due(t_stop) {
                        seg.eval(to, &mut y, &mut dy);
                        emit(model, mode, obs, due, to, &y, &dy);
                    }
                    if let Some(GuardCrossing { guard, t: tg }) = hit {
                        seg.eval(tg, &mut y, &mut dy);
                        if !y.iter().all(|v| v.is_finite()) {
                            return Err(fail(SimErrorKind::NonFinite, t, y, stats));
                        }
                        break Some((guard, tg));
                    }
                    t = target;
                    if t >= plan.t_end {
                        break None;
                    }
                };
                stats.exact_evals += seg.evaluations();
                match found {
                    Some((g, tg)) => (g, tg),
                    None => {
                        seg.eval(t, &mut y, &mut dy);
                        break 'modes;
                    }
                }
            }
            Flow::Integrated => {
                let sys = ModeSystem {
                    model,
                    mode,
                    cache: &cache,
                };
                integ
                    .reset(&sys, t, &y, keep_step)
                    .map_err(|e| fail(e.into(), t, y, stats))?;
                let mut ev_state = EventState::new();
                loop {
                    let bound = if land_on_strobe {
                        sched.next_strobe().min(plan.t_end)
                    } else {
                        plan.t_end
                    };
                    if let Err(e) = integ.step(&sys, bound) {
                        collect(&mut stats, &integ);
                        return Err(fail(e.into(), integ.t(), *integ.y(), stats));
                    }
                    if !integ.y().iter().all(|v| v.is_finite()) {
                        collect(&mut stats, &integ);
                        return Err(fail(
                            SimErrorKind::NonFinite,
                            integ.t_prev(),
                            *integ.y_prev(),
                            stats,
                        ));
                    }
                    let hit =
                        match find_first_event(&mut integ, &sys, &sys, &ev_opts, &mut ev_state) {
                            Ok(hit) => hit,
                            Err(e) => {
                                collect(&mut stats, &integ);
                                return Err(fail(e.into(), integ.t(), *integ.y(), stats));
                            }
                        };
                    let t_stop = hit.as_ref().map_or(integ.t(), |h| h.t);
                    while let Some((to, due)) = sched.pop_due(t_stop) {
                        let mut yo = if to == integ.t() {
                            *integ.y()
                        } else {
                            let mut out = SVector::zeros();
                            integ.dense(&sys, to, &mut out);
                            out
                        };
                        model.project(mode, to, &mut yo, &out_cache);
                        model.rhs(mode, to, &yo, &mut dy, &out_cache);
                        emit(model, mode, obs, due, to, &yo, &dy);
                    }
                    if let Some(h) = hit {
                        y = h.y;
                        collect(&mut stats, &integ);
                        break (h.index, h.t);
                    }
                    t = integ.t();
                    y = *integ.y();
                    if t >= plan.t_end {
                        collect(&mut stats, &integ);
                        model.project(mode, t, &mut y, &cache);
                        break 'modes;
                    }
                }
            }
        };
        // Transition.
        t = t_event;
        model.project(mode, t, &mut y, &cache);
        let before = y;
        let from = model.mode_label(mode);
        let kind = model.guard_label(mode, guard);
        let next = model
            .transition(mode, guard, t, &mut y)
            .map_err(|e| fail(e.into(), t, before, stats))?;
        stats.transitions += 1;
        if let Err(k) = chatter.record(t) {
            return Err(fail(k, t, y, stats));
        }
        if plan.events {
            obs.on_event(&EventRecord {
                t,
                kind,
                before,
                after: y,
                from,
                to: model.mode_label(next),
            });
        }
        keep_step = true;
        mode = next;
        if t >= plan.t_end {
            break;
        }
    }
    Ok(stats)
}

fn emit<const N: usize, M: RotorModel<N>, O: HybridObserver<N>>(
    model: &M,
    mode: M::Mode,
    obs: &mut O,
    due: Due,
    t: f64,
    y: &SVector<f64, N>,
    dy: &SVector<f64, N>,
) {
    let label = model.mode_label(mode);
    match due {
        Due::Strobe(k) => obs.on_strobe(&StrobePoint { k, t, y: *y, label }),
        Due::Dense => obs.on_sample(&Sample {
            t,
            y: *y,
            dy: *dy,
            label,
        }),
    }
}

fn collect<const N: usize>(stats: &mut SimStats, integ: &AnyIntegrator<Const<N>>) {
    let s = integ.stats();
    stats.steps = s.steps;
    stats.rejected = s.rejected;
    stats.rhs_evals = s.rhs_evals;
}

fn build_integrator<const N: usize>(
    opts: &SimOptions,
    period: f64,
) -> Result<AnyIntegrator<Const<N>>, SimErrorKind> {
    let mut o = Options::<Const<N>> {
        rtol: Tolerance::Scalar(opts.rtol),
        atol: Tolerance::Scalar(opts.atol),
        h_max: opts.max_step_fraction * period,
        max_steps: opts.max_steps,
        ..Options::default()
    };
    if opts.method == Method::Rk4 {
        o.fixed_step = Some(period / f64::from(opts.steps_per_period));
    }
    Ok(AnyIntegrator::new(opts.method, o)?)
}
