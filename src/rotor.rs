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
//! A linear rotor given by its matrices (a finite-element model, e.g. ROSS's export read by
//! [`RotorMatrices`]) needs no hand-written [`SmoothRotor`]: [`LinearSystem`] holds
//! $M$, $C + \Omega G$, $K$ and the unbalance in SI units, [`LinearRotor`] is its
//! [`SmoothRotor`] with the ring at a node ([`LinearRotor`]'s docs write down how the ring in
//! SI units maps onto the paper's non-dimensional ring).
//!
//! Free flight is integrated (the rotor's own vector field may be non-linear); the ring's
//! relaxation after a loss is known in closed form and enters only the onset guard. The ring's
//! two state components are *algebraic*: the composition sets them (relaxing ring in free
//! flight, $s^*(r)$ in contact) and excludes them from error control.
//!
//! **Exact free flight of linear rotors.** A rotor that is linear with constant coefficients
//! and harmonic forcing between contacts (a finite-element rotor at constant speed) can say so
//! ([`SmoothRotor::linear_free_flight`], a [`LinearFreeFlight`]): its free flight is then
//! propagated in closed form (modal decomposition of the state matrix, once per model, and the
//! particular harmonic solution: [`LinearClosedForm`]) and contact onsets are found by the
//! certified search of [`crate::ring::onset`], as in the paper's model. A closed form whose
//! modes are too ill-conditioned is refused ([`RingedRotor::closed_form`] says why) and the
//! free flight integrated.
//!
//! **Onset guarantee.** Contact onsets in integrated free flight are found by the event
//! detector, whose guarantee is relative to the integrated trajectory: every touch of the dense
//! output is found, and whether the exact orbit touches is decided to the trajectory's own
//! error. Measured on a closed-form grazing orbit: with `rtol` $10^{-8}$ to $10^{-12}$, touches
//! and misses by a tenth of `rtol` or more are decided right, shallower ones either way (the
//! paper's model, with closed-form free flight, decides them at any depth; [hybrid.md]).
//!
//! [hybrid.md]: https://docs.rs/crate/jeffcott/latest/source/docs/hybrid.md
//!
//! # Example: a Jeffcott rotor with a cubic bearing, on the ring
//!
//! The state is `[x, y, x', y', x_s, y_s]`; the station is the rotor itself (unit mass); the
//! ring is the paper's Fig. 8a ring. Everything else (contact, loss, preloads, relaxation) comes
//! from the ring.
//!
//! ```
//! use jeffcott::analysis::strobe_orbit;
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

mod bearing_table;
mod drive;
mod drive_linear;
mod exact;
mod linear;
mod linear_profiled;
mod linearization;
mod matrices;
mod modal;
mod reduction;
#[cfg(feature = "mat")]
mod ross;
mod rub;
mod run_up;
mod speed;
mod speed_law;

pub use bearing_table::BearingTable;
pub use drive::{DrivenJeffcott, MotorTorque, ETA, PHASE};
pub use drive_linear::DrivenLinearRotor;
pub use exact::{
    LinearClosedForm, LinearFreeFlight, LinearFreeSegment, LinearSegment, DEFAULT_MAX_CONDITION,
};
pub use linear::{LinearRotor, LinearSystem};
pub use linear_profiled::ProfiledLinearRotor;
pub use matrices::{DofLayout, RotorMatrices};
pub use modal::ModalRotor;
pub use reduction::{CraigBampton, ModeSelection, ResponseError};
pub use rub::{RubCache, RubMode, RubbingRotor};
use run_up::paper_ring;
pub use run_up::ProfiledJeffcott;
pub use speed::{Segment, SpeedProfile};
use std::sync::Arc;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector, Vector2, U1};
use thiserror::Error;

use crate::hybrid::{Flow, ModelError, RotorModel};
use crate::numeric::Direction;
use crate::ode::JacobianMut;
use crate::ring::onset::OnsetScan;
use crate::ring::Relaxation;
use crate::ring::{
    Branches, ForceJacobian, Kinematics, RingCache, RingError, RingGuard, RingMode, SnubberRing,
};

