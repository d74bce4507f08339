//! Generic explicit Runge–Kutta integrators with error control, dense output
//! and event detection.
//!
//! This layer knows nothing about rotors. It provides
//!
//! * [`Dop853`] — Dormand–Prince 8(5,3) with Hairer's 7th-order dense output,
//! * [`Dopri5`] — Dormand–Prince 5(4) with Shampine's 4th-order dense output,
//! * [`Rk4`] — the classical fixed-step 4th-order method with cubic Hermite
//!   dense output,
//! * [`AnyIntegrator`] — enum dispatch over the three, selected at run time by
//!   [`Method`],
//! * [`events`] — event functions $g_i(t, y)$, detection on the dense output
//!   (including grazing pairs of roots) and an Illinois root finder,
//! * [`solve`](solve::solve) — a convenience driver with outputs and events.
//!
//! All state lives in fixed-size [`SVector<f64, N>`] values; the stepping loop
//! never allocates. Integration runs forward in time only
//! ($t_{\text{bound}} \ge t$).
//!
//! # Step-size control
//!
//! For a trial step $y_0 \to y_1$ with local error estimate $e$ the scaled
//! error is the RMS norm
//! $$\mathrm{err} = \sqrt{\tfrac1N \sum_i \big(e_i / s_i\big)^2},\qquad
//! s_i = \mathrm{atol}_i + \mathrm{rtol}_i \max(|y_{0,i}|, |y_{1,i}|),$$
//! (DOP853 uses Hairer's combination of its 5th- and 3rd-order estimates). The
//! step is accepted when $\mathrm{err} \le 1$ and the next step is
//! $h_{\text{new}} = h \cdot \mathrm{clamp}\big(\mathrm{safety}\,
//! \mathrm{err}^{-\alpha}\,\mathrm{err}_{\text{old}}^{\beta},\ \mathrm{fac\_min},
//! \ \mathrm{fac\_max}\big)$ (Gustafsson's PI controller as in Hairer's codes;
//! see `docs/integrators.md`).

use nalgebra::SVector;
use thiserror::Error;

mod controller;
mod core;
pub mod dop853;
pub mod dopri5;
pub mod events;
pub mod rk4;
pub mod solve;

pub use dop853::Dop853;
pub use dopri5::Dopri5;
pub use events::{
    find_first_event, Direction, EventHit, EventOptions, EventSet, EventState, NoEvents,
    MAX_EVENTS,
};
pub use rk4::Rk4;
pub use solve::{solve, solve_with, Observer, Recorder, SolveError, SolveReport, Stopped};

/// A first-order ODE system $\dot y = f(t, y)$ with $y \in \mathbb{R}^N$.
///
/// Closures `Fn(f64, &SVector<f64, N>, &mut SVector<f64, N>)` implement this
/// trait, so `|t, y, dy| { dy[0] = y[1]; dy[1] = -y[0]; }` is a system.
pub trait OdeSystem<const N: usize> {
    /// Writes $f(t, y)$ into `dy` (every component must be written).
    fn rhs(&self, t: f64, y: &SVector<f64, N>, dy: &mut SVector<f64, N>);
}

impl<const N: usize, F> OdeSystem<N> for F
where
    F: Fn(f64, &SVector<f64, N>, &mut SVector<f64, N>),
{
    #[inline]
    fn rhs(&self, t: f64, y: &SVector<f64, N>, dy: &mut SVector<f64, N>) {
        self(t, y, dy)
    }
}

/// A tolerance, either the same for every component or one value per
/// component (dimensionless for `rtol`, units of $y_i$ for `atol`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Tolerance<const N: usize> {
    /// The same value for every component.
    Scalar(f64),
    /// One value per component.
    PerComponent(SVector<f64, N>),
}

impl<const N: usize> Tolerance<N> {
    /// The tolerance of component `i` (`i < N`; out-of-range indices return
    /// the largest component value for `PerComponent`, never panic).
    #[inline]
    pub fn get(&self, i: usize) -> f64 {
        match self {
            Tolerance::Scalar(v) => *v,
            Tolerance::PerComponent(v) => {
                if i < N {
                    v[i]
                } else {
                    v.max()
                }
            }
        }
    }

