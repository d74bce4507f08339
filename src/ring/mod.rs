//! The preloaded snubber ring as a reusable contact element.
//!
//! All quantities are non-dimensional (lengths in units of the physical gap, forces in units of
//! $k_r \gamma$, time $\tau = \omega_n t$), but the constraint radius [`SnubberRing::gap`] is kept
//! as a field so the element can be used with any scaling (it is 1 in the paper's).
//!
//! # Model
//!
//! Per axis $i \in \lbrace x, y \rbrace$ the ring is held by two preloaded spring-damper units of
//! unit stiffness $K_i > 0$ and preload $D_i \ge 0$ (see [`RingAxis`]). With $s$ the ring centre
//! (the axis index dropped where one axis is meant):
//!
//! * elastic energy
//!   $$e_i(s) = \begin{cases} K s^2 & |s| \le D,\\\\ \tfrac{K}{2}\left((|s| + D)^2 - 2 D^2\right) & |s| \ge D \end{cases}$$
//!   (both give $K D^2$ at $|s| = D$); total $E(s) = e_x(s_x) + e_y(s_y)$;
//! * elastic force $g_i(s) = e_i^\prime(s)$: $2 K s$ inside the preload and
//!   $\operatorname{sign}(s)\thinspace K (|s| + D)$ beyond it (continuous at $|s| = D$, slope
//!   $2K \to K$);
//! * damping $c_i\thinspace s_i^\prime$ with $c_i = 4 \nu_2$ inside (both units act) and
//!   $2 \nu_2$ beyond (one unit has lifted off);
//! * total force of the ring $f = g(s) + C s^\prime$, $C = \operatorname{diag}(c_x, c_y)$.
//!
//! An axis is *inside* its preload when $D > 0$ and $|s| \le D$, and *beyond* it otherwise: an
//! axis with zero preload is always beyond (then $g = K s$, $c = 2 \nu_2$). The same predicate
//! decides the energy branch, the force branch, the damping coefficient, the Jacobian and the
//! regime, so they never disagree (the paper's strict $|s| < D$ for the damping only differs on
//! the set $|s| = D$).
//!
//! In contact ($|r| > \mathrm{gap}$) the ring sits at the energy minimiser $s^{\ast}(r)$ on the
//! circle $|r - s| = \mathrm{gap}$ ([`SnubberRing::locate`], see [`locate`] and
//! [ring.md](https://docs.rs/crate/jeffcott/latest/source/docs/ring.md) for the solver); out of
//! contact the massless ring relaxes exactly ([`SnubberRing::relax`]).

use nalgebra::Vector2;
use thiserror::Error;

pub mod branch;
pub mod element;
pub mod locate;
pub mod onset;
pub mod regime;
pub mod relax;
pub mod sensitivity;
pub(crate) mod station;

pub use branch::{Branch, Branches};
pub use element::{
    Axis, Kinematics, RingCache, RingGuard, RingMode, RingState, RingTransition, ONSET_TOUCH,
};
pub use locate::{regime_ii_position, regime_v_position, RingContact, MAX_ITERATIONS};
pub use regime::{boundaries, Regime};
pub use relax::Relaxation;
pub use sensitivity::{ContactHessian, ForceJacobian, GuardGradient};

