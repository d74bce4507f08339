//! The linear algebra of a Radau5 step: the Jacobian, the two LU decompositions, the
//! simplified Newton iteration on the transformed stage system, and the error estimate.

use super::tableau::{C1, C2, DD1, DD2, DD3, T, TI};
use super::woodbury::{Coupling, Woodbury};
use crate::numeric::lu::{lu_factor, lu_solve, LuScalar};
use crate::ode::{JacobianMut, OdeSystem, Stats};
use nalgebra::allocator::Allocator;
use nalgebra::{Complex, DefaultAllocator, Dim, OVector};

/// Newton iterations per step before the step is rejected (RADAU5's `NIT`).
pub(super) const NIT: usize = 7;

/// The Jacobian and the factored Newton matrices, all preallocated.
///
/// For a second-order system ([`OdeSystem::second_order`] = $p$) the matrices factored are
/// the condensed ones of size $N - p$ (see [`condensed_solve`]), stored in the leading
/// part of the same buffers; with its diagonal springs ([`OdeSystem::diagonal_springs`])
/// they are factored as diagonal plus low rank ([`Woodbury`]) when they are.
#[derive(Debug, Clone)]
pub(super) struct Linear {
    pub n: usize,
    /// Positions eliminated from the Newton systems: $p$ of [`OdeSystem::second_order`],
    /// 0 for the full systems.
    pub p: usize,
    /// $J$, column-major.
    pub jac: Vec<f64>,
    /// LU of $(\gamma/h) I - J$ (condensed when `p > 0`).
    pub e1: Vec<f64>,
    pub piv1: Vec<usize>,
    /// LU of $((\alpha + i\beta)/h) I - J$.
    pub e2: Vec<Complex<f64>>,
    pub piv2: Vec<usize>,
    /// Right-hand side of the complex solve.
    pub rc: Vec<Complex<f64>>,
    /// $J$ split into the declared diagonal springs and a coupling of low rank, and whether
    /// the current Jacobian is so split.
    coupling: Coupling,
    split: bool,
    /// The Woodbury factors of the real and the complex matrix, when in use (else the LUs).
    wb1: Woodbury<f64>,
    wb2: Woodbury<Complex<f64>>,
    /// The last decompositions are the Woodbury ones.
    pub structured: bool,
    pub gamma: f64,
    pub alpha: f64,
    pub beta: f64,
}

impl Linear {
    pub(super) fn new(n: usize) -> Self {
        let (alpha, beta) = super::tableau::alpha_beta();
        Linear {
            n,
            p: 0,
            jac: vec![0.0; n * n],
            e1: vec![0.0; n * n],
            piv1: vec![0; n],
            e2: vec![Complex::new(0.0, 0.0); n * n],
            piv2: vec![0; n],
            rc: vec![Complex::new(0.0, 0.0); n],
            coupling: Coupling::new(n),
            split: false,
            wb1: Woodbury::new(n),
            wb2: Woodbury::new(n),
            structured: false,
            gamma: super::tableau::gamma(),
            alpha,
            beta,
        }
    }

