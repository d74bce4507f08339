//! The detector: [`find_first_event`].

use super::state::{EndValue, Leave, Scratch, Slot};
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

/// Whether the cubic Hermite interpolant through `(t, g, g')` at both ends of
/// a sample interval (derivatives of opposite signs: one interior extremum)
/// reaches zero, or at least half of the way from the nearer end value to
/// zero, at its interior extremum.
fn hermite_extremum_near_zero(a: (f64, f64, f64), b: (f64, f64, f64)) -> bool {
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
    let mut roots = [f64::NAN; 2];
    if qa.abs() <= 1e-14 * (qb.abs() + qc.abs()) {
        if qb != 0.0 {
            roots[0] = -qc / qb;
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            let q = -0.5 * (qb + qb.signum() * disc.sqrt());
            roots[0] = q / qa;
            if q != 0.0 {
                roots[1] = qc / q;
            }
        }
    }
    let nearer = ga.abs().min(gb.abs());
    let mut any = false;
    for s in roots {
        if s > 0.0 && s < 1.0 {
            any = true;
            let v = p(s);
            if v == 0.0 || (v > 0.0) != (ga > 0.0) || v.abs() <= 0.5 * nearer {
                return true;
            }
        }
    }
    // No interior extremum of the interpolant despite the derivative signs:
    // be safe and search.
    !any
}

/// Whether two vectors hold the same bits.
fn same_bits<D: Dim>(a: &OVector<f64, D>, b: &OVector<f64, D>) -> bool
where
    DefaultAllocator: Allocator<D>,
{
    a.len() == b.len()
        && a.iter()
            .zip(b.iter())
            .all(|(x, y)| x.to_bits() == y.to_bits())
}

/// The step-end screen of one guard: values and derivatives `(g, g')` at both ends of a step of
/// length `h`, of the same sign, and the cubic Hermite interpolant $p$ through them stays at
/// least half of the smaller end value $m = \min(|g_a|, |g_b|)$ away from zero on the whole
/// step (on its side). Then the guard has no root on the step as long as the interpolant's
/// error is below $m/2$ (module docs, *Screening*). Non-finite input is never cleared.
/// Usually decided by the convex hull of the Bernstein coefficients, else at the interior
/// extrema.
#[inline(always)]
fn hermite_clear(a: (f64, f64), b: (f64, f64), h: f64) -> bool {
    let (ga, da) = a;
    let (gb, db) = b;
    if !(ga != 0.0 && gb != 0.0 && (ga > 0.0) == (gb > 0.0)) {
        return false;
    }
    // Signed so that the ends are positive.
    let sign = ga.signum();
    let margin = 0.5 * ga.abs().min(gb.abs());
    // Quick sufficient test, the usual case of a guard far from zero: a cubic on [0, 1] lies
    // above the smallest of its Bernstein coefficients, (g_a, g_a + h g_a'/3, g_b - h g_b'/3,
    // g_b) signed, of which the ends are at least 2 margin.
    const THIRD: f64 = 1.0 / 3.0;
    let (b1, b2) = ((ga + h * da * THIRD) * sign, (gb - h * db * THIRD) * sign);
    if b1.min(b2) >= margin {
        return true;
    }
    // p(s) = c0 + c1 s + c2 s^2 + c3 s^3 on s in [0, 1].
    let (c0, c1) = (ga * sign, h * da * sign);
    let c2 = (3.0 * (gb - ga) - h * (2.0 * da + db)) * sign;
    let c3 = (2.0 * (ga - gb) + h * (da + db)) * sign;
    if !(c1.is_finite() && c2.is_finite() && c3.is_finite()) {
        return false;
    }
    let p = |s: f64| c0 + s * (c1 + s * (c2 + s * c3));
    // Interior extrema: roots of p'(s) = c1 + 2 c2 s + 3 c3 s^2 in (0, 1).
    let (qa, qb, qc) = (3.0 * c3, 2.0 * c2, c1);
    let mut ok = true;
    let mut check = |s: f64| {
        if s > 0.0 && s < 1.0 {
            ok &= p(s) >= margin;
        }
    };
    if qa == 0.0 {
        if qb != 0.0 {
            check(-qc / qb);
        }
    } else {
        let disc = qb * qb - 4.0 * qa * qc;
        if disc >= 0.0 {
            let q = -0.5 * (qb + disc.sqrt().copysign(qb));
            check(q / qa);
            if q != 0.0 {
                check(qc / q);
            } else {
                check(0.0);
            }
        }
    }
    ok
}

