//! Contact onset on the exact free flight, by certified conservative advancement.
//!
//! Out of contact the rotor $r(\tau)$ and the relaxing ring $s(\tau)$ are known in closed
//! form. Contact starts where $h(\tau) = |r - s|^2 - \gamma^2$ reaches zero from below. With
//! $q = r - s$,
//!
//! $$h' = 2\,q\cdot q',\qquad h'' = 2|q'|^2 + 2\,q\cdot q'',\qquad
//! h''' = 6\,q'\cdot q'' + 2\,q\cdot q'''.$$
//!
//! From any time $\tau_0$ on, $|q|, |q'|, |q''|, |q'''|$ have rigorous bounds
//! ([`FreeFlight::bounds`](super::free_flight::FreeFlight::bounds) for the rotor; each ring
//! coordinate relaxes monotonically, so $|s_i|$ and $|s_i'|$ never grow and
//! $|s_i''| = |s_i'|/T_i$, $|s_i'''| = |s_i'|/T_i^2$), hence bounds $M_2 \ge |h''|$ and
//! $M_3 \ge |h'''|$. Taylor's theorem then gives two upper bounds for $u \ge 0$,
//!
//! $$h(\tau_0 + u) \le h_0 + h_0' u + \tfrac12 M_2 u^2,\qquad
//! h(\tau_0 + u) \le h_0 + h_0' u + \tfrac12 h_0'' u^2 + \tfrac16 M_3 u^3,$$
//!
//! and the search advances by the largest $u$ for which either bound is still negative. No
//! root of $h$ can lie in the interval skipped: **no contact is missed**, however shallow or
//! brief (a grazing touch only slows the advance, it cannot be stepped over). Near a
//! transversal crossing the advance converges to the root from below like Newton's method
//! (the step error is $O(h_0^2)$); the search stops when $h \ge -\epsilon_h$ with
//! $\epsilon_h = 4\times10^{-16}\gamma^2$, i.e. the contact time is located to about
//! $\epsilon_h / h'$.

use nalgebra::Vector2;

use super::free_flight::FreeFlight;
use crate::ring::SnubberRing;

/// Result of a search for contact onset.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Onset {
    /// No contact up to and including the horizon.
    None,
    /// Contact at this time.
    At(f64),
}

/// Counts of a search, for statistics.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct OnsetStats {
    /// Closed-form evaluations of the rotor and ring.
    pub evaluations: u64,
}

/// The relaxing ring from a segment start: `s(t) = relax(s0, t - t0)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RelaxingRing {
    /// Start time.
    pub t0: f64,
    /// Ring position at `t0`.
    pub s0: Vector2<f64>,
}

impl RelaxingRing {
    /// Position and velocity at `t`.
    pub fn at(&self, ring: &SnubberRing, t: f64) -> (Vector2<f64>, Vector2<f64>) {
        if self.s0 == Vector2::zeros() {
            return (self.s0, self.s0);
        }
        let s = ring.relax(&self.s0, t - self.t0);
        (s, ring.relax_velocity(&s))
    }
}

/// First positive root of $p(u) = c_0 + c_1 u + c_2 u^2 + c_3 u^3$ ($c_3 > 0$, $p(0^+) < 0$);
/// the result is at most the true root.
fn first_root_cubic(c0: f64, c1: f64, c2: f64, c3: f64) -> f64 {
    let p = |u: f64| c0 + u * (c1 + u * (c2 + u * c3));
    // Extrema of p: roots of c1 + 2 c2 u + 3 c3 u^2; p is monotone between them.
    let (a, b, c) = (3.0 * c3, 2.0 * c2, c1);
    let disc = b * b - 4.0 * a * c;
    let mut ends = [f64::INFINITY; 3];
    if disc > 0.0 {
        let sq = disc.sqrt();
        let q = -0.5 * (b + b.signum() * sq);
        let (r1, r2) = (q / a, if q != 0.0 { c / q } else { 0.0 });
        let (lo, hi) = if r1 < r2 { (r1, r2) } else { (r2, r1) };
        ends = [lo, hi, f64::INFINITY];
    }
    let mut left = 0.0;
    for &e in &ends {
        if e <= left {
            continue;
        }
        let right = if e.is_finite() {
            e
        } else {
            // p(u) >= c3 u^3 - (|c0| + |c1| u + |c2| u^2) > 0 beyond this.
            let m = (c0.abs() / c3).cbrt() + (c1.abs() / c3).sqrt() + c2.abs() / c3 + 1e-300;
            left.max(2.0 * m)
        };
        if p(right) > 0.0 {
            return bisect_last_negative(&p, left, right);
        }
        left = right;
    }
    f64::INFINITY
}

/// On `[lo, hi]` with `p` monotone increasing, `p(lo) <= 0 < p(hi)`: a point with `p <= 0`
/// within 1/4096 of the interval below the root (a step a little short of the largest
/// certified one costs nothing in safety and saves iterations).
fn bisect_last_negative(p: &impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    for _ in 0..12 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if p(mid) <= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    lo
}

