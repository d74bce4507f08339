//! Contact onset on the exact free flight, by certified conservative advancement.
//!
//! Out of contact the rotor $r(\tau)$ and the relaxing ring $s(\tau)$ are known in closed
//! form. Contact starts where $h(\tau) = |r - s|^2 - \gamma^2$ reaches zero from below. With
//! $q = r - s$,
//!
//! $$h^\prime = 2\thinspace q\cdot q^\prime,\qquad
//! h^{\prime\prime} = 2|q^\prime|^2 + 2\thinspace q\cdot q^{\prime\prime},\qquad
//! h^{\prime\prime\prime} = 6\thinspace q^\prime\cdot q^{\prime\prime} +
//! 2\thinspace q\cdot q^{\prime\prime\prime}.$$
//!
//! # Smooth pieces
//!
//! The rotor's closed form is analytic in $\tau$. The ring's is piecewise: an axis that starts
//! beyond its preload relaxes on one exponential until it is back at $|s_i| = D_i$, at
//! $t_0 + t_{1,i}$ ([`Relaxation::preload_crossings`]), then on another. There $s_i^\prime$
//! drops by the factor 2, so $h^\prime$ jumps by $-2 q_i \operatorname{sign}(s_i) D_i/T_i$:
//! upwards when the rotor is on the far side of the ring's centre ($q_i s_i < 0$), where a
//! Taylor bound built before the crossing and used after it underestimates $h$. The search is
//! therefore **cut at every crossing**: each bound is applied on one smooth piece only, from the
//! derivatives of the piece after the node (right derivatives on a crossing). Without ring
//! damping ($\nu_2 = 0$) the relaxation is instantaneous and the ring is at its centre on the
//! whole window (the right limit at $t_0$).
//!
//! # Bounds and steps
//!
//! From a node $t_k$ to the end of its piece, $|q|, |q^\prime|, |q^{\prime\prime}|,
//! |q^{\prime\prime\prime}|$ have rigorous bounds: the rotor's from
//! [`RotorMotion::bounds_on`] on $[t_k, \text{piece end}]$ (by default [`RotorMotion::bounds`],
//! valid from the segment's start on; a linear rotor's decaying modes give bounds that shrink
//! along the segment: [`crate::rotor::LinearSegment`]). For the paper's model they are
//! [`FreeFlight::bounds`](crate::paper::FreeFlight::bounds) (the homogeneous energy never
//! grows, for every $\nu_1 \ge 0$: under-, critically and over-damped), the ring's because on a
//! piece each $|s_i|$ and $|s_i^\prime|$ decrease, with $|s_i^{\prime\prime}| =
//! |s_i^\prime|/T_i$ and $|s_i^{\prime\prime\prime}| = |s_i^\prime|/T_i^2$. They give
//! $M_2 \ge |h^{\prime\prime}|$ and $M_3 \ge |h^{\prime\prime\prime}|$ (inflated by $16\varepsilon$
//! against their own rounding), and Taylor's theorem two upper bounds for $u \ge 0$ up to the
//! piece's end,
//!
//! $$h(t_k + u) \le h_k + h_k^\prime u + \tfrac12 M_2 u^2,\qquad
//! h(t_k + u) \le h_k + h_k^\prime u + \tfrac12 h_k^{\prime\prime} u^2 + \tfrac16 M_3 u^3.$$
//!
//! The search advances to a point a little short of the first root of either bound (the
//! quadratic's root times $1 - 4\varepsilon$; the cubic's bracketed between its extrema and
//! located by [`numeric::illinois`](crate::numeric::illinois) to within 1/4096 below), but
//! never past the piece's end or the window's. Near a
//! transversal crossing it converges to the root from below like Newton's method; a grazing
//! touch only slows it.
//!
//! # The guarantee
//!
//! Let $\tilde h_k, \tilde h_k^\prime, \tilde h_k^{\prime\prime}$ be the closed form evaluated in
//! floating point at the nodes (the values the simulation itself uses) and
//! $\varepsilon_h = $ [`H_TOLERANCE`]$\thinspace\gamma^2 = 4\varepsilon\gamma^2$.
//!
//! * **No root is missed.** Every interval skipped lies in one smooth piece, and there the
//!   Taylor bound built on the node values is negative. Hence, were the node values exact,
//!   $h < 0$ on every skipped interval: $h$ has no root in $(t_0, t_s)$, or in
//!   $(t_0, t_\text{end}]$ when the result is [`Onset::None`], however shallow or brief the
//!   contact. With rounding, what is certified on the interval skipped from $t_k$ is
//!   $h(t_k + u) < \delta_k + \delta_k^\prime u + \tfrac12\delta_k^{\prime\prime} u^2$, where
//!   the $\delta$ are the rounding errors of $\tilde h_k, \tilde h_k^\prime,
//!   \tilde h_k^{\prime\prime}$ (the $u^2$ term only for the cubic bound): only a contact whose
//!   depth is at the rounding level of the closed form can be missed. That level is a few
//!   $\varepsilon\gamma(\gamma + R)$, with $R$ the size of the terms of $r$ and $s$, which
//!   includes $|Z|\thinspace|\varphi_0 + \eta\tau|$ since the forcing phase is rounded
//!   relative to its size (with the paper's parameters about $10^{-14}\gamma^2$ at
//!   $\tau = 100$, $10^{-11}\gamma^2$ at $\tau = 10^5$). The crossing times are rounded
//!   too: the closed form switches pieces within an ulp of the cut, where it is continuous.
//! * **What a reported onset means.** The result is the first node $t_s$ with
//!   $\tilde h(t_s) \ge -\varepsilon_h$: every earlier node had $\tilde h < -\varepsilon_h$,
//!   so $t_s$ is at or before the first root $\tau^\ast$ (up to the rounding above), and a near
//!   miss whose maximum is within $\varepsilon_h$ (plus rounding) of zero is reported as a
//!   touch. Where $h$ rises through zero with slope $g = h^\prime(\tau^\ast)$,
//!   $\tau^\ast - (\varepsilon_h + \delta)/g \lesssim t_s \le \tau^\ast + \delta/g$; at a grazing
//!   contact of depth $d$ ($g \approx \sqrt{2|h^{\prime\prime}|d}$) this is
//!   $(\varepsilon_h + \delta)/\sqrt{2|h^{\prime\prime}| d}$, about $10^{-9}$ for
//!   $d = 10^{-12}\gamma^2$.
//! * **Below one ulp of time.** If the certified step from a node falls below $\mathrm{ulp}(t)$
//!   ($\tilde h$ is then within about $|h^\prime|\thinspace\mathrm{ulp}(t) + M_2
//!   \mathrm{ulp}(t)^2$ of zero, so a near miss deeper than that never gets there), the search
//!   stops: the onset is within the time resolution. It reports `t.next_up()` when
//!   $\tilde h^\prime > 0$ (the first representable time on the contact side) and $t$ otherwise
//!   (a touch). Such an onset may have $\tilde h < -\varepsilon_h$, by at most about
//!   $|h^\prime|\thinspace\mathrm{ulp}(t)$ (late in long runs one ulp of time moves the
//!   rotor by more than $10^{-12}$).
//! * **A segment's start is not certified.** At $t_0 =$ `rotor.start()` with $|\tilde h| \le
//!   \varepsilon_\text{start} = \max(\varepsilon_h, 16\varepsilon\gamma(\max(|r|, R) + |s|))$,
//!   $R$ the rotor's position bound ([`MotionBounds::position`]: the size of the closed form's
//!   terms, which round $h$ even where $r$ itself is small), the start is touching (right after contact loss, or a touch without load): it fires only if
//!   $\tilde h^\prime$ exceeds $10^{-9}$ of its scale $2|q|(|r^\prime| + |s^\prime|)$, or is 0
//!   with $\tilde h^{\prime\prime} > 0$, and never with `separating`. Otherwise the first
//!   bound is built on $\min(\tilde h, 0)$ and, when $|\tilde h^\prime|$ is within that
//!   $10^{-9}$ (always with `separating`), on $\min(\tilde h^\prime, 0)$: a contact that would
//!   start within this rounding of the start state is deemed not to be a new one. With
//!   `separating` a step of one ulp may also be taken where no bound certifies any. A later
//!   window start (the search's chunks) is a node like any other.
//! * **Assumed.** $t_0 \ge$ `rotor.start()` (the rotor bounds hold after the segment's start)
//!   and $t_0 \ge$ `ring_state.t0`. A closed form that is not finite stops the search with
//!   [`Onset::At`] at that node: nothing is certified past it, and the caller meets the
//!   non-finite state there.
//!
//! `tests/suite/ring/onset_bruteforce.rs` checks this against dense sampling of the closed form on $10^4$
//! (and, ignored by default, $10^5$) constructed near-grazing cases.

