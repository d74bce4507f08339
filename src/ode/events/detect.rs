//! The detector: [`find_first_event`].

use super::state::{Leave, Slot};
use super::{Direction, EventHit, EventOptions, EventSet, EventState};
use crate::numeric::{illinois, RootOptions};
use crate::ode::{Integrator, OdeError, OdeSystem};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

/// Evaluates the dense output, exactly at the step ends.
fn y_at<D, S, I>(integ: &mut I, sys: &S, t: f64, out: &mut OVector<f64, D>)
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
{
    if t == integ.t() {
        out.copy_from(integ.y());
    } else if t == integ.t_prev() {
        out.copy_from(integ.y_prev());
    } else {
        integ.dense(sys, t, out);
    }
}

/// The interior extremum of the cubic Hermite interpolant through `(t, g, g')` at both ends
/// of a sample interval that comes nearest to zero, as its time and value (derivatives of
/// opposite signs: one interior extremum; of the same sign: none, or two); `None` when the
/// interpolant has none inside.
fn hermite_extremum(a: (f64, f64, f64), b: (f64, f64, f64)) -> Option<(f64, f64)> {
    let (ta, ga, da) = a;
    let (tb, gb, db) = b;
    let h = tb - ta;
    // p(s) = c0 + c1 s + c2 s^2 + c3 s^3 on s in [0, 1].
    let (c0, c1) = (ga, h * da);
    let c2 = 3.0 * (gb - ga) - h * (2.0 * da + db);
    let c3 = 2.0 * (ga - gb) + h * (da + db);
    let p = |s: f64| c0 + s * (c1 + s * (c2 + s * c3));
    // p'(s) = c1 + 2 c2 s + 3 c3 s^2.
    let (qa, qb, qc) = (3.0 * c3, 2.0 * c2, c1);
    let (r0, r1) = if qa.abs() <= 1e-14 * (qb.abs() + qc.abs()) {
        if qb == 0.0 {
            return None;
        }
        (-qc / qb, f64::NAN)
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc.is_nan() || disc < 0.0 {
            return None;
        }
        let q = -0.5 * (qb + qb.signum() * disc.sqrt());
        (q / qa, if q != 0.0 { qc / q } else { f64::NAN })
    };
    // The interior root whose value is nearer zero on the ends' side (signed distance, negative
    // across it); the first on a tie.
    let inside = |s: f64| s > 0.0 && s < 1.0;
    let side = |v: f64| v * ga.signum();
    match (inside(r0), inside(r1)) {
        (false, false) => None,
        (true, false) => Some((ta + r0 * h, p(r0))),
        (false, true) => Some((ta + r1 * h, p(r1))),
        (true, true) => {
            let (v0, v1) = (p(r0), p(r1));
            Some(if side(v1).total_cmp(&side(v0)).is_lt() {
                (ta + r1 * h, v1)
            } else {
                (ta + r0 * h, v0)
            })
        }
    }
}

/// Whether a value `v` on a sample interval whose ends have the values `ga`, `gb` (same sign)
/// reaches zero, or at least half of the way from the nearer end value to zero.
fn halfway_to_zero(v: f64, ga: f64, gb: f64) -> bool {
    v == 0.0 || (v > 0.0) != (ga > 0.0) || v.abs() <= 0.5 * ga.abs().min(gb.abs())
}

/// The midpoint of a sample interval with ends `(t, g, g')` and the value and slope there of
/// their cubic Hermite interpolant, $p(1/2) = (g_a + g_b)/2 + h(\dot g_a - \dot g_b)/8$ and
/// $p^\prime(1/2) = 3(g_b - g_a)/(2h) - (\dot g_a + \dot g_b)/4$.
fn hermite_midpoint(a: (f64, f64, f64), b: (f64, f64, f64)) -> (f64, f64, f64) {
    let h = b.0 - a.0;
    (
        a.0 + 0.5 * h,
        0.5 * (a.1 + b.1) + 0.125 * h * (a.2 - b.2),
        1.5 * (b.1 - a.1) / h - 0.25 * (a.2 + b.2),
    )
}

/// How many times [`Scan::confirm`] may split a sample interval whose interpolant the
/// guard contradicts (at most $2^5 - 2$ more guard values and derivatives per interval).
const CONFIRM_DEPTH: u32 = 4;

/// What the guard says of its interpolant on a sample interval ([`Scan::confirm`]).
enum Confirmed {
    /// It holds: no pair of roots to look for.
    Yes,
    /// The guard crossed at this point `(t, g)`.
    Crossed((f64, f64)),
    /// The guard comes halfway to zero, or stays unresolved: search the extremum.
    Search,
}

/// The time tolerance of a root near `t`: $\max(\text{root\\_tol}, 4\varepsilon|t|)$.
fn tol_at(root_tol: f64, t: f64) -> f64 {
    root_tol.max(4.0 * f64::EPSILON * t.abs())
}

/// A located root of one guard: `(t, direction, pre-crossing end of its bracket)`.
type Candidate = (f64, Direction, f64);

/// A sample interval searched for a grazing pair: its ends `(t, g, g')` and, when known, a
/// point inside where the guard has crossed.
type GrazingInterval = ((f64, f64, f64), (f64, f64, f64), Option<(f64, f64)>);

/// The earliest located root of a sample interval: `(t, event, direction, pre-crossing end of
/// its bracket)`.
type Best = (f64, usize, Direction, f64);

