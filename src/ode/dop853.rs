// The coefficients are kept with all the digits Hairer publishes, so that
// they can be checked against the source; Rust rounds them correctly.
#![allow(clippy::excessive_precision)]

use super::core::{Core, Trial, TrialIo};
use super::erk::{explicit_rk_impls, ExplicitRk, RkTableau};
use super::kernels::{axpy, combo};
use super::{controller::scale, Integrator, OdeError, OdeSystem, Options, Stats};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

// Nodes.
const C2: f64 = 0.526001519587677318785587544488e-01;
const C3: f64 = 0.789002279381515978178381316732e-01;
const C4: f64 = 0.118350341907227396726757197510e+00;
const C5: f64 = 0.281649658092772603273242802490e+00;
const C6: f64 = 0.333333333333333333333333333333e+00;
const C7: f64 = 0.25e+00;
const C8: f64 = 0.307692307692307692307692307692e+00;
const C9: f64 = 0.651282051282051282051282051282e+00;
const C10: f64 = 0.6e+00;
const C11: f64 = 0.857142857142857142857142857142e+00;
const C14: f64 = 0.1e+00;
const C15: f64 = 0.2e+00;
const C16: f64 = 0.777777777777777777777777777778e+00;

// 8th-order weights.
const B1: f64 = 5.42937341165687622380535766363e-2;
const B6: f64 = 4.45031289275240888144113950566e0;
const B7: f64 = 1.89151789931450038304281599044e0;
const B8: f64 = -5.8012039600105847814672114227e0;
const B9: f64 = 3.1116436695781989440891606237e-1;
const B10: f64 = -1.52160949662516078556178806805e-1;
const B11: f64 = 2.01365400804030348374776537501e-1;
const B12: f64 = 4.47106157277725905176885569043e-2;

// 3rd-order error estimate weights.
const BHH1: f64 = 0.244094488188976377952755905512e+00;
const BHH2: f64 = 0.733846688281611857341361741547e+00;
const BHH3: f64 = 0.220588235294117647058823529412e-01;

// 5th-order error estimate weights.
const ER1: f64 = 0.1312004499419488073250102996e-01;
const ER6: f64 = -0.1225156446376204440720569753e+01;
const ER7: f64 = -0.4957589496572501915214079952e+00;
const ER8: f64 = 0.1664377182454986536961530415e+01;
const ER9: f64 = -0.3503288487499736816886487290e+00;
const ER10: f64 = 0.3341791187130174790297318841e+00;
const ER11: f64 = 0.8192320648511571246570742613e-01;
const ER12: f64 = -0.2235530786388629525884427845e-01;

// Runge–Kutta matrix (A_ij multiplies stage j in stage i).
const A21: f64 = 5.26001519587677318785587544488e-2;
const A31: f64 = 1.97250569845378994544595329183e-2;
const A32: f64 = 5.91751709536136983633785987549e-2;
const A41: f64 = 2.95875854768068491816892993775e-2;
const A43: f64 = 8.87627564304205475450678981324e-2;
const A51: f64 = 2.41365134159266685502369798665e-1;
const A53: f64 = -8.84549479328286085344864962717e-1;
const A54: f64 = 9.24834003261792003115737966543e-1;
const A61: f64 = 3.7037037037037037037037037037e-2;
const A64: f64 = 1.70828608729473871279604482173e-1;
const A65: f64 = 1.25467687566822425016691814123e-1;
const A71: f64 = 3.7109375e-2;
const A74: f64 = 1.70252211019544039314978060272e-1;
const A75: f64 = 6.02165389804559606850219397283e-2;
const A76: f64 = -1.7578125e-2;
const A81: f64 = 3.70920001185047927108779319836e-2;
const A84: f64 = 1.70383925712239993810214054705e-1;
const A85: f64 = 1.07262030446373284651809199168e-1;
const A86: f64 = -1.53194377486244017527936158236e-2;
const A87: f64 = 8.27378916381402288758473766002e-3;
const A91: f64 = 6.24110958716075717114429577812e-1;
const A94: f64 = -3.36089262944694129406857109825e0;
const A95: f64 = -8.68219346841726006818189891453e-1;
const A96: f64 = 2.75920996994467083049415600797e1;
const A97: f64 = 2.01540675504778934086186788979e1;
const A98: f64 = -4.34898841810699588477366255144e1;
const A101: f64 = 4.77662536438264365890433908527e-1;
const A104: f64 = -2.48811461997166764192642586468e0;
const A105: f64 = -5.90290826836842996371446475743e-1;
const A106: f64 = 2.12300514481811942347288949897e1;
const A107: f64 = 1.52792336328824235832596922938e1;
const A108: f64 = -3.32882109689848629194453265587e1;
const A109: f64 = -2.03312017085086261358222928593e-2;
const A111: f64 = -9.3714243008598732571704021658e-1;
const A114: f64 = 5.18637242884406370830023853209e0;
const A115: f64 = 1.09143734899672957818500254654e0;
const A116: f64 = -8.14978701074692612513997267357e0;
const A117: f64 = -1.85200656599969598641566180701e1;
const A118: f64 = 2.27394870993505042818970056734e1;
const A119: f64 = 2.49360555267965238987089396762e0;
const A1110: f64 = -3.0467644718982195003823669022e0;
const A121: f64 = 2.27331014751653820792359768449e0;
const A124: f64 = -1.05344954667372501984066689879e1;
const A125: f64 = -2.00087205822486249909675718444e0;
const A126: f64 = -1.79589318631187989172765950534e1;
const A127: f64 = 2.79488845294199600508499808837e1;
const A128: f64 = -2.85899827713502369474065508674e0;
const A129: f64 = -8.87285693353062954433549289258e0;
const A1210: f64 = 1.23605671757943030647266201528e1;
const A1211: f64 = 6.43392746015763530355970484046e-1;