/// The shaft's spin at one instant ([`SmoothRotor::spin`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spin {
    /// The spin speed $\Omega$ (the paper's $\eta$ in its units).
    pub speed: f64,
    /// The shaft's angle $\varphi$, $\varphi^\prime = \Omega$ (any origin: only its changes are
    /// used).
    pub angle: f64,
    /// The spin's acceleration $\Omega^\prime$ where it is imposed (a constant speed, a
    /// profile); NaN where the spin is a state (a non-ideal drive,
    /// [`SmoothRotor::spin_speed_index`]), whose acceleration is the field's component.
    pub accel: f64,
}

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
    /// centre, in the ring's length unit (that of its gap). Must be *affine* in `y`: positions
    /// and velocities are fixed combinations of components, the position plus a constant (the
    /// station's rest position relative to the ring's centre, e.g. an eccentric ring), the
    /// velocity without one. The velocity must be the time derivative of the position under
    /// [`SmoothRotor::rhs`]. The composition relies on this: the station's acceleration is
    /// the velocity part of `station` applied to $y^\prime$, and the stability tools read the
    /// map's coefficients. [`RingedRotor::new`] checks it.
    fn station(&self, y: &OVector<f64, Self::Dim>) -> Kinematics;

    /// Adds to `dy` the effect of the force `force` acting on the rotor at the station (for a
    /// lumped station of mass $m$ whose velocities are `y[i]`, `y[j]`: `dy[i] += force.x / m`,
    /// `dy[j] += force.y / m`; for a modal model, the modal forces $\Phi_s^{\mathsf T}$ `force`
    /// divided by the modal masses). A force must accelerate the station along itself
    /// (positive mass); [`RingedRotor::new`] checks it.
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

    /// The shaft's spin at `(t, y)`: its speed and angle (rad/s and rad, or the model's time
    /// unit), for a contact law that needs the motion of the shaft's surface (friction at the
    /// ring, [`RubbingRotor`]). Default `None`: the rotor does not say, and such a law refuses
    /// it. A rotor whose speed is a state (a non-ideal drive) gives it with
    /// [`SmoothRotor::spin_speed_index`] and takes the contact's torque
    /// ([`SmoothRotor::add_shaft_torque`]).
    fn spin(&self, t: f64, y: &OVector<f64, Self::Dim>) -> Option<Spin> {
        let _ = (t, y);
        None
    }

    /// The index of the spin's speed $\Omega$ in the state where the spin is a state (a
    /// non-ideal drive): its acceleration is then the field's component there, not
    /// [`Spin::accel`], and a torque on the shaft changes it
    /// ([`SmoothRotor::add_shaft_torque`]). Default `None`: the spin is imposed (a constant
    /// speed, a profile), and a torque on the shaft is the drive's to absorb.
    fn spin_speed_index(&self) -> Option<usize> {
        None
    }

    /// Adds to `dy` the effect of a torque `torque` about the shaft's axis, positive in the
    /// spin's sense (the rub torque of friction at the ring, [`RubbingRotor`]), at the state
    /// `y`: for a rotor whose spin is a state ([`SmoothRotor::spin_speed_index`]), its share
    /// of the spin's acceleration and of the accelerations coupled to it. Default: nothing (an
    /// imposed spin; such a rotor must not override it).
    fn add_shaft_torque(
        &self,
        y: &OVector<f64, Self::Dim>,
        torque: f64,
        dy: &mut OVector<f64, Self::Dim>,
    ) {
        let _ = (y, torque, dy);
    }

    /// The time of the stroboscopic output `k` ([`RotorModel::strobe_time`], which
    /// [`RingedRotor`] passes on). Default $kP$, $P$ = [`SmoothRotor::forcing_period`]; a rotor
    /// whose speed varies returns the time its forcing phase has advanced by $2\pi k$ (or a
    /// fraction of it, [`ProfiledJeffcott`]).
    fn strobe_time(&self, k: u64) -> f64 {
        self.forcing_period() * k as f64
    }

    /// The stroboscopic output `k` at a phase in the state ([`RotorModel::strobe_phase`],
    /// which [`RingedRotor`] passes on): `Some((i, φ_k))` for a rotor whose speed is a state
    /// (the driven rotors: the shaft's turns). Default `None`.
    fn strobe_phase(&self, k: u64) -> Option<(usize, f64)> {
        let _ = k;
        None
    }

    /// A typical magnitude of each state component ([`RotorModel::state_scale`]), if the
    /// rotor knows one. Default `None`: [`RingedRotor`] derives it from the ring's gap and the
    /// station map (see [`RingedRotor::state_scale`](RotorModel::state_scale)); override it
    /// for components the station does not see (other modal coordinates) or for other units.
    fn state_scale(&self) -> Option<OVector<f64, Self::Dim>> {
        None
    }

    /// The weight of each component's error in an implicit integrator's error test, if the
    /// rotor chooses one ([`RotorModel::error_scale`], which [`RingedRotor`] passes on): a
    /// RADAU5 run's absolute tolerance of component $i$ is `atol * error_scale[i]` (the
    /// explicit methods keep the state's scale: [`RotorModel::error_scale`] says why).
    /// Default `None`: the state's scale ([`RotorModel::state_scale`]), and every run as
    /// before.
    ///
    /// The choice the crate's models make (the flexible shaft of `examples/flexible_shaft`,
    /// [`LinearRotor`]) counts a velocity by the displacement it stands for. An error
    /// $\delta v$ in the velocity of a mode of natural frequency $\omega_k$ becomes a free
    /// oscillation of displacement amplitude $\delta v/\omega_k$ (the mode's energy norm,
    /// $\tfrac12(\delta v^2 + \omega_k^2\delta q^2)$, over $\tfrac12\omega_k^2$), so the
    /// velocity's weight is its displacement's times $\max(\Omega, \omega_k)$ instead of times the
    /// forcing frequency $\Omega$: a velocity is accurate enough when it is small against its
    /// own steady amplitude $\Omega s_q$ or when the displacement it stands for is small
    /// against $s_q$. A high mode's velocity is then held to the accuracy its displacement
    /// needs, not $\omega_k/\Omega$ times more (a 64-mode shaft: 3 700 times), while the
    /// slow coordinates ($\omega_k \le \Omega$) keep the state's scale. Displacements and
    /// the ring's slots keep their weights (the state's scale for [`LinearRotor`], the gap for
    /// the shaft's modal displacements).
    fn error_scale(&self) -> Option<OVector<f64, Self::Dim>> {
        None
    }

    /// The rotor's free flight in closed form, if it is linear with constant coefficients and
    /// harmonic forcing ([`LinearFreeFlight`]; the state must then be `[q (n), q' (n), x_s,
    /// y_s]`, or the modal coordinates of a [`ModalRotor`]). [`RingedRotor`] then propagates free flight exactly and finds contact onsets by
    /// the certified search of [`crate::ring::onset`] (no touch missed, however shallow),
    /// unless the closed form is refused as ill-conditioned
    /// ([`RingedRotor::closed_form`]). Default `None`: free flight is integrated.
    fn linear_free_flight(&self) -> Option<LinearFreeFlight> {
        None
    }

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

    /// $p$ when the state is `[q (p), q' (p), others]` and [`SmoothRotor::rhs`] writes
    /// `dy[i] = y[p + i]` exactly for $i < p$ (and [`SmoothRotor::add_station_force`] leaves
    /// those rows alone): [`RingedRotor`] passes it on as [`RotorModel::second_order`], with
    /// which [`Radau5`](crate::ode::Radau5) factors matrices of size $N - p$ instead of $N$
    /// ([`OdeSystem::second_order`](crate::ode::OdeSystem::second_order)). The ring's slots
    /// must then be among the others (index $\ge 2p$). Default `None`.
    fn second_order(&self) -> Option<usize> {
        None
    }

    /// The linear part of [`SmoothRotor::rhs`], diagonal in the state's own coordinates
    /// ([`DiagonalLinearPart`](crate::ode::DiagonalLinearPart): a rotor in modal coordinates,
    /// [`ModalRotor`]), with the forcing of `rhs` declared on it if it has one
    /// ([`DiagonalLinearPart::with_forcing`](crate::ode::DiagonalLinearPart::with_forcing):
    /// the unbalance at the spin speed, a constant load), and nothing at the ring's slots.
    /// [`RingedRotor`] passes it on as
    /// [`RotorModel::linear_part`], which the exponential integrator
    /// [`Etd4`](crate::ode::Etd4) needs. Default `None`.
    fn linear_part(&self) -> Option<&crate::ode::DiagonalLinearPart> {
        None
    }

    /// The diagonal springs and dampers of [`SmoothRotor::rhs`] when it is of second order
    /// ([`SmoothRotor::second_order`]) and its coordinates are coupled only through the
    /// station's force (a rotor in real modal coordinates): [`RingedRotor`] passes it on as
    /// [`RotorModel::diagonal_springs`], with which [`Radau5`](crate::ode::Radau5) solves its
    /// Newton systems in $O(N)$ ([`OdeSystem::diagonal_springs`](crate::ode::OdeSystem::diagonal_springs)).
    /// Default `None`.
    fn diagonal_springs(&self) -> Option<crate::ode::DiagonalSprings<'_>> {
        None
    }

    /// The Jacobian of the rotor's field with a force at the station, written into `jac`:
    /// $\partial f/\partial y$ of [`SmoothRotor::rhs`] and, when `contact` is given (the
    /// ring's force $F(r, v)$ differentiated: [`ForceJacobian`]), of the force $-F(r(y), v(y))$
    /// added by [`SmoothRotor::add_station_force`]: $-B(F_r R + F_v V)$ with $B$ the force's
    /// input matrix and $R$, $V$ the station map's position and velocity rows. Every entry
    /// outside the ring slots' rows must be written (the composition writes those). Returns
    /// `false` (the default) for finite differences. [`RingedRotor`] passes it on as
    /// [`RotorModel::jacobian`], which [`Radau5`](crate::ode::Radau5) uses.
    fn jacobian(
        &self,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        contact: Option<&ForceJacobian>,
        jac: &mut JacobianMut<'_, Self::Dim>,
    ) -> bool {
        let _ = (t, y, contact, jac);
        false
    }

    /// The product $J\thinspace V$ of [`SmoothRotor::jacobian`]'s $J$ (with `contact` as
    /// there) and the columns of $V$, written into `out` (every row outside the ring slots'; both
    /// column-major, as many rows as the state, `v` as long as `out`), without
    /// forming $J$: the variational equations $V^\prime = JV$ of a rotor with hundreds of
    /// coordinates, where $J$'s structure (a second-order system's identity block, the
    /// contact's rank-two coupling) makes the product a fraction of the dense one. Returns
    /// `false` (the default, writing nothing): the product is then the dense one of
    /// [`SmoothRotor::jacobian`]'s matrix.
    fn jacobian_product(
        &self,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        contact: Option<&ForceJacobian>,
        v: &[f64],
        out: &mut [f64],
    ) -> bool {
        let _ = (t, y, contact, v, out);
        false
    }
}

/// A [`SmoothRotor`] with the snubber ring at its station: a [`RotorModel`] whose modes are the
/// ring's ([`RingMode`]) and whose guards and transitions are the ring's contact rules.
#[derive(Debug, Clone, PartialEq)]
pub struct RingedRotor<R> {
    rotor: R,
    ring: SnubberRing,
    /// The rotor's free-flight closed form: `None` without one, `Some(Err)` when refused.
    exact: Option<Result<Arc<LinearClosedForm>, RotorError>>,
}

