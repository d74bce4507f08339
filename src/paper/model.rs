//! The paper's model as a [`RotorModel`]: modes, vector fields, guards, transitions.

use std::cell::Cell;

use nalgebra::{SVector, Vector2, U6};

use super::free_flight::{FreeFlight, FreeOscillator};
use super::onset::{find_onset, Onset, OnsetStats, RelaxingRing};
use crate::hybrid::{
    simulate, ExactSegment, Flow, GuardCrossing, ModelError, OutputPlan, RotorModel, SimError,
    SimOptions, SimStats, Trajectory,
};
use crate::ode::Direction;
use crate::params::{ParamError, Params};
use crate::ring::{Branch, BranchContact, Branches, RingAxis, RingContact, SnubberRing};

/// State `[x, y, x', y', x_s, y_s]`: rotor position and velocity, ring position.
pub type State = SVector<f64, 6>;

/// Relative distance inside the gap circle within which an onset counts as a touch of the
/// rotor's surface (the onset time is located to rounding).
const ONSET_TOUCH: f64 = 1e-12;

/// Relative distance to its preload within which the other axis counts as crossing at the
/// same time as the axis whose guard fired (a corner of the regime map).
const CORNER_TOL: f64 = 1e-10;

/// A mode of the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Mode {
    /// Regime I: no contact; rotor and ring move in closed form.
    Free,
    /// Regime I right after contact loss (or a touch without load): as [`Mode::Free`], but
    /// the contact onset search starts by separating, since the ring and rotor are touching
    /// and, by the loss condition, parting (to rounding).
    Separating,
    /// Contact on the given force-law branches (regimes II..V).
    Contact(Branches),
}

/// Guard names, for event logs.
pub mod guard {
    /// Contact begins (free flight).
    pub const ONSET: &str = "contact onset";
    /// Normal contact force reaches zero.
    pub const LOSS: &str = "contact loss";
    /// Rotor back at the gap circle.
    pub const GAP: &str = "rotor at gap";
    /// x crosses its preload outward.
    pub const X_OUT: &str = "x_s beyond preload";
    /// x crosses its preload inward.
    pub const X_IN: &str = "x_s within preload";
    /// y crosses its preload outward.
    pub const Y_OUT: &str = "y_s beyond preload";
    /// y crosses its preload inward.
    pub const Y_IN: &str = "y_s within preload";
}

/// The Jeffcott rotor with a preloaded snubber ring (non-dimensional, gap 1).
#[derive(Debug, Clone, PartialEq)]
pub struct JeffcottModel {
    params: Params,
    ring: SnubberRing,
    osc: FreeOscillator,
    amp: f64,
}

/// A failed run with what was computed before the failure.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{error}")]
pub struct RunFailure {
    /// The error, with the last good time and state.
    pub error: SimError<U6>,
    /// Everything recorded up to the failure.
    pub partial: Trajectory<U6>,
}

/// Per-run scratch: the last ring location (guards evaluate it at the same point several
/// times) and the warm start of its solver.
#[derive(Debug, Default)]
pub struct Cache {
    /// `(x, y, branches, mu)` of the last ring location.
    key: Cell<Option<(f64, f64, Branches, f64)>>,
    /// The last ring location.
    contact: Cell<Option<BranchContact>>,
    /// `(t, cos, sin)` of the forcing phase at a recent time.
    phase: Cell<Option<(f64, f64, f64)>>,
}

/// $(\cos a, \sin a)$ for $|a| \le 1/4$ by Taylor polynomials (truncation below
/// $10^{-19}$): four times cheaper than `sin_cos`.
fn small_cos_sin(a: f64) -> (f64, f64) {
    let a2 = a * a;
    let sin = a
        * (1.0
            + a2 * (-1.0 / 6.0
                + a2 * (1.0 / 120.0
                    + a2 * (-1.0 / 5040.0
                        + a2 * (1.0 / 362_880.0
                            + a2 * (-1.0 / 39_916_800.0 + a2 * (1.0 / 6_227_020_800.0)))))));
    let cos = 1.0
        + a2 * (-0.5
            + a2 * (1.0 / 24.0
                + a2 * (-1.0 / 720.0
                    + a2 * (1.0 / 40_320.0
                        + a2 * (-1.0 / 3_628_800.0 + a2 * (1.0 / 479_001_600.0))))));
    (cos, sin)
}