// Extra stages for dense output (stage 13 is f(t + h, y_new)).
const A141: f64 = 5.61675022830479523392909219681e-2;
const A147: f64 = 2.53500210216624811088794765333e-1;
const A148: f64 = -2.46239037470802489917441475441e-1;
const A149: f64 = -1.24191423263816360469010140626e-1;
const A1410: f64 = 1.5329179827876569731206322685e-1;
const A1411: f64 = 8.20105229563468988491666602057e-3;
const A1412: f64 = 7.56789766054569976138603589584e-3;
const A1413: f64 = -8.298e-3;
const A151: f64 = 3.18346481635021405060768473261e-2;
const A156: f64 = 2.83009096723667755288322961402e-2;
const A157: f64 = 5.35419883074385676223797384372e-2;
const A158: f64 = -5.49237485713909884646569340306e-2;
const A1511: f64 = -1.08347328697249322858509316994e-4;
const A1512: f64 = 3.82571090835658412954920192323e-4;
const A1513: f64 = -3.40465008687404560802977114492e-4;
const A1514: f64 = 1.41312443674632500278074618366e-1;
const A161: f64 = -4.28896301583791923408573538692e-1;
const A166: f64 = -4.69762141536116384314449447206e0;
const A167: f64 = 7.68342119606259904184240953878e0;
const A168: f64 = 4.06898981839711007970213554331e0;
const A169: f64 = 3.56727187455281109270669543021e-1;
const A1613: f64 = -1.39902416515901462129418009734e-3;
const A1614: f64 = 2.9475147891527723389556272149e0;
const A1615: f64 = -9.15095847217987001081870187138e0;

