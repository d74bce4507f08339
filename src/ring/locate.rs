use nalgebra::{Matrix2, Vector2};

use super::branch::{Branch, Branches};
use super::SnubberRing;
use super::{
    check_finite, check_non_negative, check_positive, Regime, RingAxis, RingError, RingState,
};

/// Largest number of safeguarded Newton/bisection steps of the multiplier solver (1 to 4 are
/// typical; up to about 60 with a stiffness ratio of $10^7$ between the axes or a root next to
/// a branch's pole, and a poor warm start).
pub(crate) const MAX_ITERATIONS: u32 = 100;

/// The ring located in contact with the rotor at `r`, on given force-law branches.
///
/// Built by [`SnubberRing::locate`] (the true minimiser, branches chosen) or
/// [`SnubberRing::locate_on`] (the smooth extension of given branches).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingContact {
    /// Ring centre $s$, with $|r - s| = \gamma$ to rounding.
    pub s: Vector2<f64>,
    /// Lagrange multiplier $\mu$ of $g(s) = 2\mu(r - s)$; the elastic normal force is
    /// $2\mu\gamma$. Negative only on the extension of a regime inside $|r| = \gamma$.
    pub mu: f64,
    /// Unit contact normal $n = (r - s)/\gamma$, from the ring centre towards the rotor.
    pub normal: Vector2<f64>,
    /// $J = \partial s/\partial r$ on these branches.
    pub jacobian: Matrix2<f64>,
    /// The force-law branch of each axis.
    pub branches: Branches,
    /// Diagonal of the damping matrix $C$ on these branches ($4\nu_2$ inner, $2\nu_2$ outer).
    pub damping: Vector2<f64>,
    /// Elastic force $g(s) = 2\mu(r - s)$.
    pub elastic: Vector2<f64>,
    /// Newton iterations used (0 for the closed forms).
    pub iterations: u32,
}

impl RingContact {
    /// The contact regime (II..V) of the branches.
    pub fn regime(&self) -> Regime {
        self.branches.regime()
    }

    /// Ring velocity in contact, $s^\prime = J r^\prime$.
    pub fn ring_velocity(&self, r_dot: &Vector2<f64>) -> Vector2<f64> {
        self.jacobian * r_dot
    }

    /// Total force of the ring on the rotor, $f = g(s) + C J r^\prime$.
    pub fn force(&self, r_dot: &Vector2<f64>) -> Vector2<f64> {
        self.elastic + self.damping.component_mul(&self.ring_velocity(r_dot))
    }

    /// The paper's normal contact force $N = n\cdot f = 2\mu\gamma + n\cdot C J r^\prime$.
    pub fn normal_force(&self, r_dot: &Vector2<f64>) -> f64 {
        self.normal.dot(&self.force(r_dot))
    }
}

/// `(alpha, beta)` of `d = alpha/(beta + mu)` for one axis on `branch`, at rotor coordinate `r`.
#[inline(always)]
pub(super) fn coefficients(axis: &RingAxis, branch: Branch, r: f64) -> (f64, f64) {
    let k = axis.stiffness;
    match branch {
        Branch::Inner => (k * r, k),
        Branch::Outer(sigma) => (0.5 * k * (r + f64::from(sigma) * axis.preload), 0.5 * k),
    }
}

/// Multiplier at which an axis passes its preload, for `a = |r_i|`: `K D/(a - D)` if
/// `a > D > 0`, 0 if `D = 0`, infinity if `a <= D`.
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

/// The branch of an axis at multiplier `mu`, for rotor coordinate `r` (breakpoint `bp`).
#[inline(always)]
fn branch_at(axis: &RingAxis, r: f64, bp: f64, mu: f64) -> Branch {
    if axis.preload == 0.0 {
        Branch::Outer(0)
    } else if bp <= mu {
        Branch::Outer(if r >= 0.0 { 1 } else { -1 })
    } else {
        Branch::Inner
    }
}

/// $|d(\mu)|^2$ with the branches valid at `mu`.
#[inline(always)]
fn dist2_at(ring: &SnubberRing, r: &Vector2<f64>, bx: f64, by: f64, mu: f64) -> f64 {
    let (ax, bex) = coefficients(&ring.x, branch_at(&ring.x, r.x, bx, mu), r.x);
    let (ay, bey) = coefficients(&ring.y, branch_at(&ring.y, r.y, by, mu), r.y);
    let dx = ax / (bex + mu);
    let dy = ay / (bey + mu);
    dx * dx + dy * dy
}

