//! Location of the ring in contact: `s*(r) = argmin E(s)` subject to `|r - s| = gap`.
//!
//! # Lagrange conditions
//! With `d = r - s`, a minimiser satisfies `g(s) = 2 mu d`, `mu > 0`, `|d| = gap`. For a fixed
//! multiplier `mu` each axis solves the monotone piecewise-linear equation
//! `g_i(s_i) + 2 mu s_i = 2 mu r_i` in closed form; with `a = |r_i|`, written on `a` and signed
//! with `r_i` afterwards:
//!
//! * inside the preload (valid while `mu a <= (K + mu) D`): `s_i = mu a/(K + mu)`,
//!   `d_i = K a/(K + mu)`;
//! * beyond it: `s_i = (2 mu a - K D)/(K + 2 mu)`, `d_i = K (a + D)/(K + 2 mu)`.
//!
//! Both are of the form `d_i = alpha_i/(beta_i + mu)` with `(alpha, beta) = (K a, K)` inside and
//! `(K (a + D)/2, K/2)` beyond. The axis switches from inside to beyond at the breakpoint
//! `mu_i* = K D/(a - D)` (only if `a > D`; `mu_i* = 0` when `D = 0`); `d_i(mu)` is continuous
//! there. `|d(mu)|` falls strictly from `|r|` at `mu = 0` to 0 as `mu -> infinity`, so
//! `|d(mu)| = gap` has exactly one root when `|r| > gap`.
//!
//! # Solver
//! 1. Evaluate `f(mu) = |d(mu)|^2` at the (at most two) finite breakpoints, in increasing order,
//!    to find the piece `[lo, hi]` holding the root (no square roots needed).
//! 2. On that piece `f = alpha_x^2/(beta_x + mu)^2 + alpha_y^2/(beta_y + mu)^2` with fixed
//!    coefficients. If `beta_x = beta_y` (isotropic II or V, and some anisotropic pieces) or one
//!    `alpha` vanishes, the root is closed-form: `mu = |alpha|/gap - beta`.
//! 3. Otherwise (III, IV, anisotropic) run Newton on `phi(mu) = f^{-1/2} - 1/gap`, which on a
//!    piece is a power mean of exponent -2 of the affine functions `beta_i + mu`, hence
//!    increasing and concave: from a point left of the root Newton converges monotonically, and
//!    a step from the right of the root lands left of it. The bracket
//!    `[max(lo, |alpha|/gap - beta_max), min(hi, |alpha|/gap - beta_min)]` (from
//!    `|alpha|^2/(beta_max + mu)^2 <= f <= |alpha|^2/(beta_min + mu)^2`) is kept, steps leaving it
//!    are replaced by bisection, and a warm start `mu_hint` inside it is used as the first iterate
//!    (else the first-order guess `|alpha|/gap - beta_bar`, `beta_bar` the `alpha^2`-weighted mean
//!    of the betas, exact for `mu >> beta`). It stops after a Newton step
//!    `|delta| <= 1e-10 (beta_max + mu)` (the error left is `<~ delta^2/(beta + mu)`).
//!
//! The Newton step is `delta = f (sqrt(f)/gap - 1) / sum_i alpha_i^2/(beta_i + mu)^3`, one square
//! root per iteration. See `docs/ring.md` for the global bound `mu <= K_max (R~/gap - 1)`.

use nalgebra::{Matrix2, Vector2};

use super::SnubberRing;
use super::{check_finite, check_non_negative, check_positive, Regime, RingAxis, RingError};

/// Maximum number of safeguarded Newton iterations (never reached in tests: 1..4 are typical).
const MAX_ITERATIONS: u32 = 100;

