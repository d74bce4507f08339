//! The slipping ring: its location, velocity and forces (module docs of [`super`]).

use nalgebra::{Matrix2, Vector2};

use super::{FrictionRing, Slip};
use crate::numeric::{bisect, Side};
use crate::ring::locate::{coefficients, refine, valid, Distance, Probe, MAX_ITERATIONS};
use crate::ring::{Branch, Branches, Regime, RingContact, RingError};

/// The ring located in contact with a shaft slipping on it ([`FrictionRing::locate_slipping`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SlipContact {
    /// Ring centre $s$, with $|r - s| = \gamma$ to rounding.
    pub s: Vector2<f64>,
    /// $m = N/(2\gamma)$, the elastic normal force over $2\gamma$ ([`RingContact::mu`] without
    /// friction). Negative only on the extension of a regime inside $|r| = \gamma$.
    pub multiplier: f64,
    /// Unit contact normal $n = (r - s)/\gamma$.
    pub normal: Vector2<f64>,
    /// Unit tangent $t$, the normal turned by $+90°$.
    pub tangent: Vector2<f64>,
    /// $\kappa = \mu_f\sigma$: the tangential elastic force over the normal one.
    pub friction: f64,
    /// $\partial s/\partial r$ at fixed $\sigma$ on these branches.
    pub jacobian: Matrix2<f64>,
    /// The force-law branch of each axis.
    pub branches: Branches,
    /// Diagonal of the damping matrix $C$ on these branches ($4\nu_2$ inner, $2\nu_2$ outer).
    pub damping: Vector2<f64>,
    /// Elastic force $g(s) = N(n + \kappa t)$.
    pub elastic: Vector2<f64>,
    /// Newton iterations used (0 for a closed form).
    pub iterations: u32,
}

impl SlipContact {
    /// The frictionless location as a slipping one ($\kappa = 0$), its fields bit for bit.
    pub fn frictionless(c: &RingContact) -> Self {
        SlipContact {
            s: c.s,
            multiplier: c.mu,
            normal: c.normal,
            tangent: Vector2::new(-c.normal.y, c.normal.x),
            friction: 0.0,
            jacobian: c.jacobian,
            branches: c.branches,
            damping: c.damping,
            elastic: c.elastic,
            iterations: c.iterations,
        }
    }

    /// The contact regime (II..V) of the branches.
    pub fn regime(&self) -> Regime {
        self.branches.regime()
    }

    /// The elastic normal force $N = n\cdot g(s) = 2m\gamma$.
    pub fn elastic_normal(&self) -> f64 {
        self.normal.dot(&self.elastic)
    }

    /// The elastic tangential force $F_t = t\cdot g(s) = \kappa N$.
    pub fn elastic_tangential(&self) -> f64 {
        self.tangent.dot(&self.elastic)
    }

    /// Ring velocity $s^\prime = J r^\prime$.
    pub fn ring_velocity(&self, r_dot: &Vector2<f64>) -> Vector2<f64> {
        self.jacobian * r_dot
    }

    /// Total force of the ring on the rotor, $f = g(s) + C J r^\prime$.
    pub fn force(&self, r_dot: &Vector2<f64>) -> Vector2<f64> {
        self.elastic + self.damping.component_mul(&self.ring_velocity(r_dot))
    }

    /// The normal part of the total force, $n\cdot f$ (contact lasts while it is positive).
    pub fn normal_force(&self, r_dot: &Vector2<f64>) -> f64 {
        self.normal.dot(&self.force(r_dot))
    }

    /// The tangential part of the total force, $t\cdot f$.
    pub fn tangential_force(&self, r_dot: &Vector2<f64>) -> f64 {
        self.tangent.dot(&self.force(r_dot))
    }

