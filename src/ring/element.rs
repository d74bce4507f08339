use std::cell::RefCell;

use nalgebra::Vector2;

use super::{Branch, Branches, Regime, Relaxation, RingContact, RingError, SnubberRing};
use crate::numeric::Direction;

/// The station's acceleration $r^{\prime\prime}$ given the ring's force $f$ on the rotor
/// ([`SnubberRing::guard_values_with`]): a rotor's right-hand side at one point, as a
/// function of the one force it cannot know before the ring is located.
pub type AccelOfForce<'a> = &'a dyn Fn(&Vector2<f64>) -> Vector2<f64>;

/// Relative distance inside the gap circle within which a touch still counts as a touch of the
/// circle itself (the onset time is located to rounding): the contact branches' smooth
/// extension covers that hair. Farther inside, a touch by a relaxing ring leaves the ring at its
/// centre. The tolerance also grows with the rounding of time: $4\varepsilon|t|\thinspace|r^\prime|$.
pub const ONSET_TOUCH: f64 = 1e-12;

/// Relative distance to its preload within which the other axis counts as crossing at the same
/// time as the axis whose guard fired (a corner of the regime map), or a starting contact takes
/// the branch it moves into.
pub(crate) const CORNER_TOL: f64 = 1e-10;

/// Time, relative to $\max(|t|, 1)$, within which a ring moving towards its preload counts as
/// on it: more than the resolution of an event located at $t$ and of the start-of-segment
/// window of [`ode`, Events](crate::ode#events) ($8\varepsilon\max(|t|, |t_\text{end}|)$, for steps up
/// to $7\max(|t|, 1)$ long). A preload guard closer to zero than its rate times that window
/// at a mode's start, moving towards it, would be taken for the zero at the start time.
const PRELOAD_TIME_TOL: f64 = 64.0 * f64::EPSILON;

/// The rotor's displacement and velocity at the ring's station, relative to the ring's rest
/// centre (in the ring's non-dimensional units: lengths over the gap of the paper's scaling, or
/// whatever unit [`SnubberRing::gap`] is given in).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    /// Displacement $r$.
    pub r: Vector2<f64>,
    /// Velocity $r^\prime$.
    pub v: Vector2<f64>,
}

impl Kinematics {
    /// From displacement `(x, y)` and velocity `(vx, vy)`.
    pub fn new(r: [f64; 2], v: [f64; 2]) -> Self {
        Self {
            r: Vector2::new(r[0], r[1]),
            v: Vector2::new(v[0], v[1]),
        }
    }
}

/// The ring's mode between two events.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub enum RingMode {
    /// Regime I: no contact; the ring relaxes from `relax`.
    Free {
        /// Where the relaxation started.
        relax: Relaxation,
        /// The ring and the rotor touch at the start and part (right after a loss or a touch
        /// that did not start contact): the onset guard must not fire at the start.
        separating: bool,
        /// How far $h = |r - s|^2 - \gamma^2$ must rise above zero before the onset guard
        /// fires: zero, unless the free flight starts touching the ring ($h$ within its
        /// rounding of zero, [`SnubberRing::onset_margin`]). There the onset guard is
        /// $h - m$, which starts clearly negative, so that a rotor that curves back into the
        /// ring (the zero-force slide) or was released a hair inside it is caught by an event
        /// detector's sign change, at a penetration of at most $m$; a guard on zero at the
        /// start would be taken for the zero at the start time
        /// ([`ode`, Events](crate::ode#events), start-of-segment rule 3).
        onset_margin: f64,
    },
    /// Contact on these branches (regimes II..V).
    Contact(Branches),
}

impl RingMode {
    /// Free flight with the ring relaxing from `relax`, not separating.
    pub fn free(relax: Relaxation) -> Self {
        RingMode::Free {
            relax,
            separating: false,
            onset_margin: 0.0,
        }
    }

    /// Whether the mode is a contact mode.
    pub fn is_contact(&self) -> bool {
        matches!(self, RingMode::Contact(_))
    }

    /// The paper's regime: I in free flight, II..V in contact.
    pub fn regime(&self) -> Regime {
        match self {
            RingMode::Free { .. } => Regime::I,
            RingMode::Contact(b) => b.regime(),
        }
    }
}

/// An axis of the ring.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Axis {
    /// The horizontal axis.
    X,
    /// The vertical axis.
    Y,
}

impl Axis {
    /// 0 for x, 1 for y.
    pub fn index(self) -> usize {
        match self {
            Axis::X => 0,
            Axis::Y => 1,
        }
    }

    fn other(self) -> Axis {
        match self {
            Axis::X => Axis::Y,
            Axis::Y => Axis::X,
        }
    }
}

/// A guard of the ring: a function of time and the rotor's kinematics whose zero crossing in
/// its [`direction`](RingGuard::direction) ends the current mode.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum RingGuard {
    /// Free flight: $h = |r - s(t)|^2 - \gamma^2$ rises through 0.
    Onset,
    /// Contact: the loss force $\max(N, \lambda)$ falls through 0.
    Loss,
    /// Contact: $|r|^2 - \gamma^2$ falls through 0 (the rotor back at the gap circle).
    Gap,
    /// Contact: the ring reaches the preload of `axis`, going beyond it (`outward`, from the
    /// inner branch: $|s_i| - D_i$ rises through 0) or coming back inside (from the outer
    /// branch on side $\sigma$: $\sigma s_i - D_i$ falls through 0).
    Preload {
        /// The crossing axis.
        axis: Axis,
        /// Going beyond the preload.
        outward: bool,
    },
}

impl RingGuard {
    /// The crossing direction that fires the guard.
    pub const fn direction(self) -> Direction {
        match self {
            RingGuard::Onset => Direction::Rising,
            RingGuard::Loss | RingGuard::Gap => Direction::Falling,
            RingGuard::Preload { outward, .. } => {
                if outward {
                    Direction::Rising
                } else {
                    Direction::Falling
                }
            }
        }
    }

    /// Short name, for event logs.
    pub const fn label(self) -> &'static str {
        match self {
            RingGuard::Onset => "contact onset",
            RingGuard::Loss => "contact loss",
            RingGuard::Gap => "rotor at gap",
            RingGuard::Preload { axis, outward } => match (axis, outward) {
                (Axis::X, true) => "x_s beyond preload",
                (Axis::X, false) => "x_s within preload",
                (Axis::Y, true) => "y_s beyond preload",
                (Axis::Y, false) => "y_s within preload",
            },
        }
    }
}

/// The ring in a mode at one instant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingState {
    /// Ring centre $s$.
    pub s: Vector2<f64>,
    /// Ring velocity $s^\prime$.
    pub s_dot: Vector2<f64>,
    /// Force of the ring on the rotor, $f = g(s) + C s^\prime$ in contact, 0 in free flight: it
    /// enters the rotor's equation as $\ldots + f = $ forcing.
    pub force: Vector2<f64>,
}

