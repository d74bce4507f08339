//! Your rotor on the snubber ring: a smooth rotor model of any size, composed with the ring's
//! contact element ([`crate::ring`]) into a piecewise-smooth [`RotorModel`] that the driver
//! ([`crate::hybrid::simulate`]) and every analysis ([`crate::analysis`]) run.
//!
//! A rotordynamics code describes its rotor without contact, [`SmoothRotor`]: its vector field,
//! the displacement and velocity of the station where the ring sits, how a force at that
//! station enters the equations, and two slots of the state for the ring's position.
//! [`RingedRotor`] adds the ring: its modes, guards, transitions and force, with the contact
//! rules of [`crate::ring`] (acceptance of a touch, the loss force, preload crossings, the
//! corner, the relaxation after loss). The model author cannot get those rules wrong because
//! they do not write them.
//!
//! Free flight is integrated (the rotor's own vector field may be non-linear); the ring's
//! relaxation after a loss is known in closed form and enters only the onset guard. The ring's
//! two state components are *algebraic*: the composition sets them (relaxing ring in free
//! flight, $s^*(r)$ in contact) and excludes them from error control.
//!
//! # Example: a Jeffcott rotor with a cubic bearing, on the ring
//!
//! The state is `[x, y, x', y', x_s, y_s]`; the station is the rotor itself (unit mass); the
//! ring is the paper's Fig. 8a ring. Everything else (contact, loss, preloads, relaxation) comes
//! from the ring.
//!
//! ```
//! use jeffcott::analysis::orbit::strobe_orbit;
//! use jeffcott::hybrid::SimOptions;
//! use jeffcott::nalgebra::{SVector, Vector2, U6};
//! use jeffcott::ring::{Kinematics, SnubberRing};
//! use jeffcott::rotor::{RingedRotor, SmoothRotor};
//!
//! struct CubicRotor {
//!     eta: f64,
//!     k3: f64,
//! }
//!
//! impl SmoothRotor for CubicRotor {
//!     type Dim = U6;
//!     fn dim(&self) -> U6 {
//!         U6
//!     }
//!     fn rhs(&self, t: f64, y: &SVector<f64, 6>, dy: &mut SVector<f64, 6>) {
//!         let (ux, uy) = (y[0] - 0.9, y[1]); // rest position e = (0.9, 0)
//!         let cubic = self.k3 * (ux * ux + uy * uy);
//!         let b = 0.119 * self.eta * self.eta; // out-of-balance beta eta^2
//!         let (sin, cos) = (self.eta * t).sin_cos();
//!         dy[0] = y[2];
//!         dy[1] = y[3];
//!         dy[2] = b * cos - 0.25 * y[2] - ux - cubic * ux;
//!         dy[3] = b * sin - 0.25 * y[3] - uy - cubic * uy;
//!     }
//!     fn station(&self, y: &SVector<f64, 6>) -> Kinematics {
//!         Kinematics::new([y[0], y[1]], [y[2], y[3]])
//!     }
//!     fn add_station_force(&self, _y: &SVector<f64, 6>, f: &Vector2<f64>, dy: &mut SVector<f64, 6>) {
//!         dy[2] += f.x;
//!         dy[3] += f.y;
//!     }
//!     fn ring_slots(&self) -> [usize; 2] {
//!         [4, 5]
//!     }
//!     fn forcing_period(&self) -> f64 {
//!         std::f64::consts::TAU / self.eta
//!     }
//! }
//!
//! let ring = SnubberRing::isotropic(30.0, 0.0, 0.002)?; // K = 30, no preload, nu2 = 0.002
//! let model = RingedRotor::new(CubicRotor { eta: 2.0, k3: 0.5 }, ring)?;
//! let orbit = strobe_orbit(&model, &SVector::zeros(), 300, 10, &SimOptions::default())?;
//! assert!(orbit.stats.transitions > 0); // the rotor meets the ring
//! println!("{}", orbit.period(&Default::default())?);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector, Vector2};

