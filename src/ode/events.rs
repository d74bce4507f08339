//! Event functions, their detection on the dense output of the last step, and
//! root location by the Illinois method.
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
//! $\max(\text{root\_tol}, 4\varepsilon|t|)$.
//!
//! **Guarantee.** Relative to the dense-output interpolant $u(t)$, every
//! crossing of an allowed direction is found, provided that between two
//! consecutive samples $g_i(t, u(t))$ has at most one root, or has two roots
//! and at most one extremum *and* the event supplies its derivative. Pairs of
//! roots inside one sample interval are invisible without the derivative
//! (see the tests: a $10^{-6}$-deep dip inside one large step is found with
//! the derivative and missed by the plain sign check).
//!
//! # Re-arming rule (no immediate re-firing)
//!
//! The *segment origin* is the left end of the first step scanned after
//! [`EventState::new`]/[`EventState::reset`], or the time of the last hit
//! returned. At the origin $t_o$:
//!
//! 1. an event with $|g_i(t_o)| \le$ `value_tol` is *disarmed*: it ignores
//!    sign changes until the first sample with $|g_i| >$ `value_tol`, which
//!    becomes its reference value;
//! 2. a root located within the re-arm window
//!    $\max(\text{rearm\_time}, 2\cdot\text{tol})$ after $t_o$ is treated
//!    as the zero at the start time (round-off of the event that just fired
//!    or of a reset map) and is ignored; scanning continues after it.
//!
//! Away from the origin, a sample with $g_i = 0$ exactly is the right end of
//! a reported crossing (if its direction was allowed) and the event stays
//! disarmed until $g_i \ne 0$ again, so a root is never reported twice.

use super::{Integrator, OdeError, OdeSystem};
use nalgebra::SVector;
use std::marker::PhantomData;

/// Maximum number of events in one [`EventSet`] (fixed so that detection
/// needs no heap allocation).
pub const MAX_EVENTS: usize = 16;

/// Maximum number of interior samples per step.
pub const MAX_SAMPLES: usize = 64;

/// Allowed crossing direction of an event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Direction {
    /// $g$ goes from negative to non-negative.
    Rising,
    /// $g$ goes from positive to non-positive.
    Falling,
    /// Both.
    Either,
}

impl Direction {
    /// Whether a crossing in direction `d` (Rising or Falling) is allowed.
    pub fn allows(self, d: Direction) -> bool {
        matches!(self, Direction::Either) || self == d
    }

    fn opposite(self) -> Direction {
        match self {
            Direction::Rising => Direction::Falling,
            Direction::Falling => Direction::Rising,
            Direction::Either => Direction::Either,
        }
    }
}

/// A set of event functions $g_i(t, y)$, $i < $ `len()` $\le$ [`MAX_EVENTS`].
pub trait EventSet<const N: usize> {
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
    fn value(&self, i: usize, t: f64, y: &SVector<f64, N>) -> f64;
    /// Optional time derivative of event `i` along the flow,
    /// $\dot g_i = \partial_t g_i + \nabla_y g_i \cdot \dot y$, given `y` and
    /// `dy` $= f(t, y)$; enables detection of grazing (two roots inside one
    /// sample interval without a sign change). Must return `None` for every
    /// argument when not available (the detector probes it once per call).
    fn derivative(
        &self,
        i: usize,
        t: f64,
        y: &SVector<f64, N>,
        dy: &SVector<f64, N>,
    ) -> Option<f64> {
        let _ = (i, t, y, dy);
        None
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

impl<const N: usize> EventSet<N> for NoEvents {
    fn len(&self) -> usize {
        0
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Either
    }
    fn value(&self, _i: usize, _t: f64, _y: &SVector<f64, N>) -> f64 {
        1.0
    }
}

/// A located event.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventHit<const N: usize> {
    /// Index of the event in its set.
    pub index: usize,
    /// Event time (post-crossing end of the final bracket).
    pub t: f64,
    /// Dense-output state at `t`.
    pub y: SVector<f64, N>,
    /// Direction of the crossing: `Rising` or `Falling`.
    pub direction: Direction,
}

/// Options of the event detector.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventOptions {
    /// Interior dense-output samples per step (clamped to
    /// `1..=`[`MAX_SAMPLES`]). Default `4`.
    pub samples_per_step: usize,
    /// Time tolerance of the root finder (units of $t$); the effective
    /// tolerance is $\max(\text{root\_tol}, 4\varepsilon|t|)$, i.e. about 4
    /// ulp for the default `0`.
    pub root_tol: f64,
    /// Values with $|g| \le$ `value_tol` at the segment origin count as zero
    /// (event disarmed until it moves away). Default `0`.
    pub value_tol: f64,
    /// Re-arm window after the segment origin (units of $t$), see the module
    /// docs; the effective window is $\max(\text{rearm\_time}, 2\,\text{tol})$.
    /// Default `0`.
    pub rearm_time: f64,
    /// Maximum iterations of each root/extremum search. Default `200`.
    pub max_iter: usize,
}

