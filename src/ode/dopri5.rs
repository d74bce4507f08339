use super::core::{Core, Trial, TrialIo};
use super::erk::{explicit_rk_impls, ExplicitRk, RkTableau};
use super::kernels::{axpy, combo};
use super::{controller::scale, Integrator, OdeError, OdeSystem, Options, Stats};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

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
/// Shampine's 4th-order continuous extension, as in Hairer's `dopri5.f`. Seven stages,
/// first-same-as-last, so an accepted step costs 6 evaluations of $f$. The local error estimate
/// is the difference between the 5th-order propagating solution and the embedded 4th-order one.
///
/// Dense output on $[t_{\text{prev}}, t_{\text{prev}} + h]$ with
/// $\theta = (t - t_{\text{prev}})/h$:
/// $$u(\theta) = r_1 + \theta\big(r_2 + (1-\theta)\big(r_3 + \theta\thinspace(r_4 + (1-\theta) r_5)\big)\big)$$
/// with $r_1 = y_0$, $r_2 = y_1 - y_0$, $r_3 = h k_1 - r_2$,
/// $r_4 = r_2 - h k_7 - r_3$, $r_5 = h \sum_j d_j k_j$.
///
/// All vectors are allocated by the constructor; stepping, dense output and
/// truncation never allocate.
#[derive(Debug, Clone)]
pub struct Dopri5<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// The shared explicit Runge–Kutta driver with this method's stages $k_1 \dots k_7$ and
    /// dense-output row $r_5$.
    rk: ExplicitRk<D, Tableau, 7, 1>,
}

/// The method's own part: stages, error estimate and $r_5$.
#[derive(Debug, Clone)]
struct Tableau;

explicit_rk_impls!(Dopri5);

impl RkTableau<7, 1> for Tableau {
    const NAME: &'static str = "DOPRI5";
    const CONTROL: (f64, f64, f64) = (5.0, 0.75, 5.0);

    #[inline(always)]
    fn trial<D, Sys>(
        sys: &Sys,
        k: &mut [OVector<f64, D>; 7],
        yt: &mut OVector<f64, D>,
        io: TrialIo<'_, D>,
    ) -> Trial
    where
        D: Dim,
        DefaultAllocator: Allocator<D>,
        Sys: OdeSystem<D>,
    {
        let TrialIo {
            opts,
            n_ctrl,
            t,
            y,
            h,
            y_new,
            f_new,
            stats,
            ..
        } = io;
        axpy(yt.as_mut_slice(), y.as_slice(), k[0].as_slice(), h * A21);
        sys.rhs(t + C2 * h, yt, &mut k[1]);
        combo!(yt, y, h, [k[0] => A31, k[1] => A32]);
        sys.rhs(t + C3 * h, yt, &mut k[2]);
        combo!(yt, y, h, [k[0] => A41, k[1] => A42, k[2] => A43]);
        sys.rhs(t + C4 * h, yt, &mut k[3]);
        combo!(yt, y, h, [k[0] => A51, k[1] => A52, k[2] => A53, k[3] => A54]);
        sys.rhs(t + C5 * h, yt, &mut k[4]);
        combo!(yt, y, h, [
            k[0] => A61, k[1] => A62, k[2] => A63, k[3] => A64, k[4] => A65,
        ]);
        sys.rhs(t + h, yt, &mut k[5]);
        combo!(y_new, y, h, [
            k[0] => A71, k[2] => A73, k[3] => A74, k[4] => A75, k[5] => A76,
        ]);
        sys.rhs(t + h, y_new, &mut k[6]);
        f_new.copy_from(&k[6]);
        stats.rhs_evals += 6;
        Trial {
            err: error_norm(opts, n_ctrl, y, y_new, k, h),
            f_new_done: true,
        }
    }

    fn higher_rows<D, Sys>(
        _sys: &Sys,
        c: &mut Core<D>,
        k: &mut [OVector<f64, D>; 7],
        _yt: &mut OVector<f64, D>,
        rows: &mut [OVector<f64, D>; 1],
    ) where
        D: Dim,
        DefaultAllocator: Allocator<D>,
        Sys: OdeSystem<D>,
    {
        let h = c.h_dense;
        let n = c.y.len();
        let ks: [&[f64]; 7] = std::array::from_fn(|j| &k[j].as_slice()[..n]);
        let r5 = &mut rows[0].as_mut_slice()[..n];
        for i in 0..n {
            r5[i] = (ks[0][i] * D1
                + ks[2][i] * D3
                + ks[3][i] * D4
                + ks[4][i] * D5
                + ks[5][i] * D6
                + ks[6][i] * D7)
                * h;
        }
    }

    #[inline(always)]
    fn higher(r: &[&[f64]; 1], i: usize, _s: f64, _s1: f64) -> f64 {
        r[0][i]
    }
}

/// The scaled RMS norm of the local error estimate $h \sum_j e_j k_j$ of the step from `y`
/// to `y_new`.
#[inline(always)]
fn error_norm<D>(
    opts: &Options<D>,
    n_ctrl: f64,
    y: &OVector<f64, D>,
    y_new: &OVector<f64, D>,
    k: &[OVector<f64, D>; 7],
    h: f64,
) -> f64
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
{
    let n = y.len();
    let (ys, yn) = (&y.as_slice()[..n], &y_new.as_slice()[..n]);
    let ks: [&[f64]; 7] = std::array::from_fn(|j| &k[j].as_slice()[..n]);
    let mut sum = 0.0;
    for i in 0..n {
        let e = h
            * (E1 * ks[0][i]
                + E3 * ks[2][i]
                + E4 * ks[3][i]
                + E5 * ks[4][i]
                + E6 * ks[5][i]
                + E7 * ks[6][i]);
        let sk = scale(opts, i, ys[i], yn[i]);
        sum += (e / sk) * (e / sk);
    }
    (sum / n_ctrl).sqrt()
}