    /// The tolerance as a vector.
    pub fn to_vector(&self) -> SVector<f64, N> {
        match self {
            Tolerance::Scalar(v) => SVector::from_element(*v),
            Tolerance::PerComponent(v) => *v,
        }
    }

    /// Checks that every value is finite and non-negative; the error names
    /// `field`.
    pub fn validate(&self, field: &'static str) -> Result<(), OdeError> {
        for i in 0..N {
            let v = self.get(i);
            if !(v.is_finite() && v >= 0.0) {
                return Err(OdeError::InvalidOption {
                    field,
                    value: v,
                    hint: "tolerances must be finite and >= 0 (typical: rtol 1e-9, atol 1e-12)",
                });
            }
        }
        Ok(())
    }
}

impl<const N: usize> From<f64> for Tolerance<N> {
    fn from(v: f64) -> Self {
        Tolerance::Scalar(v)
    }
}

/// Integrator options. A plain struct: build it with struct-update syntax,
/// e.g. `Options { rtol: 1e-10.into(), ..Options::default() }`.
///
/// Times and step sizes are in the time unit of the system.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options<const N: usize> {
    /// Relative tolerance (dimensionless). Default `1e-9`.
    pub rtol: Tolerance<N>,
    /// Absolute tolerance (units of $y_i$). Default `1e-12`.
    /// For every component `rtol + atol > 0` is required.
    pub atol: Tolerance<N>,
    /// Initial step size (> 0). `None` (default) = Hairer's automatic
    /// initial step selection.
    pub h_init: Option<f64>,
    /// Largest step size (> 0). Default `+inf`.
    pub h_max: f64,
    /// Step-size underflow threshold (>= 0): when the controller wants a
    /// step smaller than `h_min` (or smaller than $10\,\varepsilon\,|t|$) the
    /// integrator returns [`OdeError::StepSizeUnderflow`]. Default `0`.
    pub h_min: f64,
    /// Maximum number of step attempts (accepted + rejected) between two
    /// calls of [`Integrator::reset`] (so per call of [`solve`]).
    /// Default `1_000_000`.
    pub max_steps: u64,
    /// Safety factor of the step-size controller, in (0, 1]. Default `0.9`.
    pub safety: f64,
    /// Smallest step-size ratio $h_{\text{new}}/h$, in (0, 1]. Default `0.2`.
    pub fac_min: f64,
    /// Largest step-size ratio $h_{\text{new}}/h$, >= 1. Default `10`.
    pub fac_max: f64,
    /// PI-controller exponent $\beta$ on the previous error, in [0, 0.2].
    /// `None` (default) = the method's default: `0.04` (DOPRI5 and DOP853;
    /// Hairer's `dop853.f` uses 0 — set `Some(0.0)` to reproduce it).
    pub beta: Option<f64>,
    /// Fixed step size (> 0). Required by [`Rk4`]. For [`Dopri5`] and
    /// [`Dop853`] `Some(h)` switches error control off and takes steps of
    /// exactly `h` (the last one before a bound is shortened to land on it);
    /// this is meant for convergence studies and reproducing fixed grids.
    /// Default `None`.
    pub fixed_step: Option<f64>,
}

impl<const N: usize> Default for Options<N> {
    fn default() -> Self {
        Options {
            rtol: Tolerance::Scalar(1e-9),
            atol: Tolerance::Scalar(1e-12),
            h_init: None,
            h_max: f64::INFINITY,
            h_min: 0.0,
            max_steps: 1_000_000,
            safety: 0.9,
            fac_min: 0.2,
            fac_max: 10.0,
            beta: None,
            fixed_step: None,
        }
    }
}

impl<const N: usize> Options<N> {
    /// Options with the given scalar tolerances and defaults otherwise.
    pub fn with_tol(rtol: f64, atol: f64) -> Self {
        Options {
            rtol: Tolerance::Scalar(rtol),
            atol: Tolerance::Scalar(atol),
            ..Options::default()
        }
    }

    /// Options for fixed steps of size `h` (see [`Options::fixed_step`]).
    pub fn fixed(h: f64) -> Self {
        Options {
            fixed_step: Some(h),
            ..Options::default()
        }
    }

