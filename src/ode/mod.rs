//! Generic Runge–Kutta integrators (explicit, and one implicit for stiff problems) with
//! error control, dense output and event detection.
//!
//! This layer knows nothing about rotors. It provides
//!
//! * [`Dop853`] — Dormand–Prince 8(5,3) with Hairer's 7th-order dense output,
//! * [`Dopri5`] — Dormand–Prince 5(4) with Shampine's 4th-order dense output,
//! * [`Rk4`] — the classical fixed-step 4th-order method with cubic Hermite
//!   dense output,
//! * [`Radau5`] — the implicit three-stage Radau IIA method of order 5 (Hairer and
//!   Wanner's RADAU5) for stiff problems, with its collocation polynomial as dense output
//!   and the system's Jacobian ([`OdeSystem::jacobian`]) or finite differences,
//! * [`AnyIntegrator`] — enum dispatch over the four, selected at run time by
//!   [`Method`],
//! * [`events`] — event functions $g_i(t, y)$ (as a trait, or from closures
//!   with [`EventFns`]) and their detection on the dense output, including
//!   grazing pairs of roots,
//! * event roots located by the crate's bracketing root finder
//!   [`numeric::illinois`](crate::numeric::illinois),
//! * [`solve`](solve::solve) — a convenience driver with outputs and events.
//!
//! # Dimensions: fixed or known at run time
//!
//! Everything is generic over a nalgebra dimension `D` and works on
//! [`OVector<f64, D>`](nalgebra::OVector):
//!
//! * a fixed size (`U6`, `Const<6>`; [`SVector<f64, 6>`](nalgebra::SVector) is
//!   the same type as `OVector<f64, Const<6>>`): stack storage, loops unrolled
//!   by the compiler, built with `Dop853::new(options)`;
//! * [`Dyn`](nalgebra::Dyn) (a size known at run time, e.g. a finite-element
//!   shaft): heap storage, built with `Dop853::with_dim(Dyn(n), options)`.
//!
//! The arithmetic does not depend on the storage: the same problem run with
//! `Dyn(n)` and with `Const<n>` gives bitwise identical trajectories, events
//! and counters (tested). Every vector an integrator or an [`EventState`]
//! needs is allocated when it is built (or, for an [`EventState`], on first
//! use); after that, `step`, `dense`, `truncate`, `reset` and
//! [`find_first_event`] never allocate, for `Dyn` too (tested with a counting
//! allocator). Integration runs forward in time only
//! ($t_{\text{bound}} \ge t$).
//!
//! # Examples
//!
//! The convenience driver with outputs on a grid:
//!
//! ```
//! use jeffcott::ode::{solve, Dop853, NoEvents, Options, Recorder};
//! use nalgebra::SVector;
//!
//! let osc = |_t: f64, y: &SVector<f64, 2>, dy: &mut SVector<f64, 2>| {
//!     dy[0] = y[1];
//!     dy[1] = -y[0];
//! };
//! let mut integ = Dop853::new(Options::with_tol(1e-10, 1e-12))?;
//! let mut rec = Recorder::with_grid(vec![1.0, 2.0]);
//! let y0 = SVector::<f64, 2>::new(1.0, 0.0);
//! let rep = solve(&mut integ, &osc, 0.0, &y0, 2.0, &NoEvents, &mut rec)?;
//! assert_eq!(rep.t, 2.0);
//! assert!((rec.outputs[0].1[0] - 1f64.cos()).abs() < 1e-8);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The same with a dimension known at run time:
//!
//! ```
//! use jeffcott::ode::{solve, Dop853, NoEvents, Options, Recorder};
//! use nalgebra::{DVector, Dyn};
//!
//! let n = 2;
//! let osc = |_t: f64, y: &DVector<f64>, dy: &mut DVector<f64>| {
//!     dy[0] = y[1];
//!     dy[1] = -y[0];
//! };
//! let mut integ = Dop853::with_dim(Dyn(n), Options::with_tol(1e-10, 1e-12))?;
//! let mut rec = Recorder::with_grid(vec![1.0]);
//! let y0 = DVector::from_vec(vec![1.0, 0.0]);
//! solve(&mut integ, &osc, 0.0, &y0, 1.0, &NoEvents, &mut rec)?;
//! assert!((rec.outputs[0].1[0] - 1f64.cos()).abs() < 1e-8);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A hybrid loop (as a piecewise-smooth driver would write it): step, look
//! for an event on the step, truncate there, apply a reset map, restart.
//! The bouncing ball below keeps its step size across impacts, so steps soon
//! span whole flights; the start-of-segment rule of [`events`] still finds
//! every impact.
//!
//! ```
//! use jeffcott::ode::{
//!     find_first_event, Dop853, EventOptions, EventSet, EventState, Integrator,
//!     Options,
//! };
//! use jeffcott::numeric::Direction;
//! use nalgebra::{SVector, U2};
//! type V2 = SVector<f64, 2>;
//!
//! /// Impact when the height x[0] falls through 0.
//! struct Floor;
//! impl EventSet<U2> for Floor {
//!     fn len(&self) -> usize { 1 }
//!     fn direction(&self, _i: usize) -> Direction { Direction::Falling }
//!     fn value(&self, _i: usize, _t: f64, y: &V2) -> f64 { y[0] }
//! }
//! let ball = |_t: f64, y: &V2, dy: &mut V2| {
//!     dy[0] = y[1];
//!     dy[1] = -1.0;
//! };
//! let mut integ = Dop853::new(Options::with_tol(1e-12, 1e-12))?;
//! integ.reset(&ball, 0.0, &V2::new(0.5, 0.0), false)?;
//! let mut state = EventState::new();
//! let opts = EventOptions::default();
//! let mut impacts = Vec::new();
//! while impacts.len() < 10 {
//!     integ.step(&ball, 20.0)?;
//!     if let Some(hit) = find_first_event(&mut integ, &ball, &Floor, &opts, &mut state)? {
//!         let (t_hit, y_hit) = (hit.t, hit.y);
//!         integ.truncate(&ball, t_hit)?;
//!         let y_new = V2::new(y_hit[0], -0.8 * y_hit[1]); // reset map
//!         integ.reset(&ball, t_hit, &y_new, true)?; // keep the step size
//!         state.reset();
//!         impacts.push(t_hit);
//!     }
//!     assert!(integ.y()[0] > -1e-9, "fell through the floor at t = {}", integ.t());
//! }
//! // Dropped from 0.5 under unit gravity: t_1 = 1, then flights of 2 * 0.8^k.
//! let t10 = 1.0 + (1..10).map(|k| 2.0 * 0.8f64.powi(k)).sum::<f64>();
//! assert!((impacts[0] - 1.0).abs() < 1e-12 && (impacts[9] - t10).abs() < 1e-10);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Step-size control
//!
//! For a trial step $y_0 \to y_1$ with local error estimate $e$ the scaled
//! error is the RMS norm over the $n_c$ error-controlled components
//! $$\mathrm{err} = \sqrt{\tfrac{1}{n_c} \sum_i \big(e_i / s_i\big)^2},\qquad
//! s_i = \mathrm{atol}\_i + \mathrm{rtol}\_i \max(|y_{0,i}|, |y_{1,i}|),$$
//! (DOP853 uses Hairer's combination of its 5th- and 3rd-order estimates).
//! A component with $\mathrm{atol}\_i = +\infty$ has $s_i = \infty$: it adds
//! nothing to the sum and is not counted in $n_c$ (see [`Options::atol`]);
//! otherwise $n_c = N$. The step is accepted when $\mathrm{err} \le 1$ and the
//! next step is $h_{\text{new}} = h \cdot \mathrm{clamp}\big(\mathrm{safety}\thinspace
//! \mathrm{err}^{-\alpha}\thinspace\mathrm{err}_{\text{old}}^{\beta},\ \mathrm{fac\\_min},
//! \ \mathrm{fac\\_max}\big)$ (Gustafsson's PI controller as in Hairer's codes;
//! see [integrators.md](https://docs.rs/crate/jeffcott/latest/source/docs/integrators.md)).

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

