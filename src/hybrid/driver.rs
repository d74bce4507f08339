//! The hybrid driver: advances a [`RotorModel`] through its modes, locating guards and
//! applying transitions, and reports outputs to an observer.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector, U1};
use thiserror::Error;

use super::record::{EventRecord, HybridObserver, OutputPlan, Sample, StrobePoint};
use super::{ExactSegment, Flow, GuardCrossing, ModelError, RotorModel};
use crate::numeric::{illinois, Direction, RootOptions};
use crate::ode::{
    find_first_event, AnyIntegrator, EventOptions, EventSet, EventState, Integrator, JacobianMut,
    Method, OdeError, OdeSystem, Options, Tolerance, MAX_SAMPLES,
};

/// Options of a hybrid run. Start from `Default` and change fields with the `with_` builders.
// serde always, not only with the feature: the sweeps of `global` record it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub struct SimOptions {
    /// Integration method of integrated modes. Default [`Method::Dop853`].
    pub method: Method,
    /// Relative tolerance of adaptive methods. Default `1e-10`.
    pub rtol: f64,
    /// Absolute tolerance of adaptive methods, in units of the model's
    /// [`RotorModel::error_scale`] if it gives one and the method is implicit
    /// ([`Method::is_implicit`]), else of its [`RotorModel::state_scale`] (component $i$'s is
    /// `atol * scale[i]`). Default `1e-12`.
    pub atol: f64,
    /// Fixed steps per forcing period for [`Method::Rk4`] (>= 1). Default 400. RK4 is stable
    /// only while $h\lambda \lesssim 2.8$ for the fastest rate $\lambda$ of the motion (in
    /// the paper's model about $\sqrt{1 + 2K} + 2\nu_1 + 4\nu_2$ in contact): beyond it the
    /// run goes on with finite garbage on which no guard is located reliably (see
    /// `docs/reliability.md`).
    pub steps_per_period: u32,
    /// Largest step as a fraction of the forcing period (> 0). Default 0.25.
    pub max_step_fraction: f64,
    /// Interior samples per step for guard detection on the dense output, in
    /// `1..=`[`MAX_SAMPLES`], evenly spaced. Default `None`: the method's
    /// ([`Method::event_samples`]: 4, and 3 for ETD4, whose dense output is cheapest at the
    /// step's quarters).
    pub event_samples: Option<usize>,
    /// Chattering bound: more transitions than this within one forcing period is an error
    /// ([`SimErrorKind::Chattering`]), reported once time is seen to advance past the transition
    /// that exceeded the bound (so that raising it lets the run go further). Default 1000.
    /// Transitions that do not advance time are [`SimErrorKind::Stalled`] after 64 in a row,
    /// whatever this bound (a lower bound does not shorten the evidence for a stall).
    pub max_events_per_period: u32,
    /// Step attempts (accepted and rejected) allowed in a run, all integrated phases together
    /// (each phase's integrator is held to it too). A run that needs more ends in
    /// [`SimErrorKind::TooManySteps`] with what it computed: the bound on a run's work, however
    /// many contacts split it into phases. Default 1e7.
    pub max_steps: u64,
}

/// Builders: each returns the options with one field changed.
impl SimOptions {
    /// With [`method`](Self::method) = `value`.
    #[must_use]
    pub fn with_method(mut self, value: Method) -> Self {
        self.method = value;
        self
    }

    /// With [`rtol`](Self::rtol) = `value`.
    #[must_use]
    pub fn with_rtol(mut self, value: f64) -> Self {
        self.rtol = value;
        self
    }

    /// With [`atol`](Self::atol) = `value`.
    #[must_use]
    pub fn with_atol(mut self, value: f64) -> Self {
        self.atol = value;
        self
    }

    /// With [`steps_per_period`](Self::steps_per_period) = `value`.
    #[must_use]
    pub fn with_steps_per_period(mut self, value: u32) -> Self {
        self.steps_per_period = value;
        self
    }

    /// With [`max_step_fraction`](Self::max_step_fraction) = `value`.
    #[must_use]
    pub fn with_max_step_fraction(mut self, value: f64) -> Self {
        self.max_step_fraction = value;
        self
    }

    /// The interior samples per step a run takes: [`event_samples`](Self::event_samples), or
    /// the method's.
    pub fn samples_per_step(&self) -> usize {
        self.event_samples
            .unwrap_or_else(|| self.method.event_samples())
    }

    /// With [`event_samples`](Self::event_samples) = `Some(value)`.
    #[must_use]
    pub fn with_event_samples(mut self, value: usize) -> Self {
        self.event_samples = Some(value);
        self
    }

    /// With [`max_events_per_period`](Self::max_events_per_period) = `value`.
    #[must_use]
    pub fn with_max_events_per_period(mut self, value: u32) -> Self {
        self.max_events_per_period = value;
        self
    }

    /// With [`max_steps`](Self::max_steps) = `value`.
    #[must_use]
    pub fn with_max_steps(mut self, value: u64) -> Self {
        self.max_steps = value;
        self
    }
}

impl Default for SimOptions {
    fn default() -> Self {
        Self {
            method: Method::Dop853,
            rtol: 1e-10,
            atol: 1e-12,
            steps_per_period: 400,
            max_step_fraction: 0.25,
            event_samples: None,
            max_events_per_period: 1000,
            max_steps: 10_000_000,
        }
    }
}