/// The scanned part of a step and the constants of its rules (fixed for one call of
/// [`find_first_event`]).
#[derive(Debug, Clone, Copy)]
struct Step {
    /// Where the scan starts: `t_prev`, or the last hit on this step.
    start: f64,
    /// The step's end.
    t_end: f64,
    /// `t_end - start`.
    span: f64,
    /// Interior samples (`samples_per_step`).
    samples: usize,
    /// Whether `start` is the segment origin (start-of-segment rules).
    at_origin: bool,
    /// The event whose hit defined the origin (rule 2), if `at_origin`.
    fired: Option<usize>,
    /// The last hit returned, with its direction.
    last_hit: Option<(usize, Direction)>,
    /// [`EventOptions::value_tol`].
    vtol: f64,
    /// [`EventOptions::root_tol`].
    root_tol: f64,
    /// The re-arm window $w$.
    window: f64,
    /// The probe time $t_p$ of guards that may have left zero at the origin.
    t_probe: f64,
}

impl Step {
    /// The constants of a scan of `start..t_end` whose segment origin is `origin`.
    fn new(
        opts: &EventOptions,
        (start, t_end): (f64, f64),
        origin: f64,
        last_hit: Option<(usize, Direction)>,
    ) -> Self {
        let at_origin = origin == start;
        let m = opts.samples_per_step;
        // Twice the root tolerance of any interval of this step (the zero left by
        // a hit located on an earlier, similar step is within it).
        let window = opts
            .rearm_time
            .max(2.0 * tol_at(opts.root_tol, start.abs().max(t_end.abs())));
        let span = t_end - start;
        let t_probe = start
            + (4.0 * window)
                .max(span * 2f64.powi(-20))
                .min(span / (2 * (m + 1)) as f64);
        Step {
            start,
            t_end,
            span,
            samples: m,
            at_origin,
            fired: if at_origin {
                last_hit.map(|(j, _)| j)
            } else {
                None
            },
            last_hit,
            vtol: opts.value_tol,
            root_tol: opts.root_tol,
            window,
            t_probe,
        }
    }

    /// Whether a root at `r` of a guard that sits on zero at the start (`zero_at_start`) is
    /// that zero, left within the window of the origin: not an event.
    fn ignorable(&self, r: f64, zero_at_start: bool) -> bool {
        self.at_origin && r - self.start <= self.window && zero_at_start
    }

    /// **The per-guard arming rule** (module docs, *Start of a segment and re-arming*), from
    /// each guard's value and derivative at the start (`g_ref`, `d_ref`). Away from the
    /// origin a guard is armed with its sign. At the origin (rule 1) one beyond `value_tol` is
    /// armed, one on zero waits for the first sample beyond it; the event that just fired
    /// keeps its post-crossing sign (rule 2), so that the second root of a grazing pair in
    /// the same sample interval is still found; any other guard on zero, or within the
    /// window of it on either side, records how it leaves zero (rule 3: towards the sign of its
    /// derivative, or unknown without one: the probe decides), because leaving zero is the
    /// start, not an event, while crossing back is.
    fn arm(&self, slots: &mut [Slot]) {
        let (vtol, window) = (self.vtol, self.window);
        for (i, s) in slots.iter_mut().enumerate() {
            if !s.active {
                continue;
            }
            let g = s.g_ref;
            s.g_origin = g;
            s.armed = if self.at_origin {
                g.abs() > vtol
            } else {
                g != 0.0 && !g.is_nan()
            };
            if self.at_origin
                && !s.armed
                && let Some((j, d)) = self.last_hit
                && j == i
            {
                // The event that just fired keeps its post-crossing sign.
                s.armed = true;
                s.g_ref = if d == Direction::Falling {
                    -f64::MIN_POSITIVE
                } else {
                    f64::MIN_POSITIVE
                };
            }
            if self.at_origin && self.fired != Some(i) && !g.is_nan() {
                // How this guard may leave zero (start-of-segment rule). Within the window of
                // zero, whichever way it moves, it is on zero: the round-off of a located root
                // or a reset map puts it either side. A derivative of exactly zero is a
                // derivative: such a guard is on zero only within `value_tol` (a guard offset
                // from zero at a tangency, then curving through it inside the window, crosses;
                // it does not leave the start's zero).
                let d = s.d_ref;
                s.leave = if s.has_der && !d.is_nan() {
                    let on_zero = g.abs() <= vtol || g.abs() <= d.abs() * window;
                    match (on_zero, d != 0.0) {
                        (false, _) => Leave::No,
                        (true, true) => Leave::Towards(d.signum()),
                        // On zero at rest: the probe tells where it goes.
                        (true, false) => Leave::Probe,
                    }
                } else {
                    Leave::Probe
                };
            }
        }
    }
}

/// One sample interval `t_a..t_b` of the scan (the `k`-th, from 1), its time tolerance, and
/// the earliest root located in it so far.
#[derive(Debug, Clone, Copy)]
struct Interval {
    k: usize,
    t_a: f64,
    t_b: f64,
    tol: f64,
    best: Option<Best>,
}

/// The scan of one step: what the rules evaluate (the step's dense output in `integ`, the
/// system for the `dy` of derivatives that read it, the event set), the work vectors of
/// evaluations inside the step, and the step's constants. Every rule below is a method.
struct Scan<'a, D, S, I, E: ?Sized>
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
{
    integ: &'a mut I,
    sys: &'a S,
    events: &'a E,
    /// The state at the last point evaluated inside the step.
    tmp: &'a mut OVector<f64, D>,
    /// `dy` there, for derivatives that read it.
    f_c: &'a mut OVector<f64, D>,
    /// Always zero: the `dy` of derivatives that do not read it.
    zero: &'a OVector<f64, D>,
    /// The dense output at the probe time (evaluated once, when first needed: `probed`).
    y_p: &'a mut OVector<f64, D>,
    probed: bool,
    /// [`EventOptions::max_iter`].
    max_iter: usize,
    step: Step,
}