/// Locates the root of event `i` in the bracket `lo`..`hi` (values of
/// opposite sign, or zero at `hi`); returns the final bracket `(lo, hi)`, `hi` the
/// post-crossing end. A NaN of the event inside the bracket is
/// [`OdeError::EventNotANumber`].
#[allow(clippy::too_many_arguments)]
fn locate<D, S, I, E>(
    integ: &mut I,
    sys: &S,
    events: &E,
    i: usize,
    lo: (f64, f64),
    hi: (f64, f64),
    tol: f64,
    max_iter: usize,
    tmp: &mut OVector<f64, D>,
) -> Result<(f64, f64), OdeError>
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
    E: EventSet<D> + ?Sized,
{
    let opts = RootOptions::default().tol(tol).max_evaluations(max_iter);
    let found = illinois(lo, hi, &opts, |t| {
        y_at(integ, sys, t, tmp);
        events.value(i, t, tmp)
    });
    match found {
        Ok(b) => match b.nan_at {
            Some(t) => Err(OdeError::EventNotANumber { index: i, t }),
            None => Ok((b.lo, b.hi)),
        },
        // The callers pass a sign change; were it none, the bracket stays as given.
        Err(_) => Ok((lo.0, hi.0)),
    }
}

/// Narrows the bracket `lo`..`hi` (values of opposite sign, as for [`locate`]) of event `i`
/// before the root search, when the derivatives at both ends are known (finite): the root
/// of the cubic Hermite interpolant of the two ends, $t^*$, is usually within a tiny fraction
/// of the bracket of the root, so $g$ is evaluated at $t^* \pm \delta$ with
/// $\delta = 2^{-16}$ of the bracket (at least `tol`) and the narrowest sub-bracket with a
/// verified sign change is returned (the given one when the estimate misses). Two evaluations
/// that save about half of the root finder's.
#[allow(clippy::too_many_arguments)]
fn narrow_bracket<D, S, I, E>(
    integ: &mut I,
    sys: &S,
    events: &E,
    i: usize,
    lo: (f64, f64, f64),
    hi: (f64, f64, f64),
    tol: f64,
    tmp: &mut OVector<f64, D>,
) -> ((f64, f64), (f64, f64))
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
    E: EventSet<D> + ?Sized,
{
    let (ta, ga, da) = lo;
    let (tb, gb, db) = hi;
    let plain = ((ta, ga), (tb, gb));
    let h = tb - ta;
    let delta = (h * 2f64.powi(-16)).max(tol);
    if gb == 0.0 || !(da.is_finite() && db.is_finite()) || 4.0 * delta >= h {
        return plain;
    }
    // Hermite cubic on s in [0, 1], p(0) = ga, p(1) = gb of opposite signs: its root by
    // bisection safeguarded Newton on the polynomial (no guard evaluations).
    let c1 = h * da;
    let c2 = 3.0 * (gb - ga) - h * (2.0 * da + db);
    let c3 = 2.0 * (ga - gb) + h * (da + db);
    let p = |u: f64| ga + u * (c1 + u * (c2 + u * c3));
    let dp = |u: f64| c1 + u * (2.0 * c2 + u * 3.0 * c3);
    let (mut a, mut b) = (0.0f64, 1.0f64);
    let mut u = ga / (ga - gb);
    let resolution = 1e-3 * delta / h;
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
    let est = ta + u * h;
    let (l, r) = (est - delta, est + delta);
    if !(l > ta && r < tb) {
        return plain;
    }
    let mut g_at = |t: f64| {
        y_at(integ, sys, t, tmp);
        events.value(i, t, tmp)
    };
    let crossed = |g: f64| g == 0.0 || (g > 0.0) != (ga > 0.0);
    let gl = g_at(l);
    if gl.is_nan() {
        return plain;
    }
    if crossed(gl) {
        return ((ta, ga), (l, gl));
    }
    let gr = g_at(r);
    if gr.is_nan() {
        return ((l, gl), (tb, gb));
    }
    if crossed(gr) {
        ((l, gl), (r, gr))
    } else {
        ((r, gr), (tb, gb))
    }
}

