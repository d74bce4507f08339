use nalgebra::allocator::Allocator;
use nalgebra::{Complex, DefaultAllocator, Dim, DimName, OVector};

use super::core::{core_accessors, fit, zeros, Core, Trial, TrialIo};
use super::linear_part::{phi_functions, DiagonalLinearPart, Slot};
use super::{controller::scale, Integrator, OdeError, OdeSystem, Options, Stats};

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
/// $\tfrac\tau2\varphi_1(\tau\lambda/2)$, $e^{\tau\lambda}$, and the weights
/// $\tau(\varphi_1 - 3\varphi_2 + 4\varphi_3)$, $\tau(2\varphi_2 - 4\varphi_3)$,
/// $\tau(-\varphi_2 + 4\varphi_3)$ at $\tau\lambda$.
type Coefficients = [Complex<f64>; 6];

/// Exponential time differencing of order 4 (Cox and Matthews' ETDRK4) for
/// $y^\prime = L y + N(t, y)$ with $L$ diagonal in real and complex blocks
/// ([`OdeSystem::linear_part`], [`DiagonalLinearPart`]), with step doubling for the error and
/// a dense output from the same $\varphi$-functions.
///
/// **The step** of length $\tau$ from $(t, u)$, per block of eigenvalue $\lambda$
/// ($E = e^{\tau\lambda}$, $E_2 = e^{\tau\lambda/2}$, $Q = \tfrac\tau2\varphi_1(\tau\lambda/2)$,
/// $N = f - L y$):
/// $$a = E_2 u + Q N_a,\quad b = E_2 u + Q N_b,\quad c = E_2 a + Q(2N_c - N_a),$$
/// $$u_1 = E u + \tau\big[(\varphi_1 - 3\varphi_2 + 4\varphi_3) N_a + (2\varphi_2 - 4\varphi_3)
/// (N_b + N_c) + (-\varphi_2 + 4\varphi_3) N_d\big],$$
/// $\varphi_k = \varphi_k(\tau\lambda)$ ([`phi_functions`](super::phi_functions)). It is the
/// variation-of-constants formula $u_1 = e^{\tau L}u + \int_0^\tau e^{(\tau - s)L}p(s)\thinspace ds$
/// with $p$ the quadratic through $N_a$, $(N_b + N_c)/2$ and $N_d$ at $0$, $\tau/2$, $\tau$:
/// **exact for the linear part whatever $|\lambda\tau|$, and for a forcing constant or linear
/// in time**, of classical order 4. A stiff mode ($\tau\operatorname{Re}\lambda \ll -1$) costs
/// nothing: $e^{\tau\lambda}$ vanishes and the weights tend to the quasi-static response.
/// (Lawson's method, $e^{\tau L}$ applied to an explicit method's stages, is not exact for a
/// constant force when $|\lambda\tau| \gg 1$; this one is.)
///
/// **Error and step size.** Each step is taken once with $h$ and twice with $h/2$; the error
/// of the two half steps is $(u_{h/2,h/2} - u_h)/15$ (Richardson, order 4), measured in the
/// usual RMS norm, and the two half steps are kept. A trial costs 10 evaluations of $f$, plus
/// one at the accepted point; the controller is the PI controller of the explicit methods
/// with the exponent of an order-5 local error.
///
/// **Dense output** on each half step $[t_j, t_j + \tau]$ with $\theta \in [0, 1]$:
/// $u(t_j + \theta\tau) = e^{\theta\tau L}u_j + \theta\tau\big[\varphi_1 N_a + \theta\varphi_2
/// (-3N_a + 4N_m - N_d) + \theta^2\varphi_3(4N_a - 8N_m + 4N_d)\big]$, $N_m = (N_b + N_c)/2$,
/// $\varphi_k = \varphi_k(\theta\tau L)$: the same quadrature to $\theta\tau$, equal to the
/// step at $\theta = 1$, exact for the linear part.
///
/// **Cost.** Every operation is per block: $O(N)$ a step besides the evaluations of $f$
/// (three $\varphi$ evaluations per block and trial, one per block and dense point). Nothing
/// is allocated after construction. The steps are set by $N$ (a contact, the forcing), not by
/// the fastest mode of $L$.
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
    /// Per block (at its first component): coefficients of a step of $h$ and of $h/2$.
    coef_full: Vec<Coefficients>,
    coef_half: Vec<Coefficients>,
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

/// The coefficients of steps of $h$ and $h/2$ for every block.
fn coefficients(
    lp: &DiagonalLinearPart,
    h: f64,
    full: &mut [Coefficients],
    half: &mut [Coefficients],
) {
    let values = lp.values();
    for_blocks(lp.slots(), |i, _| {
        let z = values[i] * h;
        let q = phi_functions(z * 0.25);
        let m = phi_functions(z * 0.5);
        let w = phi_functions(z);
        let weights = |p: &[Complex<f64>; 4], tau: f64| {
            [
                (p[1] - p[2] * 3.0 + p[3] * 4.0) * tau,
                (p[2] * 2.0 - p[3] * 4.0) * tau,
                (p[3] * 4.0 - p[2]) * tau,
            ]
        };
        let [f1, f2, f3] = weights(&w, h);
        full[i] = [m[0], m[1] * (0.5 * h), w[0], f1, f2, f3];
        let [g1, g2, g3] = weights(&m, 0.5 * h);
        half[i] = [q[0], q[1] * (0.25 * h), m[0], g1, g2, g3];
    });
}

