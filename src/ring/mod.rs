//! TEMPORARY stand-in for the ring element (replaced by the `ring` branch at merge).
#![allow(missing_docs)]
use nalgebra::{Matrix2, Vector2};
use thiserror::Error;
pub mod branch;
pub use branch::{Branch, BranchContact, Branches};

#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RingError {
    #[error("rotor inside the gap")]
    InsideGap { r: f64 },
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingAxis {
    pub stiffness: f64,
    pub preload: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnubberRing {
    pub x: RingAxis,
    pub y: RingAxis,
    pub damping: f64,
    pub gap: f64,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum Regime {
    I = 1,
    II = 2,
    III = 3,
    IV = 4,
    V = 5,
}

impl Regime {
    pub fn number(self) -> u8 {
        self as u8
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingContact {
    pub s: Vector2<f64>,
    pub mu: f64,
    pub regime: Regime,
    pub jacobian: Matrix2<f64>,
    pub normal: Vector2<f64>,
    pub iterations: u32,
}

impl RingContact {
    pub fn ring_velocity(&self, r_dot: &Vector2<f64>) -> Vector2<f64> {
        self.jacobian * r_dot
    }
    pub fn force(&self, ring: &SnubberRing, r_dot: &Vector2<f64>) -> Vector2<f64> {
        ring.force(&self.s, &self.ring_velocity(r_dot))
    }
    pub fn normal_force(&self, ring: &SnubberRing, r_dot: &Vector2<f64>) -> f64 {
        self.normal.dot(&self.force(ring, r_dot))
    }
}

fn axis_g(a: &RingAxis, s: f64) -> (f64, f64) {
    if a.preload > 0.0 && s.abs() < a.preload {
        (2.0 * a.stiffness * s, 2.0 * a.stiffness)
    } else {
        (s.signum() * a.stiffness * (s.abs() + a.preload), a.stiffness)
    }
}

fn beyond(a: &RingAxis, s: f64) -> bool {
    a.preload == 0.0 || s.abs() > a.preload
}

impl SnubberRing {
    pub fn new(x: RingAxis, y: RingAxis, damping: f64, gap: f64) -> Result<Self, RingError> {
        Ok(Self { x, y, damping, gap })
    }
    pub fn isotropic(stiffness: f64, preload: f64, damping: f64) -> Result<Self, RingError> {
        let a = RingAxis { stiffness, preload };
        Self::new(a, a, damping, 1.0)
    }
    pub fn elastic_force(&self, s: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(axis_g(&self.x, s.x).0, axis_g(&self.y, s.y).0)
    }
    pub fn damping_coefficients(&self, s: &Vector2<f64>) -> Vector2<f64> {
        let c = |a: &RingAxis, v: f64| {
            if beyond(a, v) {
                2.0 * self.damping
            } else {
                4.0 * self.damping
            }
        };
        Vector2::new(c(&self.x, s.x), c(&self.y, s.y))
    }
    pub fn force(&self, s: &Vector2<f64>, s_dot: &Vector2<f64>) -> Vector2<f64> {
        self.elastic_force(s) + self.damping_coefficients(s).component_mul(s_dot)
    }
    pub fn regime_of_ring(&self, s: &Vector2<f64>) -> Regime {
        match (beyond(&self.x, s.x), beyond(&self.y, s.y)) {
            (false, false) => Regime::II,
            (true, false) => Regime::III,
            (false, true) => Regime::IV,
            (true, true) => Regime::V,
        }
    }
    pub fn locate(&self, r: &Vector2<f64>) -> Result<RingContact, RingError> {
        self.locate_from(r, f64::NAN)
    }
    pub fn locate_from(&self, r: &Vector2<f64>, _hint: f64) -> Result<RingContact, RingError> {
        let rn = r.norm();
        if rn <= self.gap || !rn.is_finite() {
            return Err(RingError::InsideGap { r: rn });
        }
        let d_of = |mu: f64| {
            let ax = |a: &RingAxis, ri: f64| {
                let k = a.stiffness;
                if mu * ri.abs() <= (k + mu) * a.preload {
                    (k * ri / (k + mu), mu * ri / (k + mu))
                } else {
                    let sg = ri.signum();
                    (
                        k * (ri + sg * a.preload) / (k + 2.0 * mu),
                        (2.0 * mu * ri - sg * k * a.preload) / (k + 2.0 * mu),
                    )
                }
            };
            let (dx, sx) = ax(&self.x, r.x);
            let (dy, sy) = ax(&self.y, r.y);
            (Vector2::new(dx, dy), Vector2::new(sx, sy))
        };
        let kmax = self.x.stiffness.max(self.y.stiffness);
        let rt = (r.x.abs() + self.x.preload).hypot(r.y.abs() + self.y.preload);
        let (mut lo, mut hi) = (0.0, kmax * (rt / self.gap - 1.0) + 1e-300);
        let mut it = 0;
        while it < 200 && hi - lo > 1e-16 * hi {
            let mid = 0.5 * (lo + hi);
            if d_of(mid).0.norm() > self.gap {
                lo = mid;
            } else {
                hi = mid;
            }
            it += 1;
        }
        let mu = 0.5 * (lo + hi);
        let (d, _) = d_of(mu);
        let s = r - d * (self.gap / d.norm());
        let d = r - s;
        let gp = Vector2::new(axis_g(&self.x, s.x).1, axis_g(&self.y, s.y).1);
        let a_inv = Vector2::new(1.0 / (gp.x + 2.0 * mu), 1.0 / (gp.y + 2.0 * mu));
        let w = a_inv.component_mul(&d);
        let jac = Matrix2::from_diagonal(&(a_inv * (2.0 * mu)))
            + w * (d - w * (2.0 * mu)).transpose() / d.dot(&w);
        Ok(RingContact {
            s,
            mu,
            regime: self.regime_of_ring(&s),
            jacobian: jac,
            normal: d / d.norm(),
            iterations: it,
        })
    }
    pub fn relaxation_time(&self) -> Vector2<f64> {
        Vector2::new(
            2.0 * self.damping / self.x.stiffness,
            2.0 * self.damping / self.y.stiffness,
        )
    }
    pub fn relax(&self, s0: &Vector2<f64>, t: f64) -> Vector2<f64> {
        let ax = |a: &RingAxis, s: f64, tc: f64| {
            if tc == 0.0 || !tc.is_finite() {
                return if t > 0.0 { 0.0 } else { s };
            }
            let d = a.preload;
            if s.abs() > d {
                let t1 = tc * ((s.abs() + d) / (2.0 * d)).ln();
                if t < t1 || d == 0.0 {
                    return s.signum() * ((s.abs() + d) * (-t / tc).exp() - d);
                }
                return s.signum() * d * (-(t - t1) / tc).exp();
            }
            s * (-t / tc).exp()
        };
        let tc = self.relaxation_time();
        Vector2::new(ax(&self.x, s0.x, tc.x), ax(&self.y, s0.y, tc.y))
    }
    pub fn relax_velocity(&self, s: &Vector2<f64>) -> Vector2<f64> {
        let tc = self.relaxation_time();
        let ax = |a: &RingAxis, s: f64, tc: f64| {
            if tc == 0.0 {
                return 0.0;
            }
            if s.abs() > a.preload {
                -(s + s.signum() * a.preload) / tc
            } else {
                -s / tc
            }
        };
        Vector2::new(ax(&self.x, s.x, tc.x), ax(&self.y, s.y, tc.y))
    }
    pub fn has_preload(&self) -> bool {
        self.x.preload > 0.0 || self.y.preload > 0.0
    }
    pub fn is_isotropic(&self) -> bool {
        self.x.stiffness == self.y.stiffness
    }
}
