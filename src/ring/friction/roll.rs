//! The rolling ring: the contact direction is a state, the forces follow from it.

use nalgebra::Vector2;

use super::{FrictionRing, Slip};
use crate::ring::{check_finite, Branches, Regime, RingError};

/// The ring in contact with a shaft rolling on it at the contact direction $\theta$
/// ([`FrictionRing::rolling`]): $s = r - \gamma n(\theta)$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RollContact {
    /// Ring centre $s = r - \gamma n$.
    pub s: Vector2<f64>,
    /// The contact direction $\theta$ (radians).
    pub angle: f64,
    /// Unit contact normal $n = (\cos\theta, \sin\theta)$.
    pub normal: Vector2<f64>,
    /// Unit tangent $t = (-\sin\theta, \cos\theta)$.
    pub tangent: Vector2<f64>,
    /// The force-law branch of each axis at $s$.
    pub branches: Branches,
    /// Diagonal of the damping matrix $C$ on these branches.
    pub damping: Vector2<f64>,
    /// Elastic force $g(s)$.
    pub elastic: Vector2<f64>,
}

impl RollContact {
    /// The contact regime (II..V) of the ring's position.
    pub fn regime(&self) -> Regime {
        self.branches.regime()
    }

    /// The elastic normal force $N = n\cdot g(s)$.
    pub fn elastic_normal(&self) -> f64 {
        self.normal.dot(&self.elastic)
    }

    /// The elastic tangential force $F_t = t\cdot g(s)$.
    pub fn elastic_tangential(&self) -> f64 {
        self.tangent.dot(&self.elastic)
    }

    /// The rate of the contact direction while rolling, $\theta^\prime = -\eta a/\gamma$, for
    /// the surface speed `surface_speed` $= \eta a$ and constraint radius `gap`.
    pub fn angle_rate(surface_speed: f64, gap: f64) -> f64 {
        -surface_speed / gap
    }

    /// Ring velocity while rolling, $s^\prime = r^\prime - \gamma\theta^\prime t =
    /// r^\prime + \eta a\thinspace t$.
    pub fn ring_velocity(&self, r_dot: &Vector2<f64>, surface_speed: f64) -> Vector2<f64> {
        r_dot + self.tangent * surface_speed
    }

    /// Total force of the ring on the rotor, $f = g(s) + C s^\prime$.
    pub fn force(&self, r_dot: &Vector2<f64>, surface_speed: f64) -> Vector2<f64> {
        self.elastic
            + self
                .damping
                .component_mul(&self.ring_velocity(r_dot, surface_speed))
    }

    /// The loss force $\max(n\cdot f, \lambda)$ ([`SlipContact::loss_force`](super::SlipContact::loss_force)):
    /// contact lasts while it is positive.
    pub fn loss_force(&self, r_dot: &Vector2<f64>, surface_speed: f64) -> f64 {
        let normal = self.normal.dot(&self.force(r_dot, surface_speed));
        crate::ring::element::loss_force(self.damping, self.normal, self.elastic, normal, r_dot)
    }

    /// $\mu_f N - |F_t|$: rolling lasts while it is not negative.
    pub fn stick_margin(&self, friction: f64) -> f64 {
        friction * self.elastic_normal() - self.elastic_tangential().abs()
    }

    /// The sense in which the contact slips when rolling ends: that of $F_t$.
    pub fn release(&self) -> Option<Slip> {
        Slip::of(self.elastic_tangential())
    }
}

impl FrictionRing {
    /// The ring with the shaft at `r` rolling on it at the contact direction `angle`.
    ///
    /// # Errors
    /// [`RingError::NonFinite`] (`"r.x"`, `"r.y"`, `"angle"`).
    pub fn rolling(&self, r: &Vector2<f64>, angle: f64) -> Result<RollContact, RingError> {
        self.rolling_at(r, angle, None)
    }

    /// As [`FrictionRing::rolling`] on given branches: their force law's smooth (affine)
    /// extension, $g_i = 2K_is_i$ inner and $K_i(s_i + \sigma D_i)$ outer, wherever $s$ lies
    /// (a rolling mode keeps its branches until a preload crossing's event changes them).
    ///
    /// # Errors
    /// As [`FrictionRing::rolling`].
    pub fn rolling_on(
        &self,
        r: &Vector2<f64>,
        angle: f64,
        branches: Branches,
    ) -> Result<RollContact, RingError> {
        self.rolling_at(r, angle, Some(branches))
    }

    fn rolling_at(
        &self,
        r: &Vector2<f64>,
        angle: f64,
        branches: Option<Branches>,
    ) -> Result<RollContact, RingError> {
        check_finite("r.x", r.x)?;
        check_finite("r.y", r.y)?;
        check_finite("angle", angle)?;
        let (sin, cos) = angle.sin_cos();
        let (normal, tangent) = (Vector2::new(cos, sin), Vector2::new(-sin, cos));
        let s = r - normal * self.ring.gap;
        let (branches, elastic) = match branches {
            None => (Branches::of(&self.ring, &s), self.ring.elastic_force(&s)),
            Some(b) => (b, self.ring.elastic_force_on(b, &s)),
        };
        Ok(RollContact {
            s,
            angle,
            normal,
            tangent,
            branches,
            damping: self.ring.branch_damping(branches),
            elastic,
        })
    }
}
