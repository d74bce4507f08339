use nalgebra::allocator::Allocator;
use nalgebra::{Complex, DefaultAllocator, Dim, DimName, OVector};

mod dense;
mod forcing;

use super::core::{core_accessors, fit, zeros, Core, Trial, TrialIo};
use super::linear_part::{phi_functions, phi_functions_to, DiagonalLinearPart, Forcing, Slot};
use super::{controller::scale, Integrator, OdeError, OdeSystem, Options, Stats};
use dense::{quadratic_middle, quartic_coefficients, DenseStep, Quartic};

/// The four nonlinear stage values of one ETDRK4 step: $N_a$ at $t$, $N_b$, $N_c$ at
/// $t + \tau/2$, $N_d$ at $t + \tau$.
#[derive(Debug, Clone)]
struct Stages<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    n: [OVector<f64, D>; 4],
}

/// The coefficients of one step of length $\tau$ for one block: $e^{\tau\lambda/2}$,
/// $\tfrac\tau2\varphi_1(\tau\lambda/2)$, $e^{\tau\lambda}$, the weights
/// $\tau(\varphi_1 - 3\varphi_2 + 4\varphi_3)$, $\tau(2\varphi_2 - 4\varphi_3)$,
/// $\tau(-\varphi_2 + 4\varphi_3)$ at $\tau\lambda$, and $\tau\varphi_1(\tau\lambda)$ (the
/// response to a unit constant over $\tau$, for a declared forcing).
type Coefficients = [Complex<f64>; 7];

/// Per forced block, its exact response from zero to the declared forcing over the parts of one
/// substep of length $\tau$ from $t_0$: $[F(t_0, \tau/2), F(t_0 + \tau/2, \tau/2),
/// F(t_0, \tau)]$, $F(t_0, s) = \int_0^s e^{(s - r)\lambda} g(t_0 + r)\thinspace dr$.
type Increments = [Complex<f64>; 3];

/// The declared forcing's increments for one substep: the forced blocks (first components)
/// and, per component, their [`Increments`].
#[derive(Clone, Copy)]
struct Forced<'a> {
    blocks: &'a [usize],
    increments: &'a [Increments],
}

