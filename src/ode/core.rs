//! State and stepping logic shared by the Runge–Kutta integrators.

use super::controller::{initial_step, PiController};
use super::{OdeError, OdeSystem, Options, Stats};
use nalgebra::SVector;

/// Result of one trial step computed by a method.
pub(crate) struct Trial {
    /// Scaled error norm (ignored in fixed-step mode). Non-finite = the
    /// stages produced non-finite values.
    pub err: f64,
    /// Whether `f_new = f(t + h, y_new)` was already computed (FSAL).
    pub f_new_done: bool,
}

/// Common integrator state.
#[derive(Debug, Clone)]
pub(crate) struct Core<const N: usize> {
    pub opts: Options<N>,
    pub stats: Stats,
    pub t: f64,
    pub y: SVector<f64, N>,
    pub f: SVector<f64, N>,
    pub t_prev: f64,
    pub y_prev: SVector<f64, N>,
    pub f_prev: SVector<f64, N>,
    /// Step-size suggestion for the next step (0 = none yet).
    pub h: f64,
    pub init: bool,
    /// Whether a step exists (dense output available).
    pub has_step: bool,
    /// Length of the last accepted step (before any truncation).
    pub h_dense: f64,
    /// State at the right end of the last full step (before truncation).
    pub y_end: SVector<f64, N>,
    /// $f$ at the right end of the last full step (before truncation).
    pub f_end: SVector<f64, N>,
    /// Attempts since the last reset.
    pub attempts: u64,
    pub pi: PiController,
    /// Order used by the automatic initial step.
    pub order: f64,
}

fn finite<const N: usize>(v: &SVector<f64, N>) -> bool {
    v.iter().all(|x| x.is_finite())
}

impl<const N: usize> Core<N> {
    pub(crate) fn new(opts: Options<N>, q: f64, coupling: f64, order: f64) -> Result<Self, OdeError> {
        opts.validate()?;
        let beta = opts.beta.unwrap_or(0.04);
        let z = SVector::<f64, N>::zeros();
        Ok(Core {
            opts,
            stats: Stats::default(),
            t: 0.0,
            y: z,
            f: z,
            t_prev: 0.0,
            y_prev: z,
            f_prev: z,
            h: 0.0,
            init: false,
            has_step: false,
            h_dense: 0.0,
            y_end: z,
            f_end: z,
            attempts: 0,
            pi: PiController::new(q, coupling, beta),
            order,
        })
    }

