use super::core::{core_accessors, fit, zeros, Core, Trial, TrialIo};
use super::kernels::axpy;
use super::{Integrator, OdeError, OdeSystem, Options, Stats};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, DimName, OVector};

/// Classical RK4 with fixed step [`Options::fixed_step`] (required) and no
/// error control: 4 evaluations of $f$ per step.
///
/// Dense output is the cubic Hermite interpolant of $(y_0, f_0)$ and
/// $(y_1, f_1)$: with $\theta = (t - t_0)/h$,
/// $$u(\theta) = (1-\theta) y_0 + \theta y_1 + \theta(\theta-1)\big[(1-2\theta)(y_1-y_0) + (\theta-1) h f_0 + \theta h f_1\big],$$
/// which is 3rd-order accurate (local error $O(h^4)$).
#[derive(Debug, Clone)]
pub struct Rk4<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    core: Core<D>,
    /// Stages 2..4 and the stage argument (scratch).
    k: [OVector<f64, D>; 4],
}

impl<D: DimName> Rk4<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Creates the integrator for a fixed dimension, validating `options`;
    /// `fixed_step` must be `Some(h)` (else [`OdeError::InvalidOption`]
    /// naming `fixed_step`).
    pub fn new(options: Options<D>) -> Result<Self, OdeError> {
        Self::with_dim(D::name(), options)
    }
}

impl<D: Dim> Rk4<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Creates the integrator for dimension `dim` (e.g. `Dyn(n)`); as
    /// [`Rk4::new`] otherwise.
    pub fn with_dim(dim: D, options: Options<D>) -> Result<Self, OdeError> {
        if options.fixed_step.is_none() {
            return Err(OdeError::InvalidOption {
                field: "fixed_step",
                value: f64::NAN,
                hint: "RK4 has no error control: set Options::fixed_step = Some(h), or use DOPRI5/DOP853",
            });
        }
        let z = zeros(dim);
        Ok(Rk4 {
            core: Core::new(dim, options, 4.0, 0.0, 4.0)?,
            k: std::array::from_fn(|_| z.clone()),
        })
    }

    /// Evaluates the Hermite interpolant of the last full step at `t`.
    fn eval_dense(c: Hermite<'_>, t: f64, out: &mut [f64]) {
        let h = c.h;
        let s = (t - c.t0) / h;
        let n = out.len();
        let (y0, y1) = (&c.y0[..n], &c.y1[..n]);
        let (f0, f1) = (&c.f0[..n], &c.f1[..n]);
        let (w0, w1) = (1.0 - s, s);
        let (wd, wf0, wf1, wb) = (1.0 - 2.0 * s, (s - 1.0) * h, s * h, s * (s - 1.0));
        for i in 0..n {
            let d = y1[i] - y0[i];
            out[i] = y0[i] * w0 + y1[i] * w1 + (d * wd + f0[i] * wf0 + f1[i] * wf1) * wb;
        }
    }
}

/// The data of the Hermite interpolant: the full last step.
struct Hermite<'a> {
    t0: f64,
    h: f64,
    y0: &'a [f64],
    y1: &'a [f64],
    f0: &'a [f64],
    f1: &'a [f64],
}

impl<'a> Hermite<'a> {
    fn of<D: Dim>(c: &'a Core<D>) -> Self
    where
        DefaultAllocator: Allocator<D>,
    {
        Hermite {
            t0: c.t_prev,
            h: c.h_dense,
            y0: c.y_prev.as_slice(),
            y1: c.y_end.as_slice(),
            f0: c.f_prev.as_slice(),
            f1: c.f_end.as_slice(),
        }
    }
}

impl<D: Dim> Integrator<D> for Rk4<D>
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
        self.core.reset(sys, t, y, keep_step)
    }

    fn step<S: OdeSystem<D>>(&mut self, sys: &S, t_bound: f64) -> Result<(), OdeError> {
        let [k2, k3, k4, yt] = &mut self.k;
        self.core.step(sys, t_bound, |sys, io| {
            let TrialIo {
                t,
                y,
                f,
                h,
                y_new,
                stats,
                ..
            } = io;
            let hh = 0.5 * h;
            axpy(yt.as_mut_slice(), y.as_slice(), f.as_slice(), hh);
            sys.rhs(t + hh, yt, k2);
            axpy(yt.as_mut_slice(), y.as_slice(), k2.as_slice(), hh);
            sys.rhs(t + hh, yt, k3);
            axpy(yt.as_mut_slice(), y.as_slice(), k3.as_slice(), h);
            sys.rhs(t + h, yt, k4);
            stats.rhs_evals += 3;
            let w = h / 6.0;
            let n = y.len();
            let (ys, fs) = (&y.as_slice()[..n], &f.as_slice()[..n]);
            let (a, b, c) = (
                &k2.as_slice()[..n],
                &k3.as_slice()[..n],
                &k4.as_slice()[..n],
            );
            let yn = &mut y_new.as_mut_slice()[..n];
            for i in 0..n {
                yn[i] = ys[i] + (fs[i] + (a[i] + b[i]) * 2.0 + c[i]) * w;
            }
            Trial {
                err: 0.0,
                f_new_done: false,
            }
        })
    }

    fn dense<S: OdeSystem<D>>(&mut self, _sys: &S, t: f64, out: &mut OVector<f64, D>) {
        if !self.core.has_step {
            self.core.copy_state(out);
            return;
        }
        // Hermite data of the full step, kept valid after truncation.
        fit(out, self.core.dim);
        Self::eval_dense(Hermite::of(&self.core), t, out.as_mut_slice());
    }

    fn truncate<S: OdeSystem<D>>(&mut self, sys: &S, t_new: f64) -> Result<(), OdeError> {
        self.core.check_truncate(t_new)?;
        if t_new == self.core.t {
            return Ok(());
        }
        let c = &mut self.core;
        let data = Hermite {
            t0: c.t_prev,
            h: c.h_dense,
            y0: c.y_prev.as_slice(),
            y1: c.y_end.as_slice(),
            f0: c.f_prev.as_slice(),
            f1: c.f_end.as_slice(),
        };
        Self::eval_dense(data, t_new, c.y_new.as_mut_slice());
        c.apply_truncate(sys, t_new)
    }

    core_accessors!();

    fn name(&self) -> &'static str {
        "RK4"
    }
}