/// The outcome of a guard crossing: the next mode and where the ring is now.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingTransition {
    /// The next mode.
    pub mode: RingMode,
    /// The ring's position after the transition (write it into the state's ring components).
    pub s: Vector2<f64>,
}

/// Per-run scratch of the ring: the last contact location, reused when guards and the vector
/// field ask for the same point, and the warm start of the next. Not shared between threads.
#[derive(Debug, Default)]
pub struct RingCache {
    /// The last location and the rotor position `(x, y)` it was made for (its branches are
    /// the contact's). Read in place: a location is large, and copying it on every hit cost as
    /// much as the closed-form location itself.
    last: RefCell<Option<CachedContact>>,
}

#[derive(Debug, Clone, Copy)]
struct CachedContact {
    x: f64,
    y: f64,
    contact: RingContact,
}

impl RingContact {
    /// $\lambda = n\cdot C^{-1} f/(n\cdot C^{-1} n) = 2\mu\gamma + n\cdot r^\prime/(n\cdot C^{-1}n)$:
    /// the normal force the massless ring's own force balance needs to keep contact (module
    /// docs). Equals [`RingContact::normal_force`] for isotropic damping (regimes II and V, or
    /// $\nu_2 = 0$), where it returns exactly that.
    pub fn separation_force(&self, r_dot: &Vector2<f64>) -> f64 {
        if self.damping.x == self.damping.y {
            return self.normal_force(r_dot);
        }
        separation_force(self.damping, self.normal, self.elastic, r_dot)
    }

    /// The loss force $L = \max(N, \lambda)$: contact lasts while it is positive (module docs).
    /// Exactly the paper's $N$ for isotropic damping.
    pub fn loss_force(&self, r_dot: &Vector2<f64>) -> f64 {
        loss_force(
            self.damping,
            self.normal,
            self.elastic,
            self.normal_force(r_dot),
            r_dot,
        )
    }

    /// Rounding level of [`RingContact::loss_force`]: its elastic part $2\mu\gamma$ carries
    /// the rounding of $\mu$ relative to $K + \mu$, its damping part that of $C J r^\prime$.
    fn loss_force_rounding(&self, stiffness: f64, gap: f64, r_dot: &Vector2<f64>) -> f64 {
        let damping = self
            .damping
            .component_mul(&self.ring_velocity(r_dot))
            .norm();
        16.0 * f64::EPSILON * (2.0 * (self.mu.abs() + stiffness) * gap + damping)
    }
}

/// $\lambda = (c_xc_y\thinspace n\cdot r^\prime + c_y n_x g_x + c_x n_y g_y)/(c_y n_x^2 + c_x n_y^2)$
/// for anisotropic damping `c`: the normal force the freed ring's balance needs to keep
/// $n\cdot(r^\prime - s^\prime) = 0$, i.e. (over $n\cdot C^{-1}n$) the rate at which a ring
/// released now would part from the rotor, whatever held it in contact (module docs).
/// Multiplied through by $c_xc_y$: no division by a vanishing damping.
pub(crate) fn separation_force(
    c: Vector2<f64>,
    n: Vector2<f64>,
    g: Vector2<f64>,
    r_dot: &Vector2<f64>,
) -> f64 {
    let (cx, cy) = (c.x, c.y);
    (cx * cy * n.dot(r_dot) + cy * n.x * g.x + cx * n.y * g.y) / (cy * n.x * n.x + cx * n.y * n.y)
}

/// The motion of a contact that the rate of its loss force needs: the normal $n$, the elastic
/// force $g$, the station's velocity $r^\prime$ and acceleration $r^{\prime\prime}$, with the
/// rates $n^\prime$, $g^\prime$.
pub(crate) struct LossMotion {
    pub n: Vector2<f64>,
    pub n_dot: Vector2<f64>,
    pub g: Vector2<f64>,
    pub g_dot: Vector2<f64>,
    pub r_dot: Vector2<f64>,
    pub r_ddot: Vector2<f64>,
}

/// The rate of [`loss_force`] along the motion `m`, given the normal force `normal` and its
/// rate: that rate where the loss force is `normal`, else the rate of $\lambda = P/Q$
/// ([`separation_force`], $P = c_xc_y\thinspace n\cdot r^\prime + c_yn_xg_x + c_xn_yg_y$,
/// $Q = c_yn_x^2 + c_xn_y^2$), $\lambda^\prime = (P^\prime Q - PQ^\prime)/Q^2$.
pub(crate) fn loss_force_rate(c: Vector2<f64>, m: &LossMotion, normal: f64, rate: f64) -> f64 {
    if c.x == c.y || normal >= separation_force(c, m.n, m.g, &m.r_dot) {
        return rate;
    }
    let (cx, cy, n, nd, g, gd) = (c.x, c.y, m.n, m.n_dot, m.g, m.g_dot);
    let p = cx * cy * n.dot(&m.r_dot) + cy * n.x * g.x + cx * n.y * g.y;
    let p_dot = cx * cy * (nd.dot(&m.r_dot) + n.dot(&m.r_ddot))
        + cy * (nd.x * g.x + n.x * gd.x)
        + cx * (nd.y * g.y + n.y * gd.y);
    let q = cy * n.x * n.x + cx * n.y * n.y;
    let q_dot = 2.0 * (cy * n.x * nd.x + cx * n.y * nd.y);
    (p_dot * q - p * q_dot) / (q * q)
}

/// The loss force $\max(N, \lambda)$ from the normal force `normal` $= n\cdot f$: `normal`
/// itself for isotropic damping, where the two agree.
pub(crate) fn loss_force(
    c: Vector2<f64>,
    n: Vector2<f64>,
    g: Vector2<f64>,
    normal: f64,
    r_dot: &Vector2<f64>,
) -> f64 {
    if c.x == c.y {
        return normal;
    }
    normal.max(separation_force(c, n, g, r_dot))
}

impl SnubberRing {
    /// The ring located on `branches` at `r`, reusing the cached location at the same point
    /// and warm-starting from the last one on the same branches.
    ///
    /// # Errors
    /// As [`SnubberRing::locate_on`].
    pub fn contact_on(
        &self,
        branches: Branches,
        r: &Vector2<f64>,
        cache: &RingCache,
    ) -> Result<RingContact, RingError> {
        self.with_contact(branches, r, cache, |c| *c)
    }

