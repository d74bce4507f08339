use nalgebra::{Matrix2, Vector2};

use super::element::{preload_sign, Kinematics, RingCache, RingGuard, RingMode};
use super::{Branch, Branches, Relaxation, RingAxis, RingContact, SnubberRing};

/// Second derivatives of the ring located on fixed branches (module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactHessian {
    /// $\partial\mu/\partial r$.
    pub mu_gradient: Vector2<f64>,
    /// $\partial J/\partial r_k$ for $k = x, y$: entry $(i, j)$ of element $k$ is
    /// $\partial^2 s_i^*/\partial r_j\partial r_k$ (symmetric in $j, k$).
    pub jacobian_derivative: [Matrix2<f64>; 2],
    /// $\partial^2\mu/\partial r^2$ (symmetric).
    pub mu_hessian: Matrix2<f64>,
}

impl ContactHessian {
    /// $\partial(J v)/\partial r$ at fixed $v$: column $k$ is $(\partial J/\partial r_k)\thinspace v$.
    pub fn jacobian_times(&self, v: &Vector2<f64>) -> Matrix2<f64> {
        let [dx, dy] = &self.jacobian_derivative;
        Matrix2::from_columns(&[dx * v, dy * v])
    }
}

/// Jacobian of the contact force $F(r, v) = g(s^*(r)) + C J(r) v$ on fixed branches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceJacobian {
    /// $\partial F/\partial r = G^\prime J + C\thinspace \partial(Jv)/\partial r$.
    pub position: Matrix2<f64>,
    /// $\partial F/\partial v = C J$.
    pub velocity: Matrix2<f64>,
    /// The force $F(r, v)$ itself, for a rotor whose force input depends on its state (a
    /// driven rotor's, through the out-of-balance's phase).
    pub force: Vector2<f64>,
}

impl ForceJacobian {
    /// $\partial F/\partial r = G^\prime J + C\thinspace\partial(Jv)/\partial r$ and
    /// $\partial F/\partial v = CJ$ from the branches' slopes $G^\prime$ and damping $C$ (both
    /// diagonal) and a located ring's $J$ and second derivatives.
    pub(super) fn of(
        slopes: Vector2<f64>,
        damping: Vector2<f64>,
        jacobian: &Matrix2<f64>,
        hess: &ContactHessian,
        v: &Vector2<f64>,
        force: Vector2<f64>,
    ) -> Self {
        let damping = Matrix2::from_diagonal(&damping);
        ForceJacobian {
            position: Matrix2::from_diagonal(&slopes) * jacobian + damping * hess.jacobian_times(v),
            velocity: damping * jacobian,
            force,
        }
    }
}

/// Gradient of a guard of the ring (module docs) with respect to the rotor's kinematics at the
/// station, the ring's current position and time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuardGradient {
    /// $\partial g/\partial r$.
    pub r: Vector2<f64>,
    /// $\partial g/\partial v$.
    pub v: Vector2<f64>,
    /// $\partial g/\partial s$, the ring's position at time $t$: nonzero only for the onset guard,
    /// whose ring relaxes independently of the rotor. Chain it with the relaxation's
    /// sensitivities ([`Relaxation::sensitivity`], [`Relaxation::start_time_sensitivity`]) for
    /// perturbations of where and when the relaxation started.
    pub s: Vector2<f64>,
    /// $\partial g/\partial t$ at fixed $(r, v)$ and a fixed relaxation (its start $s_0$, $t_0$):
    /// $-2q\cdot s^\prime(t)$ for the onset guard, 0 for the contact guards.
    pub t: f64,
}

impl GuardGradient {
    fn rotor(r: Vector2<f64>, v: Vector2<f64>) -> Self {
        Self {
            r,
            v,
            s: Vector2::zeros(),
            t: 0.0,
        }
    }
}

/// Elastic slopes $g_i^\prime$ on the branches: $2K_i$ inner, $K_i$ outer.
pub(super) fn branch_slopes(ring: &SnubberRing, b: Branches) -> Vector2<f64> {
    let slope = |axis: &RingAxis, branch: Branch| {
        if branch.is_outer() {
            axis.stiffness
        } else {
            2.0 * axis.stiffness
        }
    };
    Vector2::new(slope(&ring.x, b.x), slope(&ring.y, b.y))
}

