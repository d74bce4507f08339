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
//! * [`Etd4`] — an exponential integrator (ETDRK4 with step doubling) for systems whose
//!   linear part is diagonal in their own coordinates ([`OdeSystem::linear_part`]): exact for
//!   the linear part and a forcing declared with it, $O(N)$ a step, steps set by the rest of
//!   the right-hand side,
//! * [`AnyIntegrator`] — enum dispatch over the five, selected at run time by
//!   [`Method`],
//! * [events](#events) — event functions $g_i(t, y)$ (as a trait, or from closures
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
//! span whole flights; the start-of-segment rule of [events](#events) still finds
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
//! (DOP853 uses Hairer's combination of its 5th- and 3rd-order estimates, per component).
//! A component with $\mathrm{atol}\_i = +\infty$ has $s_i = \infty$: it adds
//! nothing to the sum and is not counted in $n_c$ (see [`Options::atol`]);
//! otherwise $n_c = N$. The step is accepted when $\mathrm{err} \le 1$ and the
//! next step is $h_{\text{new}} = h \cdot \mathrm{clamp}\big(\mathrm{safety}\thinspace
//! \mathrm{err}^{-\alpha}\thinspace\mathrm{err}_{\text{old}}^{\beta},\ \mathrm{fac\\_min},
//! \ \mathrm{fac\\_max}\big)$ (Gustafsson's PI controller as in Hairer's codes;
//! see [integrators.md](https://docs.rs/crate/jeffcott/latest/source/docs/integrators.md)).
//!
//! # Events
//!
//! Event functions, their detection on the dense output of the last step, and
//! root location by the Illinois method ([`numeric::illinois`](crate::numeric::illinois)).
//!
//! An event set is either a type implementing [`EventSet`] or a list of
//! closures wrapped in [`EventFns`]. [`find_first_event`] looks for the
//! earliest crossing on the last step of an [`Integrator`];
//! [`EventState`] carries what it needs between calls (the segment origin,
//! per-event bookkeeping sized from the set, and scratch vectors), so that
//! detection never allocates once warm, whatever the dimension and however
//! many events the set has.
//!
//! ## Detection
//!
//! For the last accepted step $[t_{\text{prev}}, t]$ (or its part after the
//! last reported hit, see [`EventState`]) the detector evaluates every active
//! event $g_i$ at `samples_per_step` equally spaced interior dense-output
//! points plus both ends, every event of a sample at once
//! ([`EventSet::values_and_derivatives`]: a set whose events share work, a
//! contact location, does it once a sample). Scanning the sample intervals in
//! time order:
//!
//! * **sign change** — $g_i(a) \ne 0$ and ($g_i(b) = 0$ or
//!   $\operatorname{sign} g_i(b) \ne \operatorname{sign} g_i(a)$): a crossing
//!   bracketed in $[a, b]$; rising if $g_i(a) < 0$, falling otherwise. If the
//!   direction is allowed, the root is located by the Illinois method.
//! * **grazing pair** — no sign change, but the event supplies
//!   [`EventSet::derivative`] and $\dot g_i$ changes sign between $a$ and $b$
//!   (the derivative is evaluated with $\dot y = f(t, y_{\text{dense}}(t))$,
//!   at the step's ends the integrator's own $f$ ([`Integrator::dy`]), and no
//!   $f$ at all for an event whose derivative does not read it,
//!   [`EventSet::derivative_needs_rhs_of`]):
//!   the extremum is bracketed; the Illinois method on $\dot g_i$ moves
//!   towards it, and as soon as a probe $c$ has $g_i(c)$ of the opposite sign
//!   the two roots are bracketed by $[a, c]$ and $[c, b]$ (a probe where $g_i$ is
//!   exactly zero does not stop it: next to a start where the guard leaves zero
//!   it reads zero by rounding, and only a point strictly across brackets the
//!   second root; it is the crossing if none is found). The first one in an
//!   allowed direction is located.
//!
//! The first interval that yields a located root ends the scan; among the
//! roots found in that interval the earliest wins, ties going to the lowest
//! event index. The reported time is the end of the final bracket on the
//! *post-crossing* side (so $g_i$ there already has its new sign, or is 0),
//! and the bracket is narrower than the time tolerance
//! $\max(\text{root\\_tol}, 4\varepsilon|t|)$.
//!
//!   The extremum is searched when the cubic Hermite interpolant of
//!   $g_i$ through the two samples (values and derivatives) gets at least
//!   halfway from the nearer end value towards zero, or across it. An
//!   extremum of the interpolant far from zero (the usual case, e.g. a ring
//!   coordinate turning back well inside its preload) costs one value and
//!   derivative of $g_i$ there, which must confirm it: on the same side, within
//!   a quarter of the nearer end value $m$ of the interpolant, its slope within
//!   $m/h$ of the interpolant's over an interval of length $h$, and not halfway
//!   to zero either (else the extremum is searched); so do the two extrema that derivatives
//!   of the same sign imply when the end values move against them. A crossing
//!   seen there is located; a guard that contradicts its interpolant splits the
//!   interval there, each half checked the same way up to 4 levels, then the
//!   extremum is searched. A sample interval longer than the guard's time scale
//!   can have quiet ends while $g_i$ swings through zero between them.
//!
//! **Guarantee.** Relative to the dense-output interpolant $u(t)$, every
//! crossing of an allowed direction is found, provided that between two
//! consecutive samples $g_i(t, u(t))$ has at most one root, or has two roots
//! and at most one extremum, the event supplies its derivative, and the
//! cubic Hermite interpolant of the samples places that extremum at least
//! halfway to zero or is contradicted by $g_i$ at a point checked (true
//! whenever the Hermite interpolant's error is below half the end values; a
//! dip narrower than the checks, about 1/16 of the interval, can be missed).
//! Pairs of roots inside one sample interval are invisible without the
//! derivative (see the tests: a $10^{-6}$-deep dip inside one large step is
//! found with the derivative and missed by the plain sign check). At the
//! start of a segment the rule below adds its own condition.
//!
//! The screens need the slope of $g_i(t, u(t))$; they take the event's rate along the flow
//! (with $f(u)$), which is that slope where $u$ is tangent to $f$. The explicit methods'
//! interpolants are built on $f$ at each step's start. [`Radau5`]'s dense output is made
//! tangent to $f$ on the first step after a reset (the segment origin, where a guard can sit
//! on zero with a rate of 0, as at a contact loss; its collocation polynomial alone leaves
//! the start off tangent by the stage error, enough to cross such a guard and come back);
//! on later steps it is the collocation polynomial, whose slope at the start differs from
//! $f$ by the stage error, as its values do inside the step.
//!
//! Every step is sampled: there is no step-end screen (0.2.0 had one, `EventOptions::screen`,
//! which skipped a guard whose cubic Hermite interpolant of the step's ends stayed away from
//! zero; it was removed because nothing at a step's ends bounds the guard between them: on a
//! step longer than the guard's time scale it cleared crossings, issue 16's class S).
//!
//! ## Start of a segment and re-arming (no immediate re-firing)
//!
//! The *segment origin* $t_o$ is the left end of the first step scanned after
//! [`EventState::new`]/[`EventState::reset`], or the time of the last hit
//! returned. Let $s$ be the length of the scanned step, $m$ =
//! `samples_per_step`, $t_1$ the first interior sample, and
//! $w = \max(\text{rearm\\_time}, 2\thinspace\text{tol})$ the *re-arm window*,
//! with tol the time tolerance at the end of the step (twice the bracket
//! width allowed to the root that defined the origin). At the origin:
//!
//! 1. an event with $|g_i(t_o)| >$ `value_tol` is armed with its sign; one
//!    with $|g_i(t_o)| \le$ `value_tol` (default: exactly 0) is disarmed until
//!    the first sample with $|g_i| >$ `value_tol`, which becomes its
//!    reference;
//! 2. the event of the hit that defined the origin (if the state was not
//!    reset since) stays armed with its post-crossing sign, so that a
//!    crossing back inside the same sample interval (the second root of a
//!    grazing pair) is still found;
//! 3. **a guard on zero leaves it in the direction it is moving.** Any other
//!    event is *on zero* at $t_o$ if $|g_i(t_o)| \le$ `value_tol`, or if it
//!    is within the window of zero, whichever way it moves:
//!    $|g_i(t_o)| \le |\dot g_i|\thinspace w$ (the round-off left by a located
//!    root or a reset map, on either side of zero; a guard a few ulps on its
//!    new side, moving away, may read the old side next to the start, and a
//!    root searched from there lands in that rounding). A derivative of exactly zero is a derivative: such
//!    a guard is on zero only within `value_tol`, and one off zero (offset by a
//!    margin at a tangency) that curves through zero inside the window crosses.
//!    Its direction of motion is the sign of
//!    $\dot g_i(t_o)$ if the set supplies [`EventSet::derivative`] (and it is
//!    non-zero); otherwise the sign of $g_i$ at the *probe time*
//!    $t_p = t_o + \delta$ on the dense output, with
//!    $$\delta = \min\big(\max(4w,\ 2^{-20} s),\ s/(2(m+1))\big)$$
//!    (beyond the window, about a millionth of the step, inside the first
//!    half of the first sample interval), the slope of the test above then
//!    being the secant $(g_i(t_p) - g_i(t_o))/\delta$. Leaving zero is the
//!    zero at the start time, never an event. A guard that leaves zero
//!    *away* from its allowed crossing direction (the `Falling` floor guard
//!    of a ball bouncing up) and crosses back is an event, found even when
//!    both crossings fall inside the first sample interval (steps spanning
//!    whole flights), where the samples at its ends have the same sign: when
//!    the first sample $t_k$ with $|g_i| >$ `value_tol` (for a guard armed at
//!    the origin: $t_1$, with no grazing pair found and no sign change; or
//!    with a sign change, first of all when its derivative pointed away from
//!    $t_1$'s side, since next to the start its rounding may read either side
//!    of zero, beyond the window where it moves slowly; else when the root
//!    searched from the start is within the window, the start's zero)
//!    shows the guard on the side it must cross back into, in an allowed
//!    direction, and its motion at $t_o$ pointed the other way, the detector
//!    evaluates $g_i(t_p)$; if it is beyond `value_tol` on the other side,
//!    the crossing back is located in $[t_p, t_k]$. If it is already back on
//!    the side of $t_k$ while the derivative at $t_o$ pointed away (an
//!    excursion shorter than $\delta$), the offset is halved,
//!    $t_o + \delta/2, t_o + \delta/4, \ldots$ down to $w$, until a point is on
//!    the departure side, and the crossing back is located between it and
//!    $t_p$.
//!    **Conditions.** The probe is made only when it can change the result
//!    (a set whose guards never sit on zero sees exactly the evaluations of
//!    the plain rules). A guard that returns to zero within $w$ of the
//!    origin (within $\delta$ without a derivative) is taken as part of the
//!    start. Without a derivative, the probe
//!    is made for a guard armed at the origin only if $|g_i(t_1)| \ge
//!    |g_i(t_o)|$; a departure and return that leave the first sample closer
//!    to zero than the origin is a pair of roots inside one sample interval,
//!    which needs the derivative (see the guarantee above). The motion is
//!    read correctly when the guard moves off zero faster than its round-off:
//!    with `value_tol` = 0 and roots located to a few ulp this holds unless it
//!    is tangent to zero at $t_o$;
//! 4. a root located within the re-arm window $w$ after $t_o$ of the event
//!    that just fired or of a guard on zero at $t_o$ (rule 3) is treated as
//!    the zero at the start time (round-off of the event that just fired or of
//!    a reset map) and is ignored; scanning continues after it. A root of any
//!    other guard, however close to $t_o$, is a crossing: a guard that starts
//!    off zero and comes back through it within the window (a non-smooth
//!    guard such as $|s| - D$ passing its kink, or a fast one late in a long
//!    run, where $w$ is large) is not round-off.
//!
//! Away from the origin, a sample with $g_i = 0$ exactly is the right end of
//! a reported crossing (if its direction was allowed) and the event stays
//! disarmed until $g_i \ne 0$ again, so a root is never reported twice.
//!
//! **NaN is not a sign.** An event that returns NaN where the detector needs its sign stops
//! the scan with [`OdeError::EventNotANumber`]: at the start of the scanned step; at a sample,
//! unless another event crosses earlier in that sample interval and this one has a value at
//! the pre-crossing end of that root's bracket (then it is located before it if it has crossed
//! by then; an event undefined beyond another's crossing, such as a contact force once the
//! contact is lost, is allowed); at the probe points of rule 3; inside a root or extremum
//! search ([`numeric::illinois`](crate::numeric::illinois) stops at a NaN, not converged). An event
//! function must have a value wherever the integration may go before another event ends it.
//! A NaN *derivative* inside the extremum search of a grazing pair ends that search without a
//! result, as for an event without a derivative (a pair of roots inside one sample interval
//! may then be missed, see the guarantee above).

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