impl<D, S, I, E> Scan<'_, D, S, I, E>
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
    E: EventSet<D> + ?Sized,
{
    /// Event `i` at time `t` of the step (the state in `tmp`).
    fn value(&mut self, i: usize, t: f64) -> f64 {
        y_at(self.integ, self.sys, t, self.tmp);
        self.events.value(i, t, self.tmp)
    }

    /// Locates the root of event `i` in the bracket `lo`..`hi` (values of
    /// opposite sign, or zero at `hi`); returns the final bracket `(lo, hi)`, `hi` the
    /// post-crossing end. A NaN of the event inside the bracket is
    /// [`OdeError::EventNotANumber`].
    fn locate(
        &mut self,
        i: usize,
        lo: (f64, f64),
        hi: (f64, f64),
        tol: f64,
    ) -> Result<(f64, f64), OdeError> {
        let opts = RootOptions::default()
            .with_tol(tol)
            .with_max_evaluations(self.max_iter);
        match illinois(lo, hi, &opts, |t| self.value(i, t)) {
            Ok(b) => match b.nan_at {
                Some(t) => Err(OdeError::EventNotANumber { index: i, t }),
                None => Ok((b.lo, b.hi)),
            },
            // The callers pass a sign change; were it none, the bracket stays as given.
            Err(_) => Ok((lo.0, hi.0)),
        }
    }

    /// Narrows the bracket `lo`..`hi` (values of opposite sign, as for [`Scan::locate`]) of
    /// event `i` before the root search, when the derivatives at both ends are known
    /// (finite): the root of the cubic Hermite interpolant of the two ends, $t^*$, is
    /// usually within a tiny fraction of the bracket of the root, so $g$ is evaluated at
    /// $t^* \pm \delta$ with $\delta = 2^{-16}$ of the bracket (at least `tol`) and the
    /// narrowest sub-bracket with a verified sign change is returned (the given one when
    /// the estimate misses). Two evaluations that save about half of the root finder's.
    fn narrow_bracket(
        &mut self,
        i: usize,
        lo: (f64, f64, f64),
        hi: (f64, f64, f64),
        tol: f64,
    ) -> ((f64, f64), (f64, f64)) {
        let (ta, ga, da) = lo;
        let (tb, gb, db) = hi;
        let plain = ((ta, ga), (tb, gb));
        let h = tb - ta;
        let delta = (h * 2f64.powi(-16)).max(tol);
        if gb == 0.0 || !(da.is_finite() && db.is_finite()) || 4.0 * delta >= h {
            return plain;
        }
        let est = ta + hermite_root(ga, (gb, da, db), h, 1e-3 * delta / h) * h;
        let (l, r) = (est - delta, est + delta);
        if !(l > ta && r < tb) {
            return plain;
        }
        let crossed = |g: f64| g == 0.0 || (g > 0.0) != (ga > 0.0);
        let gl = self.value(i, l);
        if gl.is_nan() {
            return plain;
        }
        if crossed(gl) {
            return ((ta, ga), (l, gl));
        }
        let gr = self.value(i, r);
        if gr.is_nan() {
            return ((l, gl), (tb, gb));
        }
        if crossed(gr) {
            ((l, gl), (r, gr))
        } else {
            ((r, gr), (tb, gb))
        }
    }

    /// **The start values**: every active guard's value and derivative at the start of the
    /// scan (`y_a`), into `g_ref` and `d_ref`, evaluated all at once, derivatives with the integrator's `f` at the start if
    /// known (`f_a`, `f_a_known`), else with zeros, which is exact unless the guard reads
    /// `dy`, which is then evaluated once. A guard with no value at the start is
    /// [`OdeError::EventNotANumber`]: nothing can be said about the step.
    fn start_values(
        &mut self,
        slots: &mut [Slot],
        y_a: &OVector<f64, D>,
        f_a: &mut OVector<f64, D>,
        f_a_known: bool,
    ) -> Result<(), OdeError> {
        let (events, start) = (self.events, self.step.start);
        for (i, s) in slots.iter_mut().enumerate() {
            *s = Slot {
                active: events.active(i),
                ..Slot::default()
            };
            if s.active {
                s.needs_rhs = events.derivative_needs_rhs_of(i);
            }
        }
        if !slots.iter().any(|s| s.active) {
            return Ok(());
        }
        let dy: &OVector<f64, D> = if f_a_known { f_a } else { self.zero };
        let mut start_rhs = false;
        events.values_and_derivatives(start, y_a, dy, true, &mut |i, g, d| {
            let s = &mut slots[i];
            s.g_ref = g;
            if let Some(d) = d {
                s.has_der = true;
                if f_a_known || !s.needs_rhs {
                    s.d_ref = d;
                } else {
                    start_rhs = true;
                }
            }
        });
        if start_rhs {
            self.sys.rhs(start, y_a, f_a);
            self.integ.stats_mut().rhs_evals += 1;
            for (i, s) in slots.iter_mut().enumerate() {
                if s.active && s.has_der && s.needs_rhs {
                    s.d_ref = events.derivative(i, start, y_a, f_a).unwrap_or(0.0);
                }
            }
        }
        match slots.iter().position(|s| s.active && s.g_ref.is_nan()) {
            Some(i) => Err(OdeError::EventNotANumber { index: i, t: start }),
            None => Ok(()),
        }
    }
}

