//! Piecewise-smooth rotor models and the driver that runs them through modes and events.
//!
//! A piecewise-smooth model is a set of **modes** (free flight, contact on one branch of a
//! force law, ...). In each mode the state $y \in \mathbb{R}^N$ follows a smooth vector field,
//! either integrated numerically ([`Flow::Integrated`]) or known in closed form
//! ([`Flow::Exact`]). **Guards** $g_i(t, y)$ end a mode when they cross zero in their
//! direction; the model's **transition** map then gives the next mode and may reset the state.
//!
//! The [`RotorModel`] trait is that interface: a larger rotordynamics code (a 4-DOF rotor, a
//! reduced finite-element rotor with the same snubber ring element) implements it and reuses
//! [`simulate`], the event machinery of [`crate::ode`] and the analyses of
//! [`crate::analysis`]. [`crate::paper::JeffcottModel`] is the paper's model.
//!
//! # Dimensions
//!
//! A model chooses its state dimension as a nalgebra [`Dim`]: a size fixed at compile time
//! (`U6`, i.e. `Const<6>`: stack storage, `SVector<f64, 6>` is `OVector<f64, U6>`) or
//! [`Dyn`](nalgebra::Dyn), a size known at run time (a reduced finite-element shaft whose
//! number of modes is read from a file). Everything downstream (the driver, the records, every
//! analysis) is generic over it. The arithmetic does not depend on the storage: a model run
//! with `Dyn(n)` gives bitwise the same results as the same model with `Const<n>`. The driver
//! allocates its scratch when a run starts; stepping, event location, projections and
//! transitions then allocate nothing, for `Dyn` too (outputs allocate only if the observer
//! stores them).
//!
//! # The rules of a model
//!
//! Everything a model must respect, with what the driver does, is stated on [`RotorModel`]
//! (one method each); in short:
//!
//! * inside a mode the vector field must be smooth (extend each branch's formula beyond its
//!   boundary rather than switching formulas inside a mode), so no step straddles a kink;
//! * guards of integrated modes are located on the dense output (with grazing detection when
//!   [`RotorModel::guard_derivative`] is given); exact modes find their own guards
//!   ([`ExactSegment::next_guard`]), as only the model knows the bounds that make that safe;
//! * a guard that is zero at the start of a mode fires only on a later crossing: it takes the
//!   sign of its motion and a departure in its crossing direction is not an event (see
//!   [`RotorModel::guard_direction`]);
//! * algebraic components (set by the model, e.g. the position of a massless ring held by its
//!   contact law) are placed by [`RotorModel::project`] and left out of the step-size control
//!   ([`RotorModel::is_algebraic`]).
//!
//! # Your rotor with the snubber ring
//!
//! A rotor that meets the crate's snubber ring need not implement [`RotorModel`] by hand:
//! write its smooth equations as a [`crate::rotor::SmoothRotor`] and
//! [`crate::rotor::RingedRotor`] adds the ring's modes, guards and transitions (see
//! `examples/custom_rotor/`). Implement [`RotorModel`] directly for other contact laws; its
//! documentation carries a worked example of a model sized at run time.
//!
//! # Linearisation
//!
//! [`Variational`] extends [`RotorModel`] with the model's linearisation (field, guard, reset
//! and closed-form Jacobians, algebraic rows), each with a finite-difference default. It lives
//! here, with the models, so that each model implements it beside itself (the paper's model
//! analytically, [`crate::rotor::RingedRotor`] with the ring's parts analytic) and the analyses
//! of [`crate::stability`] use it without naming any model.

mod driver;
mod linearization;
mod record;

pub use driver::{simulate, SimError, SimErrorKind, SimOptions, SimStats};
pub(crate) use linearization::{field_differences, guard_differences, reset_differences};
pub use linearization::{Variational, VariationalAlloc, Workspace};
pub use record::{
    DenseSampling, EventRecord, HybridObserver, OutputPlan, Sample, StrobePoint, StrobeRange,
    Trajectory,
};

use std::fmt::Debug;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