/// `out = f(t, y) - L y`, with `fk` the scratch for $f$.
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
    lp.apply(y.as_slice(), out.as_mut_slice());
    for (o, f) in out.iter_mut().zip(fk.iter()) {
        *o = f - *o;
    }
}

/// One ETDRK4 step of length `tau` from `(t, u)` with the coefficients `cf`; `st.n[0]` holds
/// $N_a$ on entry, the other stages on exit; the result goes into `out`.
#[allow(clippy::too_many_arguments)]
fn substep<D: Dim, S: OdeSystem<D>>(
    sys: &S,
    lp: &DiagonalLinearPart,
    cf: &[Coefficients],
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
        let unit = [Complex::new(0.0, 0.0); 6];
        Ok(Etd4 {
            core: Core::new(dim, options, 5.0, 0.75, 4.0)?,
            full: stages(dim),
            halves_trial: [stages(dim), stages(dim)],
            u_mid_trial: z.clone(),
            halves: [stages(dim), stages(dim)],
            u_mid: z.clone(),
            u_full: z.clone(),
            stage: std::array::from_fn(|_| z.clone()),
            fk: z,
            coef_full: vec![unit; n],
            coef_half: vec![unit; n],
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
}

/// The dense output at `t` into `out`: the half step of `[t_prev, t_prev + h]` that holds `t`
/// (extrapolated outside the step), from its start state and stages.
#[allow(clippy::too_many_arguments)]
fn dense_at<D: Dim>(
    lp: &DiagonalLinearPart,
    halves: &[Stages<D>; 2],
    y_prev: &OVector<f64, D>,
    u_mid: &OVector<f64, D>,
    t_prev: f64,
    h: f64,
    t: f64,
    out: &mut [f64],
) where
    DefaultAllocator: Allocator<D>,
{
    let tau = 0.5 * h;
    let s = (t - t_prev) / tau;
    let (half, u0, theta) = if s <= 1.0 {
        (&halves[0], y_prev.as_slice(), s)
    } else {
        (&halves[1], u_mid.as_slice(), s - 1.0)
    };
    let [na, nb, nc, nd] = half.n.each_ref().map(|v| v.as_slice());
    let values = lp.values();
    for_blocks(lp.slots(), |i, p| {
        let phi = phi_functions(values[i] * (theta * tau));
        let a = get(na, i, p);
        let m = (get(nb, i, p) + get(nc, i, p)) * 0.5;
        let d = get(nd, i, p);
        let p2 = m * 4.0 - a * 3.0 - d;
        let p3 = (a - m * 2.0 + d) * 4.0;
        let value = phi[0] * get(u0, i, p)
            + (phi[1] * a + phi[2] * p2 * theta + phi[3] * p3 * (theta * theta)) * (theta * tau);
        put(out, i, p, value);
    });
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
            coefficients(lp, h, coef_full, coef_half);
            // N_a = f(t, y) - L y, shared by the full and the first half step.
            lp.apply(y.as_slice(), halves[0].n[0].as_mut_slice());
            for (o, fi) in halves[0].n[0].iter_mut().zip(f.iter()) {
                *o = fi - *o;
            }
            full.n[0].copy_from(&halves[0].n[0]);
            substep(sys, lp, coef_full, t, h, y, full, stage, fk, u_full);
            substep(
                sys,
                lp,
                coef_half,
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
                coef_half,
                t + 0.5 * h,
                0.5 * h,
                u_mid,
                second,
                stage,
                fk,
                y_new,
            );
            stats.rhs_evals += 10;
            let (ys, yn, yf) = (y.as_slice(), y_new.as_slice(), u_full.as_slice());
            let mut sum = 0.0;
            for i in 0..ys.len() {
                let e = (yn[i] - yf[i]) / 15.0;
                let sk = scale(opts, i, ys[i], yn[i]);
                sum += (e / sk) * (e / sk);
            }
            Trial {
                err: (sum / n_ctrl).sqrt(),
                f_new_done: false,
            }
        });
        if self.core.t != t_before {
            std::mem::swap(&mut self.halves, &mut self.halves_trial);
            std::mem::swap(&mut self.u_mid, &mut self.u_mid_trial);
        }
        result
    }

    fn dense<S: OdeSystem<D>>(&mut self, sys: &S, t: f64, out: &mut OVector<f64, D>) {
        fit(out, self.core.dim);
        match (self.core.has_step, sys.linear_part()) {
            (true, Some(lp)) if lp.dim() == self.core.dim.value() => {
                let c = &self.core;
                let (y0, h) = (&c.y_prev, c.h_dense);
                dense_at(
                    lp,
                    &self.halves,
                    y0,
                    &self.u_mid,
                    c.t_prev,
                    h,
                    t,
                    out.as_mut_slice(),
                )
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
        let Etd4 {
            core,
            halves,
            u_mid,
            ..
        } = self;
        let (y0, t0, h) = (&core.y_prev, core.t_prev, core.h_dense);
        dense_at(
            lp,
            halves,
            y0,
            u_mid,
            t0,
            h,
            t_new,
            core.y_new.as_mut_slice(),
        );
        core.apply_truncate(sys, t_new)
    }

    core_accessors!();

    fn name(&self) -> &'static str {
        "ETD4"
    }
}