/// The root of $|d| = \gamma$ on fixed branch coefficients.
struct Root {
    /// The multiplier $\mu$.
    mu: f64,
    /// $\beta_i + \mu$ of each axis, computed from $u = \beta_{\min} + \mu$ so that it keeps its
    /// relative accuracy next to the soft axis' pole.
    shift: (f64, f64),
    /// $d = r - s$, of length $\gamma$ to rounding.
    d: (f64, f64),
    /// Newton and bisection steps used.
    iterations: u32,
}

/// $d_i = \alpha_i/(o_i + u)$ of both axes at $u = \beta_{\min} + \mu$ (offsets
/// $o_i = \beta_i - \beta_{\min}$). At the pole itself ($u = 0$, where the soft axis' formula is
/// $0/0$: reached only when its $\alpha$ vanishes) the soft axis takes its limit from $u > 0$,
/// the rest of the length on the side of the sign of $\alpha$ (so that $r_i = \pm 0$ gives
/// the limits of $r_i \to 0^\pm$).
#[inline(always)]
fn distances((ax, ox): (f64, f64), (ay, oy): (f64, f64), gap: f64, u: f64) -> (f64, f64) {
    let (dx, dy) = (ax / (ox + u), ay / (oy + u));
    let rest = |other: f64| ((gap - other.abs()) * (gap + other.abs())).max(0.0).sqrt();
    match (dx.is_nan(), dy.is_nan()) {
        (true, false) => (rest(dy).copysign(ax), dy),
        (false, true) => (dx, rest(dx).copysign(ay)),
        _ => (dx, dy),
    }
}

/// Solves $|d(\mu)| = \gamma$ for fixed coefficients inside `[lo, hi]` (a piece of the branch
/// map), on $\mu > -\beta_{\min}$ (module docs), in the variable $u = \beta_{\min} + \mu$.
fn solve_mu(
    (ax, bx): (f64, f64),
    (ay, by): (f64, f64),
    gap: f64,
    (lo, hi): (f64, f64),
    hint: f64,
) -> Result<Root, RingError> {
    // Callers check that |alpha| is positive and finite.
    let eq = Equation::new((ax, bx), (ay, by), gap);
    let (left, right) = eq.bracket(lo, hi);
    if left >= right {
        // A closed form (equal betas: u = |alpha|/gamma; the pole's limit), or the piece and
        // the bracket touch through rounding: the root is at their meeting.
        return Ok(eq.root(0.5 * (left + right), 0));
    }
    let u = eq.first_guess(hint, left, right);
    eq.refine(u, left, right)
}

/// $|d(u)| = \gamma$ on fixed branch coefficients, in $u = \beta_{\min} + \mu$: each axis'
/// $(\alpha_i, o_i)$ with the offset $o_i = \beta_i - \beta_{\min}$.
struct Equation {
    cx: (f64, f64),
    cy: (f64, f64),
    gap: f64,
    bmin: f64,
    /// $|\alpha|$.
    norm: f64,
    /// Whether the x axis is the soft one ($\beta_x \le \beta_y$).
    soft_x: bool,
}

/// Inside the bracket and off the pole at u = 0.
#[inline(always)]
pub(super) fn valid(u: f64, left: f64, right: f64) -> bool {
    u >= left && u <= right && u > 0.0
}

impl Equation {
    #[inline(always)]
    fn new((ax, bx): (f64, f64), (ay, by): (f64, f64), gap: f64) -> Self {
        let bmin = bx.min(by);
        Equation {
            cx: (ax, bx - bmin),
            cy: (ay, by - bmin),
            gap,
            bmin,
            norm: (ax * ax + ay * ay).sqrt(),
            soft_x: bx <= by,
        }
    }

    /// The root record at `u`.
    #[inline(always)]
    fn root(&self, u: f64, iterations: u32) -> Root {
        Root {
            mu: u - self.bmin,
            shift: (self.cx.1 + u, self.cy.1 + u),
            d: distances(self.cx, self.cy, self.gap, u),
            iterations,
        }
    }