/// A rotor that cannot be put on the ring: the ring's parameters, or a [`SmoothRotor`] method
/// that breaks its contract ([`RingedRotor::new`]). Each variant names the method and the
/// values it gave.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum RotorError {
    /// The ring's parameters are invalid.
    #[error(transparent)]
    Ring(#[from] RingError),
    /// The paper's parameters are invalid (a rotor built from [`Params`](crate::params::Params)).
    #[error(transparent)]
    Params(#[from] crate::params::ParamError),
    /// A speed profile's parameter is invalid ([`SpeedProfile::piecewise`],
    /// [`SpeedProfile::from_fn`]).
    #[error("speed profile: {field} = {value}: {reason}")]
    SpeedProfile {
        /// The parameter (`"eta_from"`, `"eta_to"`, `"rate"`, `"duration"`, a user law's `"end"` or
        /// `"eta"`, `"strobes_per_revolution"`).
        field: &'static str,
        /// Its value.
        value: f64,
        /// What is wrong.
        reason: &'static str,
    },
    /// Friction at the ring cannot be added to this rotor ([`RubbingRotor::new`]): the field,
    /// its value and why.
    #[error("friction at the ring: {field} = {value}: {reason}")]
    Friction {
        /// `"shaft_radius"`, `"spin"` (the rotor gives none), `"x.preload"`, `"y.preload"`.
        field: &'static str,
        /// Its value (NaN where the rotor gives none).
        value: f64,
        /// What is wrong.
        reason: &'static str,
    },
    /// A [`BearingTable`]'s grid point is invalid ([`BearingTable::new`]), or the table does
    /// not fit the system it is given to.
    #[error("bearing table: {field} at grid point {index}: {reason} (value {value})")]
    BearingTable {
        /// `"speeds"`, `"stiffness"` or `"damping"`.
        field: &'static str,
        /// The grid point (0-based).
        index: usize,
        /// The offending value (a speed, an entry, a count or a size, as `reason` says).
        value: f64,
        /// What is wrong.
        reason: &'static str,
    },
    /// The ring's slots are not two distinct components of the state.
    #[error("SmoothRotor::ring_slots is {slots:?} but the state has {dim} components (SmoothRotor::dim): give two distinct indices below {dim}")]
    RingSlots {
        /// The slots returned.
        slots: [usize; 2],
        /// The state's dimension.
        dim: usize,
    },
    /// A method returned a non-finite value at a finite probe state.
    #[error(
        "SmoothRotor::{method} returned {value} at a finite probe state: it must be finite there"
    )]
    NonFinite {
        /// The method (`"station"`, `"add_station_force"`).
        method: &'static str,
        /// The value returned.
        value: f64,
    },
    /// The station's velocity at the zero state is not zero (the velocity has an offset).
    #[error("SmoothRotor::station: at the zero state the velocity is ({}, {}), not zero: the velocity must be a fixed combination of state components without offset (only the position may have one)", velocity[0], velocity[1])]
    StationVelocityOffset {
        /// `station(0).v`.
        velocity: [f64; 2],
    },
    /// The station map is not affine: `station(a x + b z) - station(0)` differs from
    /// `a (station(x) - station(0)) + b (station(z) - station(0))`.
    #[error("SmoothRotor::station is not affine in the state: for a = {a}, b = {b}, station(a x + b z) - station(0) = {got:?} but a (station(x) - station(0)) + b (station(z) - station(0)) = {want:?} (r.x, r.y, v.x, v.y); positions and velocities must be fixed combinations of state components")]
    StationNotAffine {
        /// Coefficient of the first probe state.
        a: f64,
        /// Coefficient of the second probe state.
        b: f64,
        /// `station(a x + b z) - station(0)`, as `[r.x, r.y, v.x, v.y]`.
        got: [f64; 4],
        /// `a (station(x) - station(0)) + b (station(z) - station(0))`.
        want: [f64; 4],
    },
    /// The station's velocity is not the time derivative of its position under the rotor's
    /// field.
    #[error("SmoothRotor::station: at a probe state (t = {t}) the velocity is {velocity:?} but the position's time derivative under SmoothRotor::rhs is {derivative:?}: station(y).v must be d/dt station(y).r (check the velocity's sign and components)")]
    StationVelocity {
        /// The probe's time.
        t: f64,
        /// `station(y).v`.
        velocity: [f64; 2],
        /// `station(rhs(t, y)).r - station(0).r`.
        derivative: [f64; 2],
    },
    /// A rotor's matrices do not have a whole number of nodes ([`RotorMatrices::new`]).
    #[error("the matrices have {dofs} DOFs, not a positive multiple of the layout's {per_node} DOFs a node")]
    DofCount {
        /// Rows of `M`.
        dofs: usize,
        /// DOFs a node of the layout.
        per_node: usize,
    },
    /// A matrix is not square or not of `M`'s size ([`RotorMatrices::new`]), or not of the
    /// full size a [`CraigBampton`] reduction expects.
    #[error(
        "matrix {matrix} is {rows} x {cols}, expected {expected} x {expected} (the size of M)"
    )]
    MatrixShape {
        /// `"M"`, `"C"`, `"G"` or `"K"` (`"D"`: $C + \Omega G$; `"projected"`: the matrix
        /// given to [`CraigBampton::project`]).
        matrix: &'static str,
        /// Its rows.
        rows: usize,
        /// Its columns.
        cols: usize,
        /// Rows of `M`.
        expected: usize,
    },
    /// A matrix entry is not finite ([`RotorMatrices::new`]).
    #[error("matrix {matrix} has the non-finite entry {value} at ({row}, {col})")]
    MatrixEntry {
        /// `"M"`, `"C"`, `"G"` or `"K"`.
        matrix: &'static str,
        /// Row (0-based).
        row: usize,
        /// Column (0-based).
        col: usize,
        /// The entry.
        value: f64,
    },
    /// A lateral DOF is coupled to an axial or torsional one, so the lateral DOFs cannot be
    /// taken alone ([`RotorMatrices::lateral`]).
    #[error("matrix {matrix} couples lateral and axial/torsional DOFs: entry ({row}, {col}) is {value}, not 0")]
    LateralCoupling {
        /// `"M"`, `"C"`, `"G"` or `"K"`.
        matrix: &'static str,
        /// Row (0-based, in the 6-DOF layout).
        row: usize,
        /// Column.
        col: usize,
        /// The entry.
        value: f64,
    },
    /// A node index beyond the rotor's nodes.
    #[error("node {node} is out of range: the rotor has nodes 0 to {}", nodes.saturating_sub(1))]
    NodeOutOfRange {
        /// The node asked for.
        node: usize,
        /// Number of nodes.
        nodes: usize,
    },
    /// A rotor file could not be read.
    #[error("cannot read the rotor file: {0}")]
    Io(std::io::ErrorKind),
    /// A rotor file is not a MATLAB (v5) MAT file.
    #[error("the rotor file is not a MATLAB v5 MAT file (ROSS writes one with rotor.save_mat(file, speed))")]
    NotMatFile,
    /// A MAT file lacks one of ROSS's matrices, or holds it as something else than a real
    /// double 2-D array.
    #[error("the MAT file has no real 2-D double matrix '{key}': not a ROSS export (rotor.save_mat writes M, K, C, G)")]
    MissingMatrix {
        /// The key looked for.
        key: &'static str,
    },
    /// A [`LinearFreeFlight`]'s station does not fit its system (or its offset is not finite).
    #[error("LinearFreeFlight: station {station:?} does not fit the {dofs} coordinates (indices below {dofs}) or its offset is not finite")]
    LinearStation {
        /// The station's coordinates.
        station: [usize; 2],
        /// The number of coordinates.
        dofs: usize,
    },
    /// The eigen-decomposition of a linear rotor's state matrix failed.
    #[error("LinearFreeFlight: the eigen-decomposition of the state matrix failed: {0}")]
    Eigen(crate::numeric::NumericError),
    /// The state matrix's eigenvectors are too ill-conditioned for the closed form (modes
    /// close to coalescing, e.g. near critical damping): the free flight is integrated.
    #[error("LinearFreeFlight: the eigenvector matrix has condition number {condition:e} > {limit:e} (near-defective modes): closed-form free flight refused, free flight is integrated")]
    IllConditionedModes {
        /// $\kappa_1(V)$ (balanced).
        condition: f64,
        /// [`LinearFreeFlight::max_condition`].
        limit: f64,
    },
    /// The eigen-decomposition does not reproduce the state matrix to the required accuracy.
    #[error("LinearFreeFlight: eigenpair residual {residual:e}, reconstruction error {reconstruction:e} (relative; at most 1e-10 accepted): closed-form free flight refused")]
    EigenResidual {
        /// $|AV - V\Lambda| / (|A||V|)$.
        residual: f64,
        /// $|V\Lambda V^{-1} - A| / |A|$.
        reconstruction: f64,
    },
    /// A rotor's [`SmoothRotor::linear_free_flight`] does not fit its state: the state must
    /// be `[q (n), q' (n), x_s, y_s]` with the ring's slots last.
    #[error("SmoothRotor::linear_free_flight has {dofs} coordinates but the state has {dim} components with the ring slots at {slots:?}: it must be [q ({dofs}), q' ({dofs}), x_s, y_s]")]
    LinearLayout {
        /// $n$.
        dofs: usize,
        /// The state's dimension.
        dim: usize,
        /// [`SmoothRotor::ring_slots`].
        slots: [usize; 2],
    },
    /// A linear rotor's closed form would lose the contact to rounding: from rest, its
    /// station is the sum of a forced response and transients that cancel it, each far larger
    /// than the gap (a soft mount's static deflection). Free flight is integrated instead
    /// (the check of [`RingedRotor::new`]).
    #[error("LinearFreeFlight: the closed form's station sums terms of {terms:e} (forced response and transients from rest), whose rounding {rounding:e} is above 1e-10 of the gap {gap:e}: closed-form free flight refused, free flight is integrated")]
    ClosedFormRounding {
        /// The station's sum of magnitudes over a forcing period from rest.
        terms: f64,
        /// Its rounding, $16\epsilon$ times that.
        rounding: f64,
        /// The ring's gap.
        gap: f64,
    },
    /// A rotor's linear closed form disagrees with its own vector field or station.
    #[error("SmoothRotor::linear_free_flight disagrees with SmoothRotor::{method} (t = {t}): component {index} is {closed_form} by the closed form, {rotor} by the rotor (difference {difference:e} above the tolerance {tolerance:e})")]
    LinearMismatch {
        /// `"rhs"` or `"station"`.
        method: &'static str,
        /// The probe's time.
        t: f64,
        /// The component compared.
        index: usize,
        /// The closed form's value.
        closed_form: f64,
        /// The rotor's value.
        rotor: f64,
        /// Their difference.
        difference: f64,
        /// The tolerance.
        tolerance: f64,
    },
    /// The spin speed of a [`LinearSystem`] is not finite and positive.
    #[error("the spin speed must be finite and > 0 rad/s, got {value} (the unbalance rotates at it and it sets the forcing period)")]
    Speed {
        /// The speed given, rad/s.
        value: f64,
    },
    /// A driven rotor's polar inertia is not finite or not above the out-of-balance's share
    /// ([`LinearRotor::with_drive`]).
    #[error("the polar inertia must be finite and above {required} (the out-of-balance's largest b M^-1 b; any physical rotor has more), got {inertia}")]
    Inertia {
        /// The polar inertia given.
        inertia: f64,
        /// $\max_\varphi b\cdot M^{-1}b$.
        required: f64,
    },
    /// A scalar input is not finite.
    #[error("{field} must be finite, got {value}")]
    Parameter {
        /// The input (`"unbalance magnitude"`, `"ring offset x"`, ...).
        field: &'static str,
        /// Its value.
        value: f64,
    },
    /// A coordinate index beyond the system's coordinates.
    #[error("{field} = {index} is out of range: the system has coordinates 0 to {}", dofs.saturating_sub(1))]
    DofOutOfRange {
        /// What the index is for (`"station x"`, `"force dof"`, ...).
        field: &'static str,
        /// The index given.
        index: usize,
        /// Number of coordinates.
        dofs: usize,
    },
    /// The station's x and y are the same coordinate.
    #[error("the station's x and y are both coordinate {index}: give two distinct coordinates")]
    StationCoincident {
        /// The coordinate given twice.
        index: usize,
    },
    /// A force vector is not of the system's size.
    #[error("vector {vector} has {len} entries, expected {expected} (the size of M)")]
    VectorLength {
        /// `"F_hat"` or `"f0"`.
        vector: &'static str,
        /// Its length.
        len: usize,
        /// Rows of `M`.
        expected: usize,
    },
    /// A matrix that must be inverted is singular.
    #[error("{matrix} is singular (LU found a zero pivot): {hint}")]
    Singular {
        /// The matrix (`"M"`, `"K"`, `"K - W^2 M + i W D"`).
        matrix: &'static str,
        /// What to check.
        hint: &'static str,
    },
    /// A force at the station does not accelerate it along the force.
    #[error("SmoothRotor::add_station_force: the force {force:?} at the station changes the station's acceleration by {accel:?}, whose component along the force is {along}, not positive: a force must push the station along itself (dy[velocity] += force / mass)")]
    StationForce {
        /// The force applied.
        force: [f64; 2],
        /// The change of the station's acceleration.
        accel: [f64; 2],
        /// `accel · force / |force|`.
        along: f64,
    },
    /// A boundary DOF given twice ([`CraigBampton::new`]).
    #[error("boundary DOF {dof} is given twice: list each boundary DOF once")]
    DuplicateBoundaryDof {
        /// The DOF repeated.
        dof: usize,
    },
    /// A matrix that must be symmetric is not: the mass matrix `M` ([`LinearSystem::new`],
    /// [`RotorMatrices::new`], [`CraigBampton::new`]). The pair differs by more than
    /// $10^{-10}\sqrt{|M_{ii} M_{jj}|}$ (rounding of an assembled or projected matrix is far
    /// below).
    #[error("matrix {matrix} must be symmetric: entry ({row}, {col}) is {value} but ({col}, {row}) is {transposed}")]
    NotSymmetric {
        /// `"M"`.
        matrix: &'static str,
        /// Row of the first entry found (0-based).
        row: usize,
        /// Its column.
        col: usize,
        /// The entry at (`row`, `col`).
        value: f64,
        /// The entry at (`col`, `row`).
        transposed: f64,
    },
    /// The gyroscopic matrix `G` is not skew-symmetric ($G^{\mathsf T} = -G$: the gyroscopic
    /// moments do no work) ([`RotorMatrices::new`]).
    #[error("matrix G must be skew-symmetric (G^T = -G): entry ({row}, {col}) is {value} but ({col}, {row}) is {transposed}")]
    NotSkewSymmetric {
        /// Row of the first entry found (0-based).
        row: usize,
        /// Its column.
        col: usize,
        /// The entry at (`row`, `col`).
        value: f64,
        /// The entry at (`col`, `row`).
        transposed: f64,
    },
    /// The mass matrix is not positive definite: some motion has no kinetic energy, or a
    /// negative one ([`LinearSystem::new`], [`RotorMatrices::new`], [`CraigBampton::new`]).
    #[error("the mass matrix M must be positive definite: its lowest eigenvalue is {eigenvalue}, its eigenvector largest at DOF {dof} (a DOF without mass, or with a negative one: condense massless DOFs first)")]
    MassNotPositiveDefinite {
        /// The lowest eigenvalue of $M$.
        eigenvalue: f64,
        /// The DOF where that eigenvalue's eigenvector is largest: the DOF to look at.
        dof: usize,
    },
    /// The interior mass of a reduction (the rotor's mass with the boundary DOFs held) is not
    /// positive definite ([`CraigBampton::new`]).
    #[error("the interior mass matrix M_ii (symmetric part) is not positive definite: its lowest eigenvalue is {eigenvalue}; every DOF not on the boundary needs mass (condense massless DOFs first)")]
    InteriorMass {
        /// Lowest eigenvalue of $\tfrac12(M_{ii} + M_{ii}^{\mathsf T})$ (0 if the
        /// factorisation failed on a zero pivot).
        eigenvalue: f64,
    },
    /// The interior stiffness of a reduction does not hold the rotor with the boundary DOFs
    /// fixed: a rigid-body mode or a DOF without stiffness ([`CraigBampton::new`]).
    #[error("the interior stiffness K_ii (symmetric part) is not positive definite with the boundary DOFs held: lowest generalized eigenvalue omega^2 = {eigenvalue} (rad/s)^2; drop DOFs without stiffness to ground (RotorMatrices::lateral drops ROSS's axial and torsional ones) or hold a free rotor at more boundary DOFs")]
    InteriorStiffness {
        /// Lowest eigenvalue $\omega^2$ of $(K_{ii}, M_{ii})$ (symmetric parts).
        eigenvalue: f64,
    },
    /// More fixed-interface modes asked for than the interior has DOFs ([`CraigBampton::new`]).
    #[error("{requested} fixed-interface modes requested but the interior has only {available} DOFs (modes)")]
    ModeCount {
        /// Modes requested.
        requested: usize,
        /// Interior DOFs.
        available: usize,
    },
    /// A reduction that keeps no coordinate: no boundary DOF and no mode ([`CraigBampton::new`]).
    #[error("the reduction keeps no coordinate: give at least one boundary DOF or one mode")]
    EmptyReduction,
    /// A reduction's frequency cut-off is NaN or negative ([`CraigBampton::new`]).
    #[error("mode cut-off {cutoff} rad/s: give a frequency >= 0 (f64::INFINITY keeps all modes)")]
    ModeCutoff {
        /// The cut-off given (rad/s).
        cutoff: f64,
    },
    /// No number of fixed-interface modes brings a reduction's response error within the
    /// tolerance ([`CraigBampton::fewest_modes`]).
    #[error("no number of modes reaches the relative response error {tolerance}: the best is {best} (all modes kept leave rounding only, about the condition number of K - W^2 M + i W D times 1e-16)")]
    ModeTolerance {
        /// The tolerance asked for.
        tolerance: f64,
        /// The smallest worst-over-speeds error reached.
        best: f64,
    },
}