/// Solver of the bordered system $\mathcal M (x; m) = (b_1; b_2)$ through the diagonal $A$.
struct Bordered {
    inv_a: Vector2<f64>,
    d: Vector2<f64>,
    /// $1/(2\thinspace d\cdot A^{-1}d)$.
    inv_dw2: f64,
}

impl Bordered {
    fn new(ring: &SnubberRing, c: &RingContact) -> Self {
        let slopes = branch_slopes(ring, c.branches);
        let inv_a = Vector2::new(1.0 / (slopes.x + 2.0 * c.mu), 1.0 / (slopes.y + 2.0 * c.mu));
        let d = c.normal * ring.gap;
        let dw = d.dot(&d.component_mul(&inv_a));
        Self {
            inv_a,
            d,
            inv_dw2: 0.5 / dw,
        }
    }

    fn solve(&self, b1: &Vector2<f64>, b2: f64) -> (Vector2<f64>, f64) {
        let ab1 = b1.component_mul(&self.inv_a);
        let m = (b2 - self.d.dot(&ab1)) * self.inv_dw2;
        let x = (b1 + self.d * (2.0 * m)).component_mul(&self.inv_a);
        (x, m)
    }
}

impl SnubberRing {
    /// Second derivatives of the ring located on `c`'s branches: $\partial\mu/\partial r$,
    /// $\partial^2\mu/\partial r^2$ and $\partial J/\partial r$ (module docs). `c` must come from
    /// [`SnubberRing::locate`] or [`SnubberRing::locate_on`] of this ring.
    pub fn contact_hessian(&self, c: &RingContact) -> ContactHessian {
        let sys = Bordered::new(self, c);
        let e = [Vector2::x(), Vector2::y()];
        // First derivatives: J e_k (recomputed here, equal to c.jacobian to rounding) and mu_k.
        let first: [(Vector2<f64>, f64); 2] =
            std::array::from_fn(|k| sys.solve(&(e[k] * (2.0 * c.mu)), sys.d[k]));
        let slip: [Vector2<f64>; 2] = std::array::from_fn(|k| e[k] - first[k].0);
        let mut dj = [Matrix2::zeros(); 2];
        let mut mu_hessian = Matrix2::zeros();
        for k in 0..2 {
            for j in 0..2 {
                let b1 = slip[j] * (2.0 * first[k].1) + slip[k] * (2.0 * first[j].1);
                let (h, m) = sys.solve(&b1, slip[k].dot(&slip[j]));
                dj[k].set_column(j, &h);
                mu_hessian[(j, k)] = m;
            }
        }
        ContactHessian {
            mu_gradient: Vector2::new(first[0].1, first[1].1),
            jacobian_derivative: dj,
            mu_hessian,
        }
    }

    /// Jacobian of the contact force $F = g(s^*(r)) + C J v$ on `c`'s branches at rotor
    /// velocity `v` (module docs).
    pub fn force_jacobian(&self, c: &RingContact, v: &Vector2<f64>) -> ForceJacobian {
        let hess = self.contact_hessian(c);
        self.force_jacobian_with(c, &hess, v)
    }

    fn force_jacobian_with(
        &self,
        c: &RingContact,
        hess: &ContactHessian,
        v: &Vector2<f64>,
    ) -> ForceJacobian {
        let slopes = branch_slopes(self, c.branches);
        ForceJacobian::of(slopes, c.damping, &c.jacobian, hess, v, c.force(v))
    }

    /// Gradient of the loss force $\max(N, \lambda)$ of [`RingContact::loss_force`] at rotor
    /// velocity `v` (of whichever of the two is the larger; module docs).
    pub fn loss_force_gradient(&self, c: &RingContact, v: &Vector2<f64>) -> GuardGradient {
        let jac = self.force_jacobian(c, v);
        let n = c.normal;
        // dn/dr = (I - J)/gamma.
        let dn = (Matrix2::identity() - c.jacobian) / self.gap;
        let force = c.force(v);
        let normal_gradient = || {
            GuardGradient::rotor(
                dn.transpose() * force + jac.position.transpose() * n,
                jac.velocity.transpose() * n,
            )
        };
        let (cx, cy) = (c.damping.x, c.damping.y);
        if cx == cy || c.normal_force(v) >= c.separation_force(v) {
            return normal_gradient();
        }
        // lambda = a/b (module docs), g = G' J-driven elastic force.
        let g = c.elastic;
        let dg = Matrix2::from_diagonal(&branch_slopes(self, c.branches)) * c.jacobian;
        let (dnx, dny) = (dn.row(0).transpose(), dn.row(1).transpose());
        let (dgx, dgy) = (dg.row(0).transpose(), dg.row(1).transpose());
        let a = cx * cy * n.dot(v) + cy * n.x * g.x + cx * n.y * g.y;
        let b = cy * n.x * n.x + cx * n.y * n.y;
        let lambda = a / b;
        let da_r = dn.transpose() * v * (cx * cy)
            + (dnx * g.x + dgx * n.x) * cy
            + (dny * g.y + dgy * n.y) * cx;
        let db_r = dnx * (2.0 * cy * n.x) + dny * (2.0 * cx * n.y);
        GuardGradient::rotor((da_r - db_r * lambda) / b, n * (cx * cy / b))
    }

