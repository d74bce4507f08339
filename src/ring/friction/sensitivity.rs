//! Second derivatives of the slipping ring, its force's Jacobian, and the gradients of the
//! friction's own guards: what implicit integrators and the variational equations need.

use nalgebra::{Matrix2, Vector2};

use super::{FrictionRing, RollContact, SlipContact};
use crate::ring::sensitivity::branch_slopes;
use crate::ring::{Branch, ContactHessian, ForceJacobian, GuardGradient, RingAxis, RingContact};

/// $\beta_i$ of a branch: $K$ inside the preload, $K/2$ beyond it.
fn beta(axis: &RingAxis, branch: Branch) -> f64 {
    if branch.is_outer() {
        0.5 * axis.stiffness
    } else {
        axis.stiffness
    }
}

/// The 2-D cross product $a \times b = a_x b_y - a_y b_x$.
fn cross(a: &Vector2<f64>, b: &Vector2<f64>) -> f64 {
    a.x * b.y - a.y * b.x
}

impl SlipContact {
    /// The frictionless ring's record of this location (its fields, bit for bit).
    fn frictionless_record(&self) -> RingContact {
        RingContact {
            s: self.s,
            mu: self.multiplier,
            normal: self.normal,
            jacobian: self.jacobian,
            branches: self.branches,
            damping: self.damping,
            elastic: self.elastic,
            iterations: self.iterations,
        }
    }
}

impl FrictionRing {
    /// Second derivatives of the slipping ring on `c`'s branches at fixed $\sigma$:
    /// $\partial m/\partial r$, $\partial^2 m/\partial r^2$ and $\partial J/\partial r$
    /// ([`ContactHessian`], its `mu` fields holding the multiplier $m$). Differentiating
    /// $\gamma A(m) n(\theta) = \alpha(r)$ twice, along $e$ and $e^\prime$: the first
    /// derivatives solve $\gamma At\thinspace\theta_e + \gamma Mn\thinspace m_e = Be$, the second
    /// the same system with the right-hand side
    /// $-\gamma\left[Mt(\theta_e m_{e^\prime} + \theta_{e^\prime}m_e) - An\thinspace\theta_e
    /// \theta_{e^\prime}\right]$, and $\partial^2 s[e, e^\prime] = \gamma(n\thinspace\theta_e
    /// \theta_{e^\prime} - t\thinspace\theta_{ee^\prime})$. Without friction, the frictionless
    /// ring's [`contact_hessian`](crate::ring::SnubberRing::contact_hessian) bit for bit. `c`
    /// must come from this ring.
    pub fn slip_hessian(&self, c: &SlipContact) -> ContactHessian {
        if c.friction == 0.0 {
            return self.ring.contact_hessian(&c.frictionless_record());
        }
        let (gap, n, t, m, k) = (self.ring.gap, c.normal, c.tangent, c.multiplier, c.friction);
        let b = Vector2::new(
            beta(&self.ring.x, c.branches.x),
            beta(&self.ring.y, c.branches.y),
        );
        let a = Matrix2::new(b.x + m, -k * m, k * m, b.y + m);
        let big_m = Matrix2::new(1.0, -k, k, 1.0);
        let (u, v) = (a * t * gap, big_m * n * gap);
        let det = cross(&u, &v);
        // (theta, m) of [U | V] (theta, m) = rhs, by Cramer's rule.
        let solve = |rhs: Vector2<f64>| (cross(&rhs, &v) / det, cross(&u, &rhs) / det);
        let first = [solve(Vector2::new(b.x, 0.0)), solve(Vector2::new(0.0, b.y))];
        let (mt, an) = (big_m * t, a * n);
        let mut jacobian_derivative = [Matrix2::zeros(); 2];
        let mut mu_hessian = Matrix2::zeros();
        for kk in 0..2 {
            for j in 0..2 {
                let ((th_j, m_j), (th_k, m_k)) = (first[j], first[kk]);
                let rhs = -(mt * (th_j * m_k + th_k * m_j) - an * (th_j * th_k)) * gap;
                let (th_jk, m_jk) = solve(rhs);
                let column = (n * (th_j * th_k) - t * th_jk) * gap;
                jacobian_derivative[kk].set_column(j, &column);
                mu_hessian[(j, kk)] = m_jk;
            }
        }
        ContactHessian {
            mu_gradient: Vector2::new(first[0].1, first[1].1),
            jacobian_derivative,
            mu_hessian,
        }
    }