/// Work done by a run.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
    /// Fixed (RK4) steps longer than the inverse of the model's bound on its rates
    /// ([`RotorModel::max_rate`]): steps that do not resolve the motion. A run with any is
    /// not trustworthy (its outputs may be inconsistent, e.g. the rotor beyond the ring):
    /// raise [`SimOptions::steps_per_period`] until this is 0. Always 0 for the adaptive
    /// methods and for models that give no bound.
    pub unresolved_steps: u64,
    /// Jacobians of the right-hand side computed by the integrator ([`Radau5`](crate::ode::Radau5);
    /// 0 for the explicit methods).
    #[cfg_attr(feature = "serde", serde(default))]
    pub jacobians: u64,
    /// LU decompositions of the integrator's Newton matrices ([`Radau5`](crate::ode::Radau5):
    /// its real and complex one counted as one; 0 for the explicit methods).
    #[cfg_attr(feature = "serde", serde(default))]
    pub lu_decompositions: u64,
    /// Of `lu_decompositions`, those made as diagonal plus low rank (the model's
    /// [`RotorModel::diagonal_springs`]): $O(N)$ each.
    #[cfg_attr(feature = "serde", serde(default))]
    pub woodbury_decompositions: u64,
}

/// The work of two runs together, field by field: the work of a run continued from where
/// another ended (e.g. one stopped by its observer, [`SimErrorKind::Stopped`]).
///
/// ```
/// use jeffcott::hybrid::SimStats;
/// let mut total = SimStats { steps: 3, woodbury_decompositions: 1, ..Default::default() };
/// total += SimStats { steps: 4, woodbury_decompositions: 2, ..Default::default() };
/// assert_eq!((total.steps, total.woodbury_decompositions), (7, 3));
/// ```
impl std::ops::AddAssign for SimStats {
    fn add_assign(&mut self, s: Self) {
        // Destructured: a field added to `SimStats` must be added here too.
        let SimStats {
            steps,
            rejected,
            rhs_evals,
            exact_evals,
            transitions,
            unresolved_steps,
            jacobians,
            lu_decompositions,
            woodbury_decompositions,
        } = s;
        self.steps += steps;
        self.rejected += rejected;
        self.rhs_evals += rhs_evals;
        self.exact_evals += exact_evals;
        self.transitions += transitions;
        self.unresolved_steps += unresolved_steps;
        self.jacobians += jacobians;
        self.lu_decompositions += lu_decompositions;
        self.woodbury_decompositions += woodbury_decompositions;
    }
}

/// What went wrong in a run.
#[derive(Debug, Clone, PartialEq, Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum SimErrorKind {
    /// The model rejected the initial state or a transition.
    #[error(transparent)]
    Model(#[from] ModelError),
    /// The integrator failed (step-size underflow, non-finite values, too many steps).
    #[error(transparent)]
    Integrator(#[from] OdeError),
    /// Transitions accumulate: chattering or Zeno behaviour. Time still advances between
    /// them: the error is reported at the first transition after the bound was exceeded that
    /// advances time (or at the end of the run), with the time and state of the transition
    /// that exceeded it, so a larger bound lets the run go further. A run that cannot advance
    /// at all is [`SimErrorKind::Stalled`].
    #[error("chattering: {count} transitions within one forcing period (bound {bound}); raise SimOptions::max_events_per_period if this is expected")]
    Chattering {
        /// Transitions counted in the window.
        count: u32,
        /// The bound.
        bound: u32,
    },
    /// Transitions follow each other without time advancing beyond a few ulps: the model's
    /// transition map cycles at one instant (e.g. a contact that can neither persist nor
    /// separate), so no bound on the number of transitions would let the run go on.
    #[error("stalled at t = {t}: {transitions} transitions without time advancing (last guard `{last_guard}`); the model has no consistent continuation from this state, so raising max_events_per_period will not help: inspect the state (SimError::y) and the event log, or perturb the state or the parameters")]
    Stalled {
        /// Time at which the run stalled.
        t: f64,
        /// Consecutive transitions that did not advance time.
        transitions: u32,
        /// Label of the last guard that fired ([`RotorModel::guard_label`]).
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        last_guard: crate::StaticStr,
    },
    /// The run took more step attempts than [`SimOptions::max_steps`], all integrated phases
    /// together (a phase alone that needs more is the integrator's
    /// [`OdeError::TooManySteps`](crate::ode::OdeError::TooManySteps)).
    #[error("too many steps: {attempts} step attempts in the run (SimOptions::max_steps = {max_steps}); raise it or loosen the tolerances")]
    TooManySteps {
        /// Attempts made (accepted and rejected).
        attempts: u64,
        /// The bound.
        max_steps: u64,
    },
    /// The state became NaN or infinite.
    #[error("non-finite state")]
    NonFinite,
    /// A guard returned NaN where the event detector needed its sign (it cannot tell whether
    /// or where the guard crosses zero): the run stops rather than skip it. `source` is the
    /// model's reason ([`RotorModel::guard_error`]; for the ring's models the ring element's
    /// error, [`ModelError::Ring`]). The error's `t`, `y` are the start of the step where it
    /// happened.
    #[error("guard `{guard}` has no value at t = {t}: {source}")]
    Guard {
        /// Label of the guard ([`RotorModel::guard_label`]).
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        guard: crate::StaticStr,
        /// Time at which it returned NaN.
        t: f64,
        /// Why ([`RotorModel::guard_error`]).
        source: ModelError,
    },
    /// An option is invalid.
    #[error("invalid option `{field}` = {value}: {hint}")]
    InvalidOption {
        /// Field of [`SimOptions`] or [`OutputPlan`], or an argument with a documented rule of
        /// the function called (e.g. `record` of [`strobe_orbit`](crate::analysis::strobe_orbit),
        /// `dt` of [`phase_portrait`](crate::analysis::phase_portrait)).
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// Offending value.
        value: f64,
        /// What to do.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        hint: crate::StaticStr,
    },
    /// The observer asked the run to stop ([`HybridObserver::should_stop`]).
    #[error("stopped at the observer's request (HybridObserver::should_stop)")]
    Stopped,
    /// The initial state's length is not the model's dimension
    /// ([`RotorModel::dim`](crate::hybrid::RotorModel::dim); only possible with
    /// [`Dyn`](nalgebra::Dyn)): a condition of the call, not of an option.
    #[error("the initial state has {found} components but the model's dimension is {expected} (RotorModel::dim)")]
    DimensionMismatch {
        /// The model's dimension.
        expected: usize,
        /// The initial state's length.
        found: usize,
    },
}

/// A failed run: the error, where it happened, and the work done. Whatever the observer
/// recorded up to that point stays in the observer.
#[derive(Debug, Clone, PartialEq, Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
#[error("simulation failed at t = {t}: {kind}")]
pub struct SimError<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// What went wrong.
    pub kind: SimErrorKind,
    /// Last good time.
    pub t: f64,
    /// Last good state.
    pub y: OVector<f64, D>,
    /// Work done until then (boxed: it keeps the error small, clippy's `result_large_err`).
    pub stats: Box<SimStats>,
}