    /// $J$ at $(t, y)$ with $f_0 = f(t, y)$: the system's own, or forward differences with
    /// RADAU5's increments $\delta_j = \sqrt{\varepsilon\max(10^{-5}, |y_j|)}$ (`yt`, `ft`
    /// are scratch).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn jacobian<D: Dim, S: OdeSystem<D>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &OVector<f64, D>,
        f0: &OVector<f64, D>,
        yt: &mut OVector<f64, D>,
        ft: &mut OVector<f64, D>,
        stats: &mut Stats,
    ) where
        DefaultAllocator: Allocator<D>,
    {
        let dim = y.shape_generic().0;
        let n = self.n;
        self.p = sys.second_order().filter(|&p| 2 * p <= n).unwrap_or(0);
        stats.jacobians += 1;
        let mut view = JacobianMut::from_slice_generic(&mut self.jac, dim, dim);
        if !sys.jacobian(t, y, &mut view) {
            self.differences(sys, t, y, f0, yt, ft, stats);
        }
        // e1 is free until the decompositions that follow.
        self.split = match sys.diagonal_springs() {
            Some(s) => self.coupling.split(&self.jac, (n, self.p), s, &mut self.e1),
            None => false,
        };
    }

    /// $J$ by forward differences (see [`Linear::jacobian`]).
    #[allow(clippy::too_many_arguments)]
    fn differences<D: Dim, S: OdeSystem<D>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &OVector<f64, D>,
        f0: &OVector<f64, D>,
        yt: &mut OVector<f64, D>,
        ft: &mut OVector<f64, D>,
        stats: &mut Stats,
    ) where
        DefaultAllocator: Allocator<D>,
    {
        let n = self.n;
        yt.copy_from(y);
        for j in 0..n {
            let yj = y[j];
            let delta = (f64::EPSILON * yj.abs().max(1e-5)).sqrt();
            yt[j] = yj + delta;
            sys.rhs(t, yt, ft);
            yt[j] = yj;
            let col = &mut self.jac[j * n..(j + 1) * n];
            for (c, (a, b)) in col.iter_mut().zip(ft.iter().zip(f0.iter())) {
                *c = (a - b) / delta;
            }
        }
        stats.rhs_evals += n as u64;
    }

    /// Factors $(\gamma/h) I - J$ and $((\alpha + i\beta)/h) I - J$ (condensed when `p > 0`,
    /// diagonal plus low rank when it is: [`LowRank`]); `false` if either is singular to
    /// working precision.
    pub(super) fn decompose(&mut self, h: f64, stats: &mut Stats) -> bool {
        let (g, ar, ai) = (self.gamma / h, self.alpha / h, self.beta / h);
        stats.lu_decompositions += 1;
        self.structured = false;
        if self.p > 0 {
            let (n, p) = (self.n, self.p);
            let c = Complex::new(ar, ai);
            if self.split
                && self.wb1.factor(&self.coupling, g)
                && self.wb2.factor(&self.coupling, c)
            {
                self.structured = true;
                stats.woodbury_decompositions += 1;
                return true;
            }
            condense(&self.jac, n, p, g, &mut self.e1);
            condense(&self.jac, n, p, c, &mut self.e2);
            return lu_factor(&mut self.e1, n - p, &mut self.piv1).is_ok()
                && lu_factor(&mut self.e2, n - p, &mut self.piv2).is_ok();
        }
        let n = self.n;
        for (k, (e1, e2)) in self.e1.iter_mut().zip(self.e2.iter_mut()).enumerate() {
            let j = -self.jac[k];
            *e1 = j;
            *e2 = Complex::new(j, 0.0);
        }
        for i in 0..n {
            self.e1[i * n + i] += g;
            self.e2[i * n + i] += Complex::new(ar, ai);
        }
        lu_factor(&mut self.e1, n, &mut self.piv1).is_ok()
            && lu_factor(&mut self.e2, n, &mut self.piv2).is_ok()
    }

    /// Solves $((\gamma/h) I - J) x = b$ in place with the factors of [`Linear::decompose`].
    pub(super) fn solve_real(&self, h: f64, b: &mut [f64]) {
        if self.structured {
            split_solve(&self.coupling, self.p, self.gamma / h, &self.wb1, b);
        } else if self.p > 0 {
            condensed_solve(
                &self.jac,
                self.n,
                self.p,
                self.gamma / h,
                &self.e1,
                &self.piv1,
                b,
            );
        } else {
            lu_solve(&self.e1, self.n, &self.piv1, b);
        }
    }

    /// Solves $(((\alpha + i\beta)/h) I - J) x = b$ in place, `b` = `self.rc`.
    fn solve_complex(&mut self, h: f64) {
        let c = Complex::new(self.alpha / h, self.beta / h);
        if self.structured {
            split_solve(&self.coupling, self.p, c, &self.wb2, &mut self.rc);
        } else if self.p > 0 {
            condensed_solve(
                &self.jac,
                self.n,
                self.p,
                c,
                &self.e2,
                &self.piv2,
                &mut self.rc,
            );
        } else {
            lu_solve(&self.e2, self.n, &self.piv2, &mut self.rc);
        }
    }

    /// Solves the transformed linear systems in place: on entry `z` holds
    /// $(T^{-1}\otimes I) F(y + Z)$ and `w` the current iterate $W$; on exit `z` holds the
    /// Newton correction $\Delta W$.
    pub(super) fn solve(&mut self, h: f64, z: &mut [&mut [f64]; 3], w: &[&[f64]; 3]) {
        let (g, ar, ai) = (self.gamma / h, self.alpha / h, self.beta / h);
        let n = self.n;
        for i in 0..n {
            z[0][i] -= w[0][i] * g;
            let re = z[1][i] - w[1][i] * ar + w[2][i] * ai;
            let im = z[2][i] - w[1][i] * ai - w[2][i] * ar;
            self.rc[i] = Complex::new(re, im);
        }
        self.solve_real(h, z[0]);
        self.solve_complex(h);
        for i in 0..n {
            z[1][i] = self.rc[i].re;
            z[2][i] = self.rc[i].im;
        }
    }
}

