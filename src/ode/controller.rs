//! Step-size control: error scaling, Gustafsson's PI controller (in Hairer's
//! formulation) and Hairer's automatic initial step.

use super::{OdeSystem, Options, Stats};
use nalgebra::SVector;

/// Error scale $s_i = \mathrm{atol}_i + \mathrm{rtol}_i \max(|y_{0,i}|, |y_{1,i}|)$.
#[inline]
pub(crate) fn scale<const N: usize>(
    opts: &Options<N>,
    i: usize,
    y0: &SVector<f64, N>,
    y1: &SVector<f64, N>,
) -> f64 {
    opts.atol.get(i) + opts.rtol.get(i) * y0[i].abs().max(y1[i].abs())
}

/// PI step-size controller.
///
/// With $q$ the order used for the exponent (5 for DOPRI5, 8 for DOP853) and
/// $c$ Hairer's coupling constant (0.75 for DOPRI5, 0.2 for DOP853), the
/// exponent on the current error is $\alpha = 1/q - c\beta$ and the step
/// ratio on acceptance is
/// $\mathrm{clamp}(\mathrm{safety}\cdot\mathrm{err}^{-\alpha}\,
/// \mathrm{err}_{\text{old}}^{\beta}, \mathrm{fac\_min}, \mathrm{fac\_max})$,
/// where $\mathrm{err}_{\text{old}} = \max(\mathrm{err}_{\text{prev. accepted}}, 10^{-4})$.
/// After a rejection the ratio is $\max(\mathrm{fac\_min}, \mathrm{safety}\cdot
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
    pub(crate) fn accept<const N: usize>(&mut self, err: f64, opts: &Options<N>) -> f64 {
        let alpha = self.inv_q - self.coupling * self.beta;
        let ratio = opts.safety * err.powf(-alpha) * self.err_old.powf(self.beta);
        self.err_old = err.max(1e-4);
        if ratio.is_nan() {
            return opts.fac_max;
        }
        ratio.clamp(opts.fac_min, opts.fac_max)
    }

    /// Step ratio after a rejected step (`err > 1`).
    pub(crate) fn reject<const N: usize>(&self, err: f64, opts: &Options<N>) -> f64 {
        let alpha = self.inv_q - self.coupling * self.beta;
        (opts.safety * err.powf(-alpha)).clamp(opts.fac_min, 1.0)
    }
}

/// Hairer's initial step selection (`HINIT` of DOPRI5/DOP853), with RMS
/// norms: $d_0 = \|y_0\|$, $d_1 = \|f_0\|$, $h_0 = 0.01\, d_0/d_1$ (or
/// $10^{-6}$ if either is tiny), one explicit Euler step to estimate
/// $d_2 = \|f(t+h_0, y_0+h_0f_0) - f_0\|/h_0$, and
/// $h = \min\big(100 h_0,\ (0.01/\max(d_1,d_2))^{1/p},\ h_{\max}\big)$,
/// raised to at least $\max(h_{\min}, 100\,\varepsilon\,|t|)$.
pub(crate) fn initial_step<const N: usize, S: OdeSystem<N>>(
    sys: &S,
    t: f64,
    y: &SVector<f64, N>,
    f: &SVector<f64, N>,
    order: f64,
    opts: &Options<N>,
    stats: &mut Stats,
) -> f64 {
    let n = N.max(1) as f64;
    let mut dnf = 0.0;
    let mut dny = 0.0;
    for i in 0..N {
        let sk = scale(opts, i, y, y);
        dnf += (f[i] / sk).powi(2);
        dny += (y[i] / sk).powi(2);
    }
    dnf /= n;
    dny /= n;
    let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
        1e-6
    } else {
        (dny / dnf).sqrt() * 0.01
    };
    h = h.min(opts.h_max);
    let y1 = y + f * h;
    let mut f1 = SVector::<f64, N>::zeros();
    sys.rhs(t + h, &y1, &mut f1);
    stats.rhs_evals += 1;
    let mut der2 = 0.0;
    for i in 0..N {
        let sk = scale(opts, i, y, y);
        der2 += ((f1[i] - f[i]) / sk).powi(2);
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