/// The model in one mode, as an [`OdeSystem`].
struct ModeSystem<'a, M: RotorModel>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    model: &'a M,
    mode: M::Mode,
    cache: &'a M::Cache,
}

impl<M: RotorModel> OdeSystem<M::Dim> for ModeSystem<'_, M>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    #[inline]
    fn rhs(&self, t: f64, y: &OVector<f64, M::Dim>, dy: &mut OVector<f64, M::Dim>) {
        self.model.rhs(self.mode, t, y, dy, self.cache);
    }

    fn jacobian(
        &self,
        t: f64,
        y: &OVector<f64, M::Dim>,
        jac: &mut JacobianMut<'_, M::Dim>,
    ) -> bool {
        self.model.jacobian(self.mode, t, y, jac, self.cache)
    }

    fn second_order(&self) -> Option<usize> {
        self.model.second_order()
    }

    fn linear_part(&self) -> Option<&crate::ode::DiagonalLinearPart> {
        self.model.linear_part()
    }

    fn diagonal_springs(&self) -> Option<crate::ode::DiagonalSprings<'_>> {
        self.model.diagonal_springs()
    }
}

impl<M: RotorModel> EventSet<M::Dim> for ModeSystem<'_, M>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    fn len(&self) -> usize {
        self.model.guard_count(self.mode)
    }
    fn direction(&self, i: usize) -> Direction {
        self.model.guard_direction(self.mode, i)
    }
    fn value(&self, i: usize, t: f64, y: &OVector<f64, M::Dim>) -> f64 {
        self.model.guard_value(self.mode, i, t, y, self.cache)
    }
    fn derivative(
        &self,
        i: usize,
        t: f64,
        y: &OVector<f64, M::Dim>,
        dy: &OVector<f64, M::Dim>,
    ) -> Option<f64> {
        self.model
            .guard_derivative(self.mode, i, t, y, dy, self.cache)
    }
    fn derivative_needs_rhs(&self) -> bool {
        self.model.guard_derivative_needs_rhs()
    }
    fn derivative_needs_rhs_of(&self, i: usize) -> bool {
        self.model.guard_derivative_needs_rhs_of(self.mode, i)
    }
    fn values_and_derivatives(
        &self,
        t: f64,
        y: &OVector<f64, M::Dim>,
        dy: &OVector<f64, M::Dim>,
        with_derivatives: bool,
        out: &mut dyn FnMut(usize, f64, Option<f64>),
    ) {
        self.model
            .guard_values(self.mode, t, y, dy, with_derivatives, self.cache, out);
    }
}

/// Pending outputs, in time order. Strobe times are the model's
/// ([`RotorModel::strobe_time`]), cached for the next index; or, for strobes at a phase in the
/// state ([`RotorModel::strobe_phase`]), infinite until a step reaches the next one's phase
/// and [`Schedule::locate_phase_strobe`] finds its time.
struct Schedule {
    strobe_at: f64,
    /// Strobes at a phase in the state, and the time of the last strobe (where the search for
    /// the next begins).
    by_phase: bool,
    strobe_floor: f64,
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
    fn new<M: RotorModel>(
        plan: &OutputPlan,
        model: &M,
        (t0, y0): (f64, &OVector<f64, M::Dim>),
    ) -> Self
    where
        DefaultAllocator: Allocator<M::Dim>,
    {
        let (first, last) = plan.strobe.map_or((1, 0), |r| (r.first, r.last));
        let (d0, dt) = plan
            .dense
            .map_or((f64::INFINITY, 1.0), |d| (d.t_start, d.dt));
        let by_phase = model.strobe_phase(first).is_some();
        let mut s = Self {
            strobe_at: if by_phase {
                f64::INFINITY
            } else {
                model.strobe_time(first)
            },
            by_phase,
            strobe_floor: t0,
            strobe_next: first,
            strobe_last: last,
            has_strobe: plan.strobe.is_some() && first <= last,
            dense_t0: d0,
            dense_dt: dt,
            dense_next: 0,
            has_dense: plan.dense.is_some(),
            t_end: plan.t_end,
        };
        // Skip outputs before the start (phase strobes: targets the start has passed).
        let passed = |s: &Self| match model.strobe_phase(s.strobe_next) {
            Some((i, target)) => target < y0[i],
            None => s.strobe_time() < t0,
        };
        while s.has_strobe && passed(&s) {
            s.advance_strobe(model);
        }
        while s.has_dense && s.dense_time() < t0 {
            s.advance_dense();
        }
        s
    }
    fn strobe_time(&self) -> f64 {
        self.strobe_at
    }
    fn dense_time(&self) -> f64 {
        self.dense_t0 + self.dense_dt * self.dense_next as f64
    }
    fn advance_strobe<M: RotorModel>(&mut self, model: &M)
    where
        DefaultAllocator: Allocator<M::Dim>,
    {
        self.strobe_next += 1;
        if self.strobe_next > self.strobe_last {
            self.has_strobe = false;
        } else if self.by_phase {
            // (Targets skipped at the start were never located: their time is infinite.)
            if self.strobe_at.is_finite() {
                self.strobe_floor = self.strobe_floor.max(self.strobe_at);
            }
            self.strobe_at = f64::INFINITY;
        } else {
            self.strobe_at = model.strobe_time(self.strobe_next);
        }
    }

