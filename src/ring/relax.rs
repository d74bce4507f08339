use nalgebra::Vector2;

use super::{RingAxis, SnubberRing};

/// Position at time `t` of one axis started at `s0` (see the module docs).
fn relax_axis(axis: &RingAxis, damping: f64, s0: f64, t: f64) -> f64 {
    if t.is_nan() {
        return f64::NAN;
    }
    if t <= 0.0 {
        return s0;
    }
    if damping == 0.0 {
        return 0.0;
    }
    let tc = 2.0 * damping / axis.stiffness;
    let d = axis.preload;
    if d == 0.0 || axis.is_inside(s0) {
        return s0 * decay(t / tc);
    }
    let a = s0.abs();
    let t1 = tc * ((a - d) / (2.0 * d)).ln_1p();
    let mag = if t <= t1 {
        (a + d) * (-t / tc).exp() - d
    } else {
        d * decay((t - t1) / tc)
    };
    mag.copysign(s0)
}

/// $e^{-x}$, without calling `exp` where it is 0 (the ring has relaxed for more than 746 time
/// constants, most of a free flight).
#[inline]
fn decay(x: f64) -> f64 {
    if x > 746.0 {
        0.0
    } else {
        (-x).exp()
    }
}

/// Velocity of one free axis at state `s`.
fn velocity_axis(axis: &RingAxis, damping: f64, s: f64) -> f64 {
    let push = if axis.is_inside(s) || s == 0.0 {
        s
    } else {
        s + axis.preload.copysign(s)
    };
    if damping == 0.0 {
        if push == 0.0 {
            0.0
        } else {
            f64::INFINITY.copysign(-push)
        }
    } else {
        -push * axis.stiffness / (2.0 * damping)
    }
}

/// Time for one free axis to relax from `s0` to the preload `|s| = D`.
fn time_to_preload_axis(axis: &RingAxis, damping: f64, s0: f64) -> f64 {
    let d = axis.preload;
    if axis.is_inside(s0) || damping == 0.0 {
        0.0
    } else if d == 0.0 {
        f64::INFINITY
    } else {
        2.0 * damping / axis.stiffness * ((s0.abs() - d) / (2.0 * d)).ln_1p()
    }
}

impl SnubberRing {
    /// Exact position at time `t >= 0` of the free ring started at `s0` ([free relaxation](crate::ring#free-relaxation)): piecewise exponential per axis. `t <= 0` returns `s0`; a NaN `t` gives NaN;
    /// with `nu2 = 0` every `t > 0` gives the rest position 0.
    pub fn relax(&self, s0: &Vector2<f64>, t: f64) -> Vector2<f64> {
        Vector2::new(
            relax_axis(&self.x, self.damping, s0.x, t),
            relax_axis(&self.y, self.damping, s0.y, t),
        )
    }

    /// Velocity `s'` of the free ring at state `s`: `-s/T` inside the preload,
    /// `-(s + sign(s) D)/T` beyond it (`T = 2 nu2/K`). With `nu2 = 0` the velocity is not finite:
    /// `-sign(s) * infinity` per axis (0 where `s = 0`).
    pub fn relax_velocity(&self, s: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(
            velocity_axis(&self.x, self.damping, s.x),
            velocity_axis(&self.y, self.damping, s.y),
        )
    }

    /// Exact velocity at time `t` of the free ring started at `s0`:
    /// `relax_velocity(relax(s0, t))`.
    pub fn relax_velocity_at(&self, s0: &Vector2<f64>, t: f64) -> Vector2<f64> {
        self.relax_velocity(&self.relax(s0, t))
    }

    /// Per axis, the time the free ring started at `s0` needs to come back inside the preload,
    /// `t1 = T ln((|s0| + D)/(2 D))` (0 if already inside or `nu2 = 0`; infinity if `D = 0` and
    /// `s0 != 0`, since such an axis is never inside).
    pub fn time_to_preload(&self, s0: &Vector2<f64>) -> Vector2<f64> {
        Vector2::new(
            time_to_preload_axis(&self.x, self.damping, s0.x),
            time_to_preload_axis(&self.y, self.damping, s0.y),
        )
    }