use nalgebra::Vector2;

use super::{Relaxation, SnubberRing};
use crate::numeric::{illinois, RootOptions};

/// The search's stopping tolerance relative to $\gamma^2$: it reports an onset at the first node
/// where $h \ge -\varepsilon_h$, $\varepsilon_h = 4\varepsilon\gamma^2$.
pub const H_TOLERANCE: f64 = 4.0 * f64::EPSILON;

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

/// Bounds on the rotor's motion at the ring's station, valid for every time after a free
/// flight's start ([`RotorMotion::bounds`]) or on a stretch of it ([`RotorMotion::bounds_on`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MotionBounds {
    /// Bound on $|r|$ (distance from the ring's rest centre).
    pub position: f64,
    /// Bound on $|r^\prime|$.
    pub velocity: f64,
    /// Bound on $|r^{\prime\prime}|$.
    pub acceleration: f64,
    /// Bound on $|r^{\prime\prime\prime}|$.
    pub jerk: f64,
}

/// The rotor's free motion at the ring's station, known in closed form from a start time on,
/// with rigorous bounds: what the certified onset search needs from a rotor model that solves
/// its free flight exactly (the paper's model: [`crate::paper::FreeFlight`]).
pub trait RotorMotion {
    /// Start time of the closed form.
    fn start(&self) -> f64;
    /// Position, velocity and acceleration at the station at time `t >= start()`.
    fn kinematics(&self, t: f64) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>);
    /// Bounds on $|r|$, $|r^\prime|$, $|r^{\prime\prime}|$, $|r^{\prime\prime\prime}|$ valid
    /// for every $t \ge$ `start()` (the search's certificate rests on them).
    fn bounds(&self) -> MotionBounds;
    /// Bounds valid on $[t_\text{from}, t_\text{to}]$ ($t_\text{from} \ge$ `start()`,
    /// $t_\text{to}$ possibly infinite): the search asks for them at every node, for the
    /// stretch up to the end of the node's smooth piece. A motion made of decaying modes gives
    /// far smaller bounds late in a segment than at its start (a mode of rate $10^6$ has a
    /// jerk bound $10^{18}$ times its amplitude at the start, none once it has decayed); a
    /// growing one gives bounds on a finite window only. Default: [`RotorMotion::bounds`].
    fn bounds_on(&self, from: f64, to: f64) -> MotionBounds {
        let _ = (from, to);
        self.bounds()
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
        let p_right = p(right);
        if p_right > 0.0 {
            return last_negative(&p, left, right, p_right);
        }
        left = right;
    }
    f64::INFINITY
}

