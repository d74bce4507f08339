//! The step driver shared by the explicit Runge–Kutta methods with a continuous extension of
//! Hairer's form (DOPRI5, DOP853).
//!
//! [`ExplicitRk`] owns the state ([`Core`]), the stages, the dense-output rows and the stage
//! scratch, and does the bookkeeping every such method repeats: stepping through
//! [`Core::step`], invalidating the dense output when a step is accepted, preparing it lazily,
//! evaluating it and truncating to it. A method supplies only what is its own through
//! [`RkTableau`]: its stages and error estimate, the rows of its dense output above the common
//! cubic part, and how those rows enter the interpolant.
//!
//! Both continuous extensions share their first four rows: on $[t_0, t_0 + h]$ with
//! $\theta = (t - t_0)/h$, $\bar\theta = 1 - \theta$,
//! $$u(\theta) = r_1 + \theta\big(r_2 + \bar\theta\big(r_3 + \theta\thinspace(r_4 + \bar\theta\thinspace p(\theta))\big)\big)$$
//! with $r_1 = y_0$, $r_2 = y_1 - y_0$, $r_3 = h f_0 - r_2$, $r_4 = r_2 - h f_1 - r_3$, where
//! $f_0 = f(t_0, y_0) = k_1$ and $f_1 = f(t_0 + h, y_1)$ (the first-same-as-last stage); the
//! method's higher part $p(\theta)$ is built from its rows $r_5, \dots$ ([`RkTableau::higher`]).

use super::core::{fit, zeros, Core, Trial, TrialIo};
use super::{OdeError, OdeSystem, Options};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};
use std::marker::PhantomData;

/// What is specific to an explicit Runge–Kutta method with `S` stage vectors (including those
/// only dense output needs) and `R` dense-output rows above the common four.
pub(crate) trait RkTableau<const S: usize, const R: usize> {
    /// The method's name ([`Integrator::name`](super::Integrator::name)).
    const NAME: &'static str;
    /// The step-size controller's exponent $q$ and PI coupling, and the order used by the
    /// automatic initial step ([`Core::new`]).
    const CONTROL: (f64, f64, f64);

    /// One trial step from `io`: the stages into `k` (with $k_1 = f(t, y)$ in `k[0]`), the new
    /// point into `io.y_new`, and its scaled error norm; `yt` is the stage argument scratch.
    fn trial<D, Sys>(
        sys: &Sys,
        k: &mut [OVector<f64, D>; S],
        yt: &mut OVector<f64, D>,
        io: TrialIo<'_, D>,
    ) -> Trial
    where
        D: Dim,
        DefaultAllocator: Allocator<D>,
        Sys: OdeSystem<D>;

    /// The rows $r_5, r_6, \dots$ (`rows[0]`, `rows[1]`, ...) of the last accepted step of `c`,
    /// from its stages `k`, evaluating any extra stages the extension needs (counted in
    /// `c.stats`).
    fn higher_rows<D, Sys>(
        sys: &Sys,
        c: &mut Core<D>,
        k: &mut [OVector<f64, D>; S],
        yt: &mut OVector<f64, D>,
        rows: &mut [OVector<f64, D>; R],
    ) where
        D: Dim,
        DefaultAllocator: Allocator<D>,
        Sys: OdeSystem<D>;

    /// Component `i` of the higher part $p(\theta)$ of the interpolant (see the module docs)
    /// from the rows `r` ($r_5, \dots$, sliced to the dimension), $\theta$ = `s` and
    /// $1 - \theta$ = `s1`.
    fn higher(r: &[&[f64]; R], i: usize, s: f64, s1: f64) -> f64;
}

/// An explicit Runge–Kutta integrator: the shared state and bookkeeping of the method `T`
/// (see the module docs). Every vector is allocated by [`ExplicitRk::with_dim`].
#[derive(Debug, Clone)]
pub(crate) struct ExplicitRk<D: Dim, T, const S: usize, const R: usize>
where
    DefaultAllocator: Allocator<D>,
{
    pub core: Core<D>,
    /// Stages of the last trial (of the last accepted step after a successful `step`).
    k: [OVector<f64, D>; S],
    /// The common dense-output rows $r_1 \dots r_4$ of the last accepted step, once prepared.
    cubic: [OVector<f64, D>; 4],
    /// The method's rows $r_5, \dots$ of the last accepted step, once prepared.
    rows: [OVector<f64, D>; R],
    /// Scratch: the argument of the stages.
    yt: OVector<f64, D>,
    /// Whether `rows` belong to the last accepted step.
    dense_ready: bool,
    tableau: PhantomData<T>,
}

