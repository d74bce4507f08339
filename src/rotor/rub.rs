//! A rotor on the ring with Coulomb friction at the contact (docs/friction.md): the
//! frictionless composition [`RingedRotor`] for free flight and the touch, the ring with
//! friction ([`FrictionRing`]) for the contact, slipping or rolling.

use std::cell::Cell;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Matrix2, OVector, Vector2};

use super::{LinearFreeSegment, RingedRotor, RotorError, SmoothRotor, Spin};

mod linearization;
mod transition;
use crate::hybrid::{Flow, ModelError, RotorModel};
use crate::numeric::Direction;
use crate::ode::JacobianMut;
use crate::ring::{
    loss_force_rate, preload_sign, Axis, Branches, ContactStart, ForceJacobian, FrictionRing,
    Kinematics, LossMotion, RingCache, RingError, RingGuard, RingMode, Slip,
};

/// The mode of a [`RubbingRotor`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum RubMode {
    /// The frictionless composition's mode: free flight (and, without friction, its contact).
    Ring(RingMode),
    /// In contact, the shaft slipping on the ring.
    Slip {
        /// The sense of the slip.
        sense: Slip,
        /// The ring's force-law branches (a preload crossing's event changes them).
        branches: Branches,
    },
    /// In contact, the shaft rolling on the ring: the contact direction was `angle` when the
    /// shaft's angle was `shaft` (at the mode's last event: the roll's start or a preload
    /// crossing), and turns back as the shaft turns,
    /// $\theta = \text{angle} - (a/\gamma)(\varphi - \text{shaft})$.
    Roll {
        /// The contact direction at the mode's last event (the roll's start or a preload crossing).
        angle: f64,
        /// The shaft's angle at that event.
        shaft: f64,
        /// The ring's force-law branches (a preload crossing's event changes them).
        branches: Branches,
    },
}

impl RubMode {
    /// The ring's branches in a contact mode (`None` in the frictionless composition's modes).
    pub fn branches(&self) -> Option<Branches> {
        match *self {
            RubMode::Ring(_) => None,
            RubMode::Slip { branches, .. } | RubMode::Roll { branches, .. } => Some(branches),
        }
    }
}

/// Per-run scratch of a [`RubbingRotor`]: the frictionless ring's, and the slipping ring's
/// last multiplier (its warm start).
#[derive(Debug, Default)]
pub struct RubCache {
    ring: RingCache,
    hint: Cell<f64>,
}

/// Any [`SmoothRotor`] on the ring with Coulomb friction $\mu_f$ between a shaft of radius $a$
/// and the ring (`../shared/MODEL.md`; docs/friction.md). Free flight, the touch and the
/// closed forms are the frictionless [`RingedRotor`]'s; a contact that starts slips forward,
/// slips backward or rolls by the ring's onset rule ([`FrictionRing::start`]) and moves
/// between them at the slip velocity's zero (into rolling) and the friction cone's edge
/// (out of it). With $\mu_f = 0$ every mode and number is the [`RingedRotor`]'s.
///
/// The ring may be preloaded and anisotropic: each contact mode keeps its force-law branches
/// (the smooth extension of its regime) and ends at a preload crossing, as the frictionless
/// contact does, with the ring's position continuous through it.
///
/// The rotor must give its spin ([`SmoothRotor::spin`]): a constant speed, a profile, or a
/// non-ideal drive ([`super::DrivenJeffcott`], [`super::DrivenLinearRotor`]), whose speed
/// equation then takes the rub torque $a\thinspace n\times(-f) = -a\thinspace t\cdot f$
/// ([`SmoothRotor::add_shaft_torque`]; `../shared/MODEL.md`: $-F_t a$), $f$ the ring's force
/// (dampers included), $n$ and $t$ the contact's normal and tangent.
///
/// Its linearisation ([`crate::hybrid::Variational`]: periodic orbits, Floquet multipliers,
/// Lyapunov exponents) goes through slip and roll for an imposed spin (docs/friction.md).
///
/// Mode labels ([`RotorModel::mode_label`]): the ring's 1..5 (regimes), 6 slipping forward,
/// 7 slipping backward, 8 rolling. Guards of a contact mode: loss, gap, the friction guard,
/// then one per preloaded axis (its preload crossing).
#[derive(Debug)]
pub struct RubbingRotor<R> {
    inner: RingedRotor<R>,
    rub: FrictionRing,
    radius: f64,
}