use crate::hybrid::{Flow, ModelError, NoExactModes, RotorModel};
use crate::ode::Direction;
use crate::ring::{Kinematics, RingCache, RingError, RingGuard, RingMode, SnubberRing};

/// A rotor without the ring: smooth, of state dimension [`SmoothRotor::Dim`] (fixed, e.g.
/// `U6`, or `Dyn` for a size known at run time), with one station where the ring acts. The
/// state holds the rotor's coordinates and velocities in any order the model likes, plus two
/// components reserved for the ring's position ([`SmoothRotor::ring_slots`]).
pub trait SmoothRotor
where
    DefaultAllocator: Allocator<Self::Dim>,
{
    /// The state's dimension type.
    type Dim: Dim;

    /// The state's dimension (the ring's two slots included).
    fn dim(&self) -> Self::Dim;

    /// The rotor's vector field without contact, $y^\prime = f(t, y)$. Write every component
    /// except the two ring slots (the composition writes those).
    fn rhs(&self, t: f64, y: &OVector<f64, Self::Dim>, dy: &mut OVector<f64, Self::Dim>);

    /// Displacement and velocity of the rotor at the ring's station, relative to the ring's rest
    /// centre, in units of the ring's gap. Must be linear in `y` (positions and velocities are
    /// components or fixed combinations of components): applied to $y^\prime$ it then gives the
    /// station's velocity and acceleration, which the ring's acceptance test uses.
    fn station(&self, y: &OVector<f64, Self::Dim>) -> Kinematics;

    /// Adds to `dy` the effect of the force `force` acting on the rotor at the station (for a
    /// lumped station of mass $m$ whose velocities are `y[i]`, `y[j]`: `dy[i] += force.x / m`,
    /// `dy[j] += force.y / m`; for a modal model, the modal forces $\Phi_s^{\mathsf T}$ `force`
    /// divided by the modal masses).
    fn add_station_force(
        &self,
        y: &OVector<f64, Self::Dim>,
        force: &Vector2<f64>,
        dy: &mut OVector<f64, Self::Dim>,
    );

    /// Indices of the ring's position $(x_s, y_s)$ in the state.
    fn ring_slots(&self) -> [usize; 2];

    /// The forcing period (stroboscopic sampling and the chattering window use it; an unforced
    /// rotor gives a characteristic period, e.g. that of its first mode).
    fn forcing_period(&self) -> f64;

    /// An upper bound of the rates of the rotor's motion at `(t, y)` with a spring of
    /// stiffness `stiffness` and a damper of coefficient `damping` acting at the station (both
    /// 0 in free flight; in contact the ring's [`SnubberRing::contact_bounds`]), if known: for
    /// a unit-mass station of stiffness $k_0$ and damping $c_0$,
    /// $\sqrt{k_0 + k} + c_0 + c$. [`RingedRotor`] passes it on as
    /// [`RotorModel::max_rate`], which flags fixed steps that do not resolve the motion.
    /// Default: `None`.
    fn max_rate(
        &self,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        stiffness: f64,
        damping: f64,
    ) -> Option<f64> {
        let _ = (t, y, stiffness, damping);
        None
    }
}

/// A [`SmoothRotor`] with the snubber ring at its station: a [`RotorModel`] whose modes are the
/// ring's ([`RingMode`]) and whose guards and transitions are the ring's contact rules.
#[derive(Debug, Clone, PartialEq)]
pub struct RingedRotor<R> {
    rotor: R,
    ring: SnubberRing,
}

impl<R> RingedRotor<R> {
    /// Composes `rotor` with `ring`.
    ///
    /// # Errors
    /// The ring's [`RingError`] if its parameters are invalid.
    pub fn new(rotor: R, ring: SnubberRing) -> Result<Self, RingError> {
        ring.validate()?;
        Ok(Self { rotor, ring })
    }

    /// The rotor.
    pub fn rotor(&self) -> &R {
        &self.rotor
    }