    /// Checks every field; the error names the first offending field.
    pub fn validate(&self) -> Result<(), OdeError> {
        self.rtol.validate("rtol")?;
        self.atol.validate("atol")?;
        for i in 0..N {
            if self.rtol.get(i) + self.atol.get(i) <= 0.0 {
                return Err(OdeError::InvalidOption {
                    field: "atol",
                    value: self.atol.get(i),
                    hint: "rtol and atol are both zero for a component; make atol > 0",
                });
            }
        }
        fn bad(field: &'static str, value: f64, hint: &'static str) -> Result<(), OdeError> {
            Err(OdeError::InvalidOption { field, value, hint })
        }
        if let Some(h) = self.h_init {
            if !(h.is_finite() && h > 0.0) {
                return bad("h_init", h, "use a finite h_init > 0, or None for automatic");
            }
        }
        if !(self.h_max > 0.0) {
            return bad("h_max", self.h_max, "h_max must be > 0 (f64::INFINITY = no limit)");
        }
        if !(self.h_min.is_finite() && self.h_min >= 0.0 && self.h_min <= self.h_max) {
            return bad("h_min", self.h_min, "h_min must be finite, >= 0 and <= h_max");
        }
        if self.max_steps == 0 {
            return bad("max_steps", 0.0, "max_steps must be >= 1");
        }
        if !(self.safety > 0.0 && self.safety <= 1.0) {
            return bad("safety", self.safety, "safety must be in (0, 1]; typical 0.9");
        }
        if !(self.fac_min > 0.0 && self.fac_min <= 1.0) {
            return bad("fac_min", self.fac_min, "fac_min must be in (0, 1]; typical 0.2");
        }
        if !(self.fac_max >= 1.0 && self.fac_max.is_finite()) {
            return bad("fac_max", self.fac_max, "fac_max must be finite and >= 1; typical 10");
        }
        if let Some(b) = self.beta {
            if !(0.0..=0.2).contains(&b) {
                return bad("beta", b, "beta must be in [0, 0.2]; typical 0.04");
            }
        }
        if let Some(h) = self.fixed_step {
            if !(h.is_finite() && h > 0.0) {
                return bad("fixed_step", h, "fixed_step must be finite and > 0");
            }
        }
        Ok(())
    }
}

/// Work counters of an integrator (since construction).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected step attempts (error too large or non-finite values).
    pub rejected: u64,
    /// Evaluations of the right-hand side $f$ (including dense-output stages,
    /// truncations, resets and evaluations made by the event detector).
    pub rhs_evals: u64,
    /// Events reported by [`find_first_event`].
    pub events: u64,
}

/// Errors of the ODE layer. Every variant says where it happened and what to
/// try.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[non_exhaustive]
pub enum OdeError {
    /// An option is invalid.
    #[error("invalid option `{field}` = {value}: {hint}")]
    InvalidOption {
        /// Name of the field of [`Options`] (or [`EventOptions`]).
        field: &'static str,
        /// The offending value (`NaN` when the value is missing).
        value: f64,
        /// What to do instead.
        hint: &'static str,
    },
    /// The initial time or state given to [`Integrator::reset`] is not finite.
    #[error("non-finite initial value at t = {t}: component {component} = {value}; pass a finite time and state")]
    NonFiniteInitial {
        /// Initial time.
        t: f64,
        /// Offending component (`usize::MAX` for the time itself).
        component: usize,
        /// Offending value.
        value: f64,
    },
    /// The right-hand side produced non-finite values and reducing the step
    /// size did not help (or they occurred at an accepted point).
    #[error("right-hand side returned NaN/inf at t = {t} (step size h = {h}); check the model's domain, or stop before it with an event")]
    NonFiniteRhs {
        /// Last accepted time.
        t: f64,
        /// Step size of the failing attempt.
        h: f64,
    },
    /// The controller wants a step smaller than `h_min` or than the
    /// resolution of `t` (stiffness, a singularity or a discontinuity).
    #[error("step size underflow at t = {t}: h = {h} < h_min = {h_min}; the solution may blow up or be non-smooth here (locate the discontinuity with an event) or the tolerances are too tight")]
    StepSizeUnderflow {
        /// Last accepted time.
        t: f64,
        /// The rejected step size.
        h: f64,
        /// Effective minimum step (max of `h_min` and $10\varepsilon|t|$).
        h_min: f64,
    },
    /// More than `max_steps` attempts since the last reset.
    #[error("too many steps: {max_steps} attempts since the last reset, reached t = {t} with h = {h}; raise Options::max_steps or loosen the tolerances")]
    TooManySteps {
        /// Last accepted time.
        t: f64,
        /// Current step size.
        h: f64,
        /// The limit.
        max_steps: u64,
    },
    /// `step` or `truncate` was called before `reset`.
    #[error("integrator not initialised: call Integrator::reset(sys, t0, y0, false) first")]
    NotInitialized,
    /// The bound passed to `step` is not finite or lies behind the current
    /// time (integration is forward only).
    #[error("invalid bound t_bound = {t_bound} at t = {t}: the bound must be finite and >= t (forward integration only)")]
    InvalidBound {
        /// Current time.
        t: f64,
        /// The bound.
        t_bound: f64,
    },
    /// `truncate` was given a time outside `(t_prev, t]`.
    #[error("truncate at t_new = {t_new} outside the last step ({t_prev}, {t}]; truncate only inside the last accepted step")]
    TruncateOutOfRange {
        /// Requested time.
        t_new: f64,
        /// Left end of the last step.
        t_prev: f64,
        /// Right end of the last step.
        t: f64,
    },
    /// An event set has more events than [`MAX_EVENTS`].
    #[error("event set has {len} events, more than MAX_EVENTS = {max}; split the set or switch events off")]
    TooManyEvents {
        /// Number of events of the set.
        len: usize,
        /// The limit.
        max: usize,
    },
}