impl Default for EventOptions {
    fn default() -> Self {
        EventOptions {
            samples_per_step: 4,
            root_tol: 0.0,
            value_tol: 0.0,
            rearm_time: 0.0,
            max_iter: 200,
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

/// Checks that an event set is small enough for the detector.
pub fn check_event_set<const N: usize, E: EventSet<N> + ?Sized>(events: &E) -> Result<(), OdeError> {
    if events.len() > MAX_EVENTS {
        return Err(OdeError::TooManyEvents {
            len: events.len(),
            max: MAX_EVENTS,
        });
    }
    Ok(())
}

/// Bookkeeping of the detector between calls: the segment origin (for the
/// re-arming rule, see the module docs) and where to resume after a hit
/// inside the current step. Fixed size, no allocation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventState<const N: usize> {
    /// Time of the segment origin; `None` = the left end of the next scanned
    /// step.
    origin: Option<f64>,
    /// `(t_prev, t_hit)` of the last hit: scanning of a step with the same
    /// `t_prev` resumes at `t_hit`.
    resume: Option<(f64, f64)>,
    _marker: PhantomData<[f64; N]>,
}

impl<const N: usize> Default for EventState<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> EventState<N> {
    /// Fresh state: the left end of the next scanned step is a segment origin.
    pub fn new() -> Self {
        EventState {
            origin: None,
            resume: None,
            _marker: PhantomData,
        }
    }

    /// Call after [`Integrator::reset`]: the next scanned step starts a new
    /// segment (its left end is the origin) and nothing is resumed.
    pub fn reset(&mut self) {
        *self = Self::new();
    }

    /// The current segment origin, if fixed.
    pub fn origin(&self) -> Option<f64> {
        self.origin
    }
}

/// Illinois (modified regula falsi) on a bracket with `fa != 0` and `fb` of
/// the opposite sign or zero. Returns `(a, b)` with `b - a <= tol` (or the
/// iteration limit reached), `g(a)` of the sign of `fa` and `g(b)` of the
/// other sign or zero. Falls back to bisection when the secant point is not
/// strictly inside or every fourth iteration without halving.
pub fn illinois(
    mut a: f64,
    mut fa: f64,
    mut b: f64,
    mut fb: f64,
    tol: f64,
    max_iter: usize,
    mut g: impl FnMut(f64) -> f64,
) -> (f64, f64) {
    let pos_a = fa > 0.0;
    let mut side = 0i8;
    let mut width = b - a;
    let mut slow = 0u32;
    for _ in 0..max_iter {
        if fb == 0.0 || b - a <= tol {
            break;
        }
        let mut c = if slow >= 3 {
            slow = 0;
            0.5 * (a + b)
        } else {
            b - fb * (b - a) / (fb - fa)
        };
        if !(c > a && c < b) {
            c = 0.5 * (a + b);
            if !(c > a && c < b) {
                break; // adjacent floats
            }
        }
        let fc = g(c);
        if fc == 0.0 || (fc > 0.0) != pos_a {
            b = c;
            fb = fc;
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        } else {
            a = c;
            fa = fc;
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        }
        if b - a > 0.5 * width {
            slow += 1;
        } else {
            slow = 0;
        }
        width = b - a;
    }
    (a, b)
}

/// Evaluates the dense output, exactly at the step ends.
fn y_at<const N: usize, S: OdeSystem<N>, I: Integrator<N>>(
    integ: &mut I,
    sys: &S,
    t: f64,
    out: &mut SVector<f64, N>,
) {
    if t == integ.t() {
        *out = *integ.y();
    } else if t == integ.t_prev() {
        *out = *integ.y_prev();
    } else {
        integ.dense(sys, t, out);
    }
}

/// Locates the root of event `i` in the bracket `lo`..`hi` (values of
/// opposite sign, or zero at `hi`); returns the post-crossing end.
#[allow(clippy::too_many_arguments)]
fn locate<const N: usize, S, I, E>(
    integ: &mut I,
    sys: &S,
    events: &E,
    i: usize,
    lo: (f64, f64),
    hi: (f64, f64),
    tol: f64,
    max_iter: usize,
) -> f64
where
    S: OdeSystem<N>,
    I: Integrator<N>,
    E: EventSet<N> + ?Sized,
{
    let mut tmp = SVector::<f64, N>::zeros();
    let (_, b) = illinois(lo.0, lo.1, hi.0, hi.1, tol, max_iter, |t| {
        y_at(integ, sys, t, &mut tmp);
        events.value(i, t, &tmp)
    });
    b
}

/// Look for the earliest event on the last step of `integ` using its dense
/// output; returns the earliest hit with the root located to near machine
/// precision by the Illinois method (ties: smallest index). See the module
/// docs for the detection algorithm, its guarantee and the re-arming rule.
///
/// Only the first [`MAX_EVENTS`] events are considered (use
/// [`check_event_set`] to reject larger sets); `samples_per_step` is clamped
/// to `1..=`[`MAX_SAMPLES`]. Counts the hit in `integ.stats().events` and the
/// rhs evaluations made for event derivatives in `rhs_evals`.
pub fn find_first_event<const N: usize, S, I, E>(
    integ: &mut I,
    sys: &S,
    events: &E,
    opts: &EventOptions,
    state: &mut EventState<N>,
) -> Option<EventHit<N>>
where
    S: OdeSystem<N>,
    I: Integrator<N>,
    E: EventSet<N> + ?Sized,
{
    let t_prev = integ.t_prev();
    let t_end = integ.t();
    let ne = events.len().min(MAX_EVENTS);
    if ne == 0 || !(t_end > t_prev) {
        return None;
    }
    // Where to start: after the last hit on this same step, else t_prev.
    let mut start = t_prev;
    if let Some((tp, th)) = state.resume {
        if tp == t_prev && th > t_prev {
            if th >= t_end {
                return None;
            }
            start = th;
        }
    }
    let origin = match state.origin {
        None => {
            state.origin = Some(start);
            start
        }
        Some(o) => o,
    };
    let at_origin = origin == start;

    let m = opts.samples_per_step.clamp(1, MAX_SAMPLES);
    let max_iter = opts.max_iter.max(1);
    let tol_at = |t: f64| opts.root_tol.max(4.0 * f64::EPSILON * t.abs());
    let window = opts.rearm_time.max(2.0 * tol_at(start));

    let mut y_a = SVector::<f64, N>::zeros();
    y_at(integ, sys, start, &mut y_a);
    let zero = SVector::<f64, N>::zeros();

    let mut active = [false; MAX_EVENTS];
    let mut has_der = [false; MAX_EVENTS];
    let mut armed = [false; MAX_EVENTS];
    let mut g_ref = [0.0f64; MAX_EVENTS];
    let mut d_ref = [0.0f64; MAX_EVENTS];
    let mut any_der = false;
    for i in 0..ne {
        active[i] = events.active(i);
        if active[i] {
            has_der[i] = events.derivative(i, start, &y_a, &zero).is_some();
            any_der |= has_der[i];
        }
    }
    let mut f_a = SVector::<f64, N>::zeros();
    if any_der {
        sys.rhs(start, &y_a, &mut f_a);
        integ.stats_mut().rhs_evals += 1;
    }
    for i in 0..ne {
        if !active[i] {
            continue;
        }
        let g = events.value(i, start, &y_a);
        g_ref[i] = g;
        armed[i] = if at_origin {
            g.abs() > opts.value_tol
        } else {
            g != 0.0
        };
        if has_der[i] {
            d_ref[i] = events.derivative(i, start, &y_a, &f_a).unwrap_or(0.0);
        }
    }

    let span = t_end - start;
    let mut t_a = start;
    let mut y_b = SVector::<f64, N>::zeros();
    let mut f_b = SVector::<f64, N>::zeros();
    let mut tmp = SVector::<f64, N>::zeros();
    for k in 1..=m + 1 {
        let t_b = if k == m + 1 {
            t_end
        } else {
            start + span * (k as f64 / (m + 1) as f64)
        };
        y_at(integ, sys, t_b, &mut y_b);
        if any_der {
            sys.rhs(t_b, &y_b, &mut f_b);
            integ.stats_mut().rhs_evals += 1;
        }
        // Best candidate of this interval: (t, index, direction).
        let mut best: Option<(f64, usize, Direction)> = None;
        let first_interval = k == 1;
        for i in 0..ne {
            if !active[i] {
                continue;
            }
            let g_b = events.value(i, t_b, &y_b);
            let d_b = if has_der[i] {
                events.derivative(i, t_b, &y_b, &f_b).unwrap_or(0.0)
            } else {
                0.0
            };
            if !armed[i] {
                if g_b.abs() > opts.value_tol && g_b != 0.0 {
                    armed[i] = true;
                    g_ref[i] = g_b;
                }
                d_ref[i] = d_b;
                continue;
            }
            let g_a = g_ref[i];
            let dir_first = if g_a < 0.0 {
                Direction::Rising
            } else {
                Direction::Falling
            };
            let allowed = events.direction(i);
            let tol = tol_at(t_a.abs().max(t_b.abs()));
            let mut candidate: Option<(f64, Direction)> = None;
            let ignorable = |r: f64| first_interval && at_origin && r - start <= window;
            if g_b == 0.0 || (g_b > 0.0) != (g_a > 0.0) {
                if allowed.allows(dir_first) {
                    let r = locate(integ, sys, events, i, (t_a, g_a), (t_b, g_b), tol, max_iter);
                    if !ignorable(r) {
                        candidate = Some((r, dir_first));
                    }
                }
            } else if has_der[i] && d_ref[i] != 0.0 && d_b != 0.0 && (d_ref[i] > 0.0) != (d_b > 0.0)
            {
                // Possible grazing pair: search the extremum of g, stop as
                // soon as g changes sign.
                let mut crossed: Option<(f64, f64)> = None;
                let pos_g = g_a > 0.0;
                let mut f_c = SVector::<f64, N>::zeros();
                let mut evals = 0u64;
                illinois(t_a, d_ref[i], t_b, d_b, tol, max_iter, |t| {
                    if crossed.is_some() {
                        return 0.0; // terminate: bracket found
                    }
                    y_at(integ, sys, t, &mut tmp);
                    let g = events.value(i, t, &tmp);
                    if g == 0.0 || (g > 0.0) != pos_g {
                        crossed = Some((t, g));
                        return 0.0;
                    }
                    sys.rhs(t, &tmp, &mut f_c);
                    evals += 1;
                    events.derivative(i, t, &tmp, &f_c).unwrap_or(0.0)
                });
                integ.stats_mut().rhs_evals += evals;
                if let Some((c, g_c)) = crossed {
                    if allowed.allows(dir_first) {
                        let r = locate(integ, sys, events, i, (t_a, g_a), (c, g_c), tol, max_iter);
                        if !ignorable(r) {
                            candidate = Some((r, dir_first));
                        }
                    }
                    if candidate.is_none() && allowed.allows(dir_first.opposite()) && g_c != 0.0 {
                        let r = locate(integ, sys, events, i, (c, g_c), (t_b, g_b), tol, max_iter);
                        if !ignorable(r) {
                            candidate = Some((r, dir_first.opposite()));
                        }
                    }
                }
            }
            if let Some((r, d)) = candidate {
                if best.is_none_or(|(tb, _, _)| r < tb) {
                    best = Some((r, i, d));
                }
            }
            if g_b == 0.0 {
                armed[i] = false;
            }
            g_ref[i] = g_b;
            d_ref[i] = d_b;
        }
        if let Some((r, i, d)) = best {
            let mut y_hit = SVector::<f64, N>::zeros();
            y_at(integ, sys, r, &mut y_hit);
            state.origin = Some(r);
            state.resume = Some((t_prev, r));
            integ.stats_mut().events += 1;
            return Some(EventHit {
                index: i,
                t: r,
                y: y_hit,
                direction: d,
            });
        }
        t_a = t_b;
    }
    None
}