/// Errors of the snubber-ring element: every variant names the offending field and its value.
#[derive(Debug, Clone, Copy, PartialEq, Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum RingError {
    /// A parameter or input is NaN or infinite.
    #[error("{field} must be finite, got {value}")]
    NonFinite {
        /// Name of the field or argument (e.g. `"x.stiffness"`, `"r.y"`).
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// The offending value.
        value: f64,
    },
    /// A parameter that must be `>= 0` is negative.
    #[error("{field} must be >= 0, got {value}")]
    Negative {
        /// Name of the field.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// The offending value.
        value: f64,
    },
    /// A parameter that must be `> 0` is zero or negative.
    #[error("{field} must be > 0, got {value}")]
    NotPositive {
        /// Name of the field.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// The offending value.
        value: f64,
    },
    /// A routine that assumes equal stiffness on both axes got an anisotropic ring.
    #[error("x.stiffness = {x} and y.stiffness = {y} differ; an isotropic stiffness is required")]
    AnisotropicStiffness {
        /// `K_x`.
        x: f64,
        /// `K_y`.
        y: f64,
    },
    /// The rotor is not in contact: `|r| <= gap`, so there is no contact position.
    #[error("rotor at distance |r| = {distance} is inside the gap {gap}: no contact")]
    InsideGap {
        /// `|r|`, the distance of the rotor centre from the ring's rest position.
        distance: f64,
        /// The gap (constraint radius).
        gap: f64,
    },
    /// The branch formulas of a contact mode have no solution at the rotor position
    /// `(x, y)` (both axes exactly at their branch centre $r_i = -\sigma_i D_i$, or a
    /// non-finite position): the contact mode cannot continue there.
    #[error("no ring placement on the contact branches at r = ({x}, {y})")]
    NoPlacement {
        /// `r.x`.
        x: f64,
        /// `r.y`.
        y: f64,
    },
    /// The multiplier solver did not converge (not expected for finite input: bisection halves
    /// the bracket every step).
    #[error("ring location did not converge in {iterations} iterations (bracket width {bracket})")]
    NotConverged {
        /// Iterations made.
        iterations: u32,
        /// Width of the remaining bracket of the multiplier.
        bracket: f64,
    },
    /// The rotor is beyond the ring: `|r - s| > gap` (more than the tolerance), an impossible
    /// state.
    #[error("rotor beyond the ring: |r - s| = {distance} > gap {gap}; place the ring with SnubberRing::consistent_position")]
    BeyondRing {
        /// `|r - s|`.
        distance: f64,
        /// The gap.
        gap: f64,
    },
    /// At a contact transition at time `t`, a preloaded axis' whole inner region ($2D_i$
    /// wide) is narrower than the resolution at which the ring's branch is decided there (the
    /// rounding of the located position plus the distance the ring moves in the time
    /// resolution of an event), with the ring within that resolution of it: which side of the
    /// preload the ring is on cannot be decided, and a contact run on the wrong branch would
    /// be a silent wrong answer (docs/reliability.md, "Preloads below the resolution of the
    /// run"). Set such a preload to 0, or make it larger than the resolution (shorter runs,
    /// a rest position nearer the ring, slower motion).
    #[error("{field} = {preload:e} is below the resolution {resolution:e} of the ring's position at t = {t}: the side of the preload cannot be decided; set it to 0 or above the resolution")]
    PreloadBelowResolution {
        /// `"x.preload"` or `"y.preload"`.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// The preload $D_i$.
        preload: f64,
        /// The resolution: $64\varepsilon(|r| + \gamma) + |s_i^\prime|\tau$, with
        /// $\tau = 64\varepsilon\max(|t|, 1)$.
        resolution: f64,
        /// Time of the transition.
        t: f64,
    },
    /// In contact, the ring is not at its minimum-energy position $s^*(r)$.
    #[error("rotor in contact but the ring is {offset} away from its minimum-energy position; place it with SnubberRing::consistent_position")]
    RingOffMinimum {
        /// `|s - s*(r)|`.
        offset: f64,
    },
}

/// Checks that `value` is finite.
pub(crate) fn check_finite(field: &'static str, value: f64) -> Result<f64, RingError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(RingError::NonFinite { field, value })
    }
}

/// Checks that `value` is finite and `>= 0`.
pub(crate) fn check_non_negative(field: &'static str, value: f64) -> Result<f64, RingError> {
    check_finite(field, value)?;
    if value >= 0.0 {
        Ok(value)
    } else {
        Err(RingError::Negative { field, value })
    }
}

/// Checks that `value` is finite and `> 0`.
pub(crate) fn check_positive(field: &'static str, value: f64) -> Result<f64, RingError> {
    check_finite(field, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(RingError::NotPositive { field, value })
    }
}