    /// For strobes at a phase in the state: the time of the next one, if the state's phase
    /// `phase_at(t)` reaches its target by `b` (the end of the stretch being output, whose
    /// start is `a`), located by [`illinois`] to a few ulp. A no-op once it is located or
    /// for strobes at known times. `phase_at(t, i)` is the state's component `i` at `t`.
    /// `Err` carries a time where it gave NaN.
    fn locate_phase_strobe<M: RotorModel>(
        &mut self,
        model: &M,
        (a, b): (f64, f64),
        mut phase_at: impl FnMut(f64, usize) -> f64,
    ) -> Result<(), f64>
    where
        DefaultAllocator: Allocator<M::Dim>,
    {
        if !(self.by_phase && self.has_strobe && self.strobe_at == f64::INFINITY) {
            return Ok(());
        }
        let Some((i, target)) = model.strobe_phase(self.strobe_next) else {
            return Ok(());
        };
        let mut g = |t: f64| phase_at(t, i) - target;
        let gb = g(b);
        if gb.is_nan() {
            return Err(b);
        }
        if gb < 0.0 {
            return Ok(());
        }
        let a = a.max(self.strobe_floor).min(b);
        let ga = g(a);
        if ga.is_nan() {
            return Err(a);
        }
        if ga >= 0.0 {
            self.strobe_at = a;
            return Ok(());
        }
        let opts = RootOptions {
            tol: 4.0 * f64::EPSILON * a.abs().max(b.abs()),
            ..RootOptions::default()
        };
        let root = illinois((a, ga), (b, gb), &opts, g).map_err(|_| a)?;
        if let Some(t) = root.nan_at {
            return Err(t);
        }
        self.strobe_at = root.hi;
        Ok(())
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
    fn pop_due<M: RotorModel>(&mut self, t: f64, model: &M) -> Option<(f64, Due)>
    where
        DefaultAllocator: Allocator<M::Dim>,
    {
        let ts = self.next_strobe();
        let td = if self.has_dense {
            self.dense_time()
        } else {
            f64::INFINITY
        };
        if ts <= t && ts <= td {
            let k = self.strobe_next;
            self.advance_strobe(model);
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

/// Consecutive transitions without time advancing after which a run is
/// [`SimErrorKind::Stalled`]. Not lowered with the chattering bound: a single transition at
/// the start instant (a start on a boundary) is no evidence of a stall, and the chattering
/// error waits for the stall guard's verdict (`SimOptions::max_events_per_period`).
const STALL_TRANSITIONS: u32 = 64;

/// A transition advances time if it is more than this many units of roundoff of the time
/// scale after the previous one.
const STALL_ULPS: f64 = 8.0;

/// Counts consecutive transitions that do not advance time (beyond [`STALL_ULPS`] since the
/// previous transition, or the start).
struct StallGuard {
    last_t: f64,
    count: u32,
    bound: u32,
    period: f64,
}

impl StallGuard {
    fn record(&mut self, t: f64, guard: &'static str) -> Result<(), SimErrorKind> {
        let tol = STALL_ULPS * f64::EPSILON * t.abs().max(self.last_t.abs()).max(self.period);
        if t - self.last_t <= tol {
            self.count += 1;
        } else {
            self.count = 0;
        }
        self.last_t = t;
        if self.count >= self.bound {
            return Err(SimErrorKind::Stalled {
                t,
                transitions: self.count,
                last_guard: guard,
            });
        }
        Ok(())
    }
}

fn check_options(
    opts: &SimOptions,
    plan: &OutputPlan,
    t0: f64,
    period: f64,
) -> Result<(), SimErrorKind> {
    let bad = |field, value, hint| Err(SimErrorKind::InvalidOption { field, value, hint });
    if !(period.is_finite() && period > 0.0) {
        return bad(
            "RotorModel::forcing_period",
            period,
            "the model's forcing (or characteristic) period must be finite and > 0",
        );
    }
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
    let samples = opts.samples_per_step();
    if samples == 0 || samples > MAX_SAMPLES {
        return bad(
            "event_samples",
            samples as f64,
            "use 1..=ode::MAX_SAMPLES (64) interior samples per step, e.g. 4",
        );
    }
    if let Some(r) = plan.strobe
        && r.first > r.last
    {
        return bad(
            "strobe.first",
            r.first as f64,
            "the stroboscopic range is reversed: first must not exceed last",
        );
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

/// Work vectors of a run, allocated once when it starts.
struct Scratch<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Derivative of the current state (exact modes) or of an output.
    dy: OVector<f64, D>,
    /// An output state (projected copy).
    yo: OVector<f64, D>,
    out: Outputs<D>,
    event: EventRecord<D>,
}

/// The records handed to the observer, reused.
struct Outputs<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    strobe: StrobePoint<D>,
    sample: Sample<D>,
}

impl<D: Dim> Scratch<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn new(dim: D) -> Self {
        let z = || OVector::zeros_generic(dim, U1);
        Self {
            dy: z(),
            yo: z(),
            out: Outputs {
                strobe: StrobePoint {
                    k: 0,
                    t: 0.0,
                    y: z(),
                    label: 0,
                },
                sample: Sample {
                    t: 0.0,
                    y: z(),
                    dy: z(),
                    label: 0,
                },
            },
            event: EventRecord {
                t: 0.0,
                kind: "",
                before: z(),
                after: z(),
                from: 0,
                to: 0,
            },
        }
    }
}

impl<D: Dim> Outputs<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Passes the output `due` at `(t, y, dy)` to the observer.
    fn emit<O: HybridObserver<D>>(
        &mut self,
        obs: &mut O,
        due: Due,
        t: f64,
        y: &OVector<f64, D>,
        dy: &OVector<f64, D>,
        label: u8,
    ) {
        match due {
            Due::Strobe(k) => {
                let p = &mut self.strobe;
                (p.k, p.t, p.label) = (k, t, label);
                p.y.copy_from(y);
                obs.on_strobe(p);
            }
            Due::Dense => {
                let s = &mut self.sample;
                (s.t, s.label) = (t, label);
                s.y.copy_from(y);
                s.dy.copy_from(dy);
                obs.on_sample(s);
            }
        }
    }
}

/// Runs `model` from `(t0, y0)` to `plan.t_end`, reporting outputs to `obs`.
///
/// See [`RotorModel`] for what the driver does with the model (initial projection,
/// transitions, outputs). Outputs (stroboscopic points, dense samples, the event log) never
/// change the trajectory: the steps go towards the next event or `plan.t_end` whatever is
/// asked for, and outputs in integrated modes are read from the dense output of the step that
/// contains them (DOP853: 7th order; DOPRI5: 4th order; RK4: the cubic Hermite interpolant of
/// the step's ends, 3rd order, local error $O(h^4)$, so a strobe point of an RK4 run is as
/// accurate as the run, $O(h^4)$, not exact to its step); in exact modes they are the closed
/// form. A run with outputs gives bitwise the same steps, events and final state as one
/// without. All work vectors are allocated when the run starts: stepping allocates nothing,
/// whatever the dimension.
///
/// # Errors
/// [`SimError`] with the last good `(t, y)`; the observer keeps what was recorded. A `y0` of
/// the wrong length (for `Dyn`) is [`SimErrorKind::InvalidOption`].
pub fn simulate<M, O>(
    model: &M,
    t0: f64,
    y0: &OVector<f64, M::Dim>,
    plan: &OutputPlan,
    opts: &SimOptions,
    obs: &mut O,
) -> Result<SimStats, SimError<M::Dim>>
where
    M: RotorModel,
    O: HybridObserver<M::Dim>,
    DefaultAllocator: Allocator<M::Dim>,
{
    check_start(model, t0, y0, plan, opts)?;
    // Outputs use their own scratch so that asking for them never changes the trajectory
    // (warm starts and the like would otherwise differ at the rounding level).
    let (trajectory, outputs) = (model.new_cache(), model.new_cache());
    let caches = Caches {
        trajectory: &trajectory,
        outputs: &outputs,
    };
    let mut run = Run::new(model, (t0, y0), plan, opts, obs, caches)?;
    loop {
        let found = match model.flow(run.mode) {
            Flow::Exact => run.exact_phase()?,
            Flow::Integrated => run.integrated_phase()?,
        };
        let Some((guard, t_event)) = found else {
            break;
        };
        if run.transition(guard, t_event)? {
            break;
        }
    }
    match run.chattering {
        Some(e) => Err(e),
        None => Ok(run.stats),
    }
}

/// A run's error at `(t, y)`, with the work done so far.
fn fail<D: Dim>(kind: SimErrorKind, t: f64, y: &OVector<f64, D>, stats: SimStats) -> SimError<D>
where
    DefaultAllocator: Allocator<D>,
{
    SimError {
        kind,
        t,
        y: y.clone(),
        stats: Box::new(stats),
    }
}

/// Checks a run's options, output plan and start before anything is built: the options
/// ([`check_options`]), `y0`'s length (the model's dimension) and that the start is finite.
fn check_start<M: RotorModel>(
    model: &M,
    t0: f64,
    y0: &OVector<f64, M::Dim>,
    plan: &OutputPlan,
    opts: &SimOptions,
) -> Result<(), SimError<M::Dim>>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    let stats = SimStats::default();
    if let Err(k) = check_options(opts, plan, t0, model.forcing_period()) {
        return Err(fail(k, t0, y0, stats));
    }
    if y0.len() != model.dim().value() {
        let kind = SimErrorKind::DimensionMismatch {
            expected: model.dim().value(),
            found: y0.len(),
        };
        return Err(fail(kind, t0, y0, stats));
    }
    if !(t0.is_finite() && y0.iter().all(|v| v.is_finite())) {
        return Err(fail(SimErrorKind::NonFinite, t0, y0, stats));
    }
    Ok(())
}

/// The model's two per-run caches: one for the trajectory (stepping, guards, transitions),
/// one for outputs, so that asking for outputs never changes the trajectory.
struct Caches<'a, C> {
    trajectory: &'a C,
    outputs: &'a C,
}