/// Guard indices of the contact modes.
const LOSS: usize = 0;
const GAP: usize = 1;
/// The slip velocity's zero (slipping) or the friction cone's edge (rolling).
const FRICTION: usize = 2;

impl<R: SmoothRotor> RubbingRotor<R>
where
    DefaultAllocator: Allocator<R::Dim>,
{
    /// `inner` with friction coefficient `friction` between the ring and a shaft of radius
    /// `shaft_radius` at the ring (in the ring's length unit).
    ///
    /// # Errors
    /// [`RotorError::Ring`] for a friction coefficient the ring refuses
    /// ([`FrictionRing::new`]); [`RotorError::Friction`] for a shaft radius that is not finite
    /// and positive and, with friction, a rotor without a spin or whose spin is a state that a
    /// torque on the shaft does not accelerate ([`SmoothRotor::add_shaft_torque`]; without
    /// friction every rotor the frictionless composition takes).
    pub fn new(
        inner: RingedRotor<R>,
        friction: f64,
        shaft_radius: f64,
    ) -> Result<Self, RotorError> {
        let bad = |field, value, reason| {
            Err(RotorError::Friction {
                field,
                value,
                reason,
            })
        };
        if !(shaft_radius.is_finite() && shaft_radius > 0.0) {
            return bad("shaft_radius", shaft_radius, "must be finite and > 0");
        }
        let ring = *inner.ring();
        let rub = FrictionRing::new(ring, friction)?;
        if friction == 0.0 {
            // Everything is the frictionless composition's: nothing more to ask.
            return Ok(Self {
                inner,
                rub,
                radius: shaft_radius,
            });
        }
        let rest = inner.zero_state();
        if inner.rotor().spin(0.0, &rest).is_none() {
            return bad(
                "spin",
                f64::NAN,
                "the rotor gives no spin (SmoothRotor::spin)",
            );
        }
        if let Some(i) = inner.rotor().spin_speed_index() {
            // A unit torque must accelerate the spin (a drive that ignores the rub torque
            // would run on as if nothing braked it).
            let mut dy = rest.clone();
            dy.fill(0.0);
            inner.rotor().add_shaft_torque(&rest, 1.0, &mut dy);
            let rate = dy.get(i).copied().unwrap_or(f64::NAN);
            if !(rate.is_finite() && rate > 0.0) {
                return bad(
                    "spin_speed_index",
                    rate,
                    "the spin is a state, but a unit torque on the shaft (SmoothRotor::add_shaft_torque) does not accelerate it",
                );
            }
        }
        Ok(Self {
            inner,
            rub,
            radius: shaft_radius,
        })
    }

    /// The frictionless composition.
    pub fn ringed(&self) -> &RingedRotor<R> {
        &self.inner
    }

    /// The ring with friction.
    pub fn friction_ring(&self) -> &FrictionRing {
        &self.rub
    }

    /// The shaft's radius $a$ at the ring.
    pub fn shaft_radius(&self) -> f64 {
        self.radius
    }

    /// The force of the ring on the rotor at its station in a state `y` of a run at time `t`
    /// with the mode label `label` (a sample's or an event's side): the frictionless
    /// composition's ([`RingedRotor::contact_force`]) for the labels 1 to 5; slipping (6, 7),
    /// $-(g(s) + CJr^\prime)$ with the ring located at the station's $r$; rolling (8),
    /// $-(g(s) + C(r^\prime + \eta a\thinspace t))$ with the contact direction of the ring's
    /// position in `y`. Its part along $t$ is the friction force, the rest the normal force.
    ///
    /// # Errors
    /// [`ModelError::InvalidState`] where the ring has no placement (a state that is not one
    /// of the run's).
    pub fn contact_force(
        &self,
        t: f64,
        y: &OVector<f64, R::Dim>,
        label: u8,
    ) -> Result<Vector2<f64>, ModelError> {
        let invalid = |e: RingError| ModelError::InvalidState {
            t,
            reason: e.to_string(),
        };
        let k = self.station(y);
        let surface = self.radius * self.spin(t, y).speed;
        // The ring's position in `y` gives its branches (on a preload, either: the extensions
        // meet there) and, rolling, the contact direction.
        let s = self.ring_position(y);
        let branches = Branches::of(self.rub.ring(), &s);
        match label {
            6 | 7 => {
                let slip = if label == 6 {
                    Slip::Forward
                } else {
                    Slip::Backward
                };
                let c = self
                    .rub
                    .locate_slipping_on(&k.r, slip, branches, f64::NAN)
                    .map_err(invalid)?;
                Ok(-c.force(&k.v))
            }
            8 => {
                let n: Vector2<f64> = k.r - s;
                let c = self
                    .rub
                    .rolling_on(&k.r, n.y.atan2(n.x), branches)
                    .map_err(invalid)?;
                Ok(-c.force(&k.v, surface))
            }
            _ => self.inner.contact_force(y, label != 1),
        }
    }

    /// The slip velocity $v = (r^\prime - s^\prime)\cdot t + \Omega a$ at the contact in a
    /// state `y` of a run at time `t` with the mode label `label` (MODEL.md: the contact
    /// direction's whirl speed plus the shaft's surface speed; $> 0$ where the shaft's surface
    /// slides forward over the ring): slipping (6, 7) with the ring located at the station's
    /// $r$ and its velocity $s^\prime$ from that location's sensitivity; rolling (8), 0 (the
    /// contact sticks); NaN out of contact (labels 1 to 5: no friction acts). Friction
    /// dissipates $-f_t v \ge 0$ per unit time ($f_t$ the ring's force on the rotor along
    /// $t$, [`RubbingRotor::contact_force`]'s tangential part).
    ///
    /// # Errors
    /// As [`RubbingRotor::contact_force`].
    pub fn slip_velocity(
        &self,
        t: f64,
        y: &OVector<f64, R::Dim>,
        label: u8,
    ) -> Result<f64, ModelError> {
        let slip = match label {
            6 => Slip::Forward,
            7 => Slip::Backward,
            8 => return Ok(0.0),
            _ => return Ok(f64::NAN),
        };
        let k = self.station(y);
        let s = self.ring_position(y);
        let c = self
            .rub
            .locate_slipping_on(&k.r, slip, Branches::of(self.rub.ring(), &s), f64::NAN)
            .map_err(|e| ModelError::InvalidState {
                t,
                reason: e.to_string(),
            })?;
        Ok(c.slip_velocity(&k.v, self.radius * self.spin(t, y).speed))
    }

    fn spin(&self, t: f64, y: &OVector<f64, R::Dim>) -> Spin {
        let nan = Spin {
            speed: f64::NAN,
            angle: f64::NAN,
            accel: f64::NAN,
        };
        self.inner.rotor.spin(t, y).unwrap_or(nan)
    }

    /// The spin's acceleration at `(t, y)` under the field `dy`: the imposed one, or a
    /// state's rate.
    fn spin_accel(&self, t: f64, y: &OVector<f64, R::Dim>, dy: &OVector<f64, R::Dim>) -> f64 {
        match self.inner.rotor.spin_speed_index() {
            Some(i) => dy[i],
            None => self.spin(t, y).accel,
        }
    }

    fn station(&self, y: &OVector<f64, R::Dim>) -> Kinematics {
        self.inner.rotor.station(y)
    }

    /// The ring's position held in the state.
    fn ring_position(&self, y: &OVector<f64, R::Dim>) -> Vector2<f64> {
        let [i, j] = self.inner.rotor.ring_slots();
        Vector2::new(y[i], y[j])
    }

    /// The ring's preload guard `i` (3 and on) of a contact mode on `branches`: the
    /// frictionless contact's guard `i - 1` ([`crate::ring::SnubberRing::guard`]).
    fn preload_guard(&self, branches: Branches, i: usize) -> Option<(Axis, RingGuard)> {
        let guard = self
            .rub
            .ring()
            .guard(&RingMode::Contact(branches), i.checked_sub(1)?)?;
        match guard {
            RingGuard::Preload { axis, .. } => Some((axis, guard)),
            _ => None,
        }
    }

    /// The frictionless composition's mode that stands for `mode` where only its branches
    /// matter (the rate bound, the free segment).
    fn ring_mode(mode: RubMode) -> RingMode {
        match mode {
            RubMode::Ring(m) => m,
            RubMode::Slip { branches, .. } | RubMode::Roll { branches, .. } => {
                RingMode::Contact(branches)
            }
        }
    }

    /// The ring's position, velocity and force on the rotor in a contact mode.
    fn contact(
        &self,
        mode: RubMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        cache: &RubCache,
    ) -> Result<Contact, RingError> {
        let k = self.station(y);
        let spin = self.spin(t, y);
        let surface = self.radius * spin.speed;
        match mode {
            RubMode::Slip { sense, branches } => {
                let c = self
                    .rub
                    .locate_slipping_on(&k.r, sense, branches, cache.hint.get())?;
                cache.hint.set(c.multiplier);
                let s_dot = c.ring_velocity(&k.v);
                Ok(Contact {
                    s: c.s,
                    branches,
                    damping: c.damping,
                    s_dot,
                    force: c.force(&k.v),
                    guards: [
                        c.loss_force(&k.v),
                        k.r.norm_squared() - self.rub.ring().gap.powi(2),
                        sense.sign() * c.slip_velocity(&k.v, surface),
                    ],
                })
            }
            RubMode::Roll {
                angle,
                shaft,
                branches,
            } => {
                let theta = angle - self.radius / self.rub.ring().gap * (spin.angle - shaft);
                let c = self.rub.rolling_on(&k.r, theta, branches)?;
                Ok(Contact {
                    s: c.s,
                    branches,
                    damping: c.damping,
                    s_dot: c.ring_velocity(&k.v, surface),
                    force: c.force(&k.v, surface),
                    guards: [
                        c.loss_force(&k.v, surface),
                        k.r.norm_squared() - self.rub.ring().gap.powi(2),
                        c.stick_margin(self.rub.friction()),
                    ],
                })
            }
            RubMode::Ring(_) => Err(RingError::NoPlacement { x: k.r.x, y: k.r.y }),
        }
    }

    /// The contact mode a contact starts in at `(t, y)` (the ring's onset rule, on `branches`
    /// where given) and the ring's position there.
    fn start(
        &self,
        t: f64,
        y: &OVector<f64, R::Dim>,
        branches: Option<Branches>,
    ) -> Result<(RubMode, Vector2<f64>), RingError> {
        let k = self.station(y);
        let spin = self.spin(t, y);
        let surface = self.radius * spin.speed;
        let start = match branches {
            Some(b) => self.rub.start_on(&k.r, &k.v, surface, b)?,
            None => self.rub.start(&k.r, &k.v, surface)?,
        };
        let (mode, s, s_dot) = match start {
            ContactStart::Slipping(c) => (
                RubMode::Slip {
                    sense: slip_of(c.friction),
                    branches: c.branches,
                },
                c.s,
                c.ring_velocity(&k.v),
            ),
            ContactStart::Rolling(c) => (
                RubMode::Roll {
                    angle: c.angle,
                    shaft: spin.angle,
                    branches: c.branches,
                },
                c.s,
                c.ring_velocity(&k.v, surface),
            ),
        };
        // A preload narrower than the time resolution cannot be resolved (as without friction).
        self.rub
            .ring()
            .check_preload_resolution(t, &k.r, &s, &s_dot)?;
        Ok((mode, s))
    }

    /// The rate of the friction guard of `mode` at `(t, y)`, the rotor's field taken in that
    /// mode.
    fn friction_rate(
        &self,
        mode: RubMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        cache: &RubCache,
    ) -> Result<f64, RingError> {
        let mut dy = y.clone_owned();
        self.rhs(mode, t, y, &mut dy, cache);
        self.guard_rates(mode, t, y, &dy, cache)
            .map(|r| r[FRICTION])
    }

    /// The rates of the loss, gap and friction guards of a contact mode along the flow
    /// (`dy` the field at `y`): from the ring's gradients and the station's acceleration.
    fn guard_rates(
        &self,
        mode: RubMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        dy: &OVector<f64, R::Dim>,
        cache: &RubCache,
    ) -> Result<[f64; 3], RingError> {
        let k = self.station(y);
        let accel = self.station(dy).v;
        let spin = self.spin(t, y);
        let spin_accel = self.spin_accel(t, y, dy);
        let (gap, a) = (self.rub.ring().gap, self.radius);
        let surface = a * spin.speed;
        let gap_rate = 2.0 * k.r.dot(&k.v);
        // G' s' per axis (written out: the rotor's generic dimension confuses inference).
        let g_dot = |b: Branches, s_dot: &Vector2<f64>| -> Vector2<f64> {
            let k = self.rub.ring().branch_slopes(b);
            Vector2::new(k.x * s_dot.x, k.y * s_dot.y)
        };
        match mode {
            RubMode::Slip { sense, branches } => {
                let c = self
                    .rub
                    .locate_slipping_on(&k.r, sense, branches, cache.hint.get())?;
                let (jac, g) = self.rub.slip_rates(&c, &k.v);
                // n . f with n' = (I - J) r'/gamma, then max(n . f, lambda)'s rate.
                let s_dot = c.ring_velocity(&k.v);
                let n_dot = (k.v - s_dot) / gap;
                let normal = c.normal.dot(&jac.force);
                let normal_rate = n_dot.dot(&jac.force)
                    + c.normal.dot(&(jac.position * k.v + jac.velocity * accel));
                let motion = LossMotion {
                    n: c.normal,
                    n_dot,
                    g: c.elastic,
                    g_dot: g_dot(branches, &s_dot),
                    r_dot: k.v,
                    r_ddot: accel,
                };
                let loss = loss_force_rate(c.damping, &motion, normal, normal_rate);
                let v_rate = g.r.dot(&k.v) + g.v.dot(&accel) + a * spin_accel;
                Ok([loss, gap_rate, sense.sign() * v_rate])
            }
            RubMode::Roll {
                angle,
                shaft,
                branches,
            } => {
                let theta = angle - a / gap * (spin.angle - shaft);
                let c = self.rub.rolling_on(&k.r, theta, branches)?;
                let theta_rate = -surface / gap;
                let s_dot: Vector2<f64> = c.ring_velocity(&k.v, surface);
                // f = g(s) + C (r' + eta a t): f' = G' s' + C (r'' + (eta a)' t - eta a n theta').
                let f = c.force(&k.v, surface);
                let w: Vector2<f64> =
                    accel + c.tangent * (a * spin_accel) - c.normal * (surface * theta_rate);
                let g_dot = g_dot(branches, &s_dot);
                let f_rate = Vector2::new(g_dot.x + c.damping.x * w.x, g_dot.y + c.damping.y * w.y);
                let n_dot = c.tangent * theta_rate;
                let normal_rate = n_dot.dot(&f) + c.normal.dot(&f_rate);
                let motion = LossMotion {
                    n: c.normal,
                    n_dot,
                    g: c.elastic,
                    g_dot,
                    r_dot: k.v,
                    r_ddot: accel,
                };
                let loss = loss_force_rate(c.damping, &motion, c.normal.dot(&f), normal_rate);
                let (gr, gtheta) = self.rub.stick_margin_gradient(&c);
                Ok([loss, gap_rate, gr.dot(&k.v) + gtheta * theta_rate])
            }
            RubMode::Ring(_) => Err(RingError::NoPlacement { x: k.r.x, y: k.r.y }),
        }
    }

    /// The value of guard `i` of a contact mode at its ring `c`: loss, gap and friction, then
    /// the preload distances ([`crate::ring::SnubberRing::guard_value`]'s).
    fn guard_of(&self, c: &Contact, i: usize) -> f64 {
        if i <= FRICTION {
            return c.guards[i];
        }
        self.preload_guard(c.branches, i)
            .map_or(f64::NAN, |(axis, _)| {
                let s = c.s[axis.index()];
                self.rub.ring().preload_distance(&c.branches, axis, s)
            })
    }

    /// The rate of a preload guard `i` (3 and on) at the ring `c`: $\pm s_i^\prime$.
    fn preload_rate(&self, c: &Contact, i: usize) -> Option<f64> {
        let (axis, _) = self.preload_guard(c.branches, i)?;
        let k = axis.index();
        Some(preload_sign(&c.branches, axis, c.s[k]) * c.s_dot[k])
    }

    fn write_slots(&self, y: &mut OVector<f64, R::Dim>, s: Vector2<f64>) {
        let [i, j] = self.inner.rotor.ring_slots();
        y[i] = s.x;
        y[j] = s.y;
    }
}