// Dense-output coefficients: row r (4..7) weights of stages 1, 6..16.
const D4: [f64; 12] = [
    -0.84289382761090128651353491142e+01,
    0.56671495351937776962531783590e+00,
    -0.30689499459498916912797304727e+01,
    0.23846676565120698287728149680e+01,
    0.21170345824450282767155149946e+01,
    -0.87139158377797299206789907490e+00,
    0.22404374302607882758541771650e+01,
    0.63157877876946881815570249290e+00,
    -0.88990336451333310820698117400e-01,
    0.18148505520854727256656404962e+02,
    -0.91946323924783554000451984436e+01,
    -0.44360363875948939664310572000e+01,
];
const D5: [f64; 12] = [
    0.10427508642579134603413151009e+02,
    0.24228349177525818288430175319e+03,
    0.16520045171727028198505394887e+03,
    -0.37454675472269020279518312152e+03,
    -0.22113666853125306036270938578e+02,
    0.77334326684722638389603898808e+01,
    -0.30674084731089398182061213626e+02,
    -0.93321305264302278729567221706e+01,
    0.15697238121770843886131091075e+02,
    -0.31139403219565177677282850411e+02,
    -0.93529243588444783865713862664e+01,
    0.35816841486394083752465898540e+02,
];
const D6: [f64; 12] = [
    0.19985053242002433820987653617e+02,
    -0.38703730874935176555105901742e+03,
    -0.18917813819516756882830838328e+03,
    0.52780815920542364900561016686e+03,
    -0.11573902539959630126141871134e+02,
    0.68812326946963000169666922661e+01,
    -0.10006050966910838403183860980e+01,
    0.77771377980534432092869265740e+00,
    -0.27782057523535084065932004339e+01,
    -0.60196695231264120758267380846e+02,
    0.84320405506677161018159903784e+02,
    0.11992291136182789328035130030e+02,
];
const D7: [f64; 12] = [
    -0.25693933462703749003312586129e+02,
    -0.15418974869023643374053993627e+03,
    -0.23152937917604549567536039109e+03,
    0.35763911791061412378285349910e+03,
    0.93405324183624310003907691704e+02,
    -0.37458323136451633156875139351e+02,
    0.10409964950896230045147246184e+03,
    0.29840293426660503123344363579e+02,
    -0.43533456590011143754432175058e+02,
    0.96324553959188282948394950600e+02,
    -0.39177261675615439165231486172e+02,
    -0.14972683625798562581422125276e+03,
];
/// Stage indices (0-based) multiplied by the entries of `D4`..`D7`.
const D_STAGES: [usize; 12] = [0, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15];

/// Dormand–Prince 8(5,3) integrator with 7th-order dense output.
///
/// The method of Hairer's `dop853.f`. Twelve stages per step (first-same-as-last: 12
/// evaluations of $f$ per accepted step, 11 per rejected one). The error estimate combines the
/// 5th-order estimate $e_5$ and the 3rd-order estimate $e_3$ component by component,
/// $$\mathrm{err} = |h|\thinspace\sqrt{\frac1N\sum_i \frac{a_i^2}{a_i + 0.01\thinspace b_i}},
/// \qquad a_i = (e_{5,i}/s_i)^2,\quad b_i = (e_{3,i}/s_i)^2$$
/// (terms with $a_i + b_i = 0$ left out), which behaves like an 8th-order estimate. Hairer's
/// code combines the sums instead, $(\sum a_i)^2/(\sum a_i + 0.01\sum b_i)$, never more than
/// the sum above (Sedrakyan's inequality), equal for one component: a large $e_3$ of smooth
/// components then shrank the estimate of others, and on a rotor whose contact made a
/// component stiff (steps at DOP853's stability bound, where $e_5$ and $e_3$ of that
/// component are alike) the steps' true local errors were up to 47 times the estimate and
/// the run 400 `rtol` off (docs/integrators.md, "DOP853's error estimate"). Dense
/// output needs three more stages ($k_{14}, k_{15}, k_{16}$), computed lazily on the first call
/// of `dense` after a step.
///
/// Dense output on $[t_{\text{prev}}, t_{\text{prev}} + h]$ with
/// $\theta = (t - t_{\text{prev}})/h$, $\bar\theta = 1 - \theta$:
/// $$u(\theta) = r_1 + \theta\big(r_2 + \bar\theta\big(r_3 + \theta\big(r_4 + \bar\theta\thinspace(r_5 + \theta(r_6 + \bar\theta(r_7 + \theta r_8)))\big)\big)\big)$$
/// with $r_1 = y_0$, $r_2 = y_1 - y_0$, $r_3 = h k_1 - r_2$,
/// $r_4 = r_2 - h k_{13} - r_3$ and $r_{5..8} = h\sum_j d_{r,j} k_j$ over
/// stages $1, 6, \dots, 16$.
///
/// Every stage, dense-output coefficient and scratch vector is allocated by
/// the constructor: stepping, dense output and truncation never allocate,
/// also for [`Dyn`](nalgebra::Dyn).
#[derive(Debug, Clone)]
pub struct Dop853<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// The shared explicit Runge–Kutta driver with this method's stages $k_1 \dots k_{16}$
    /// ($k_{13} = f(t, y)$ at the step end, $k_{14} \dots k_{16}$ lazily) and dense-output rows
    /// $r_5 \dots r_8$.
    rk: ExplicitRk<D, Tableau, 16, 4>,
}