    /// The loss force $\max(n\cdot f, \lambda)$: contact lasts while it is positive. $\lambda$
    /// is the frictionless ring's separation force
    /// ([`RingContact::separation_force`]) at this ring: once released the ring relaxes without
    /// friction, so it parts from the rotor only if that is not positive either. Exactly
    /// $n\cdot f$ for isotropic damping (regimes II and V), MODEL.md's rule.
    pub fn loss_force(&self, r_dot: &Vector2<f64>) -> f64 {
        let normal = self.normal_force(r_dot);
        crate::ring::element::loss_force(self.damping, self.normal, self.elastic, normal, r_dot)
    }

    /// $\gamma\theta^\prime = (r^\prime - s^\prime)\cdot t$: the speed at which the contact
    /// point runs round the ring (positive counter-clockwise).
    pub fn whirl_speed(&self, r_dot: &Vector2<f64>) -> f64 {
        (r_dot - self.ring_velocity(r_dot)).dot(&self.tangent)
    }

    /// The slip velocity $v = \gamma\theta^\prime + \eta a$ for the shaft's surface speed
    /// `surface_speed` $= \eta a$.
    pub fn slip_velocity(&self, r_dot: &Vector2<f64>, surface_speed: f64) -> f64 {
        self.whirl_speed(r_dot) + surface_speed
    }
}

/// $A(m) d = \alpha$, $|d| = \gamma$ on fixed branches, in $u = m - m_c$ (module docs).
struct SlipEquation {
    /// $\alpha$.
    alpha: (f64, f64),
    /// $\beta$.
    beta: (f64, f64),
    /// $\beta_i + m_c$, computed without cancellation ($\ge 0$).
    offset: (f64, f64),
    /// $m_c$, the bound above which $|d|$ falls.
    m_c: f64,
    kappa: f64,
    gap: f64,
}

/// $A$'s entries and $d = A^{-1}\alpha$ at one $u$.
struct Solved {
    p: f64,
    q: f64,
    c: f64,
    det: f64,
    d: (f64, f64),
}

impl SlipEquation {
    fn new(alpha: (f64, f64), beta: (f64, f64), kappa: f64, gap: f64) -> Self {
        let (bmin, h2) = (beta.0.min(beta.1), (beta.1 - beta.0).abs());
        let k2 = kappa * kappa;
        let root = (1.0 + k2).sqrt();
        // beta_min + m_c = kappa^2 (beta_min + h/(root + 1))/(1 + kappa^2), h = |b_y - b_x|/2.
        let soft = k2 * (bmin + 0.5 * h2 / (root + 1.0)) / (1.0 + k2);
        let offset = if beta.0 <= beta.1 {
            (soft, soft + h2)
        } else {
            (soft + h2, soft)
        };
        SlipEquation {
            alpha,
            beta,
            offset,
            m_c: soft - bmin,
            kappa,
            gap,
        }
    }

    #[inline(always)]
    fn solve(&self, u: f64) -> Solved {
        let (ax, ay) = self.alpha;
        let (p, q) = (self.offset.0 + u, self.offset.1 + u);
        let c = self.kappa * (self.m_c + u);
        let det = p * q + c * c;
        Solved {
            p,
            q,
            c,
            det,
            d: ((q * ax + c * ay) / det, (p * ay - c * ax) / det),
        }
    }

    /// $T = |\alpha|/\gamma$.
    fn reach(&self) -> f64 {
        self.alpha.0.hypot(self.alpha.1) / self.gap
    }

    /// The bracket of the root in $u$: $|d| \ge |\alpha|/\lVert A\rVert \ge \gamma$ at the left
    /// end (0 where that bound gives nothing), $|d| \le \gamma$ at the right.
    fn bracket(&self) -> (f64, f64) {
        let (t, k) = (self.reach(), self.kappa.abs());
        let o_max = self.offset.0.max(self.offset.1);
        let right = t / (1.0 + self.kappa * self.kappa).sqrt();
        // ||A|| <= o_max + u + |kappa| |m_c + u|: where that is at most T, |d| >= gamma.
        let zero_load = -self.m_c;
        let loaded = (t - o_max - k * self.m_c) / (1.0 + k);
        let left = if loaded >= zero_load {
            loaded
        } else if k < 1.0 {
            ((t - o_max + k * self.m_c) / (1.0 - k)).min(zero_load)
        } else {
            0.0
        };
        (left.max(0.0).min(right), right)
    }