/// An explicit one-step integrator with dense output.
///
/// Typical use: `reset` once, then `step` repeatedly towards a bound; after
/// each step, `dense` interpolates on $[t_{\text{prev}}, t]$ and
/// [`find_first_event`] looks for events; `truncate` moves the current point
/// back to an event inside the step.
pub trait Integrator<const N: usize> {
    /// Start (or restart after a discontinuity/reset) at `(t, y)`: evaluates
    /// $f(t, y)$, clears the last step (dense output becomes the constant
    /// `y`) and the per-reset attempt counter. Keeps the last step-size
    /// suggestion if `keep_step` is true and one exists (useful after
    /// events), otherwise selects an initial step (`h_init` or Hairer's
    /// automatic choice).
    fn reset<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &SVector<f64, N>,
        keep_step: bool,
    ) -> Result<(), OdeError>;
    /// Take one accepted step (internally retrying rejected ones), never
    /// beyond `t_bound`; the step lands exactly on `t_bound` if it reaches
    /// it (a step that would end within 1% of a step beyond the bound is
    /// stretched to it). `t_bound == t()` is a no-op.
    fn step<S: OdeSystem<N>>(&mut self, sys: &S, t_bound: f64) -> Result<(), OdeError>;
    /// Current time (right end of the last step).
    fn t(&self) -> f64;
    /// Current state.
    fn y(&self) -> &SVector<f64, N>;
    /// Left end of the last accepted step (equals `t()` right after reset).
    fn t_prev(&self) -> f64;
    /// State at `t_prev()`.
    fn y_prev(&self) -> &SVector<f64, N>;
    /// Dense output on the last accepted step $[t_{\text{prev}}, t]$ at full
    /// order (DOP853: 7th order, 3 extra rhs evaluations computed lazily once
    /// per step; DOPRI5: 4th order; RK4: cubic Hermite). Times outside the
    /// step extrapolate the same polynomial (no panic). Before the first
    /// step, returns `y()`.
    fn dense<S: OdeSystem<N>>(&mut self, sys: &S, t: f64, out: &mut SVector<f64, N>);
    /// Truncate the last step at `t_new` in $(t_{\text{prev}}, t]$: the
    /// current point becomes `(t_new, dense(t_new))` and $f$ is re-evaluated
    /// there; the step-size suggestion is kept, and `dense` stays valid on
    /// $[t_{\text{prev}}, t_{\text{new}}]$.
    fn truncate<S: OdeSystem<N>>(&mut self, sys: &S, t_new: f64) -> Result<(), OdeError>;
    /// Work counters.
    fn stats(&self) -> &Stats;
    /// Mutable work counters, for drivers and event code that evaluate the
    /// system themselves.
    fn stats_mut(&mut self) -> &mut Stats;
    /// The options.
    fn options(&self) -> &Options<N>;
    /// The current step-size suggestion for the next step (0 before reset).
    fn h_next(&self) -> f64;
    /// Name for reports: `"DOP853"`, `"DOPRI5"`, `"RK4"`.
    fn name(&self) -> &'static str;
}