/// The method's own part: stages, error estimate, the extra stages and rows of dense output.
#[derive(Debug, Clone)]
struct Tableau;

explicit_rk_impls!(Dop853);

impl RkTableau<16, 4> for Tableau {
    const NAME: &'static str = "DOP853";
    const CONTROL: (f64, f64, f64) = (8.0, 0.2, 8.0);

    #[inline(always)]
    fn trial<D, Sys>(
        sys: &Sys,
        k: &mut [OVector<f64, D>; 16],
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
            stats,
            ..
        } = io;
        stages(sys, k, yt, t, y, h);
        stats.rhs_evals += 11;
        Trial {
            err: new_point_and_error(opts, n_ctrl, y, k, h, y_new),
            f_new_done: false,
        }
    }

    /// The three extra stages $k_{14}, k_{15}, k_{16}$, then $r_5 \dots r_8$.
    fn higher_rows<D, Sys>(
        sys: &Sys,
        c: &mut Core<D>,
        k: &mut [OVector<f64, D>; 16],
        yt: &mut OVector<f64, D>,
        rows: &mut [OVector<f64, D>; 4],
    ) where
        D: Dim,
        DefaultAllocator: Allocator<D>,
        Sys: OdeSystem<D>,
    {
        let h = c.h_dense;
        extra_stages(sys, k, yt, c.t_prev, &c.y_prev, &c.f_end, h);
        c.stats.rhs_evals += 3;
        let n = c.y.len();
        for (r, d) in rows.iter_mut().zip([D4, D5, D6, D7].iter()) {
            let r = &mut r.as_mut_slice()[..n];
            for i in 0..n {
                // Summed from 0 in stage order, as the vector sum it replaces.
                let mut acc = 0.0;
                for (j, &s) in D_STAGES.iter().enumerate() {
                    acc += k[s][i] * d[j];
                }
                r[i] = acc * h;
            }
        }
    }

    #[inline(always)]
    fn higher(r: &[&[f64]; 4], i: usize, s: f64, s1: f64) -> f64 {
        r[0][i] + (r[1][i] + (r[2][i] + r[3][i] * s) * s1) * s
    }
}

/// The extra stages $k_{14}, k_{15}, k_{16}$ of dense output for the step of size `h` from
/// `(t, y)`, with $k_{13}$ = `f_end` $= f(t + h, y_1)$.
#[inline]
fn extra_stages<D, S>(
    sys: &S,
    k: &mut [OVector<f64, D>; 16],
    yt: &mut OVector<f64, D>,
    t: f64,
    y: &OVector<f64, D>,
    f_end: &OVector<f64, D>,
    h: f64,
) where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
{
    k[12].copy_from(f_end);
    combo!(yt, y, h, [
        k[0] => A141, k[6] => A147, k[7] => A148, k[8] => A149,
        k[9] => A1410, k[10] => A1411, k[11] => A1412, k[12] => A1413,
    ]);
    sys.rhs(t + C14 * h, yt, &mut k[13]);
    combo!(yt, y, h, [
        k[0] => A151, k[5] => A156, k[6] => A157, k[7] => A158,
        k[10] => A1511, k[11] => A1512, k[12] => A1513, k[13] => A1514,
    ]);
    sys.rhs(t + C15 * h, yt, &mut k[14]);
    combo!(yt, y, h, [
        k[0] => A161, k[5] => A166, k[6] => A167, k[7] => A168,
        k[8] => A169, k[12] => A1613, k[13] => A1614, k[14] => A1615,
    ]);
    sys.rhs(t + C16 * h, yt, &mut k[15]);
}

