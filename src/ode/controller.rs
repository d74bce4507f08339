//! Step-size control: error scaling, Gustafsson's PI controller (in Hairer's
//! formulation) and Hairer's automatic initial step.

use super::{OdeSystem, Options, Stats};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

/// Error scale $s_i = \mathrm{atol}_i + \mathrm{rtol}_i \max(|y_{0,i}|, |y_{1,i}|)$
/// of component `i` with values `y0i`, `y1i` (infinite for a component
/// excluded from error control).
#[inline(always)]
pub(crate) fn scale<D: Dim>(opts: &Options<D>, i: usize, y0i: f64, y1i: f64) -> f64
where
    DefaultAllocator: Allocator<D>,
{
    opts.atol.get(i) + opts.rtol.get(i) * y0i.abs().max(y1i.abs())
}

/// PI step-size controller.
///
/// With $q$ the order used for the exponent (5 for DOPRI5, 8 for DOP853) and
/// $c$ Hairer's coupling constant (0.75 for DOPRI5, 0.2 for DOP853), the
/// exponent on the current error is $\alpha = 1/q - c\beta$ and the step
/// ratio on acceptance is
/// $\mathrm{clamp}(\mathrm{safety}\cdot\mathrm{err}^{-\alpha}\thinspace
/// \mathrm{err}_{\text{old}}^{\beta}, \mathrm{fac\\_min}, \mathrm{fac\\_max})$,
/// where $\mathrm{err}_{\text{old}} = \max(\mathrm{err}_{\text{prev. accepted}}, 10^{-4})$.
/// After a rejection the ratio is $\max(\mathrm{fac\\_min}, \mathrm{safety}\cdot
/// \mathrm{err}^{-1/q})$ and the following accepted step may not grow.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PiController {
    pub inv_q: f64,
    pub coupling: f64,
    pub beta: f64,
    pub err_old: f64,
}

impl PiController {
    pub(crate) fn new(q: f64, coupling: f64, beta: f64) -> Self {
        PiController {
            inv_q: 1.0 / q,
            coupling,
            beta,
            err_old: 1e-4,
        }
    }

    /// Step ratio after an accepted step with error `err <= 1` (updates the
    /// memory).
    pub(crate) fn accept<D: Dim>(&mut self, err: f64, opts: &Options<D>) -> f64
    where
        DefaultAllocator: Allocator<D>,
    {
        let alpha = self.inv_q - self.coupling * self.beta;
        let ratio = opts.safety * err.powf(-alpha) * self.err_old.powf(self.beta);
        self.err_old = err.max(1e-4);
        if ratio.is_nan() {
            return opts.fac_max;
        }
        ratio.clamp(opts.fac_min, opts.fac_max)
    }

    /// Step ratio after a rejected step (`err > 1`).
    pub(crate) fn reject<D: Dim>(&self, err: f64, opts: &Options<D>) -> f64
    where
        DefaultAllocator: Allocator<D>,
    {
        let alpha = self.inv_q - self.coupling * self.beta;
        (opts.safety * err.powf(-alpha)).clamp(opts.fac_min, 1.0)
    }
}

/// Hairer's initial step selection (`HINIT` of DOPRI5/DOP853), with RMS
/// norms over the $n_c$ error-controlled components: $d_0 = \Vert y_0\Vert$,
/// $d_1 = \Vert f_0\Vert$, $h_0 = 0.01\thinspace d_0/d_1$ (or $10^{-6}$ if either is
/// tiny), one explicit Euler step to estimate
/// $d_2 = \Vert f(t+h_0, y_0+h_0f_0) - f_0\Vert/h_0$, and
/// $h = \min\big(100 h_0,\ (0.01/\max(d_1,d_2))^{1/p},\ h_{\max}\big)$,
/// raised to at least $\max(h_{\min}, 100\thinspace\varepsilon\thinspace|t|)$.
/// `y1` and `f1` are scratch vectors.
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step<D: Dim, S: OdeSystem<D>>(
    sys: &S,
    t: f64,
    y: &OVector<f64, D>,
    f: &OVector<f64, D>,
    order: f64,
    opts: &Options<D>,
    n_ctrl: f64,
    y1: &mut OVector<f64, D>,
    f1: &mut OVector<f64, D>,
    stats: &mut Stats,
) -> f64
where
    DefaultAllocator: Allocator<D>,
{
    let n = n_ctrl;
    let (ys, fs) = (y.as_slice(), f.as_slice());
    let mut dnf = 0.0;
    let mut dny = 0.0;
    for i in 0..ys.len() {
        let sk = scale(opts, i, ys[i], ys[i]);
        dnf += (fs[i] / sk).powi(2);
        dny += (ys[i] / sk).powi(2);
    }
    dnf /= n;
    dny /= n;
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
        1e-6
    } else {
        (dny / dnf).sqrt() * 0.01
    };
    h = h.min(opts.h_max);
    super::kernels::axpy(y1.as_mut_slice(), ys, fs, h);
    sys.rhs(t + h, y1, f1);
    stats.rhs_evals += 1;
    let mut der2 = 0.0;
    let f1s = f1.as_slice();
    for i in 0..ys.len() {
        let sk = scale(opts, i, ys[i], ys[i]);
        der2 += ((f1s[i] - fs[i]) / sk).powi(2);
    }
    let der2 = (der2 / n).sqrt() / h;
    let der12 = der2.max(dnf.sqrt());
    let h1 = if der12 > 1e-15 {
        (0.01 / der12).powf(1.0 / order)
    } else {
        // also taken for NaN: fall back to a cautious step
        (h * 1e-3).max(1e-6)
    };
    let h = (100.0 * h).min(h1).min(opts.h_max);
    // Never start below the step-size underflow threshold (Hairer's estimate
    // can be tiny when |y0| is small compared with atol but above it).
    let floor = opts.h_min.max(100.0 * f64::EPSILON * t.abs());
    if h.is_finite() && h > 0.0 {
        h.max(floor).min(opts.h_max)
    } else {
        1e-6f64.max(floor).min(opts.h_max)
    }
}