mod any;
mod controller;
mod core;
mod dop853;
mod dopri5;
mod erk;
mod error;
mod etd4;
mod events;
pub(crate) mod kernels;
mod linear_part;
mod options;
mod radau5;
mod rk4;
mod solve;

pub use any::{AnyIntegrator, Method};
pub use dop853::Dop853;
pub use dopri5::Dopri5;
pub use error::OdeError;
pub use etd4::Etd4;
pub use events::{
    find_first_event, EventDerivative, EventFns, EventHit, EventOptions, EventSet, EventState,
    NoDerivative, NoEvents, MAX_SAMPLES,
};
pub use linear_part::{
    phi_functions, phi_functions_to, BlockForcing, DiagonalLinearPart, DiagonalSprings,
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

    /// $p$ when the system is of second order in its first $2p$ components: the state is
    /// $y = (q, v, z)$ with positions $q$ and velocities $v$ in $\mathbb R^p$ and any other
    /// components $z$ after them, and $q^\prime = v$ **exactly** (`dy[i] = y[p + i]` for
    /// $i < p$, nothing else in those rows). Default `None`.
    ///
    /// Only [`Radau5`] uses it: its Newton matrices $cI - J$ ($c = \gamma/h$ real, $c =
    /// (\alpha + i\beta)/h$ complex) have the Jacobian
    /// $J = \begin{pmatrix} 0 & I & 0\\\\ A_q & A_v & A_z\\\\ G_q & G_v & G_z\end{pmatrix}$,
    /// and eliminating $x_q = (b_q + x_v)/c$ from $(cI - J)x = b$ leaves
    /// $$\Big(cI - \begin{pmatrix} A_v + A_q/c & A_z\\\\ G_v + G_q/c & G_z\end{pmatrix}\Big)
    /// \begin{pmatrix}x_v\\\\ x_z\end{pmatrix} = \begin{pmatrix}b_v\\\\ b_z\end{pmatrix} +
    /// \frac1c\begin{pmatrix}A_q\\\\ G_q\end{pmatrix} b_q,$$
    /// of size $N - p$ instead of $N$ (Hairer and Wanner's RADAU5 option `M1` = `M2` = $p$).
    /// For a mechanical system, $N = 2p + m$, the LU decompositions, which dominate a step's
    /// cost for large $N$, become up to 8 times cheaper. The rows of $J$ for $q$ are not read
    /// (the structure gives them); a system whose position rows are not exactly $v$ gets a
    /// wrong Newton matrix, which shows as slow convergence, never as a wrong step. A value
    /// with $2p > N$ is ignored.
    fn second_order(&self) -> Option<usize> {
        None
    }

    /// The linear part $L$ of $f(t, y) = L y + g(t) + N(t, y)$ when it is diagonal in real and
    /// complex blocks in the system's own coordinates ([`DiagonalLinearPart`]; e.g. a linear
    /// system in its modal coordinates), with the forcing $g$ of its blocks at one frequency
    /// if declared ([`DiagonalLinearPart::with_forcing`]), or `None` (the default).
    ///
    /// Only the exponential integrator [`Etd4`] uses it (and refuses a system without one,
    /// [`OdeError::NoLinearPart`]): it propagates $L$ and $g$ exactly and integrates only
    /// $N = f - Ly - g$, so its steps follow $N$ (a contact force, a forcing not declared) and
    /// not the fastest mode of $L$ or the declared forcing. Any $L$ and $g$ are *correct* (the
    /// split is exact: $N$ is computed as $f - Ly - g$); the method is *efficient* when $N$ is
    /// smooth and mild where $L$ is stiff.
    fn linear_part(&self) -> Option<&DiagonalLinearPart> {
        None
    }

    /// For a system of second order ([`OdeSystem::second_order`] = $p$): the diagonal springs
    /// and dampers $k$, $d \in \mathbb R^p$ of its Jacobian's velocity rows,
    /// $A_q = -\mathrm{diag}(k) + \dots$, $A_v = -\mathrm{diag}(d) + \dots$, where the rest
    /// of $J$ (the dots, with the rows and columns of the other components $z$) is of low rank:
    /// a modal model whose modes are coupled only by a force acting through a few coordinates
    /// (a contact at a station: rank 2). Default `None`.
    ///
    /// Only [`Radau5`] uses it: its condensed Newton matrix is then $D + UW^\top$, $D$
    /// diagonal ($c + d_i + k_i/c$), and it solves with the Sherman-Morrison-Woodbury formula
    /// at $O(Nr)$ a solve instead of a dense LU at $O(N^3)$. The rank $r$ is found from the
    /// Jacobian at each factorisation (at most [`DiagonalSprings::MAX_RANK`]); where the
    /// rest is not of low rank (the values are wrong, the coupling is full), Radau5 falls back
    /// to the dense LU: a wrong value costs time, never accuracy.
    fn diagonal_springs(&self) -> Option<DiagonalSprings<'_>> {
        None
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
    /// Of `lu_decompositions`, those made as diagonal plus low rank, for the Woodbury formula
    /// ([`OdeSystem::diagonal_springs`]): $O(N)$ each instead of $O(N^3)$.
    #[cfg_attr(feature = "serde", serde(default))]
    pub woodbury_decompositions: u64,
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