/// The eleven stages $k_2 \dots k_{12}$ of a step of size `h` from `(t, y)`, with $k_1 = f(t, y)$
/// already in `k[0]`; `yt` is the scratch argument. Stage order and sums as in Hairer's code.
#[inline]
fn stages<D, S>(
    sys: &S,
    k: &mut [OVector<f64, D>; 16],
    yt: &mut OVector<f64, D>,
    t: f64,
    y: &OVector<f64, D>,
    h: f64,
) where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
{
    axpy(yt.as_mut_slice(), y.as_slice(), k[0].as_slice(), h * A21);
    sys.rhs(t + C2 * h, yt, &mut k[1]);
    combo!(yt, y, h, [k[0] => A31, k[1] => A32]);
    sys.rhs(t + C3 * h, yt, &mut k[2]);
    combo!(yt, y, h, [k[0] => A41, k[2] => A43]);
    sys.rhs(t + C4 * h, yt, &mut k[3]);
    combo!(yt, y, h, [k[0] => A51, k[2] => A53, k[3] => A54]);
    sys.rhs(t + C5 * h, yt, &mut k[4]);
    combo!(yt, y, h, [k[0] => A61, k[3] => A64, k[4] => A65]);
    sys.rhs(t + C6 * h, yt, &mut k[5]);
    combo!(yt, y, h, [k[0] => A71, k[3] => A74, k[4] => A75, k[5] => A76]);
    sys.rhs(t + C7 * h, yt, &mut k[6]);
    combo!(yt, y, h, [
        k[0] => A81, k[3] => A84, k[4] => A85, k[5] => A86, k[6] => A87,
    ]);
    sys.rhs(t + C8 * h, yt, &mut k[7]);
    combo!(yt, y, h, [
        k[0] => A91, k[3] => A94, k[4] => A95, k[5] => A96, k[6] => A97, k[7] => A98,
    ]);
    sys.rhs(t + C9 * h, yt, &mut k[8]);
    combo!(yt, y, h, [
        k[0] => A101, k[3] => A104, k[4] => A105, k[5] => A106, k[6] => A107,
        k[7] => A108, k[8] => A109,
    ]);
    sys.rhs(t + C10 * h, yt, &mut k[9]);
    combo!(yt, y, h, [
        k[0] => A111, k[3] => A114, k[4] => A115, k[5] => A116, k[6] => A117,
        k[7] => A118, k[8] => A119, k[9] => A1110,
    ]);
    sys.rhs(t + C11 * h, yt, &mut k[10]);
    combo!(yt, y, h, [
        k[0] => A121, k[3] => A124, k[4] => A125, k[5] => A126, k[6] => A127,
        k[7] => A128, k[8] => A129, k[9] => A1210, k[10] => A1211,
    ]);
    sys.rhs(t + h, yt, &mut k[11]);
}

/// The 8th-order point into `y_new` and, in the same pass over the components, the combined
/// error estimate (the struct docs' formula; 0 errors give a denominator of 1).
#[inline]
fn new_point_and_error<D>(
    opts: &Options<D>,
    n_ctrl: f64,
    y: &OVector<f64, D>,
    k: &[OVector<f64, D>; 16],
    h: f64,
    y_new: &mut OVector<f64, D>,
) -> f64
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
{
    // The new point and both error estimates in one pass.
    let n = y.len();
    let ys = &y.as_slice()[..n];
    let yn = &mut y_new.as_mut_slice()[..n];
    let ks: [&[f64]; 12] = std::array::from_fn(|j| &k[j].as_slice()[..n]);
    let mut err = 0.0;
    for i in 0..n {
        let incr = ks[0][i] * B1
            + ks[5][i] * B6
            + ks[6][i] * B7
            + ks[7][i] * B8
            + ks[8][i] * B9
            + ks[9][i] * B10
            + ks[10][i] * B11
            + ks[11][i] * B12;
        yn[i] = ys[i] + incr * h;
        let sk = scale(opts, i, ys[i], yn[i]);
        let e3 = incr - BHH1 * ks[0][i] - BHH2 * ks[8][i] - BHH3 * ks[11][i];
        let e5 = ER1 * ks[0][i]
            + ER6 * ks[5][i]
            + ER7 * ks[6][i]
            + ER8 * ks[7][i]
            + ER9 * ks[8][i]
            + ER10 * ks[9][i]
            + ER11 * ks[10][i]
            + ER12 * ks[11][i];
        let (a, b) = ((e5 / sk) * (e5 / sk), (e3 / sk) * (e3 / sk));
        let deno = a + 0.01 * b;
        // Zero for a component without error (or excluded: `sk` infinite); NaN passes on.
        if deno != 0.0 {
            err += a * a / deno;
        }
    }
    h.abs() * (err / n_ctrl).sqrt()
}