/// On `[lo, hi]` with `p` monotone increasing, `p(lo) <= 0 < p(hi)` (`p_hi`): a point with
/// `p <= 0` within 1/4096 of the interval below the root (a step a little short of the largest
/// certified one costs nothing in safety and saves iterations), by the crate's root finder
/// [`illinois`] with its stopping rule of 1/4096 of the interval or 64 evaluations and without
/// its bisection of slow steps (this search's rule since it was written: the Illinois steps
/// on these monotone cubics, each point kept at least half of that resolution inside the
/// bracket, so that it closes once an end sits on the root). The bracket always holds the
/// root, as with bisection, in about a third of bisection's evaluations.
fn last_negative(p: &impl Fn(f64) -> f64, lo: f64, hi: f64, p_hi: f64) -> f64 {
    // A point with p = 0 is on the certified side (`p <= 0`): its value is given the sign of
    // that side (the smallest negative number), which the root finder's tie rule (a zero
    // joins the far end) would otherwise put on the other.
    let g = |u: f64| {
        let v = p(u);
        if v > 0.0 || v.is_nan() {
            v
        } else {
            v.min(-f64::from_bits(1))
        }
    };
    let opts = RootOptions::default()
        .with_tol((hi - lo) / 4096.0)
        .with_max_evaluations(64)
        .with_bisect_when_slow(false);
    illinois((lo, g(lo)), (hi, p_hi), &opts, g).map_or(lo, |b| b.lo)
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

/// Searches $(t_0, t_\text{end}]$ for contact onset, with the guarantee stated in the
/// [module docs](self): no root of $h$ skipped (to the rounding of the closed form), the onset
/// reported at the first node where $h \ge -\varepsilon_h$ (or within one ulp of time).
/// `rotor` and `ring_state` describe the exact motion from their start times (at most `t0`).
/// With `separating`, the rotor and ring are known to be parting at `t0` (right after contact
/// loss: $h^\prime = 2\gamma N/c \le 0$ and $h^{\prime\prime} < 0$ there), so a touching
/// start never fires, whatever the rounding of $h^\prime$. `stats` counts the closed-form
/// evaluations (one per node; a preload crossing inside the window adds at most one node).
pub fn find_onset(
    rotor: &impl RotorMotion,
    ring_state: &Relaxation,
    ring: &SnubberRing,
    (t0, t_end): (f64, f64),
    separating: bool,
    stats: &mut OnsetStats,
) -> Onset {
    let search = OnsetSearch::new(rotor, ring_state, ring, separating, (t0, t_end));
    let mut t = t0;
    // Only a segment's start can be touching (right after contact loss, or a touch without
    // load); a later window start is a node like any other.
    let mut first = t0 == rotor.start();
    loop {
        let mut node = search.node(t);
        stats.evaluations += 1;
        if !(node.h.is_finite() && node.h1.is_finite() && node.h2.is_finite()) {
            // No bound holds on a closed form that is not finite: stop here rather than
            // certify anything; the caller meets the non-finite state at t.
            return Onset::At(t);
        }
        let fires = if first {
            first = false;
            search.fires_at_start(&mut node)
        } else {
            node.h >= -search.eps_h
        };
        if fires {
            return Onset::At(t);
        }
        if t >= t_end {
            return Onset::None;
        }
        // The closed form is smooth up to the next preload crossing: the Taylor bounds are
        // applied on [t, piece_end] only, from the derivatives of the piece after t.
        let piece_end = next_after(&search.crossings, t).min(t_end);
        let mut t_next = t + search.certified_step(&node, t, piece_end);
        if t_next <= t && separating && t == t0 {
            // Parting by assumption: make progress even when no bound certifies any.
            t_next = t.next_up();
        }
        if t_next <= t {
            // The certified step is below the time resolution ulp(t): the crossing is within
            // one ulp. Report the first representable time after t when h is rising (so the
            // onset lies on the contact side), t itself otherwise (a touch).
            return Onset::At(if node.h1 > 0.0 {
                t.next_up().min(t_end)
            } else {
                t
            });
        }
        if t_next >= t_end && piece_end >= t_end {
            // The certified step covers the rest of the window: no onset up to t_end, without
            // an evaluation at t_end (the next window starts there with one).
            return Onset::None;
        }
        t = t_next.min(piece_end);
    }
}

/// The onset search of one free-flight segment, as an exact mode's
/// [`ExactSegment::next_guard`](crate::hybrid::ExactSegment::next_guard) runs it: the driver
/// asks for consecutive windows ending at output times, and the answer must not depend on
/// them, so [`find_onset`] is run in chunks ending on multiples of a fixed length (the forcing
/// period), and the onset, once found, is kept. Only the very start of the segment is a
/// separation (`separating`: right after contact loss).
#[derive(Debug, Clone, PartialEq)]
pub struct OnsetScan {
    start: f64,
    chunk: f64,
    separating: bool,
    /// No onset before this time (certified).
    searched_to: f64,
    /// The onset, once found.
    found: Option<f64>,
    stats: OnsetStats,
}

impl OnsetScan {
    /// A scan of the segment starting at `start`, in chunks ending on multiples of `chunk`.
    pub fn new(start: f64, chunk: f64, separating: bool) -> Self {
        OnsetScan {
            start,
            chunk,
            separating,
            searched_to: start,
            found: None,
            stats: OnsetStats::default(),
        }
    }

    /// The first onset in $(t_\text{from}, t_\text{to}]$, if any, of `rotor` (started at
    /// this scan's start) against the ring relaxing as `relax`.
    pub fn next_onset(
        &mut self,
        rotor: &impl RotorMotion,
        relax: &Relaxation,
        ring: &SnubberRing,
        t_from: f64,
        t_to: f64,
    ) -> Option<f64> {
        self.searched_to = self.searched_to.max(t_from);
        loop {
            if let Some(t) = self.found {
                return (t <= t_to).then_some(t);
            }
            if self.searched_to >= t_to {
                return None;
            }
            let k = (self.searched_to / self.chunk).floor() + 1.0;
            let chunk_end = (k * self.chunk).max(self.searched_to.next_up());
            // Only the very start of the segment is a separation.
            let separating = self.separating && self.searched_to == self.start;
            match find_onset(
                rotor,
                relax,
                ring,
                (self.searched_to, chunk_end),
                separating,
                &mut self.stats,
            ) {
                Onset::None => self.searched_to = chunk_end,
                Onset::At(t) => self.found = Some(t),
            }
        }
    }

    /// Closed-form evaluations made so far.
    pub fn evaluations(&self) -> u64 {
        self.stats.evaluations
    }
}

/// What [`find_onset`] holds fixed over one window: the motions, the ring's relaxation times
/// and preload crossings, the rotor's bounds and the tolerance on $h$.
struct OnsetSearch<'a, R> {
    rotor: &'a R,
    ring_state: &'a Relaxation,
    ring: &'a SnubberRing,
    separating: bool,
    gap2: f64,
    /// $\varepsilon_h$: an onset is reported at the first node where $h \ge -\varepsilon_h$.
    eps_h: f64,
    /// $1/T_i$ of each axis (0 for an axis that does not relax).
    inv_t: Vector2<f64>,
    /// The ring's preload crossing times.
    crossings: Vector2<f64>,
    bounds: MotionBounds,
}

