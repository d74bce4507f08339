//! Event functions, their detection on the dense output of the last step, and
//! root location by the Illinois method ([`numeric::illinois`](crate::numeric::illinois)).
//!
//! An event set is either a type implementing [`EventSet`] or a list of
//! closures wrapped in [`EventFns`]. [`find_first_event`] looks for the
//! earliest crossing on the last step of an [`Integrator`](super::Integrator);
//! [`EventState`] carries what it needs between calls (the segment origin,
//! per-event bookkeeping sized from the set, and scratch vectors), so that
//! detection never allocates once warm, whatever the dimension and however
//! many events the set has.
//!
//! # Detection
//!
//! For the last accepted step $[t_{\text{prev}}, t]$ (or its part after the
//! last reported hit, see [`EventState`]) the detector evaluates every active
//! event $g_i$ at `samples_per_step` equally spaced interior dense-output
//! points plus both ends. Scanning the sample intervals in time order:
//!
//! * **sign change** — $g_i(a) \ne 0$ and ($g_i(b) = 0$ or
//!   $\operatorname{sign} g_i(b) \ne \operatorname{sign} g_i(a)$): a crossing
//!   bracketed in $[a, b]$; rising if $g_i(a) < 0$, falling otherwise. If the
//!   direction is allowed, the root is located by the Illinois method.
//! * **grazing pair** — no sign change, but the event supplies
//!   [`EventSet::derivative`] and $\dot g_i$ changes sign between $a$ and $b$
//!   (the derivative is evaluated with $\dot y = f(t, y_{\text{dense}}(t))$):
//!   the extremum is bracketed; the Illinois method on $\dot g_i$ moves
//!   towards it, and as soon as a probe $c$ has $g_i(c)$ of the opposite sign
//!   (or zero) the two roots are bracketed by $[a, c]$ and $[c, b]$. The
//!   first one in an allowed direction is located.
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
//! # Screening (opt-in: [`EventOptions::screen`])
//!
//! Before sampling, every active event is evaluated at the step's end, with its derivative
//! (the state's derivative there is the integrator's own $f$, [`Integrator::dy`](crate::ode::Integrator::dy); no
//! right-hand side is evaluated). With the values and derivatives at both ends,
//! $(g_a, \dot g_a)$ and $(g_b, \dot g_b)$, an event is **cleared** for the step when
//!
//! * it has a derivative, is armed as usual (not on zero at a segment origin, not the event
//!   that just fired), and $g_a$, $g_b$ are non-zero of the same sign;
//! * the cubic Hermite interpolant $p$ of the two ends stays on that side by at least half the
//!   smaller end value on the whole step: $\operatorname{sign}(g_a)\thinspace p(t) \ge m/2$,
//!   $m = \min(|g_a|, |g_b|)$ (checked at the interior extrema of $p$);
//! * **the premise holds at the midpoint**: the event on the dense output there, $G(1/2)$, is
//!   on that side and within $m/4$ of $p(1/2)$ (one dense-output point per step that has an
//!   event passing the tests above, every such event's value there).
//!
//! A cleared event is not sampled on that step; a step where every active event is cleared
//! is done after the end evaluations and the midpoint, without sampling. The others are sampled as
//! described above. The end values are kept and reused as the start values of the next step
//! when it starts at the same time with bitwise the same state (call
//! [`EventState::reset`] when the event set changes).
//!
//! **Guarantee of the screen.** Relative to the dense output $u$, a cleared event has no root
//! on the step provided the interpolant's error stays below half the smaller end value:
//! $|g(t, u(t)) - p(t)| < m/2$ on the step. The error vanishes to second order at both ends,
//! $G - p = s^2(1-s)^2 r(s)$ with $G(t) = g(t, u(t))$ and $s$ the fraction of the step, and
//! the midpoint test bounds $|r(1/2)| \le 4m$: the premise holds whenever $r$ varies by less
//! than a factor 2 over the step. The ends alone cannot show it: a step longer than the
//! motion's time scale (a loose tolerance, a stiff contact) can have a dense output that
//! swings through zero between quiet ends (issue 16's class S: a contact guard of $0.32$ and
//! $0.25$ at the ends, $-0.10$ at mid-step, cleared by the ends' test alone). The error of a
//! cubic Hermite interpolant over a step of length $h$ is at most $h^4 \max|G^{(4)}|/384$ with $G(t) = g(t, u(t))$ (at the
//! ends, $u$ and its derivative are the integrator's $y$ and $f$, so $\dot g$ there is the
//! derivative of $G$). **Conditions:** a derivative that is exact at the ends; a step over
//! which $G$ is smooth; and the bound above. A dip that the interpolant cannot see by more
//! than $m/2$ with an $r$ that varies by more than a factor 2 over the step can be missed
//! where the samples would have found it; a constant $r$ (a quartic term) is caught (test
//! `the_screen_checks_its_premise_at_mid_step`). An event whose end value
//! is tiny (a guard just off zero) has a tiny $m$: the screen still clears it when the
//! interpolant moves away from zero, outside the stated bound, as the first sample interval
//! does without the screen. Events on zero at a segment origin are never cleared: they follow
//! the start-of-segment rule below on the samples.
//!
//! # Start of a segment and re-arming (no immediate re-firing)
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
//!    reaches zero within the window: $g_i \dot g_i < 0$ and
//!    $|g_i(t_o)| \le |\dot g_i|\thinspace w$ (the round-off left by a located
//!    root or a reset map). Its direction of motion is the sign of
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
//!    the origin: $t_1$, with no sign change and no grazing pair found)
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