/// Relative tolerance of the station map's affinity (rounding of a fixed combination).
const AFFINE_RTOL: f64 = 1e-8;
/// Relative tolerance of the velocity against the position's derivative.
const VELOCITY_RTOL: f64 = 1e-6;
/// Absolute tolerances, as a fraction of the ring's gap (per unit time for velocities).
const GAP_ATOL: f64 = 1e-12;
/// The largest rounding of a closed form's station accepted, as a fraction of the gap.
const CLOSED_FORM_ROUNDING: f64 = 1e-10;

fn kin4(k: &Kinematics) -> [f64; 4] {
    [k.r.x, k.r.y, k.v.x, k.v.y]
}

fn sub4(a: [f64; 4], b: [f64; 4]) -> [f64; 4] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2], a[3] - b[3]]
}

/// `Err(LinearMismatch)` unless the closed form's `closed_form` and the rotor's `rotor` agree
/// within `tolerance`.
fn linear_agrees(
    method: &'static str,
    t: f64,
    index: usize,
    closed_form: f64,
    rotor: f64,
    tolerance: f64,
) -> Result<(), RotorError> {
    let difference = (closed_form - rotor).abs();
    if difference.is_nan() || difference > tolerance {
        return Err(RotorError::LinearMismatch {
            method,
            t,
            index,
            closed_form,
            rotor,
            difference,
            tolerance,
        });
    }
    Ok(())
}