    /// Applies `f` to the ring located on `branches` at `r` (as [`SnubberRing::contact_on`],
    /// reading the cached location in place).
    pub(crate) fn with_contact<T>(
        &self,
        branches: Branches,
        r: &Vector2<f64>,
        cache: &RingCache,
        f: impl FnOnce(&RingContact) -> T,
    ) -> Result<T, RingError> {
        let mut last = cache.last.borrow_mut();
        let hint = match &*last {
            Some(c) if c.contact.branches == branches => {
                if c.x == r.x && c.y == r.y {
                    return Ok(f(&c.contact));
                }
                c.contact.mu
            }
            _ => f64::NAN,
        };
        let contact = self.locate_on(r, branches, hint)?;
        let c = last.insert(CachedContact {
            x: r.x,
            y: r.y,
            contact,
        });
        Ok(f(&c.contact))
    }

    /// Number of guards of `mode`: 1 in free flight; in contact loss, gap, and one per
    /// preloaded axis.
    pub fn guard_count(&self, mode: &RingMode) -> usize {
        match mode {
            RingMode::Free { .. } => 1,
            RingMode::Contact(_) => {
                2 + usize::from(self.x.preload > 0.0) + usize::from(self.y.preload > 0.0)
            }
        }
    }

    /// Guard `i` of `mode` (`None` for `i >= guard_count(mode)`), in the order onset (free);
    /// loss, gap, x preload, y preload (contact, preload guards only for preloaded axes).
    pub fn guard(&self, mode: &RingMode, i: usize) -> Option<RingGuard> {
        match mode {
            RingMode::Free { .. } => (i == 0).then_some(RingGuard::Onset),
            RingMode::Contact(b) => match i {
                0 => Some(RingGuard::Loss),
                1 => Some(RingGuard::Gap),
                _ => {
                    let mut k = 2;
                    for (axis, branch, preload) in [
                        (Axis::X, b.x, self.x.preload),
                        (Axis::Y, b.y, self.y.preload),
                    ] {
                        if preload > 0.0 {
                            if k == i {
                                return Some(RingGuard::Preload {
                                    axis,
                                    outward: branch == Branch::Inner,
                                });
                            }
                            k += 1;
                        }
                    }
                    None
                }
            },
        }
    }

    /// Value of `guard` in `mode` at time `t` (NaN when it cannot be evaluated there, e.g. a
    /// contact guard in free flight or a contact mode with no ring placement: ask
    /// [`SnubberRing::try_guard_value`] why).
    pub fn guard_value(
        &self,
        mode: &RingMode,
        guard: RingGuard,
        t: f64,
        k: &Kinematics,
        cache: &RingCache,
    ) -> f64 {
        self.try_guard_value(mode, guard, t, k, cache)
            .unwrap_or(f64::NAN)
    }

    /// Value of `guard` in `mode` at time `t`, or why it has none.
    ///
    /// # Errors
    /// The ring's error when a contact guard cannot place the ring on the mode's branches
    /// ([`SnubberRing::locate_on`]: e.g. [`RingError::InsideGap`] once the rotor is inside the
    /// gap), or [`RingError::NoPlacement`] at the rotor's position for a guard that does not
    /// belong to `mode`.
    pub fn try_guard_value(
        &self,
        mode: &RingMode,
        guard: RingGuard,
        t: f64,
        k: &Kinematics,
        cache: &RingCache,
    ) -> Result<f64, RingError> {
        Ok(match (mode, guard) {
            (
                RingMode::Free {
                    relax,
                    onset_margin,
                    ..
                },
                RingGuard::Onset,
            ) => self.onset_guard(relax, *onset_margin, t, k).0,
            (RingMode::Contact(_), RingGuard::Gap) => self.gap_guard(k).0,
            (RingMode::Contact(b), RingGuard::Loss | RingGuard::Preload { .. }) => {
                self.with_contact(*b, &k.r, cache, |c| self.placed_value(b, guard, c, k))?
            }
            _ => return Err(RingError::NoPlacement { x: k.r.x, y: k.r.y }),
        })
    }

    /// Time derivative of `guard` along the motion, where it needs only $r$ and $r^\prime$
    /// (onset, gap, preload crossings); `None` for the loss guard (it would need $r^{\prime\prime}$) and for
    /// guards that do not belong to `mode`.
    pub fn guard_rate(
        &self,
        mode: &RingMode,
        guard: RingGuard,
        t: f64,
        k: &Kinematics,
        cache: &RingCache,
    ) -> Option<f64> {
        self.rate(mode, guard, t, k, None, cache)
    }

    /// As [`SnubberRing::guard_rate`], and for the loss guard too, given the acceleration
    /// $r^{\prime\prime}$ of the rotor's station ([`SnubberRing::loss_force_derivative`]).
    pub fn guard_rate_with_accel(
        &self,
        mode: &RingMode,
        guard: RingGuard,
        t: f64,
        k: &Kinematics,
        accel: &Vector2<f64>,
        cache: &RingCache,
    ) -> Option<f64> {
        self.rate(mode, guard, t, k, Some(accel), cache)
    }

    /// The rate of `guard` in `mode`: [`SnubberRing::guard_rate_with_accel`] with `accel`,
    /// [`SnubberRing::guard_rate`] without (then `None` for the loss guard).
    fn rate(
        &self,
        mode: &RingMode,
        guard: RingGuard,
        t: f64,
        k: &Kinematics,
        accel: Option<&Vector2<f64>>,
        cache: &RingCache,
    ) -> Option<f64> {
        match (mode, guard) {
            (RingMode::Free { relax, .. }, RingGuard::Onset) => {
                Some(self.onset_guard(relax, 0.0, t, k).1)
            }
            (RingMode::Contact(_), RingGuard::Gap) => Some(self.gap_guard(k).1),
            // Without the acceleration the loss guard has no rate: no ring placement either
            // (it would move the cache's warm start).
            (RingMode::Contact(_), RingGuard::Loss) if accel.is_none() => None,
            (RingMode::Contact(b), RingGuard::Loss | RingGuard::Preload { .. }) => self
                .with_contact(*b, &k.r, cache, |c| self.placed_rate(b, guard, c, k, accel))
                .ok()
                .flatten(),
            _ => None,
        }
    }

    /// The onset guard $h - m = |q|^2 - \gamma^2 - m$, $q = r - s(t)$ with the ring relaxing
    /// from `relax`, and its rate $h^\prime = 2\thinspace q\cdot(r^\prime - s^\prime)$: the one
    /// place where they are written (the guard methods, [`SnubberRing::guard_values`] and
    /// [`SnubberRing::onset_margin`] call it).
    fn onset_guard(&self, relax: &Relaxation, margin: f64, t: f64, k: &Kinematics) -> (f64, f64) {
        let (s, s_dot) = relax.at(self, t);
        let q = k.r - s;
        (
            q.norm_squared() - self.gap * self.gap - margin,
            2.0 * q.dot(&(k.v - s_dot)),
        )
    }