impl<D, S, I, E> Scan<'_, D, S, I, E>
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
    E: EventSet<D> + ?Sized,
{
    /// Samples the guards on the `samples` interior points and the step's end, interval by interval in time order ([`Scan::guard_interval`] for each
    /// guard); the first interval with a located root ends the scan with its earliest root
    /// (ties: smallest index). Guards without a value at an interval's end are decided after
    /// the interval's others ([`Scan::nan_in_interval`]).
    fn sample(
        &mut self,
        slots: &mut [Slot],
        y_b: &mut OVector<f64, D>,
        f_b: &mut OVector<f64, D>,
    ) -> Result<Option<Best>, OdeError> {
        let step = self.step;
        let need_rhs = slots.iter().any(|s| s.active && s.has_der && s.needs_rhs);
        let m = step.samples;
        let mut t_a = step.start;
        for k in 1..=m + 1 {
            let t_b = if k == m + 1 {
                step.t_end
            } else {
                step.start + step.span * (k as f64 / (m + 1) as f64)
            };
            y_at(self.integ, self.sys, t_b, y_b);
            // At the step's end the integrator has f (the start of the next step reads the same).
            let f_known = need_rhs && t_b == self.integ.t() && copy_known(self.integ.dy(), f_b);
            if need_rhs && !f_known {
                self.sys.rhs(t_b, y_b, f_b);
                self.integ.stats_mut().rhs_evals += 1;
            }
            let tol = tol_at(step.root_tol, t_a.abs().max(t_b.abs()));
            let mut iv = Interval {
                k,
                t_a,
                t_b,
                tol,
                best: None,
            };
            self.values_at_end(slots, t_b, y_b, if need_rhs { f_b } else { self.zero });
            let mut any_nan = false;
            for (i, s) in slots.iter_mut().enumerate() {
                s.nan = false;
                if !s.active {
                    continue;
                }
                let (g_b, d_b) = s.end;
                if g_b.is_nan() {
                    // No sign at this sample: decided after the interval's other events.
                    s.nan = true;
                    any_nan = true;
                    continue;
                }
                if let Some((r, d, l)) = self.guard_interval(s, i, &iv, (g_b, d_b))?
                    && iv.best.is_none_or(|(tb, _, _, _)| r < tb)
                {
                    iv.best = Some((r, i, d, l));
                }
            }
            if any_nan {
                iv.best = self.nan_in_interval(slots, iv.best, (t_a, t_b), tol)?;
            }
            if iv.best.is_some() {
                return Ok(iv.best);
            }
            t_a = t_b;
        }
        Ok(None)
    }

    /// Every active guard's value and derivative (0 without one) at a sample `t_b` into its
    /// slot's `end`, all at once: a set whose guards share work (a contact location) does it
    /// once a sample. `dy_b` is $f$ there when some guard's derivative reads it, else zeros (a
    /// derivative that does not read it ignores it).
    fn values_at_end(
        &self,
        slots: &mut [Slot],
        t_b: f64,
        y_b: &OVector<f64, D>,
        dy_b: &OVector<f64, D>,
    ) {
        for s in slots.iter_mut() {
            s.end = (f64::NAN, 0.0);
        }
        self.events
            .values_and_derivatives(t_b, y_b, dy_b, true, &mut |i, g, d| {
                let s = &mut slots[i];
                if s.active {
                    s.end = (g, if s.has_der { d.unwrap_or(0.0) } else { 0.0 });
                }
            });
    }

    /// The rules of one guard over one sample interval, given its value and derivative at
    /// the interval's end (`end`, not NaN); updates the guard's reference to them. A
    /// disarmed guard is armed by the first sample beyond `value_tol` (rule 1); an armed one
    /// has a **sign change** ([`Scan::sign_change`]) or maybe a **grazing pair**
    /// ([`Scan::grazing`]); a guard that may have left zero at the origin is checked for
    /// **the crossing back** ([`Scan::crossing_back`]) at the first sample that shows it on
    /// the side it must cross back into (also past a sign change whose root was the start's
    /// zero). Returns its located root, if any and not the zero
    /// left at the start.
    fn guard_interval(
        &mut self,
        s: &mut Slot,
        i: usize,
        iv: &Interval,
        end: (f64, f64),
    ) -> Result<Option<Candidate>, OdeError> {
        let (g_b, d_b) = end;
        // Only the event that fired and guards on zero at the origin have a zero at the
        // start time; any other guard's root, however close, is a crossing.
        let zero_at_start =
            self.step.fired == Some(i) || matches!(s.leave, Leave::Towards(_) | Leave::Probe);
        let mut candidate = None;
        // A guard on zero at the origin that left it on the other side of
        // g_b and came back is only visible at the probe point.
        let check_return;
        if !s.armed {
            let mut check = false;
            if g_b.abs() > self.step.vtol && g_b != 0.0 {
                s.armed = true;
                s.g_ref = g_b;
                check = s.leave != Leave::No;
            }
            s.d_ref = d_b;
            check_return = check;
        } else {
            let g_a = s.g_ref;
            if g_b == 0.0 || (g_b > 0.0) != (g_a > 0.0) {
                // A guard on zero at the origin that left it away from g_b crosses back: its
                // rounding next to the start may read either side of zero (further than the
                // window where it moves slowly), so the crossing is searched beyond the probe
                // first, then, if the probe does not show the departure, from the start.
                let away = iv.k == 1
                    && g_b != 0.0
                    && matches!(s.leave, Leave::Towards(d) if (d > 0.0) != (g_b > 0.0));
                if away {
                    candidate = self.crossing_back(s, i, iv, g_b, zero_at_start)?;
                }
                if candidate.is_none() {
                    candidate = self.sign_change(s, i, iv, end, zero_at_start)?;
                }
                // A guard on zero whose root here is the start's zero (ignored): the crossing
                // the interval's end shows is further on.
                check_return = iv.k == 1 && !away && candidate.is_none() && s.leave != Leave::No;
            } else {
                candidate = self.grazing(s, i, iv, end, zero_at_start)?;
                // No sign change over the first interval: it may hide a
                // departure from zero and the crossing back.
                check_return = iv.k == 1
                    && candidate.is_none()
                    && match s.leave {
                        Leave::No => false,
                        Leave::Towards(_) => true,
                        Leave::Probe => s.g_origin.abs() <= g_b.abs(),
                    };
            }
            if g_b == 0.0 {
                s.armed = false;
            }
            s.g_ref = g_b;
            s.d_ref = d_b;
        }
        if check_return && g_b != 0.0 {
            candidate = self.crossing_back(s, i, iv, g_b, zero_at_start)?;
        }
        Ok(candidate)
    }

    /// **Sign change**: the armed guard `s` (reference not yet updated) changes sign or
    /// reaches zero at the interval's end. In an allowed direction, its root is located
    /// (bracket narrowed by [`Scan::narrow_bracket`]). A root already found earlier in the
    /// interval (`iv.best`) bounds the search: this guard's root can only win if it has
    /// crossed by then (one root per interval); if it has no value at that root, it must
    /// have one at the pre-crossing end of the root's bracket.
    fn sign_change(
        &mut self,
        s: &Slot,
        i: usize,
        iv: &Interval,
        (g_b, d_b): (f64, f64),
        zero_at_start: bool,
    ) -> Result<Option<Candidate>, OdeError> {
        let g_a = s.g_ref;
        let dir_first = if g_a < 0.0 {
            Direction::Rising
        } else {
            Direction::Falling
        };
        if !self.events.direction(i).allows(dir_first) {
            return Ok(None);
        }
        let mut hi = (iv.t_b, g_b, d_b);
        if let Some((mut rb, _, _, rb_lo)) = iv.best {
            let mut g_r = self.value(i, rb);
            if g_r.is_nan() {
                rb = rb_lo;
                g_r = self.value(i, rb);
            }
            if g_r.is_nan() {
                return Err(OdeError::EventNotANumber { index: i, t: rb });
            }
            if g_r == 0.0 || (g_r > 0.0) != (g_a > 0.0) {
                hi = (rb, g_r, f64::NAN);
            } else {
                hi.0 = f64::NAN;
            }
        }
        if hi.0.is_nan() {
            return Ok(None);
        }
        let lo = (iv.t_a, g_a, if s.has_der { s.d_ref } else { f64::NAN });
        let (lo, hi) = self.narrow_bracket(i, lo, hi, iv.tol);
        let (l, r) = self.locate(i, lo, hi, iv.tol)?;
        Ok((!self.step.ignorable(r, zero_at_start)).then_some((r, dir_first, l)))
    }

    /// **Grazing pair**: no sign change over the interval, but the guard's derivative
    /// changes sign (one interior extremum), and the cubic Hermite interpolant of the ends
    /// puts that extremum at least halfway to zero: the extremum is searched by
    /// [`Scan::grazing_pair`]. An interior extremum of the interpolant that does not (the
    /// usual case), or that derivatives of the same sign imply (ends whose values move
    /// against their slopes: two extrema), is checked against the guard itself there
    /// ([`Scan::confirm`]): a step longer than the guard's time scale can swing through
    /// zero between quiet ends. A crossing seen there is located; a guard found halfway to
    /// zero, or unresolved, has its extremum searched (derivatives of opposite signs only).
    fn grazing(
        &mut self,
        s: &Slot,
        i: usize,
        iv: &Interval,
        (g_b, d_b): (f64, f64),
        zero_at_start: bool,
    ) -> Result<Option<Candidate>, OdeError> {
        let a = (iv.t_a, s.g_ref, s.d_ref);
        let b = (iv.t_b, g_b, d_b);
        if !s.has_der {
            return Ok(None);
        }
        let turns = s.d_ref != 0.0 && d_b != 0.0 && (s.d_ref > 0.0) != (d_b > 0.0);
        let extremum = hermite_extremum(a, b);
        let pair = if turns && extremum.is_none_or(|(_, p)| halfway_to_zero(p, a.1, g_b)) {
            (a, b, None)
        } else if let Some(at) = extremum {
            match self.confirm(i, (a, b), (at.0, at.1, 0.0), s.needs_rhs, CONFIRM_DEPTH)? {
                Confirmed::Crossed(c) => (a, b, Some(c)),
                Confirmed::Search if turns => (a, b, None),
                _ => return Ok(None),
            }
        } else {
            return Ok(None);
        };
        self.grazing_pair(i, pair, iv.tol, s.needs_rhs, zero_at_start)
    }

    /// Checks the cubic Hermite interpolant of guard `i` on the interval `a`..`b` (values of
    /// the same sign, and derivatives) at one point `(t, p, p')` (the interpolant's value and
    /// slope there) against the guard's value $G$ and derivative $\dot G$ there. A crossing
    /// ($G$ zero or across) is returned. The interpolant is confirmed when $G$ is within a
    /// quarter of the nearer end value $m$ of $p$, $\dot G$ within $m/h$ of $p^\prime$ ($h$ the
    /// interval's length: the guard cannot move by $m$ on the interval faster than the
    /// interpolant does), and $G$ is not halfway to zero; halfway to zero asks for the
    /// extremum search. Otherwise the interval is unresolved by its ends: it is split at $t$ and each
    /// half checked the same way, in time order, at its interpolant's extremum nearest zero
    /// (its midpoint if it has none), `depth` more times at most. A guard without a value at
    /// `t` leaves the interpolant to decide.
    fn confirm(
        &mut self,
        i: usize,
        (a, b): ((f64, f64, f64), (f64, f64, f64)),
        (t, p, dp): (f64, f64, f64),
        need_rhs: bool,
        depth: u32,
    ) -> Result<Confirmed, OdeError> {
        let g = self.value(i, t);
        if g.is_nan() {
            return Ok(Confirmed::Yes);
        }
        if g == 0.0 || (g > 0.0) != (a.1 > 0.0) {
            return Ok(Confirmed::Crossed((t, g)));
        }
        if need_rhs {
            self.sys.rhs(t, self.tmp, self.f_c);
            self.integ.stats_mut().rhs_evals += 1;
        }
        let dy: &OVector<f64, D> = if need_rhs { self.f_c } else { self.zero };
        let d = self.events.derivative(i, t, self.tmp, dy).unwrap_or(0.0);
        let near = a.1.abs().min(b.1.abs());
        let h = b.0 - a.0;
        if (g - p).abs() <= 0.25 * near && (d - dp).abs() * h <= near {
            return Ok(if halfway_to_zero(g, a.1, b.1) {
                Confirmed::Search
            } else {
                Confirmed::Yes
            });
        }
        if depth == 0 {
            return Ok(Confirmed::Search);
        }
        let mid = (t, g, d);
        let mut verdict = Confirmed::Yes;
        for (x, y) in [(a, mid), (mid, b)] {
            let at = hermite_extremum(x, y)
                .map(|(t, p)| (t, p, 0.0))
                .unwrap_or_else(|| hermite_midpoint(x, y));
            match self.confirm(i, (x, y), at, need_rhs, depth - 1)? {
                Confirmed::Crossed(c) => return Ok(Confirmed::Crossed(c)),
                Confirmed::Search => verdict = Confirmed::Search,
                Confirmed::Yes => {}
            }
        }
        Ok(verdict)
    }

    /// Searches a possible grazing pair of event `i` in the sample interval
    /// `a`..`b` (values of the same sign, derivatives of opposite signs): moves
    /// towards the extremum by the Illinois method on $\dot g$ and stops as soon
    /// as $g$ changes sign (or starts from `known`, a point where it has); then locates the
    /// first root in an allowed direction.
    fn grazing_pair(
        &mut self,
        i: usize,
        (a, b, known): GrazingInterval,
        tol: f64,
        need_rhs: bool,
        zero_at_start: bool,
    ) -> Result<Option<Candidate>, OdeError> {
        let (t_a, g_a, _) = a;
        let (t_b, g_b, _) = b;
        let dir_first = if g_a < 0.0 {
            Direction::Rising
        } else {
            Direction::Falling
        };
        let allowed = self.events.direction(i);
        let crossed = match known {
            Some(c) => Some(c),
            None => self.extremum_search(i, (a, b), tol, need_rhs)?,
        };
        let Some((c, g_c)) = crossed else {
            return Ok(None);
        };
        if allowed.allows(dir_first) {
            let (l, r) = self.locate(i, (t_a, g_a), (c, g_c), tol)?;
            if !self.step.ignorable(r, zero_at_start) {
                return Ok(Some((r, dir_first, l)));
            }
        }
        if allowed.allows(dir_first.opposite()) && g_c != 0.0 {
            let (l, r) = self.locate(i, (c, g_c), (t_b, g_b), tol)?;
            if !self.step.ignorable(r, zero_at_start) {
                return Ok(Some((r, dir_first.opposite(), l)));
            }
        }
        Ok(None)
    }
}