/// The closed form at one node: the rotor $r$, $r^\prime$ and the ring $s$, $s^\prime$, their
/// difference $q = r - s$, and $h = |q|^2 - \gamma^2$ with its first two derivatives.
struct Node {
    r: Vector2<f64>,
    v: Vector2<f64>,
    s: Vector2<f64>,
    sd: Vector2<f64>,
    q: Vector2<f64>,
    h: f64,
    h1: f64,
    h2: f64,
}

impl<'a, R: RotorMotion> OnsetSearch<'a, R> {
    fn new(
        rotor: &'a R,
        ring_state: &'a Relaxation,
        ring: &'a SnubberRing,
        separating: bool,
        (t0, t_end): (f64, f64),
    ) -> Self {
        let gap2 = ring.gap * ring.gap;
        let tc = ring.relaxation_time();
        OnsetSearch {
            rotor,
            ring_state,
            ring,
            separating,
            gap2,
            eps_h: H_TOLERANCE * gap2,
            inv_t: Vector2::new(inv_or_zero(tc.x), inv_or_zero(tc.y)),
            crossings: ring_state.preload_crossings(ring),
            bounds: rotor.bounds_on(t0, t_end),
        }
    }

    /// The closed form at `t` (one evaluation).
    #[inline]
    fn node(&self, t: f64) -> Node {
        let (r, v, acc) = self.rotor.kinematics(t);
        let (s, sd) = self.ring_state.right_state(self.ring, &self.crossings, t);
        let sdd = -sd.component_mul(&self.inv_t);
        let q = Vector2::new(r.x - s.x, r.y - s.y);
        let q1 = Vector2::new(v.x - sd.x, v.y - sd.y);
        let q2 = Vector2::new(acc.x - sdd.x, acc.y - sdd.y);
        Node {
            r,
            v,
            s,
            sd,
            q,
            h: q.norm_squared() - self.gap2,
            h1: 2.0 * q.dot(&q1),
            h2: 2.0 * q1.norm_squared() + 2.0 * q.dot(&q2),
        }
    }