impl JeffcottModel {
    /// Builds the model.
    ///
    /// # Errors
    /// [`ParamError`] for invalid parameters.
    pub fn new(params: Params) -> Result<Self, ParamError> {
        let p = params.validated()?;
        let ring = SnubberRing {
            x: RingAxis {
                stiffness: p.kx,
                preload: p.dx,
            },
            y: RingAxis {
                stiffness: p.ky,
                preload: p.dy,
            },
            damping: p.nu2,
            gap: 1.0,
        };
        Ok(Self {
            params: p,
            ring,
            osc: FreeOscillator::new(&p),
            amp: p.forcing_amplitude(),
        })
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The ring element.
    pub fn ring(&self) -> &SnubberRing {
        &self.ring
    }

    /// A consistent state for a rotor at `r` with velocity `v`: the ring at rest at its centre
    /// out of contact ($|r| \le 1$), at its minimum-energy location in contact.
    ///
    /// # Errors
    /// [`ModelError::InvalidState`] for non-finite input.
    pub fn state_at(&self, r: [f64; 2], v: [f64; 2]) -> Result<State, ModelError> {
        let rv = Vector2::new(r[0], r[1]);
        if !(rv.iter().chain(v.iter()).all(|x| x.is_finite())) {
            return Err(ModelError::InvalidState {
                t: 0.0,
                reason: "non-finite rotor position or velocity".into(),
            });
        }
        let s = if rv.norm() > self.ring.gap {
            self.ring
                .locate(&rv)
                .map_err(|e| ModelError::InvalidState {
                    t: 0.0,
                    reason: e.to_string(),
                })?
                .s
        } else {
            Vector2::zeros()
        };
        Ok(State::from([r[0], r[1], v[0], v[1], s.x, s.y]))
    }

    /// Runs from `(t0, y0)` with the given outputs.
    ///
    /// # Errors
    /// [`RunFailure`] carrying the error and everything recorded before it.
    pub fn run(
        &self,
        t0: f64,
        y0: &State,
        plan: &OutputPlan,
        opts: &SimOptions,
    ) -> Result<(Trajectory<U6>, SimStats), Box<RunFailure>> {
        let mut traj = Trajectory::default();
        match simulate(self, t0, y0, plan, opts, &mut traj) {
            Ok(stats) => Ok((traj, stats)),
            Err(error) => Err(Box::new(RunFailure {
                error,
                partial: traj,
            })),
        }
    }

    /// Stroboscopic states $y(2\pi k/\eta)$ for `k = first..=last`, from `y0` at time 0.
    ///
    /// # Errors
    /// [`RunFailure`] carrying the error and the states computed before it; a reversed range
    /// (`first > last`) is [`crate::hybrid::SimErrorKind::InvalidOption`].
    pub fn stroboscopic(
        &self,
        y0: &State,
        first: u64,
        last: u64,
        opts: &SimOptions,
    ) -> Result<(Trajectory<U6>, SimStats), Box<RunFailure>> {
        let plan = OutputPlan::strobe(self.params.forcing_period(), first, last);
        self.run(0.0, y0, &plan, opts)
    }

    /// $(\cos, \sin)$ of the forcing phase $\varphi_0 + \eta t$: the stages of a step are
    /// close in time, so the phase at a recent time is rotated by the small difference
    /// instead of calling `sin_cos` at every stage (the forcing by recurrence).
    fn forcing_phase(&self, t: f64, cache: &Cache) -> (f64, f64) {
        let eta = self.params.eta;
        if let Some((tb, cb, sb)) = cache.phase.get() {
            let a = eta * (t - tb);
            if a.abs() <= 0.25 {
                let (c, s) = small_cos_sin(a);
                return (cb * c - sb * s, sb * c + cb * s);
            }
        }
        let (s, c) = (self.params.phi0 + eta * t).sin_cos();
        cache.phase.set(Some((t, c, s)));
        (c, s)
    }

    /// Ring location on the mode's branches, reusing the last one at the same point.
    fn contact(&self, b: Branches, y: &State, cache: &Cache) -> Option<BranchContact> {
        let (x, yy) = (y[0], y[1]);
        // The key is small to compare; the contact is copied out only on a hit.
        let hint = match cache.key.get() {
            Some((lx, ly, lb, mu)) if lb == b => {
                if lx == x && ly == yy {
                    return cache.contact.get();
                }
                mu
            }
            _ => f64::NAN,
        };
        let c = self.ring.locate_on(&Vector2::new(x, yy), b, hint)?;
        cache.key.set(Some((x, yy, b, c.mu)));
        cache.contact.set(Some(c));
        Some(c)
    }

    /// Branches of a contact that starts here: an axis exactly on its preload (within
    /// [`CORNER_TOL`]) takes the branch it is moving into, since its guard, zero at the start,
    /// would not fire.
    fn branches_at_start(&self, c: &RingContact, r_dot: &Vector2<f64>) -> Branches {
        let mut b = Branches::of(&self.ring, &c.s);
        let v = c.ring_velocity(r_dot);
        for (i, axis) in [self.ring.x, self.ring.y].iter().enumerate() {
            let (s, d) = (c.s[i], axis.preload);
            if d > 0.0 && (s.abs() - d).abs() <= CORNER_TOL * d {
                let br = if s * v[i] > 0.0 {
                    Branch::Outer(if s >= 0.0 { 1 } else { -1 })
                } else {
                    Branch::Inner
                };
                if i == 0 {
                    b.x = br;
                } else {
                    b.y = br;
                }
            }
        }
        b
    }

    /// Guards of a contact mode: loss, gap, then one per preloaded axis.
    fn axis_guard(&self, b: Branches, i: usize) -> Option<(usize, Branch)> {
        let mut k = 2;
        for (axis, (ra, br)) in [(&self.ring.x, b.x), (&self.ring.y, b.y)]
            .into_iter()
            .enumerate()
        {
            if ra.preload > 0.0 {
                if k == i {
                    return Some((axis, br));
                }
                k += 1;
            }
        }
        None
    }
}

/// Free flight: the rotor's closed form and the ring's exact relaxation.
#[derive(Debug, Clone)]
pub struct FreeSegment {
    rotor: FreeFlight,
    start: [f64; 4],
    relax: RelaxingRing,
    ring: SnubberRing,
    stats: OnsetStats,
    /// The search is run in chunks ending on multiples of this (the forcing period), never at
    /// output times, so that asking for outputs does not move the onset by a rounding.
    chunk: f64,
    /// No onset before this time (certified).
    searched_to: f64,
    /// The onset, once found.
    found: Option<f64>,
    /// Starts touching and parting (after contact loss).
    separating: bool,
}

impl ExactSegment<U6> for FreeSegment {
    fn eval(&self, t: f64, y: &mut State, dy: &mut State) {
        let (mut r, acc) = self.rotor.state_accel(t);
        if t == self.rotor.start() {
            // The closed form's particular and homogeneous parts cancel to rounding at the
            // start; the start state is known exactly.
            r = self.start;
        }
        let (s, sd) = self.relax.at(&self.ring, t);
        *y = State::from([r[0], r[1], r[2], r[3], s.x, s.y]);
        *dy = State::from([r[2], r[3], acc[0], acc[1], sd.x, sd.y]);
    }

