//! The ring's location on a prescribed branch: the smooth extension of one contact regime.
//!
//! [`SnubberRing::locate`](super::SnubberRing::locate) picks, for each axis, the branch of the
//! piecewise-linear force law the minimiser actually lies on, so $s^*(r)$ is continuous but its
//! derivative jumps at the regime boundaries. An integrator must not step across such a
//! kink: inside one contact regime the driver uses the *same* branch formulas extended beyond
//! the boundary, which are analytic, and an event moves it to the neighbouring branch when
//! $|s_i| = D_i$ is crossed.
//!
//! On a fixed branch each axis of the Lagrange condition $g_i(s) = 2\mu(r_i - s_i)$ is linear:
//! with $d = r - s$,
//!
//! $$d_i(\mu) = \frac{K_i\,(r_i + \sigma_i D_i)}{K_i + c_i\,\mu},\qquad
//! (\sigma_i, c_i) = \begin{cases}(0, 1) & \text{inner: } g_i = 2K_i s_i\\
//! (\pm1, 2) & \text{outer: } g_i = \pm K_i(\pm s_i + D_i)\end{cases}$$
//!
//! and $\mu$ solves $|d(\mu)| = \gamma$. Newton's method is applied to
//! $\varphi(\mu) = 1/|d(\mu)| - 1/\gamma$, which is *linear* in $\mu$ when both axes share $c$
//! and $K$ (regimes II and V of an isotropic ring: one step is exact), and nearly linear
//! otherwise.

use nalgebra::{Matrix2, Vector2};

use super::{Regime, RingAxis, SnubberRing};

/// The branch of one axis' force law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Branch {
    /// Both units act: $g = 2Ks$, damping $4\nu_2$.
    Inner,
    /// One unit lifted off: $g = K(s + \sigma D)$ with $\sigma = \pm1$ the side
    /// (0 for an axis without preload), damping $2\nu_2$.
    Outer(i8),
}

impl Branch {
    /// The branch a ring coordinate `s` lies on (boundary points count as inner, as in the
    /// paper's regime II; an axis without preload is always outer).
    pub fn of(axis: &RingAxis, s: f64) -> Self {
        if axis.preload == 0.0 {
            Branch::Outer(0)
        } else if s.abs() <= axis.preload {
            Branch::Inner
        } else if s > 0.0 {
            Branch::Outer(1)
        } else {
            Branch::Outer(-1)
        }
    }

    /// $(\sigma, c)$ of the branch formula.
    fn sigma_c(self) -> (f64, f64) {
        match self {
            Branch::Inner => (0.0, 1.0),
            Branch::Outer(s) => (f64::from(s), 2.0),
        }
    }

    /// Whether the axis is beyond its preload.
    pub fn is_outer(self) -> bool {
        matches!(self, Branch::Outer(_))
    }
}

/// Branches of both axes: a contact regime with the side of each lifted-off unit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Branches {
    /// Branch of the x axis.
    pub x: Branch,
    /// Branch of the y axis.
    pub y: Branch,
}

impl Branches {
    /// The branches of a ring position.
    pub fn of(ring: &SnubberRing, s: &Vector2<f64>) -> Self {
        Self {
            x: Branch::of(&ring.x, s.x),
            y: Branch::of(&ring.y, s.y),
        }
    }

    /// The contact regime (II..V) of these branches.
    pub fn regime(&self) -> Regime {
        match (self.x.is_outer(), self.y.is_outer()) {
            (false, false) => Regime::II,
            (true, false) => Regime::III,
            (false, true) => Regime::IV,
            (true, true) => Regime::V,
        }
    }
}

/// The ring in contact on fixed branches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BranchContact {
    /// Ring centre $s$, with $|r - s| = \gamma$ to rounding.
    pub s: Vector2<f64>,
    /// Lagrange multiplier $\mu$ (negative on the extension below $|r| = \gamma$).
    pub mu: f64,
    /// Unit contact normal $n = (r - s)/\gamma$.
    pub normal: Vector2<f64>,
    /// $J = \partial s/\partial r$ on these branches.
    pub jacobian: Matrix2<f64>,
    /// Diagonal of the damping matrix $C$ on these branches.
    pub damping: Vector2<f64>,
    /// Elastic force $g(s) = 2\mu(r - s)$.
    pub elastic: Vector2<f64>,
    /// Newton iterations used.
    pub iterations: u32,
}