    /// The closed form for equal betas: $(\beta + m)^2 + \kappa^2 m^2 = T^2$.
    fn uniform_root(&self) -> Option<f64> {
        let (t, b, k2) = (self.reach(), self.beta.0, self.kappa * self.kappa);
        let disc = t * t * (1.0 + k2) - k2 * b * b;
        (disc >= 0.0).then(|| (t - b) * (t + b) / (b + disc.sqrt()) - self.m_c)
    }

    /// The hint if it is inside the bracket, else the closed form with the mean beta.
    fn first_guess(&self, hint: f64, left: f64, right: f64) -> f64 {
        if valid(hint - self.m_c, left, right) {
            return hint - self.m_c;
        }
        let (t, k2) = (self.reach(), self.kappa * self.kappa);
        let b = 0.5 * (self.beta.0 + self.beta.1);
        let disc = t * t * (1.0 + k2) - k2 * b * b;
        let guess = (t - b) * (t + b) / (b + disc.max(0.0).sqrt()) - self.m_c;
        if valid(guess, left, right) {
            guess
        } else {
            0.5 * (left + right)
        }
    }
}

impl Distance for SlipEquation {
    #[inline(always)]
    fn probe(&self, u: f64) -> Probe {
        let Solved { p, q, c, det, d } = self.solve(u);
        let k = self.kappa;
        // z = A^-1 M d: how d moves per unit of u is -z, and d.z = -(|d|^2)'/2.
        let (mx, my) = (d.0 - k * d.1, d.1 + k * d.0);
        let z = ((q * mx + c * my) / det, (p * my - c * mx) / det);
        Probe {
            dist2: d.0 * d.0 + d.1 * d.1,
            slope: d.0 * z.0 + d.1 * z.1,
            speed: z.0.hypot(z.1),
        }
    }

    #[inline(always)]
    fn gap(&self) -> f64 {
        self.gap
    }
}

impl FrictionRing {
    /// The ring in contact with a shaft at `r` (`|r| > gap`) slipping in the sense `slip`:
    /// the location with $F_t = \mu_f\sigma N$ on the branches it lies on (module docs).
    ///
    /// # Errors
    /// [`RingError::NonFinite`] (`"r.x"`, `"r.y"`), [`RingError::InsideGap`] when
    /// `|r| <= gap`, [`RingError::NotConverged`] if the solver failed (not expected).
    pub fn locate_slipping(&self, r: &Vector2<f64>, slip: Slip) -> Result<SlipContact, RingError> {
        let plain = self.ring.locate(r)?;
        if self.friction == 0.0 {
            return Ok(SlipContact::frictionless(&plain));
        }
        let kappa = self.friction * slip.sign();
        let tol = 64.0 * f64::EPSILON * (r.norm() + self.ring.gap);
        let (mut branches, mut hint) = (plain.branches, plain.mu);
        // Active set: the frictionless branches, corrected until the ring lies on them.
        for _ in 0..4 {
            let c = self.place(r, branches, kappa, hint)?;
            if violation(&self.ring, branches, &c.s) <= tol {
                return Ok(c);
            }
            (branches, hint) = (Branches::of(&self.ring, &c.s), c.multiplier);
        }
        let (branches, m) = self.branches_by_bisection(r, kappa, tol)?;
        self.place(r, branches, kappa, m)
    }