impl<D: Dim, T: RkTableau<S, R>, const S: usize, const R: usize> ExplicitRk<D, T, S, R>
where
    DefaultAllocator: Allocator<D>,
{
    /// The integrator for dimension `dim`, validating `options`.
    pub(crate) fn with_dim(dim: D, options: Options<D>) -> Result<Self, OdeError> {
        let (q, coupling, order) = T::CONTROL;
        let z = zeros(dim);
        Ok(ExplicitRk {
            core: Core::new(dim, options, q, coupling, order)?,
            k: std::array::from_fn(|_| z.clone()),
            cubic: std::array::from_fn(|_| z.clone()),
            rows: std::array::from_fn(|_| z.clone()),
            yt: z,
            dense_ready: false,
            tableau: PhantomData,
        })
    }

    /// The method's name.
    pub(crate) fn name(&self) -> &'static str {
        T::NAME
    }

    /// [`Integrator::reset`](super::Integrator::reset).
    pub(crate) fn reset<Sys: OdeSystem<D>>(
        &mut self,
        sys: &Sys,
        t: f64,
        y: &OVector<f64, D>,
        keep_step: bool,
    ) -> Result<(), OdeError> {
        self.dense_ready = false;
        self.core.reset(sys, t, y, keep_step)
    }

    /// [`Integrator::step`](super::Integrator::step): the method's trial steps driven by
    /// [`Core::step`]; an accepted step makes the dense output stale. A step that fails after
    /// trials has overwritten the stages of the last accepted step: they are computed again
    /// if its dense output still needs them.
    pub(crate) fn step<Sys: OdeSystem<D>>(
        &mut self,
        sys: &Sys,
        t_bound: f64,
    ) -> Result<(), OdeError> {
        let ExplicitRk {
            core,
            k,
            yt,
            dense_ready,
            ..
        } = self;
        let (steps, attempts) = (core.stats.steps, core.attempts);
        let r = core.step(sys, t_bound, |sys, io| {
            k[0].copy_from(io.f);
            T::trial(sys, k, yt, io)
        });
        if core.stats.steps != steps {
            *dense_ready = false;
        } else if core.attempts != attempts && core.has_step && !*dense_ready {
            self.restage(sys);
        }
        r
    }

    /// Computes the stages of the last accepted step again (the same trial, so the same
    /// values) into `k`, its new point into the scratch `y_new` (counted in the statistics).
    fn restage<Sys: OdeSystem<D>>(&mut self, sys: &Sys) {
        let ExplicitRk { core: c, k, yt, .. } = self;
        k[0].copy_from(&c.f_prev);
        let io = TrialIo {
            opts: &c.opts,
            n_ctrl: c.n_ctrl,
            t: c.t_prev,
            y: &c.y_prev,
            f: &c.f_prev,
            h: c.h_dense,
            y_new: &mut c.y_new,
            f_new: &mut c.f_new,
            stats: &mut c.stats,
        };
        T::trial(sys, k, yt, io);
    }

    /// [`Integrator::dense`](super::Integrator::dense): the current state before the first
    /// step, the continuous extension of the last step after it.
    pub(crate) fn dense<Sys: OdeSystem<D>>(
        &mut self,
        sys: &Sys,
        t: f64,
        out: &mut OVector<f64, D>,
    ) {
        if !self.core.has_step {
            self.core.copy_state(out);
            return;
        }
        fit(out, self.core.dim);
        self.prepare_dense(sys);
        let c = &self.core;
        let rows = (&self.cubic, &self.rows);
        Self::eval_dense(rows, c.t_prev, c.h_dense, t, out.as_mut_slice());
    }

    /// [`Integrator::truncate`](super::Integrator::truncate). The dense output is prepared
    /// even when `t_new` is the step end (then nothing moves), so that the counted work does
    /// not depend on where an event fell.
    pub(crate) fn truncate<Sys: OdeSystem<D>>(
        &mut self,
        sys: &Sys,
        t_new: f64,
    ) -> Result<(), OdeError> {
        self.core.check_truncate(t_new)?;
        self.prepare_dense(sys);
        if t_new == self.core.t {
            return Ok(());
        }
        let c = &mut self.core;
        let rows = (&self.cubic, &self.rows);
        Self::eval_dense(rows, c.t_prev, c.h_dense, t_new, c.y_new.as_mut_slice());
        c.apply_truncate(sys, t_new)
    }

    /// Computes the dense-output rows of the last accepted step (once per step): the common
    /// cubic rows here, the method's higher rows by [`RkTableau::higher_rows`].
    fn prepare_dense<Sys: OdeSystem<D>>(&mut self, sys: &Sys) {
        if self.dense_ready {
            return;
        }
        let ExplicitRk {
            core: c,
            k,
            cubic,
            rows,
            yt,
            ..
        } = self;
        let h = c.h_dense;
        let n = c.y.len();
        let (y0, y1) = (&c.y_prev.as_slice()[..n], &c.y_end.as_slice()[..n]);
        let (f0, f1) = (&c.f_prev.as_slice()[..n], &c.f_end.as_slice()[..n]);
        let [r1, r2, r3, r4] = cubic;
        let (r1, r2) = (&mut r1.as_mut_slice()[..n], &mut r2.as_mut_slice()[..n]);
        let (r3, r4) = (&mut r3.as_mut_slice()[..n], &mut r4.as_mut_slice()[..n]);
        for i in 0..n {
            let ydiff = y1[i] - y0[i];
            let bspl = f0[i] * h - ydiff;
            r1[i] = y0[i];
            r2[i] = ydiff;
            r3[i] = bspl;
            r4[i] = ydiff - f1[i] * h - bspl;
        }
        T::higher_rows(sys, c, k, yt, rows);
        self.dense_ready = true;
    }

    /// Evaluates the prepared dense output of the step $[t_0, t_0 + h]$ at `t` into `out`.
    fn eval_dense(rows: Rows<'_, D, R>, t0: f64, h: f64, t: f64, out: &mut [f64]) {
        let s = (t - t0) / h;
        let s1 = 1.0 - s;
        let n = out.len();
        let c: [&[f64]; 4] = std::array::from_fn(|j| &rows.0[j].as_slice()[..n]);
        let r: [&[f64]; R] = std::array::from_fn(|j| &rows.1[j].as_slice()[..n]);
        for i in 0..n {
            let p = T::higher(&r, i, s, s1);
            out[i] = c[0][i] + (c[1][i] + (c[2][i] + (c[3][i] + p * s1) * s) * s1) * s;
        }
    }
}

