use nalgebra::Vector2;

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
                assert_eq!(e.branches, c.branches);
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