    pub(crate) fn reset<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &SVector<f64, N>,
        keep_step: bool,
    ) -> Result<(), OdeError> {
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
        let mut f = SVector::<f64, N>::zeros();
        sys.rhs(t, y, &mut f);
        self.stats.rhs_evals += 1;
        if !finite(&f) {
            return Err(OdeError::NonFiniteRhs { t, h: 0.0 });
        }
        self.t = t;
        self.y = *y;
        self.f = f;
        self.t_prev = t;
        self.y_prev = *y;
        self.f_prev = f;
        self.y_end = *y;
        self.f_end = f;
        self.has_step = false;
        self.h_dense = 0.0;
        self.attempts = 0;
        self.init = true;
        self.pi.err_old = 1e-4;
        if !(keep_step && self.h > 0.0) {
            self.h = match (self.opts.fixed_step, self.opts.h_init) {
                (Some(h), _) => h,
                (None, Some(h)) => h.min(self.opts.h_max),
                (None, None) => {
                    let opts = self.opts;
                    initial_step(sys, t, y, &f, self.order, &opts, &mut self.stats)
                }
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
            return Err(OdeError::InvalidBound {
                t: self.t,
                t_bound,
            });
        }
        Ok(t_bound == self.t)
    }

    /// One accepted step using `attempt(sys, opts, t, y, f, h, y_new, f_new, stats)`.
    pub(crate) fn step<S, A>(&mut self, sys: &S, t_bound: f64, mut attempt: A) -> Result<(), OdeError>
    where
        S: OdeSystem<N>,
        A: FnMut(
            &S,
            &Options<N>,
            f64,
            &SVector<f64, N>,
            &SVector<f64, N>,
            f64,
            &mut SVector<f64, N>,
            &mut SVector<f64, N>,
            &mut Stats,
        ) -> Trial,
    {
        if self.check_bound(t_bound)? {
            return Ok(());
        }
        let opts = self.opts;
        let fixed = opts.fixed_step;
        let mut h = match fixed {
            Some(hf) => hf,
            None => self.h.min(opts.h_max),
        };
        let mut rejected_before = false;
        let mut nonfinite = false;
        let mut y_new = SVector::<f64, N>::zeros();
        let mut f_new = SVector::<f64, N>::zeros();
        loop {
            if self.attempts >= opts.max_steps {
                return Err(OdeError::TooManySteps {
                    t: self.t,
                    h,
                    max_steps: opts.max_steps,
                });
            }
            let h_floor = opts.h_min.max(10.0 * f64::EPSILON * self.t.abs());
            if fixed.is_none() && (h < h_floor || h.is_nan()) {
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
            // Land exactly on the bound when it is within 1% beyond one step.
            let (h_try, t_new, clipped) = if self.t + 1.01 * h >= t_bound {
                (t_bound - self.t, t_bound, true)
            } else {
                (h, self.t + h, false)
            };
            self.attempts += 1;
            let trial = attempt(
                sys,
                &opts,
                self.t,
                &self.y,
                &self.f,
                h_try,
                &mut y_new,
                &mut f_new,
                &mut self.stats,
            );
            let mut ok_values = finite(&y_new) && (fixed.is_some() || trial.err.is_finite());
            if ok_values && (fixed.is_some() || trial.err <= 1.0) && !trial.f_new_done {
                sys.rhs(t_new, &y_new, &mut f_new);
                self.stats.rhs_evals += 1;
            }
            if ok_values {
                ok_values = finite(&f_new) || !(fixed.is_some() || trial.err <= 1.0);
            }
            if !ok_values {
                if fixed.is_some() {
                    return Err(OdeError::NonFiniteRhs { t: self.t, h: h_try });
                }
                self.stats.rejected += 1;
                rejected_before = true;
                nonfinite = true;
                h = h_try * opts.fac_min;
                continue;
            }
            nonfinite = false;
            if fixed.is_some() || trial.err <= 1.0 {
                let mut h_next = match fixed {
                    Some(hf) => hf,
                    None => {
                        let mut ratio = self.pi.accept(trial.err, &opts);
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
                h_next = h_next.min(opts.h_max);
                self.t_prev = self.t;
                self.y_prev = self.y;
                self.f_prev = self.f;
                self.t = t_new;
                self.y = y_new;
                self.f = f_new;
                self.h_dense = h_try;
                self.y_end = y_new;
                self.f_end = f_new;
                self.has_step = true;
                self.h = h_next;
                self.stats.steps += 1;
                return Ok(());
            }
            self.stats.rejected += 1;
            rejected_before = true;
            h = h_try * self.pi.reject(trial.err, &opts);
        }
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

    /// Moves the current point to `(t_new, y_new)` and re-evaluates `f`.
    pub(crate) fn apply_truncate<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t_new: f64,
        y_new: &SVector<f64, N>,
    ) -> Result<(), OdeError> {
        if t_new == self.t {
            return Ok(());
        }
        let mut f = SVector::<f64, N>::zeros();
        sys.rhs(t_new, y_new, &mut f);
        self.stats.rhs_evals += 1;
        if !finite(&f) {
            return Err(OdeError::NonFiniteRhs {
                t: t_new,
                h: t_new - self.t_prev,
            });
        }
        self.t = t_new;
        self.y = *y_new;
        self.f = f;
        Ok(())
    }
}

/// Implements the state accessors of [`Integrator`](super::Integrator) for a
/// type with a `core: Core<N>` field.
macro_rules! core_accessors {
    () => {
        fn t(&self) -> f64 {
            self.core.t
        }
        fn y(&self) -> &SVector<f64, N> {
            &self.core.y
        }
        fn t_prev(&self) -> f64 {
            self.core.t_prev
        }
        fn y_prev(&self) -> &SVector<f64, N> {
            &self.core.y_prev
        }
        fn stats(&self) -> &Stats {
            &self.core.stats
        }
        fn stats_mut(&mut self) -> &mut Stats {
            &mut self.core.stats
        }
        fn options(&self) -> &Options<N> {
            &self.core.opts
        }
        fn h_next(&self) -> f64 {
            self.core.h
        }
    };
}
pub(crate) use core_accessors;