    /// Whether an onset fires at the segment's start: one that holds there (right after contact
    /// loss) fires only if $h$ is moving into contact. When it does not, a touching start's
    /// $h$ and $h^\prime$ are set to the safe side for the bounds.
    #[inline]
    fn fires_at_start(&self, node: &mut Node) -> bool {
        let Node { r, v, s, sd, q, .. } = *node;
        // |r - s|^2 is rounded relative to the size of the terms of r and s: the closed
        // form's terms can be far larger than r itself (a rest position many gaps out), and
        // the rotor's position bound covers them.
        let eps_start = self.eps_h.max(
            16.0 * f64::EPSILON
                * self.ring.gap
                * (r.x.hypot(r.y).max(self.bounds.position) + s.norm()),
        );
        if node.h.abs() > eps_start {
            return node.h > 0.0;
        }
        // Touching at the start: right after contact loss (where h' = 2 gamma N / c is zero up
        // to the rounding of the loss time) or a start on the ring. Only a clear move into
        // contact fires: h' above its rounding level (relative 1e-9 of its scale), or h' at
        // that level with h'' > 0.
        let scale = 2.0 * q.norm() * (v.x.hypot(v.y) + sd.norm() + 1e-300);
        if node.h1.abs() <= 1e-9 * scale || self.separating {
            node.h1 = node.h1.min(0.0);
        }
        if !self.separating && (node.h1 > 0.0 || (node.h1 == 0.0 && node.h2 > 0.0)) {
            return true;
        }
        node.h = node.h.min(0.0);
        false
    }

