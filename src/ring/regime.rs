use std::fmt;

use nalgebra::Vector2;

use super::{check_finite, check_non_negative, check_positive, RingError, SnubberRing};

/// Contact regime of the rotor-ring pair (paper section 2).
///
/// * `I`: no contact, `|r| <= gap`;
/// * `II`: contact, both axes inside the preload (`|s_x| <= D_x`, `|s_y| <= D_y`);
/// * `III`: contact, `|s_x| > D_x`, `|s_y| <= D_y`;
/// * `IV`: contact, `|s_x| <= D_x`, `|s_y| > D_y`;
/// * `V`: contact, both beyond the preload.
///
/// An axis with zero preload is always beyond, so an unpreloaded ring has only I and V.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum Regime {
    /// No contact.
    I = 1,
    /// Contact, both axes inside the preload.
    II = 2,
    /// Contact, `x` beyond the preload, `y` inside.
    III = 3,
    /// Contact, `x` inside the preload, `y` beyond.
    IV = 4,
    /// Contact, both axes beyond the preload.
    V = 5,
}

impl Regime {
    /// The regime's number 1..=5.
    pub fn number(self) -> u8 {
        self as u8
    }

    /// The contact regime for the given "beyond the preload" flags of the `x` and `y` axes.
    pub fn from_beyond(x_beyond: bool, y_beyond: bool) -> Self {
        match (x_beyond, y_beyond) {
            (false, false) => Regime::II,
            (true, false) => Regime::III,
            (false, true) => Regime::IV,
            (true, true) => Regime::V,
        }
    }

    /// `true` for the contact regimes II..V.
    pub fn is_contact(self) -> bool {
        self != Regime::I
    }

    /// The regime's roman numeral.
    pub fn roman(self) -> &'static str {
        match self {
            Regime::I => "I",
            Regime::II => "II",
            Regime::III => "III",
            Regime::IV => "IV",
            Regime::V => "V",
        }
    }
}

impl fmt::Display for Regime {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.roman())
    }
}

impl SnubberRing {
    /// Regime of the rotor at `r`: I when `|r| <= gap`, otherwise the regime of `s*(r)` (works for
    /// any valid ring, anisotropic included, through the solver).
    ///
    /// # Errors
    /// [`RingError::NonFinite`] for a non-finite `r`, or a parameter error if the ring is invalid.
    pub fn regime(&self, r: &Vector2<f64>) -> Result<Regime, RingError> {
        self.validate()?;
        check_finite("r.x", r.x)?;
        check_finite("r.y", r.y)?;
        if r.x * r.x + r.y * r.y <= self.gap * self.gap {
            return Ok(Regime::I);
        }
        Ok(self.locate(r)?.regime())
    }
}

/// Analytic boundaries between the regions I..V in the first quadrant of the rotor plane
/// (paper eqs. 23-27), generalised to a gap `gamma`, for an isotropic stiffness (`K_x = K_y`;
/// the preloads may differ). The curves do not depend on `K`. Other quadrants follow by mirror
/// symmetry `x -> -x`, `y -> -y`.
///
/// Derivation (see `docs/ring.md`): on the curve `s_x = D_x` the `x` equation
/// `g_x + 2 mu s_x = 2 mu x` gives `mu = K D_x/(x - D_x)` and `d_x = x - D_x`; then `|d| = gamma`
/// fixes `d_y = sqrt(gamma^2 - (x - D_x)^2)` and the `y` equation gives `y`: with `y` inside the
/// preload `d_y = K y/(K + mu)`, i.e. eq. 24 (II/III); with `y` beyond,
/// `d_y = K (y + D_y)/(K + 2 mu)`, i.e. eq. 27 (IV/V). Symmetrically `s_y = D_y` gives eqs. 25
/// (II/IV) and 26 (III/V). All four meet at the corner `r_c = D + gamma D/|D|`, where
/// `s* = (D_x, D_y)`; eq. 24 holds below the ray through the corner (`y/x <= D_y/D_x`) and eq. 27
/// above it, and likewise for eqs. 25/26.
pub mod boundaries {
    use super::*;

    /// One of the region boundaries in the first quadrant.
    #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
    pub enum Boundary {
        /// I / contact: the circle `|r| = gamma` (eq. 23).
        IContact,
        /// II / III: `s_x = D_x` with `y` inside (eq. 24).
        IiIii,
        /// II / IV: `s_y = D_y` with `x` inside (eq. 25).
        IiIv,
        /// III / V: `s_y = D_y` with `x` beyond (eq. 26).
        IiiV,
        /// IV / V: `s_x = D_x` with `y` beyond (eq. 27).
        IvV,
    }