    /// The bracket of the root in $u$ on the piece `[lo, hi]` of $\mu$ (empty when the root is
    /// at the bracket's meeting point).
    #[inline(always)]
    fn bracket(&self, lo: f64, hi: f64) -> (f64, f64) {
        let ((ax, ox), (ay, oy), gap, norm) = (self.cx, self.cy, self.gap, self.norm);
        let delta = ox.max(oy);
        // |alpha| of the soft axis (pole at u = 0) and of the stiff one (pole at u = -delta);
        // with equal betas both axes are soft.
        let (a_soft, a_stiff) = if delta <= 0.0 {
            (norm, 0.0)
        } else if self.soft_x {
            (ax.abs(), ay.abs())
        } else {
            (ay.abs(), ax.abs())
        };
        // The bracket: |d_soft| <= gamma, and |alpha|/(delta + u) <= |d| = gamma <= |alpha|/u.
        let left = (lo + self.bmin)
            .max(a_soft / gap)
            .max(norm / gap - delta)
            .max(0.0);
        let mut right = (hi + self.bmin).min(norm / gap);
        // If the stiff axis alone stays inside the ring up to the pole (d_t0 < gamma there),
        // the soft axis takes at least the rest of the length:
        // u <= |alpha_soft|/sqrt(gamma^2 - d_t0^2). (Zero when alpha_soft vanishes: the root
        // is the pole's limit.)
        if delta > 0.0 {
            let dt0 = a_stiff / delta;
            if dt0 < gap {
                right = right.min(a_soft / ((gap - dt0) * (gap + dt0)).sqrt());
            }
        }
        (left, right)
    }

    /// The start: the hint if it is inside the bracket, else a first-order guess, else the
    /// bracket's midpoint.
    #[inline(always)]
    fn first_guess(&self, hint: f64, left: f64, right: f64) -> f64 {
        if valid(hint + self.bmin, left, right) {
            return hint + self.bmin;
        }
        let ((ax, ox), (ay, oy)) = (self.cx, self.cy);
        let (a2x, a2y) = (ax * ax, ay * ay);
        // For u >> delta, |d|^2 ~ |alpha|^2/(u + o_bar)^2 with the alpha^2-weighted mean
        // offset o_bar.
        let o_bar = (a2x * ox + a2y * oy) / (a2x + a2y);
        let guess = (self.norm / self.gap - o_bar).max(left).min(right);
        if valid(guess, left, right) {
            guess
        } else {
            0.5 * (left + right)
        }
    }

    /// Safeguarded Newton from `u` in the bracket `[left, right]`, to the ring's rounding.
    fn refine(&self, u: f64, left: f64, right: f64) -> Result<Root, RingError> {
        let (u, iterations) = refine(self, u, left, right)?;
        Ok(self.root(u, iterations))
    }
}

impl Distance for Equation {
    #[inline(always)]
    fn probe(&self, u: f64) -> Probe {
        let (ox, oy, gap) = (self.cx.1, self.cy.1, self.gap);
        let (dx, dy) = distances(self.cx, self.cy, gap, u);
        let (px, py) = (ox + u, oy + u);
        Probe {
            dist2: dx * dx + dy * dy,
            // -f'(u)/2, and |d'(u)|: how far the ring moves per unit of u.
            slope: dx * dx / px + dy * dy / py,
            speed: ((dx / px).powi(2) + (dy / py).powi(2)).sqrt(),
        }
    }

    #[inline(always)]
    fn gap(&self) -> f64 {
        self.gap
    }
}

/// $|d|^2$ and its rates at one point of the ring's location equation, for [`refine`].
pub(super) struct Probe {
    /// $f = |d|^2$.
    pub dist2: f64,
    /// $-f^\prime(u)/2 > 0$.
    pub slope: f64,
    /// $|d^\prime(u)|$: how far the ring moves per unit of $u$.
    pub speed: f64,
}

/// A ring location equation $|d(u)| = \gamma$ with $|d|$ strictly decreasing in $u > 0$: the
/// frictionless one ([`Equation`]) and the slipping one of [`super::friction`].
pub(super) trait Distance {
    /// $|d|^2$ and its rates at `u`.
    fn probe(&self, u: f64) -> Probe;
    /// The constraint radius $\gamma$.
    fn gap(&self) -> f64;
}

