//! The ring with Coulomb friction at the contact: where the ring sits while the shaft slips on
//! it or rolls on it, and how a contact starts (`../shared/MODEL.md`, "Beyond the paper:
//! friction at the contact"; [friction.md](https://docs.rs/crate/jeffcott/latest/source/docs/friction.md)).
//!
//! A contact law beside the frictionless ring, not a branch inside it: [`FrictionRing`] is a
//! [`SnubberRing`] and a friction coefficient $\mu_f \ge 0$, and with $\mu_f = 0$ every location
//! is [`SnubberRing::locate`]'s, bit for bit.
//!
//! # Geometry and forces
//!
//! In contact the ring's centre is $s = r - \gamma n$ with the contact normal
//! $n = (\cos\theta, \sin\theta)$ and the tangent $t = (-\sin\theta, \cos\theta)$ ($n$ turned by
//! $+90°$). The ring's elastic force $g(s)$ splits into its normal part $N = n\cdot g$ and its
//! tangential part $F_t = t\cdot g$. The shaft spins counter-clockwise with surface speed
//! $\eta a$ (spin rate times the shaft's radius at the ring); the slip velocity of the shaft on
//! the ring is
//!
//! $$v = (r^\prime - s^\prime)\cdot t + \eta a = \gamma\theta^\prime + \eta a.$$
//!
//! * **Slipping** in the sense $\sigma = \operatorname{sign} v = \pm1$ ([`Slip`]):
//!   $F_t = \mu_f\sigma N$, $N \ge 0$. For a given rotor position $r$ this locates the massless
//!   ring ([`FrictionRing::locate_slipping`]); the ring's velocity follows at fixed $\sigma$.
//! * **Rolling** ($v = 0$): $\theta$ is a state of its own, $\theta^\prime = -\eta a/\gamma$,
//!   and $N$, $F_t$ follow from $g(r - \gamma n(\theta))$ ([`FrictionRing::rolling`]); it lasts
//!   while $|F_t| \le \mu_f N$.
//! * **A start** ([`FrictionRing::start`]): slipping forward if that location's slip velocity
//!   $v_+$ is positive, backward if $v_-$ is negative, rolling otherwise.
//!
//! # Where the slipping ring sits
//!
//! With $d = r - s = \gamma n$ and $\kappa = \mu_f\sigma$, the slip law says
//! $g(s) = N(n + \kappa t)$, i.e. $g(s) = 2m(d + \kappa Jd)$ with $J$ the rotation by $+90°$ and
//! $m = N/(2\gamma)$ (the frictionless multiplier [`RingContact::mu`](super::RingContact::mu) at
//! $\kappa = 0$). On fixed branches each axis' force is affine,
//! $g_i = 2(\alpha_i - \beta_i d_i)$ (the coefficients of the frictionless solver), so
//!
//! $$A(m)\thinspace d = \alpha,\qquad A(m) = \begin{pmatrix}\beta_x + m & -\kappa m\\\\
//! \kappa m & \beta_y + m\end{pmatrix},\qquad |d| = \gamma.$$
//!
//! **One root.** Along the solution, $\tfrac{d}{dm}|d|^2 = -2\thinspace d\cdot
//! (M^{-1}B + mI)^{-1} d$ with $M = I + \kappa J$, $B = \operatorname{diag}(\beta_i)$; the
//! symmetric part of $M^{-1}B$ is $(B + \kappa S)/(1 + \kappa^2)$,
//! $S = \tfrac{\beta_x - \beta_y}{2}\begin{pmatrix}0&1\\\\1&0\end{pmatrix}$, whose least
//! eigenvalue is $\lambda = \tfrac{\beta_x + \beta_y}{2} - \tfrac{|\beta_x - \beta_y|}{2}
//! \sqrt{1 + \kappa^2}$. So $|d|$ falls strictly for $m > m_c = -\lambda/(1 + \kappa^2)$, and the
//! root is unique on $m \ge 0$ (every contact, $N \ge 0$) on every branch pair with
//! $\lambda > 0$, i.e. $\kappa^2(\beta_x - \beta_y)^2 < 4\beta_x\beta_y$. Between branches the
//! solution $d(m)$ of the piecewise-affine system is continuous (its symmetric part
//! $B + mI$ is positive definite), so the whole location is unique when every branch pair the
//! ring has satisfies it: $\mu_f$ below [`FrictionRing::limit`],
//! $\min 2\sqrt{\beta_x\beta_y}/|\beta_x - \beta_y|$ over the pairs ($2\sqrt2$ for an isotropic
//! preloaded ring, unbounded without preload, $2\sqrt\rho/(\rho - 1)$ for a stiffness ratio
//! $\rho$). Beyond it a location may not be unique (a wedged ring has several), and
//! [`FrictionRing::new`] refuses the coefficient with [`RingError::FrictionBeyondUniqueness`]
//! rather than pick one. It is a sufficient bound: some rings beyond it still have one root.
//!
//! **The solver** is the frictionless one's ([`SnubberRing::locate`]): the safeguarded Newton
//! iteration on $|d| = \gamma$ in the distance $u = m - m_c > 0$ from the monotonicity bound
//! (the soft axis' pole $-\beta_{\min}$ at $\kappa = 0$), with the same stopping rule; the
//! bracket is $|\alpha|/\lVert A\rVert \ge \gamma$ on the left and
//! $u \le |\alpha|/(\gamma\sqrt{1 + \kappa^2})$ on the right (from
//! $d\cdot M^{-1}A d \ge u|d|^2$); equal $\beta$s have the closed form
//! $m = (T^2 - \beta^2)/(\beta + \sqrt{T^2(1 + \kappa^2) - \kappa^2\beta^2})$,
//! $T = |\alpha|/\gamma$. The branches are those of the frictionless minimiser, corrected until
//! the located ring lies on them (an active-set iteration); if that does not settle, bisection
//! on $m$ over the piecewise-affine solution finds them.
//!
//! **The ring's velocity.** Differentiating $A d = \alpha(r)$, $d = \gamma n(\theta)$ at fixed
//! $\sigma$ ($\partial\alpha/\partial r = B$) gives two equations for $d\theta$ and $dm$:
//! $\gamma A t\thinspace d\theta + M d\thinspace dm = B\thinspace dr$. With $U = \gamma A t$,
//! $V = Md$ and $\Delta = U \times V$ (the 2-D cross product),
//! $\partial s/\partial r = I - \gamma\thinspace t\thinspace(\beta_x V_y, -\beta_y V_x)/\Delta$,
//! where $\Delta = -\gamma^2\left[(\beta_x + m)n_y^2 + (\beta_y + m)n_x^2 +
//! \kappa(\kappa m - (\beta_y - \beta_x)n_xn_y)\right]$: at $\kappa = 0$ the frictionless
//! Jacobian, without cancellation.

