//! The Newton matrices of a second-order system with diagonal springs and a coupling of low
//! rank ([`OdeSystem::diagonal_springs`](crate::ode::OdeSystem::diagonal_springs)), solved by
//! the Sherman-Morrison-Woodbury formula in $O(Nr)$ a solve.
//!
//! With the state $(q, v, z)$ and $J = J_0 + \begin{pmatrix}0\\\\ U\end{pmatrix}W^\top$,
//! $J_0 = \begin{pmatrix}0 & I & 0\\\\ -K & -D & 0\\\\ 0 & 0 & \mathrm{diag}(G_{zz})\end{pmatrix}$
//! ($K$, $D$ the declared springs and dampers, $G_{zz}$ the diagonal of $J$'s own $z$ block),
//! $U$ ($N - p$ rows) and $W$ ($N$ rows) found once per Jacobian by cross approximation, the
//! condensed matrix (`newton::condense`) of $cI - J$ is
//! $$E(c) = \Delta(c) - U W_c^\top,\qquad \Delta = \mathrm{diag}\big(c + d_i + k_i/c,\ c - G_{z_iz_i}\big),
//! \qquad W_c = W_{vz} + W_q/c,$$
//! and $E^{-1} = \Delta^{-1} + \Delta^{-1}U\thinspace C^{-1}W_c^\top\Delta^{-1}$ with the
//! $r\times r$ capacitance matrix $C = I - W_c^\top\Delta^{-1}U$, factored by the crate's LU.

use crate::numeric::lu::{lu_factor, lu_solve, LuScalar};
use crate::ode::DiagonalSprings;

/// Largest rank handled (the rest of the matrix beyond it: the dense LU).
const MAX_RANK: usize = DiagonalSprings::MAX_RANK;

/// Entries of $J - J_0$ up to this times $\max_{ij}|J_{ij}|$ are dropped: the Newton matrix is
/// then off by as little, which slows the simplified Newton iteration by as little (it
/// converges with an approximate matrix anyway).
const DROP: f64 = 1e-12;

/// $J - J_0 = \begin{pmatrix}0\\\\ U\end{pmatrix}W^\top$ of one Jacobian (see the module docs).
#[derive(Debug, Clone)]
pub(super) struct Coupling {
    /// $U$, column-major $(N - p)\times r$ (leading columns of `MAX_RANK`).
    u: Vec<f64>,
    /// $W$, column-major $N\times r$.
    w: Vec<f64>,
    /// $G_{z_iz_i}$ for the rows $z$ (index $i - 2p$).
    gzz: Vec<f64>,
    /// The springs $k$ and dampers $d$ (leading $p$ entries).
    k: Vec<f64>,
    d: Vec<f64>,
    rank: usize,
    n: usize,
    p: usize,
}

impl Coupling {
    /// Storage for systems of size up to `n`.
    pub(super) fn new(n: usize) -> Self {
        Coupling {
            u: vec![0.0; n * MAX_RANK],
            w: vec![0.0; n * MAX_RANK],
            gzz: vec![0.0; n],
            k: vec![0.0; n],
            d: vec![0.0; n],
            rank: 0,
            n,
            p: 0,
        }
    }

    /// The rank $r$ of the coupling.
    #[cfg(test)]
    pub(super) fn rank(&self) -> usize {
        self.rank
    }

    /// Splits the column-major $N\times N$ Jacobian `jac` of a system of second order in $p$
    /// positions with the declared `springs`; `scratch` ($\ge (N-p)N$ entries) is
    /// overwritten. `false` when the springs are not $p$ long or $J - J_0$ is not within
    /// [`DROP`] of rank [`MAX_RANK`].
    pub(super) fn split(
        &mut self,
        jac: &[f64],
        (n, p): (usize, usize),
        springs: DiagonalSprings<'_>,
        scratch: &mut [f64],
    ) -> bool {
        if p == 0 || springs.stiffness.len() != p || springs.damping.len() != p {
            return false;
        }
        self.k[..p].copy_from_slice(springs.stiffness);
        self.d[..p].copy_from_slice(springs.damping);
        let (k, d) = (&self.k, &self.d);
        let m = n - p;
        (self.n, self.p) = (n, p);
        let mut big = 0.0f64;
        for j in 0..n {
            let col = &jac[j * n + p..(j + 1) * n];
            let out = &mut scratch[j * m..(j + 1) * m];
            out.copy_from_slice(col);
            for x in col {
                big = big.max(x.abs());
            }
        }
        for i in 0..p {
            scratch[i * m + i] += k[i];
            scratch[(p + i) * m + i] += d[i];
        }
        for i in p..m {
            self.gzz[i - p] = scratch[(p + i) * m + i];
            scratch[(p + i) * m + i] = 0.0;
        }
        if !big.is_finite() {
            return false;
        }
        match cross(
            &mut scratch[..m * n],
            m,
            n,
            DROP * big,
            &mut self.u,
            &mut self.w,
        ) {
            Some(r) => {
                self.rank = r;
                true
            }
            None => false,
        }
    }

    /// $b_{vz} \mathrel{+}= \frac1c A_q b_q$ with $A_q = \begin{pmatrix}-K\\\\ 0\end{pmatrix} +
    /// UW_q^\top$: the right-hand side of the condensed system.
    pub(super) fn add_position_rhs<T: LuScalar>(&self, inv_c: T, bq: &[T], bvz: &mut [T]) {
        let (p, m) = (self.p, self.n - self.p);
        for ((x, &b), &k) in bvz.iter_mut().zip(bq).zip(&self.k[..p]) {
            *x -= (b * inv_c).scale(k);
        }
        for a in 0..self.rank {
            let mut s = T::zero();
            for (&w, &b) in self.w[a * self.n..a * self.n + p].iter().zip(bq) {
                s += b.scale(w);
            }
            let s = s * inv_c;
            for (x, &u) in bvz.iter_mut().zip(&self.u[a * m..(a + 1) * m]) {
                *x += s.scale(u);
            }
        }
    }
}