    /// Jacobian of the slipping ring's force $F = g(s(r)) + CJ(r)v$ at rotor velocity `v`
    /// (as [`SnubberRing::force_jacobian`](crate::ring::SnubberRing::force_jacobian)).
    pub fn slip_force_jacobian(&self, c: &SlipContact, v: &Vector2<f64>) -> ForceJacobian {
        self.force_jacobian_with(c, v, &self.slip_hessian(c))
    }

    /// [`FrictionRing::slip_force_jacobian`] and [`FrictionRing::slip_velocity_gradient`] at
    /// rotor velocity `v`, from one [`FrictionRing::slip_hessian`] (the rates of a slipping
    /// contact's guards need both).
    pub fn slip_rates(&self, c: &SlipContact, v: &Vector2<f64>) -> (ForceJacobian, GuardGradient) {
        let hess = self.slip_hessian(c);
        (
            self.force_jacobian_with(c, v, &hess),
            velocity_gradient_with(c, v, &hess),
        )
    }

    fn force_jacobian_with(
        &self,
        c: &SlipContact,
        v: &Vector2<f64>,
        hess: &ContactHessian,
    ) -> ForceJacobian {
        let slopes = branch_slopes(&self.ring, c.branches);
        ForceJacobian::of(slopes, c.damping, &c.jacobian, hess, v, c.force(v))
    }

    /// Gradient of the slip velocity $v = (r^\prime - Jr^\prime)\cdot t + \eta a$ of a slipping
    /// contact at rotor velocity `r_dot` (the guard that ends slipping): with respect to $r$,
    /// $-(\partial(Jr^\prime)/\partial r)^{\mathsf T} t$ (the turning of $t$ drops out, as
    /// $(I - J)r^\prime$ lies along $t$), and to $r^\prime$, $(I - J)^{\mathsf T} t$; its
    /// derivative with respect to the surface speed $\eta a$ is 1.
    pub fn slip_velocity_gradient(&self, c: &SlipContact, r_dot: &Vector2<f64>) -> GuardGradient {
        velocity_gradient_with(c, r_dot, &self.slip_hessian(c))
    }

    /// Gradient of the rolling contact's [`RollContact::stick_margin`]
    /// $\mu_f N - |F_t|$ with respect to the rotor's position and to the contact direction
    /// $\theta$: with $G^\prime$ the branches' slopes, $\nabla_r N = G^\prime n$,
    /// $\nabla_r F_t = G^\prime t$, $\partial_\theta N = F_t - \gamma\thinspace n\cdot G^\prime t$,
    /// $\partial_\theta F_t = -N - \gamma\thinspace t\cdot G^\prime t$.
    pub fn stick_margin_gradient(&self, c: &RollContact) -> (Vector2<f64>, f64) {
        let slopes = Matrix2::from_diagonal(&branch_slopes(&self.ring, c.branches));
        let (n, t, gap) = (c.normal, c.tangent, self.ring.gap);
        let (normal, tangential) = (c.elastic_normal(), c.elastic_tangential());
        let sign = tangential.signum();
        let r = slopes * n * self.friction - slopes * t * sign;
        let d_normal = tangential - gap * n.dot(&(slopes * t));
        let d_tangential = -normal - gap * t.dot(&(slopes * t));
        (r, self.friction * d_normal - sign * d_tangential)
    }
}

/// The slip velocity's gradient ([`FrictionRing::slip_velocity_gradient`]) from the contact's
/// second derivatives `hess`.
fn velocity_gradient_with(
    c: &SlipContact,
    r_dot: &Vector2<f64>,
    hess: &ContactHessian,
) -> GuardGradient {
    GuardGradient {
        r: -(hess.jacobian_times(r_dot).transpose() * c.tangent),
        v: (Matrix2::identity() - c.jacobian).transpose() * c.tangent,
        s: Vector2::zeros(),
        t: 0.0,
    }
}