/// Safeguarded Newton on $|d(u)| = \gamma$ from `u` in the bracket `[left, right]`, to the
/// ring's rounding: the one iteration of every ring location (module docs, "Stopping rule and
/// tolerance"). Returns the root and the steps used.
pub(super) fn refine<E: Distance>(
    eq: &E,
    mut u: f64,
    mut left: f64,
    mut right: f64,
) -> Result<(f64, u32), RingError> {
    let gap = eq.gap();
    let mut iterations = 0;
    while iterations < MAX_ITERATIONS {
        iterations += 1;
        let Probe {
            dist2: f,
            slope: s3,
            speed,
        } = eq.probe(u);
        let residual = f.sqrt() / gap - 1.0; // > 0 left of the root
        if residual > 0.0 {
            left = u;
        } else if residual < 0.0 {
            right = u;
        } else {
            return Ok((u, iterations));
        }
        let step = f * residual / s3;
        let mut next = u + step;
        // Newton while it converges (a handful of steps); a step that leaves the bracket,
        // and every step after the first 8 (Newton lost in the rounding of the residual),
        // bisects: geometrically while the bracket spans orders of magnitude (next to the
        // pole).
        let newton = iterations <= 8 && valid(next, left, right);
        if !newton {
            next = if left > 0.0 && right > 4.0 * left {
                (left * right).sqrt()
            } else {
                0.5 * (left + right)
            };
        }
        // Resolved once a Newton step is below 1e-10 of u (the soft axis' scale: the error
        // left is ~ step^2/u, below rounding) or moves the ring by less than its rounding,
        // or the bracket is at adjacent floats or moves the ring by less than its rounding.
        let rounding = 4.0 * f64::EPSILON * gap;
        let done = (newton && (step.abs() <= 1e-10 * u || step.abs() * speed <= rounding))
            || right <= left.next_up()
            || (right - left) * speed <= rounding;
        u = next;
        if done {
            return Ok((u, iterations));
        }
    }
    Err(RingError::NotConverged {
        iterations,
        bracket: right - left,
    })
}

impl SnubberRing {
    /// The ring in contact with the rotor at `r` (`|r| > gap`): the energy minimiser on the
    /// circle $|r - s| = \gamma$, with the branches it lies on (see the module docs).
    ///
    /// # Errors
    /// [`RingError::NonFinite`] (`"r.x"`, `"r.y"`) for a non-finite `r`,
    /// [`RingError::InsideGap`] when `|r| <= gap`, or a parameter error if the ring is invalid.
    pub fn locate(&self, r: &Vector2<f64>) -> Result<RingContact, RingError> {
        self.locate_from(r, f64::NAN)
    }

    /// As [`SnubberRing::locate`], warm-started from a previous multiplier `mu_hint` (e.g. the
    /// [`RingContact::mu`] of the previous step). A hint that is NaN, infinite or outside the
    /// root's bracket is ignored; the result does not depend on the hint beyond rounding.
    ///
    /// # Errors
    /// As [`SnubberRing::locate`].
    pub fn locate_from(&self, r: &Vector2<f64>, mu_hint: f64) -> Result<RingContact, RingError> {
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
        // The piece [lo, hi] of mu holding the root, from the breakpoints.
        let bx = breakpoint(&self.x, r.x.abs());
        let by = breakpoint(&self.y, r.y.abs());
        let (b1, b2) = if bx <= by { (bx, by) } else { (by, bx) };
        let g2 = gap * gap;
        let (mut lo, mut hi) = (0.0, f64::INFINITY);
        if b1.is_finite() {
            if dist2_at(self, r, bx, by, b1) > g2 {
                lo = b1;
                if b2.is_finite() {
                    if dist2_at(self, r, bx, by, b2) > g2 {
                        lo = b2;
                    } else {
                        hi = b2;
                    }
                }
            } else {
                hi = b1;
            }
        }
        let branches = Branches {
            x: branch_at(&self.x, r.x, bx, lo),
            y: branch_at(&self.y, r.y, by, lo),
        };
        self.place(r, branches, (lo, hi), mu_hint)
    }