    fn next_guard(&mut self, t_from: f64, t_to: f64) -> Option<GuardCrossing> {
        self.searched_to = self.searched_to.max(t_from);
        loop {
            if let Some(t) = self.found {
                return (t <= t_to).then_some(GuardCrossing { guard: 0, t });
            }
            if self.searched_to >= t_to {
                return None;
            }
            let k = (self.searched_to / self.chunk).floor() + 1.0;
            let chunk_end = (k * self.chunk).max(self.searched_to.next_up());
            // Only the very start of the segment is a separation.
            let separating = self.separating && self.searched_to == self.rotor.start();
            match find_onset(
                &self.rotor,
                &self.relax,
                &self.ring,
                (self.searched_to, chunk_end),
                separating,
                &mut self.stats,
            ) {
                Onset::None => self.searched_to = chunk_end,
                Onset::At(t) => self.found = Some(t),
            }
        }
    }

    fn evaluations(&self) -> u64 {
        self.stats.evaluations
    }
}

impl RotorModel for JeffcottModel {
    type Dim = U6;
    type Mode = Mode;
    type Segment = FreeSegment;
    type Cache = Cache;

    fn dim(&self) -> U6 {
        U6
    }

    fn new_cache(&self) -> Cache {
        Cache::default()
    }

    fn initial_mode(&self, t: f64, y: &State) -> Result<Mode, ModelError> {
        let r = Vector2::new(y[0], y[1]);
        let s = Vector2::new(y[4], y[5]);
        let gap = self.ring.gap;
        let dist = (r - s).norm();
        let tol = 1e-9 * gap;
        if dist < gap - tol || (dist <= gap + tol && r.norm() <= gap) {
            return Ok(Mode::Free);
        }
        if dist > gap + tol {
            return Err(ModelError::InvalidState {
                t,
                reason: format!(
                    "rotor beyond the ring: |r - s| = {dist} > gap {gap}; place the ring with JeffcottModel::state_at"
                ),
            });
        }
        let c = self.ring.locate(&r).map_err(|e| ModelError::InvalidState {
            t,
            reason: e.to_string(),
        })?;
        if (c.s - s).norm() > 1e-8 * gap {
            return Err(ModelError::InvalidState {
                t,
                reason: format!(
                    "rotor in contact but the ring is at {s:?}, not at its minimum-energy location {:?}; use JeffcottModel::state_at",
                    c.s
                ),
            });
        }
        // A start whose contact force would pull (or vanish) is a start at contact loss.
        let v = Vector2::new(y[2], y[3]);
        if c.normal_force(&self.ring, &v) <= 0.0 {
            return Ok(Mode::Separating);
        }
        Ok(Mode::Contact(self.branches_at_start(&c, &v)))
    }