mod any;
mod controller;
mod core;
mod dop853;
mod dopri5;
mod error;
pub mod events;
pub(crate) mod kernels;
mod options;
mod radau5;
mod rk4;
mod solve;

pub use any::{AnyIntegrator, Method};
pub use dop853::Dop853;
pub use dopri5::Dopri5;
pub use error::OdeError;
pub use events::{
    find_first_event, EventDerivative, EventFns, EventHit, EventOptions, EventSet, EventState,
    NoDerivative, NoEvents, MAX_SAMPLES,
};
pub use options::{Options, Tolerance};
pub use radau5::Radau5;
pub use rk4::Rk4;
pub use solve::{solve, solve_with, Observer, Recorder, SolveError, SolveReport, Stopped};

/// A first-order ODE system $\dot y = f(t, y)$ with $y \in \mathbb{R}^N$, $N$
/// the size of the dimension `D`.
///
/// Closures `Fn(f64, &OVector<f64, D>, &mut OVector<f64, D>)` implement this
/// trait, so `|t, y: &SVector<f64, 2>, dy: &mut SVector<f64, 2>| { ... }` and
/// `|t, y: &DVector<f64>, dy: &mut DVector<f64>| { ... }` are systems.
pub trait OdeSystem<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Writes $f(t, y)$ into `dy` (every component must be written; `dy` has
    /// the length of `y`).
    fn rhs(&self, t: f64, y: &OVector<f64, D>, dy: &mut OVector<f64, D>);

    /// Writes the Jacobian $J_{ij} = \partial f_i / \partial y_j$ at $(t, y)$ into `jac` and
    /// returns `true`, or returns `false` (the default) when the system does not provide one.
    ///
    /// Only the implicit method [`Radau5`] uses it; without it Radau5 approximates $J$ by
    /// forward differences, one evaluation of $f$ per column with RADAU5's increment
    /// $\delta_j = \sqrt{\varepsilon \max(10^{-5}, |y_j|)}$. An analytic Jacobian saves those
    /// $N$ evaluations per Jacobian and is exact; it need not be: the simplified Newton
    /// iteration only needs an approximation, and a poor one shows as slow convergence
    /// (more iterations, smaller steps), never as a wrong step. Every entry must be written
    /// (`jac` holds the previous Jacobian on entry).
    ///
    /// ```
    /// use jeffcott::ode::{JacobianMut, OdeSystem};
    /// use nalgebra::{SVector, U2};
    ///
    /// /// Van der Pol's oscillator, $\varepsilon y_2' = (1 - y_1^2) y_2 - y_1$.
    /// struct VdP(f64);
    /// impl OdeSystem<U2> for VdP {
    ///     fn rhs(&self, _t: f64, y: &SVector<f64, 2>, dy: &mut SVector<f64, 2>) {
    ///         dy[0] = y[1];
    ///         dy[1] = ((1.0 - y[0] * y[0]) * y[1] - y[0]) / self.0;
    ///     }
    ///     fn jacobian(&self, _t: f64, y: &SVector<f64, 2>, jac: &mut JacobianMut<'_, U2>) -> bool {
    ///         jac[(0, 0)] = 0.0;
    ///         jac[(0, 1)] = 1.0;
    ///         jac[(1, 0)] = (-2.0 * y[0] * y[1] - 1.0) / self.0;
    ///         jac[(1, 1)] = (1.0 - y[0] * y[0]) / self.0;
    ///         true
    ///     }
    /// }
    /// # let _ = VdP(1e-3);
    /// ```
    fn jacobian(&self, t: f64, y: &OVector<f64, D>, jac: &mut JacobianMut<'_, D>) -> bool {
        let _ = (t, y, jac);
        false
    }
}