    /// The ring on the given branches: the smooth extension of that contact regime (valid also a
    /// little inside $|r| = \gamma$ and beyond the regime's boundaries), warm-started from
    /// `mu_hint` (`f64::NAN` for none). This is what an integrator uses inside one contact mode,
    /// so that no step straddles the kink of a regime boundary.
    ///
    /// # Errors
    /// [`RingError::NoPlacement`] when the branch formulas have no solution at `r` (both axes
    /// at the branch's centre $r_i = -\sigma_i D_i$, or non-finite `r`),
    /// [`RingError::NotConverged`] if the solver failed to converge.
    pub fn locate_on(
        &self,
        r: &Vector2<f64>,
        branches: Branches,
        mu_hint: f64,
    ) -> Result<RingContact, RingError> {
        if self.is_uniform(branches) {
            return self.locate_uniform(r, branches);
        }
        self.place(r, branches, (f64::NEG_INFINITY, f64::INFINITY), mu_hint)
    }

    /// Solves on fixed branches inside `[lo, hi]` and builds the contact record.
    fn place(
        &self,
        r: &Vector2<f64>,
        branches: Branches,
        bounds: (f64, f64),
        mu_hint: f64,
    ) -> Result<RingContact, RingError> {
        let cx = coefficients(&self.x, branches.x, r.x);
        let cy = coefficients(&self.y, branches.y, r.y);
        let no_placement = RingError::NoPlacement { x: r.x, y: r.y };
        if !((cx.0 * cx.0 + cy.0 * cy.0).sqrt() > 0.0 && (cx.0 + cy.0).is_finite()) {
            return Err(no_placement);
        }
        let root = solve_mu(cx, cy, self.gap, bounds, mu_hint)?;
        let (dx, dy) = root.d;
        let dn = (dx * dx + dy * dy).sqrt();
        if !(dn > 0.0 && dn.is_finite()) {
            return Err(no_placement);
        }
        let normal = Vector2::new(dx / dn, dy / dn);
        let d = normal * self.gap;
        let mu = root.mu;
        let two_mu = 2.0 * mu;
        // J = I - (2/P) [[beta_x d_y^2, -beta_y d_x d_y], [-beta_x d_x d_y, beta_y d_x^2]] with
        // P = a_y d_x^2 + a_x d_y^2, a_i = g_i' + 2 mu = 2 (beta_i + mu) (docs/ring.md): no
        // cancellation, finite at a pole (a_i = 0).
        let (bex, bey) = (cx.1, cy.1);
        let (a_x, a_y) = (2.0 * root.shift.0, 2.0 * root.shift.1);
        let q = 2.0 / (a_y * d.x * d.x + a_x * d.y * d.y);
        let jacobian = Matrix2::new(
            1.0 - q * bex * d.y * d.y,
            q * bey * d.x * d.y,
            q * bex * d.x * d.y,
            1.0 - q * bey * d.x * d.x,
        );
        let iterations = root.iterations;
        Ok(RingContact {
            s: r - d,
            mu,
            normal,
            jacobian,
            branches,
            damping: self.branch_damping(branches),
            elastic: d * two_mu,
            iterations,
        })
    }

    /// Damping coefficients of the branches: $4\nu_2$ inner, $2\nu_2$ outer.
    pub(super) fn branch_damping(&self, b: Branches) -> Vector2<f64> {
        let unit = |b: Branch| if b.is_outer() { 2.0 } else { 4.0 } * self.damping;
        Vector2::new(unit(b.x), unit(b.y))
    }

    /// Closed form when both axes share $K$ and the branch kind (regimes II and V of an
    /// isotropic ring): $|d| = K|a|/(K + c\mu) = \gamma$ with $a = r + \sigma D$, so
    /// $\mu = K(|a|/\gamma - 1)/c$, $d = \gamma a/|a|$, and with $\alpha = g^\prime + 2\mu$ the
    /// same on both axes, $J = (2\mu/\alpha) I + (1 - 2\mu/\alpha)\thinspace n n^{\mathsf T}$.
    fn locate_uniform(
        &self,
        r: &Vector2<f64>,
        branches: Branches,
    ) -> Result<RingContact, RingError> {
        let u = self.uniform(r, branches)?;
        Ok(RingContact {
            s: r - u.d,
            mu: u.mu,
            normal: u.normal,
            jacobian: u.jacobian,
            branches,
            damping: self.branch_damping(branches),
            elastic: u.d * (2.0 * u.mu),
            iterations: 0,
        })
    }