    /// The ring.
    pub fn ring(&self) -> &SnubberRing {
        &self.ring
    }
}

impl<R> RingedRotor<R> {
    /// Makes a state consistent: writes the ring's position for the rotor's station into the
    /// ring slots (its centre out of contact, $s^*(r)$ in contact:
    /// [`SnubberRing::consistent_position`]).
    ///
    /// # Errors
    /// [`ModelError::InvalidState`] for a non-finite station position.
    pub fn make_consistent(&self, y: &mut OVector<f64, R::Dim>) -> Result<(), ModelError>
    where
        R: SmoothRotor,
        DefaultAllocator: Allocator<R::Dim>,
    {
        let k = self.rotor.station(y);
        let s = self
            .ring
            .consistent_position(&k.r)
            .map_err(|e| ModelError::InvalidState {
                t: 0.0,
                reason: e.to_string(),
            })?;
        let [i, j] = self.rotor.ring_slots();
        y[i] = s.x;
        y[j] = s.y;
        Ok(())
    }

    /// The station's acceleration under a ring force `f`, from the rotor's own equations (the
    /// station map is linear, so it maps $y^\prime$ to the station's acceleration). Asked for
    /// only at a touch whose load is zero to rounding: the allocation is rare.
    fn station_accel(&self, t: f64, y: &OVector<f64, R::Dim>, f: &Vector2<f64>) -> Vector2<f64>
    where
        R: SmoothRotor,
        DefaultAllocator: Allocator<R::Dim>,
    {
        let mut dy = y.clone_owned();
        self.rotor.rhs(t, y, &mut dy);
        self.rotor.add_station_force(y, &-f, &mut dy);
        self.rotor.station(&dy).v
    }

    fn guard_of(&self, mode: &RingMode, i: usize) -> RingGuard {
        // The driver asks only for guards below `guard_count`.
        self.ring.guard(mode, i).unwrap_or(RingGuard::Onset)
    }
}