/// A mutable view of an $N\times N$ Jacobian (column-major, over storage the integrator
/// owns, so that no allocator bound on $N\times N$ matrices is needed): index it as
/// `jac[(i, j)]` for $\partial f_i/\partial y_j$. See [`OdeSystem::jacobian`].
pub type JacobianMut<'a, D> = nalgebra::MatrixViewMut<'a, f64, D, D>;

impl<D: Dim, F> OdeSystem<D> for F
where
    DefaultAllocator: Allocator<D>,
    F: Fn(f64, &OVector<f64, D>, &mut OVector<f64, D>),
{
    #[inline]
    fn rhs(&self, t: f64, y: &OVector<f64, D>, dy: &mut OVector<f64, D>) {
        self(t, y, dy)
    }
}

/// Work counters of an integrator (since construction).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stats {
    /// Accepted steps.
    pub steps: u64,
    /// Rejected step attempts (error too large or non-finite values).
    pub rejected: u64,
    /// Evaluations of the right-hand side $f$ (including dense-output stages,
    /// truncations, resets and evaluations made by the event detector).
    pub rhs_evals: u64,
    /// Events reported by [`find_first_event`].
    pub events: u64,
    /// Jacobians of $f$ computed (analytic or by finite differences; the $N$ evaluations of
    /// $f$ of a finite-difference Jacobian are counted in `rhs_evals` too). 0 for the
    /// explicit methods.
    #[cfg_attr(feature = "serde", serde(default))]
    pub jacobians: u64,
    /// LU decompositions of the Newton matrices (Radau5 counts its real and its complex
    /// decomposition as one). 0 for the explicit methods.
    #[cfg_attr(feature = "serde", serde(default))]
    pub lu_decompositions: u64,
}