/// The ring in contact with the rotor at `r`: position, multiplier, regime, Jacobian, normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingContact {
    /// Ring centre `s*(r)`, with `|r - s| = gap`.
    pub s: Vector2<f64>,
    /// Lagrange multiplier `mu > 0` of `g(s) = 2 mu (r - s)`; the normal elastic force is
    /// `2 mu gap`. Pass it to [`SnubberRing::locate_from`] as a warm start.
    pub mu: f64,
    /// Contact regime (II..V) of the ring position.
    pub regime: Regime,
    /// Jacobian `J = ds*/dr = 2 mu A^-1 + w (d - 2 mu w)^T/(d . w)` with `d = r - s`,
    /// `A = diag(g_x'(s_x) + 2 mu, g_y'(s_y) + 2 mu)`, `w = A^-1 d`.
    pub jacobian: Matrix2<f64>,
    /// Unit contact normal `n = (r - s)/|r - s|`, pointing from the ring centre to the rotor.
    pub normal: Vector2<f64>,
    /// Newton iterations used (0 on closed-form pieces).
    pub iterations: u32,
}

impl RingContact {
    /// Ring velocity in contact, `s' = J r'`.
    pub fn ring_velocity(&self, r_dot: &Vector2<f64>) -> Vector2<f64> {
        self.jacobian * r_dot
    }

    /// Total ring force on the rotor `f = g(s) + C(s) J r'`.
    pub fn force(&self, ring: &SnubberRing, r_dot: &Vector2<f64>) -> Vector2<f64> {
        ring.force(&self.s, &self.ring_velocity(r_dot))
    }

    /// Normal component `N = n . f` of the ring force: `2 mu gap + n . C J r'` (the elastic part
    /// is `n . g(s) = 2 mu |d| = 2 mu gap > 0`). Contact is lost when `N < 0`.
    pub fn normal_force(&self, ring: &SnubberRing, r_dot: &Vector2<f64>) -> f64 {
        self.normal.dot(&self.force(ring, r_dot))
    }
}

/// Coefficients `(alpha, beta)` of `d_i = alpha/(beta + mu)` on the branch `beyond`, for `a = |r_i|`.
#[inline(always)]
fn coefficients(axis: &RingAxis, a: f64, beyond: bool) -> (f64, f64) {
    let k = axis.stiffness;
    if beyond {
        (0.5 * k * (a + axis.preload), 0.5 * k)
    } else {
        (k * a, k)
    }
}

/// Multiplier at which the axis switches from inside to beyond the preload, for `a = |r_i|`:
/// `K D/(a - D)` if `a > D > 0`, 0 if `D = 0`, infinity if `a <= D`.
#[inline(always)]
fn breakpoint(axis: &RingAxis, a: f64) -> f64 {
    let d = axis.preload;
    if d == 0.0 {
        0.0
    } else if a > d {
        axis.stiffness * d / (a - d)
    } else {
        f64::INFINITY
    }
}

/// `f(mu) = |d(mu)|^2` with the branches valid at `mu` (breakpoints `bx`, `by`).
#[inline(always)]
fn dist2_at(ring: &SnubberRing, ax: f64, ay: f64, bx: f64, by: f64, mu: f64) -> f64 {
    let (alx, bex) = coefficients(&ring.x, ax, bx <= mu);
    let (aly, bey) = coefficients(&ring.y, ay, by <= mu);
    let dx = alx / (bex + mu);
    let dy = aly / (bey + mu);
    dx * dx + dy * dy
}

impl SnubberRing {
    /// Ring position in contact with the rotor at `r` (`|r| > gap`): see the module docs.
    ///
    /// # Errors
    /// [`RingError::NonFinite`] (`"r.x"`, `"r.y"`) for a non-finite `r`,
    /// [`RingError::InsideGap`] when `|r| <= gap`, or a parameter error if the ring is invalid.
    pub fn locate(&self, r: &Vector2<f64>) -> Result<RingContact, RingError> {
        self.locate_impl(r, f64::NAN)
    }

    /// As [`SnubberRing::locate`], warm-started from a previous multiplier `mu_hint` (e.g. the
    /// [`RingContact::mu`] of the previous step). A hint that is NaN, infinite, negative or
    /// outside the root's bracket is ignored; the result does not depend on the hint beyond
    /// rounding.
    ///
    /// # Errors
    /// As [`SnubberRing::locate`].
    pub fn locate_from(&self, r: &Vector2<f64>, mu_hint: f64) -> Result<RingContact, RingError> {
        self.locate_impl(r, mu_hint)
    }