fn amax(a: &[f64]) -> f64 {
    a.iter().fold(0.0, |m, v| m.max(v.abs()))
}

impl<R: SmoothRotor> RingedRotor<R>
where
    DefaultAllocator: Allocator<R::Dim>,
{
    /// Composes `rotor` with `ring`, after checking the rotor's contract on a few
    /// deterministic probe states (scaled to put the station about half the gap from its rest
    /// position; tolerances relative plus an absolute $10^{-12}$ of the gap):
    ///
    /// * [`SmoothRotor::ring_slots`] are two distinct components of the state;
    /// * [`SmoothRotor::station`] is affine, its velocity without offset (`station(0).v = 0`);
    /// * the station's velocity is the time derivative of its position under
    ///   [`SmoothRotor::rhs`] (to $10^{-6}$ relative), at two times;
    /// * a force at the station ([`SmoothRotor::add_station_force`]) accelerates it with a
    ///   positive component along the force, for forces along both axes and the station's
    ///   radius.
    ///
    /// These mistakes otherwise surface late and far from their cause: as chattering, a
    /// solution growing to overflow, or a stability tool unable to place the ring.
    ///
    /// # Errors
    /// [`RotorError::Ring`] if the ring's parameters are invalid; the other variants name the
    /// method that breaks its contract and the values it gave.
    pub fn new(rotor: R, ring: SnubberRing) -> Result<Self, RotorError> {
        ring.validate()?;
        let mut model = Self {
            rotor,
            ring,
            exact: None,
        };
        model.check_slots()?;
        let probes = model.check_station()?;
        model.check_velocity(&probes)?;
        model.check_force(&probes)?;
        model.exact = model.prepare_closed_form(&probes)?;
        Ok(model)
    }

    /// The rotor's [`SmoothRotor::linear_free_flight`], prepared: `Ok(None)` without one,
    /// `Ok(Some(Err))` when its closed form is refused (ill-conditioned modes, a failed
    /// decomposition, a resonance: free flight is then integrated), an error when it does not
    /// fit the rotor (layout, shapes, or a disagreement with the rotor's own `rhs` or
    /// `station` at the probe states).
    #[allow(clippy::type_complexity)]
    fn prepare_closed_form(
        &self,
        probes: &[OVector<f64, R::Dim>; 2],
    ) -> Result<Option<Result<Arc<LinearClosedForm>, RotorError>>, RotorError> {
        let Some(linear) = self.rotor.linear_free_flight() else {
            return Ok(None);
        };
        let (n, len) = (linear.dofs(), linear.state_len());
        let dim = self.rotor.dim().value();
        let slots = self.rotor.ring_slots();
        if dim != len + 2 || slots != [len, len + 1] {
            return Err(RotorError::LinearLayout {
                dofs: n,
                dim,
                slots,
            });
        }
        let form = match linear.prepare() {
            Ok(form) => Arc::new(form),
            Err(
                e @ (RotorError::IllConditionedModes { .. }
                | RotorError::EigenResidual { .. }
                | RotorError::Eigen(_)),
            ) => return Ok(Some(Err(e))),
            // No particular solution (an undamped resonance, or K singular under a static
            // force): integrate. A singular M is an error: nothing can be integrated.
            Err(e @ RotorError::Singular { matrix, .. }) if matrix != "M" => {
                return Ok(Some(Err(e)))
            }
            Err(e) => return Err(e),
        };
        self.check_closed_form(&linear, &form, probes)?;
        if let Err(e) = self.check_rounding(&form) {
            return Ok(Some(Err(e)));
        }
        Ok(Some(Ok(form)))
    }

    /// The closed form's rounding against the gap: the station is a sum of the particular
    /// solution and the modes' transients, which from rest cancel it; where those terms are
    /// far larger than the gap (a soft mount's static deflection, $10^{12}$ gaps), the sum's
    /// rounding, about $16\epsilon$ times their sum of magnitudes (the position bound of the
    /// segment from rest over a forcing period, [`RotorMotion::bounds_on`]), is an error in the
    /// contact itself. Above [`CLOSED_FORM_ROUNDING`] of the gap the closed form is refused
    /// ([`RotorError::ClosedFormRounding`]) and free flight is integrated.
    ///
    /// [`RotorMotion::bounds_on`]: crate::ring::onset::RotorMotion::bounds_on
    fn check_rounding(&self, form: &Arc<LinearClosedForm>) -> Result<(), RotorError> {
        let rest = vec![0.0; form.state_len()];
        let period = self.rotor.forcing_period();
        let size =
            crate::ring::onset::RotorMotion::bounds_on(&form.segment(0.0, &rest), 0.0, period)
                .position;
        let rounding = 16.0 * f64::EPSILON * size;
        if size.is_finite() && rounding > CLOSED_FORM_ROUNDING * self.ring.gap {
            return Err(RotorError::ClosedFormRounding {
                terms: size,
                rounding,
                gap: self.ring.gap,
            });
        }
        Ok(())
    }

    /// The closed form against the rotor's own `station` and `rhs`: the station at the probe
    /// states (to the affinity tolerance); the state matrix $A$ column by column against
    /// `(rhs(0, s_j e_j) - rhs(0, 0)) / s_j` (exact up to rounding for a linear field:
    /// relative $10^{-8}$ of each column's largest entry in each half, positions' and
    /// velocities' derivatives, plus the rounding of the two evaluations; $s_j$ raises the
    /// probe to the forcing's size where the column is smaller, so that a small column is not
    /// lost to cancellation against the forcing);
    /// the forcing `rhs(t, 0)` against $x_p^\prime - A x_p$ at two times (relative
    /// $10^{-8}$ of the terms). A probe's derivative is not compared through the modes: the
    /// stiff modes amplify its rounding by $|\lambda|_\text{max}\kappa$.
    fn check_closed_form(
        &self,
        linear: &LinearFreeFlight,
        form: &Arc<LinearClosedForm>,
        probes: &[OVector<f64, R::Dim>; 2],
    ) -> Result<(), RotorError> {
        let len = form.state_len();
        // Compared in groups: positions' and velocities' derivatives for [q, q'], all at once
        // in modal coordinates (each column has one mode's two entries).
        let split = if form.is_modal() { len } else { len / 2 };
        let groups = [0..split, split..len];
        let period = self.rotor.forcing_period();
        for (m, y) in probes.iter().enumerate() {
            let t = if m == 0 { 0.0 } else { 0.37 * period };
            let segment = form.segment(t, &y.as_slice()[..len]);
            let (r, v, _) = crate::ring::onset::RotorMotion::kinematics(&segment, t);
            let k = kin4(&self.rotor.station(y));
            let scale = amax(&k).max(amax(&[r.x, r.y, v.x, v.y]));
            let tol = AFFINE_RTOL * scale + GAP_ATOL * self.ring.gap;
            for (index, (a, b)) in [r.x, r.y, v.x, v.y].into_iter().zip(k).enumerate() {
                linear_agrees("station", t, index, a, b, tol)?;
            }
        }
        let a = linear.state_coordinates_matrix()?;
        let mut y = self.zero_state();
        let mut base = self.zero_state();
        let mut dy = self.zero_state();
        self.rotor.rhs(0.0, &y, &mut base);
        let forcing = amax(base.as_slice());
        for j in 0..len {
            // The probe along e_j at the column's own scale: large enough that the forcing
            // (in both evaluations) does not cancel it away (a soft mount under gravity, a
            // light damping column against the unbalance), 1 when the column is the larger.
            let column = a.column(j).amax();
            let size = if column > 0.0 && forcing > column {
                forcing / column
            } else {
                1.0
            };
            y[j] = size;
            self.rotor.rhs(0.0, &y, &mut dy);
            y[j] = 0.0;
            for half in groups.iter().cloned() {
                let col: Vec<f64> = half.clone().map(|i| (dy[i] - base[i]) / size).collect();
                let want: Vec<f64> = half.clone().map(|i| a[(i, j)]).collect();
                // Relative to the column, plus the rounding of the two evaluations' terms.
                let rounding = half
                    .clone()
                    .map(|i| dy[i].abs() + base[i].abs())
                    .fold(0.0, f64::max);
                let tol =
                    1e-8 * amax(&col).max(amax(&want)) + 64.0 * f64::EPSILON * rounding / size;
                for (k, i) in half.enumerate() {
                    linear_agrees("rhs", 0.0, i, want[k], col[k], tol)?;
                }
            }
        }
        let (mut xp, mut dxp) = (vec![0.0; len], vec![0.0; len]);
        for t in [0.0, 0.37 * period] {
            xp.fill(0.0);
            dxp.fill(0.0);
            form.add_particular(t, &mut xp, &mut dxp);
            self.rotor.rhs(t, &self.zero_state(), &mut dy);
            let terms: Vec<(f64, f64)> = (0..len)
                .map(|i| {
                    let ax: f64 = (0..len).map(|j| a[(i, j)] * xp[j]).sum();
                    let size: f64 = (0..len).map(|j| (a[(i, j)] * xp[j]).abs()).sum();
                    (dxp[i] - ax, size + dxp[i].abs())
                })
                .collect();
            for half in groups.iter().cloned() {
                let size = half
                    .clone()
                    .map(|i| terms[i].1.max(dy[i].abs()))
                    .fold(0.0, f64::max);
                for i in half {
                    linear_agrees("rhs", t, i, terms[i].0, dy[i], 1e-8 * size)?;
                }
            }
        }
        Ok(())
    }

    fn zero_state(&self) -> OVector<f64, R::Dim> {
        OVector::<f64, R::Dim>::zeros_generic(self.rotor.dim(), U1)
    }

    /// `station(y)` as `[r.x, r.y, v.x, v.y]`, refused if not finite (so that the checks below
    /// compare finite numbers).
    fn station4(&self, y: &OVector<f64, R::Dim>) -> Result<[f64; 4], RotorError> {
        let k = kin4(&self.rotor.station(y));
        match k.iter().find(|v| !v.is_finite()) {
            Some(&value) => Err(RotorError::NonFinite {
                method: "station",
                value,
            }),
            None => Ok(k),
        }
    }

    fn check_slots(&self) -> Result<(), RotorError> {
        let dim = self.rotor.dim().value();
        let slots = self.rotor.ring_slots();
        if slots[0] >= dim || slots[1] >= dim || slots[0] == slots[1] {
            return Err(RotorError::RingSlots { slots, dim });
        }
        Ok(())
    }

    /// Two probe states, deterministic and generic (no component zero but the ring's slots),
    /// scaled so that each moves the station about half the gap.
    fn probe_states(&self) -> Result<[OVector<f64, R::Dim>; 2], RotorError> {
        let zero = self.station4(&self.zero_state())?;
        let slots = self.rotor.ring_slots();
        let mut probes = [self.zero_state(), self.zero_state()];
        for (n, p) in probes.iter_mut().enumerate() {
            for k in (0..p.len()).filter(|k| !slots.contains(k)) {
                let phase = 0.9 + 1.3 * n as f64 + (1.7 + 0.6 * n as f64) * k as f64;
                p[k] = 0.25 + 0.75 * phase.sin().abs();
                if (k + n) % 2 == 1 {
                    p[k] = -p[k];
                }
            }
            let moved = amax(&sub4(self.station4(p)?, zero));
            if moved > 0.0 && moved.is_finite() {
                *p *= 0.5 * self.ring.gap / moved;
            }
        }
        Ok(probes)
    }

    /// Checks that the station map is affine with a velocity without offset; returns the
    /// probe states.
    fn check_station(&self) -> Result<[OVector<f64, R::Dim>; 2], RotorError> {
        let gap = self.ring.gap;
        let zero = self.station4(&self.zero_state())?;
        let probes = self.probe_states()?;
        let lx = sub4(self.station4(&probes[0])?, zero);
        let lz = sub4(self.station4(&probes[1])?, zero);
        let scale = amax(&lx).max(amax(&lz));
        let velocity = [zero[2], zero[3]];
        if amax(&velocity) > AFFINE_RTOL * scale + GAP_ATOL * gap {
            return Err(RotorError::StationVelocityOffset { velocity });
        }
        let (a, b) = (0.7, -1.3);
        let combo = &probes[0] * a + &probes[1] * b;
        let got = sub4(self.station4(&combo)?, zero);
        let want: [f64; 4] = std::array::from_fn(|i| a * lx[i] + b * lz[i]);
        let tol = AFFINE_RTOL * (a.abs() * amax(&lx) + b.abs() * amax(&lz)) + GAP_ATOL * gap;
        if amax(&sub4(got, want)) > tol {
            return Err(RotorError::StationNotAffine { a, b, got, want });
        }
        Ok(probes)
    }

    /// Checks that the station's velocity is the derivative of its position under the
    /// rotor's field, at the probes and two times (probes where the field is not finite are
    /// skipped: nothing can be said there).
    fn check_velocity(&self, probes: &[OVector<f64, R::Dim>; 2]) -> Result<(), RotorError> {
        let period = self.rotor.forcing_period();
        let zero_r = {
            let z = self.station4(&self.zero_state())?;
            [z[0], z[1]]
        };
        let atol = GAP_ATOL * self.ring.gap / period.abs().max(f64::MIN_POSITIVE);
        for (n, y) in probes.iter().enumerate() {
            let t = if n == 0 { 0.0 } else { 0.37 * period };
            let mut dy = self.zero_state();
            self.rotor.rhs(t, y, &mut dy);
            let [i, j] = self.rotor.ring_slots();
            dy[i] = 0.0;
            dy[j] = 0.0;
            if dy.iter().any(|v| !v.is_finite()) {
                continue;
            }
            let d = self.station4(&dy)?;
            let derivative = [d[0] - zero_r[0], d[1] - zero_r[1]];
            let k = self.station4(y)?;
            let velocity = [k[2], k[3]];
            let diff = [derivative[0] - velocity[0], derivative[1] - velocity[1]];
            let scale = amax(&derivative).max(amax(&velocity));
            if amax(&diff) > VELOCITY_RTOL * scale + atol {
                return Err(RotorError::StationVelocity {
                    t,
                    velocity,
                    derivative,
                });
            }
        }
        Ok(())
    }

    /// Checks that forces along both axes and along the station's radius accelerate the
    /// station along themselves.
    fn check_force(&self, probes: &[OVector<f64, R::Dim>; 2]) -> Result<(), RotorError> {
        let y = &probes[0];
        let zero_v = {
            let z = self.station4(&self.zero_state())?;
            [z[2], z[3]]
        };
        let r = self.rotor.station(y).r;
        let radial = if r.norm() > 0.0 {
            r / r.norm()
        } else {
            Vector2::new(1.0, 0.0)
        };
        // A load of a tenth of the gap's deflection of the stiffer ring axis.
        let size = 0.1 * self.ring.gap * self.ring.x.stiffness.max(self.ring.y.stiffness);
        for dir in [Vector2::new(1.0, 0.0), Vector2::new(0.0, 1.0), radial] {
            let force = dir * size;
            let mut dy = self.zero_state();
            self.rotor.add_station_force(y, &force, &mut dy);
            if let Some(&value) = dy.iter().find(|v| !v.is_finite()) {
                return Err(RotorError::NonFinite {
                    method: "add_station_force",
                    value,
                });
            }
            let k = self.station4(&dy)?;
            let accel = [k[2] - zero_v[0], k[3] - zero_v[1]];
            let along = accel[0] * dir.x + accel[1] * dir.y;
            if along <= AFFINE_RTOL * amax(&accel) {
                return Err(RotorError::StationForce {
                    force: [force.x, force.y],
                    accel,
                    along,
                });
            }
        }
        Ok(())
    }
}