    /// Whether [`SnubberRing::locate_on`] solves `branches` in closed form (both axes share
    /// $K$ and the branch kind).
    #[inline]
    pub(crate) fn is_uniform(&self, branches: Branches) -> bool {
        self.x.stiffness == self.y.stiffness && branches.x.is_outer() == branches.y.is_outer()
    }

    /// Position, velocity and force of the ring on uniform branches at `r` with rotor velocity
    /// `v`: the fields of [`SnubberRing::locate_on`] that the vector field needs, bitwise the
    /// same, without building the whole contact record.
    #[inline]
    pub(crate) fn uniform_state(
        &self,
        r: &Vector2<f64>,
        v: &Vector2<f64>,
        branches: Branches,
    ) -> Result<RingState, RingError> {
        let u = self.uniform(r, branches)?;
        let s_dot = u.jacobian * v;
        let force = u.d * (2.0 * u.mu) + self.branch_damping(branches).component_mul(&s_dot);
        Ok(RingState {
            s: r - u.d,
            s_dot,
            force,
        })
    }

    /// The closed form of [`SnubberRing::locate_uniform`].
    #[inline(always)]
    fn uniform(&self, r: &Vector2<f64>, branches: Branches) -> Result<Uniform, RingError> {
        let k = self.x.stiffness;
        let sigma = |b: Branch| match b {
            Branch::Inner => 0.0,
            Branch::Outer(s) => f64::from(s),
        };
        let ax = k * (r.x + sigma(branches.x) * self.x.preload);
        let ay = k * (r.y + sigma(branches.y) * self.y.preload);
        // Plain sqrt, not hypot: the arguments are O(K), far from overflow, and hypot is slow.
        let a_norm = (ax * ax + ay * ay).sqrt();
        if !(a_norm > 0.0 && a_norm.is_finite()) {
            return Err(RingError::NoPlacement { x: r.x, y: r.y });
        }
        let outer = branches.x.is_outer();
        // Divided by c = 2 (outer) or 1 (inner), exactly, without a division.
        // (A gap of 1, the paper's scaling, needs no division: the same bits.)
        let scaled = if self.gap == 1.0 {
            a_norm
        } else {
            a_norm / self.gap
        };
        let excess = scaled - k;
        let mu = if outer { excess * 0.5 } else { excess };
        let normal = Vector2::new(ax, ay) * a_norm.recip();
        let d = normal * self.gap;
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
        Ok(Uniform {
            mu,
            normal,
            d,
            jacobian,
        })
    }
}

/// The closed-form location on uniform branches.
struct Uniform {
    mu: f64,
    normal: Vector2<f64>,
    /// $d = r - s = \gamma n$.
    d: Vector2<f64>,
    jacobian: Matrix2<f64>,
}

/// Closed form of the ring position in regime II for an isotropic ring (paper eq. 22, Table 3):
/// `s = r (R - gap)/R`, `R = |r|`. It does not check that the result is in regime II
/// (`|s_x| <= D_x`, `|s_y| <= D_y`); it is independent of `K`.
///
/// # Errors
/// [`RingError::NonFinite`] for non-finite `r` or `gap`, [`RingError::NotPositive`] for
/// `gap <= 0`, [`RingError::InsideGap`] for `|r| <= gap`.
///
/// ```
/// use jeffcott::nalgebra::Vector2;
/// use jeffcott::ring::regime_ii_position;
///
/// // |r| = 1.5 with gap 1: the ring moves a third of the way along r.
/// let s = regime_ii_position(&Vector2::new(0.9, 1.2), 1.0)?;
/// assert!((s - Vector2::new(0.3, 0.4)).norm() < 1e-15);
/// # Ok::<(), jeffcott::ring::RingError>(())
/// ```
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
///
/// ```
/// use jeffcott::nalgebra::Vector2;
/// use jeffcott::ring::regime_v_position;
///
/// // r - s = sign(r_i) (|r_i| + D_i) / R~ per axis, so the ring is on the contact circle.
/// let r = Vector2::new(2.0, 1.0);
/// let s = regime_v_position(&r, 0.1, 0.2, 1.0)?;
/// assert!(((r - s).norm() - 1.0).abs() < 1e-15);
/// assert!(s.x > 0.1 && s.y > 0.2); // both axes beyond their preloads: regime V
/// # Ok::<(), jeffcott::ring::RingError>(())
/// ```
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