    /// The slipping ring on the given branches: the smooth extension of that contact regime
    /// (valid also a little inside $|r| = \gamma$ and beyond the regime's boundaries),
    /// warm-started from a previous [`SlipContact::multiplier`] (`f64::NAN` for none). What an
    /// integrator uses inside one contact mode.
    ///
    /// # Errors
    /// [`RingError::NoPlacement`] when the branch formulas have no solution at `r` (e.g. far
    /// inside the gap circle, or non-finite `r`), [`RingError::NotConverged`] (not expected).
    pub fn locate_slipping_on(
        &self,
        r: &Vector2<f64>,
        slip: Slip,
        branches: Branches,
        hint: f64,
    ) -> Result<SlipContact, RingError> {
        if self.friction == 0.0 {
            return self
                .ring
                .locate_on(r, branches, hint)
                .map(|c| SlipContact::frictionless(&c));
        }
        self.place(r, branches, self.friction * slip.sign(), hint)
    }

    /// Solves on fixed branches and builds the record.
    fn place(
        &self,
        r: &Vector2<f64>,
        branches: Branches,
        kappa: f64,
        hint: f64,
    ) -> Result<SlipContact, RingError> {
        let ring = &self.ring;
        let (ax, bx) = coefficients(&ring.x, branches.x, r.x);
        let (ay, by) = coefficients(&ring.y, branches.y, r.y);
        let no_placement = RingError::NoPlacement { x: r.x, y: r.y };
        if !(ax.hypot(ay) > 0.0 && (ax + ay).is_finite()) {
            return Err(no_placement);
        }
        let eq = SlipEquation::new((ax, ay), (bx, by), kappa, ring.gap);
        let (u, iterations) = if bx == by {
            (eq.uniform_root().ok_or(no_placement)?, 0)
        } else {
            let (left, right) = eq.bracket();
            // No root right of `left` when |d| is already inside the ring there.
            if eq.probe(left).dist2 < ring.gap * ring.gap {
                return Err(no_placement);
            }
            let start = eq.first_guess(hint, left, right);
            refine(&eq, start, left, right)?
        };
        let Solved { p, q, c, d, .. } = eq.solve(u);
        let dn = d.0.hypot(d.1);
        if !(dn > 0.0 && dn.is_finite()) {
            return Err(no_placement);
        }
        let n = Vector2::new(d.0 / dn, d.1 / dn);
        let t = Vector2::new(-n.y, n.x);
        let gap = ring.gap;
        let m = eq.m_c + u;
        // ds/dr = I - gamma t (beta_x V_y, -beta_y V_x)/Delta, V = M d (module docs).
        let v = (n + kappa * t) * gap;
        let delta =
            -gap * gap * (p * n.y * n.y + q * n.x * n.x + kappa * (c - (q - p) * n.x * n.y));
        let w = Vector2::new(bx * v.y, -by * v.x) * (gap / delta);
        let jacobian = Matrix2::identity() - t * w.transpose();
        Ok(SlipContact {
            s: r - n * gap,
            multiplier: m,
            normal: n,
            tangent: t,
            friction: kappa,
            jacobian,
            branches,
            damping: ring.branch_damping(branches),
            elastic: (n + kappa * t) * (2.0 * m * gap),
            iterations,
        })
    }

    /// The branches of the root found by bisection on $m$ over the piecewise-affine solution
    /// $d(m)$ (the fallback when the active set does not settle), with a multiplier inside.
    fn branches_by_bisection(
        &self,
        r: &Vector2<f64>,
        kappa: f64,
        tol: f64,
    ) -> Result<(Branches, f64), RingError> {
        let ring = &self.ring;
        let reach = |a: &crate::ring::RingAxis, ri: f64| a.stiffness * (ri.abs() + a.preload);
        // |d| <= |alpha|/(sqrt(1 + kappa^2) m) <= gamma here, as m_c <= 0 on every pair.
        let high = reach(&ring.x, r.x).hypot(reach(&ring.y, r.y)) / ring.gap;
        let g2 = ring.gap * ring.gap;
        let b = bisect(0.0, high, 0.0, 4 * MAX_ITERATIONS as usize, |m| {
            let (_, d) = self.solve_at(r, kappa, m, tol);
            Ok::<_, RingError>(if d.norm_squared() > g2 {
                Side::Near
            } else {
                Side::Far
            })
        })?;
        let m = b.midpoint();
        Ok((self.solve_at(r, kappa, m, tol).0, m))
    }