/// One axis of the ring: the two opposing spring-damper units along `x` or `y`.
///
/// * `stiffness` `K > 0`: stiffness of one unit (`k_s / k_r`). `K = 0` is rejected: with no
///   stiffness on an axis the ring can slide freely along it and the contact position is not
///   unique (any point of a chord of the circle has the same energy).
/// * `preload` `D >= 0`: the preload displacement (`Delta / gamma`); `D = 0` means no preload.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingAxis {
    /// Unit stiffness `K > 0` of this axis.
    pub stiffness: f64,
    /// Preload `D >= 0` of this axis.
    pub preload: f64,
}

impl RingAxis {
    /// An axis with stiffness `K` and preload `D` (validated when the ring is built).
    pub fn new(stiffness: f64, preload: f64) -> Self {
        Self { stiffness, preload }
    }

    /// `true` when `s` is inside the preload on this axis: `D > 0` and `|s| <= D`.
    #[inline]
    pub fn is_inside(&self, s: f64) -> bool {
        self.preload > 0.0 && s.abs() <= self.preload
    }

    /// Elastic energy of the axis,
    /// `e(s) = K s^2` inside the preload, `(K/2)((|s| + D)^2 - 2 D^2)` beyond it.
    #[inline]
    pub fn energy(&self, s: f64) -> f64 {
        let (k, d) = (self.stiffness, self.preload);
        if self.is_inside(s) {
            k * s * s
        } else {
            let a = s.abs() + d;
            0.5 * k * (a * a - 2.0 * d * d)
        }
    }

    /// Elastic force `g(s) = e'(s)`: `2 K s` inside the preload, `sign(s) K (|s| + D)` beyond it.
    #[inline]
    pub fn elastic_force(&self, s: f64) -> f64 {
        let (k, d) = (self.stiffness, self.preload);
        if self.is_inside(s) {
            2.0 * k * s
        } else if s == 0.0 {
            0.0
        } else {
            k * (s + d.copysign(s))
        }
    }

    /// Elastic stiffness `g'(s)`: `2 K` inside the preload, `K` beyond it (one-sided at `|s| = D`,
    /// where the inside value is returned).
    #[inline]
    pub fn elastic_slope(&self, s: f64) -> f64 {
        if self.is_inside(s) {
            2.0 * self.stiffness
        } else {
            self.stiffness
        }
    }

    /// Damping coefficient: `4 nu2` inside the preload, `2 nu2` beyond it.
    #[inline]
    pub fn damping_coefficient(&self, s: f64, damping: f64) -> f64 {
        if self.is_inside(s) {
            4.0 * damping
        } else {
            2.0 * damping
        }
    }
}

/// The preloaded snubber ring: two [`RingAxis`], the damping ratio `nu2` and the gap.
///
/// Build it with [`SnubberRing::new`] or [`SnubberRing::isotropic`], which validate the parameters.
/// The fields are public for reading; every fallible method re-validates, so a ring edited into
/// an invalid state yields a [`RingError`] (never a panic).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SnubberRing {
    /// The horizontal axis.
    pub x: RingAxis,
    /// The vertical axis.
    pub y: RingAxis,
    /// Damping ratio `nu2 >= 0` of one unit (`c_s / (2 sqrt(k_r M))`); a unit's damping force is
    /// `2 nu2 s'`.
    pub damping: f64,
    /// Constraint radius (radial clearance) `gap > 0`; 1 in the paper's scaling.
    pub gap: f64,
}

impl SnubberRing {
    /// A ring with axes `x`, `y`, damping ratio `nu2 = damping` and constraint radius `gap`.
    ///
    /// # Errors
    /// [`RingError::NonFinite`] for NaN/inf, [`RingError::NotPositive`] for `K <= 0` or
    /// `gap <= 0`, [`RingError::Negative`] for `D < 0` or `nu2 < 0`; the field is named as
    /// `"x.stiffness"`, `"y.preload"`, `"damping"`, `"gap"`.
    pub fn new(x: RingAxis, y: RingAxis, damping: f64, gap: f64) -> Result<Self, RingError> {
        let ring = Self { x, y, damping, gap };
        ring.validate()?;
        Ok(ring)
    }