use crate::numeric::Direction;
use crate::ring::RingError;

/// How a mode is advanced in time.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Flow {
    /// Integrated numerically by the driver's [`crate::ode::Integrator`].
    Integrated,
    /// Known in closed form: the model supplies an [`ExactSegment`].
    Exact,
}

/// Why a model rejected a state or a transition.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum ModelError {
    /// The state is not allowed by the model (e.g. the rotor beyond the ring).
    #[error("invalid state at t = {t}: {reason}")]
    InvalidState {
        /// Time.
        t: f64,
        /// What is wrong and what to try.
        reason: String,
    },
    /// A transition could not be computed.
    #[error("transition failed at t = {t}: {reason}")]
    Transition {
        /// Time.
        t: f64,
        /// What went wrong.
        reason: String,
    },
    /// The snubber ring could not be evaluated (e.g. no placement of the ring on the contact
    /// mode's branches at the rotor's position): the ring element's own error.
    #[error("ring at t = {t}: {source}")]
    Ring {
        /// Time.
        t: f64,
        /// The ring element's error (boxed: it keeps every run's error type small).
        source: Box<RingError>,
    },
}

impl ModelError {
    /// The error behind a ring guard that a model could not evaluate at `t`, from the ring's
    /// answer ([`SnubberRing::try_guard_value`](crate::ring::SnubberRing::try_guard_value)):
    /// the ring's error, or, should the guard `label` have a value after all, an invalid state
    /// saying so. The one mapping of every model on the ring.
    pub(crate) fn of_ring_guard(t: f64, label: &str, value: Result<f64, RingError>) -> Self {
        match value {
            Err(source) => ModelError::Ring {
                t,
                source: Box::new(source),
            },
            Ok(v) => ModelError::InvalidState {
                t,
                reason: format!("guard `{label}` = {v}: the ring gave no error"),
            },
        }
    }
}

/// The first guard crossing an [`ExactSegment`] finds.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GuardCrossing {
    /// Index of the guard that fires.
    pub guard: usize,
    /// Time of the crossing.
    pub t: f64,
}

/// The closed-form motion of an exact mode, from the state it was started with
/// ([`RotorModel::start_segment`]).
pub trait ExactSegment<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Writes the state and its time derivative at time `t` (not before the segment's start)
    /// into `y` and `dy` (both of the model's dimension; every component must be written).
    fn eval(&self, t: f64, y: &mut OVector<f64, D>, dy: &mut OVector<f64, D>);
    /// Searches $(t_\text{from}, t_\text{to}]$ for the first guard crossing; returns it, or
    /// `None` if none occurs up to `t_to`. The driver calls it with consecutive windows
    /// (`t_from` is the previous `t_to`), ending at output times and at the end of the run:
    /// the answer must not depend on how the search is split (search on a grid of your own).
    /// Must not miss a crossing (document how) and must apply the rule of
    /// [`RotorModel::guard_direction`] to a guard that is zero at the segment's start.
    fn next_guard(&mut self, t_from: f64, t_to: f64) -> Option<GuardCrossing>;
    /// Closed-form evaluations made so far (for statistics).
    fn evaluations(&self) -> u64;
}

/// The [`RotorModel::Segment`] of a model without exact modes: never started by the
/// driver when every mode is [`Flow::Integrated`].
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct NoExactModes;

impl<D: Dim> ExactSegment<D> for NoExactModes
where
    DefaultAllocator: Allocator<D>,
{
    fn eval(&self, _t: f64, y: &mut OVector<f64, D>, dy: &mut OVector<f64, D>) {
        y.fill(f64::NAN);
        dy.fill(f64::NAN);
    }
    fn next_guard(&mut self, _t_from: f64, _t_to: f64) -> Option<GuardCrossing> {
        None
    }
    fn evaluations(&self) -> u64 {
        0
    }
}