/// Exponential time differencing of order 4 (Cox and Matthews' ETDRK4) for
/// $y^\prime = L y + g(t) + N(t, y)$ with $L$ diagonal in real and complex blocks and $g$ an
/// optional harmonic and constant forcing of those blocks ([`OdeSystem::linear_part`],
/// [`DiagonalLinearPart`], [`DiagonalLinearPart::with_forcing`]), with step doubling for the
/// error, local extrapolation, and a dense output from the same $\varphi$-functions.
///
/// **The step** of length $\tau$ from $(t, u)$, per block of eigenvalue $\lambda$
/// ($E = e^{\tau\lambda}$, $E_2 = e^{\tau\lambda/2}$, $Q = \tfrac\tau2\varphi_1(\tau\lambda/2)$,
/// $N = f - L y - g$, $F$ the forcing's exact response below, 0 without one):
/// $$a = E_2 u + Q N_a + F(t, \tfrac\tau2),\quad b = E_2 u + Q N_b + F(t, \tfrac\tau2),\quad
/// c = E_2 a + Q(2N_c - N_a) + F(t + \tfrac\tau2, \tfrac\tau2),$$
/// $$u_1 = E u + F(t, \tau) + \tau\big[(\varphi_1 - 3\varphi_2 + 4\varphi_3) N_a +
/// (2\varphi_2 - 4\varphi_3) (N_b + N_c) + (-\varphi_2 + 4\varphi_3) N_d\big],$$
/// $\varphi_k = \varphi_k(\tau\lambda)$ ([`phi_functions`](super::phi_functions)). It is the
/// variation-of-constants formula $u_1 = e^{\tau L}u + \int_0^\tau e^{(\tau - s)L}(g(t + s) +
/// p(s))\thinspace ds$ with $p$ the quadratic through $N_a$, $(N_b + N_c)/2$ and $N_d$ at $0$,
/// $\tau/2$, $\tau$: **exact for the linear part whatever $|\lambda\tau|$, for the declared
/// forcing whatever $\omega\tau$, and for a rest $N$ constant or linear in time**, of classical
/// order 4 in $N$. A stiff mode ($\tau\operatorname{Re}\lambda \ll -1$) costs nothing:
/// $e^{\tau\lambda}$ vanishes and the weights tend to the quasi-static response. (Lawson's
/// method, $e^{\tau L}$ applied to an explicit method's stages, is not exact for a constant
/// force when $|\lambda\tau| \gg 1$; this one is.)
///
/// **The forcing** $g(t) = a\cos\omega t + b\sin\omega t + c = A_+e^{i\omega t} +
/// A_-e^{-i\omega t} + c$ of a block ($A_\pm = (a \mp ib)/2$) enters through its exact response
/// from zero over $[t_0, t_0 + s]$,
/// $$F(t_0, s) = \int_0^s e^{(s - r)\lambda}g(t_0 + r)\thinspace dr = A_+e^{i\omega t_0}
/// I(i\omega, s) + A_-e^{-i\omega t_0}I(-i\omega, s) + c\thinspace I(0, s),\quad
/// I(\mu, s) = s\thinspace e^{\mu s}\varphi_1(s(\lambda - \mu)).$$
/// This is ETDRK4 applied to the deviation $y - y_p$ from the forcing's particular solution
/// ($y_p = A_+e^{i\omega t}/(i\omega - \lambda) + \dots$, since $y_p(t_0 + s) =
/// e^{s\lambda}y_p(t_0) + F(t_0, s)$), written without $y_p$: it holds at and near resonance
/// ($\lambda = \pm i\omega$, or $\lambda = 0$ with a constant, where $I = s e^{\mu s}$), where
/// $y_p$ does not exist or is large.
///
/// **Error and step size.** Each step is taken once with $h$ and twice with $h/2$; the error
/// of the two half steps is $(u_{h/2,h/2} - u_h)/15$ (Richardson, order 4), measured in the
/// usual RMS norm, and the step keeps the extrapolated $u_{h/2,h/2} + (u_{h/2,h/2} - u_h)/15$
/// (local extrapolation, as DOPRI5 and DOP853 keep their higher order): of order 5, exact
/// where both are (the linear part, the declared forcing), its error well below the estimate,
/// so the global error follows the tolerance. (Keeping the two half steps, as before issue
/// 31's class L1, made each step's error the size of the estimate and the global error grow
/// with the number of steps, like $\mathrm{tol}^{4/5}$: on `tests/suite/ode/ode_etd4_dense.rs`'s
/// rotor in contact, 8.9 to 85 tol at the steps' ends for tol from $10^{-5}$ to $10^{-10}$,
/// against 0.18 to 0.32 tol extrapolated.) A trial costs 10 evaluations of $f$, plus
/// one at the accepted point; the controller is the PI controller of the explicit methods
/// with the exponent of an order-5 local error. The estimate sees what the stages integrate
/// by quadrature, $N$, and nothing else: the linear part and the **declared forcing are exact
/// in both and cancel**, so they set no step. **What is left in $N$ must be resolved by the
/// steps, as for any method**: a forcing not declared, and a rest that inherits the forcing's
/// frequency through the state (a contact force on a rotor whirling with its unbalance;
/// $N = \mu u$ beside a forcing $e^{i\omega t}$ oscillates with $\mu e^{i\omega t}/(i\omega -
/// \lambda - \mu)$). The estimate cannot see a step that does not resolve it: it samples $N$
/// at $t + kh/4$ only, so when $\omega h/4$ is near a multiple of $2\pi$ every sample sees
/// the same phase and the estimate vanishes while the step is wrong. Measured (issue 31) on
/// $u^\prime = (-0.1 + i)u + e^{10^4 it}$, $u(0) = 0.5$, rtol = atol $= 10^{-4}$ on
/// $[0, 20]$ (`tests/suite/ode/ode_etd4_forcing.rs`, with the local extrapolation): the
/// forcing in $N$, the solution 0.40 of its size off in 5 905 steps (1.19 off, with $\omega h$
/// up to 9 900, before it); declared, 4e-15 of its size in 5 steps. With a rest
/// $N = (-0.3 + 0.2i)u$ and $\omega = 100$, declared: 1.2e-2 of the size in 32 steps (119
/// tol; 9.7e-3 in 33 before issue 32's reordered rounding flipped one step's acceptance, 8.5e-3
/// before the extrapolation), 7.1e-9 with the steps capped at a quarter period (6e-8 before
/// the extrapolation). So declare the forcing, and where the rest depends on the forced motion
/// cap the steps at a fraction of its period ([`Options::h_max`];
/// [`crate::hybrid::simulate`] caps them at a quarter of the model's forcing period).
///
/// **Dense output** on each half step $[t_j, t_j + \tau]$ ($\tau = h/2$, $u_j$ its start) with
/// $\theta \in [0, 1]$: the variation-of-constants formula with $N$ replaced by the quartic
/// $p$ through $N$ at the step's $0, h/4, h/2, 3h/4, h$,
/// $$u(t_j + \theta\tau) = e^{\theta\tau L}u_j + F(t_j, \theta\tau) + \theta\tau\sum_{k=0}^4
/// k!\thinspace c_k\theta^k\varphi_{k+1}(\theta\tau L) + \theta^3\delta_j,$$
/// $c_k$ the coefficients of $p(t_j + \theta\tau)$ in powers of $\theta$
/// ([`phi_functions_to`](super::phi_functions_to)). $N$ at $0$ and $h/2$ are the half steps'
/// first stages, at $h$ it comes from the $f$ kept at the step's end, and at $h/4$, $3h/4$ it
/// is evaluated (once per step, at its first dense output: two evaluations of $f$) at states
/// given by the quadratic through one half step's stages (local error $O(h^4)$, which enters
/// the output multiplied by $h$). $\delta_j$, the difference between the half step's end
/// ($u_{j+1}$: the midpoint state, or the step's extrapolated end) and the quartic's value
/// there, of the size of the local error, makes the output continuous; entering as
/// $\theta^3$, it leaves the slope at each half step's start $L u_j + g + N(u_j) = f$, so a
/// restart is tangent to the flow (`tests/suite/ode/ode_dense_tangent.rs`), and its curvature
/// the quartic's: a guard at zero with a zero rate at a restart (a ring axis held at its
/// preload) is decided by the flow, not by $\delta_j$. (As $\theta^2$ it fired such a guard at
/// once on the linear-rotor fuzzer's case 3461 of seed `0x00F02210`: a III episode of length
/// 0, 3 150 `rtol` off afterwards.) So the output's
/// local error is $O(h^5)$, of the size of the step's error estimate, and it is exact for the
/// linear part and the forcing. (Before issue 31's class L1 it was the quadrature of the
/// quadratic through the stages alone, $O(h^4)$: 2.9 times the steps' error on
/// `ode_etd4_dense.rs`'s rotor at tol $10^{-5}$, and growing as the tolerance tightened.)
///
/// **Cost.** Every operation is per block: $O(N)$ a step besides the evaluations of $f$. A
/// trial evaluates the $\varphi$-functions three times per block, at $h\lambda/4$ and
/// $h\lambda/2$ (to $\varphi_5$, kept for the dense output) and at $h\lambda$; a forced
/// block's exact responses come from those $e^{s\lambda}$ in closed form,
/// $I(\pm i\omega, s) = (e^{s\lambda} - e^{\pm i\omega s})/(\lambda \mp i\omega)$ with the
/// inverses set up once, where $s|\lambda \mp i\omega| \ge 1/8$ (the cancellation costs at
/// most $7\times10^{-15}$ relative), the series above nearer resonance, and
/// $e^{\pm i\omega s}$ once per length for all blocks. A dense output costs one evaluation of
/// $\varphi_0, \dots, \varphi_5$ per block (the forced response from it) and five products
/// with the quartic's coefficients; the first one of a step two evaluations of $f$, its nodes
/// and jumps from the accepted trial's $\varphi$-functions and increments. (Issue 32: 41
/// evaluations of $\varphi$ a step per forced block with four event samples, now 7.) Nothing
/// is allocated after construction. The steps are set by $N$ (a contact, an undeclared
/// forcing), not by the fastest mode of $L$ or the declared forcing.
///
/// A system without [`OdeSystem::linear_part`] (or with one of another dimension) is refused
/// by [`Integrator::reset`] and [`Integrator::step`] ([`OdeError::NoLinearPart`]).
#[derive(Debug, Clone)]
pub struct Etd4<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    core: Core<D>,
    /// The full step's stages and the two half steps' of the trial.
    full: Stages<D>,
    halves_trial: [Stages<D>; 2],
    /// The state at mid-step (after the first half step) of the trial.
    u_mid_trial: OVector<f64, D>,
    /// The accepted step's half steps and mid-step state, for the dense output: swapped in
    /// from the trial's on acceptance, so that a step failing after a rejected trial leaves
    /// them as they were.
    halves: [Stages<D>; 2],
    u_mid: OVector<f64, D>,
    /// The full step's result.
    u_full: OVector<f64, D>,
    /// Scratch: stage states and $f$.
    stage: [OVector<f64, D>; 3],
    fk: OVector<f64, D>,
    /// Per block (at its first component): coefficients of a step of $h$ and of $h/2$, and
    /// the dense output's $\varphi$-functions at $h\lambda/4$ and $h\lambda/2$.
    coef_full: Vec<Coefficients>,
    coef_half: Vec<Coefficients>,
    coef_dense: Vec<DenseSets>,
    /// Per forced block: the declared forcing's increments of the full step and of the two
    /// half steps of the trial.
    increments: [Vec<Increments>; 3],
    /// The trial's $(t, h)$ that the coefficients and increments are of: the accepted step's
    /// when a step has just succeeded, which its dense output then reuses.
    coef_at: (f64, f64),
    /// The dense output's nodes of $N$ besides the half steps' first stages: at a quarter and
    /// three quarters of the accepted step (on the stages' quadratic) and at its end.
    quarters: [OVector<f64, D>; 2],
    n_end: OVector<f64, D>,
    /// Per half step and block, the dense output's quartic in powers of $\theta$.
    quartic: [Vec<Quartic>; 2],
    /// Per half step, what the dense output's quartic misses of the half step's end (added
    /// in proportion to $\theta^3$, so that the output is continuous and its slope and
    /// curvature at the half step's start are the quartic's).
    jumps: [OVector<f64, D>; 2],
    /// Whether `quarters`, `n_end`, `quartic` and `jumps` are those of the accepted step
    /// (computed at its first dense output).
    dense_ready: bool,
}