use super::{check_non_negative, RingAxis, RingError, SnubberRing};

mod roll;
mod sensitivity;
mod slip;
mod start;

pub use roll::RollContact;
pub use slip::SlipContact;
pub use start::ContactStart;

/// The sense in which the shaft slips on the ring: the sign $\sigma$ of the slip velocity $v$.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Slip {
    /// $v > 0$: the shaft's surface runs ahead of the contact point ($\sigma = +1$; a forward
    /// whirl slower than the spin, or any backward whirl slower than the surface speed).
    Forward,
    /// $v < 0$: $\sigma = -1$ (e.g. dry whip: a backward whirl faster than the surface speed).
    Backward,
}

impl Slip {
    /// $\sigma = \pm 1$.
    pub fn sign(self) -> f64 {
        match self {
            Slip::Forward => 1.0,
            Slip::Backward => -1.0,
        }
    }

    /// The sense of a slip velocity or tangential force: `Forward` for `v > 0`, `Backward` for
    /// `v < 0`, none for 0 or NaN.
    pub fn of(v: f64) -> Option<Self> {
        if v > 0.0 {
            Some(Slip::Forward)
        } else if v < 0.0 {
            Some(Slip::Backward)
        } else {
            None
        }
    }
}

/// The snubber ring with Coulomb friction $\mu_f$ between shaft and ring (module docs).
///
/// ```
/// use jeffcott::nalgebra::Vector2;
/// use jeffcott::ring::{FrictionRing, Slip, SnubberRing};
///
/// let ring = SnubberRing::isotropic(30.0, 0.1, 0.002)?;
/// let rub = FrictionRing::new(ring, 0.3)?;
/// let r = Vector2::new(1.05, 0.2);
/// let c = rub.locate_slipping(&r, Slip::Forward)?;
/// // On the contact circle, with the tangential force mu N in the sense of the slip.
/// assert!(((r - c.s).norm() - 1.0).abs() < 1e-14);
/// let (n, ft) = (c.elastic_normal(), c.elastic_tangential());
/// assert!(n > 0.0 && (ft - 0.3 * n).abs() < 1e-12 * n);
/// // Without friction, the frictionless ring's location, bit for bit.
/// let plain = FrictionRing::new(ring, 0.0)?.locate_slipping(&r, Slip::Forward)?;
/// assert_eq!(plain.s, ring.locate(&r)?.s);
/// # Ok::<(), jeffcott::ring::RingError>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrictionRing {
    ring: SnubberRing,
    friction: f64,
}