/// Run-time choice of integration method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// [`Dop853`].
    Dop853,
    /// [`Dopri5`].
    Dopri5,
    /// [`Rk4`] (needs [`Options::fixed_step`]).
    Rk4,
}

impl Method {
    /// All methods.
    pub const ALL: [Method; 3] = [Method::Dop853, Method::Dopri5, Method::Rk4];

    /// Name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Dop853 => "DOP853",
            Method::Dopri5 => "DOPRI5",
            Method::Rk4 => "RK4",
        }
    }

    /// Classical order of the propagating formula (8, 5, 4).
    pub fn order(self) -> u32 {
        match self {
            Method::Dop853 => 8,
            Method::Dopri5 => 5,
            Method::Rk4 => 4,
        }
    }
}

/// Enum dispatch over the integrators, so the method can be chosen at run
/// time without trait objects (the trait has generic methods).
#[derive(Debug, Clone)]
pub enum AnyIntegrator<const N: usize> {
    /// DOP853.
    Dop853(Dop853<N>),
    /// DOPRI5.
    Dopri5(Dopri5<N>),
    /// RK4.
    Rk4(Rk4<N>),
}

impl<const N: usize> AnyIntegrator<N> {
    /// Builds the integrator of `method`, validating `options`.
    pub fn new(method: Method, options: Options<N>) -> Result<Self, OdeError> {
        Ok(match method {
            Method::Dop853 => AnyIntegrator::Dop853(Dop853::new(options)?),
            Method::Dopri5 => AnyIntegrator::Dopri5(Dopri5::new(options)?),
            Method::Rk4 => AnyIntegrator::Rk4(Rk4::new(options)?),
        })
    }

    /// The method of this integrator.
    pub fn method(&self) -> Method {
        match self {
            AnyIntegrator::Dop853(_) => Method::Dop853,
            AnyIntegrator::Dopri5(_) => Method::Dopri5,
            AnyIntegrator::Rk4(_) => Method::Rk4,
        }
    }
}

macro_rules! dispatch {
    ($self:expr, $i:ident => $e:expr) => {
        match $self {
            AnyIntegrator::Dop853($i) => $e,
            AnyIntegrator::Dopri5($i) => $e,
            AnyIntegrator::Rk4($i) => $e,
        }
    };
}

impl<const N: usize> Integrator<N> for AnyIntegrator<N> {
    fn reset<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &SVector<f64, N>,
        keep_step: bool,
    ) -> Result<(), OdeError> {
        dispatch!(self, i => i.reset(sys, t, y, keep_step))
    }
    fn step<S: OdeSystem<N>>(&mut self, sys: &S, t_bound: f64) -> Result<(), OdeError> {
        dispatch!(self, i => i.step(sys, t_bound))
    }
    fn t(&self) -> f64 {
        dispatch!(self, i => i.t())
    }
    fn y(&self) -> &SVector<f64, N> {
        dispatch!(self, i => i.y())
    }
    fn t_prev(&self) -> f64 {
        dispatch!(self, i => i.t_prev())
    }
    fn y_prev(&self) -> &SVector<f64, N> {
        dispatch!(self, i => i.y_prev())
    }
    fn dense<S: OdeSystem<N>>(&mut self, sys: &S, t: f64, out: &mut SVector<f64, N>) {
        dispatch!(self, i => i.dense(sys, t, out))
    }
    fn truncate<S: OdeSystem<N>>(&mut self, sys: &S, t_new: f64) -> Result<(), OdeError> {
        dispatch!(self, i => i.truncate(sys, t_new))
    }
    fn stats(&self) -> &Stats {
        dispatch!(self, i => i.stats())
    }
    fn stats_mut(&mut self) -> &mut Stats {
        dispatch!(self, i => i.stats_mut())
    }
    fn options(&self) -> &Options<N> {
        dispatch!(self, i => i.options())
    }
    fn h_next(&self) -> f64 {
        dispatch!(self, i => i.h_next())
    }
    fn name(&self) -> &'static str {
        dispatch!(self, i => i.name())
    }
}