impl BranchContact {
    /// Ring velocity $s' = J r'$.
    pub fn ring_velocity(&self, r_dot: &Vector2<f64>) -> Vector2<f64> {
        self.jacobian * r_dot
    }

    /// Total ring force on the rotor $f = g(s) + C J r'$.
    pub fn force(&self, r_dot: &Vector2<f64>) -> Vector2<f64> {
        self.elastic + self.damping.component_mul(&self.ring_velocity(r_dot))
    }
}

impl SnubberRing {
    /// Locates the ring on the given branches (the smooth extension of that regime), warm
    /// started from `mu_hint` (pass `f64::NAN` for none). Returns `None` only for inputs with no
    /// solution (non-finite `r`, or an axis with zero stiffness on which the extension is
    /// singular).
    pub fn locate_on(
        &self,
        r: &Vector2<f64>,
        branches: Branches,
        mu_hint: f64,
    ) -> Option<BranchContact> {
        let (sx, cx) = branches.x.sigma_c();
        let (sy, cy) = branches.y.sigma_c();
        let (kx, ky) = (self.x.stiffness, self.y.stiffness);
        let ax = kx * (r.x + sx * self.x.preload);
        let ay = ky * (r.y + sy * self.y.preload);
        if kx == ky && cx == cy {
            return self.locate_on_uniform(r, branches, ax, ay, cx);
        }
        let inv_gap = self.gap.recip();
        // Pole of d(mu): mu must stay above -min(K_i / c_i).
        let pole = -(kx / cx).min(ky / cy);
        let mut mu = if mu_hint.is_finite() && mu_hint > pole {
            mu_hint
        } else {
            // Exact when both axes share K and c.
            let c = 0.5 * (cx + cy);
            let k = 0.5 * (kx + ky);
            (k * (ax * ax + ay * ay).sqrt() / k.max(f64::MIN_POSITIVE) * inv_gap - k) / c
        };
        if !mu.is_finite() || mu <= pole {
            mu = 0.0f64.max(pole * 0.5);
        }
        let mut iterations = 0;
        let mut d = Vector2::zeros();
        while iterations < 60 {
            iterations += 1;
            let (ex, ey) = (kx + cx * mu, ky + cy * mu);
            d = Vector2::new(ax / ex, ay / ey);
            let dn2 = d.norm_squared();
            let dn = dn2.sqrt();
            // phi = 1/|d| - 1/gap; phi' = (sum c_i d_i^2 / e_i) / |d|^3
            let phi = dn.recip() - inv_gap;
            let dphi = (cx * d.x * d.x / ex + cy * d.y * d.y / ey) / (dn2 * dn);
            if !(phi.is_finite() && dphi.is_finite()) || dphi <= 0.0 {
                return None;
            }
            let mut next = mu - phi / dphi;
            if next <= pole {
                next = 0.5 * (mu + pole);
            }
            // mu enters as K_i + c_i mu: it is resolved to rounding relative to that sum.
            let done = (next - mu).abs() <= 4.0 * f64::EPSILON * (mu.abs() + kx.max(ky))
                || phi.abs() <= 2.0 * f64::EPSILON * inv_gap;
            mu = next;
            if done {
                let (ex, ey) = (kx + cx * mu, ky + cy * mu);
                d = Vector2::new(ax / ex, ay / ey);
                break;
            }
        }
        let dn = d.norm();
        if !(dn > 0.0 && dn.is_finite()) {
            return None;
        }
        let normal = d / dn;
        let dvec = normal * self.gap;
        let s = r - dvec;
        // g'(s) + 2 mu on each branch: inner 2K + 2mu, outer K + 2mu.
        let gp = |b: Branch, k: f64| if b.is_outer() { k } else { 2.0 * k };
        let a_inv = Vector2::new(
            (gp(branches.x, kx) + 2.0 * mu).recip(),
            (gp(branches.y, ky) + 2.0 * mu).recip(),
        );
        let w = a_inv.component_mul(&dvec);
        let jacobian = Matrix2::from_diagonal(&(a_inv * (2.0 * mu)))
            + w * (dvec - w * (2.0 * mu)).transpose() / dvec.dot(&w);
        let unit = |b: Branch| if b.is_outer() { 2.0 } else { 4.0 } * self.damping;
        Some(BranchContact {
            s,
            mu,
            normal,
            jacobian,
            damping: Vector2::new(unit(branches.x), unit(branches.y)),
            elastic: dvec * (2.0 * mu),
            iterations,
        })
    }
}