impl<R: SmoothRotor> RotorModel for RingedRotor<R>
where
    DefaultAllocator: Allocator<R::Dim>,
{
    type Dim = R::Dim;
    type Mode = RingMode;
    type Segment = NoExactModes;
    type Cache = RingCache;

    fn dim(&self) -> R::Dim {
        self.rotor.dim()
    }

    fn new_cache(&self) -> RingCache {
        RingCache::default()
    }

    /// The ring's two slots: set by the composition, never limiting the step.
    fn is_algebraic(&self, i: usize) -> bool {
        self.rotor.ring_slots().contains(&i)
    }

    /// The ring's [`SnubberRing::start_mode`]: a start touching the ring and moving into it
    /// begins with the touch (the driver then projects the ring onto the mode).
    fn initial_mode(&self, t: f64, y: &OVector<f64, R::Dim>) -> Result<RingMode, ModelError> {
        let [i, j] = self.rotor.ring_slots();
        self.ring
            .start_mode(
                t,
                &self.rotor.station(y),
                &Vector2::new(y[i], y[j]),
                |f: &Vector2<f64>| self.station_accel(t, y, f),
            )
            .map(|next| next.mode)
            .map_err(|e| ModelError::InvalidState {
                t,
                reason: e.to_string(),
            })
    }

    fn flow(&self, _mode: RingMode) -> Flow {
        Flow::Integrated
    }

    fn rhs(
        &self,
        mode: RingMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        dy: &mut OVector<f64, R::Dim>,
        cache: &RingCache,
    ) {
        self.rotor.rhs(t, y, dy);
        let [i, j] = self.rotor.ring_slots();
        match self
            .ring
            .ring_state(&mode, t, &self.rotor.station(y), cache)
        {
            Ok(ring) => {
                self.rotor.add_station_force(y, &-ring.force, dy);
                dy[i] = ring.s_dot.x;
                dy[j] = ring.s_dot.y;
            }
            Err(_) => dy.fill(f64::NAN),
        }
    }

    fn guard_count(&self, mode: RingMode) -> usize {
        self.ring.guard_count(&mode)
    }

    fn guard_direction(&self, mode: RingMode, i: usize) -> Direction {
        self.guard_of(&mode, i).direction()
    }

    fn guard_value(
        &self,
        mode: RingMode,
        i: usize,
        t: f64,
        y: &OVector<f64, R::Dim>,
        cache: &RingCache,
    ) -> f64 {
        let guard = self.guard_of(&mode, i);
        self.ring
            .guard_value(&mode, guard, t, &self.rotor.station(y), cache)
    }

    fn guard_derivative(
        &self,
        mode: RingMode,
        i: usize,
        t: f64,
        y: &OVector<f64, R::Dim>,
        dy: &OVector<f64, R::Dim>,
        cache: &RingCache,
    ) -> Option<f64> {
        let guard = self.guard_of(&mode, i);
        let k = self.rotor.station(y);
        if guard != RingGuard::Loss {
            return self.ring.guard_rate(&mode, guard, t, &k, cache);
        }
        // The station map is linear: applied to y' it gives the station's acceleration.
        let accel = self.rotor.station(dy).v;
        self.ring
            .guard_rate_with_accel(&mode, guard, t, &k, &accel, cache)
    }

    fn guard_derivative_needs_rhs(&self) -> bool {
        // The loss force's rate reads the station's acceleration.
        true
    }

    fn guard_derivative_needs_rhs_of(&self, mode: RingMode, i: usize) -> bool {
        // The other guard rates need only the station's position and velocity.
        self.guard_of(&mode, i) == RingGuard::Loss
    }

    fn guard_values(
        &self,
        mode: RingMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        dy: &OVector<f64, R::Dim>,
        with_rates: bool,
        cache: &RingCache,
        out: &mut dyn FnMut(usize, f64, Option<f64>),
    ) {
        let accel = self.rotor.station(dy).v;
        self.ring.guard_values(
            &mode,
            t,
            &self.rotor.station(y),
            with_rates.then_some(&accel),
            cache,
            out,
        );
    }

    fn guard_label(&self, mode: RingMode, i: usize) -> &'static str {
        self.guard_of(&mode, i).label()
    }

    fn transition(
        &self,
        mode: RingMode,
        guard: usize,
        t: f64,
        y: &mut OVector<f64, R::Dim>,
    ) -> Result<RingMode, ModelError> {
        let at: &OVector<f64, R::Dim> = y;
        let accel = |f: &Vector2<f64>| self.station_accel(t, at, f);
        let next = self
            .ring
            .transition(
                &mode,
                self.guard_of(&mode, guard),
                t,
                &self.rotor.station(y),
                accel,
            )
            .map_err(|e| ModelError::Transition {
                t,
                reason: e.to_string(),
            })?;
        let [i, j] = self.rotor.ring_slots();
        y[i] = next.s.x;
        y[j] = next.s.y;
        Ok(next.mode)
    }

    fn start_segment(&self, _mode: RingMode, _t: f64, _y: &OVector<f64, R::Dim>) -> NoExactModes {
        NoExactModes
    }

    fn project(&self, mode: RingMode, t: f64, y: &mut OVector<f64, R::Dim>, cache: &RingCache) {
        if let Ok(ring) = self
            .ring
            .ring_state(&mode, t, &self.rotor.station(y), cache)
        {
            let [i, j] = self.rotor.ring_slots();
            y[i] = ring.s.x;
            y[j] = ring.s.y;
        }
    }

    fn mode_label(&self, mode: RingMode) -> u8 {
        mode.regime().number()
    }

    fn forcing_period(&self) -> f64 {
        self.rotor.forcing_period()
    }

    fn max_rate(&self, mode: RingMode, t: f64, y: &OVector<f64, R::Dim>) -> Option<f64> {
        let (k, c) = match mode {
            RingMode::Contact(_) => self.ring.contact_bounds(),
            _ => (0.0, 0.0),
        };
        self.rotor.max_rate(t, y, k, c)
    }
}