    fn locate_impl(&self, r: &Vector2<f64>, hint: f64) -> Result<RingContact, RingError> {
        self.validate()?;
        check_finite("r.x", r.x)?;
        check_finite("r.y", r.y)?;
        let gap = self.gap;
        let r2 = r.x * r.x + r.y * r.y;
        if r2 <= gap * gap {
            return Err(RingError::InsideGap {
                distance: r2.sqrt(),
                gap,
            });
        }
        let (mu, iterations, cx, cy) = self.solve_mu(r.x.abs(), r.y.abs(), hint);
        Ok(self.contact_from_mu(r, mu, iterations, cx, cy))
    }

    /// Solves `|d(mu)| = gap` for `a = (|r_x|, |r_y|)` with `|a| > gap`; returns
    /// `(mu, iterations, (alpha_x, beta_x), (alpha_y, beta_y))` of the root's piece.
    #[inline]
    fn solve_mu(&self, ax: f64, ay: f64, hint: f64) -> (f64, u32, (f64, f64), (f64, f64)) {
        let gap = self.gap;
        let g2 = gap * gap;
        let bx = breakpoint(&self.x, ax);
        let by = breakpoint(&self.y, ay);
        let (b1, b2) = if bx <= by { (bx, by) } else { (by, bx) };
        // Piece [lo, hi] of mu holding the root.
        let mut lo = 0.0;
        let mut hi = f64::INFINITY;
        if b1.is_finite() {
            if dist2_at(self, ax, ay, bx, by, b1) > g2 {
                lo = b1;
                if b2.is_finite() {
                    if dist2_at(self, ax, ay, bx, by, b2) > g2 {
                        lo = b2;
                    } else {
                        hi = b2;
                    }
                }
            } else {
                hi = b1;
            }
        }
        let (alx, bex) = coefficients(&self.x, ax, bx <= lo);
        let (aly, bey) = coefficients(&self.y, ay, by <= lo);
        // Closed forms: a single active axis, or equal betas.
        let (cx, cy) = ((alx, bex), (aly, bey));
        if alx == 0.0 {
            return ((aly / gap - bey).max(lo).min(hi), 0, cx, cy);
        }
        if aly == 0.0 {
            return ((alx / gap - bex).max(lo).min(hi), 0, cx, cy);
        }
        let norm = (alx * alx + aly * aly).sqrt();
        if bex == bey {
            return ((norm / gap - bex).max(lo).min(hi), 0, cx, cy);
        }
        let (bmin, bmax) = if bex < bey { (bex, bey) } else { (bey, bex) };
        let mut left = lo.max(norm / gap - bmax);
        let mut right = hi.min(norm / gap - bmin);
        if left > right {
            let m = 0.5 * (left + right);
            left = m;
            right = m;
        }
        let (a2x, a2y) = (alx * alx, aly * aly);
        let mut mu = if hint >= left && hint <= right {
            hint
        } else {
            // First-order guess: for mu >> beta, f ~ |alpha|^2/(mu + beta_bar)^2 with the
            // alpha^2-weighted mean beta_bar.
            let beta_bar = (a2x * bex + a2y * bey) / (a2x + a2y);
            (norm / gap - beta_bar).max(left).min(right)
        };
        let inv_gap = 1.0 / gap;
        let mut iterations = 0;
        while iterations < MAX_ITERATIONS {
            iterations += 1;
            let ix = 1.0 / (bex + mu);
            let iy = 1.0 / (bey + mu);
            let tx = a2x * ix * ix;
            let ty = a2y * iy * iy;
            let f = tx + ty;
            let s3 = tx * ix + ty * iy;
            let residual = f.sqrt() * inv_gap - 1.0; // > 0 left of the root
            if residual > 0.0 {
                left = mu;
            } else if residual < 0.0 {
                right = mu;
            } else {
                break;
            }
            let step = f * residual / s3;
            let mut next = mu + step;
            let newton = next >= left && next <= right;
            if !newton {
                next = 0.5 * (left + right);
            }
            // On a piece the Newton error after a step delta is <= delta^2/(beta + mu), so a
            // step below 1e-10 (beta_max + mu) leaves an error far below rounding.
            let scale = bmax + mu;
            let done = (newton && step.abs() <= 1e-10 * scale)
                || right - left <= 16.0 * f64::EPSILON * scale;
            mu = next;
            if done {
                break;
            }
        }
        (mu, iterations, cx, cy)
    }

