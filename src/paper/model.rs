//! The paper's model as a [`RotorModel`]: the rotor's closed-form free flight composed with the
//! ring's contact element ([`crate::ring`]), whose modes, guards and transitions it uses as they
//! are.

use std::cell::Cell;

use nalgebra::{SVector, Vector2, U6};

use super::free_flight::{FreeFlight, FreeOscillator};
use crate::hybrid::{
    simulate, ExactSegment, Flow, GuardCrossing, ModelError, OutputPlan, RotorModel, SimError,
    SimOptions, SimStats, Trajectory,
};
use crate::numeric::Direction;
use crate::params::{ParamError, Params};
use crate::ring::onset::OnsetScan;
use crate::ring::{
    AccelOfForce, Kinematics, Relaxation, RingAxis, RingCache, RingError, RingGuard, RingMode,
    SnubberRing,
};

/// State `[x, y, x', y', x_s, y_s]`: rotor position and velocity, ring position.
pub type State = SVector<f64, 6>;

/// A mode of the model: the ring's mode (free flight relaxing from where it was left, or
/// contact on given force-law branches).
pub type Mode = RingMode;

/// Guard names, for event logs (the ring's [`RingGuard::label`]s).
pub mod guard {
    use crate::ring::{Axis, RingGuard};
    /// Contact begins (free flight).
    pub const ONSET: &str = RingGuard::Onset.label();
    /// The loss force reaches zero.
    pub const LOSS: &str = RingGuard::Loss.label();
    /// Rotor back at the gap circle.
    pub const GAP: &str = RingGuard::Gap.label();
    /// x crosses its preload outward.
    pub const X_OUT: &str = RingGuard::Preload {
        axis: Axis::X,
        outward: true,
    }
    .label();
    /// x crosses its preload inward.
    pub const X_IN: &str = RingGuard::Preload {
        axis: Axis::X,
        outward: false,
    }
    .label();
    /// y crosses its preload outward.
    pub const Y_OUT: &str = RingGuard::Preload {
        axis: Axis::Y,
        outward: true,
    }
    .label();
    /// y crosses its preload inward.
    pub const Y_IN: &str = RingGuard::Preload {
        axis: Axis::Y,
        outward: false,
    }
    .label();
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

/// Per-run scratch: the ring's cache (guards and the vector field evaluate the ring at the
/// same point several times) and the forcing phase at a recent time.
#[derive(Debug, Default)]
pub struct Cache {
    ring: RingCache,
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
    /// out of contact ($|r| \le 1$), at its minimum-energy location in contact
    /// ([`SnubberRing::consistent_position`]).
    ///
    /// # Errors
    /// [`ModelError::InvalidState`] for non-finite input.
    pub fn state_at(&self, r: [f64; 2], v: [f64; 2]) -> Result<State, ModelError> {
        let invalid = |e: RingError| ModelError::InvalidState {
            t: 0.0,
            reason: e.to_string(),
        };
        if !v.iter().all(|x| x.is_finite()) {
            return Err(ModelError::InvalidState {
                t: 0.0,
                reason: "non-finite rotor velocity".into(),
            });
        }
        let s = self
            .ring
            .consistent_position(&Vector2::new(r[0], r[1]))
            .map_err(invalid)?;
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

    /// Stroboscopic states $y(2\pi k/\eta)$ for the index range `k = first..=last` (both
    /// included; `k = 0` is `y0` itself), from `y0` at time 0: the raw range of
    /// [`OutputPlan::strobe`], with the driver's full [`Trajectory`].
    ///
    /// The analyses' convention is `(transient, record)` instead: `transient` periods
    /// discarded, the points `k = transient + 1 ..= transient + record` kept
    /// ([`crate::analysis::strobe_orbit`], whose [`StrobeOrbit`](crate::analysis::StrobeOrbit)
    /// tests the period). `strobe_range(y0, t + 1, t + r, opts)` gives the same points as
    /// `strobe_orbit(model, y0, t, r, opts)`.
    ///
    /// # Errors
    /// [`RunFailure`] carrying the error and the states computed before it; a reversed range
    /// (`first > last`) is [`crate::hybrid::SimErrorKind::InvalidOption`].
    pub fn strobe_range(
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

    /// The rotor's acceleration but for the ring's force, given the forcing phase's
    /// $(\cos, \sin)(\varphi_0 + \eta t)$: $\beta\eta^2(\cos, \sin) - 2\nu_1 r^\prime - (r - e)$
    /// (`rhs` and the guards' rates pass [`JeffcottModel::forcing_phase`]'s, so they share its
    /// bits).
    fn accel_off_ring(&self, (cs, sn): (f64, f64), y: &State) -> Vector2<f64> {
        let p = &self.params;
        Vector2::new(
            self.amp * cs - 2.0 * p.nu1 * y[2] - (y[0] - p.ex),
            self.amp * sn - 2.0 * p.nu1 * y[3] - (y[1] - p.ey),
        )
    }

    /// The rotor's kinematics at the ring.
    fn kinematics(y: &State) -> Kinematics {
        Kinematics::new([y[0], y[1]], [y[2], y[3]])
    }

    fn guard_of(&self, mode: &Mode, i: usize) -> RingGuard {
        // The driver asks only for guards below `guard_count`.
        self.ring.guard(mode, i).unwrap_or(RingGuard::Onset)
    }
}

/// Free flight: the rotor's closed form and the ring's exact relaxation.
#[derive(Debug, Clone)]
pub struct FreeSegment {
    rotor: FreeFlight,
    start: [f64; 4],
    relax: Relaxation,
    ring: SnubberRing,
    /// The onset search, in chunks of the forcing period (never ending at output times, so
    /// that asking for outputs does not move the onset by a rounding).
    scan: OnsetScan,
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
        self.scan
            .next_onset(&self.rotor, &self.relax, &self.ring, t_from, t_to)
            .map(|t| GuardCrossing { guard: 0, t })
    }

    fn evaluations(&self) -> u64 {
        self.scan.evaluations()
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

    /// 1 for every component: the model is non-dimensional, lengths in units of the gap and
    /// velocities in units of the gap times $\omega_n$.
    fn state_scale(&self) -> State {
        State::repeat(1.0)
    }

    fn new_cache(&self) -> Cache {
        Cache::default()
    }

    fn initial_mode(&self, t: f64, y: &State) -> Result<Mode, ModelError> {
        self.ring
            .initial_mode(t, &Self::kinematics(y), &Vector2::new(y[4], y[5]))
            .map_err(|e| ModelError::InvalidState {
                t,
                reason: e.to_string(),
            })
    }

    fn flow(&self, mode: Mode) -> Flow {
        match mode {
            RingMode::Contact(_) => Flow::Integrated,
            _ => Flow::Exact,
        }
    }

    fn rhs(&self, mode: Mode, t: f64, y: &State, dy: &mut State, cache: &Cache) {
        let mut f = self.accel_off_ring(self.forcing_phase(t, cache), y);
        let (sdx, sdy) = match self
            .ring
            .ring_state(&mode, t, &Self::kinematics(y), &cache.ring)
        {
            Ok(ring) => {
                f -= ring.force;
                (ring.s_dot.x, ring.s_dot.y)
            }
            Err(_) => (f64::NAN, f64::NAN),
        };
        *dy = State::from([y[2], y[3], f.x, f.y, sdx, sdy]);
    }

    fn guard_count(&self, mode: Mode) -> usize {
        self.ring.guard_count(&mode)
    }

    fn guard_direction(&self, mode: Mode, i: usize) -> Direction {
        self.guard_of(&mode, i).direction()
    }

    /// The ring's [`RingGuard::Onset`].
    fn is_contact_onset(&self, mode: Mode, i: usize) -> bool {
        self.guard_of(&mode, i) == RingGuard::Onset
    }

    fn guard_value(&self, mode: Mode, i: usize, t: f64, y: &State, cache: &Cache) -> f64 {
        let guard = self.guard_of(&mode, i);
        self.ring
            .guard_value(&mode, guard, t, &Self::kinematics(y), &cache.ring)
    }

    fn guard_derivative(
        &self,
        mode: Mode,
        i: usize,
        t: f64,
        y: &State,
        _dy: &State,
        cache: &Cache,
    ) -> Option<f64> {
        let guard = self.guard_of(&mode, i);
        let k = Self::kinematics(y);
        if guard != RingGuard::Loss {
            // Position and velocity suffice: they are in the state.
            return self.ring.guard_rate(&mode, guard, t, &k, &cache.ring);
        }
        // The loss force's rate needs the rotor's acceleration: the right-hand side's, from
        // the same formulas.
        let mut accel = self.accel_off_ring(self.forcing_phase(t, cache), y);
        if let Ok(ring) = self.ring.ring_state(&mode, t, &k, &cache.ring) {
            accel -= ring.force;
        }
        self.ring
            .guard_rate_with_accel(&mode, guard, t, &k, &accel, &cache.ring)
    }

    fn guard_derivative_needs_rhs(&self) -> bool {
        // Every rate is computed from the state (the loss guard's with the acceleration of
        // `rhs`): the event detector evaluates no right-hand side at its samples.
        false
    }

    fn guard_values(
        &self,
        mode: Mode,
        t: f64,
        y: &State,
        _dy: &State,
        with_rates: bool,
        cache: &Cache,
        out: &mut dyn FnMut(usize, f64, Option<f64>),
    ) {
        // The acceleration of `rhs` from the ring's force at the contact the guards locate.
        let accel_of =
            |force: &Vector2<f64>| self.accel_off_ring(self.forcing_phase(t, cache), y) - force;
        self.ring.guard_values_with(
            &mode,
            t,
            &Self::kinematics(y),
            with_rates.then_some(&accel_of as AccelOfForce<'_>),
            &cache.ring,
            out,
        );
    }

    fn guard_label(&self, mode: Mode, i: usize) -> &'static str {
        self.guard_of(&mode, i).label()
    }

    /// The ring element's error ([`SnubberRing::try_guard_value`]).
    fn guard_error(&self, mode: Mode, i: usize, t: f64, y: &State, cache: &Cache) -> ModelError {
        let guard = self.guard_of(&mode, i);
        let k = Self::kinematics(y);
        ModelError::of_ring_guard(
            t,
            guard.label(),
            self.ring.try_guard_value(&mode, guard, t, &k, &cache.ring),
        )
    }

    fn transition(
        &self,
        mode: Mode,
        guard: usize,
        t: f64,
        y: &mut State,
    ) -> Result<Mode, ModelError> {
        // The rotor's acceleration without the ring, for the ring's acceptance test.
        let p = &self.params;
        let (sn, cs) = (p.phi0 + p.eta * t).sin_cos();
        let free = self.accel_off_ring((cs, sn), y);
        let next = self
            .ring
            .transition(
                &mode,
                self.guard_of(&mode, guard),
                t,
                &Self::kinematics(y),
                |f| free - f,
            )
            .map_err(|e| ModelError::Transition {
                t,
                reason: e.to_string(),
            })?;
        y[4] = next.s.x;
        y[5] = next.s.y;
        Ok(next.mode)
    }

    fn start_segment(&self, mode: Mode, t: f64, y: &State) -> FreeSegment {
        let (relax, separating) = match mode {
            RingMode::Free {
                relax, separating, ..
            } => (relax, separating),
            // Never started for a contact mode (it is integrated); a ring at rest is harmless.
            _ => (Relaxation::at_rest(t), false),
        };
        let start = [y[0], y[1], y[2], y[3]];
        FreeSegment {
            rotor: self.osc.segment(t, &start),
            start,
            relax,
            ring: self.ring,
            scan: OnsetScan::new(t, self.params.forcing_period(), separating),
        }
    }

    fn project(&self, mode: Mode, t: f64, y: &mut State, cache: &Cache) {
        if mode.is_contact()
            && let Ok(ring) = self
                .ring
                .ring_state(&mode, t, &Self::kinematics(y), &cache.ring)
        {
            y[4] = ring.s.x;
            y[5] = ring.s.y;
        }
    }

    fn mode_label(&self, mode: Mode) -> u8 {
        mode.regime().number()
    }

    fn forcing_period(&self) -> f64 {
        self.params.forcing_period()
    }

    /// $\max(\sqrt{1 + k} + 2\nu_1 + c,\ \eta)$ with the ring's
    /// [`SnubberRing::contact_bounds`] $(k, c)$ in contact (0 in free flight, which is exact):
    /// the motion's rates and the forcing's frequency.
    fn max_rate(&self, mode: Mode, _t: f64, _y: &State) -> Option<f64> {
        let (k, c) = match mode {
            RingMode::Contact(_) => self.ring.contact_bounds(),
            _ => (0.0, 0.0),
        };
        Some(((1.0 + k).sqrt() + 2.0 * self.params.nu1 + c).max(self.params.eta))
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