impl FrictionRing {
    /// The ring with friction coefficient `friction`.
    ///
    /// # Errors
    /// A parameter error of the ring; [`RingError::NonFinite`] or [`RingError::Negative`]
    /// (`"friction"`); [`RingError::FrictionBeyondUniqueness`] when `friction` is at or above
    /// [`FrictionRing::limit`] of the ring.
    pub fn new(ring: SnubberRing, friction: f64) -> Result<Self, RingError> {
        ring.validate()?;
        check_non_negative("friction", friction)?;
        let limit = Self::limit(&ring);
        if friction >= limit {
            return Err(RingError::FrictionBeyondUniqueness { friction, limit });
        }
        Ok(Self { ring, friction })
    }

    /// The frictionless ring.
    pub fn ring(&self) -> &SnubberRing {
        &self.ring
    }

    /// The friction coefficient $\mu_f$.
    pub fn friction(&self) -> f64 {
        self.friction
    }

    /// The friction coefficient below which every slipping location of `ring` is unique
    /// (module docs): $\min 2\sqrt{\beta_x\beta_y}/|\beta_x - \beta_y|$ over the branch pairs
    /// the ring has ($\beta = K/2$ beyond a preload, $K$ inside one), infinite when all pairs
    /// are equal.
    ///
    /// ```
    /// use jeffcott::ring::{FrictionRing, RingAxis, SnubberRing};
    ///
    /// // Isotropic with preload: the pairs (K, K/2) give 2 sqrt(2).
    /// let preloaded = SnubberRing::isotropic(30.0, 0.1, 0.002)?;
    /// assert!((FrictionRing::limit(&preloaded) - 8f64.sqrt()).abs() < 1e-15);
    /// // Isotropic without preload: one pair, no bound.
    /// assert!(FrictionRing::limit(&SnubberRing::isotropic(30.0, 0.0, 0.002)?).is_infinite());
    /// // A stiffness ratio of 4 without preload: 2 sqrt(4)/3.
    /// let aniso = SnubberRing::new(RingAxis::new(1.0, 0.0), RingAxis::new(4.0, 0.0), 0.0, 1.0)?;
    /// assert!((FrictionRing::limit(&aniso) - 4.0 / 3.0).abs() < 1e-15);
    /// # Ok::<(), jeffcott::ring::RingError>(())
    /// ```
    pub fn limit(ring: &SnubberRing) -> f64 {
        let betas = |a: &RingAxis| {
            [
                Some(0.5 * a.stiffness),
                (a.preload > 0.0).then_some(a.stiffness),
            ]
        };
        let mut limit = f64::INFINITY;
        for bx in betas(&ring.x).into_iter().flatten() {
            for by in betas(&ring.y).into_iter().flatten() {
                if bx != by {
                    limit = limit.min(2.0 * (bx * by).sqrt() / (bx - by).abs());
                }
            }
        }
        limit
    }
}