impl<D: DimName> Etd4<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Creates the integrator for a fixed dimension, validating `options`.
    pub fn new(options: Options<D>) -> Result<Self, OdeError> {
        Self::with_dim(D::name(), options)
    }
}

fn stages<D: Dim>(dim: D) -> Stages<D>
where
    DefaultAllocator: Allocator<D>,
{
    Stages {
        n: std::array::from_fn(|_| zeros(dim)),
    }
}

#[inline(always)]
fn get(v: &[f64], i: usize, pair: bool) -> Complex<f64> {
    Complex::new(v[i], if pair { v[i + 1] } else { 0.0 })
}

#[inline(always)]
fn put(v: &mut [f64], i: usize, pair: bool, c: Complex<f64>) {
    v[i] = c.re;
    if pair {
        v[i + 1] = c.im;
    }
}

/// Calls `op(i, pair)` once per block: at each scalar component and at the first component
/// of each pair.
#[inline(always)]
fn for_blocks(slots: &[Slot], mut op: impl FnMut(usize, bool)) {
    for (i, slot) in slots.iter().enumerate() {
        match slot {
            Slot::Scalar => op(i, false),
            Slot::PairRe => op(i, true),
            Slot::PairIm => {}
        }
    }
}

/// $[\varphi_0, \dots, \varphi_5]$ of one block at $h\lambda/4$ and $h\lambda/2$: the dense
/// output's at the middle and the end of a half step ([`dense`]).
type DenseSets = [[Complex<f64>; 6]; 2];

