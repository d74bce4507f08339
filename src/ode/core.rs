//! State and stepping logic shared by the Runge–Kutta integrators.

use super::controller::{initial_step, PiController};
use super::kernels::all_finite;
use super::{OdeError, OdeSystem, Options, Stats};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector, U1};

/// Result of one trial step computed by a method.
pub(crate) struct Trial {
    /// Scaled error norm (ignored in fixed-step mode). Non-finite = the
    /// stages produced non-finite values.
    pub err: f64,
    /// Whether `f_new = f(t + h, y_new)` was already computed (FSAL).
    pub f_new_done: bool,
}

/// What a method's trial step gets: the current point and the scratch to
/// write the new point into.
pub(crate) struct TrialIo<'a, D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    pub opts: &'a Options<D>,
    /// Number of error-controlled components (>= 1), the $N$ of the RMS norm.
    pub n_ctrl: f64,
    pub t: f64,
    pub y: &'a OVector<f64, D>,
    pub f: &'a OVector<f64, D>,
    pub h: f64,
    pub y_new: &'a mut OVector<f64, D>,
    pub f_new: &'a mut OVector<f64, D>,
    pub stats: &'a mut Stats,
}

/// A zero vector of dimension `dim`.
pub(crate) fn zeros<D: Dim>(dim: D) -> OVector<f64, D>
where
    DefaultAllocator: Allocator<D>,
{
    OVector::zeros_generic(dim, U1)
}

/// Common integrator state. Every vector is allocated by [`Core::new`].
#[derive(Debug, Clone)]
pub(crate) struct Core<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    pub dim: D,
    pub opts: Options<D>,
    /// Number of error-controlled components (`atol` finite), at least 1.
    pub n_ctrl: f64,
    pub stats: Stats,
    pub t: f64,
    pub y: OVector<f64, D>,
    pub f: OVector<f64, D>,
    pub t_prev: f64,
    pub y_prev: OVector<f64, D>,
    pub f_prev: OVector<f64, D>,
    /// Step-size suggestion for the next step (0 = none yet).
    pub h: f64,
    pub init: bool,
    /// Whether a step exists (dense output available).
    pub has_step: bool,
    /// Length of the last accepted step (before any truncation).
    pub h_dense: f64,
    /// State at the right end of the last full step (before truncation).
    pub y_end: OVector<f64, D>,
    /// $f$ at the right end of the last full step (before truncation).
    pub f_end: OVector<f64, D>,
    /// Scratch: the trial point, the truncation point.
    pub y_new: OVector<f64, D>,
    /// Scratch: $f$ at the trial point.
    pub f_new: OVector<f64, D>,
    /// Attempts since the last reset.
    pub attempts: u64,
    pub pi: PiController,
    /// Order used by the automatic initial step.
    pub order: f64,
}