    /// An isotropic ring (`K_x = K_y = stiffness`, `D_x = D_y = preload`) with gap 1.
    ///
    /// # Errors
    /// As [`SnubberRing::new`].
    pub fn isotropic(stiffness: f64, preload: f64, damping: f64) -> Result<Self, RingError> {
        let axis = RingAxis::new(stiffness, preload);
        Self::new(axis, axis, damping, 1.0)
    }

    /// Checks all parameters (see [`SnubberRing::new`]).
    ///
    /// # Errors
    /// The first invalid field, as a typed [`RingError`].
    pub fn validate(&self) -> Result<(), RingError> {
        check_positive("x.stiffness", self.x.stiffness)?;
        check_non_negative("x.preload", self.x.preload)?;
        check_positive("y.stiffness", self.y.stiffness)?;
        check_non_negative("y.preload", self.y.preload)?;
        check_non_negative("damping", self.damping)?;
        check_positive("gap", self.gap)?;
        Ok(())
    }

    /// `true` when both axes have the same stiffness and the same preload.
    pub fn is_isotropic(&self) -> bool {
        self.x == self.y
    }

    /// Bounds of the stiffness and of the damping coefficient with which the ring in contact
    /// acts on the rotor's station: $2\max(K_x, K_y)$ (both units of the stiffer axis; the ring
    /// is never stiffer than its stiffest branch) and $4\nu_2$ (both dampers of an inner
    /// branch). For [`crate::hybrid::RotorModel::max_rate`]: a unit-mass station with the
    /// ring adds at most $\sqrt{k}$ and $c$ to the rates of its motion.
    pub fn contact_bounds(&self) -> (f64, f64) {
        (
            2.0 * self.x.stiffness.max(self.y.stiffness),
            4.0 * self.damping,
        )
    }

    /// `true` when at least one axis is preloaded (`D_x > 0` or `D_y > 0`).
    pub fn has_preload(&self) -> bool {
        self.x.preload > 0.0 || self.y.preload > 0.0
    }

    /// Elastic energy `E(s) = e_x(s_x) + e_y(s_y)` (see [`RingAxis::energy`]).
    pub fn energy(&self, s: &Vector2<f64>) -> f64 {
        self.x.energy(s.x) + self.y.energy(s.y)
    }

    /// Elastic force `g(s) = grad E(s) = (g_x(s_x), g_y(s_y))` (see [`RingAxis::elastic_force`]).
    pub fn elastic_force(&self, s: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(self.x.elastic_force(s.x), self.y.elastic_force(s.y))
    }

    /// Diagonal of the elastic stiffness matrix `g'(s)`: `2K` inside, `K` beyond the preload.
    pub fn elastic_slopes(&self, s: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(self.x.elastic_slope(s.x), self.y.elastic_slope(s.y))
    }

    /// Diagonal of the damping matrix `C(s)`: `4 nu2` inside, `2 nu2` beyond the preload.
    pub fn damping_coefficients(&self, s: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(
            self.x.damping_coefficient(s.x, self.damping),
            self.y.damping_coefficient(s.y, self.damping),
        )
    }

    /// Total force of the ring `f = g(s) + C(s) s'` at position `s` and velocity `s_dot`.
    pub fn force(&self, s: &Vector2<f64>, s_dot: &Vector2<f64>) -> Vector2<f64> {
        let c = self.damping_coefficients(s);
        self.elastic_force(s) + c.component_mul(s_dot)
    }

    /// The contact regime (II..V) of a ring at `s`, from the preload predicates of its axes:
    /// II both inside, III `x` beyond, IV `y` beyond, V both beyond. (An axis with zero preload
    /// is always beyond.)
    pub fn regime_of_ring(&self, s: &Vector2<f64>) -> Regime {
        Regime::from_beyond(!self.x.is_inside(s.x), !self.y.is_inside(s.y))
    }

    /// Relaxation time constants `(T_x, T_y)`, `T_i = 2 nu2 / K_i`, of the free ring.
    pub fn relaxation_time(&self) -> Vector2<f64> {
        Vector2::new(
            2.0 * self.damping / self.x.stiffness,
            2.0 * self.damping / self.y.stiffness,
        )
    }
}