    /// The gap guard $|r|^2 - \gamma^2$ and its rate $2\thinspace r\cdot r^\prime$.
    fn gap_guard(&self, k: &Kinematics) -> (f64, f64) {
        (
            k.r.norm_squared() - self.gap * self.gap,
            2.0 * k.r.dot(&k.v),
        )
    }

    /// Value of a guard that needs the ring's placement `c` on the branches `b`: the loss force,
    /// a preload distance (NaN for the other guards, which need none).
    fn placed_value(&self, b: &Branches, guard: RingGuard, c: &RingContact, k: &Kinematics) -> f64 {
        match guard {
            RingGuard::Loss => c.loss_force(&k.v),
            RingGuard::Preload { axis, .. } => self.preload_distance(b, axis, c.s[axis.index()]),
            _ => f64::NAN,
        }
    }

    /// Rate of a guard that needs the ring's placement `c` on the branches `b`: the loss
    /// force's (only given `accel`), a preload distance's (`None` for the other guards).
    fn placed_rate(
        &self,
        b: &Branches,
        guard: RingGuard,
        c: &RingContact,
        k: &Kinematics,
        accel: Option<&Vector2<f64>>,
    ) -> Option<f64> {
        match guard {
            RingGuard::Loss => accel.map(|a| self.loss_force_derivative(c, &k.v, a)),
            RingGuard::Preload { axis, .. } => {
                let i = axis.index();
                Some(preload_sign(b, axis, c.s[i]) * c.ring_velocity(&k.v)[i])
            }
            _ => None,
        }
    }

    /// Time derivative $\dot L$ of the loss force $L = \max(N, \lambda)$ along the contact
    /// flow on the branches of `c`, for the station's velocity $r^\prime$ (`r_dot`) and
    /// acceleration $r^{\prime\prime}$ (`r_ddot`).
    ///
    /// On fixed branches each axis' elastic force is affine, $g_i(s) = a_i s_i + b_i$
    /// ($a_i = 2K_i$ inner, $K_i$ outer). With $d = r - s$, $A = \operatorname{diag}(a_i + 2\mu)$
    /// and $w = A^{-1}d$, differentiating the Lagrange system $g(s) = 2\mu d$, $|d| = \gamma$
    /// twice gives
    /// $$\dot\mu = \frac{(d - 2\mu w)\cdot r^\prime}{2\thinspace d\cdot w},\qquad
    /// \ddot\mu = \frac{(d - 2\mu w)\cdot r^{\prime\prime} - 4\dot\mu\thinspace w\cdot\dot d +
    /// |\dot d|^2}{2\thinspace d\cdot w},$$
    /// $$\ddot s = A^{-1}(2\mu r^{\prime\prime} + 4\dot\mu\dot d) + 2\ddot\mu\thinspace w,$$
    /// with $\dot s = J r^\prime$ and $\dot d = r^\prime - \dot s$. The force
    /// $f = 2\mu d + C\dot s$ then has $\dot f = 2\dot\mu d + 2\mu\dot d + C\ddot s$,
    /// $\dot N = (\dot d\cdot f + d\cdot\dot f)/\gamma$, and for an anisotropic damping
    /// $\lambda = 2\mu\gamma + c_x c_y P/Q$ with $P = n\cdot r^\prime$,
    /// $Q = c_y n_x^2 + c_x n_y^2$ gives
    /// $\dot\lambda = 2\gamma\dot\mu + c_x c_y(\dot P Q - P\dot Q)/Q^2$. The derivative of the
    /// larger of $N$ and $\lambda$ is returned.
    pub fn loss_force_derivative(
        &self,
        c: &RingContact,
        r_dot: &Vector2<f64>,
        r_ddot: &Vector2<f64>,
    ) -> f64 {
        let gap = self.gap;
        let mu = c.mu;
        let two_mu = 2.0 * mu;
        let d = c.normal * gap;
        let slope = |b: Branch, k: f64| if b.is_outer() { k } else { 2.0 * k };
        let a = Vector2::new(
            slope(c.branches.x, self.x.stiffness),
            slope(c.branches.y, self.y.stiffness),
        );
        let inv_ax = 1.0 / (a.x + two_mu);
        // Equal slopes (uniform branches) need one division: the same bits.
        let inv_ay = if a.y == a.x {
            inv_ax
        } else {
            1.0 / (a.y + two_mu)
        };
        let inv_a = Vector2::new(inv_ax, inv_ay);
        let w = d.component_mul(&inv_a);
        let inv_dw2 = 0.5 / d.dot(&w);
        let u = d - w * two_mu;
        let s_dot = c.ring_velocity(r_dot);
        let d_dot = r_dot - s_dot;
        let mu_dot = u.dot(r_dot) * inv_dw2;
        let mu_ddot =
            (u.dot(r_ddot) - 4.0 * mu_dot * w.dot(&d_dot) + d_dot.norm_squared()) * inv_dw2;
        let s_ddot =
            (r_ddot * two_mu + d_dot * (4.0 * mu_dot)).component_mul(&inv_a) + w * (2.0 * mu_ddot);
        let f = c.elastic + c.damping.component_mul(&s_dot);
        let f_dot = d * (2.0 * mu_dot) + d_dot * two_mu + c.damping.component_mul(&s_ddot);
        let inv_gap = 1.0 / gap;
        let n_dot = (d_dot.dot(&f) + d.dot(&f_dot)) * inv_gap;
        let (cx, cy) = (c.damping.x, c.damping.y);
        if cx == cy || c.normal_force(r_dot) >= c.separation_force(r_dot) {
            return n_dot;
        }
        let n = c.normal;
        let nd = d_dot * inv_gap;
        let p = n.dot(r_dot);
        let q = cy * n.x * n.x + cx * n.y * n.y;
        let p_dot = nd.dot(r_dot) + n.dot(r_ddot);
        let q_dot = 2.0 * (cy * n.x * nd.x + cx * n.y * nd.y);
        2.0 * gap * mu_dot + cx * cy * (p_dot * q - p * q_dot) / (q * q)
    }