impl<C> Clone for Caches<'_, C> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<C> Copy for Caches<'_, C> {}

/// A run in progress: the model, what it reports to, and the state of the hybrid driver
/// (mode, time, state, integrator, detector, output schedule, transition counters, work).
struct Run<'a, M: RotorModel, O>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    model: &'a M,
    plan: &'a OutputPlan,
    obs: &'a mut O,
    caches: Caches<'a, M::Cache>,
    /// RK4: each step's resolution is checked ([`SimStats::unresolved_steps`]).
    fixed_step: bool,
    /// Step attempts allowed in the run ([`SimOptions::max_steps`]).
    max_steps: u64,
    ev_opts: EventOptions,
    integ: AnyIntegrator<M::Dim>,
    ev_state: EventState<M::Dim>,
    w: Scratch<M::Dim>,
    sched: Schedule,
    chatter: ChatterGuard,
    stall: StallGuard,
    stats: SimStats,
    mode: M::Mode,
    t: f64,
    y: OVector<f64, M::Dim>,
    /// Whether the integrator keeps its step size across the next reset (after a transition).
    keep_step: bool,
    /// A chattering error waiting for time to advance (see [`Run::transition`]).
    chattering: Option<SimError<M::Dim>>,
}

impl<'a, M, O> Run<'a, M, O>
where
    M: RotorModel,
    O: HybridObserver<M::Dim>,
    DefaultAllocator: Allocator<M::Dim>,
{
    /// Builds a run from the checked start `(t0, y0)`: the initial mode, the integrator, the
    /// work vectors (all allocated now), the output schedule, and the start projected onto
    /// its mode.
    fn new(
        model: &'a M,
        (t0, y0): (f64, &OVector<f64, M::Dim>),
        plan: &'a OutputPlan,
        opts: &SimOptions,
        obs: &'a mut O,
        caches: Caches<'a, M::Cache>,
    ) -> Result<Self, SimError<M::Dim>> {
        let stats = SimStats::default();
        let period = model.forcing_period();
        let dim = model.dim();
        let mode = model
            .initial_mode(t0, y0)
            .map_err(|e| fail(e.into(), t0, y0, stats))?;
        let integ = build_integrator(model, opts, period).map_err(|e| fail(e, t0, y0, stats))?;
        let mut run = Run {
            model,
            plan,
            obs,
            caches,
            fixed_step: opts.method == Method::Rk4,
            max_steps: opts.max_steps,
            ev_opts: EventOptions::default().with_samples_per_step(opts.samples_per_step()),
            integ,
            ev_state: EventState::with_dim(dim),
            w: Scratch::new(dim),
            sched: Schedule::new(plan, model, (t0, y0)),
            chatter: ChatterGuard {
                window_start: t0,
                count: 0,
                bound: opts.max_events_per_period,
                period,
            },
            stall: StallGuard {
                last_t: t0,
                count: 0,
                bound: STALL_TRANSITIONS,
                period,
            },
            stats,
            mode,
            t: t0,
            y: y0.clone(),
            keep_step: false,
            chattering: None,
        };
        model.project(mode, t0, &mut run.y, caches.trajectory);
        Ok(run)
    }

    /// The model in the current mode, as the integrator's system and the detector's event set.
    fn system(&self) -> ModeSystem<'a, M> {
        ModeSystem {
            model: self.model,
            mode: self.mode,
            cache: self.caches.trajectory,
        }
    }

    /// The integrator's error at the end of its last step (`at_end`) or at its start (the
    /// last good point), with the work done so far.
    fn fail_on_step(&mut self, kind: SimErrorKind, at_end: bool) -> SimError<M::Dim> {
        collect(&mut self.stats, &self.integ);
        if at_end {
            fail(kind, self.integ.t(), self.integ.y(), self.stats)
        } else {
            fail(kind, self.integ.t_prev(), self.integ.y_prev(), self.stats)
        }
    }

    /// A mode with a closed form: from `t` to its first guard crossing, with the outputs due
    /// before it. `Some((guard, t))` with `y` at the crossing, or `None` at `plan.t_end`
    /// (`y` there).
    fn exact_phase(&mut self) -> Result<Option<(usize, f64)>, SimError<M::Dim>> {
        let (model, t_end) = (self.model, self.plan.t_end);
        let mut seg = model.start_segment(self.mode, self.t, &self.y);
        let label = model.mode_label(self.mode);
        let found = loop {
            let target = self.sched.next_time().min(t_end);
            let hit = seg.next_guard(self.t, target);
            let t_stop = hit.map_or(target, |h| h.t);
            loop {
                let (t, w) = (self.t, &mut self.w);
                let located = self.sched.locate_phase_strobe(model, (t, t_stop), |to, i| {
                    seg.eval(to, &mut w.yo, &mut w.dy);
                    w.yo[i]
                });
                if located.is_err() {
                    // The closed form is not finite inside the stretch: the last good state
                    // is its start.
                    seg.eval(self.t, &mut self.y, &mut self.w.dy);
                    self.stats.exact_evals += seg.evaluations();
                    return Err(fail(SimErrorKind::NonFinite, self.t, &self.y, self.stats));
                }
                let Some((to, due)) = self.sched.pop_due(t_stop, model) else {
                    break;
                };
                seg.eval(to, &mut self.y, &mut self.w.dy);
                self.w
                    .out
                    .emit(self.obs, due, to, &self.y, &self.w.dy, label);
            }
            if let Some(GuardCrossing { guard, t: tg }) = hit {
                seg.eval(tg, &mut self.y, &mut self.w.dy);
                if !self.y.iter().all(|v| v.is_finite()) {
                    return Err(fail(SimErrorKind::NonFinite, self.t, &self.y, self.stats));
                }
                break Some((guard, tg));
            }
            self.t = target;
            if self.t >= t_end {
                break None;
            }
            if self.obs.should_stop() {
                self.stats.exact_evals += seg.evaluations();
                seg.eval(self.t, &mut self.y, &mut self.w.dy);
                return Err(fail(SimErrorKind::Stopped, self.t, &self.y, self.stats));
            }
        };
        self.stats.exact_evals += seg.evaluations();
        if found.is_none() {
            seg.eval(self.t, &mut self.y, &mut self.w.dy);
        }
        Ok(found)
    }

    /// An integrated mode: steps from `t` (the step size kept across a transition), each
    /// step scanned for the first guard crossing, the outputs due before it read from the
    /// step's dense output. `Some((guard, t))` with `y` at the crossing, or `None` at
    /// `plan.t_end` (`y` there, projected).
    fn integrated_phase(&mut self) -> Result<Option<(usize, f64)>, SimError<M::Dim>> {
        let sys = self.system();
        self.integ
            .reset(&sys, self.t, &self.y, self.keep_step)
            .map_err(|e| fail(e.into(), self.t, &self.y, self.stats))?;
        self.ev_state.reset();
        let label = self.model.mode_label(self.mode);
        loop {
            self.step(&sys)?;
            let hit = self.detect(&sys)?;
            self.emit_outputs(&sys, hit.map_or(self.integ.t(), |h| h.1), label)?;
            if let Some(h) = hit {
                self.y.copy_from(&self.ev_state.hit().y);
                if !self.y.iter().all(|v| v.is_finite()) {
                    // As for outputs: the event was located on a dense output that is not
                    // finite.
                    return Err(self.fail_on_step(SimErrorKind::NonFinite, false));
                }
                collect(&mut self.stats, &self.integ);
                return Ok(Some(h));
            }
            if self.obs.should_stop() {
                return Err(self.fail_on_step(SimErrorKind::Stopped, true));
            }
            self.t = self.integ.t();
            self.y.copy_from(self.integ.y());
            if self.t >= self.plan.t_end {
                collect(&mut self.stats, &self.integ);
                let cache = self.caches.trajectory;
                self.model.project(self.mode, self.t, &mut self.y, cache);
                return Ok(None);
            }
        }
    }

    /// One accepted step (outputs never bound a step: they come from the dense output); RK4
    /// steps are checked against the model's fastest rate.
    fn step(&mut self, sys: &ModeSystem<'a, M>) -> Result<(), SimError<M::Dim>> {
        let done = self.integ.stats();
        let attempts = done.steps + done.rejected;
        if attempts >= self.max_steps {
            // The run's budget: the integrator's own bound counts one phase only.
            let max_steps = self.max_steps;
            let kind = SimErrorKind::TooManySteps {
                attempts,
                max_steps,
            };
            return Err(self.fail_on_step(kind, true));
        }
        if let Err(e) = self.integ.step(sys, self.plan.t_end) {
            return Err(self.fail_on_step(e.into(), true));
        }
        if self.fixed_step {
            let h = self.integ.t() - self.integ.t_prev();
            let rate = self
                .model
                .max_rate(self.mode, self.integ.t_prev(), self.integ.y_prev());
            self.stats.unresolved_steps += u64::from(rate.is_some_and(|l| h * l > 1.0));
        }
        if !self.integ.y().iter().all(|v| v.is_finite()) {
            return Err(self.fail_on_step(SimErrorKind::NonFinite, false));
        }
        Ok(())
    }

    /// The first guard crossing on the last step, `(guard, t)`. A guard without a value is
    /// the model's typed error for it ([`RotorModel::guard_error`]), at the step's start
    /// (where every guard had one).
    fn detect(
        &mut self,
        sys: &ModeSystem<'a, M>,
    ) -> Result<Option<(usize, f64)>, SimError<M::Dim>> {
        match find_first_event(&mut self.integ, sys, sys, &self.ev_opts, &mut self.ev_state) {
            Ok(hit) => Ok(hit.map(|h| (h.index, h.t))),
            Err(OdeError::EventNotANumber { index, t: t_nan }) => {
                collect(&mut self.stats, &self.integ);
                self.integ.dense(sys, t_nan, &mut self.w.yo);
                let kind = if self.w.yo.iter().all(|v| v.is_finite()) {
                    let (model, mode) = (self.model, self.mode);
                    SimErrorKind::Guard {
                        guard: model.guard_label(mode, index),
                        t: t_nan,
                        // The detector's cache (a warm start may matter).
                        source: model.guard_error(mode, index, t_nan, &self.w.yo, sys.cache),
                    }
                } else {
                    // The dense output itself is not finite there.
                    SimErrorKind::NonFinite
                };
                Err(self.fail_on_step(kind, false))
            }
            Err(e) => Err(self.fail_on_step(e.into(), true)),
        }
    }

    /// The outputs due up to `t_stop` on the last step, from its dense output (projected,
    /// with their own cache; dense samples with their derivative).
    fn emit_outputs(
        &mut self,
        sys: &ModeSystem<'a, M>,
        t_stop: f64,
        label: u8,
    ) -> Result<(), SimError<M::Dim>> {
        let (model, mode, cache) = (self.model, self.mode, self.caches.outputs);
        loop {
            let (integ, yo) = (&mut self.integ, &mut self.w.yo);
            let span = (integ.t_prev(), t_stop);
            let located = self.sched.locate_phase_strobe(model, span, |to, i| {
                // The step's ends as they are (a start on a target is a strobe there).
                if to == integ.t() {
                    integ.y()[i]
                } else if to == integ.t_prev() {
                    integ.y_prev()[i]
                } else {
                    integ.dense(sys, to, yo);
                    yo[i]
                }
            });
            if located.is_err() {
                return Err(self.fail_on_step(SimErrorKind::NonFinite, false));
            }
            let Some((to, due)) = self.sched.pop_due(t_stop, model) else {
                break;
            };
            if to == self.integ.t() {
                self.w.yo.copy_from(self.integ.y());
            } else {
                self.integ.dense(sys, to, &mut self.w.yo);
            }
            if !self.w.yo.iter().all(|v| v.is_finite()) {
                // The dense output inside an accepted step can overflow where the step's
                // ends did not (DOP853's extra stages): the last good state is the step's
                // start.
                return Err(self.fail_on_step(SimErrorKind::NonFinite, false));
            }
            model.project(mode, to, &mut self.w.yo, cache);
            // Only dense samples carry the derivative.
            if matches!(due, Due::Dense) {
                model.rhs(mode, to, &self.w.yo, &mut self.w.dy, cache);
            }
            self.w
                .out
                .emit(self.obs, due, to, &self.w.yo, &self.w.dy, label);
        }
        Ok(())
    }

    /// The transition of `guard` at `t_event` (from `y` there, projected), counted against
    /// the stall and chattering guards and reported to the observer. Returns whether the
    /// run has reached `plan.t_end`.
    ///
    /// Stalling is checked first: the chattering error's advice holds only when time
    /// advances. Chattering is reported once time is seen to advance past the transition
    /// that exceeded the bound (or at the end of the run): while transitions pile up at one
    /// instant the stall guard decides, so that raising the bound always lets the run go
    /// further in time.
    fn transition(&mut self, guard: usize, t_event: f64) -> Result<bool, SimError<M::Dim>> {
        let (model, mode, t) = (self.model, self.mode, t_event);
        self.t = t;
        model.project(mode, t, &mut self.y, self.caches.trajectory);
        self.w.event.before.copy_from(&self.y);
        let from = model.mode_label(mode);
        let kind = model.guard_label(mode, guard);
        let next = match model.transition(mode, guard, t, &mut self.y) {
            Ok(next) => next,
            Err(e) => return Err(fail(e.into(), t, &self.w.event.before, self.stats)),
        };
        self.stats.transitions += 1;
        if let Err(k) = self.stall.record(t, kind) {
            return Err(fail(k, t, &self.y, self.stats));
        }
        if self.stall.count == 0
            && let Some(e) = self.chattering.take()
        {
            return Err(e);
        }
        if let Err(k) = self.chatter.record(t)
            && self.chattering.is_none()
        {
            self.chattering = Some(fail(k, t, &self.y, self.stats));
        }
        if self.plan.events {
            let e = &mut self.w.event;
            (e.t, e.kind, e.from, e.to) = (t, kind, from, model.mode_label(next));
            e.after.copy_from(&self.y);
            self.obs.on_event(e);
        }
        self.keep_step = true;
        self.mode = next;
        Ok(t >= self.plan.t_end)
    }
}