impl SnubberRing {
    /// Closed form when both axes share $K$ and $c$ (regimes II and V of an isotropic
    /// ring): $|d| = K|a|/(K + c\mu) = \gamma$ with $a = r + \sigma D$, so
    /// $\mu = K(|a|/\gamma - 1)/c$, $d = \gamma a/|a|$, and with $\alpha = g' + 2\mu$ the same on
    /// both axes, $J = (2\mu/\alpha) I + (1 - 2\mu/\alpha)\, n n^T$.
    fn locate_on_uniform(
        &self,
        r: &Vector2<f64>,
        branches: Branches,
        ax: f64,
        ay: f64,
        c: f64,
    ) -> Option<BranchContact> {
        let k = self.x.stiffness;
        // Plain sqrt, not hypot: the arguments are O(K), far from overflow, and hypot is slow.
        let a_norm = (ax * ax + ay * ay).sqrt();
        if !(a_norm > 0.0 && a_norm.is_finite()) {
            return None;
        }
        let mu = (a_norm / self.gap - k) / c;
        let normal = Vector2::new(ax, ay) * a_norm.recip();
        let dvec = normal * self.gap;
        let outer = branches.x.is_outer();
        let alpha = if outer { k } else { 2.0 * k } + 2.0 * mu;
        let ratio = 2.0 * mu / alpha;
        let q = 1.0 - ratio;
        let nxy = q * normal.x * normal.y;
        let jacobian = Matrix2::new(
            ratio + q * normal.x * normal.x,
            nxy,
            nxy,
            ratio + q * normal.y * normal.y,
        );
        let unit = if outer { 2.0 } else { 4.0 } * self.damping;
        Some(BranchContact {
            s: r - dvec,
            mu,
            normal,
            jacobian,
            damping: Vector2::new(unit, unit),
            elastic: dvec * (2.0 * mu),
            iterations: 0,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rings() -> Vec<SnubberRing> {
        let a = |k, d| RingAxis {
            stiffness: k,
            preload: d,
        };
        vec![
            SnubberRing::isotropic(30.0, 0.0, 0.002).unwrap(),
            SnubberRing::isotropic(30.0, 0.1, 0.002).unwrap(),
            SnubberRing::new(a(30.0, 0.1), a(12.0, 0.3), 0.002, 1.0).unwrap(),
            SnubberRing::new(a(1000.0, 0.05), a(1000.0, 0.0), 0.01, 1.0).unwrap(),
        ]
    }

    #[test]
    fn agrees_with_the_general_solver_on_the_actual_branch() {
        for ring in rings() {
            for i in 0..400 {
                let ang = i as f64 * 0.137;
                let rad = 1.0 + 0.002 * (i % 97) as f64 + 1e-6;
                let r = Vector2::new(rad * ang.cos(), rad * ang.sin());
                let c = ring.locate(&r).unwrap();
                let b = Branches::of(&ring, &c.s);
                let e = ring.locate_on(&r, b, f64::NAN).unwrap();
                assert!((e.s - c.s).norm() < 1e-12, "{ring:?} {r:?}");
                assert!(((r - e.s).norm() - 1.0).abs() < 1e-14);
                assert!((e.jacobian - c.jacobian).norm() < 1e-8 * c.jacobian.norm().max(1.0));
                assert!(e.iterations <= 8, "{} iterations", e.iterations);
            }
        }
    }

    #[test]
    fn jacobian_matches_finite_differences_on_the_extension() {
        let ring = rings()[2];
        let b = Branches {
            x: Branch::Outer(1),
            y: Branch::Inner,
        };
        let r = Vector2::new(1.05, 0.2);
        let c = ring.locate_on(&r, b, f64::NAN).unwrap();
        let h = 1e-6;
        for j in 0..2 {
            let mut rp = r;
            let mut rm = r;
            rp[j] += h;
            rm[j] -= h;
            let sp = ring.locate_on(&rp, b, f64::NAN).unwrap().s;
            let sm = ring.locate_on(&rm, b, f64::NAN).unwrap().s;
            let col = (sp - sm) / (2.0 * h);
            assert!((col - c.jacobian.column(j)).norm() < 1e-7);
        }
    }
}