/// The coefficients of steps of $h$ and $h/2$ for every block, and the dense output's
/// $\varphi$-functions at the half steps' middles and ends.
fn coefficients(
    lp: &DiagonalLinearPart,
    h: f64,
    full: &mut [Coefficients],
    half: &mut [Coefficients],
    dense: &mut [DenseSets],
) {
    let values = lp.values();
    for_blocks(lp.slots(), |i, _| {
        let z = values[i] * h;
        let q = phi_functions_to::<6>(z * 0.25);
        let m = phi_functions_to::<6>(z * 0.5);
        let w = phi_functions(z);
        let weights = |p: &[Complex<f64>], tau: f64| {
            [
                (p[1] - p[2] * 3.0 + p[3] * 4.0) * tau,
                (p[2] * 2.0 - p[3] * 4.0) * tau,
                (p[3] * 4.0 - p[2]) * tau,
            ]
        };
        let [f1, f2, f3] = weights(&w, h);
        full[i] = [m[0], m[1] * (0.5 * h), w[0], f1, f2, f3, w[1] * h];
        let [g1, g2, g3] = weights(&m, 0.5 * h);
        half[i] = [q[0], q[1] * (0.25 * h), m[0], g1, g2, g3, m[1] * (0.5 * h)];
        dense[i] = [q, m];
    });
}