mod closures;
mod detect;
mod state;

pub use closures::{EventDerivative, EventFns, NoDerivative};
pub use detect::find_first_event;
pub use state::EventState;

use super::OdeError;
use crate::numeric::Direction;
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

/// Maximum number of interior samples per step
/// ([`EventOptions::samples_per_step`]).
pub const MAX_SAMPLES: usize = 64;

/// A set of event functions $g_i(t, y)$, $i <$ `len()` (any number: the
/// detector's bookkeeping grows with the largest set it has seen).
pub trait EventSet<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Number of events.
    fn len(&self) -> usize;
    /// Whether the set is empty.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Allowed crossing direction of event `i`.
    fn direction(&self, i: usize) -> Direction;
    /// Whether event `i` stops the integration ([`solve`](super::solve())).
    fn terminal(&self, i: usize) -> bool {
        let _ = i;
        true
    }
    /// Value $g_i(t, y)$.
    fn value(&self, i: usize, t: f64, y: &OVector<f64, D>) -> f64;
    /// Optional time derivative of event `i` along the flow,
    /// $\dot g_i = \partial_t g_i + \nabla_y g_i \cdot \dot y$, given `y` and
    /// `dy` $= f(t, y)$; enables detection of grazing (two roots inside one
    /// sample interval without a sign change) and gives the direction of a
    /// guard that is zero at the start of a segment. Must return `None` for
    /// every argument when not available (the detector asks at the start of
    /// a scanned step, and with the screen keeps the answer while it reuses
    /// the previous step's end values).
    fn derivative(
        &self,
        i: usize,
        t: f64,
        y: &OVector<f64, D>,
        dy: &OVector<f64, D>,
    ) -> Option<f64> {
        let _ = (i, t, y, dy);
        None
    }
    /// Whether [`EventSet::derivative`] reads its `dy` argument. When `false`
    /// the detector does not evaluate $f$ at the samples (saving one
    /// right-hand side per sample) and passes zeros as `dy`: return `false`
    /// when the derivatives are computed from `y` alone (e.g. a mechanical
    /// system whose velocities are part of the state).
    fn derivative_needs_rhs(&self) -> bool {
        true
    }
    /// Whether the derivative of event `i` reads its `dy` argument (default:
    /// [`EventSet::derivative_needs_rhs`] for every event). A set whose
    /// events differ (one derivative needs $f$, the others only $y$) saves the
    /// rhs evaluations at the samples of steps where only the others are
    /// sampled.
    fn derivative_needs_rhs_of(&self, i: usize) -> bool {
        let _ = i;
        self.derivative_needs_rhs()
    }
    /// Every active event's value and, if `with_derivatives`, its derivative (as
    /// [`EventSet::derivative`] returns it) at one point: calls `out(i, value, derivative)`
    /// for each active `i` in increasing order. `dy` is $f(t, y)$ (the detector calls this at
    /// a step's ends, where it has $f$ for free) or zeros when no event's derivative reads it.
    /// The default calls [`EventSet::value`] and [`EventSet::derivative`]; a set whose events
    /// share work (a contact location) can evaluate them together, with the same numbers.
    fn values_and_derivatives(
        &self,
        t: f64,
        y: &OVector<f64, D>,
        dy: &OVector<f64, D>,
        with_derivatives: bool,
        out: &mut dyn FnMut(usize, f64, Option<f64>),
    ) {
        for i in 0..self.len() {
            if self.active(i) {
                let d = if with_derivatives {
                    self.derivative(i, t, y, dy)
                } else {
                    None
                };
                out(i, self.value(i, t, y), d);
            }
        }
    }
    /// Whether event `i` is currently active (lets a model switch events off
    /// without reallocating).
    fn active(&self, i: usize) -> bool {
        let _ = i;
        true
    }
}

