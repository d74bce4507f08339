//! The classical 4th-order Runge–Kutta method with fixed steps and cubic
//! Hermite dense output.

use super::core::{core_accessors, Core, Trial};
use super::{Integrator, OdeError, OdeSystem, Options, Stats};
use nalgebra::SVector;

/// Classical RK4 with fixed step [`Options::fixed_step`] (required) and no
/// error control: 4 evaluations of $f$ per step.
///
/// Dense output is the cubic Hermite interpolant of $(y_0, f_0)$ and
/// $(y_1, f_1)$: with $\theta = (t - t_0)/h$,
/// $$u(\theta) = (1-\theta) y_0 + \theta y_1 + \theta(\theta-1)\big[(1-2\theta)(y_1-y_0) + (\theta-1) h f_0 + \theta h f_1\big],$$
/// which is 3rd-order accurate (local error $O(h^4)$).
#[derive(Debug, Clone)]
pub struct Rk4<const N: usize> {
    core: Core<N>,
}

impl<const N: usize> Rk4<N> {
    /// Creates the integrator, validating `options`; `fixed_step` must be
    /// `Some(h)` (else [`OdeError::InvalidOption`] naming `fixed_step`).
    pub fn new(options: Options<N>) -> Result<Self, OdeError> {
        if options.fixed_step.is_none() {
            return Err(OdeError::InvalidOption {
                field: "fixed_step",
                value: f64::NAN,
                hint: "RK4 has no error control: set Options::fixed_step = Some(h), or use DOPRI5/DOP853",
            });
        }
        Ok(Rk4 {
            core: Core::new(options, 4.0, 0.0, 4.0)?,
        })
    }
}

impl<const N: usize> Integrator<N> for Rk4<N> {
    fn reset<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &SVector<f64, N>,
        keep_step: bool,
    ) -> Result<(), OdeError> {
        self.core.reset(sys, t, y, keep_step)
    }

    fn step<S: OdeSystem<N>>(&mut self, sys: &S, t_bound: f64) -> Result<(), OdeError> {
        self.core.step(sys, t_bound, |sys, _opts, t, y, f, h, y_new, _f_new, stats| {
            let mut k2 = SVector::<f64, N>::zeros();
            let mut k3 = SVector::<f64, N>::zeros();
            let mut k4 = SVector::<f64, N>::zeros();
            let hh = 0.5 * h;
            sys.rhs(t + hh, &(y + f * hh), &mut k2);
            sys.rhs(t + hh, &(y + k2 * hh), &mut k3);
            sys.rhs(t + h, &(y + k3 * h), &mut k4);
            stats.rhs_evals += 3;
            *y_new = y + (f + (k2 + k3) * 2.0 + k4) * (h / 6.0);
            Trial {
                err: 0.0,
                f_new_done: false,
            }
        })
    }

    fn dense<S: OdeSystem<N>>(&mut self, _sys: &S, t: f64, out: &mut SVector<f64, N>) {
        let c = &self.core;
        if !c.has_step {
            *out = c.y;
            return;
        }
        // Hermite data of the full step, kept valid after truncation.
        let h = c.h_dense;
        let s = (t - c.t_prev) / h;
        let (y0, y1, f0, f1) = (&c.y_prev, &c.y_end, &c.f_prev, &c.f_end);
        let d = y1 - y0;
        *out = y0 * (1.0 - s)
            + y1 * s
            + (d * (1.0 - 2.0 * s) + f0 * ((s - 1.0) * h) + f1 * (s * h)) * (s * (s - 1.0));
    }

    fn truncate<S: OdeSystem<N>>(&mut self, sys: &S, t_new: f64) -> Result<(), OdeError> {
        self.core.check_truncate(t_new)?;
        let mut y = SVector::<f64, N>::zeros();
        self.dense(sys, t_new, &mut y);
        if t_new == self.core.t {
            y = self.core.y;
        }
        self.core.apply_truncate(sys, t_new, &y)
    }

    core_accessors!();

    fn name(&self) -> &'static str {
        "RK4"
    }
}