/// Cross approximation with full pivoting of the column-major $m\times n$ matrix `e`
/// (overwritten by the residual): $e \approx UW^\top$, exact for a matrix of rank $r$ after
/// $r$ crosses; stops when no entry exceeds `tol`. The rank, or `None` beyond [`MAX_RANK`].
fn cross(
    e: &mut [f64],
    m: usize,
    n: usize,
    tol: f64,
    u: &mut [f64],
    w: &mut [f64],
) -> Option<usize> {
    for k in 0..=MAX_RANK {
        let (mut best, mut at) = (0.0, 0);
        for (idx, x) in e.iter().enumerate() {
            // A NaN counts as too large (and stops the cross below).
            if x.abs() > best || x.is_nan() {
                best = x.abs();
                at = idx;
            }
        }
        if best <= tol {
            return Some(k);
        }
        if k == MAX_RANK || !best.is_finite() {
            return None;
        }
        let (pi, pj) = (at % m, at / m);
        let inv = 1.0 / e[at];
        u[k * m..(k + 1) * m].copy_from_slice(&e[pj * m..(pj + 1) * m]);
        for j in 0..n {
            w[k * n + j] = e[j * m + pi] * inv;
        }
        let (uk, wk) = (&u[k * m..(k + 1) * m], &w[k * n..(k + 1) * n]);
        for (j, &wj) in wk.iter().enumerate() {
            if wj != 0.0 {
                for (x, &ui) in e[j * m..(j + 1) * m].iter_mut().zip(uk) {
                    *x -= ui * wj;
                }
            }
        }
    }
    None
}

/// The factors of one condensed matrix $E(c) = \Delta - UW_c^\top$ (module docs): $\Delta^{-1}$,
/// $\tilde U = \Delta^{-1}U$, $W_c$ and the LU of $C = I - W_c^\top\tilde U$, preallocated.
#[derive(Debug, Clone)]
pub(super) struct Woodbury<T> {
    dinv: Vec<T>,
    u: Vec<T>,
    w: Vec<T>,
    cap: Vec<T>,
    piv: Vec<usize>,
    rank: usize,
    m: usize,
}

impl<T: LuScalar> Woodbury<T> {
    /// Storage for systems of size up to `n`.
    pub(super) fn new(n: usize) -> Self {
        Woodbury {
            dinv: vec![T::zero(); n],
            u: vec![T::zero(); n * MAX_RANK],
            w: vec![T::zero(); n * MAX_RANK],
            cap: vec![T::zero(); MAX_RANK * MAX_RANK],
            piv: vec![0; MAX_RANK],
            rank: 0,
            m: 0,
        }
    }

    /// Factors $E(c)$ for the split `cpl`; `false` when $\Delta$ or $C$ is singular to
    /// working precision.
    pub(super) fn factor(&mut self, cpl: &Coupling, c: T) -> bool {
        let (n, p, r) = (cpl.n, cpl.p, cpl.rank);
        let (k, d) = (&cpl.k, &cpl.d);
        let m = n - p;
        (self.m, self.rank) = (m, r);
        let inv_c = T::one() / c;
        for i in 0..m {
            let delta = if i < p {
                c + T::from_real(d[i]) + inv_c.scale(k[i])
            } else {
                c - T::from_real(cpl.gzz[i - p])
            };
            let inv = T::one() / delta;
            if !inv.norm1().is_finite() || delta == T::zero() {
                return false;
            }
            self.dinv[i] = inv;
        }
        for a in 0..r {
            let (ua, wa) = (&cpl.u[a * m..(a + 1) * m], &cpl.w[a * n..(a + 1) * n]);
            for i in 0..m {
                self.u[a * m + i] = self.dinv[i].scale(ua[i]);
                let wq = if i < p { inv_c.scale(wa[i]) } else { T::zero() };
                self.w[a * m + i] = T::from_real(wa[p + i]) + wq;
            }
        }
        for b in 0..r {
            for a in 0..r {
                let wa = &self.w[a * m..(a + 1) * m];
                let ub = &self.u[b * m..(b + 1) * m];
                let mut s = if a == b { T::one() } else { T::zero() };
                for (&x, &y) in wa.iter().zip(ub) {
                    s -= x * y;
                }
                self.cap[a + b * r] = s;
            }
        }
        lu_factor(&mut self.cap[..r * r], r, &mut self.piv).is_ok()
    }

    /// Solves $E(c)x = b$ in place: $y = \Delta^{-1}b$, $s = C^{-1}W_c^\top y$, $x = y + \tilde U s$.
    pub(super) fn solve(&self, b: &mut [T]) {
        let (m, r) = (self.m, self.rank);
        for (x, &di) in b.iter_mut().zip(&self.dinv[..m]) {
            *x *= di;
        }
        if r == 0 {
            return;
        }
        let mut s = [T::zero(); MAX_RANK];
        for (a, sa) in s[..r].iter_mut().enumerate() {
            for (&w, &y) in self.w[a * m..(a + 1) * m].iter().zip(b.iter()) {
                *sa += w * y;
            }
        }
        lu_solve(&self.cap[..r * r], r, &self.piv, &mut s[..r]);
        for (a, &sa) in s[..r].iter().enumerate() {
            for (x, &u) in b.iter_mut().zip(&self.u[a * m..(a + 1) * m]) {
                *x += u * sa;
            }
        }
    }
}