impl<R> RingedRotor<R> {
    /// The rotor.
    pub fn rotor(&self) -> &R {
        &self.rotor
    }

    /// The rotor's free flight in closed form ([`SmoothRotor::linear_free_flight`]): `None`
    /// when the rotor gives none (free flight integrated), `Some(Ok)` when free flight is
    /// exact, `Some(Err)` with the reason when the closed form was refused (free flight
    /// integrated).
    pub fn closed_form(&self) -> Option<Result<&LinearClosedForm, &RotorError>> {
        self.exact.as_ref().map(|r| r.as_ref().map(|f| &**f))
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

    /// The force of the ring on the rotor at its station in a state `y` of a run (a sample's
    /// or an event's), in contact or not (`in_contact`: the sample's mode label is not 1,
    /// regime I). Zero in free flight (the massless ring relaxes on its own); in contact
    /// $-f$, the reaction to the ring's elastic and damping force
    /// $f = g(s) + C\thinspace J r^\prime$
    /// ([`RingContact::force`](crate::ring::RingContact::force)) with the ring on the branches
    /// of its position $s$ in `y` (its slots), located at the station's $r$ and moving with
    /// $s^\prime = J r^\prime$. Its normal part $N = n\cdot f$,
    /// $n = (r - s)/\gamma$, is the paper's contact force; the elastic part $g(s)$ lies along
    /// $n$, the damping part too where both axes damp alike (regimes II and V). In the ring's
    /// force unit (N for a ring [`SnubberRing::from_units`] in SI).
    ///
    /// # Errors
    /// [`ModelError::InvalidState`] where the ring has no placement on those branches at $r$
    /// (a state that is not one of the run's, or not finite).
    pub fn contact_force(
        &self,
        y: &OVector<f64, R::Dim>,
        in_contact: bool,
    ) -> Result<Vector2<f64>, ModelError>
    where
        R: SmoothRotor,
        DefaultAllocator: Allocator<R::Dim>,
    {
        if !in_contact {
            return Ok(Vector2::new(0.0, 0.0));
        }
        let k = self.rotor.station(y);
        let [i, j] = self.rotor.ring_slots();
        let branches = Branches::of(&self.ring, &Vector2::new(y[i], y[j]));
        let contact = self.ring.locate_on(&k.r, branches, f64::NAN).map_err(|e| {
            ModelError::InvalidState {
                t: f64::NAN,
                reason: e.to_string(),
            }
        })?;
        Ok(-contact.force(&k.v))
    }

    /// The contact's normal force $N = -n\cdot f$ at the state `y` ($f$ the force on the rotor,
    /// [`RingedRotor::contact_force`], $n = (r - s)/\gamma$ the outward normal): what presses
    /// the rotor and the ring together, 0 out of contact. A loss event is where it falls
    /// through 0. In the ring's force unit.
    ///
    /// # Errors
    /// Those of [`RingedRotor::contact_force`].
    pub fn normal_force(
        &self,
        y: &OVector<f64, R::Dim>,
        in_contact: bool,
    ) -> Result<f64, ModelError>
    where
        R: SmoothRotor,
        DefaultAllocator: Allocator<R::Dim>,
    {
        if !in_contact {
            return Ok(0.0);
        }
        let f = self.contact_force(y, true)?;
        let r = self.rotor.station(y).r;
        let [i, j] = self.rotor.ring_slots();
        let d = r - Vector2::new(y[i], y[j]);
        Ok(-d.dot(&f) / d.norm())
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

impl<R: SmoothRotor> RingedRotor<R>
where
    DefaultAllocator: Allocator<R::Dim>,
{
    /// The ring force's Jacobian in `mode` at `y` ([`SnubberRing::force_jacobian`] on the
    /// mode's branches): `Some(None)` out of contact, `None` where the ring cannot be placed
    /// on the branches.
    pub(crate) fn force_jacobian(
        &self,
        mode: RingMode,
        y: &OVector<f64, R::Dim>,
        cache: &RingCache,
    ) -> Option<Option<ForceJacobian>> {
        match mode {
            RingMode::Contact(branches) => {
                let k = self.rotor.station(y);
                let c = self.ring.contact_on(branches, &k.r, cache).ok()?;
                Some(Some(self.ring.force_jacobian(&c, &k.v)))
            }
            _ => Some(None),
        }
    }
}

impl<R: SmoothRotor> RotorModel for RingedRotor<R>
where
    DefaultAllocator: Allocator<R::Dim>,
{
    type Dim = R::Dim;
    type Mode = RingMode;
    type Segment = LinearFreeSegment;
    type Cache = RingCache;

    fn dim(&self) -> R::Dim {
        self.rotor.dim()
    }

    /// The rotor's [`SmoothRotor::state_scale`] if it gives one; otherwise derived from the
    /// ring's gap $\gamma$ and the station map (affine: `station(e_j) - station(0)` is the
    /// station's motion per unit of component $j$): a component that moves the station's
    /// position by $c$ per unit has the scale $\gamma/c$ (the rotor's displacement, in the
    /// gap's unit, for a lumped station), one that moves only its velocity has
    /// $\gamma\Omega/c$ with $\Omega = 2\pi/P$ the forcing frequency
    /// ([`SmoothRotor::forcing_period`]); the ring's slots and the components the station does
    /// not see have $\gamma$. For the paper's rotor in its units that is 1 for positions and
    /// $\eta$ for velocities; in SI units the gap in metres and the gap times $\Omega$ in m/s.
    fn state_scale(&self) -> OVector<f64, R::Dim> {
        if let Some(scale) = self.rotor.state_scale() {
            return scale;
        }
        let gap = self.ring.gap;
        let omega = std::f64::consts::TAU / self.rotor.forcing_period();
        let zero = kin4(&self.rotor.station(&self.zero_state()));
        let slots = self.rotor.ring_slots();
        let mut unit = self.zero_state();
        OVector::from_fn_generic(self.rotor.dim(), U1, |j, _| {
            if slots.contains(&j) {
                return gap;
            }
            unit[j] = 1.0;
            let d = sub4(kin4(&self.rotor.station(&unit)), zero);
            unit[j] = 0.0;
            let (position, velocity) = (amax(&d[..2]), amax(&d[2..]));
            let scale = if position > 0.0 {
                gap / position
            } else if velocity > 0.0 {
                gap * omega / velocity
            } else {
                gap
            };
            if scale.is_finite() && scale > 0.0 {
                scale
            } else {
                gap
            }
        })
    }

    /// The rotor's [`SmoothRotor::error_scale`].
    fn error_scale(&self) -> Option<OVector<f64, R::Dim>> {
        self.rotor.error_scale()
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

    /// Free flight is [`Flow::Exact`] when the rotor has an accepted closed form
    /// ([`RingedRotor::closed_form`]); everything else is integrated.
    fn flow(&self, mode: RingMode) -> Flow {
        match (mode, &self.exact) {
            (RingMode::Free { .. }, Some(Ok(_))) => Flow::Exact,
            _ => Flow::Integrated,
        }
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

    /// The ring's [`RingGuard::Onset`].
    fn is_contact_onset(&self, mode: RingMode, i: usize) -> bool {
        self.guard_of(&mode, i) == RingGuard::Onset
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

    /// The ring element's error ([`SnubberRing::try_guard_value`]).
    fn guard_error(
        &self,
        mode: RingMode,
        i: usize,
        t: f64,
        y: &OVector<f64, R::Dim>,
        cache: &RingCache,
    ) -> ModelError {
        let guard = self.guard_of(&mode, i);
        let k = self.rotor.station(y);
        ModelError::of_ring_guard(
            t,
            guard.label(),
            self.ring.try_guard_value(&mode, guard, t, &k, cache),
        )
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

    /// The linear rotor's closed form ([`LinearSegment`]) with the ring's relaxation and the
    /// certified onset search, in chunks of the forcing period (as the paper's model).
    fn start_segment(&self, mode: RingMode, t: f64, y: &OVector<f64, R::Dim>) -> LinearFreeSegment {
        let (relax, separating) = match mode {
            RingMode::Free {
                relax, separating, ..
            } => (relax, separating),
            // Never started for a contact mode (it is integrated); a ring at rest is harmless.
            _ => (Relaxation::at_rest(t), false),
        };
        let motion = match &self.exact {
            Some(Ok(form)) => Some(form.segment(t, &y.as_slice()[..form.state_len()])),
            _ => None,
        };
        LinearFreeSegment {
            motion,
            relax,
            ring: self.ring,
            scan: OnsetScan::new(t, self.rotor.forcing_period(), separating),
        }
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

    fn strobe_time(&self, k: u64) -> f64 {
        self.rotor.strobe_time(k)
    }

    fn strobe_phase(&self, k: u64) -> Option<(usize, f64)> {
        self.rotor.strobe_phase(k)
    }

    fn max_rate(&self, mode: RingMode, t: f64, y: &OVector<f64, R::Dim>) -> Option<f64> {
        let (k, c) = match mode {
            RingMode::Contact(_) => self.ring.contact_bounds(),
            _ => (0.0, 0.0),
        };
        self.rotor.max_rate(t, y, k, c)
    }

    /// The rotor's [`SmoothRotor::second_order`] (the ring's force enters only the velocity
    /// rows, its slots are set after the rotor's $2p$ components), `None` if a ring slot
    /// lies among the positions and velocities.
    /// The rotor's [`SmoothRotor::jacobian`] with, in contact, the ring force's Jacobian on
    /// the mode's branches ([`SnubberRing::force_jacobian`]); the ring slots' rows are zero.
    /// Exact in free flight, where the ring relaxes independently of the state; in contact
    /// the ring's velocity $J(r)\thinspace r^\prime$ depends on the rotor, but nothing
    /// depends on the slots (the force is a function of the station's motion), so the zero
    /// rows only delay the slots' Newton convergence, and the slots are algebraic: excluded
    /// from error control and from the Newton norm, and set by the ring's rules at every
    /// output and event.
    fn jacobian(
        &self,
        mode: RingMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        jac: &mut JacobianMut<'_, R::Dim>,
        cache: &RingCache,
    ) -> bool {
        let Some(force) = self.force_jacobian(mode, y, cache) else {
            return false;
        };
        if !self.rotor.jacobian(t, y, force.as_ref(), jac) {
            return false;
        }
        for i in self.rotor.ring_slots() {
            jac.row_mut(i).fill(0.0);
        }
        true
    }

    /// The rotor's [`SmoothRotor::linear_part`], with its forcing: the ring's force and slots
    /// are the rest of the field (a force on the rotor in contact, which moves with the
    /// unbalance, is resolved by the steps).
    fn linear_part(&self) -> Option<&crate::ode::DiagonalLinearPart> {
        self.rotor.linear_part()
    }

    fn second_order(&self) -> Option<usize> {
        let p = self.rotor.second_order()?;
        let slots_after = self.rotor.ring_slots().iter().all(|&i| i >= 2 * p);
        slots_after.then_some(p)
    }

    /// The rotor's [`SmoothRotor::diagonal_springs`], when it is of second order here.
    fn diagonal_springs(&self) -> Option<crate::ode::DiagonalSprings<'_>> {
        self.second_order()?;
        self.rotor.diagonal_springs()
    }
}