fn collect<D: Dim>(stats: &mut SimStats, integ: &AnyIntegrator<D>)
where
    DefaultAllocator: Allocator<D>,
{
    let s = integ.stats();
    stats.steps = s.steps;
    stats.rejected = s.rejected;
    stats.rhs_evals = s.rhs_evals;
    stats.jacobians = s.jacobians;
    stats.lu_decompositions = s.lu_decompositions;
    stats.woodbury_decompositions = s.woodbury_decompositions;
}

/// The integrator of a run: the model's dimension, its algebraic components out of the error
/// control (`atol = inf`).
fn build_integrator<M: RotorModel>(
    model: &M,
    opts: &SimOptions,
    period: f64,
) -> Result<AnyIntegrator<M::Dim>, SimErrorKind>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    let dim = model.dim();
    let any_algebraic = (0..dim.value()).any(|i| model.is_algebraic(i));
    // The model's error weights for an implicit method only: an explicit one at its
    // stability limit keeps its fast components stable through their error test, which the
    // looser weights would weaken (`RotorModel::error_scale`).
    let scale = opts
        .method
        .is_implicit()
        .then(|| model.error_scale())
        .flatten()
        .unwrap_or_else(|| model.state_scale());
    // A scalar tolerance when nothing is algebraic or scaled keeps the arithmetic of a plain
    // run (and `atol * 1.0` is `atol`).
    let atol = if any_algebraic || scale.iter().any(|&s| s != 1.0) {
        Tolerance::PerComponent(OVector::from_fn_generic(dim, U1, |i, _| {
            if model.is_algebraic(i) {
                f64::INFINITY
            } else {
                opts.atol * scale[i]
            }
        }))
    } else {
        Tolerance::Scalar(opts.atol)
    };
    let mut o = Options::<M::Dim>::default()
        .with_rtol(opts.rtol)
        .with_atol(atol)
        .with_h_max(opts.max_step_fraction * period)
        .with_max_steps(opts.max_steps);
    if opts.method == Method::Rk4 {
        o = o.with_fixed_step(period / f64::from(opts.steps_per_period));
    }
    Ok(AnyIntegrator::with_dim(opts.method, dim, o)?)
}