    fn flow(&self, mode: Mode) -> Flow {
        match mode {
            Mode::Free | Mode::Separating => Flow::Exact,
            Mode::Contact(_) => Flow::Integrated,
        }
    }

    fn rhs(&self, mode: Mode, t: f64, y: &State, dy: &mut State, cache: &Cache) {
        let (cs, sn) = self.forcing_phase(t, cache);
        let p = &self.params;
        let mut fx = self.amp * cs - 2.0 * p.nu1 * y[2] - (y[0] - p.ex);
        let mut fy = self.amp * sn - 2.0 * p.nu1 * y[3] - (y[1] - p.ey);
        let (mut sdx, mut sdy) = (0.0, 0.0);
        if let Mode::Contact(b) = mode {
            let rd = Vector2::new(y[2], y[3]);
            match self.contact(b, y, cache) {
                Some(c) => {
                    let sd = c.ring_velocity(&rd);
                    let f = c.elastic + c.damping.component_mul(&sd);
                    fx -= f.x;
                    fy -= f.y;
                    sdx = sd.x;
                    sdy = sd.y;
                }
                None => {
                    fx = f64::NAN;
                    fy = f64::NAN;
                }
            }
        }
        *dy = State::from([y[2], y[3], fx, fy, sdx, sdy]);
    }

    fn guard_count(&self, mode: Mode) -> usize {
        match mode {
            Mode::Free | Mode::Separating => 1,
            Mode::Contact(_) => {
                2 + usize::from(self.ring.x.preload > 0.0) + usize::from(self.ring.y.preload > 0.0)
            }
        }
    }

    fn guard_direction(&self, mode: Mode, i: usize) -> Direction {
        match mode {
            Mode::Free | Mode::Separating => Direction::Rising,
            Mode::Contact(b) => match self.axis_guard(b, i) {
                None => Direction::Falling,
                Some((_, Branch::Inner)) => Direction::Rising,
                Some((_, Branch::Outer(_))) => Direction::Falling,
            },
        }
    }

    fn guard_value(&self, mode: Mode, i: usize, _t: f64, y: &State, cache: &Cache) -> f64 {
        let Mode::Contact(b) = mode else {
            // Free flight guards are located by the exact segment.
            return -1.0;
        };
        let r = Vector2::new(y[0], y[1]);
        if i == 1 {
            return r.norm_squared() - self.ring.gap * self.ring.gap;
        }
        let Some(c) = self.contact(b, y, cache) else {
            return f64::NAN;
        };
        match self.axis_guard(b, i) {
            None => c.normal.dot(&c.force(&Vector2::new(y[2], y[3]))),
            Some((axis, br)) => {
                let (s, d) = if axis == 0 {
                    (c.s.x, self.ring.x.preload)
                } else {
                    (c.s.y, self.ring.y.preload)
                };
                match br {
                    Branch::Inner => s.abs() - d,
                    Branch::Outer(sg) => f64::from(sg) * s - d,
                }
            }
        }
    }