impl<D, S, I, E> Scan<'_, D, S, I, E>
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
    E: EventSet<D> + ?Sized,
{
    /// The extremum search of a grazing pair of event `i` on the sample interval `a`..`b`
    /// (values of the same sign, derivatives of opposite signs): the Illinois method on
    /// $\dot g$, stopped at the first probe where $g$ changes sign, which it returns; else
    /// the first probe where $g$ is zero (a zero alone does not stop it: a guard that leaves
    /// its zero at the interval's start reads zero next to it, and only a point strictly across
    /// brackets the second root); `None` when the extremum is reached without either, or the
    /// derivative has no value (then, as for an event without a derivative, the pair is not
    /// searched).
    fn extremum_search(
        &mut self,
        i: usize,
        (a, b): ((f64, f64, f64), (f64, f64, f64)),
        tol: f64,
        need_rhs: bool,
    ) -> Result<Option<(f64, f64)>, OdeError> {
        let (t_a, g_a, d_a) = a;
        let (t_b, _, d_b) = b;
        let mut crossed: Option<(f64, f64)> = None;
        // A probe exactly on zero: the crossing if none lies strictly across.
        let mut touched: Option<(f64, f64)> = None;
        let mut g_nan: Option<f64> = None;
        let pos_g = g_a > 0.0;
        let mut evals = 0u64;
        let opts = RootOptions::default()
            .with_tol(tol)
            .with_max_evaluations(self.max_iter);
        let search = illinois((t_a, d_a), (t_b, d_b), &opts, |t| {
            if crossed.is_some() {
                return 0.0; // terminate: bracket found
            }
            let g = self.value(i, t);
            if g.is_nan() {
                g_nan = Some(t);
                return f64::NAN; // stops the search (below)
            }
            if g != 0.0 && (g > 0.0) != pos_g {
                crossed = Some((t, g));
                return 0.0;
            }
            // On zero (a guard leaving its zero at the interval's start, to rounding) the
            // search goes on: only a point strictly across brackets the pair's second root.
            if g == 0.0 && touched.is_none() {
                touched = Some((t, g));
            }
            if need_rhs {
                self.sys.rhs(t, self.tmp, self.f_c);
                evals += 1;
            }
            let dy: &OVector<f64, D> = if need_rhs { self.f_c } else { self.zero };
            self.events.derivative(i, t, self.tmp, dy).unwrap_or(0.0)
        });
        self.integ.stats_mut().rhs_evals += evals;
        if let Some(t) = g_nan {
            // The event has no value there.
            return Err(OdeError::EventNotANumber { index: i, t });
        }
        if search.map_or(true, |b| b.nan_at.is_some()) {
            return Ok(None);
        }
        Ok(crossed.or(touched))
    }

    /// **The crossing back** (start-of-segment rule 3): the guard `s`, on zero at the origin,
    /// is now (`g_b`, at the end of the first sample beyond `value_tol`) on the side it
    /// must cross back into in an allowed direction, and its motion at the origin pointed
    /// the other way (or is unknown). The probe at $t_p$ decides whether it left zero to the
    /// other side (without a derivative, also that it reached zero within the window: the
    /// secant from the origin); if the probe is already back while the derivative pointed
    /// away, [`Scan::departure_point`] looks closer to the origin. The crossing back is
    /// located between the departure-side point and the interval's end.
    fn crossing_back(
        &mut self,
        s: &Slot,
        i: usize,
        iv: &Interval,
        g_b: f64,
        zero_at_start: bool,
    ) -> Result<Option<Candidate>, OdeError> {
        let step = self.step;
        let t_b = iv.t_b;
        // The crossing back ends on the side of g_b.
        let dir_back = if g_b > 0.0 {
            Direction::Rising
        } else {
            Direction::Falling
        };
        let left_to_other_side = match s.leave {
            Leave::Towards(sign) => (sign > 0.0) != (g_b > 0.0),
            _ => true,
        };
        if !(self.events.direction(i).allows(dir_back) && left_to_other_side) {
            return Ok(None);
        }
        let t_probe = step.t_probe;
        if !self.probed {
            y_at(self.integ, self.sys, t_probe, self.y_p);
            self.probed = true;
        }
        let g_p = self.events.value(i, t_probe, self.y_p);
        if g_p.is_nan() {
            return Err(OdeError::EventNotANumber {
                index: i,
                t: t_probe,
            });
        }
        let g_o = s.g_origin;
        // The probe must be beyond value_tol on the other side,
        // and, without a derivative, the guard must have reached
        // zero within the window (secant from the origin).
        let left = g_p.abs() > step.vtol
            && (g_p > 0.0) != (g_b > 0.0)
            && (s.leave != Leave::Probe
                || g_o.abs() <= step.vtol
                || g_o.abs() * (t_probe - step.start) <= (g_p - g_o).abs() * step.window);
        let mut bracket = left.then_some((t_probe, g_p, t_b, g_b));
        if !left && matches!(s.leave, Leave::Towards(_)) && (g_p > 0.0) == (g_b > 0.0) {
            bracket = self.departure_point(i, g_p, g_b)?;
        }
        let Some((t_l, g_l, t_r, g_r)) = bracket else {
            return Ok(None);
        };
        let (l, r) = self.locate(i, (t_l, g_l), (t_r, g_r), iv.tol)?;
        Ok((!step.ignorable(r, zero_at_start)).then_some((r, dir_back, l)))
    }

    /// The derivative says the guard left zero and the probe (`g_p`) is already back on the
    /// side of `g_b`: the excursion is shorter than the probe offset. Halves the offset
    /// (state in `tmp`) until a point lies on the departure side beyond `value_tol`, no
    /// closer to the origin than the window; returns the bracket of the crossing back,
    /// from that point to the probe.
    fn departure_point(
        &mut self,
        i: usize,
        g_p: f64,
        g_b: f64,
    ) -> Result<Option<(f64, f64, f64, f64)>, OdeError> {
        let step = self.step;
        let mut dt = (step.t_probe - step.start) * 0.5;
        while dt > step.window {
            let t_h = step.start + dt;
            let g_h = self.value(i, t_h);
            if g_h.is_nan() {
                return Err(OdeError::EventNotANumber { index: i, t: t_h });
            }
            if g_h.abs() > step.vtol && (g_h > 0.0) != (g_b > 0.0) {
                return Ok(Some((t_h, g_h, step.t_probe, g_p)));
            }
            dt *= 0.5;
        }
        Ok(None)
    }

    /// Events that were NaN at the right end of the sample interval `t_a`..`t_b` (flagged
    /// `nan`): without a hit earlier in the interval nothing can be said about their crossing,
    /// [`OdeError::EventNotANumber`] at `t_b`. With a hit, each must have a value at the
    /// pre-crossing end of the hit's bracket (else the same error there); one that has crossed by
    /// then in an allowed direction is located in `t_a`.. that point and wins if earlier. (An event
    /// that is undefined beyond another's crossing, e.g. a contact force once the contact is
    /// lost, is so allowed to be NaN after it.)
    fn nan_in_interval(
        &mut self,
        slots: &[Slot],
        best: Option<Best>,
        (t_a, t_b): (f64, f64),
        tol: f64,
    ) -> Result<Option<Best>, OdeError> {
        let mut out = best;
        for (j, s) in slots.iter().enumerate() {
            if !s.nan {
                continue;
            }
            let Some((_, _, _, r_lo)) = best else {
                return Err(OdeError::EventNotANumber { index: j, t: t_b });
            };
            let g = self.value(j, r_lo);
            if g.is_nan() {
                return Err(OdeError::EventNotANumber { index: j, t: r_lo });
            }
            if !s.armed || !(g == 0.0 || (g > 0.0) != (s.g_ref > 0.0)) {
                continue;
            }
            let dir = if s.g_ref < 0.0 {
                Direction::Rising
            } else {
                Direction::Falling
            };
            if !self.events.direction(j).allows(dir) || r_lo <= t_a {
                continue;
            }
            let (l, r) = self.locate(j, (t_a, s.g_ref), (r_lo, g), tol)?;
            if out.is_none_or(|(tb, _, _, _)| r < tb) {
                out = Some((r, j, dir, l));
            }
        }
        Ok(out)
    }
}