/// The forcing's [`Increments`] of a trial from `t` with step `h`: of the full step and of
/// the two half steps (`out`), for each forced block, with
/// $F(t_0, s) = A_+ e^{i\omega t_0} I(i\omega, s) + A_- e^{-i\omega t_0} I(-i\omega, s) +
/// c\thinspace I(0, s)$ ([`forcing::combine`]): $I(\pm i\omega, s)$ once per length from the
/// coefficients' $e^{s\lambda}$ ([`forcing::Harmonics::of`]), $I(0, s) = s\varphi_1(s\lambda)$
/// from the coefficients.
fn forcing_increments(
    lp: &DiagonalLinearPart,
    forcing: &Forcing,
    (full, half): (&[Coefficients], &[Coefficients]),
    t: f64,
    h: f64,
    out: &mut [Vec<Increments>; 3],
) {
    let w = forcing.frequency;
    let p = [t, t + 0.25 * h, t + 0.5 * h, t + 0.75 * h].map(|time| forcing::unit(w * time));
    let lengths = [0.25 * h, 0.5 * h, h].map(|s| forcing::Harmonics::new(w, s));
    let values = lp.values();
    let [f_full, f_first, f_second] = out;
    for &i in &forcing.forced {
        let Some(block) = &forcing.responses[i] else {
            continue;
        };
        let lambda = values[i];
        let exps = [half[i][0], full[i][0], full[i][2]];
        let [q, m, e] = [0, 1, 2].map(|k| lengths[k].of(lambda, exps[k], block));
        let (q0, m0, e0) = (half[i][1], full[i][1], full[i][6]);
        let f = |pk, r, r0| forcing::combine(block, pk, r, r0);
        f_full[i] = [f(p[0], m, m0), f(p[2], m, m0), f(p[0], e, e0)];
        f_first[i] = [f(p[0], q, q0), f(p[1], q, q0), f(p[0], m, m0)];
        f_second[i] = [f(p[2], q, q0), f(p[3], q, q0), f(p[2], m, m0)];
    }
}

/// `v += F` at each forced block, $F$ its increment number `k` ([`Increments`]).
fn add_increments(v: &mut [f64], slots: &[Slot], forced: Option<Forced<'_>>, k: usize) {
    let Some(forced) = forced else { return };
    for &i in forced.blocks {
        put_add(v, i, slots[i] == Slot::PairRe, forced.increments[i][k]);
    }
}

#[inline(always)]
fn put_add(v: &mut [f64], i: usize, pair: bool, c: Complex<f64>) {
    v[i] += c.re;
    if pair {
        v[i + 1] += c.im;
    }
}

/// `out = f - L y - g(t)`: the rest $N$ at `(t, y)` from $f(t, y)$.
fn rest<D: Dim>(
    lp: &DiagonalLinearPart,
    t: f64,
    y: &OVector<f64, D>,
    f: &OVector<f64, D>,
    out: &mut OVector<f64, D>,
) where
    DefaultAllocator: Allocator<D>,
{
    lp.apply(y.as_slice(), out.as_mut_slice());
    for (o, fi) in out.iter_mut().zip(f.iter()) {
        *o = fi - *o;
    }
    lp.subtract_forcing(t, out.as_mut_slice());
}

/// `out = f(t, y) - L y - g(t)`, with `fk` the scratch for $f$.
fn nonlinear<D: Dim, S: OdeSystem<D>>(
    sys: &S,
    lp: &DiagonalLinearPart,
    t: f64,
    y: &OVector<f64, D>,
    fk: &mut OVector<f64, D>,
    out: &mut OVector<f64, D>,
) where
    DefaultAllocator: Allocator<D>,
{
    sys.rhs(t, y, fk);
    rest(lp, t, y, fk, out);
}