/// The condensed Newton matrix of a second-order system. With the state $(q, v, z)$,
/// $q, v \in \mathbb R^p$, $q^\prime = v$ exactly, the Jacobian is
/// $J = \begin{pmatrix} 0 & I & 0\\\\ A_q & A_v & A_z\\\\ G_q & G_v & G_z\end{pmatrix}$
/// and $(cI - J)x = b$ reads $c x_q - x_v = b_q$ and, with $x_q = (b_q + x_v)/c$ substituted,
/// $$\Big(cI - \begin{pmatrix} A_v + A_q/c & A_z\\\\ G_v + G_q/c & G_z\end{pmatrix}\Big)
/// \begin{pmatrix}x_v\\\\ x_z\end{pmatrix} = \begin{pmatrix}b_v\\\\ b_z\end{pmatrix} +
/// \frac1c\begin{pmatrix}A_q\\\\ G_q\end{pmatrix} b_q$$
/// (Hairer and Wanner's RADAU5 with `M1` = `M2` = $p$): an $(N - p)$ square matrix, written
/// column-major into `e`; the rows of $J$ for $q$ are not read.
fn condense<T: LuScalar>(jac: &[f64], n: usize, p: usize, c: T, e: &mut [T]) {
    let m = n - p;
    let inv = T::one() / c;
    for j in 0..m {
        let col = &jac[(p + j) * n + p..(p + j + 1) * n];
        let out = &mut e[j * m..(j + 1) * m];
        for (x, &v) in out.iter_mut().zip(col) {
            *x = T::from_real(-v);
        }
        if j < p {
            let colq = &jac[j * n + p..(j + 1) * n];
            for (x, &v) in out.iter_mut().zip(colq) {
                *x -= inv.scale(v);
            }
        }
        out[j] += c;
    }
}

/// Solves $(cI - J)x = b$ in place through the condensed factors of [`condense`]: the
/// right-hand side $b_{v,z} + \frac1c (A_q; G_q) b_q$, the condensed solve for $(x_v, x_z)$,
/// then $x_q = (b_q + x_v)/c$.
fn condensed_solve<T: LuScalar>(
    jac: &[f64],
    n: usize,
    p: usize,
    c: T,
    e: &[T],
    piv: &[usize],
    b: &mut [T],
) {
    let inv = T::one() / c;
    let (bq, bvz) = b.split_at_mut(p);
    for (k, &bk) in bq.iter().enumerate() {
        let bk = bk * inv;
        if bk != T::zero() {
            for (x, &v) in bvz.iter_mut().zip(&jac[k * n + p..(k + 1) * n]) {
                *x += bk.scale(v);
            }
        }
    }
    lu_solve(e, n - p, piv, bvz);
    for (x, &v) in bq.iter_mut().zip(bvz.iter()) {
        *x = (*x + v) * inv;
    }
}