/// The common and the method's dense-output rows.
type Rows<'a, D, const R: usize> = (&'a [OVector<f64, D>; 4], &'a [OVector<f64, D>; R]);

/// The constructors `new` and `with_dim` and the [`Integrator`](super::Integrator) impl of a
/// public method type `$name<D>` whose one field `rk` is an [`ExplicitRk`], by delegation.
/// Used in the method's module, where the names of [`super`] used below are imported.
macro_rules! explicit_rk_impls {
    ($name:ident) => {
        impl<D: nalgebra::DimName> $name<D>
        where
            DefaultAllocator: Allocator<D>,
        {
            /// Creates the integrator for a fixed dimension (`U6`, `Const<6>`),
            /// validating `options` (typed error naming the offending field). Call
            /// [`Integrator::reset`] before stepping.
            pub fn new(options: Options<D>) -> Result<Self, OdeError> {
                Self::with_dim(D::name(), options)
            }
        }

        impl<D: Dim> $name<D>
        where
            DefaultAllocator: Allocator<D>,
        {
            /// Creates the integrator for dimension `dim` (e.g. `Dyn(n)` for a size
            /// known at run time), validating `options` (per-component tolerances
            /// must have `dim` components). Allocates every vector it will use.
            pub fn with_dim(dim: D, options: Options<D>) -> Result<Self, OdeError> {
                Ok($name {
                    rk: $crate::ode::erk::ExplicitRk::with_dim(dim, options)?,
                })
            }
        }

        impl<D: Dim> Integrator<D> for $name<D>
        where
            DefaultAllocator: Allocator<D>,
        {
            fn reset<S: OdeSystem<D>>(
                &mut self,
                sys: &S,
                t: f64,
                y: &OVector<f64, D>,
                keep_step: bool,
            ) -> Result<(), OdeError> {
                self.rk.reset(sys, t, y, keep_step)
            }

            fn step<S: OdeSystem<D>>(&mut self, sys: &S, t_bound: f64) -> Result<(), OdeError> {
                self.rk.step(sys, t_bound)
            }

            fn dense<S: OdeSystem<D>>(&mut self, sys: &S, t: f64, out: &mut OVector<f64, D>) {
                self.rk.dense(sys, t, out)
            }

            fn truncate<S: OdeSystem<D>>(&mut self, sys: &S, t_new: f64) -> Result<(), OdeError> {
                self.rk.truncate(sys, t_new)
            }

            fn name(&self) -> &'static str {
                self.rk.name()
            }

            $crate::ode::core::core_accessors!(rk.core);
        }
    };
}
pub(crate) use explicit_rk_impls;