    impl Boundary {
        /// All five boundaries.
        pub const ALL: [Boundary; 5] = [
            Boundary::IContact,
            Boundary::IiIii,
            Boundary::IiIv,
            Boundary::IiiV,
            Boundary::IvV,
        ];

        /// A short label such as `"II/III"`.
        pub fn label(self) -> &'static str {
            match self {
                Boundary::IContact => "I/contact",
                Boundary::IiIii => "II/III",
                Boundary::IiIv => "II/IV",
                Boundary::IiiV => "III/V",
                Boundary::IvV => "IV/V",
            }
        }
    }

    /// Region boundaries for preloads `dx`, `dy` and gap `gap` (isotropic stiffness).
    #[derive(Debug, Clone, Copy, PartialEq)]
    pub struct RegionBoundaries {
        /// Preload `D_x >= 0`.
        pub dx: f64,
        /// Preload `D_y >= 0`.
        pub dy: f64,
        /// Gap `gamma > 0`.
        pub gap: f64,
    }

    impl RegionBoundaries {
        /// Boundaries for preloads `dx`, `dy` and gap `gap`.
        ///
        /// # Errors
        /// Typed errors for non-finite or negative preloads (`"dx"`, `"dy"`) and a non-positive
        /// `"gap"`.
        pub fn new(dx: f64, dy: f64, gap: f64) -> Result<Self, RingError> {
            check_non_negative("dx", dx)?;
            check_non_negative("dy", dy)?;
            check_positive("gap", gap)?;
            Ok(Self { dx, dy, gap })
        }

        /// Boundaries of a ring's regions.
        ///
        /// # Errors
        /// A parameter error if the ring is invalid, or [`RingError::AnisotropicStiffness`] when
        /// `K_x != K_y` (the curves below assume equal stiffness; use
        /// [`SnubberRing::regime`] for anisotropic rings).
        pub fn from_ring(ring: &SnubberRing) -> Result<Self, RingError> {
            ring.validate()?;
            if ring.x.stiffness != ring.y.stiffness {
                return Err(RingError::AnisotropicStiffness {
                    x: ring.x.stiffness,
                    y: ring.y.stiffness,
                });
            }
            Self::new(ring.x.preload, ring.y.preload, ring.gap)
        }

        /// The corner `r_c = D + gamma D/|D|` where the four contact boundaries meet (there
        /// `s* = (D_x, D_y)`); `None` without preload.
        pub fn corner(&self) -> Option<Vector2<f64>> {
            let norm = self.dx.hypot(self.dy);
            if norm > 0.0 {
                let q = 1.0 + self.gap / norm;
                Some(Vector2::new(self.dx * q, self.dy * q))
            } else {
                None
            }
        }

        /// Eq. 23: `y = sqrt(gamma^2 - x^2)` for `0 <= x <= gamma`, else `None`.
        pub fn circle(&self, x: f64) -> Option<f64> {
            (x >= 0.0 && x <= self.gap).then(|| (self.gap * self.gap - x * x).max(0.0).sqrt())
        }

        /// Eq. 24 as a formula: `y = x sqrt(gamma^2 - (x - D_x)^2)/(x - D_x)` for
        /// `D_x < x <= D_x + gamma`, else `None` (no check of which side of the corner).
        pub fn eq24(&self, x: f64) -> Option<f64> {
            let u = x - self.dx;
            (u > 0.0 && u <= self.gap).then(|| x * (self.gap * self.gap - u * u).sqrt() / u)
        }

        /// Eq. 25 as a formula: `x = y sqrt(gamma^2 - (y - D_y)^2)/(y - D_y)` for
        /// `D_y < y <= D_y + gamma`, else `None`.
        pub fn eq25(&self, y: f64) -> Option<f64> {
            let u = y - self.dy;
            (u > 0.0 && u <= self.gap).then(|| y * (self.gap * self.gap - u * u).sqrt() / u)
        }

        /// Eq. 26 as a formula: `x = -D_x + (y + D_y) sqrt(gamma^2 - (y - D_y)^2)/(y - D_y)` for
        /// `D_y < y <= D_y + gamma`, else `None`.
        pub fn eq26(&self, y: f64) -> Option<f64> {
            let u = y - self.dy;
            (u > 0.0 && u <= self.gap)
                .then(|| -self.dx + (y + self.dy) * (self.gap * self.gap - u * u).sqrt() / u)
        }

        /// Eq. 27 as a formula: `y = -D_y + (x + D_x) sqrt(gamma^2 - (x - D_x)^2)/(x - D_x)` for
        /// `D_x < x <= D_x + gamma`, else `None`.
        pub fn eq27(&self, x: f64) -> Option<f64> {
            let u = x - self.dx;
            (u > 0.0 && u <= self.gap)
                .then(|| -self.dy + (x + self.dx) * (self.gap * self.gap - u * u).sqrt() / u)
        }

        /// II/III boundary as `y(x)`: eq. 24 restricted to `x_c <= x <= D_x + gamma` (below the
        /// corner). `None` outside, or when `D_x = 0` or `D_y = 0` (no region II).
        pub fn ii_iii(&self, x: f64) -> Option<f64> {
            let c = self.corner()?;
            if self.dx == 0.0 || self.dy == 0.0 || x < c.x {
                return None;
            }
            self.eq24(x)
        }

        /// II/IV boundary as `x(y)`: eq. 25 restricted to `y_c <= y <= D_y + gamma`. `None`
        /// outside, or when `D_x = 0` or `D_y = 0`.
        pub fn ii_iv(&self, y: f64) -> Option<f64> {
            let c = self.corner()?;
            if self.dx == 0.0 || self.dy == 0.0 || y < c.y {
                return None;
            }
            self.eq25(y)
        }

        /// III/V boundary as `x(y)`: eq. 26 restricted to `D_y < y <= y_c`. `None` outside or when
        /// `D_y = 0` (then `y` is always beyond: no III). Works for `D_x = 0` (then `y_c = D_y + gamma`).
        pub fn iii_v(&self, y: f64) -> Option<f64> {
            let c = self.corner()?;
            if self.dy == 0.0 || y > c.y {
                return None;
            }
            self.eq26(y)
        }

        /// IV/V boundary as `y(x)`: eq. 27 restricted to `D_x < x <= x_c`. `None` outside or when
        /// `D_x = 0`.
        pub fn iv_v(&self, x: f64) -> Option<f64> {
            let c = self.corner()?;
            if self.dx == 0.0 || x > c.x {
                return None;
            }
            self.eq27(x)
        }

        /// Point of a boundary at the parameter `theta` in `[0, pi/2]`: `u = gamma cos(theta)` is
        /// the offset `x - D_x` (or `y - D_y`) and `gamma sin(theta)` the square root of the
        /// formulas. `None` where that point is not on the valid piece of the boundary.
        pub fn point(&self, b: Boundary, theta: f64) -> Option<Vector2<f64>> {
            let (c, s) = (self.gap * theta.cos(), self.gap * theta.sin());
            match b {
                Boundary::IContact => (0.0..=std::f64::consts::FRAC_PI_2)
                    .contains(&theta)
                    .then(|| Vector2::new(c, s)),
                Boundary::IiIii => {
                    let x = self.dx + c;
                    self.ii_iii(x).map(|y| Vector2::new(x, y))
                }
                Boundary::IvV => {
                    let x = self.dx + c;
                    self.iv_v(x).map(|y| Vector2::new(x, y))
                }
                Boundary::IiIv => {
                    let y = self.dy + c;
                    self.ii_iv(y).map(|x| Vector2::new(x, y))
                }
                Boundary::IiiV => {
                    let y = self.dy + c;
                    self.iii_v(y).map(|x| Vector2::new(x, y))
                }
            }
        }

        /// Polyline of a boundary: `n` parameters `theta` uniform in `[0, pi/2)`, keeping the valid
        /// points with both coordinates `<= limit`, plus the corner (for the contact boundaries)
        /// so the pieces join. For plotting; allocates.
        pub fn polyline(&self, b: Boundary, n: usize, limit: f64) -> Vec<Vector2<f64>> {
            let mut pts: Vec<Vector2<f64>> = (0..n)
                .filter_map(|i| {
                    let theta = std::f64::consts::FRAC_PI_2 * i as f64 / n.max(1) as f64;
                    self.point(b, theta)
                })
                .filter(|p| p.x <= limit && p.y <= limit)
                .collect();
            if b != Boundary::IContact
                && !pts.is_empty()
                && let Some(c) = self.corner()
                && c.x <= limit
                && c.y <= limit
            {
                // Order along the curve: insert at the end nearest to the corner.
                let first = (pts[0] - c).norm();
                let last = (pts[pts.len() - 1] - c).norm();
                if first < last {
                    pts.insert(0, c);
                } else {
                    pts.push(c);
                }
            }
            pts
        }
    }
}