/// Look for the earliest event on the last step of `integ` using its dense
/// output; returns the earliest hit with the root located to near machine
/// precision by the Illinois method (ties: smallest index). See the [module
/// docs](super) for the detection algorithm, its guarantee and the
/// start-of-segment and re-arming rules.
///
/// The hit is held by `state` (a reference is returned, nothing is
/// allocated); clone it to keep it past the next call (`.copied()` on the
/// result for fixed dimensions). Every event of the set is considered,
/// however many. Counts the hit in `integ.stats().events` and the rhs
/// evaluations made for event derivatives in `rhs_evals`.
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
    let t_prev = integ.t_prev();
    let t_end = integ.t();
    let ne = events.len();
    if ne == 0 || t_end.partial_cmp(&t_prev) != Some(std::cmp::Ordering::Greater) {
        return Ok(None);
    }
    // Where to start: after the last hit on this same step, else t_prev.
    let mut start = t_prev;
    if let Some((tp, th)) = state.resume {
        if tp == t_prev && th > t_prev {
            if th >= t_end {
                return Ok(None);
            }
            start = th;
        }
    }
    state.prepare(integ.dim(), ne);
    let EventState {
        origin: st_origin,
        resume,
        last_hit,
        slots,
        end_at,
        end_len,
        scratch,
        hit,
    } = state;
    let Scratch {
        y_a,
        f_a,
        y_b,
        f_b,
        y_p,
        y_e,
        tmp,
        f_c,
        zero,
    } = scratch;
    let slots = &mut slots[..ne];

    let origin = match *st_origin {
        None => {
            *st_origin = Some(start);
            start
        }
        Some(o) => o,
    };
    let at_origin = origin == start;

    let m = opts.samples_per_step;
    let max_iter = opts.max_iter;
    let vtol = opts.value_tol;
    let tol_at = |t: f64| opts.root_tol.max(4.0 * f64::EPSILON * t.abs());
    // Twice the root tolerance of any interval of this step (the zero left by
    // a hit located on an earlier, similar step is within it).
    let window = opts
        .rearm_time
        .max(2.0 * tol_at(start.abs().max(t_end.abs())));
    let span = t_end - start;
    // Probe point of guards that may have left zero at the origin.
    let t_probe = start
        + (4.0 * window)
            .max(span * 2f64.powi(-20))
            .min(span / (2 * (m + 1)) as f64);
    let mut probed = false;

    y_at(integ, sys, start, y_a);
    // f at the start, when the integrator keeps it there.
    let f_a_known = start == t_prev
        && match integ.dy_prev() {
            Some(f) => {
                f_a.copy_from(f);
                true
            }
            None => false,
        };
    // The end values of the last screened step, if this step starts there with the same state.
    let reuse = opts.screen
        && start == t_prev
        && *end_at == Some(start)
        && *end_len == ne
        && same_bits(y_a, y_e);

    let mut fresh = false;
    for (i, s) in slots.iter_mut().enumerate() {
        let e = s.end;
        *s = Slot {
            active: events.active(i),
            end: e,
            ..Slot::default()
        };
        if !s.active {
            continue;
        }
        if reuse && e.known {
            s.has_der = e.has_der;
            s.needs_rhs = e.needs_rhs;
            s.g_ref = e.g;
            s.d_ref = e.d;
        } else {
            s.needs_rhs = events.derivative_needs_rhs_of(i);
            fresh = true;
        }
    }
    if fresh {
        // All events at once, the derivatives with the true f if known, else with zeros:
        // exact unless the event reads f, which is then evaluated.
        let dy: &OVector<f64, D> = if f_a_known { f_a } else { zero };
        let mut start_rhs = false;
        events.values_and_derivatives(start, y_a, dy, true, &mut |i, g, d| {
            let s = &mut slots[i];
            if reuse && s.end.known {
                return;
            }
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
            sys.rhs(start, y_a, f_a);
            integ.stats_mut().rhs_evals += 1;
            for (i, s) in slots.iter_mut().enumerate() {
                if s.active && s.has_der && s.needs_rhs && !(reuse && s.end.known) {
                    s.d_ref = events.derivative(i, start, y_a, f_a).unwrap_or(0.0);
                }
            }
        }
    }
    // No sign at the start: nothing can be said about this step.
    if let Some(i) = slots.iter().position(|s| s.active && s.g_ref.is_nan()) {
        return Err(OdeError::EventNotANumber { index: i, t: start });
    }
    // The event that defined the origin (start-of-segment rule 2).
    let fired = if at_origin {
        last_hit.map(|(j, _)| j)
    } else {
        None
    };
    for (i, s) in slots.iter_mut().enumerate() {
        if !s.active {
            continue;
        }
        let g = s.g_ref;
        s.g_origin = g;
        s.armed = if at_origin {
            g.abs() > vtol
        } else {
            g != 0.0 && !g.is_nan()
        };
        if at_origin && !s.armed {
            if let Some((j, d)) = *last_hit {
                if j == i {
                    // The event that just fired keeps its post-crossing sign.
                    s.armed = true;
                    s.g_ref = if d == Direction::Falling {
                        -f64::MIN_POSITIVE
                    } else {
                        f64::MIN_POSITIVE
                    };
                }
            }
        }
        if at_origin && fired != Some(i) && !g.is_nan() {
            // How this guard may leave zero (start-of-segment rule).
            s.leave = if s.d_ref != 0.0 && !s.d_ref.is_nan() {
                let on_zero =
                    g.abs() <= vtol || (g * s.d_ref < 0.0 && g.abs() <= s.d_ref.abs() * window);
                if on_zero {
                    Leave::Towards(s.d_ref.signum())
                } else {
                    Leave::No
                }
            } else {
                Leave::Probe
            };
        }
    }

    // Screening: every guard at the step's end, then the cubic Hermite test of each.
    if opts.screen {
        y_b.copy_from(integ.y());
        let f_b_known = match integ.dy() {
            Some(f) => {
                f_b.copy_from(f);
                true
            }
            None => false,
        };
        let need_f = !f_b_known && slots.iter().any(|s| s.active && s.has_der && s.needs_rhs);
        if need_f {
            sys.rhs(t_end, y_b, f_b);
            integ.stats_mut().rhs_evals += 1;
        }
        let dy: &OVector<f64, D> = if f_b_known || need_f { f_b } else { zero };
        let any_der = slots.iter().any(|s| s.active && s.has_der);
        for s in slots.iter_mut() {
            s.end.known = false;
        }
        events.values_and_derivatives(t_end, y_b, dy, any_der, &mut |i, g, d| {
            let s = &mut slots[i];
            s.end = EndValue {
                known: true,
                has_der: s.has_der,
                needs_rhs: s.needs_rhs,
                g,
                d: if s.has_der { d.unwrap_or(0.0) } else { 0.0 },
            };
        });
        let mut all_cleared = true;
        for (i, s) in slots.iter_mut().enumerate() {
            if !s.active {
                continue;
            }
            if !s.end.known {
                // Not reported by the set's batch evaluation: one by one.
                let d = if s.has_der {
                    events.derivative(i, t_end, y_b, dy).unwrap_or(0.0)
                } else {
                    0.0
                };
                s.end = EndValue {
                    known: true,
                    has_der: s.has_der,
                    needs_rhs: s.needs_rhs,
                    g: events.value(i, t_end, y_b),
                    d,
                };
            }
            // Only a guard armed as usual, with a derivative, can be cleared (a guard on zero
            // at the origin follows the start-of-segment rule on the samples).
            s.cleared = s.has_der
                && s.armed
                && s.leave == Leave::No
                && fired != Some(i)
                && hermite_clear((s.g_ref, s.d_ref), (s.end.g, s.end.d), span);
            all_cleared &= s.cleared;
        }
        *end_at = Some(t_end);
        *end_len = ne;
        y_e.copy_from(y_b);
        if all_cleared {
            return Ok(None);
        }
    } else {
        *end_at = None;
    }
    let need_rhs = slots
        .iter()
        .any(|s| s.active && !s.cleared && s.has_der && s.needs_rhs);

    let mut t_a = start;
    for k in 1..=m + 1 {
        let t_b = if k == m + 1 {
            t_end
        } else {
            start + span * (k as f64 / (m + 1) as f64)
        };
        // The step's end was evaluated by the screen.
        let screened_end = opts.screen && k == m + 1;
        if !screened_end {
            y_at(integ, sys, t_b, y_b);
            if need_rhs {
                sys.rhs(t_b, y_b, f_b);
                integ.stats_mut().rhs_evals += 1;
            }
        }
        // Best candidate of this interval: (t, index, direction, pre-crossing end of its bracket).
        let mut best: Option<(f64, usize, Direction, f64)> = None;
        let mut any_nan = false;
        for (i, s) in slots.iter_mut().enumerate() {
            s.nan = false;
            if !s.active || s.cleared {
                continue;
            }
            let (g_b, d_b) = if screened_end {
                (s.end.g, s.end.d)
            } else {
                let dy_b: &OVector<f64, D> = if s.needs_rhs { f_b } else { zero };
                let d_b = if s.has_der {
                    events.derivative(i, t_b, y_b, dy_b).unwrap_or(0.0)
                } else {
                    0.0
                };
                (events.value(i, t_b, y_b), d_b)
            };
            if g_b.is_nan() {
                // No sign at this sample: decided after the interval's other events.
                s.nan = true;
                any_nan = true;
                continue;
            }
            let allowed = events.direction(i);
            let tol = tol_at(t_a.abs().max(t_b.abs()));
            // Only the event that fired and guards on zero at the origin have a zero at the
            // start time; any other guard's root, however close, is a crossing.
            let zero_at_start =
                fired == Some(i) || matches!(s.leave, Leave::Towards(_) | Leave::Probe);
            let ignorable = |r: f64| at_origin && r - start <= window && zero_at_start;
            // (t, direction, pre-crossing end of the bracket)
            let mut candidate: Option<(f64, Direction, f64)> = None;
            // A guard on zero at the origin that left it on the other side of
            // g_b and came back is only visible at the probe point.
            let mut check_return = false;
            if !s.armed {
                if g_b.abs() > vtol && g_b != 0.0 {
                    s.armed = true;
                    s.g_ref = g_b;
                    check_return = s.leave != Leave::No;
                }
                s.d_ref = d_b;
                if !check_return {
                    continue;
                }
            } else {
                let g_a = s.g_ref;
                let dir_first = if g_a < 0.0 {
                    Direction::Rising
                } else {
                    Direction::Falling
                };
                if g_b == 0.0 || (g_b > 0.0) != (g_a > 0.0) {
                    if allowed.allows(dir_first) {
                        // A root already found earlier in this interval: this guard's root
                        // can only win if it has crossed by then (one root per interval).
                        // (If this event has no value at that root, it must have one at the
                        // pre-crossing end of the root's bracket.)
                        let mut hi = (t_b, g_b, d_b);
                        if let Some((mut rb, _, _, rb_lo)) = best {
                            y_at(integ, sys, rb, tmp);
                            let mut g_r = events.value(i, rb, tmp);
                            if g_r.is_nan() {
                                rb = rb_lo;
                                y_at(integ, sys, rb, tmp);
                                g_r = events.value(i, rb, tmp);
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
                        if !hi.0.is_nan() {
                            let lo = (t_a, g_a, if s.has_der { s.d_ref } else { f64::NAN });
                            let (lo, hi) = narrow_bracket(integ, sys, events, i, lo, hi, tol, tmp);
                            let (l, r) = locate(integ, sys, events, i, lo, hi, tol, max_iter, tmp)?;
                            if !ignorable(r) {
                                candidate = Some((r, dir_first, l));
                            }
                        }
                    }
                } else {
                    if s.has_der
                        && s.d_ref != 0.0
                        && d_b != 0.0
                        && (s.d_ref > 0.0) != (d_b > 0.0)
                        && hermite_extremum_near_zero((t_a, g_a, s.d_ref), (t_b, g_b, d_b))
                    {
                        candidate = grazing_pair(
                            integ,
                            sys,
                            events,
                            i,
                            (t_a, g_a, s.d_ref),
                            (t_b, g_b, d_b),
                            (tol, max_iter, s.needs_rhs),
                            tmp,
                            f_c,
                            zero,
                            ignorable,
                        )?;
                    }
                    // No sign change over the first interval: it may hide a
                    // departure from zero and the crossing back.
                    check_return = k == 1
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
                if allowed.allows(dir_back) && left_to_other_side {
                    if !probed {
                        y_at(integ, sys, t_probe, y_p);
                        probed = true;
                    }
                    let g_p = events.value(i, t_probe, y_p);
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
                    let left = g_p.abs() > vtol
                        && (g_p > 0.0) != (g_b > 0.0)
                        && (s.leave != Leave::Probe
                            || g_o.abs() <= vtol
                            || g_o.abs() * (t_probe - start) <= (g_p - g_o).abs() * window);
                    // The derivative says the guard left zero and the probe is already back
                    // on the side of g_b: the excursion is shorter than the probe offset.
                    // Halve the offset (own state in `tmp`) until a point lies on the
                    // departure side, no closer to the origin than the window.
                    let mut bracket = left.then_some((t_probe, g_p, t_b, g_b));
                    if !left && matches!(s.leave, Leave::Towards(_)) && (g_p > 0.0) == (g_b > 0.0) {
                        let mut dt = (t_probe - start) * 0.5;
                        while dt > window {
                            let t_h = start + dt;
                            y_at(integ, sys, t_h, tmp);
                            let g_h = events.value(i, t_h, tmp);
                            if g_h.is_nan() {
                                return Err(OdeError::EventNotANumber { index: i, t: t_h });
                            }
                            if g_h.abs() > vtol && (g_h > 0.0) != (g_b > 0.0) {
                                bracket = Some((t_h, g_h, t_probe, g_p));
                                break;
                            }
                            dt *= 0.5;
                        }
                    }
                    if let Some((t_l, g_l, t_r, g_r)) = bracket {
                        let (l, r) = locate(
                            integ,
                            sys,
                            events,
                            i,
                            (t_l, g_l),
                            (t_r, g_r),
                            tol,
                            max_iter,
                            tmp,
                        )?;
                        if !ignorable(r) {
                            candidate = Some((r, dir_back, l));
                        }
                    }
                }
            }
            if let Some((r, d, l)) = candidate {
                if best.is_none_or(|(tb, _, _, _)| r < tb) {
                    best = Some((r, i, d, l));
                }
            }
        }
        if any_nan {
            best = nan_in_interval(
                integ,
                sys,
                events,
                slots,
                best,
                (t_a, t_b),
                (tol_at(t_a.abs().max(t_b.abs())), max_iter),
                tmp,
            )?;
        }
        if let Some((r, i, d, _)) = best {
            y_at(integ, sys, r, &mut hit.y);
            hit.index = i;
            hit.t = r;
            hit.direction = d;
            *st_origin = Some(r);
            *resume = Some((t_prev, r));
            *last_hit = Some((i, d));
            integ.stats_mut().events += 1;
            return Ok(Some(hit));
        }
        t_a = t_b;
    }
    Ok(None)
}

/// Searches a possible grazing pair of event `i` in the sample interval
/// `a`..`b` (values of the same sign, derivatives of opposite signs): moves
/// towards the extremum by the Illinois method on $\dot g$ and stops as soon
/// as $g$ changes sign; then locates the first root in an allowed direction.
#[allow(clippy::too_many_arguments)]
fn grazing_pair<D, S, I, E>(
    integ: &mut I,
    sys: &S,
    events: &E,
    i: usize,
    a: (f64, f64, f64),
    b: (f64, f64, f64),
    (tol, max_iter, need_rhs): (f64, usize, bool),
    tmp: &mut OVector<f64, D>,
    f_c: &mut OVector<f64, D>,
    zero: &OVector<f64, D>,
    ignorable: impl Fn(f64) -> bool,
) -> Result<Option<(f64, Direction, f64)>, OdeError>
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
    E: EventSet<D> + ?Sized,
{
    let (t_a, g_a, d_a) = a;
    let (t_b, g_b, d_b) = b;
    let dir_first = if g_a < 0.0 {
        Direction::Rising
    } else {
        Direction::Falling
    };
    let allowed = events.direction(i);
    let mut crossed: Option<(f64, f64)> = None;
    let mut g_nan: Option<f64> = None;
    let pos_g = g_a > 0.0;
    let mut evals = 0u64;
    let opts = RootOptions::default().tol(tol).max_evaluations(max_iter);
    let search = illinois((t_a, d_a), (t_b, d_b), &opts, |t| {
        if crossed.is_some() {
            return 0.0; // terminate: bracket found
        }
        y_at(integ, sys, t, tmp);
        let g = events.value(i, t, tmp);
        if g.is_nan() {
            g_nan = Some(t);
            return f64::NAN; // stops the search (below)
        }
        if g == 0.0 || (g > 0.0) != pos_g {
            crossed = Some((t, g));
            return 0.0;
        }
        if need_rhs {
            sys.rhs(t, tmp, f_c);
            evals += 1;
        }
        let dy: &OVector<f64, D> = if need_rhs { f_c } else { zero };
        events.derivative(i, t, tmp, dy).unwrap_or(0.0)
    });
    integ.stats_mut().rhs_evals += evals;
    if let Some(t) = g_nan {
        // The event has no value there.
        return Err(OdeError::EventNotANumber { index: i, t });
    }
    if search.map_or(true, |b| b.nan_at.is_some()) {
        // Its derivative has none (or no sign change, not searched): as for an event without a
        // derivative, the pair is not searched.
        return Ok(None);
    }
    let Some((c, g_c)) = crossed else {
        return Ok(None);
    };
    if allowed.allows(dir_first) {
        let (l, r) = locate(
            integ,
            sys,
            events,
            i,
            (t_a, g_a),
            (c, g_c),
            tol,
            max_iter,
            tmp,
        )?;
        if !ignorable(r) {
            return Ok(Some((r, dir_first, l)));
        }
    }
    if allowed.allows(dir_first.opposite()) && g_c != 0.0 {
        let (l, r) = locate(
            integ,
            sys,
            events,
            i,
            (c, g_c),
            (t_b, g_b),
            tol,
            max_iter,
            tmp,
        )?;
        if !ignorable(r) {
            return Ok(Some((r, dir_first.opposite(), l)));
        }
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
#[allow(clippy::too_many_arguments)]
fn nan_in_interval<D, S, I, E>(
    integ: &mut I,
    sys: &S,
    events: &E,
    slots: &[Slot],
    best: Option<(f64, usize, Direction, f64)>,
    (t_a, t_b): (f64, f64),
    (tol, max_iter): (f64, usize),
    tmp: &mut OVector<f64, D>,
) -> Result<Option<(f64, usize, Direction, f64)>, OdeError>
where
    D: Dim,
    DefaultAllocator: Allocator<D>,
    S: OdeSystem<D>,
    I: Integrator<D>,
    E: EventSet<D> + ?Sized,
{
    let mut out = best;
    for (j, s) in slots.iter().enumerate() {
        if !s.nan {
            continue;
        }
        let Some((_, _, _, r_lo)) = best else {
            return Err(OdeError::EventNotANumber { index: j, t: t_b });
        };
        y_at(integ, sys, r_lo, tmp);
        let g = events.value(j, r_lo, tmp);
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
        if !events.direction(j).allows(dir) || r_lo <= t_a {
            continue;
        }
        let (l, r) = locate(
            integ,
            sys,
            events,
            j,
            (t_a, s.g_ref),
            (r_lo, g),
            tol,
            max_iter,
            tmp,
        )?;
        if out.is_none_or(|(tb, _, _, _)| r < tb) {
            out = Some((r, j, dir, l));
        }
    }
    Ok(out)
}