    fn guard_derivative(
        &self,
        mode: Mode,
        i: usize,
        _t: f64,
        y: &State,
        dy: &State,
        cache: &Cache,
    ) -> Option<f64> {
        let Mode::Contact(b) = mode else {
            return None;
        };
        let _ = dy; // velocities are part of the state
        if i == 1 {
            return Some(2.0 * (y[0] * y[2] + y[1] * y[3]));
        }
        let (axis, br) = self.axis_guard(b, i)?;
        let c = self.contact(b, y, cache)?;
        let sd = c.ring_velocity(&Vector2::new(y[2], y[3]));
        let (s, v) = if axis == 0 {
            (c.s.x, sd.x)
        } else {
            (c.s.y, sd.y)
        };
        Some(match br {
            Branch::Inner => s.signum() * v,
            Branch::Outer(sg) => f64::from(sg) * v,
        })
    }

    fn guard_derivative_needs_rhs(&self) -> bool {
        false
    }

    fn guard_label(&self, mode: Mode, i: usize) -> &'static str {
        match mode {
            Mode::Free | Mode::Separating => guard::ONSET,
            Mode::Contact(b) => match (i, self.axis_guard(b, i)) {
                (0, _) => guard::LOSS,
                (1, _) => guard::GAP,
                (_, Some((0, Branch::Inner))) => guard::X_OUT,
                (_, Some((0, _))) => guard::X_IN,
                (_, Some((_, Branch::Inner))) => guard::Y_OUT,
                _ => guard::Y_IN,
            },
        }
    }

    fn transition(
        &self,
        mode: Mode,
        guard: usize,
        t: f64,
        y: &mut State,
    ) -> Result<Mode, ModelError> {
        let r = Vector2::new(y[0], y[1]);
        match mode {
            Mode::Free | Mode::Separating => {
                let gap = self.ring.gap;
                // A touch of the gap circle, up to the rounding of the onset time: the rotor
                // moves |r'| ulp(t) per representable time step.
                let speed = y[2].hypot(y[3]);
                let touch = (ONSET_TOUCH * gap).max(4.0 * f64::EPSILON * t.abs() * speed);
                if r.norm() < gap - touch {
                    // The relaxing ring touched a rotor that is inside the gap circle: its
                    // minimum-energy location (the centre) is within reach, so the touch ends
                    // the relaxation and free flight goes on (docs/model.md).
                    y[4] = 0.0;
                    y[5] = 0.0;
                    return Ok(Mode::Free);
                }
                // Onset is located to rounding, possibly a hair inside |r| = gap: start from
                // the relaxed ring's branches, whose smooth extension covers that hair.
                let b = if r.norm() > gap {
                    let c = self.ring.locate(&r).map_err(|e| ModelError::Transition {
                        t,
                        reason: e.to_string(),
                    })?;
                    self.branches_at_start(&c, &Vector2::new(y[2], y[3]))
                } else {
                    Branches::of(&self.ring, &Vector2::zeros())
                };
                let c =
                    self.ring
                        .locate_on(&r, b, f64::NAN)
                        .ok_or_else(|| ModelError::Transition {
                            t,
                            reason: format!("no ring location at r = {r:?}"),
                        })?;
                let v = Vector2::new(y[2], y[3]);
                if c.normal.dot(&v) < 0.0 && c.normal.dot(&c.force(&v)) < 0.0 {
                    // The contact would pull: an unrelaxed ring retreating as fast as an
                    // inward-moving rotor touches it without load (right after contact loss,
                    // to rounding). Free flight goes on; inside the gap circle the touch also
                    // ends the relaxation (docs/model.md).
                    if r.norm() <= gap {
                        y[4] = 0.0;
                        y[5] = 0.0;
                    }
                    return Ok(Mode::Separating);
                }
                y[4] = c.s.x;
                y[5] = c.s.y;
                Ok(Mode::Contact(b))
            }
            Mode::Contact(b) => match self.axis_guard(b, guard) {
                None => Ok(Mode::Separating),
                Some((axis, br)) => {
                    let s = if axis == 0 { y[4] } else { y[5] };
                    let nb = match br {
                        Branch::Inner => Branch::Outer(if s >= 0.0 { 1 } else { -1 }),
                        Branch::Outer(_) => Branch::Inner,
                    };
                    let mut next = b;
                    if axis == 0 {
                        next.x = nb;
                    } else {
                        next.y = nb;
                    }
                    // At a corner both preloads are crossed at once; the other axis' guard
                    // sits at zero at the new mode's start, where the event layer does not
                    // fire it again, so it is switched here if it is on its boundary and
                    // moving across it.
                    let other = 1 - axis;
                    let other_axis = if other == 0 {
                        &self.ring.x
                    } else {
                        &self.ring.y
                    };
                    let other_branch = if other == 0 { b.x } else { b.y };
                    if other_axis.preload > 0.0 {
                        let r = Vector2::new(y[0], y[1]);
                        if let Some(c) = self.ring.locate_on(&r, b, f64::NAN) {
                            let v = c.ring_velocity(&Vector2::new(y[2], y[3]))[other];
                            let sv = c.s[other];
                            let d = other_axis.preload;
                            let near = (sv.abs() - d).abs() <= CORNER_TOL * d;
                            let flipped = match other_branch {
                                Branch::Inner if near && sv * v > 0.0 => {
                                    Some(Branch::Outer(if sv >= 0.0 { 1 } else { -1 }))
                                }
                                Branch::Outer(sg) if near && f64::from(sg) * v < 0.0 => {
                                    Some(Branch::Inner)
                                }
                                _ => None,
                            };
                            if let Some(f) = flipped {
                                if other == 0 {
                                    next.x = f;
                                } else {
                                    next.y = f;
                                }
                            }
                        }
                    }
                    Ok(Mode::Contact(next))
                }
            },
        }
    }