/// The ring in a contact mode.
struct Contact {
    s: Vector2<f64>,
    /// The mode's branches.
    branches: Branches,
    /// The dampers' coefficients on the ring's branches.
    damping: Vector2<f64>,
    s_dot: Vector2<f64>,
    force: Vector2<f64>,
    /// Loss, gap and friction guards.
    guards: [f64; 3],
}

fn slip_of(kappa: f64) -> Slip {
    if kappa < 0.0 {
        Slip::Backward
    } else {
        Slip::Forward
    }
}

fn transition_error(t: f64, e: RingError) -> ModelError {
    ModelError::Transition {
        t,
        reason: e.to_string(),
    }
}

impl<R: SmoothRotor> RotorModel for RubbingRotor<R>
where
    DefaultAllocator: Allocator<R::Dim>,
{
    type Dim = R::Dim;
    type Mode = RubMode;
    type Segment = LinearFreeSegment;
    type Cache = RubCache;

    fn dim(&self) -> R::Dim {
        self.inner.dim()
    }

    fn state_scale(&self) -> OVector<f64, R::Dim> {
        self.inner.state_scale()
    }

    fn error_scale(&self) -> Option<OVector<f64, R::Dim>> {
        self.inner.error_scale()
    }

    fn new_cache(&self) -> RubCache {
        RubCache {
            ring: self.inner.new_cache(),
            hint: Cell::new(f64::NAN),
        }
    }

    fn is_algebraic(&self, i: usize) -> bool {
        self.inner.is_algebraic(i)
    }

    /// The frictionless composition's start, except that with friction a rotor beyond the gap
    /// circle starts in the contact mode of the ring's onset rule (the driver then places the
    /// ring for it).
    fn initial_mode(&self, t: f64, y: &OVector<f64, R::Dim>) -> Result<RubMode, ModelError> {
        let gap = self.rub.ring().gap;
        if self.rub.friction() > 0.0 && self.station(y).r.norm() > gap {
            return self
                .start(t, y, None)
                .map(|(m, _)| m)
                .map_err(|e| ModelError::InvalidState {
                    t,
                    reason: e.to_string(),
                });
        }
        let mode = self.inner.initial_mode(t, y)?;
        if let (RingMode::Contact(b), true) = (mode, self.rub.friction() > 0.0) {
            return self.start(t, y, Some(b)).map(|(m, _)| m).map_err(|e| {
                ModelError::InvalidState {
                    t,
                    reason: e.to_string(),
                }
            });
        }
        Ok(RubMode::Ring(mode))
    }

    fn flow(&self, mode: RubMode) -> Flow {
        match mode {
            RubMode::Ring(m) => self.inner.flow(m),
            _ => Flow::Integrated,
        }
    }

    fn rhs(
        &self,
        mode: RubMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        dy: &mut OVector<f64, R::Dim>,
        cache: &RubCache,
    ) {
        if let RubMode::Ring(m) = mode {
            return self.inner.rhs(m, t, y, dy, &cache.ring);
        }
        self.inner.rotor.rhs(t, y, dy);
        match self.contact(mode, t, y, cache) {
            Ok(c) => {
                self.inner.rotor.add_station_force(y, &-c.force, dy);
                if self.inner.rotor.spin_speed_index().is_some() {
                    // The rub torque a n x (-f) = -a t . f, t = (-n_y, n_x).
                    let n = (self.station(y).r - c.s) / self.rub.ring().gap;
                    let torque = -self.radius * (n.x * c.force.y - n.y * c.force.x);
                    self.inner.rotor.add_shaft_torque(y, torque, dy);
                }
                let [i, j] = self.inner.rotor.ring_slots();
                dy[i] = c.s_dot.x;
                dy[j] = c.s_dot.y;
            }
            Err(_) => dy.fill(f64::NAN),
        }
    }

    fn guard_count(&self, mode: RubMode) -> usize {
        match mode {
            RubMode::Ring(m) => self.inner.guard_count(m),
            // The frictionless contact's loss, gap and preloads, and the friction guard.
            _ => 1 + self.rub.ring().guard_count(&Self::ring_mode(mode)),
        }
    }

    fn guard_direction(&self, mode: RubMode, i: usize) -> Direction {
        match (mode, mode.branches()) {
            (RubMode::Ring(m), _) => self.inner.guard_direction(m, i),
            (_, Some(b)) if i > FRICTION => self
                .preload_guard(b, i)
                .map_or(Direction::Falling, |(_, g)| g.direction()),
            _ => Direction::Falling,
        }
    }

    fn is_contact_onset(&self, mode: RubMode, i: usize) -> bool {
        match mode {
            RubMode::Ring(m) => self.inner.is_contact_onset(m, i),
            _ => false,
        }
    }

    fn guard_value(
        &self,
        mode: RubMode,
        i: usize,
        t: f64,
        y: &OVector<f64, R::Dim>,
        cache: &RubCache,
    ) -> f64 {
        match mode {
            RubMode::Ring(m) => self.inner.guard_value(m, i, t, y, &cache.ring),
            _ => self
                .contact(mode, t, y, cache)
                .map_or(f64::NAN, |c| self.guard_of(&c, i)),
        }
    }

    fn guard_derivative(
        &self,
        mode: RubMode,
        i: usize,
        t: f64,
        y: &OVector<f64, R::Dim>,
        dy: &OVector<f64, R::Dim>,
        cache: &RubCache,
    ) -> Option<f64> {
        match mode {
            RubMode::Ring(m) => self.inner.guard_derivative(m, i, t, y, dy, &cache.ring),
            _ if i > FRICTION => self
                .contact(mode, t, y, cache)
                .ok()
                .and_then(|c| self.preload_rate(&c, i)),
            _ => self.guard_rates(mode, t, y, dy, cache).ok().map(|r| r[i]),
        }
    }

    fn guard_derivative_needs_rhs(&self) -> bool {
        true
    }

    fn guard_derivative_needs_rhs_of(&self, mode: RubMode, i: usize) -> bool {
        match mode {
            RubMode::Ring(m) => self.inner.guard_derivative_needs_rhs_of(m, i),
            // The gap's and the preloads' rates need only the state.
            _ => i == LOSS || i == FRICTION,
        }
    }

    fn guard_values(
        &self,
        mode: RubMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        dy: &OVector<f64, R::Dim>,
        with_rates: bool,
        cache: &RubCache,
        out: &mut dyn FnMut(usize, f64, Option<f64>),
    ) {
        if let RubMode::Ring(m) = mode {
            return self
                .inner
                .guard_values(m, t, y, dy, with_rates, &cache.ring, out);
        }
        let contact = self.contact(mode, t, y, cache).ok();
        let rates = with_rates
            .then(|| self.guard_rates(mode, t, y, dy, cache).ok())
            .flatten();
        for i in 0..self.guard_count(mode) {
            let value = contact.as_ref().map_or(f64::NAN, |c| self.guard_of(c, i));
            let rate = if i <= FRICTION {
                rates.map(|r| r[i])
            } else {
                with_rates
                    .then(|| contact.as_ref().and_then(|c| self.preload_rate(c, i)))
                    .flatten()
            };
            out(i, value, rate);
        }
    }

    fn guard_error(
        &self,
        mode: RubMode,
        i: usize,
        t: f64,
        y: &OVector<f64, R::Dim>,
        cache: &RubCache,
    ) -> ModelError {
        match mode {
            RubMode::Ring(m) => self.inner.guard_error(m, i, t, y, &cache.ring),
            _ => match self.contact(mode, t, y, cache) {
                Err(e) => ModelError::InvalidState {
                    t,
                    reason: e.to_string(),
                },
                Ok(_) => ModelError::InvalidState {
                    t,
                    reason: format!("guard {i} of the friction contact returned NaN"),
                },
            },
        }
    }

    fn guard_label(&self, mode: RubMode, i: usize) -> &'static str {
        match (mode, i) {
            (RubMode::Ring(m), _) => self.inner.guard_label(m, i),
            (_, LOSS) => "contact loss",
            (_, GAP) => "rotor at gap",
            (RubMode::Slip { .. }, FRICTION) => "slip velocity zero",
            (RubMode::Roll { .. }, FRICTION) => "friction cone's edge",
            (RubMode::Slip { branches, .. } | RubMode::Roll { branches, .. }, _) => self
                .preload_guard(branches, i)
                .map_or("no such guard", |(_, g)| g.label()),
        }
    }

    fn transition(
        &self,
        mode: RubMode,
        guard: usize,
        t: f64,
        y: &mut OVector<f64, R::Dim>,
    ) -> Result<RubMode, ModelError> {
        match (mode, guard) {
            (RubMode::Ring(m), _) => {
                let next = self.inner.transition(m, guard, t, y)?;
                let RingMode::Contact(b) = next else {
                    return Ok(RubMode::Ring(next));
                };
                if self.rub.friction() == 0.0 {
                    return Ok(RubMode::Ring(next));
                }
                let (mode, s) = self
                    .start(t, y, Some(b))
                    .map_err(|e| transition_error(t, e))?;
                self.write_slots(y, s);
                Ok(mode)
            }
            (_, LOSS | GAP) => self.release(mode, t, y),
            (RubMode::Slip { sense, branches }, FRICTION) => self.stop(sense, branches, t, y),
            (RubMode::Roll { .. }, FRICTION) => self.slide(mode, t, y),
            _ => self.cross(mode, guard, t, y),
        }
    }

    fn start_segment(&self, mode: RubMode, t: f64, y: &OVector<f64, R::Dim>) -> LinearFreeSegment {
        // Never started for a contact mode (integrated).
        self.inner.start_segment(Self::ring_mode(mode), t, y)
    }

    fn project(&self, mode: RubMode, t: f64, y: &mut OVector<f64, R::Dim>, cache: &RubCache) {
        match mode {
            RubMode::Ring(m) => self.inner.project(m, t, y, &cache.ring),
            _ => {
                if let Ok(c) = self.contact(mode, t, y, cache) {
                    self.write_slots(y, c.s);
                }
            }
        }
    }

    fn mode_label(&self, mode: RubMode) -> u8 {
        match mode {
            RubMode::Ring(m) => self.inner.mode_label(m),
            RubMode::Slip {
                sense: Slip::Forward,
                ..
            } => 6,
            RubMode::Slip {
                sense: Slip::Backward,
                ..
            } => 7,
            RubMode::Roll { .. } => 8,
        }
    }

    fn forcing_period(&self) -> f64 {
        self.inner.forcing_period()
    }

    fn strobe_time(&self, k: u64) -> f64 {
        self.inner.strobe_time(k)
    }

    fn strobe_phase(&self, k: u64) -> Option<(usize, f64)> {
        self.inner.strobe_phase(k)
    }

    fn max_rate(&self, mode: RubMode, t: f64, y: &OVector<f64, R::Dim>) -> Option<f64> {
        self.inner.max_rate(Self::ring_mode(mode), t, y)
    }

    /// The frictionless composition's in its modes; in contact the rotor's Jacobian with the
    /// ring force's: slipping, [`FrictionRing::slip_force_jacobian`]; rolling,
    /// $\partial F/\partial r = G^\prime$ and $\partial F/\partial v = C$ (the contact direction
    /// follows the shaft, not the rotor). In contact on a non-ideal drive (the rub torque's
    /// and the rolling direction's dependence on the spin's state are not written out), `false`:
    /// finite differences.
    fn jacobian(
        &self,
        mode: RubMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        jac: &mut JacobianMut<'_, R::Dim>,
        cache: &RubCache,
    ) -> bool {
        let k = self.station(y);
        let force = match mode {
            RubMode::Ring(m) => return self.inner.jacobian(m, t, y, jac, &cache.ring),
            _ if self.inner.rotor.spin_speed_index().is_some() => return false,
            RubMode::Slip { sense, branches } => {
                match self
                    .rub
                    .locate_slipping_on(&k.r, sense, branches, cache.hint.get())
                {
                    Ok(c) => self.rub.slip_force_jacobian(&c, &k.v),
                    Err(_) => return false,
                }
            }
            RubMode::Roll { branches, .. } => {
                let Ok(c) = self.contact(mode, t, y, cache) else {
                    return false;
                };
                ForceJacobian {
                    position: Matrix2::from_diagonal(&self.rub.ring().branch_slopes(branches)),
                    velocity: Matrix2::from_diagonal(&c.damping),
                    force: c.force,
                }
            }
        };
        if !self.inner.rotor.jacobian(t, y, Some(&force), jac) {
            return false;
        }
        for i in self.inner.rotor.ring_slots() {
            jac.row_mut(i).fill(0.0);
        }
        true
    }

    fn linear_part(&self) -> Option<&crate::ode::DiagonalLinearPart> {
        self.inner.linear_part()
    }

    fn second_order(&self) -> Option<usize> {
        self.inner.second_order()
    }

    fn diagonal_springs(&self) -> Option<crate::ode::DiagonalSprings<'_>> {
        self.inner.diagonal_springs()
    }
}