/// First positive root of $c_0 + c_1 u + c_2 u^2$ with $c_2 > 0$, $c_0 \le 0$, computed
/// without cancellation; at most the true root.
fn first_root_quadratic(c0: f64, c1: f64, c2: f64) -> f64 {
    let disc = c1 * c1 - 4.0 * c2 * c0;
    let sq = disc.max(0.0).sqrt();
    // u = (-c1 + sq) / (2 c2) = -2 c0 / (c1 + sq)
    let u = if c1 >= 0.0 {
        if c1 + sq > 0.0 {
            -2.0 * c0 / (c1 + sq)
        } else {
            0.0
        }
    } else {
        (-c1 + sq) / (2.0 * c2)
    };
    u * (1.0 - 4.0 * f64::EPSILON)
}

/// Searches $(t_0, t_\text{end}]$ for contact onset. `rotor` and `ring_state` describe the
/// exact motion from their start times (at most `t0`). With `separating`, the rotor and ring
/// are known to be parting at `t0` (right after contact loss: $h' = 2\gamma N/c \le 0$ and
/// $h'' < 0$ there), so a touching start never fires, whatever the rounding of $h'$.
pub fn find_onset(
    rotor: &FreeFlight,
    ring_state: &RelaxingRing,
    ring: &SnubberRing,
    (t0, t_end): (f64, f64),
    separating: bool,
    stats: &mut OnsetStats,
) -> Onset {
    let gap2 = ring.gap * ring.gap;
    let eps_h = 4.0 * f64::EPSILON * gap2;
    let tc = ring.relaxation_time();
    let inv_t = Vector2::new(inv_or_zero(tc.x), inv_or_zero(tc.y));
    let rb = rotor.bounds();
    let r_bound = rotor.eccentricity_norm() + rb.position;
    let mut t = t0;
    let mut first = true;
    loop {
        let (y, acc) = rotor.state_accel(t);
        let (s, sd) = ring_state.at(ring, t);
        stats.evaluations += 1;
        let sdd = -sd.component_mul(&inv_t);
        let q = Vector2::new(y[0] - s.x, y[1] - s.y);
        let q1 = Vector2::new(y[2] - sd.x, y[3] - sd.y);
        let q2 = Vector2::new(acc[0] - sdd.x, acc[1] - sdd.y);
        let mut h = q.norm_squared() - gap2;
        let mut h1 = 2.0 * q.dot(&q1);
        let h2 = 2.0 * q1.norm_squared() + 2.0 * q.dot(&q2);
        if first {
            // An onset that holds at the start (right after contact loss) does not fire again
            // unless h is moving into contact.
            first = false;
            // |r - s|^2 is rounded relative to the size of r and s.
            let eps_start =
                eps_h.max(16.0 * f64::EPSILON * ring.gap * (y[0].hypot(y[1]) + s.norm()));
            if h.abs() <= eps_start {
                // Touching at the start: right after contact loss (where h' = 2 gamma N / c
                // is zero up to the rounding of the loss time) or a start on the ring. Only a
                // clear move into contact fires: h' above its rounding level (relative 1e-9
                // of its scale), or h' at that level with h'' > 0.
                let scale = 2.0 * q.norm() * (y[2].hypot(y[3]) + sd.norm() + 1e-300);
                if h1.abs() <= 1e-9 * scale || separating {
                    h1 = h1.min(0.0);
                }
                if !separating && (h1 > 0.0 || (h1 == 0.0 && h2 > 0.0)) {
                    return Onset::At(t);
                }
                h = h.min(0.0);
            } else if h > 0.0 {
                return Onset::At(t);
            }
        } else if h >= -eps_h {
            return Onset::At(t);
        }
        if t >= t_end {
            return Onset::None;
        }
        // Bounds on |q|, |q'|, |q''|, |q'''| for all later times.
        let sd_abs = Vector2::new(sd.x.abs(), sd.y.abs());
        let ring_acc = sd_abs.component_mul(&inv_t).norm();
        let ring_jerk = sd_abs.component_mul(&inv_t).component_mul(&inv_t).norm();
        let q0 = r_bound + s.norm();
        let q1m = rb.velocity + sd.norm();
        let q2m = rb.acceleration + ring_acc;
        let q3m = rb.jerk + ring_jerk;
        let m2 = 2.0 * q1m * q1m + 2.0 * q0 * q2m;
        let mut du = if h < 0.0 || h1 < 0.0 {
            first_root_quadratic(h, h1, 0.5 * m2)
        } else {
            0.0
        };
        if du < 1e-3 * (t_end - t).max(1e-300) {
            let m3 = 6.0 * q1m * q2m + 2.0 * q0 * q3m;
            if m3 > 0.0 && (h < 0.0 || h1 < 0.0 || (h1 == 0.0 && h2 < 0.0)) {
                du = du
                    .max(first_root_cubic(h, h1, 0.5 * h2, m3 / 6.0) * (1.0 - 4.0 * f64::EPSILON));
            }
        }
        let mut t_next = t + du;
        if t_next <= t && separating && t == t0 {
            // Parting by assumption: make progress even when no bound certifies any.
            t_next = t.next_up();
        }
        if t_next <= t {
            // The certified step is below the time resolution ulp(t): the crossing is within
            // one ulp. Report the first representable time after t when h is rising (so the
            // onset lies on the contact side), t itself otherwise (a touch).
            return Onset::At(if h1 > 0.0 { t.next_up().min(t_end) } else { t });
        }
        t = t_next.min(t_end);
    }
}

fn inv_or_zero(x: f64) -> f64 {
    if x > 0.0 {
        x.recip()
    } else {
        0.0
    }
}