    /// Builds the contact record from the multiplier: position, normal, regime, Jacobian.
    #[inline]
    fn contact_from_mu(
        &self,
        r: &Vector2<f64>,
        mu: f64,
        iterations: u32,
        (alx, bex): (f64, f64),
        (aly, bey): (f64, f64),
    ) -> RingContact {
        let dx = (alx / (bex + mu)).copysign(r.x);
        let dy = (aly / (bey + mu)).copysign(r.y);
        let inv = 1.0 / (dx * dx + dy * dy).sqrt();
        let normal = Vector2::new(dx * inv, dy * inv);
        let gap = self.gap;
        let d = normal * gap;
        let s = r - d;
        let regime = self.regime_of_ring(&s);
        let slopes = self.elastic_slopes(&s);
        let two_mu = 2.0 * mu;
        let (ax_, ay_) = (slopes.x + two_mu, slopes.y + two_mu);
        let (ix, iy) = (1.0 / ax_, 1.0 / ay_);
        let w = Vector2::new(d.x * ix, d.y * iy);
        let dw = d.dot(&w);
        let v = (d - w * two_mu) * (1.0 / dw);
        let jacobian = Matrix2::new(
            two_mu * ix + w.x * v.x,
            w.x * v.y,
            w.y * v.x,
            two_mu * iy + w.y * v.y,
        );
        RingContact {
            s,
            mu,
            regime,
            jacobian,
            normal,
            iterations,
        }
    }
}

/// Closed form of the ring position in regime II for an isotropic ring (paper eq. 22, Table 3):
/// `s = r (R - gap)/R`, `R = |r|`. It does not check that the result is in regime II
/// (`|s_x| <= D_x`, `|s_y| <= D_y`); it is independent of `K`.
///
/// # Errors
/// [`RingError::NonFinite`] for non-finite `r` or `gap`, [`RingError::NotPositive`] for
/// `gap <= 0`, [`RingError::InsideGap`] for `|r| <= gap`.
pub fn regime_ii_position(r: &Vector2<f64>, gap: f64) -> Result<Vector2<f64>, RingError> {
    check_finite("r.x", r.x)?;
    check_finite("r.y", r.y)?;
    check_positive("gap", gap)?;
    let big_r = r.x.hypot(r.y);
    if big_r <= gap {
        return Err(RingError::InsideGap {
            distance: big_r,
            gap,
        });
    }
    Ok(r * ((big_r - gap) / big_r))
}

/// Closed form of the ring position in regime V for an isotropic ring (paper Table 3):
/// `s_i = sign(r_i) [ (|r_i| + D_i)(R~ - gap)/R~ - D_i ]` with
/// `R~ = |(|r_x| + D_x, |r_y| + D_y)|` (the paper's Table 3 writes `r_i + D_i`; the modulus is
/// meant, as its `sign(r_i)` shows). It does not check that the result is in regime V; it is
/// independent of `K`.
///
/// # Errors
/// [`RingError::NonFinite`] for non-finite inputs, [`RingError::Negative`] for a negative
/// preload (`"dx"`, `"dy"`), [`RingError::NotPositive`] for `gap <= 0`,
/// [`RingError::InsideGap`] for `|r| <= gap`.
pub fn regime_v_position(
    r: &Vector2<f64>,
    dx: f64,
    dy: f64,
    gap: f64,
) -> Result<Vector2<f64>, RingError> {
    check_finite("r.x", r.x)?;
    check_finite("r.y", r.y)?;
    check_non_negative("dx", dx)?;
    check_non_negative("dy", dy)?;
    check_positive("gap", gap)?;
    let big_r = r.x.hypot(r.y);
    if big_r <= gap {
        return Err(RingError::InsideGap {
            distance: big_r,
            gap,
        });
    }
    let (tx, ty) = (r.x.abs() + dx, r.y.abs() + dy);
    let rt = tx.hypot(ty);
    let q = (rt - gap) / rt;
    let sign = |v: f64| if v < 0.0 { -1.0 } else { 1.0 };
    Ok(Vector2::new(
        (tx * q - dx) * sign(r.x),
        (ty * q - dy) * sign(r.y),
    ))
}