/// The root in $(0, 1)$ of the cubic Hermite interpolant on $s \in [0, 1]$ with $p(0) =$
/// `ga`, $p(1) =$ `gb` (of opposite signs) and derivatives `da`, `db` over a step of length
/// `h`, by bisection-safeguarded Newton on the polynomial (no guard evaluations), to
/// `resolution`.
fn hermite_root(ga: f64, (gb, da, db): (f64, f64, f64), h: f64, resolution: f64) -> f64 {
    let c1 = h * da;
    let c2 = 3.0 * (gb - ga) - h * (2.0 * da + db);
    let c3 = 2.0 * (ga - gb) + h * (da + db);
    let p = |u: f64| ga + u * (c1 + u * (c2 + u * c3));
    let dp = |u: f64| c1 + u * (2.0 * c2 + u * 3.0 * c3);
    let (mut a, mut b) = (0.0f64, 1.0f64);
    let mut u = ga / (ga - gb);
    for _ in 0..60 {
        let v = p(u);
        if v == 0.0 {
            break;
        }
        if (v > 0.0) == (ga > 0.0) {
            a = u;
        } else {
            b = u;
        }
        let next = u - v / dp(u);
        let newton = next > a && next < b;
        let step = if newton { next - u } else { 0.5 * (a + b) - u };
        u += step;
        if (newton && step.abs() < resolution) || b - a < resolution {
            break;
        }
    }
    u
}