    /// The solution $d$ of the piecewise-affine system $g(r - d) = 2m(d + \kappa Jd)$ at one
    /// $m \ge 0$ and its branches: the branch pair whose affine solution it holds (unique up to
    /// `tol`, as the system is monotone), else the least violated one.
    fn solve_at(&self, r: &Vector2<f64>, kappa: f64, m: f64, tol: f64) -> (Branches, Vector2<f64>) {
        let ring = &self.ring;
        let sides = |preload: f64| -> &'static [Branch] {
            if preload > 0.0 {
                &[Branch::Inner, Branch::Outer(1), Branch::Outer(-1)]
            } else {
                &[Branch::Outer(0)]
            }
        };
        let mut best = (
            f64::INFINITY,
            Branches {
                x: Branch::Outer(0),
                y: Branch::Outer(0),
            },
            Vector2::zeros(),
        );
        for &x in sides(ring.x.preload) {
            for &y in sides(ring.y.preload) {
                let branches = Branches { x, y };
                let (ax, bx) = coefficients(&ring.x, x, r.x);
                let (ay, by) = coefficients(&ring.y, y, r.y);
                let (p, q, c) = (bx + m, by + m, kappa * m);
                let det = p * q + c * c;
                let d = Vector2::new((q * ax + c * ay) / det, (p * ay - c * ax) / det);
                let s = r - d;
                let miss = violation(ring, branches, &s);
                if miss <= tol {
                    return (branches, d);
                }
                if miss < best.0 {
                    best = (miss, branches, d);
                }
            }
        }
        (best.1, best.2)
    }
}

/// How far a ring position lies off the given branches (0 on them).
pub(super) fn violation(ring: &crate::ring::SnubberRing, b: Branches, s: &Vector2<f64>) -> f64 {
    let off = |a: &crate::ring::RingAxis, branch: Branch, si: f64| match branch {
        Branch::Inner => (si.abs() - a.preload).max(0.0),
        Branch::Outer(0) => 0.0,
        Branch::Outer(side) => (a.preload - f64::from(side) * si).max(0.0),
    };
    off(&ring.x, b.x, s.x) + off(&ring.y, b.y, s.y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ring::{RingAxis, SnubberRing};

    /// The bisection fallback finds the branches and the location that the active set finds,
    /// on rings with preloads and anisotropy (a fallback no ordinary input reaches).
    #[test]
    fn bisection_finds_the_active_sets_location() {
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for _ in 0..2000 {
            let axis =
                |u: f64, v: f64| RingAxis::new(10f64.powf(3.0 * u - 1.0), (v - 0.3).max(0.0));
            let ring =
                SnubberRing::new(axis(next(), next()), axis(next(), next()), 0.0, 1.0).unwrap();
            let rub = FrictionRing::new(ring, 0.95 * next() * FrictionRing::limit(&ring).min(2.0))
                .unwrap();
            let r = Vector2::new(6.0 * next() - 3.0, 6.0 * next() - 3.0);
            if r.norm() <= 1.0 || rub.friction == 0.0 {
                continue;
            }
            let slip = if next() < 0.5 {
                Slip::Forward
            } else {
                Slip::Backward
            };
            let kappa = rub.friction * slip.sign();
            let tol = 64.0 * f64::EPSILON * (r.norm() + 1.0);
            let (branches, m) = rub.branches_by_bisection(&r, kappa, tol).unwrap();
            let fallback = rub.place(&r, branches, kappa, m).unwrap();
            let active = rub.locate_slipping(&r, slip).unwrap();
            let off = (fallback.s - active.s).norm();
            assert!(
                off <= 1e-12 * (r.norm() + 1.0),
                "{ring:?} {r:?} {slip:?}: {off:e}"
            );
        }
    }
}