/// A one-step integrator with dense output (the explicit methods and [`Radau5`]).
///
/// Typical use: `reset` once, then `step` repeatedly towards a bound; after
/// each step, `dense` interpolates on $[t_{\text{prev}}, t]$ and
/// [`find_first_event`] looks for events; `truncate` moves the current point
/// back to an event inside the step. None of these allocates.
pub trait Integrator<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Start (or restart after a discontinuity/reset) at `(t, y)`: evaluates
    /// $f(t, y)$, clears the last step (dense output becomes the constant
    /// `y`) and the per-reset attempt counter. Keeps the last step-size
    /// suggestion if `keep_step` is true and one exists (useful after
    /// events), otherwise selects an initial step (`h_init` or Hairer's
    /// automatic choice). A `y` of another length than the integrator's
    /// dimension is [`OdeError::DimensionMismatch`].
    fn reset<S: OdeSystem<D>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &OVector<f64, D>,
        keep_step: bool,
    ) -> Result<(), OdeError>;
    /// Take one accepted step (internally retrying rejected ones), never
    /// beyond `t_bound`; the step lands exactly on `t_bound` if it reaches
    /// it (a step that would end within 1% of a step beyond the bound is
    /// stretched to it). `t_bound == t()` is a no-op.
    fn step<S: OdeSystem<D>>(&mut self, sys: &S, t_bound: f64) -> Result<(), OdeError>;
    /// Current time (right end of the last step).
    fn t(&self) -> f64;
    /// Current state.
    fn y(&self) -> &OVector<f64, D>;
    /// Left end of the last accepted step (equals `t()` right after reset).
    fn t_prev(&self) -> f64;
    /// State at `t_prev()`.
    fn y_prev(&self) -> &OVector<f64, D>;
    /// Dense output on the last accepted step $[t_{\text{prev}}, t]$ at full
    /// order (DOP853: 7th order, 3 extra rhs evaluations computed lazily once
    /// per step; DOPRI5: 4th order; RK4: cubic Hermite; RADAU5: the collocation cubic). Times outside the
    /// step extrapolate the same polynomial (no panic). Before the first
    /// step, returns `y()`. An `out` of the wrong length (possible for `Dyn`
    /// only) is replaced by a vector of the right one.
    fn dense<S: OdeSystem<D>>(&mut self, sys: &S, t: f64, out: &mut OVector<f64, D>);
    /// Truncate the last step at `t_new` in $(t_{\text{prev}}, t]$: the current point becomes
    /// `(t_new, y_new)` and $f$ is re-evaluated there; the step-size suggestion is kept, and
    /// `dense` stays valid on $[t_{\text{prev}}, t_{\text{new}}]$. The explicit methods take
    /// `y_new = dense(t_new)`; [`Radau5`] takes the step again to `t_new` (its dense output
    /// is of order 3, its steps of order 5), so after an event restart from [`Integrator::y`],
    /// which is at least as accurate as the dense output ([`EventHit::y`]).
    fn truncate<S: OdeSystem<D>>(&mut self, sys: &S, t_new: f64) -> Result<(), OdeError>;
    /// Work counters.
    fn stats(&self) -> &Stats;
    /// Mutable work counters, for drivers and event code that evaluate the
    /// system themselves.
    fn stats_mut(&mut self) -> &mut Stats;
    /// The options.
    fn options(&self) -> &Options<D>;
    /// The current step-size suggestion for the next step (0 before reset).
    fn h_next(&self) -> f64;
    /// Name for reports: `"DOP853"`, `"DOPRI5"`, `"RK4"`, `"RADAU5"`.
    fn name(&self) -> &'static str;
    /// The dimension of the state.
    fn dim(&self) -> D {
        self.y().shape_generic().0
    }
    /// $f(t, y)$ at the current point, if the integrator keeps it (the crate's integrators
    /// do: it is the first stage of the next step). Lets the event detector read the state's
    /// derivative at a step's ends instead of evaluating $f$. Default: `None`.
    fn dy(&self) -> Option<&OVector<f64, D>> {
        None
    }
    /// $f$ at [`Integrator::t_prev`], if kept (see [`Integrator::dy`]). Default: `None`.
    fn dy_prev(&self) -> Option<&OVector<f64, D>> {
        None
    }
}