/// Look for the earliest event on the last step of `integ` using its dense
/// output; returns the earliest hit with the root located to near machine
/// precision by the Illinois method (ties: smallest index). See the [`ode` docs,
/// Events](crate::ode#events) for the detection algorithm, its guarantee and the
/// start-of-segment and re-arming rules.
///
/// The hit is held by `state` (a reference is returned, nothing is
/// allocated); clone it to keep it past the next call (`.copied()` on the
/// result for fixed dimensions). Every event of the set is considered,
/// however many. Counts the hit in `integ.stats().events` and the rhs
/// evaluations made for event derivatives in `rhs_evals`.
///
/// The rules, in order (private functions of this module, each documented with its rule):
/// the start values and the per-guard arming and start rule (`Step::arm`), and the location
/// on the samples (`Scan::sample`: sign changes, grazing pairs, crossings back).
///
/// # Errors
/// [`OdeError::InvalidOption`] if `opts` is invalid
/// ([`EventOptions::validate`]); nothing is evaluated then.
pub fn find_first_event<'s, D, S, I, E>(
    integ: &mut I,
    sys: &S,
    events: &E,
    opts: &EventOptions,
    state: &'s mut EventState<D>,
) -> Result<Option<&'s EventHit<D>>, OdeError>
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
    E: EventSet<D> + ?Sized,
{
    opts.validate()?;
    let (t_prev, t_end) = (integ.t_prev(), integ.t());
    let ne = events.len();
    if ne == 0 || t_end.partial_cmp(&t_prev) != Some(std::cmp::Ordering::Greater) {
        return Ok(None);
    }
    let Some(start) = scan_start(state.resume, t_prev, t_end) else {
        return Ok(None);
    };
    state.prepare(integ.dim(), ne);
    let origin = *state.origin.get_or_insert(start);
    let step = Step::new(opts, (start, t_end), origin, state.last_hit);
    let sc = &mut state.scratch;
    y_at(integ, sys, start, &mut sc.y_a);
    // f at the start, when the integrator keeps it there.
    let f_a_known = start == t_prev && copy_known(integ.dy_prev(), &mut sc.f_a);
    let slots = &mut state.slots[..ne];
    let mut scan = Scan {
        integ,
        sys,
        events,
        tmp: &mut sc.tmp,
        f_c: &mut sc.f_c,
        zero: &sc.zero,
        y_p: &mut sc.y_p,
        probed: false,
        max_iter: opts.max_iter,
        step,
    };
    scan.start_values(slots, &sc.y_a, &mut sc.f_a, f_a_known)?;
    step.arm(slots);
    let Some((r, i, d, _)) = scan.sample(slots, &mut sc.y_b, &mut sc.f_b)? else {
        return Ok(None);
    };
    let hit = &mut state.hit;
    y_at(scan.integ, sys, r, &mut hit.y);
    (hit.index, hit.t, hit.direction) = (i, r, d);
    state.origin = Some(r);
    state.resume = Some((t_prev, r));
    state.last_hit = Some((i, d));
    scan.integ.stats_mut().events += 1;
    Ok(Some(&state.hit))
}

/// Where the scan of the step `t_prev..t_end` starts: just after the last hit on this same
/// step (`resume`), else at `t_prev`; `None` if that hit is at the step's end.
fn scan_start(resume: Option<(f64, f64)>, t_prev: f64, t_end: f64) -> Option<f64> {
    match resume {
        Some((tp, th)) if tp == t_prev && th > t_prev => (th < t_end).then_some(th),
        _ => Some(t_prev),
    }
}

/// Copies `src` into `dst` if there is one; whether there was.
fn copy_known<D: Dim>(src: Option<&OVector<f64, D>>, dst: &mut OVector<f64, D>) -> bool
where
    DefaultAllocator: Allocator<D>,
{
    match src {
        Some(f) => {
            dst.copy_from(f);
            true
        }
        None => false,
    }
}
