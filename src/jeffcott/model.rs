//! The paper's model as a [`RotorModel`]: modes, vector fields, guards, transitions.

use std::cell::Cell;

use nalgebra::{SVector, Vector2};

use super::free_flight::{FreeFlight, FreeOscillator};
use super::onset::{find_onset, Onset, OnsetStats, RelaxingRing};
use crate::hybrid::{
    simulate, ExactSegment, Flow, ModelError, OutputPlan, RotorModel, SimError, SimOptions,
    SimStats, Trajectory,
};
use crate::ode::Direction;
use crate::params::{ParamError, Params};
use crate::ring::{Branch, BranchContact, Branches, RingAxis, SnubberRing};

/// State `[x, y, x', y', x_s, y_s]`: rotor position and velocity, ring position.
pub type State = SVector<f64, 6>;

/// Relative distance inside the gap circle within which an onset counts as a touch of the
/// rotor's surface (the onset time is located to rounding).
const ONSET_TOUCH: f64 = 1e-12;

/// A mode of the model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Mode {
    /// Regime I: no contact; rotor and ring move in closed form.
    Free,
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
    pub error: SimError<6>,
    /// Everything recorded up to the failure.
    pub partial: Trajectory<6>,
}

/// Per-run scratch: the last ring location (guards evaluate it at the same point several
/// times) and the warm start of its solver.
#[derive(Debug, Default)]
pub struct Cache {
    last: Cell<Option<(f64, f64, Branches, BranchContact)>>,
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
    ) -> Result<(Trajectory<6>, SimStats), Box<RunFailure>> {
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
    /// [`RunFailure`] carrying the error and the states computed before it.
    pub fn stroboscopic(
        &self,
        y0: &State,
        first: u64,
        last: u64,
        opts: &SimOptions,
    ) -> Result<(Trajectory<6>, SimStats), Box<RunFailure>> {
        let plan = OutputPlan::strobe(self.params.forcing_period(), first, last);
        self.run(0.0, y0, &plan, opts)
    }

    /// Ring location on the mode's branches, reusing the last one at the same point.
    fn contact(&self, b: Branches, y: &State, cache: &Cache) -> Option<BranchContact> {
        let (x, yy) = (y[0], y[1]);
        let hint = match cache.last.get() {
            Some((lx, ly, lb, c)) if lb == b => {
                if lx == x && ly == yy {
                    return Some(c);
                }
                c.mu
            }
            _ => f64::NAN,
        };
        let c = self.ring.locate_on(&Vector2::new(x, yy), b, hint)?;
        cache.last.set(Some((x, yy, b, c)));
        Some(c)
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
    relax: RelaxingRing,
    ring: SnubberRing,
    stats: OnsetStats,
}

impl ExactSegment<6> for FreeSegment {
    fn eval(&self, t: f64, y: &mut State, dy: &mut State) {
        let (r, acc) = self.rotor.state_accel(t);
        let (s, sd) = self.relax.at(&self.ring, t);
        *y = State::from([r[0], r[1], r[2], r[3], s.x, s.y]);
        *dy = State::from([r[2], r[3], acc[0], acc[1], sd.x, sd.y]);
    }

    fn next_guard(&mut self, t_from: f64, t_to: f64) -> Option<(usize, f64)> {
        match find_onset(
            &self.rotor,
            &self.relax,
            &self.ring,
            t_from,
            t_to,
            &mut self.stats,
        ) {
            Onset::None => None,
            Onset::At(t) => Some((0, t)),
        }
    }

    fn evaluations(&self) -> u64 {
        self.stats.evaluations
    }
}

impl RotorModel<6> for JeffcottModel {
    type Mode = Mode;
    type Segment = FreeSegment;
    type Cache = Cache;

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
        Ok(Mode::Contact(Branches::of(&self.ring, &c.s)))
    }

    fn flow(&self, mode: Mode) -> Flow {
        match mode {
            Mode::Free => Flow::Exact,
            Mode::Contact(_) => Flow::Integrated,
        }
    }

    fn rhs(&self, mode: Mode, t: f64, y: &State, dy: &mut State, cache: &Cache) {
        let (sn, cs) = (self.params.phi0 + self.params.eta * t).sin_cos();
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
            Mode::Free => 1,
            Mode::Contact(_) => {
                2 + usize::from(self.ring.x.preload > 0.0) + usize::from(self.ring.y.preload > 0.0)
            }
        }
    }

    fn guard_direction(&self, mode: Mode, i: usize) -> Direction {
        match mode {
            Mode::Free => Direction::Rising,
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
        if i == 1 {
            return Some(2.0 * (y[0] * dy[0] + y[1] * dy[1]));
        }
        let (axis, br) = self.axis_guard(b, i)?;
        let c = self.contact(b, y, cache)?;
        let sd = c.ring_velocity(&Vector2::new(y[2], y[3]));
        let (s, v) = if axis == 0 { (c.s.x, sd.x) } else { (c.s.y, sd.y) };
        Some(match br {
            Branch::Inner => s.signum() * v,
            Branch::Outer(sg) => f64::from(sg) * v,
        })
    }

    fn guard_label(&self, mode: Mode, i: usize) -> &'static str {
        match mode {
            Mode::Free => guard::ONSET,
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

    fn transition(&self, mode: Mode, guard: usize, t: f64, y: &mut State) -> Result<Mode, ModelError> {
        let r = Vector2::new(y[0], y[1]);
        match mode {
            Mode::Free => {
                let gap = self.ring.gap;
                if r.norm() < gap * (1.0 - ONSET_TOUCH) {
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
                    Branches::of(&self.ring, &c.s)
                } else {
                    Branches::of(&self.ring, &Vector2::zeros())
                };
                let c = self
                    .ring
                    .locate_on(&r, b, f64::NAN)
                    .ok_or_else(|| ModelError::Transition {
                        t,
                        reason: format!("no ring location at r = {r:?}"),
                    })?;
                y[4] = c.s.x;
                y[5] = c.s.y;
                Ok(Mode::Contact(b))
            }
            Mode::Contact(b) => match self.axis_guard(b, guard) {
                None => Ok(Mode::Free),
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
                    Ok(Mode::Contact(next))
                }
            },
        }
    }

    fn start_segment(&self, _mode: Mode, t: f64, y: &State) -> FreeSegment {
        FreeSegment {
            rotor: self.osc.segment(t, &[y[0], y[1], y[2], y[3]]),
            relax: RelaxingRing {
                t0: t,
                s0: Vector2::new(y[4], y[5]),
            },
            ring: self.ring,
            stats: OnsetStats::default(),
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
            Mode::Free => 1,
            Mode::Contact(b) => b.regime().number(),
        }
    }

    fn forcing_period(&self) -> f64 {
        self.params.forcing_period()
    }
}