impl<D: Dim> Core<D>
where
    DefaultAllocator: Allocator<D>,
{
    pub(crate) fn new(
        dim: D,
        opts: Options<D>,
        q: f64,
        coupling: f64,
        order: f64,
    ) -> Result<Self, OdeError> {
        opts.validate()?;
        opts.check_dim(dim.value())?;
        let beta = opts.beta.unwrap_or(0.04);
        let n_ctrl = opts.controlled_components(dim.value()).max(1) as f64;
        let z = zeros(dim);
        Ok(Core {
            dim,
            opts,
            n_ctrl,
            stats: Stats::default(),
            t: 0.0,
            y: z.clone(),
            f: z.clone(),
            t_prev: 0.0,
            y_prev: z.clone(),
            f_prev: z.clone(),
            h: 0.0,
            init: false,
            has_step: false,
            h_dense: 0.0,
            y_end: z.clone(),
            f_end: z.clone(),
            y_new: z.clone(),
            f_new: z,
            attempts: 0,
            pi: PiController::new(q, coupling, beta),
            order,
        })
    }

    pub(crate) fn reset<S: OdeSystem<D>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &OVector<f64, D>,
        keep_step: bool,
    ) -> Result<(), OdeError> {
        if y.len() != self.dim.value() {
            return Err(OdeError::DimensionMismatch {
                field: "y0",
                expected: self.dim.value(),
                found: y.len(),
            });
        }
        if !t.is_finite() {
            return Err(OdeError::NonFiniteInitial {
                t,
                component: usize::MAX,
                value: t,
            });
        }
        if let Some(i) = y.iter().position(|v| !v.is_finite()) {
            return Err(OdeError::NonFiniteInitial {
                t,
                component: i,
                value: y[i],
            });
        }
        sys.rhs(t, y, &mut self.f_new);
        self.stats.rhs_evals += 1;
        if !all_finite(self.f_new.as_slice()) {
            return Err(OdeError::NonFiniteRhs { t, h: 0.0 });
        }
        self.t = t;
        self.y.copy_from(y);
        self.f.copy_from(&self.f_new);
        self.t_prev = t;
        self.y_prev.copy_from(y);
        self.f_prev.copy_from(&self.f_new);
        self.y_end.copy_from(y);
        self.f_end.copy_from(&self.f_new);
        self.has_step = false;
        self.h_dense = 0.0;
        self.attempts = 0;
        self.init = true;
        self.pi.err_old = 1e-4;
        if !(keep_step && self.h > 0.0) {
            self.h = match (self.opts.fixed_step, self.opts.h_init) {
                (Some(h), _) => h,
                (None, Some(h)) => h.min(self.opts.h_max),
                (None, None) => initial_step(
                    sys,
                    t,
                    &self.y,
                    &self.f,
                    self.order,
                    &self.opts,
                    self.n_ctrl,
                    &mut self.y_new,
                    &mut self.f_new,
                    &mut self.stats,
                ),
            };
        }
        Ok(())
    }

    /// Checks the bound; `Ok(true)` means nothing to do.
    pub(crate) fn check_bound(&self, t_bound: f64) -> Result<bool, OdeError> {
        if !self.init {
            return Err(OdeError::NotInitialized);
        }
        if !(t_bound.is_finite() && t_bound >= self.t) {
            return Err(OdeError::InvalidBound { t: self.t, t_bound });
        }
        Ok(t_bound == self.t)
    }

    /// One accepted step; `attempt` computes a trial step into
    /// `io.y_new` (and `io.f_new` if it reports `f_new_done`). A trial with non-finite values
    /// is retried at `fac_min` times its size (an error at a fixed step), a trial whose error
    /// exceeds 1 at the controller's smaller size.
    pub(crate) fn step<S, A>(
        &mut self,
        sys: &S,
        t_bound: f64,
        mut attempt: A,
    ) -> Result<(), OdeError>
    where
        S: OdeSystem<D>,
        A: FnMut(&S, TrialIo<'_, D>) -> Trial,
    {
        if self.check_bound(t_bound)? {
            return Ok(());
        }
        let fixed = self.opts.fixed_step;
        let mut h = match fixed {
            Some(hf) => hf,
            None => self.h.min(self.opts.h_max),
        };
        let mut rejected_before = false;
        let mut nonfinite = false;
        loop {
            self.check_budget(h, nonfinite)?;
            let (h_try, t_new, clipped) = land_on_bound(self.t, h, t_bound);
            match self.try_step(sys, &mut attempt, h_try, t_new) {
                Verdict::NonFinite if fixed.is_some() => {
                    return Err(OdeError::NonFiniteRhs {
                        t: self.t,
                        h: h_try,
                    });
                }
                Verdict::NonFinite => {
                    self.stats.rejected += 1;
                    rejected_before = true;
                    nonfinite = true;
                    h = h_try * self.opts.fac_min;
                }
                Verdict::Accept(err) => {
                    let h_next = match fixed {
                        Some(hf) => hf,
                        None => {
                            let mut ratio = self.pi.accept(err, &self.opts);
                            if rejected_before {
                                ratio = ratio.min(1.0);
                            }
                            let hn = h_try * ratio;
                            if clipped {
                                hn.max(h)
                            } else {
                                hn
                            }
                        }
                    };
                    self.advance(t_new, h_try, h_next.min(self.opts.h_max));
                    return Ok(());
                }
                Verdict::Reject(err) => {
                    nonfinite = false;
                    self.stats.rejected += 1;
                    rejected_before = true;
                    h = h_try * self.pi.reject(err, &self.opts);
                }
            }
        }
    }

    /// The attempt's budget (`max_steps`) and, for adaptive steps, the floor of the step size
    /// ($\max(h_\text{min}, 10\varepsilon|t|)$): below it the step has underflowed, or, after
    /// non-finite trials, the right-hand side cannot be evaluated near `t`.
    #[inline]
    fn check_budget(&self, h: f64, nonfinite: bool) -> Result<(), OdeError> {
        if self.attempts >= self.opts.max_steps {
            return Err(OdeError::TooManySteps {
                t: self.t,
                h,
                max_steps: self.opts.max_steps,
            });
        }
        let h_floor = self.opts.h_min.max(10.0 * f64::EPSILON * self.t.abs());
        if self.opts.fixed_step.is_none() && (h < h_floor || h.is_nan()) {
            return Err(if nonfinite {
                OdeError::NonFiniteRhs { t: self.t, h }
            } else {
                OdeError::StepSizeUnderflow {
                    t: self.t,
                    h,
                    h_min: h_floor,
                }
            });
        }
        Ok(())
    }

    /// One trial of size `h_try` to `t_new`, with $f$ at its end when it is to be accepted
    /// (unless the method computed it). Counts the attempt.
    #[inline]
    fn try_step<S, A>(&mut self, sys: &S, attempt: &mut A, h_try: f64, t_new: f64) -> Verdict
    where
        S: OdeSystem<D>,
        A: FnMut(&S, TrialIo<'_, D>) -> Trial,
    {
        self.attempts += 1;
        let fixed = self.opts.fixed_step.is_some();
        let trial = attempt(
            sys,
            TrialIo {
                opts: &self.opts,
                n_ctrl: self.n_ctrl,
                t: self.t,
                y: &self.y,
                f: &self.f,
                h: h_try,
                y_new: &mut self.y_new,
                f_new: &mut self.f_new,
                stats: &mut self.stats,
            },
        );
        let acceptable = fixed || trial.err <= 1.0;
        let mut ok_values = all_finite(self.y_new.as_slice()) && (fixed || trial.err.is_finite());
        if ok_values && acceptable && !trial.f_new_done {
            sys.rhs(t_new, &self.y_new, &mut self.f_new);
            self.stats.rhs_evals += 1;
        }
        if ok_values {
            ok_values = all_finite(self.f_new.as_slice()) || !acceptable;
        }
        if !ok_values {
            Verdict::NonFinite
        } else if acceptable {
            Verdict::Accept(trial.err)
        } else {
            Verdict::Reject(trial.err)
        }
    }

    /// Accepts the trial point: the current point becomes the previous one, the trial the
    /// current one and the end of the dense step; `h_next` is the next suggestion.
    #[inline]
    pub(crate) fn advance(&mut self, t_new: f64, h_try: f64, h_next: f64) {
        self.t_prev = self.t;
        self.y_prev.copy_from(&self.y);
        self.f_prev.copy_from(&self.f);
        self.t = t_new;
        self.y.copy_from(&self.y_new);
        self.f.copy_from(&self.f_new);
        self.h_dense = h_try;
        self.y_end.copy_from(&self.y_new);
        self.f_end.copy_from(&self.f_new);
        self.has_step = true;
        self.h = h_next;
        self.stats.steps += 1;
    }

    /// Validates a truncation time.
    pub(crate) fn check_truncate(&self, t_new: f64) -> Result<(), OdeError> {
        if !self.init {
            return Err(OdeError::NotInitialized);
        }
        if !(t_new > self.t_prev && t_new <= self.t) {
            return Err(OdeError::TruncateOutOfRange {
                t_new,
                t_prev: self.t_prev,
                t: self.t,
            });
        }
        Ok(())
    }

    /// Moves the current point to `(t_new, y_new)` (the dense output at
    /// `t_new`, left in the scratch `self.y_new` by the caller) and
    /// re-evaluates `f` there.
    pub(crate) fn apply_truncate<S: OdeSystem<D>>(
        &mut self,
        sys: &S,
        t_new: f64,
    ) -> Result<(), OdeError> {
        if t_new == self.t {
            return Ok(());
        }
        sys.rhs(t_new, &self.y_new, &mut self.f_new);
        self.stats.rhs_evals += 1;
        if !all_finite(self.f_new.as_slice()) {
            return Err(OdeError::NonFiniteRhs {
                t: t_new,
                h: t_new - self.t_prev,
            });
        }
        self.t = t_new;
        self.y.copy_from(&self.y_new);
        self.f.copy_from(&self.f_new);
        Ok(())
    }

    /// Copies the state into `out`, reallocating `out` only if its length
    /// differs (possible for `Dyn` only).
    #[inline]
    pub(crate) fn copy_state(&self, out: &mut OVector<f64, D>) {
        fit(out, self.dim);
        out.copy_from(&self.y);
    }
}

/// How a trial step ended ([`Core::step`]).
enum Verdict {
    /// Finite values and an error estimate of at most 1 (or a fixed step): taken.
    Accept(f64),
    /// Finite values, error estimate above 1: retried smaller.
    Reject(f64),
    /// The trial point, its error or $f$ there (when it would be taken) not finite.
    NonFinite,
}

/// The trial `(h_try, t_new, clipped)` from `t` with step `h`: the step lands exactly on the
/// bound when that is within 1% beyond one step (`clipped`).
#[inline]
fn land_on_bound(t: f64, h: f64, t_bound: f64) -> (f64, f64, bool) {
    if t + 1.01 * h >= t_bound {
        (t_bound - t, t_bound, true)
    } else {
        (h, t + h, false)
    }
}

/// Makes `out` a vector of dimension `dim`, reallocating only if its length
/// differs (never for fixed dimensions).
#[inline]
pub(crate) fn fit<D: Dim>(out: &mut OVector<f64, D>, dim: D)
where
    DefaultAllocator: Allocator<D>,
{
    if out.len() != dim.value() {
        *out = zeros(dim);
    }
}

/// Implements the state accessors of [`Integrator`](super::Integrator) for a
/// type with a `core: Core<D>` field, or with the [`Core`] at the field path given
/// (`core_accessors!(rk.core)`).
macro_rules! core_accessors {
    () => {
        $crate::ode::core::core_accessors!(core);
    };
    ($($field:ident).+) => {
        fn t(&self) -> f64 {
            self.$($field).+.t
        }
        fn y(&self) -> &OVector<f64, D> {
            &self.$($field).+.y
        }
        fn t_prev(&self) -> f64 {
            self.$($field).+.t_prev
        }
        fn y_prev(&self) -> &OVector<f64, D> {
            &self.$($field).+.y_prev
        }
        fn stats(&self) -> &Stats {
            &self.$($field).+.stats
        }
        fn stats_mut(&mut self) -> &mut Stats {
            &mut self.$($field).+.stats
        }
        fn options(&self) -> &Options<D> {
            &self.$($field).+.opts
        }
        fn h_next(&self) -> f64 {
            self.$($field).+.h
        }
        fn dim(&self) -> D {
            self.$($field).+.dim
        }
        fn dy(&self) -> Option<&OVector<f64, D>> {
            Some(&self.$($field).+.f)
        }
        fn dy_prev(&self) -> Option<&OVector<f64, D>> {
            Some(&self.$($field).+.f_prev)
        }
    };
}
pub(crate) use core_accessors;