    /// Componentwise bounds `(lo, hi)` of the free ring's position over the whole interval
    /// `[0, t]`: each coordinate moves monotonically towards 0 without changing sign, so it lies
    /// between `s0` and `relax(s0, t)`. Useful to exclude contact over a step without sampling.
    pub fn relax_bounds(&self, s0: &Vector2<f64>, t: f64) -> (Vector2<f64>, Vector2<f64>) {
        let st = self.relax(s0, t);
        (
            Vector2::new(s0.x.min(st.x), s0.y.min(st.y)),
            Vector2::new(s0.x.max(st.x), s0.y.max(st.y)),
        )
    }
}

/// The free ring relaxing from `s0` since time `t0`: the ring's state out of contact.
///
/// Out of contact the massless ring's motion does not depend on the rotor, so these two numbers
/// describe it completely: $s(t) = $ [`SnubberRing::relax`]$(s_0, t - t_0)$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relaxation {
    /// Start time of the relaxation (the last contact loss or placement).
    pub t0: f64,
    /// Ring position at `t0`.
    pub s0: Vector2<f64>,
}

impl Relaxation {
    /// A ring at rest at its centre (fully relaxed) from time `t0` on.
    pub fn at_rest(t0: f64) -> Self {
        Self {
            t0,
            s0: Vector2::zeros(),
        }
    }

    /// Whether the ring is at its centre, where it stays.
    pub fn is_at_rest(&self) -> bool {
        self.s0 == Vector2::zeros()
    }

    /// Ring position and velocity at time `t >= t0`.
    pub fn at(&self, ring: &SnubberRing, t: f64) -> (Vector2<f64>, Vector2<f64>) {
        if self.is_at_rest() {
            return (self.s0, self.s0);
        }
        let s = ring.relax(&self.s0, t - self.t0);
        (s, ring.relax_velocity(&s))
    }

    /// Absolute times $t_0 + t_{1,i}$ at which each axis of the free ring comes back inside its
    /// preload ([`SnubberRing::time_to_preload`]): there the ring's velocity drops by the factor
    /// 2 and $h^\prime$ jumps, so the search is cut there. Infinity for an axis that never crosses: at
    /// rest, inside its preload from the start, without preload, or without ring damping.
    pub fn preload_crossings(&self, ring: &SnubberRing) -> Vector2<f64> {
        let t1 = ring.time_to_preload(&self.s0);
        let crossing = |i: usize, axis: &RingAxis| {
            if ring.damping > 0.0 && axis.preload > 0.0 && !axis.is_inside(self.s0[i]) {
                self.t0 + t1[i]
            } else {
                f64::INFINITY
            }
        };
        Vector2::new(crossing(0, &ring.x), crossing(1, &ring.y))
    }

    /// Position and *right* velocity $s^\prime(t^+)$ at `t`, on the smooth piece that starts at or
    /// contains `t`: an axis is on its inner piece from its crossing time (`crossings`, from
    /// [`Relaxation::preload_crossings`]) on, included, so that a node on a crossing gets the
    /// derivatives of the piece after it. Without ring damping the ring is at its centre (the
    /// right limit at $t_0$ of the instantaneous relaxation).
    pub(crate) fn right_state(
        &self,
        ring: &SnubberRing,
        crossings: &Vector2<f64>,
        t: f64,
    ) -> (Vector2<f64>, Vector2<f64>) {
        if self.s0 == Vector2::zeros() || ring.damping == 0.0 {
            return (Vector2::zeros(), Vector2::zeros());
        }
        let s = ring.relax(&self.s0, t - self.t0);
        let tc = ring.relaxation_time();
        let v = |i: usize, axis: &RingAxis| {
            // Beyond the preload (or without one) only one unit pushes back.
            let beyond = !axis.is_inside(self.s0[i]) && t < crossings[i];
            let push = if beyond {
                s[i] + axis.preload.copysign(self.s0[i])
            } else {
                s[i]
            };
            -push / tc[i]
        };
        (s, Vector2::new(v(0, &ring.x), v(1, &ring.y)))
    }
}