/// One ETDRK4 step of length `tau` from `(t, u)` with the coefficients `cf` and the forcing's
/// increments `forced`; `st.n[0]` holds $N_a$ on entry, the other stages on exit; the result
/// goes into `out`.
#[allow(clippy::too_many_arguments)]
fn substep<D: Dim, S: OdeSystem<D>>(
    sys: &S,
    lp: &DiagonalLinearPart,
    (cf, forced): (&[Coefficients], Option<Forced<'_>>),
    t: f64,
    tau: f64,
    u: &OVector<f64, D>,
    st: &mut Stages<D>,
    scratch: &mut [OVector<f64, D>; 3],
    fk: &mut OVector<f64, D>,
    out: &mut OVector<f64, D>,
) where
    DefaultAllocator: Allocator<D>,
{
    let slots = lp.slots();
    let [a, b, c] = scratch;
    let [na, nb, nc, nd] = &mut st.n;
    let us = u.as_slice();
    for_blocks(slots, |i, p| {
        let k = &cf[i];
        put(
            a.as_mut_slice(),
            i,
            p,
            k[0] * get(us, i, p) + k[1] * get(na.as_slice(), i, p),
        );
    });
    add_increments(a.as_mut_slice(), slots, forced, 0);
    nonlinear(sys, lp, t + 0.5 * tau, a, fk, nb);
    for_blocks(slots, |i, p| {
        let k = &cf[i];
        put(
            b.as_mut_slice(),
            i,
            p,
            k[0] * get(us, i, p) + k[1] * get(nb.as_slice(), i, p),
        );
    });
    add_increments(b.as_mut_slice(), slots, forced, 0);
    nonlinear(sys, lp, t + 0.5 * tau, b, fk, nc);
    for_blocks(slots, |i, p| {
        let k = &cf[i];
        let forcing = get(nc.as_slice(), i, p) * 2.0 - get(na.as_slice(), i, p);
        put(
            c.as_mut_slice(),
            i,
            p,
            k[0] * get(a.as_slice(), i, p) + k[1] * forcing,
        );
    });
    add_increments(c.as_mut_slice(), slots, forced, 1);
    nonlinear(sys, lp, t + tau, c, fk, nd);
    for_blocks(slots, |i, p| {
        let k = &cf[i];
        let mid = get(nb.as_slice(), i, p) + get(nc.as_slice(), i, p);
        let value = k[2] * get(us, i, p)
            + k[3] * get(na.as_slice(), i, p)
            + k[4] * mid
            + k[5] * get(nd.as_slice(), i, p);
        put(out.as_mut_slice(), i, p, value);
    });
    add_increments(out.as_mut_slice(), slots, forced, 2);
}

impl<D: Dim> Etd4<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Creates the integrator for dimension `dim` (e.g. `Dyn(n)`), validating `options`.
    /// Allocates every vector it will use. Refuses [`Options::fixed_step`] (the step size is
    /// controlled by step doubling).
    pub fn with_dim(dim: D, options: Options<D>) -> Result<Self, OdeError> {
        if let Some(h) = options.fixed_step {
            return Err(OdeError::InvalidOption {
                field: "fixed_step",
                value: h,
                hint: "ETD4 controls its steps; use RK4 for fixed steps",
            });
        }
        let z = zeros(dim);
        let n = dim.value();
        let unit = [Complex::new(0.0, 0.0); 7];
        Ok(Etd4 {
            core: Core::new(dim, options, 5.0, 0.75, 4.0)?,
            full: stages(dim),
            halves_trial: [stages(dim), stages(dim)],
            u_mid_trial: z.clone(),
            halves: [stages(dim), stages(dim)],
            u_mid: z.clone(),
            u_full: z.clone(),
            stage: std::array::from_fn(|_| z.clone()),
            fk: z.clone(),
            coef_full: vec![unit; n],
            coef_half: vec![unit; n],
            coef_dense: vec![[[Complex::new(0.0, 0.0); 6]; 2]; n],
            increments: std::array::from_fn(|_| vec![[Complex::new(0.0, 0.0); 3]; n]),
            coef_at: (f64::NAN, f64::NAN),
            quarters: [z.clone(), z.clone()],
            n_end: z.clone(),
            quartic: std::array::from_fn(|_| vec![[Complex::new(0.0, 0.0); 5]; n]),
            jumps: [z.clone(), z],
            dense_ready: false,
        })
    }

    fn linear_part<'s, S: OdeSystem<D>>(
        &self,
        sys: &'s S,
    ) -> Result<&'s DiagonalLinearPart, OdeError> {
        let lp = sys.linear_part().ok_or(OdeError::NoLinearPart)?;
        let expected = self.core.dim.value();
        if lp.dim() != expected {
            return Err(OdeError::DimensionMismatch {
                field: "linear_part",
                expected,
                found: lp.dim(),
            });
        }
        Ok(lp)
    }

    /// The dense output's nodes and jumps of the accepted step, once per step (two
    /// evaluations of $f$): $N$ at a quarter and three quarters of the step, at states placed
    /// by the stages' interpolant ([`quadratic_at`]; their $O(h^4)$ error enters the output
    /// multiplied by $h$), $N$ at the step's end from the kept $f$, and per half step the
    /// difference $\delta_j$ between its end and the quartic's output there, of the size of
    /// the local error.
    fn prepare_dense<S: OdeSystem<D>>(&mut self, sys: &S, lp: &DiagonalLinearPart) {
        if self.dense_ready {
            return;
        }
        let Etd4 {
            core,
            halves,
            u_mid,
            stage,
            fk,
            coef_full,
            coef_half,
            coef_dense,
            increments,
            coef_at,
            quarters,
            n_end,
            quartic,
            jumps,
            ..
        } = self;
        let (t0, h) = (core.t_prev, core.h_dense);
        // The last trial is the accepted step's unless a later step failed or was refused.
        if *coef_at != (t0, h) {
            coefficients(lp, h, coef_full, coef_half, coef_dense);
            if let Some(forcing) = lp.forcing() {
                let cf = (coef_full.as_slice(), coef_half.as_slice());
                forcing_increments(lp, forcing, cf, t0, h, increments);
            }
            *coef_at = (t0, h);
        }
        let starts = [&core.y_prev, &*u_mid];
        for (j, q) in quarters.iter_mut().enumerate() {
            let t = t0 + (0.25 + 0.5 * j as f64) * h;
            let u = &mut stage[0];
            let interpolant = (&halves[j], starts[j].as_slice());
            let cached = (coef_dense.as_slice(), increments[1 + j].as_slice());
            quadratic_middle(lp, interpolant, cached, 0.5 * h, u.as_mut_slice());
            nonlinear(sys, lp, t, u, fk, q);
        }
        core.stats.rhs_evals += 2;
        rest(lp, t0 + h, &core.y_end, &core.f_end, n_end);
        let nodes = [
            &halves[0].n[0],
            &quarters[0],
            &halves[1].n[0],
            &quarters[1],
            n_end,
        ];
        quartic_coefficients(lp, nodes.map(|v| v.as_slice()), quartic);
        let [jump0, jump1] = jumps;
        let dense = DenseStep::new(quartic, starts, t0, h);
        for (half, (jump, end)) in [(jump0, &*u_mid), (jump1, &core.y_end)]
            .into_iter()
            .enumerate()
        {
            let cached = (coef_dense.as_slice(), increments[1 + half].as_slice());
            dense.half_end(lp, half, cached, jump.as_mut_slice());
            for (d, e) in jump.iter_mut().zip(end.iter()) {
                *d = e - *d;
            }
        }
        self.dense_ready = true;
    }
}

