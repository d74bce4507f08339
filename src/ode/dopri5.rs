//! DOPRI5: the Dormand–Prince 5(4) pair with Shampine's 4th-order continuous
//! extension (as in Hairer's `dopri5.f`).
//!
//! Seven stages, first-same-as-last, so an accepted step costs 6 evaluations
//! of $f$. The local error estimate is the difference between the 5th-order
//! propagating solution and the embedded 4th-order one.

use super::core::{core_accessors, Core, Trial};
use super::{controller::scale, Integrator, OdeError, OdeSystem, Options, Stats};
use nalgebra::SVector;

const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;

const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
const A71: f64 = 35.0 / 384.0;
const A73: f64 = 500.0 / 1113.0;
const A74: f64 = 125.0 / 192.0;
const A75: f64 = -2187.0 / 6784.0;
const A76: f64 = 11.0 / 84.0;

// Error coefficients: 5th-order weights minus embedded 4th-order weights.
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

// Dense output (Shampine 1986).
const D1: f64 = -12715105075.0 / 11282082432.0;
const D3: f64 = 87487479700.0 / 32700410799.0;
const D4: f64 = -10690763975.0 / 1880347072.0;
const D5: f64 = 701980252875.0 / 199316789632.0;
const D6: f64 = -1453857185.0 / 822651844.0;
const D7: f64 = 69997945.0 / 29380423.0;

/// Dormand–Prince 5(4) integrator with 4th-order dense output.
///
/// Dense output on $[t_{\text{prev}}, t_{\text{prev}} + h]$ with
/// $\theta = (t - t_{\text{prev}})/h$:
/// $$u(\theta) = r_1 + \theta\big(r_2 + (1-\theta)\big(r_3 + \theta\,(r_4 + (1-\theta) r_5)\big)\big)$$
/// with $r_1 = y_0$, $r_2 = y_1 - y_0$, $r_3 = h k_1 - r_2$,
/// $r_4 = r_2 - h k_7 - r_3$, $r_5 = h \sum_j d_j k_j$.
#[derive(Debug, Clone)]
pub struct Dopri5<const N: usize> {
    core: Core<N>,
    k: [SVector<f64, N>; 7],
    cont: [SVector<f64, N>; 5],
    dense_ready: bool,
}

impl<const N: usize> Dopri5<N> {
    /// Creates the integrator, validating `options` (typed error naming the
    /// offending field). Call [`Integrator::reset`] before stepping.
    pub fn new(options: Options<N>) -> Result<Self, OdeError> {
        let z = SVector::<f64, N>::zeros();
        Ok(Dopri5 {
            core: Core::new(options, 5.0, 0.75, 5.0)?,
            k: [z; 7],
            cont: [z; 5],
            dense_ready: false,
        })
    }

    fn prepare_dense(&mut self) {
        if self.dense_ready {
            return;
        }
        let c = &self.core;
        let h = c.h_dense;
        let k = &self.k;
        let ydiff = c.y_end - c.y_prev;
        let bspl = k[0] * h - ydiff;
        self.cont[0] = c.y_prev;
        self.cont[1] = ydiff;
        self.cont[2] = bspl;
        self.cont[3] = ydiff - k[6] * h - bspl;
        self.cont[4] = (k[0] * D1 + k[2] * D3 + k[3] * D4 + k[4] * D5 + k[5] * D6 + k[6] * D7) * h;
        self.dense_ready = true;
    }
}

impl<const N: usize> Integrator<N> for Dopri5<N> {
    fn reset<S: OdeSystem<N>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &SVector<f64, N>,
        keep_step: bool,
    ) -> Result<(), OdeError> {
        self.dense_ready = false;
        self.core.reset(sys, t, y, keep_step)
    }

    fn step<S: OdeSystem<N>>(&mut self, sys: &S, t_bound: f64) -> Result<(), OdeError> {
        let Dopri5 {
            core,
            k,
            dense_ready,
            ..
        } = self;
        let before = core.stats.steps;
        let r = core.step(sys, t_bound, |sys, opts, t, y, f, h, y_new, f_new, stats| {
            k[0] = *f;
            let mut yt = y + k[0] * (h * A21);
            sys.rhs(t + C2 * h, &yt, &mut k[1]);
            yt = y + (k[0] * A31 + k[1] * A32) * h;
            sys.rhs(t + C3 * h, &yt, &mut k[2]);
            yt = y + (k[0] * A41 + k[1] * A42 + k[2] * A43) * h;
            sys.rhs(t + C4 * h, &yt, &mut k[3]);
            yt = y + (k[0] * A51 + k[1] * A52 + k[2] * A53 + k[3] * A54) * h;
            sys.rhs(t + C5 * h, &yt, &mut k[4]);
            yt = y + (k[0] * A61 + k[1] * A62 + k[2] * A63 + k[3] * A64 + k[4] * A65) * h;
            sys.rhs(t + h, &yt, &mut k[5]);
            *y_new = y + (k[0] * A71 + k[2] * A73 + k[3] * A74 + k[4] * A75 + k[5] * A76) * h;
            sys.rhs(t + h, y_new, &mut k[6]);
            *f_new = k[6];
            stats.rhs_evals += 6;
            let mut sum = 0.0;
            for i in 0..N {
                let e = h
                    * (E1 * k[0][i]
                        + E3 * k[2][i]
                        + E4 * k[3][i]
                        + E5 * k[4][i]
                        + E6 * k[5][i]
                        + E7 * k[6][i]);
                let sk = scale(opts, i, y, y_new);
                sum += (e / sk) * (e / sk);
            }
            Trial {
                err: (sum / N.max(1) as f64).sqrt(),
                f_new_done: true,
            }
        });
        if core.stats.steps != before {
            *dense_ready = false;
        }
        r
    }

    fn dense<S: OdeSystem<N>>(&mut self, _sys: &S, t: f64, out: &mut SVector<f64, N>) {
        if !self.core.has_step {
            *out = self.core.y;
            return;
        }
        self.prepare_dense();
        let s = (t - self.core.t_prev) / self.core.h_dense;
        let s1 = 1.0 - s;
        let c = &self.cont;
        *out = c[0] + (c[1] + (c[2] + (c[3] + c[4] * s1) * s) * s1) * s;
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
        "DOPRI5"
    }
}