/// Solves $(cI - J)x = b$ in place with the Woodbury factors of the condensed matrix: the
/// right-hand side $b_{vz} + \frac1c A_q b_q$ ([`Coupling::add_position_rhs`]), the
/// condensed solve for $(x_v, x_z)$, then $x_q = (b_q + x_v)/c$ (as [`condensed_solve`]).
fn split_solve<T: LuScalar>(cpl: &Coupling, p: usize, c: T, wb: &Woodbury<T>, b: &mut [T]) {
    let inv = T::one() / c;
    let (bq, bvz) = b.split_at_mut(p);
    cpl.add_position_rhs(inv, bq, bvz);
    wb.solve(bvz);
    for (x, &v) in bq.iter_mut().zip(bvz.iter()) {
        *x = (*x + v) * inv;
    }
}

/// Outcome of the Newton iteration.
pub(super) enum Newton {
    /// Converged after `iterations` (the contraction rate is left in [`Rate`]).
    Converged { iterations: usize },
    /// Diverging or too slow: reject and multiply the step by `factor`.
    Failed { factor: f64, non_finite: bool },
}

/// The Newton iteration's inputs that do not change during a step.
pub(super) struct StepInput<'a, D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    pub t: f64,
    pub h: f64,
    pub y: &'a OVector<f64, D>,
    pub scal: &'a OVector<f64, D>,
    pub n_ctrl: f64,
    pub fnewt: f64,
    /// Fixed steps: no step to reduce, so iterate up to [`NIT_FIXED`] times while the
    /// iteration contracts instead of giving up early on a slow prediction.
    pub patient: bool,
}

/// Newton iterations allowed with fixed steps.
pub(super) const NIT_FIXED: usize = 30;

/// Newton state carried across steps (RADAU5's `THETA`, `FACCON`).
#[derive(Debug, Clone, Copy)]
pub(super) struct Rate {
    pub theta: f64,
    pub faccon: f64,
}

/// Simplified Newton on the transformed stage system $W = T^{-1} Z$:
/// $\big(h^{-1}\Lambda \otimes I - I\otimes J\big)\Delta W = (T^{-1}\otimes I) F(y + Z) - h^{-1}(\Lambda\otimes I) W$,
/// $\Lambda = T^{-1}A^{-1}T$, until the contraction-corrected increment
/// $\frac{\theta}{1-\theta}\Vert\Delta W\Vert \le \kappa$ (`fnewt`). `z` holds the starting
/// values on entry, the stage increments $Z_i = Y_i - y$ on success; `w` their transform;
/// `yt` is scratch. Fails when $\theta \ge 0.99$, when the predicted error after the
/// remaining iterations exceeds $\kappa$, after [`NIT`] iterations, or on non-finite stages.
#[allow(clippy::too_many_arguments)]
pub(super) fn iterate<D: Dim, S: OdeSystem<D>>(
    sys: &S,
    inp: &StepInput<'_, D>,
    lin: &mut Linear,
    z: &mut [OVector<f64, D>; 3],
    w: &mut [OVector<f64, D>; 3],
    yt: &mut OVector<f64, D>,
    rate: &mut Rate,
    stats: &mut Stats,
) -> Newton
where
    DefaultAllocator: Allocator<D>,
{
    rate.faccon = rate.faccon.max(f64::EPSILON).powf(0.8);
    rate.theta = super::THETA_JAC;
    let mut history = Contraction {
        dynold: 0.0,
        thqold: 0.0,
    };
    let nit = if inp.patient { NIT_FIXED } else { NIT };
    let non_finite = Newton::Failed {
        factor: 0.5,
        non_finite: true,
    };
    for newt in 1..=nit {
        if !stage_fields(sys, inp, z, yt, stats) {
            return non_finite;
        }
        let [z0, z1, z2] = z;
        let (z0, z1, z2) = (z0.as_mut_slice(), z1.as_mut_slice(), z2.as_mut_slice());
        transform(&TI, [&mut *z0, &mut *z1, &mut *z2]);
        {
            let ws = [w[0].as_slice(), w[1].as_slice(), w[2].as_slice()];
            lin.solve(inp.h, &mut [&mut *z0, &mut *z1, &mut *z2], &ws);
        }
        let dyno = increment_norm([&*z0, &*z1, &*z2], inp.scal.as_slice(), inp.n_ctrl);
        if !dyno.is_finite() {
            return non_finite;
        }
        if newt > 1
            && newt < nit
            && let Some(failed) = history.check(rate, inp, newt, dyno)
        {
            return failed;
        }
        history.dynold = dyno.max(f64::EPSILON);
        update_stages(w, [z0, z1, z2]);
        if rate.faccon * dyno <= inp.fnewt {
            return Newton::Converged { iterations: newt };
        }
    }
    Newton::Failed {
        factor: 0.5,
        non_finite: false,
    }
}