    fn start_segment(&self, mode: Mode, t: f64, y: &State) -> FreeSegment {
        // Without ring damping the relaxation is instantaneous: the ring is at its centre as
        // soon as free flight starts.
        let s0 = if self.ring.damping > 0.0 {
            Vector2::new(y[4], y[5])
        } else {
            Vector2::zeros()
        };
        let start = [y[0], y[1], y[2], y[3]];
        FreeSegment {
            rotor: self.osc.segment(t, &start),
            start,
            relax: RelaxingRing { t0: t, s0 },
            ring: self.ring,
            stats: OnsetStats::default(),
            chunk: self.params.forcing_period(),
            searched_to: t,
            found: None,
            separating: mode == Mode::Separating,
        }
    }

    fn project(&self, mode: Mode, _t: f64, y: &mut State, cache: &Cache) {
        if let Mode::Contact(b) = mode {
            if let Some(c) = self.contact(b, y, cache) {
                y[4] = c.s.x;
                y[5] = c.s.y;
            }
        }
    }

    fn mode_label(&self, mode: Mode) -> u8 {
        match mode {
            Mode::Free | Mode::Separating => 1,
            Mode::Contact(b) => b.regime().number(),
        }
    }

    fn forcing_period(&self) -> f64 {
        self.params.forcing_period()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Preset;

    #[test]
    fn forcing_by_rotation_matches_sin_cos() {
        let model = JeffcottModel::new(Preset::Fig9b.params()).unwrap();
        let cache = Cache::default();
        let mut worst = 0.0f64;
        for i in 0..20_000 {
            let t = 0.37 * (i as f64).sqrt() + 1e-3 * i as f64;
            let (c, s) = model.forcing_phase(t, &cache);
            let arg = model.params.phi0 + model.params.eta * t;
            let (se, ce) = arg.sin_cos();
            // Both sides carry the rounding of the phase argument, ~eps |arg|.
            let scale = 1.0 + arg.abs();
            worst = worst
                .max((c - ce).abs() / scale)
                .max((s - se).abs() / scale);
        }
        assert!(worst < 4.0 * f64::EPSILON, "{worst:e}");
    }
}