    /// Every guard of `mode` at one point, in the order of [`SnubberRing::guard`]: calls
    /// `out(i, value, rate)` for each, with the value of [`SnubberRing::guard_value`] and, if
    /// `accel` is given ($r^{\prime\prime}$ of the station), the rate of
    /// [`SnubberRing::guard_rate_with_accel`] (`None` without it). Bitwise the same numbers as
    /// the one-guard methods (both evaluate the same formulas; `tests/suite/ring/ring_element.rs` checks
    /// it), for one ring location instead of one per guard.
    pub fn guard_values(
        &self,
        mode: &RingMode,
        t: f64,
        k: &Kinematics,
        accel: Option<&Vector2<f64>>,
        cache: &RingCache,
        out: &mut dyn FnMut(usize, f64, Option<f64>),
    ) {
        let given = accel.map(|a| move |_: &Vector2<f64>| *a);
        let accel_of = given.as_ref().map(|f| f as AccelOfForce<'_>);
        self.guard_values_with(mode, t, k, accel_of, cache, out);
    }

    /// As [`SnubberRing::guard_values`], with the station's acceleration $r^{\prime\prime}$
    /// from the ring's force on the rotor: `accel_of(f)`, called at most once a point with the
    /// force $f$ ([`RingContact::force`]) of the contact the guards are evaluated on (rates are
    /// returned when `accel_of` is given). A rotor whose acceleration depends on that force,
    /// every rotor on the ring, so locates the ring once a point for its guards and their
    /// rates, not once for its right-hand side and again for the guards.
    pub fn guard_values_with(
        &self,
        mode: &RingMode,
        t: f64,
        k: &Kinematics,
        accel_of: Option<AccelOfForce<'_>>,
        cache: &RingCache,
        out: &mut dyn FnMut(usize, f64, Option<f64>),
    ) {
        let b = match mode {
            RingMode::Free {
                relax,
                onset_margin,
                ..
            } => {
                let (value, rate) = self.onset_guard(relax, *onset_margin, t, k);
                out(0, value, accel_of.map(|_| rate));
                return;
            }
            RingMode::Contact(b) => b,
        };
        let n = self.guard_count(mode);
        let gap = self.gap_guard(k);
        let with_rates = accel_of.is_some();
        let done = self.with_contact(*b, &k.r, cache, |c| {
            let accel = accel_of.map(|f| f(&c.force(&k.v)));
            for i in 0..n {
                match self.guard(mode, i) {
                    Some(RingGuard::Gap) => out(i, gap.0, with_rates.then_some(gap.1)),
                    Some(guard) => out(
                        i,
                        self.placed_value(b, guard, c, k),
                        accel
                            .as_ref()
                            .and_then(|a| self.placed_rate(b, guard, c, k, Some(a))),
                    ),
                    None => {}
                }
            }
        });
        if done.is_err() {
            // No placement: the contact guards are NaN (the gap guard needs none).
            for i in 0..n {
                if i == 1 {
                    out(1, gap.0, with_rates.then_some(gap.1));
                } else {
                    out(i, f64::NAN, None);
                }
            }
        }
    }

    /// Signed distance of an axis to its preload on the mode's branch: $|s_i| - D_i$ on the inner
    /// branch (negative inside), $\sigma s_i - D_i$ on the outer branch (positive beyond).
    pub(crate) fn preload_distance(&self, b: &Branches, axis: Axis, s: f64) -> f64 {
        let d = self.axis(axis).preload;
        match branch_of(b, axis) {
            Branch::Inner => s.abs() - d,
            Branch::Outer(sigma) => f64::from(sigma) * s - d,
        }
    }

    fn axis(&self, axis: Axis) -> &super::RingAxis {
        match axis {
            Axis::X => &self.x,
            Axis::Y => &self.y,
        }
    }

    /// The ring's position, velocity and force on the rotor in `mode` at time `t`.
    ///
    /// # Errors
    /// In contact, as [`SnubberRing::locate_on`] (no placement on the mode's branches).
    pub fn ring_state(
        &self,
        mode: &RingMode,
        t: f64,
        k: &Kinematics,
        cache: &RingCache,
    ) -> Result<RingState, RingError> {
        match mode {
            RingMode::Free { relax, .. } => {
                let (s, s_dot) = relax.at(self, t);
                Ok(RingState {
                    s,
                    s_dot,
                    force: Vector2::zeros(),
                })
            }
            // Closed form: computed directly (the cache would only cost a copy).
            RingMode::Contact(b) if self.is_uniform(*b) => self.uniform_state(&k.r, &k.v, *b),
            RingMode::Contact(b) => self.with_contact(*b, &k.r, cache, |c| {
                let s_dot = c.ring_velocity(&k.v);
                RingState {
                    s: c.s,
                    s_dot,
                    force: c.elastic + c.damping.component_mul(&s_dot),
                }
            }),
        }
    }

    /// Where the ring is when nothing moves it: the minimiser of its energy over the disk
    /// $|r - s| \le \gamma$, i.e. its centre for $|r| \le \gamma$ and $s^*(r)$ beyond. Use it
    /// to build a consistent initial state.
    ///
    /// # Errors
    /// As [`SnubberRing::locate`] for `|r| > gap` (non-finite `r`, invalid ring).
    pub fn consistent_position(&self, r: &Vector2<f64>) -> Result<Vector2<f64>, RingError> {
        self.validate()?;
        super::check_finite("r.x", r.x)?;
        super::check_finite("r.y", r.y)?;
        if r.norm_squared() <= self.gap * self.gap {
            Ok(Vector2::zeros())
        } else {
            Ok(self.locate(r)?.s)
        }
    }

    /// The mode of a state at time `t` with the ring at `s`: free if the rotor is inside the
    /// ring, contact if it touches it with the ring at its minimum-energy position and a
    /// positive loss force (separating free flight if that force is not positive).
    ///
    /// # Errors
    /// [`RingError::BeyondRing`] if $|r - s| > \gamma$ (by more than $10^{-9}\gamma$),
    /// [`RingError::RingOffMinimum`] if in contact the ring is more than $10^{-8}\gamma$ from
    /// $s^*(r)$, or an error of [`SnubberRing::locate`].
    pub fn initial_mode(
        &self,
        t: f64,
        k: &Kinematics,
        s: &Vector2<f64>,
    ) -> Result<RingMode, RingError> {
        self.validate()?;
        let gap = self.gap;
        let dist = (k.r - s).norm();
        let tol = 1e-9 * gap;
        if !dist.is_finite() {
            super::check_finite("r.x", k.r.x)?;
            super::check_finite("r.y", k.r.y)?;
            super::check_finite("s.x", s.x)?;
            super::check_finite("s.y", s.y)?;
        }
        if dist < gap - tol || (dist <= gap + tol && k.r.norm() <= gap) {
            let relax = self.released(t, *s);
            return Ok(RingMode::Free {
                relax,
                separating: false,
                onset_margin: self.onset_margin(t, k, &relax),
            });
        }
        if dist > gap + tol {
            return Err(RingError::BeyondRing {
                distance: dist,
                gap,
            });
        }
        let c = self.locate(&k.r)?;
        let offset = (c.s - s).norm();
        if offset > 1e-8 * gap {
            return Err(RingError::RingOffMinimum { offset });
        }
        // The load on the branches the contact would start on (an axis on its preload takes
        // the one it moves into, and the damping differs between them).
        let b = self.branches_at_start(t, &c, &k.v);
        let on_b = self.locate_on(&k.r, b, c.mu)?;
        if on_b.loss_force(&k.v) <= 0.0 {
            return Ok(self.release(t, k, c.s).mode);
        }
        Ok(RingMode::Contact(b))
    }

    /// The mode of a run's start, as [`SnubberRing::initial_mode`], with a touch at the start
    /// applied: a free start with the rotor touching the ring ($h$ within its rounding of
    /// zero, [`SnubberRing::onset_margin`]) and moving into it ($h^\prime$ above $10^{-9}$ of
    /// its scale $2|r - s|(|r^\prime| + |s^\prime|)$) starts with the onset, decided by the
    /// touch rule of [`SnubberRing::transition`] (`accel` as there). Use it for a model whose
    /// free flight is integrated: its onset guard would start on zero and leave it rising,
    /// which an event detector takes for the zero at the start time, not an event (an exact
    /// onset search such as [`crate::ring::onset::find_onset`] fires there by itself). Write
    /// the returned position into the state's ring components.
    ///
    /// # Errors
    /// As [`SnubberRing::initial_mode`] and [`SnubberRing::transition`].
    pub fn start_mode(
        &self,
        t: f64,
        k: &Kinematics,
        s: &Vector2<f64>,
        accel: impl Fn(&Vector2<f64>) -> Vector2<f64>,
    ) -> Result<RingTransition, RingError> {
        let mode = self.initial_mode(t, k, s)?;
        if let RingMode::Free {
            relax,
            separating: false,
            onset_margin,
        } = mode
        {
            if onset_margin > 0.0 && self.moves_in(t, k, &relax, &accel) {
                return self.transition(&mode, RingGuard::Onset, t, k, accel);
            }
            return Ok(RingTransition {
                mode,
                s: relax.at(self, t).0,
            });
        }
        let s = match mode {
            RingMode::Contact(b) => self.locate_on(&k.r, b, f64::NAN)?.s,
            RingMode::Free { relax, .. } => relax.s0,
        };
        Ok(RingTransition { mode, s })
    }

    /// Whether a rotor touching the ring relaxing from `relax` at time `t` moves into it:
    /// $h^\prime = 2q\cdot(r^\prime - s^\prime) > 10^{-9}$ of its scale ($q = r - s$), or
    /// at rest relative to the ring (the rate zero to that level) and accelerated into it,
    /// $h^{\prime\prime} = 2|r^\prime - s^\prime|^2 + 2q\cdot r^{\prime\prime} > 0$ (the
    /// ring's own acceleration left out: a touch that finds no load releases the ring anyway).
    /// Such a start crosses the onset margin within the detector's window late in long runs (a
    /// cubic bearing pulling at 1e7 towards a rest position 200 gaps out: 3e-11 at
    /// $t = 1.3\times10^5$): it begins with the touch.
    fn moves_in(
        &self,
        t: f64,
        k: &Kinematics,
        relax: &Relaxation,
        accel: &impl Fn(&Vector2<f64>) -> Vector2<f64>,
    ) -> bool {
        let (s, s_dot) = relax.at(self, t);
        let q = k.r - s;
        let rate = 2.0 * q.dot(&(k.v - s_dot));
        let scale = 2.0 * q.norm() * (k.v.norm() + s_dot.norm());
        let curvature = 2.0 * (k.v - s_dot).norm_squared() + 2.0 * q.dot(&accel(&Vector2::zeros()));
        rate > 1e-9 * scale || (rate >= -1e-9 * scale && curvature > 0.0)
    }

    /// The onset margin of a free flight that starts at time `t` with the rotor at `k` and the
    /// ring relaxing from `relax` ([`RingMode::Free`]). With $h_0 = |r - s|^2 - \gamma^2$, its
    /// rate $h_0^\prime = 2(r - s)\cdot(r^\prime - s^\prime)$, its rounding
    /// $\rho = 16\varepsilon\gamma(|r| + |s| + \gamma)$ and the time resolution
    /// $\tau = 64\varepsilon\max(|t|, 1)$, let $a = \rho + \max(h_0^\prime, 0)\thinspace\tau$.
    /// Where the rotor touches the ring up to $a$ ($h_0 \ge -a$: on it, or arriving within
    /// the time resolution), $m = \max(h_0, 0) + 2a$; else 0. The onset guard $h - m$ then
    /// starts at or below $-2a$: beyond the rounding of $h$ and, for a rotor moving into the
    /// ring, beyond what an event detector's start-of-segment window
    /// ($8\varepsilon\max(|t|, |t_\text{end}|)$ times the rate, for steps up to
    /// $15\max(|t|, 1)$ long) takes for the zero at the start time.
    pub fn onset_margin(&self, t: f64, k: &Kinematics, relax: &Relaxation) -> f64 {
        let (h0, rate) = self.onset_guard(relax, 0.0, t, k);
        let (s, _) = relax.at(self, t);
        let rounding = 16.0 * f64::EPSILON * self.gap * (k.r.norm() + s.norm() + self.gap);
        let a = rounding + rate.max(0.0) * 64.0 * f64::EPSILON * t.abs().max(1.0);
        if h0 >= -a {
            h0.max(0.0) + 2.0 * a
        } else {
            0.0
        }
    }

    /// The relaxation of a ring released at `s` at time `t` (instant with no ring damping). An
    /// axis a hair beyond its preload (within the corner tolerance: rounding of a ring located
    /// on its preload) is put exactly on it: it relaxes inward with both units acting, and the
    /// hair would otherwise run the one-unit law, twice as fast, for a few ulps of time and
    /// touch the rotor again.
    fn released(&self, t: f64, s: Vector2<f64>) -> Relaxation {
        if self.damping == 0.0 {
            return Relaxation::at_rest(t);
        }
        let snap = |s: f64, d: f64| {
            if d > 0.0 && s.abs() > d && s.abs() - d <= CORNER_TOL * d {
                d.copysign(s)
            } else {
                s
            }
        };
        Relaxation {
            t0: t,
            s0: Vector2::new(snap(s.x, self.x.preload), snap(s.y, self.y.preload)),
        }
    }

    /// Whether the ring located as `c` on branches `b` for the rotor at `k` at time `t` lies
    /// on them: each preloaded axis on its preload up to [`CORNER_TOL`] and the rounding of
    /// the located position ($64\varepsilon(|r| + \gamma)$), or on the branch
    /// [`SnubberRing::branch_at`] gives.
    fn branches_hold(&self, t: f64, b: &Branches, c: &RingContact, k: &Kinematics) -> bool {
        let sd = c.ring_velocity(&k.v);
        let rounding = 64.0 * f64::EPSILON * (k.r.norm() + self.gap);
        [Axis::X, Axis::Y].into_iter().all(|axis| {
            let (i, d) = (axis.index(), self.axis(axis).preload);
            let on_preload = (c.s[i].abs() - d).abs() <= CORNER_TOL * d + rounding;
            on_preload
                || self
                    .branch_at(axis, t, c.s[i], sd[i])
                    .is_none_or(|branch| branch == branch_of(b, axis))
        })
    }

    /// The branch of a preloaded `axis` whose ring coordinate is `s`, moving at `rate`, at
    /// time `t` (`None` without a preload); the rule of the module docs, "Preload crossings". On the preload (within [`CORNER_TOL`]) it is the
    /// branch the ring moves into; elsewhere the branch of the position it reaches within the
    /// time resolution, $s + s^\prime\tau$, $\tau$ = [`PRELOAD_TIME_TOL`] $\max(|t|, 1)$: a
    /// preload the ring reaches (or passes, through its centre, to the other side's) within
    /// that time is crossed at `t`, since its guard would start inside an event detector's
    /// start-of-segment window and be taken for the zero at the start time.
    pub(crate) fn branch_at(&self, axis: Axis, t: f64, s: f64, rate: f64) -> Option<Branch> {
        let d = self.axis(axis).preload;
        if d == 0.0 {
            return None;
        }
        let side = |s: f64| {
            if s.abs() > d {
                Branch::Outer(if s >= 0.0 { 1 } else { -1 })
            } else {
                Branch::Inner
            }
        };
        if (s.abs() - d).abs() <= CORNER_TOL * d {
            return Some(if s * rate > 0.0 {
                side(s.signum() * 2.0 * d)
            } else {
                Branch::Inner
            });
        }
        let ahead = s + rate * PRELOAD_TIME_TOL * t.abs().max(1.0);
        Some(side(if ahead.is_finite() { ahead } else { s }))
    }

    /// [`RingError::PreloadBelowResolution`] when a preloaded axis' inner region ($2D_i$) is
    /// narrower than the resolution at which its branch is decided at time `t` for the ring
    /// located as `c` with the rotor at `k` (the rounding of the located position,
    /// $64\varepsilon(|r| + \gamma)$, plus the distance the ring moves in the time resolution,
    /// $|s_i^\prime|\tau$), and the ring is within that resolution of it.
    fn check_resolution(&self, t: f64, c: &RingContact, k: &Kinematics) -> Result<(), RingError> {
        self.check_preload_resolution(t, &k.r, &c.s, &c.ring_velocity(&k.v))
    }

    /// [`RingError::PreloadBelowResolution`] as [`SnubberRing::check_resolution`], for the ring
    /// at `s` moving at `sd` with the rotor at `r` (a contact of any law: the friction's too).
    pub(crate) fn check_preload_resolution(
        &self,
        t: f64,
        r: &Vector2<f64>,
        s: &Vector2<f64>,
        sd: &Vector2<f64>,
    ) -> Result<(), RingError> {
        let rounding = 64.0 * f64::EPSILON * (r.norm() + self.gap);
        let tau = PRELOAD_TIME_TOL * t.abs().max(1.0);
        for (axis, field) in [(Axis::X, "x.preload"), (Axis::Y, "y.preload")] {
            let (i, d) = (axis.index(), self.axis(axis).preload);
            let resolution = rounding + (sd[i] * tau).abs();
            // (A NaN velocity, a ring without damping released at once, fails neither test.)
            if d > 0.0 && 2.0 * d < resolution && s[i].abs() <= d + resolution {
                return Err(RingError::PreloadBelowResolution {
                    field,
                    preload: d,
                    resolution,
                    t,
                });
            }
        }
        Ok(())
    }

    /// Branches of a contact that starts at time `t` at the located ring `c`: an axis on its
    /// preload, or arriving at it within the time resolution, takes the branch its ring
    /// velocity moves into ([`SnubberRing::branch_at`]), since its guard, zero at the start,
    /// would not fire.
    fn branches_at_start(&self, t: f64, c: &RingContact, v: &Vector2<f64>) -> Branches {
        let mut b = c.branches;
        let sd = c.ring_velocity(v);
        for axis in [Axis::X, Axis::Y] {
            let i = axis.index();
            if let Some(branch) = self.branch_at(axis, t, c.s[i], sd[i]) {
                set_branch(&mut b, axis, branch);
            }
        }
        b
    }

    /// The transition after `guard` of `mode` fired at time `t` with the rotor at `k`: the
    /// next mode and the ring's position (module docs for the rules).
    ///
    /// `accel(f)` is the acceleration $r^{\prime\prime}$ of the rotor's station when the ring pushes on the
    /// rotor with the force `f` (entering the rotor's equations as $\ldots + f = $ forcing: for
    /// a unit-mass station, its acceleration without the ring minus `f`). It is used only when a
    /// touch leaves the loss force at zero to rounding, to tell whether the force would rise.
    ///
    /// # Errors
    /// A [`RingError`] when the ring cannot be placed (no solution on the branches, a
    /// non-finite state), or [`RingError::NoPlacement`] for a guard that does not belong to
    /// `mode`.
    pub fn transition(
        &self,
        mode: &RingMode,
        guard: RingGuard,
        t: f64,
        k: &Kinematics,
        accel: impl Fn(&Vector2<f64>) -> Vector2<f64>,
    ) -> Result<RingTransition, RingError> {
        match (mode, guard) {
            (RingMode::Free { .. }, RingGuard::Onset) => self.touch(t, k, accel),
            (RingMode::Contact(b), RingGuard::Loss | RingGuard::Gap) => {
                let c = self.locate_on(&k.r, *b, f64::NAN)?;
                let parted = self.release(t, k, c.s);
                // The gap guard falls through zero only with the rotor moving in: one moving
                // out (or curving out) at its located root was on zero within rounding (a
                // contact that began on the circle, the guard's ulp larger than its motion) or
                // on an integration error. Releasing it as a parting one would let it run into
                // the ring unseen (the onset search skips a separating start): it touches.
                if let (RingGuard::Gap, RingMode::Free { relax, .. }) = (guard, parted.mode)
                    && self.moves_in(t, k, &relax, &accel)
                {
                    return self.touch(t, k, accel);
                }
                Ok(parted)
            }
            (RingMode::Contact(b), RingGuard::Preload { axis, .. }) => {
                let c = self.locate_on(&k.r, *b, f64::NAN)?;
                self.check_resolution(t, &c, k)?;
                let mut next = *b;
                let flip = |branch: Branch, s: f64| match branch {
                    Branch::Inner => Branch::Outer(if s >= 0.0 { 1 } else { -1 }),
                    Branch::Outer(_) => Branch::Inner,
                };
                set_branch(&mut next, axis, flip(branch_of(b, axis), c.s[axis.index()]));
                // The other axis, on the branch it is on within the time resolution: it crosses
                // its preload at the same instant (a corner of the regime map), or has crossed
                // within the resolution of this event (a preload the ring passes in less).
                let other = axis.other();
                let i = other.index();
                let rate = c.ring_velocity(&k.v)[i];
                if let Some(branch) = self.branch_at(other, t, c.s[i], rate) {
                    set_branch(&mut next, other, branch);
                }
                let mut on_next = self.locate_on(&k.r, next, c.mu)?;
                let mut s = c.s;
                if k.r.norm() > self.gap && !self.branches_hold(t, &next, &on_next, k) {
                    // The fired axis itself crossed again within the resolution (through the
                    // ring's centre): start from the minimum-energy position's branches (inside
                    // the gap circle the gap guard ends the contact instead).
                    let g = self.locate(&k.r)?;
                    next = self.branches_at_start(t, &g, &k.v);
                    on_next = self.locate_on(&k.r, next, g.mu)?;
                    s = on_next.s;
                }
                // The damping, hence the loss force, jumps at a preload: contact on the new
                // branches holds only if it still carries load there.
                if on_next.loss_force(&k.v) <= 0.0 {
                    return Ok(self.release(t, k, c.s));
                }
                Ok(RingTransition {
                    mode: RingMode::Contact(next),
                    s,
                })
            }
            _ => Err(RingError::NoPlacement { x: k.r.x, y: k.r.y }),
        }
    }

    /// Free flight from a ring released at `s` with the rotor at `k`: the ring and the rotor
    /// touch and part (a contact law with friction ends its contacts here too).
    pub(crate) fn release(&self, t: f64, k: &Kinematics, s: Vector2<f64>) -> RingTransition {
        let relax = self.released(t, s);
        RingTransition {
            mode: RingMode::Free {
                relax,
                separating: true,
                onset_margin: self.onset_margin(t, k, &relax),
            },
            s: relax.s0,
        }
    }

    /// The onset guard fired: place the ring and decide whether contact starts.
    fn touch(
        &self,
        t: f64,
        k: &Kinematics,
        accel: impl Fn(&Vector2<f64>) -> Vector2<f64>,
    ) -> Result<RingTransition, RingError> {
        let gap = self.gap;
        let rn = k.r.norm();
        // A touch of the gap circle, up to the rounding of the onset time: the rotor moves
        // |r'| ulp(t) per representable time step.
        let touch = (ONSET_TOUCH * gap).max(4.0 * f64::EPSILON * t.abs() * k.v.norm());
        if rn < gap - touch {
            // The relaxing ring met a rotor inside the gap circle: the ring's minimum-energy
            // position, its centre, is within reach.
            let relax = Relaxation::at_rest(t);
            return Ok(RingTransition {
                mode: RingMode::Free {
                    relax,
                    separating: false,
                    onset_margin: self.onset_margin(t, k, &relax),
                },
                s: Vector2::zeros(),
            });
        }
        // Within the touch tolerance of the circle the contact starts from the relaxed ring's
        // branches, whose smooth extension covers the hair inside |r| = gap.
        let b = if rn > gap {
            self.branches_at_start(t, &self.locate(&k.r)?, &k.v)
        } else {
            Branches::of(self, &Vector2::zeros())
        };
        let c = self.locate_on(&k.r, b, f64::NAN)?;
        self.check_resolution(t, &c, k)?;
        let load = c.loss_force(&k.v);
        let stiffness = self.x.stiffness.max(self.y.stiffness);
        // A rotor inside the circle within the touch tolerance has mu < 0 by up to
        // K (gap - |r|)/gap on the smooth extension: the load there is zero to that level too.
        let inside = 2.0 * stiffness * (gap - rn).max(0.0);
        let rounding = c.loss_force_rounding(stiffness, gap, &k.v) + inside;
        let starts =
            load > rounding || (load >= -rounding && self.load_rises(&c, k, &accel, rounding));
        if starts {
            return Ok(RingTransition {
                mode: RingMode::Contact(b),
                s: c.s,
            });
        }
        // No load: the ring stays where contact would put it (the minimiser of its energy over
        // the disk |r - s| <= gap) and the two part, h' = 2 gamma G <= 0.
        Ok(self.release(t, k, if rn > gap { c.s } else { Vector2::zeros() }))
    }

    /// Whether the loss force, zero to rounding at the touch, rises along the contact flow on
    /// `c`'s branches: by the sign of its central difference over the time in which the station
    /// moves $10^{-6}\gamma$ (a relaxed ring touched on the circle without ring damping, or the
    /// end of a sequence of touches without load). Where that difference is itself at the
    /// force's rounding level `rounding` (its first derivative vanishes too: without ring
    /// damping, a rotor at rest on the circle or moving along it) and the second difference is
    /// clearly positive, the force grows from a minimum of zero: it rises.
    fn load_rises(
        &self,
        c: &RingContact,
        k: &Kinematics,
        accel: &impl Fn(&Vector2<f64>) -> Vector2<f64>,
        rounding: f64,
    ) -> bool {
        let a = accel(&c.force(&k.v));
        let scale = k.v.norm().max((a.norm() * self.gap).sqrt());
        let dt = if scale > 0.0 {
            1e-6 * self.gap / scale
        } else {
            1e-6
        };
        let at = |sign: f64| {
            let h = sign * dt;
            let r = k.r + k.v * h + a * (0.5 * h * h);
            let v = k.v + a * h;
            self.locate_on(&r, c.branches, c.mu)
                .map_or(f64::NAN, |c| c.loss_force(&v))
        };
        let (ahead, behind) = (at(1.0), at(-1.0));
        if (ahead - behind).abs() <= 2.0 * rounding
            && ahead + behind - 2.0 * c.loss_force(&k.v) > 4.0 * rounding
        {
            return true;
        }
        ahead > behind
    }
}

/// $\partial g/\partial s_i$ of the preload guard of `axis` on the branches `b` with the ring at
/// `s` on that axis: $\operatorname{sign}(s_i)$ on the inner branch ($|s_i| - D_i$),
/// $\sigma$ on the outer one ($\sigma s_i - D_i$). Its rate and gradient are this times
/// $s_i^\prime$ and $\nabla_r s_i$.
pub(crate) fn preload_sign(b: &Branches, axis: Axis, s: f64) -> f64 {
    match branch_of(b, axis) {
        Branch::Inner => s.signum(),
        Branch::Outer(sigma) => f64::from(sigma),
    }
}

fn branch_of(b: &Branches, axis: Axis) -> Branch {
    match axis {
        Axis::X => b.x,
        Axis::Y => b.y,
    }
}

fn set_branch(b: &mut Branches, axis: Axis, branch: Branch) {
    match axis {
        Axis::X => b.x = branch,
        Axis::Y => b.y = branch,
    }
}