/// $F(y + Z_s)$ at the three stage times, written over $Z_s$ (rebuilt from $W$ after the
/// solve); `false` if a value is not finite.
fn stage_fields<D: Dim, S: OdeSystem<D>>(
    sys: &S,
    inp: &StepInput<'_, D>,
    z: &mut [OVector<f64, D>; 3],
    yt: &mut OVector<f64, D>,
    stats: &mut Stats,
) -> bool
where
    DefaultAllocator: Allocator<D>,
{
    let c = [C1, C2, 1.0];
    for s in 0..3 {
        for i in 0..yt.len() {
            yt[i] = inp.y[i] + z[s][i];
        }
        sys.rhs(inp.t + c[s] * inp.h, yt, &mut z[s]);
    }
    stats.rhs_evals += 3;
    // Over slices: nalgebra's element iterator is several times slower.
    z.iter().all(|v| v.as_slice().iter().all(|x| x.is_finite()))
}

/// $(M \otimes I)\thinspace x$ in place for the three stage vectors (`m` is $T^{-1}$ here).
fn transform(m: &[[f64; 3]; 3], x: [&mut [f64]; 3]) {
    let [x0, x1, x2] = x;
    for i in 0..x0.len() {
        let (a1, a2, a3) = (x0[i], x1[i], x2[i]);
        x0[i] = m[0][0] * a1 + m[0][1] * a2 + m[0][2] * a3;
        x1[i] = m[1][0] * a1 + m[1][1] * a2 + m[1][2] * a3;
        x2[i] = m[2][0] * a1 + m[2][1] * a2 + m[2][2] * a3;
    }
}

/// The RMS norm of the Newton increment $\Delta W$ scaled by `scal`, over the `n_ctrl`
/// error-controlled components of each stage.
fn increment_norm(dw: [&[f64]; 3], scal: &[f64], n_ctrl: f64) -> f64 {
    let [z0, z1, z2] = dw;
    let mut sum = 0.0;
    for i in 0..z0.len() {
        sum += (z0[i] / scal[i]).powi(2) + (z1[i] / scal[i]).powi(2) + (z2[i] / scal[i]).powi(2);
    }
    (sum / (3.0 * n_ctrl)).sqrt()
}

/// $W \mathrel{+}= \Delta W$ and $Z = (T \otimes I) W$ (`dw` holds $\Delta W$ on entry, $Z$
/// on return; $T$'s last row is $(T_{31}, 1, 0)$).
fn update_stages<D: Dim>(w: &mut [OVector<f64, D>; 3], dw: [&mut [f64]; 3])
where
    DefaultAllocator: Allocator<D>,
{
    let [w0, w1, w2] = w;
    let (w0, w1, w2) = (w0.as_mut_slice(), w1.as_mut_slice(), w2.as_mut_slice());
    let [z0, z1, z2] = dw;
    for i in 0..z0.len() {
        w0[i] += z0[i];
        w1[i] += z1[i];
        w2[i] += z2[i];
        z0[i] = T[0][0] * w0[i] + T[0][1] * w1[i] + T[0][2] * w2[i];
        z1[i] = T[1][0] * w0[i] + T[1][1] * w1[i] + T[1][2] * w2[i];
        z2[i] = T[2][0] * w0[i] + w1[i];
    }
}