    /// The largest step from the node at `t` over which $h$ certainly stays below 0, within
    /// the smooth piece ahead, which ends at `piece_end`: the first root of the quadratic (or,
    /// when that is short, cubic) Taylor bound on $h$.
    #[inline]
    fn certified_step(&self, node: &Node, t: f64, piece_end: f64) -> f64 {
        let Node {
            s, sd, h, h1, h2, ..
        } = *node;
        let piece = piece_end - t;
        let rb = &self.rotor.bounds_on(t, piece_end);
        // Bounds on the derivatives of q on the piece: the rotor's on [t, piece_end] (by
        // default from the segment start, valid for all later times), the ring's from t (each
        // coordinate and its velocity decay monotonically on a piece, with s_i'' = -s_i'/T_i).
        let sd_abs = Vector2::new(sd.x.abs(), sd.y.abs());
        let ring_acc = sd_abs.component_mul(&self.inv_t).norm();
        let ring_jerk = sd_abs
            .component_mul(&self.inv_t)
            .component_mul(&self.inv_t)
            .norm();
        let q0 = rb.position + s.norm();
        let q1m = rb.velocity + sd.norm();
        let q2m = rb.acceleration + ring_acc;
        let q3m = rb.jerk + ring_jerk;
        let m2 = (2.0 * q1m * q1m + 2.0 * q0 * q2m) * BOUND_MARGIN;
        let mut du = if h < 0.0 || h1 < 0.0 {
            first_root_quadratic(h, h1, 0.5 * m2)
        } else {
            0.0
        };
        if du < 1e-3 * piece.max(1e-300) {
            let m3 = (6.0 * q1m * q2m + 2.0 * q0 * q3m) * BOUND_MARGIN;
            if m3 > 0.0 && (h < 0.0 || h1 < 0.0 || (h1 == 0.0 && h2 < 0.0)) {
                du = du
                    .max(first_root_cubic(h, h1, 0.5 * h2, m3 / 6.0) * (1.0 - 4.0 * f64::EPSILON));
            }
        }
        du
    }
}

/// Relative inflation of the bounds $M_2$, $M_3$ against their own rounding (sums and
/// products of a few positive numbers).
const BOUND_MARGIN: f64 = 1.0 + 16.0 * f64::EPSILON;

/// The first of `times` strictly after `t` (infinity if none).
fn next_after(times: &Vector2<f64>, t: f64) -> f64 {
    times
        .iter()
        .filter(|&&c| c > t)
        .fold(f64::INFINITY, |a, &c| a.min(c))
}

fn inv_or_zero(x: f64) -> f64 {
    if x > 0.0 {
        x.recip()
    } else {
        0.0
    }
}