/// The empty event set.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoEvents;

impl<D: Dim> EventSet<D> for NoEvents
where
    DefaultAllocator: Allocator<D>,
{
    fn len(&self) -> usize {
        0
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Either
    }
    fn value(&self, _i: usize, _t: f64, _y: &OVector<f64, D>) -> f64 {
        1.0
    }
}

/// A located event. [`find_first_event`] returns a reference to the hit held
/// by the [`EventState`] (no allocation); clone it to keep it (`Copy` for
/// fixed dimensions).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct EventHit<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Index of the event in its set.
    pub index: usize,
    /// Event time (post-crossing end of the final bracket).
    pub t: f64,
    /// Dense-output state at `t`.
    pub y: OVector<f64, D>,
    /// Direction of the crossing: `Rising` or `Falling`.
    pub direction: Direction,
}

impl<D: Dim> Copy for EventHit<D>
where
    DefaultAllocator: Allocator<D>,
    OVector<f64, D>: Copy,
{
}

/// Options of the event detector. Every entry point that takes them
/// ([`find_first_event`], [`solve_with`](super::solve_with)) validates them
/// first ([`EventOptions::validate`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EventOptions {
    /// Interior dense-output samples per step, in `1..=`[`MAX_SAMPLES`]
    /// (others are an [`OdeError::InvalidOption`]). Default `4`.
    pub samples_per_step: usize,
    /// Time tolerance of the root finder (units of $t$); the effective
    /// tolerance is $\max(\text{root\\_tol}, 4\varepsilon|t|)$, i.e. about 4
    /// ulp for the default `0`.
    pub root_tol: f64,
    /// Values with $|g| \le$ `value_tol` at the segment origin count as zero
    /// (the event takes the sign of its motion, see the module docs).
    /// Default `0`.
    pub value_tol: f64,
    /// Re-arm window after the segment origin (units of $t$), see the module
    /// docs; the effective window is $\max(\text{rearm\\_time}, 2\thinspace\text{tol})$.
    /// Default `0`.
    pub rearm_time: f64,
    /// Maximum iterations of each root/extremum search (>= 1). Default `200`.
    pub max_iter: usize,
    /// Screen each step from the guards' values and derivatives at its two ends before
    /// sampling it (see the module docs, *Screening*): a guard whose cubic Hermite
    /// interpolant stays well away from zero is not sampled, and a step where every guard is
    /// so cleared costs no dense output at all. Applies to events with a derivative; the
    /// others are sampled as without it. Default `false`, as in the hybrid driver
    /// ([`SimOptions::screen_events`](crate::hybrid::SimOptions::screen_events)): the screen's
    /// guarantee is conditional (module docs, *Guarantee of the screen*).
    pub screen: bool,
}

impl Default for EventOptions {
    fn default() -> Self {
        EventOptions {
            samples_per_step: 4,
            root_tol: 0.0,
            value_tol: 0.0,
            rearm_time: 0.0,
            max_iter: 200,
            screen: false,
        }
    }
}

impl EventOptions {
    /// Checks the fields; the error names the offending field.
    pub fn validate(&self) -> Result<(), OdeError> {
        let check = |field: &'static str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(OdeError::InvalidOption {
                    field,
                    value: v,
                    hint: "event tolerances must be finite and >= 0 (0 = automatic)",
                })
            }
        };
        check("root_tol", self.root_tol)?;
        check("value_tol", self.value_tol)?;
        check("rearm_time", self.rearm_time)?;
        if self.samples_per_step == 0 || self.samples_per_step > MAX_SAMPLES {
            return Err(OdeError::InvalidOption {
                field: "samples_per_step",
                value: self.samples_per_step as f64,
                hint: "samples_per_step must be in 1..=MAX_SAMPLES (64); typical 4",
            });
        }
        if self.max_iter == 0 {
            return Err(OdeError::InvalidOption {
                field: "max_iter",
                value: 0.0,
                hint: "max_iter must be >= 1; typical 200",
            });
        }
        Ok(())
    }
}