/// The previous increment's norm and contraction quotient of a Newton iteration.
struct Contraction {
    dynold: f64,
    thqold: f64,
}

impl Contraction {
    /// The contraction rate $\theta$ after iteration `newt` with increment norm `dyno`, and
    /// the error predicted after the remaining iterations: a failure if the iteration
    /// diverges ($\theta \ge 0.99$) or will not reach $\kappa$ in time.
    fn check<D: Dim>(
        &mut self,
        rate: &mut Rate,
        inp: &StepInput<'_, D>,
        newt: usize,
        dyno: f64,
    ) -> Option<Newton>
    where
        DefaultAllocator: Allocator<D>,
    {
        let thq = dyno / self.dynold;
        rate.theta = if newt == 2 {
            thq
        } else {
            (thq * self.thqold).sqrt()
        };
        self.thqold = thq;
        // Written so that a NaN rate fails as a diverging one.
        if rate.theta < 0.99 {
            rate.faccon = rate.theta / (1.0 - rate.theta);
            let left = (NIT.max(newt + 1) - 1 - newt) as i32;
            let dyth = rate.faccon * dyno * rate.theta.powi(left) / inp.fnewt;
            if dyth >= 1.0 && !inp.patient {
                let qnewt = dyth.clamp(1e-4, 20.0);
                return Some(Newton::Failed {
                    factor: 0.8 * qnewt.powf(-1.0 / (4.0 + left as f64)),
                    non_finite: false,
                });
            }
            None
        } else {
            Some(Newton::Failed {
                factor: 0.5,
                non_finite: false,
            })
        }
    }
}

/// RADAU5's error estimate: $e = (\tfrac{\gamma}{h} I - J)^{-1}\big(f(t, y) + \tfrac1h\sum_i d_i Z_i\big)$,
/// and, when its norm exceeds 1 on a first or a rejected step (where stiff components can
/// make it too pessimistic), the filtered one with $f(t, y + e)$ in place of $f(t, y)$.
/// Returns $\max(\Vert e\Vert, 10^{-10})$ (RMS norm scaled by `scal`).
#[allow(clippy::too_many_arguments)]
pub(super) fn error_estimate<D: Dim, S: OdeSystem<D>>(
    sys: &S,
    inp: &StepInput<'_, D>,
    f0: &OVector<f64, D>,
    lin: &Linear,
    z: &[OVector<f64, D>; 3],
    refine: bool,
    e: &mut OVector<f64, D>,
    f2: &mut OVector<f64, D>,
    yt: &mut OVector<f64, D>,
    stats: &mut Stats,
) -> f64
where
    DefaultAllocator: Allocator<D>,
{
    let n = lin.n;
    let (h1, h2, h3) = (DD1 / inp.h, DD2 / inp.h, DD3 / inp.h);
    for i in 0..n {
        f2[i] = h1 * z[0][i] + h2 * z[1][i] + h3 * z[2][i];
        e[i] = f2[i] + f0[i];
    }
    lin.solve_real(inp.h, e.as_mut_slice());
    let mut err = rms(e, inp.scal, inp.n_ctrl);
    if err >= 1.0 && refine {
        for i in 0..n {
            yt[i] = inp.y[i] + e[i];
        }
        sys.rhs(inp.t, yt, e);
        stats.rhs_evals += 1;
        for i in 0..n {
            e[i] += f2[i];
        }
        lin.solve_real(inp.h, e.as_mut_slice());
        err = rms(e, inp.scal, inp.n_ctrl);
    }
    // NaN stays NaN (a rejection), tiny errors are floored as RADAU5 does.
    if err.is_nan() {
        err
    } else {
        err.max(1e-10)
    }
}