    /// Gradient of `guard` of `mode` at time `t` and rotor kinematics `k` (module docs); `None`
    /// for a guard that does not belong to `mode` or a contact that cannot be placed on the
    /// mode's branches. The values are those of [`SnubberRing::guard_value`] differentiated.
    pub fn guard_gradient(
        &self,
        mode: &RingMode,
        guard: RingGuard,
        t: f64,
        k: &Kinematics,
        cache: &RingCache,
    ) -> Option<GuardGradient> {
        match (mode, guard) {
            (RingMode::Free { relax, .. }, RingGuard::Onset) => {
                let (s, s_dot) = relax.at(self, t);
                let q = k.r - s;
                Some(GuardGradient {
                    r: q * 2.0,
                    v: Vector2::zeros(),
                    s: q * -2.0,
                    t: -2.0 * q.dot(&s_dot),
                })
            }
            (RingMode::Contact(_), RingGuard::Gap) => {
                Some(GuardGradient::rotor(k.r * 2.0, Vector2::zeros()))
            }
            (RingMode::Contact(b), RingGuard::Loss) => {
                let c = self.contact_on(*b, &k.r, cache).ok()?;
                Some(self.loss_force_gradient(&c, &k.v))
            }
            (RingMode::Contact(b), RingGuard::Preload { axis, .. }) => {
                let c = self.contact_on(*b, &k.r, cache).ok()?;
                let i = axis.index();
                let sign = preload_sign(b, axis, c.s[i]);
                Some(GuardGradient::rotor(
                    c.jacobian.row(i).transpose() * sign,
                    Vector2::zeros(),
                ))
            }
            _ => None,
        }
    }

    /// Per axis, $\partial s(t)/\partial s_0$ of the free ring started at `s0` and relaxed for a
    /// time `t` (module docs): $e^{-t/T}$, halved after the preload crossing of an axis started
    /// beyond its preload; 1 for `t <= 0`; 0 for `t > 0` without ring damping.
    pub fn relax_sensitivity(&self, s0: &Vector2<f64>, t: f64) -> Vector2<f64> {
        let t1 = self.time_to_preload(s0);
        let axis = |i: usize, axis: &RingAxis| {
            if t <= 0.0 {
                return 1.0;
            }
            if self.damping == 0.0 {
                return 0.0;
            }
            let tc = 2.0 * self.damping / axis.stiffness;
            let decay = (-t / tc).exp();
            let crossed = axis.preload > 0.0 && !axis.is_inside(s0[i]) && t > t1[i];
            if crossed {
                0.5 * decay
            } else {
                decay
            }
        };
        Vector2::new(axis(0, &self.x), axis(1, &self.y))
    }
}

impl Relaxation {
    /// Per axis, $\partial s(t)/\partial s_0$: the sensitivity of the relaxing ring at time `t`
    /// to its position at the start `t0` ([`SnubberRing::relax_sensitivity`]).
    pub fn sensitivity(&self, ring: &SnubberRing, t: f64) -> Vector2<f64> {
        ring.relax_sensitivity(&self.s0, t - self.t0)
    }

    /// Per axis, $\partial s(t)/\partial t_0 = -s^\prime(t)$: the sensitivity of the relaxing ring
    /// at time `t > t0` to the start time (at a fixed start position). Zero for `t <= t0`
    /// (where the relaxation returns $s_0$) and without ring damping.
    pub fn start_time_sensitivity(&self, ring: &SnubberRing, t: f64) -> Vector2<f64> {
        if t <= self.t0 || ring.damping == 0.0 {
            return Vector2::zeros();
        }
        -ring.relax_velocity(&ring.relax(&self.s0, t - self.t0))
    }
}