impl<D: Dim> Integrator<D> for Etd4<D>
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
        self.linear_part(sys)?;
        self.core.reset(sys, t, y, keep_step)
    }

    fn step<S: OdeSystem<D>>(&mut self, sys: &S, t_bound: f64) -> Result<(), OdeError> {
        let lp = self.linear_part(sys)?;
        let Etd4 {
            core,
            full,
            halves_trial: halves,
            u_mid_trial: u_mid,
            u_full,
            stage,
            fk,
            coef_full,
            coef_half,
            coef_dense,
            increments,
            coef_at,
            ..
        } = self;
        let t_before = core.t;
        let result = core.step(sys, t_bound, |sys, io| {
            let TrialIo {
                opts,
                n_ctrl,
                t,
                y,
                f,
                h,
                y_new,
                stats,
                ..
            } = io;
            coefficients(lp, h, coef_full, coef_half, coef_dense);
            if let Some(forcing) = lp.forcing() {
                let cf = (coef_full.as_slice(), coef_half.as_slice());
                forcing_increments(lp, forcing, cf, t, h, increments);
            }
            *coef_at = (t, h);
            let forced = |k: usize| {
                lp.forcing().map(|f| Forced {
                    blocks: &f.forced,
                    increments: &increments[k],
                })
            };
            // N_a = f(t, y) - L y - g(t), shared by the full and the first half step.
            rest(lp, t, y, f, &mut halves[0].n[0]);
            full.n[0].copy_from(&halves[0].n[0]);
            let plan = (coef_full.as_slice(), forced(0));
            substep(sys, lp, plan, t, h, y, full, stage, fk, u_full);
            substep(
                sys,
                lp,
                (coef_half.as_slice(), forced(1)),
                t,
                0.5 * h,
                y,
                &mut halves[0],
                stage,
                fk,
                u_mid,
            );
            let [_, second] = halves;
            let [na2, ..] = &mut second.n;
            nonlinear(sys, lp, t + 0.5 * h, u_mid, fk, na2);
            substep(
                sys,
                lp,
                (coef_half.as_slice(), forced(2)),
                t + 0.5 * h,
                0.5 * h,
                u_mid,
                second,
                stage,
                fk,
                y_new,
            );
            stats.rhs_evals += 10;
            let (ys, yn, yf) = (y.as_slice(), y_new.as_mut_slice(), u_full.as_slice());
            let mut sum = 0.0;
            for i in 0..ys.len() {
                let e = (yn[i] - yf[i]) / 15.0;
                let sk = scale(opts, i, ys[i], yn[i]);
                sum += (e / sk) * (e / sk);
                // Local extrapolation: the step keeps the order-5 combination.
                yn[i] += e;
            }
            Trial {
                err: (sum / n_ctrl).sqrt(),
                f_new_done: false,
            }
        });
        if self.core.t != t_before {
            std::mem::swap(&mut self.halves, &mut self.halves_trial);
            std::mem::swap(&mut self.u_mid, &mut self.u_mid_trial);
            self.dense_ready = false;
        }
        result
    }

    fn dense<S: OdeSystem<D>>(&mut self, sys: &S, t: f64, out: &mut OVector<f64, D>) {
        fit(out, self.core.dim);
        match (self.core.has_step, sys.linear_part()) {
            (true, Some(lp)) if lp.dim() == self.core.dim.value() => {
                self.prepare_dense(sys, lp);
                let Etd4 {
                    core,
                    u_mid,
                    quartic,
                    jumps,
                    coef_dense,
                    increments,
                    coef_at,
                    ..
                } = self;
                let starts = [&core.y_prev, &*u_mid];
                DenseStep::new(quartic, starts, core.t_prev, core.h_dense)
                    .with_jumps(jumps)
                    .reusing(*coef_at, coef_dense, [&increments[1], &increments[2]])
                    .at(lp, t, out.as_mut_slice());
            }
            _ => self.core.copy_state(out),
        }
    }

    fn truncate<S: OdeSystem<D>>(&mut self, sys: &S, t_new: f64) -> Result<(), OdeError> {
        self.core.check_truncate(t_new)?;
        if t_new == self.core.t {
            return Ok(());
        }
        let lp = self.linear_part(sys)?;
        self.prepare_dense(sys, lp);
        let Etd4 {
            core,
            u_mid,
            quartic,
            jumps,
            coef_dense,
            increments,
            coef_at,
            ..
        } = self;
        let Core {
            y_prev,
            y_new,
            t_prev,
            h_dense,
            ..
        } = core;
        DenseStep::new(quartic, [y_prev, u_mid], *t_prev, *h_dense)
            .with_jumps(jumps)
            .reusing(*coef_at, coef_dense, [&increments[1], &increments[2]])
            .at(lp, t_new, y_new.as_mut_slice());
        core.apply_truncate(sys, t_new)
    }

    core_accessors!();

    fn name(&self) -> &'static str {
        "ETD4"
    }
}