/// $\sqrt{\frac{1}{n_c}\sum_i (e_i/s_i)^2}$.
fn rms<D: Dim>(e: &OVector<f64, D>, scal: &OVector<f64, D>, n_ctrl: f64) -> f64
where
    DefaultAllocator: Allocator<D>,
{
    let mut s = 0.0;
    for (a, b) in e.as_slice().iter().zip(scal.as_slice()) {
        s += (a / b) * (a / b);
    }
    (s / n_ctrl).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Jacobian of a second-order system: state $(q, v, z)$, $p = 3$, $m = 2$; rows of $q$
    /// exactly $(0, I, 0)$, the rest dense and unsymmetric.
    fn second_order_jacobian(p: usize, m: usize) -> Vec<f64> {
        let n = 2 * p + m;
        let mut jac = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n {
                jac[i + j * n] = if i < p {
                    if j == p + i {
                        1.0
                    } else {
                        0.0
                    }
                } else {
                    ((i * 7 + j * 11) % 13) as f64 - 6.0 + if i == j { -20.0 } else { 0.0 }
                };
            }
        }
        jac
    }

    /// The condensed solve against the full LU of $cI - J$ (independent: no elimination of
    /// the positions), real and complex, on a right-hand side with every entry nonzero.
    #[test]
    fn condensed_solve_matches_the_full_system() {
        let (p, m) = (3, 2);
        let n = 2 * p + m;
        let jac = second_order_jacobian(p, m);
        let check = |c: Complex<f64>| {
            let mut full: Vec<Complex<f64>> = jac.iter().map(|&v| Complex::new(-v, 0.0)).collect();
            for i in 0..n {
                full[i * n + i] += c;
            }
            let mut piv = vec![0; n];
            lu_factor(&mut full, n, &mut piv).unwrap();
            let b: Vec<Complex<f64>> = (0..n)
                .map(|i| Complex::new(1.0 + i as f64, 0.5 - i as f64))
                .collect();
            let mut want = b.clone();
            lu_solve(&full, n, &piv, &mut want);
            let mut e = vec![Complex::new(0.0, 0.0); n * n];
            condense(&jac, n, p, c, &mut e);
            let mut piv_c = vec![0; n];
            lu_factor(&mut e, n - p, &mut piv_c).unwrap();
            let mut got = b;
            condensed_solve(&jac, n, p, c, &e, &piv_c, &mut got);
            let scale = want.iter().map(|v| v.norm()).fold(0.0, f64::max);
            for i in 0..n {
                assert!(
                    (got[i] - want[i]).norm() < 1e-13 * scale,
                    "{c} {i}: {} {}",
                    got[i],
                    want[i]
                );
            }
        };
        check(Complex::new(3.7, 0.0));
        check(Complex::new(2.1, 4.3));
        // The real path (f64) against the complex one with zero imaginary part.
        let c = 3.7;
        let mut e = vec![0.0; n * n];
        condense(&jac, n, p, c, &mut e);
        let mut piv = vec![0; n];
        lu_factor(&mut e, n - p, &mut piv).unwrap();
        let mut x: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
        let b = x.clone();
        condensed_solve(&jac, n, p, c, &e, &piv, &mut x);
        // Residual of (cI - J) x = b.
        for i in 0..n {
            let mut r = c * x[i] - b[i];
            for j in 0..n {
                r -= jac[i + j * n] * x[j];
            }
            assert!(r.abs() < 1e-12 * n as f64, "row {i}: residual {r}");
        }
    }

    /// A second-order Jacobian with diagonal springs $k_i$, dampers $d_i$, a coupling of
    /// rank 2 through a "station" and two dense rows and columns $z$: the Woodbury solve
    /// against the full LU of $cI - J$ (independent: no condensation, no splitting), real
    /// and complex; a full coupling refused.
    #[test]
    fn woodbury_solve_matches_the_full_system() {
        use super::super::woodbury::{Coupling, Woodbury};
        use crate::ode::DiagonalSprings;
        let (p, mz) = (6, 2);
        let n = 2 * p + mz;
        let k: Vec<f64> = (0..p).map(|i| 1.0 + (i * i) as f64).collect();
        let d: Vec<f64> = (0..p).map(|i| 0.1 * (i + 1) as f64).collect();
        let phi = |i: usize| (1.0 + i as f64).sin();
        let psi = |i: usize| (0.3 * i as f64).cos();
        let mut jac = vec![0.0; n * n];
        let at = |i: usize, j: usize| i + j * n;
        for i in 0..p {
            jac[at(i, p + i)] = 1.0;
            jac[at(p + i, i)] = -k[i];
            jac[at(p + i, p + i)] = -d[i];
            for l in 0..p {
                jac[at(p + i, l)] -= phi(i) * 2.0 * phi(l) + psi(i) * psi(l);
                jac[at(p + i, p + l)] -= 0.5 * phi(i) * phi(l);
            }
            for z in 0..mz {
                jac[at(p + i, 2 * p + z)] = phi(i) * (1.0 + z as f64);
            }
        }
        for z in 2 * p..n {
            for j in 0..n {
                jac[at(z, j)] = ((z * 3 + j * 5) % 7) as f64 - 3.0;
            }
        }
        let springs = DiagonalSprings {
            stiffness: &k,
            damping: &d,
        };
        let mut cpl = Coupling::new(n);
        let mut scratch = vec![0.0; n * n];
        assert!(cpl.split(&jac, (n, p), springs, &mut scratch));
        assert!(cpl.rank() <= 5, "rank {}", cpl.rank());
        let b: Vec<Complex<f64>> = (0..n)
            .map(|i| Complex::new(1.0 + i as f64, 0.5 - i as f64))
            .collect();
        let full_solve = |c: Complex<f64>| {
            let mut full: Vec<Complex<f64>> = jac.iter().map(|&v| Complex::new(-v, 0.0)).collect();
            for i in 0..n {
                full[i * n + i] += c;
            }
            let mut piv = vec![0; n];
            lu_factor(&mut full, n, &mut piv).unwrap();
            let mut x = b.clone();
            lu_solve(&full, n, &piv, &mut x);
            x
        };
        let c = Complex::new(2.1, 4.3);
        let mut wb = Woodbury::new(n);
        assert!(wb.factor(&cpl, c));
        let mut got = b.clone();
        split_solve(&cpl, p, c, &wb, &mut got);
        let want = full_solve(c);
        let scale = want.iter().map(|v| v.norm()).fold(0.0, f64::max);
        for i in 0..n {
            assert!(
                (got[i] - want[i]).norm() < 1e-12 * scale,
                "{i}: {} {}",
                got[i],
                want[i]
            );
        }
        let c = 3.7;
        let mut wb = Woodbury::<f64>::new(n);
        assert!(wb.factor(&cpl, c));
        let mut got: Vec<f64> = b.iter().map(|v| v.re).collect();
        split_solve(&cpl, p, c, &wb, &mut got);
        let want = {
            let b_re: Vec<Complex<f64>> = b.iter().map(|v| Complex::new(v.re, 0.0)).collect();
            let mut full: Vec<Complex<f64>> = jac.iter().map(|&v| Complex::new(-v, 0.0)).collect();
            for i in 0..n {
                full[i * n + i] += Complex::new(c, 0.0);
            }
            let mut piv = vec![0; n];
            lu_factor(&mut full, n, &mut piv).unwrap();
            let mut x = b_re;
            lu_solve(&full, n, &piv, &mut x);
            x
        };
        for i in 0..n {
            assert!(
                (got[i] - want[i].re).abs() < 1e-12 * scale,
                "{i}: {} {}",
                got[i],
                want[i]
            );
        }
        // Coupled in every entry (a dense block of 12 velocity rows, beyond the largest
        // rank): not of low rank, the dense LU takes it.
        let p = 12;
        let n = 2 * p;
        let mut jac = vec![0.0; n * n];
        for i in 0..p {
            jac[i + (p + i) * n] = 1.0;
            for l in 0..n {
                jac[p + i + l * n] = ((i * 7 + l * 11) % 13) as f64;
            }
        }
        let (k, d) = (vec![1.0; p], vec![0.1; p]);
        let springs = DiagonalSprings {
            stiffness: &k,
            damping: &d,
        };
        let mut cpl = Coupling::new(n);
        let mut scratch = vec![0.0; n * n];
        assert!(!cpl.split(&jac, (n, p), springs, &mut scratch));
    }
}