/// A piecewise-smooth rotor model: modes, their vector fields, guards and transitions, on a
/// state of dimension [`RotorModel::Dim`].
///
/// Methods take `&self`: a model is immutable and can be shared across threads; per-run
/// scratch (warm starts of inner solvers, run-time-sized work vectors) lives in
/// [`RotorModel::Cache`], made by [`RotorModel::new_cache`] when a run starts.
///
/// # What the driver does with a model
///
/// [`simulate`] from $(t_0, y_0)$:
///
/// 1. checks the options, then asks [`initial_mode`](RotorModel::initial_mode) (which may
///    reject the state) and makes the state consistent with
///    [`project`](RotorModel::project) in that mode: **an initial state's algebraic components
///    are placed by the model**, whatever they were (a model may instead reject a state that
///    is far from consistent in `initial_mode`, as the paper's model does). The first output
///    is this projected state;
/// 2. advances the mode: an [`Exact`](Flow::Exact) mode by its closed form
///    ([`start_segment`](RotorModel::start_segment), [`ExactSegment`]), an
///    [`Integrated`](Flow::Integrated) one by the integrator on [`rhs`](RotorModel::rhs),
///    locating the guards on each step's dense output. Outputs in between are projected
///    copies (a separate cache, so that asking for outputs never changes the trajectory);
/// 3. at the first guard crossing $(t_e, y_e)$: projects $y_e$ in the old mode, records it as
///    the event's `before`, calls [`transition`](RotorModel::transition), which returns the
///    new mode and may change the state (the event's `after`), and goes on from there with
///    the integrator's step size kept. The state after a transition is not projected again:
///    `transition` must leave it consistent for the new mode;
/// 4. stops at the plan's end time (the final state projected), or with a [`SimError`]
///    holding the last good state.
///
/// # Example: a model of your own, sized at run time
///
/// A chain of `m` unit masses joined by unit springs between fixed walls, damped, the first
/// mass forced by $A\cos(t/2)$ and meeting a stop of stiffness 20 at $x_1 = 1$; the state
/// $(x_1, \dots, x_m, v_1, \dots, v_m)$ has $2m$ components, known at run time. Every analysis
/// of [`crate::analysis`] runs on it; here a bifurcation diagram over $A$:
///
/// ```
/// use jeffcott::analysis::{bifurcation, start_from, BifurcationOptions};
/// use jeffcott::hybrid::{Flow, ModelError, NoExactModes, RotorModel};
/// use jeffcott::nalgebra::{DVector, Dyn};
/// use jeffcott::numeric::Direction;
///
/// struct Chain {
///     m: usize,
///     amp: f64,
/// }
///
/// #[derive(Debug, Clone, Copy, PartialEq)]
/// enum Contact {
///     Free,
///     Stop,
/// }
///
/// impl RotorModel for Chain {
///     type Dim = Dyn;
///     type Mode = Contact;
///     type Segment = NoExactModes;
///     type Cache = ();
///
///     fn dim(&self) -> Dyn {
///         Dyn(2 * self.m)
///     }
///     fn new_cache(&self) {}
///     fn initial_mode(&self, _t: f64, y: &DVector<f64>) -> Result<Contact, ModelError> {
///         Ok(if y[0] < 1.0 { Contact::Free } else { Contact::Stop })
///     }
///     fn flow(&self, _mode: Contact) -> Flow {
///         Flow::Integrated
///     }
///     fn rhs(&self, mode: Contact, t: f64, y: &DVector<f64>, dy: &mut DVector<f64>, _: &()) {
///         let m = self.m;
///         for i in 0..m {
///             let left = if i > 0 { y[i - 1] } else { 0.0 };
///             let right = if i + 1 < m { y[i + 1] } else { 0.0 };
///             dy[i] = y[m + i];
///             dy[m + i] = left + right - 2.0 * y[i] - 0.1 * y[m + i];
///         }
///         dy[m] += self.amp * (0.5 * t).cos();
///         if mode == Contact::Stop {
///             dy[m] -= 20.0 * (y[0] - 1.0); // the stop's formula, extended smoothly in its mode
///         }
///     }
///     fn guard_count(&self, _mode: Contact) -> usize {
///         1
///     }
///     fn guard_direction(&self, mode: Contact, _i: usize) -> Direction {
///         match mode {
///             Contact::Free => Direction::Rising,
///             Contact::Stop => Direction::Falling,
///         }
///     }
///     fn guard_value(&self, _: Contact, _i: usize, _t: f64, y: &DVector<f64>, _: &()) -> f64 {
///         y[0] - 1.0
///     }
///     fn guard_label(&self, mode: Contact, _i: usize) -> &'static str {
///         match mode {
///             Contact::Free => "hit",
///             Contact::Stop => "leave",
///         }
///     }
///     fn transition(
///         &self,
///         mode: Contact,
///         _guard: usize,
///         _t: f64,
///         _y: &mut DVector<f64>,
///     ) -> Result<Contact, ModelError> {
///         Ok(match mode {
///             Contact::Free => Contact::Stop,
///             Contact::Stop => Contact::Free,
///         })
///     }
///     fn start_segment(&self, _: Contact, _t: f64, _y: &DVector<f64>) -> NoExactModes {
///         NoExactModes
///     }
///     fn mode_label(&self, mode: Contact) -> u8 {
///         match mode {
///             Contact::Free => 1,
///             Contact::Stop => 2,
///         }
///     }
///     fn forcing_period(&self) -> f64 {
///         4.0 * std::f64::consts::PI
///     }
/// }
///
/// // Three masses, two amplitudes, every value from rest (the closures build the model and
/// // give each run's initial state).
/// let build = |amp: f64| -> Result<Chain, String> { Ok(Chain { m: 3, amp }) };
/// let config = BifurcationOptions::default().with_transient(100).with_record(8);
/// let diagram = bifurcation(&[0.2, 1.5], build, start_from(DVector::zeros(6)), &config, None)?;
/// // A = 0.2 stays clear of the stop (steady amplitude 0.22): linear, period 1.
/// let low = diagram.columns[0].as_ref().unwrap();
/// assert_eq!(low.periodicity.period(), Some(1));
/// assert_eq!(low.orbit.stats.transitions, 0);
/// // A = 1.5 would reach 1.65: it hits the stop.
/// let high = diagram.columns[1].as_ref().unwrap();
/// assert!(high.orbit.stats.transitions > 0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub trait RotorModel
where
    DefaultAllocator: Allocator<Self::Dim>,
{
    /// The state dimension: `U6` (`Const<6>`) for a size fixed at compile time,
    /// [`Dyn`](nalgebra::Dyn) for a size known at run time.
    type Dim: Dim;
    /// The model's modes.
    type Mode: Copy + PartialEq + Debug;
    /// Closed-form motion of exact modes ([`NoExactModes`] if there are none).
    type Segment: ExactSegment<Self::Dim>;
    /// Per-run scratch, e.g. `Cell`s holding warm starts, or work vectors sized at run time.
    /// The driver makes two per run ([`RotorModel::new_cache`]): one for the trajectory, one
    /// for outputs.
    type Cache;

    /// The state dimension (for `Dyn` the run-time size, e.g. `Dyn(n)`; for `Const<N>` the
    /// constant). Every state the driver passes has this dimension.
    fn dim(&self) -> Self::Dim;

    /// A typical magnitude of each state component, in the model's units: the scale of the
    /// analyses' relative-plus-absolute tests, `|e_i| <= atol * scale_i + rtol * |y_i|`
    /// (Newton's and the period test's stopping rules, attractor matching, finite-difference
    /// increments). The default is 1 for every component (a non-dimensional model).
    fn state_scale(&self) -> OVector<f64, Self::Dim> {
        OVector::from_element_generic(self.dim(), nalgebra::Const::<1>, 1.0)
    }

    /// The weight of each component's error in an implicit integrator's error test, if the
    /// model chooses one: with [`Method::Radau5`](crate::ode::Method::Radau5) the absolute
    /// tolerance of component $i$ is then `atol * error_scale[i]` instead of
    /// `atol * state_scale[i]` ([`SimOptions::atol`]). It is a modelling choice of which
    /// errors matter, e.g. a velocity counted by the displacement it stands for
    /// ([`SmoothRotor::error_scale`](crate::rotor::SmoothRotor::error_scale)); the analyses'
    /// tests keep [`RotorModel::state_scale`]. The explicit methods keep the state's scale:
    /// where the fast components set their step, it is those components' error test that
    /// keeps them stable, and looser weights let the parasitic oscillation grow to them
    /// (measured on the 64-mode flexible shaft at `rtol = atol = 1e-8`: DOP853 6e-7 of the gap
    /// from its reference with the weights, 4e-11 without, in the same time). Entries must be finite and $> 0$: a negative or
    /// NaN one is the integrator's invalid-tolerance error when the run starts (algebraic
    /// components, [`RotorModel::is_algebraic`], are not tested whatever their entry).
    /// Default `None`: the state's scale, and every run as before.
    fn error_scale(&self) -> Option<OVector<f64, Self::Dim>> {
        None
    }

    /// A fresh per-run scratch. Called when a run starts (never while stepping), so it may
    /// allocate.
    fn new_cache(&self) -> Self::Cache;

    /// The mode of an initial state.
    ///
    /// # Errors
    /// [`ModelError::InvalidState`] when the state is not allowed.
    fn initial_mode(&self, t: f64, y: &OVector<f64, Self::Dim>) -> Result<Self::Mode, ModelError>;

    /// How `mode` is advanced.
    fn flow(&self, mode: Self::Mode) -> Flow;

    /// Vector field of an integrated mode, smooth within the mode: writes $f(t, y)$ into `dy`
    /// (every component).
    ///
    /// For an **algebraic** component ([`RotorModel::is_algebraic`]) `dy[i]` is what the
    /// integrator advances that component with between projections: give its time derivative
    /// along the flow if it is known (it is then exact to the integrator's order, its dense
    /// output is meaningful, and it is the derivative reported in dense samples, e.g. a
    /// massless ring's velocity with its jumps), or 0 (the component then holds its last
    /// projected value between projections). It never limits the step size either way.
    fn rhs(
        &self,
        mode: Self::Mode,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        dy: &mut OVector<f64, Self::Dim>,
        cache: &Self::Cache,
    );

    /// Whether component `i` is **algebraic**: set by the model in [`RotorModel::project`]
    /// rather than determined by integrating [`RotorModel::rhs`] (e.g. the position of a
    /// massless ring, which sits where its contact law puts it). The driver gives such
    /// components `atol = f64::INFINITY` in the integrator's error control, so that they never
    /// limit the step ([`crate::ode::Options::atol`]); the other components use
    /// [`SimOptions::atol`]. Asked once per run for `i in 0..dim`. Default: `false` for every
    /// component (everything error-controlled).
    fn is_algebraic(&self, i: usize) -> bool {
        let _ = i;
        false
    }

    /// $p$ when every mode's field is of second order in the first $2p$ components
    /// (positions, then velocities, then the rest: `dy[i] = y[p + i]` exactly for $i < p$),
    /// passed to the integrator as [`OdeSystem::second_order`](crate::ode::OdeSystem::second_order),
    /// where [`Radau5`](crate::ode::Radau5) solves its Newton systems condensed to
    /// $N - p$ unknowns. Default `None`.
    fn second_order(&self) -> Option<usize> {
        None
    }

    /// The linear part of every mode's field, diagonal in the state's own coordinates, passed
    /// to the integrator as [`OdeSystem::linear_part`](crate::ode::OdeSystem::linear_part)
    /// (the exponential integrator [`Etd4`](crate::ode::Etd4) needs it), with the forcing of
    /// the field declared on it if it has one. The same for every mode: what a mode adds (a
    /// contact force) is the rest of its field. Default `None`.
    fn linear_part(&self) -> Option<&crate::ode::DiagonalLinearPart> {
        None
    }

    /// The diagonal springs and dampers of every mode's field (second order, the same for
    /// every mode: what a mode adds, a contact force, is of low rank), passed to the
    /// integrator as [`OdeSystem::diagonal_springs`](crate::ode::OdeSystem::diagonal_springs),
    /// with which [`Radau5`](crate::ode::Radau5) solves its Newton systems in $O(N)$.
    /// Default `None`.
    fn diagonal_springs(&self) -> Option<crate::ode::DiagonalSprings<'_>> {
        None
    }

    /// The Jacobian $\partial f/\partial y$ of `mode`'s field at $(t, y)$ written into `jac`
    /// (every entry), `true`; or `false` (the default) for finite differences. Passed to the
    /// integrator as [`OdeSystem::jacobian`](crate::ode::OdeSystem::jacobian) (only
    /// [`Radau5`](crate::ode::Radau5) uses it; an approximation slows its Newton iteration,
    /// never makes a step wrong).
    fn jacobian(
        &self,
        mode: Self::Mode,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        jac: &mut crate::ode::JacobianMut<'_, Self::Dim>,
        cache: &Self::Cache,
    ) -> bool {
        let _ = (mode, t, y, jac, cache);
        false
    }

    /// Number of guards of an integrated mode (any number).
    fn guard_count(&self, mode: Self::Mode) -> usize;

    /// Crossing direction of guard `i` that ends `mode`: the guard fires when
    /// $g_i$ goes from negative to non-negative ([`Direction::Rising`]), from positive to
    /// non-positive ([`Direction::Falling`]), or either.
    ///
    /// **A guard that is zero at the start of a mode** (a transition left the state on it, or
    /// two guards crossed at the same time) takes the sign of its motion there: the sign of
    /// [`RotorModel::guard_derivative`] if given and non-zero, else the sign of the guard a
    /// little way along the step (see [`ode`, Events](crate::ode#events)). If it leaves zero in its
    /// crossing direction, that departure is the zero at the start time, not an event (the
    /// transition must have dealt with it, e.g. by choosing the mode beyond that boundary); if
    /// it leaves zero the other way, its next crossing fires as usual, even within the first
    /// step. Exact modes apply the same rule in [`ExactSegment::next_guard`]. "On zero" includes
    /// a guard that reaches zero, moving in its crossing direction, within the event
    /// detector's time resolution $8\varepsilon\max(|t|, |t_\text{end}|)$ of the start: such a
    /// guard cannot be told from the round-off of a located root. If the model's next motion
    /// may cross a guard that the transition left (nearly) on zero, let the transition choose
    /// the mode beyond it, or offset the guard so that it starts clearly on its pre-crossing
    /// side (what [`crate::ring::RingMode::Free`]'s `onset_margin` does for a free flight that
    /// starts touching the ring). A guard that starts off zero is never dropped, however close
    /// to the start its crossing is.
    fn guard_direction(&self, mode: Self::Mode, i: usize) -> Direction;

    /// Whether guard `i` of `mode` is a contact onset (free flight reaching the ring): the
    /// analyses report its margin as the distance to a grazing. The default: no guard is.
    fn is_contact_onset(&self, mode: Self::Mode, i: usize) -> bool {
        let _ = (mode, i);
        false
    }

    /// Value $g_i(t, y)$ of guard `i` of an integrated mode (smooth along the mode's flow).
    fn guard_value(
        &self,
        mode: Self::Mode,
        i: usize,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        cache: &Self::Cache,
    ) -> f64;

    /// Time derivative of guard `i` along the flow, $\dot g_i = \partial_t g_i + \nabla_y g_i
    /// \cdot f$, given `y` and `dy` $= f(t, y)$ (or zeros, see
    /// [`RotorModel::guard_derivative_needs_rhs`]): enables grazing detection (two crossings
    /// between two samples) and gives the direction of a guard that is zero at a mode's start.
    /// Default: `None` (not available; must then be `None` for every argument).
    fn guard_derivative(
        &self,
        mode: Self::Mode,
        i: usize,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        dy: &OVector<f64, Self::Dim>,
        cache: &Self::Cache,
    ) -> Option<f64> {
        let _ = (mode, i, t, y, dy, cache);
        None
    }

    /// Whether [`RotorModel::guard_derivative`] reads its `dy` argument; `false` saves a
    /// right-hand side evaluation per event sample (`dy` is then zeros; see
    /// [`crate::ode::EventSet::derivative_needs_rhs`]). Default: `true`.
    fn guard_derivative_needs_rhs(&self) -> bool {
        true
    }

    /// Whether the derivative of guard `i` of `mode` reads its `dy` argument (default:
    /// [`RotorModel::guard_derivative_needs_rhs`]). A model whose guards differ saves the
    /// right-hand side at the samples of steps where only the others are sampled.
    fn guard_derivative_needs_rhs_of(&self, mode: Self::Mode, i: usize) -> bool {
        let _ = (mode, i);
        self.guard_derivative_needs_rhs()
    }

    /// Every guard of `mode` at one point: calls `out(i, value, rate)` for `i` in
    /// `0..guard_count(mode)`, with [`RotorModel::guard_value`] and, if `with_rates`,
    /// [`RotorModel::guard_derivative`] (`dy` as there). The default calls those two for each
    /// guard; a model whose guards share work (a contact location) can evaluate them together,
    /// returning the same numbers. The driver's event detector uses it at every step's end.
    #[allow(clippy::too_many_arguments)]
    fn guard_values(
        &self,
        mode: Self::Mode,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        dy: &OVector<f64, Self::Dim>,
        with_rates: bool,
        cache: &Self::Cache,
        out: &mut dyn FnMut(usize, f64, Option<f64>),
    ) {
        for i in 0..self.guard_count(mode) {
            let rate = if with_rates {
                self.guard_derivative(mode, i, t, y, dy, cache)
            } else {
                None
            };
            out(i, self.guard_value(mode, i, t, y, cache), rate);
        }
    }

    /// Why guard `i` of `mode` has no value at `(t, y)`: the driver asks when
    /// [`RotorModel::guard_value`] (or [`RotorModel::guard_values`]) returned NaN where the event
    /// detector needed the guard's sign, and stops the run with
    /// [`SimErrorKind::Guard`] carrying the answer. NaN is not a
    /// way to say "no event here": a guard must have a value wherever the mode's flow may go
    /// before another guard ends the mode. `y` is the integrator's dense output at `t` (not
    /// projected). Default: [`ModelError::InvalidState`] saying that the guard returned NaN; a
    /// model whose guards can fail should say why (the ring's models give
    /// [`ModelError::Ring`]).
    fn guard_error(
        &self,
        mode: Self::Mode,
        i: usize,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        cache: &Self::Cache,
    ) -> ModelError {
        let _ = (mode, y, cache);
        ModelError::InvalidState {
            t,
            reason: format!("guard {i} returned NaN: it has no value at this state"),
        }
    }

    /// Short name of guard `i` of `mode`, for event logs.
    fn guard_label(&self, mode: Self::Mode, i: usize) -> &'static str;

    /// Transition map: the mode after guard `guard` of `mode` fired.
    ///
    /// Receives the event time `t` and the state there, located on the dense output (or the
    /// closed form) and already projected in the old mode ([`RotorModel::project`]); may change
    /// `y` (a reset map, e.g. place the algebraic components for the new mode, or an impact
    /// law). The driver does not project the result: it must be consistent for the returned
    /// mode. A guard of the new mode that is zero at `t` follows the rule of
    /// [`RotorModel::guard_direction`].
    ///
    /// # Errors
    /// [`ModelError`] when no successor mode exists.
    fn transition(
        &self,
        mode: Self::Mode,
        guard: usize,
        t: f64,
        y: &mut OVector<f64, Self::Dim>,
    ) -> Result<Self::Mode, ModelError>;

    /// Starts the closed-form motion of an exact mode at `(t, y)`. Called once per exact
    /// mode entered (not per step).
    fn start_segment(&self, mode: Self::Mode, t: f64, y: &OVector<f64, Self::Dim>)
        -> Self::Segment;

    /// Makes the algebraic components of `y` consistent with the others in `mode` and must
    /// change nothing else. Called on the initial state, on every output of an integrated mode
    /// (a copy, with the output cache), before every transition, and on the final state.
    /// Default: changes nothing (a model without algebraic components).
    fn project(
        &self,
        mode: Self::Mode,
        t: f64,
        y: &mut OVector<f64, Self::Dim>,
        cache: &Self::Cache,
    ) {
        let _ = (mode, t, y, cache);
    }

    /// A small number labelling the mode in outputs (the paper's regime number for its
    /// model).
    fn mode_label(&self, mode: Self::Mode) -> u8;

    /// The period $P$ of the excitation: stroboscopic outputs are at $t_k = kP$
    /// ([`StrobeRange`]; unless [`RotorModel::strobe_time`] says otherwise) and the chattering bound counts transitions per window of length
    /// $P$ ([`SimOptions::max_events_per_period`]), as does the maximum step
    /// ([`SimOptions::max_step_fraction`]) and the fixed step of RK4
    /// ([`SimOptions::steps_per_period`]). An **unforced** model returns a characteristic
    /// period of its motion instead (e.g. $2\pi/\omega_n$ of its lowest mode, or the sampling
    /// interval wanted for its stroboscopic outputs): finite and > 0.
    fn forcing_period(&self) -> f64;

    /// The time $t_k$ of the stroboscopic output `k` ([`StrobeRange`]): the default is
    /// $t_k = kP$ ($P$ = [`RotorModel::forcing_period`]), the forcing's phase back at its
    /// start after `k` periods. A model whose forcing frequency varies in time (a run-up,
    /// [`crate::rotor::SpeedProfile`]) returns the times its forcing phase reaches its
    /// start plus $2\pi k$ (or a fraction of it). Must increase with `k` and be finite for
    /// the indices asked for.
    fn strobe_time(&self, k: u64) -> f64 {
        self.forcing_period() * k as f64
    }

    /// Stroboscopic outputs at a **phase in the state** instead of at known times: `Some((i,
    /// φ_k))` puts the output `k` where the state's component `i` (a shaft angle, increasing
    /// with time) reaches $\varphi_k$, located on each step's dense output (or the closed
    /// form) by [`illinois`](crate::numeric::illinois) to a few ulp of the time, and
    /// [`RotorModel::strobe_time`] is not asked. For a model whose speed is a state (a
    /// non-ideal drive): its strobes at the shaft's turns. A target already passed by the
    /// start state is skipped; where the angle crosses a target and back within one step the
    /// output is missed (the angle must increase: the shaft turns forwards). Must return the
    /// same index for every `k` and targets that increase with `k`. Default `None` (the
    /// strobes at [`RotorModel::strobe_time`]).
    fn strobe_phase(&self, k: u64) -> Option<(usize, f64)> {
        let _ = k;
        None
    }

    /// An upper bound $\lambda$ of the rates of the motion in `mode` at `(t, y)` (the spectral
    /// radius of the vector field's Jacobian, for a unit-mass oscillator of stiffness $k$ and
    /// damping coefficient $c$ bounded by $\sqrt{k} + c$, and the forcing's frequency), if the
    /// model knows one. The driver
    /// counts the fixed (RK4) steps $h$ with $h\lambda > 1$ in
    /// [`SimStats::unresolved_steps`](crate::hybrid::SimStats::unresolved_steps): beyond that
    /// the fixed step does not resolve the motion (RK4's stability limit is $h\lambda \approx
    /// 2.8$; past it the state explodes to finite garbage within a few steps), guards are
    /// located on a dense output that means nothing, and a transition there can leave the
    /// rotor beyond the ring. Default: `None` (such steps are not counted).
    fn max_rate(&self, mode: Self::Mode, t: f64, y: &OVector<f64, Self::Dim>) -> Option<f64> {
        let _ = (mode, t, y);
        None
    }
}
