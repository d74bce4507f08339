//! The rub map: a branch of periodic orbits continued in a parameter (the speed), each orbit
//! measured at the ring over its period: the largest radius, the fraction of the period in
//! contact and the largest normal force, with its stability (module docs, "The rub map").

use nalgebra::{DefaultAllocator, OVector};

use super::{continue_orbit_with_progress, Branch, ContinuationOptions, StabilityError};
use crate::analysis::{per_revolution, Progress};
use crate::hybrid::{simulate, DenseSampling, OutputPlan, StrobeRange, Trajectory};
use crate::hybrid::{Variational, VariationalAlloc};
use crate::ring::Kinematics;

/// What the rub map reads off one state of the model: the station relative to the ring's
/// centre, and the contact's normal force (0 out of contact; for a rotor on the ring,
/// [`RingedRotor::normal_force`](crate::rotor::RingedRotor::normal_force)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RingReading {
    /// The station's position and velocity relative to the ring's centre.
    pub station: Kinematics,
    /// The normal force pressing the rotor on the ring.
    pub normal_force: f64,
}

/// Options of [`rub_map`]: the continuation's, and how finely each orbit is sampled.
///
/// The default continuation is [`ContinuationOptions::default`] with 20 corrector
/// iterations (not 8): where a contact starts or ends (a grazing) the map is only once
/// differentiable and Newton's convergence slows from quadratic (on the 8-mode S1 rotor the
/// first correction past the grazing needed 9 to 12).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct RubMapOptions {
    /// The continuation's options ([`continue_orbit`](super::continue_orbit)); default: 20
    /// corrector iterations.
    pub continuation: ContinuationOptions,
    /// Dense samples over each orbit's period (at least 4): knots of the located peak radius
    /// and the points where the normal force is read. Default 256.
    pub samples: usize,
}

impl Default for RubMapOptions {
    fn default() -> Self {
        Self {
            continuation: ContinuationOptions::default().with_max_iterations(20),
            samples: 256,
        }
    }
}

impl RubMapOptions {
    /// With the continuation's options.
    pub fn with_continuation(mut self, value: ContinuationOptions) -> Self {
        self.continuation = value;
        self
    }
    /// With [`samples`](Self::samples) a period.
    pub fn with_samples(mut self, value: usize) -> Self {
        self.samples = value;
        self
    }
}

/// One orbit of the rub map, as measured at the ring.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RubPoint {
    /// The parameter (the speed).
    pub parameter: f64,
    /// The largest radius of the station from the ring's centre over the orbit, located
    /// between the samples and events on the station's Hermite interpolant
    /// ([`per_revolution`]'s peak).
    pub amplitude: f64,
    /// The fraction of the orbit's period in contact.
    pub contact_fraction: f64,
    /// The largest normal force over the samples and the events' states (sampled, not
    /// located: finer [`RubMapOptions::samples`] for a sharper impact).
    pub peak_force: f64,
    /// Whether every Floquet multiplier is inside the unit circle.
    pub stable: bool,
    /// Contact onsets per orbit.
    pub contacts: usize,
    /// Whether an event of the orbit is crossed at a grazing margin
    /// ([`BranchPoint::grazing`](super::BranchPoint::grazing)).
    pub grazing: bool,
}

/// A rub map: the continued branch (its points, special points and end, as
/// [`continue_orbit`](super::continue_orbit) returns them) and each point measured.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RubMap {
    /// The branch.
    pub branch: Branch,
    /// One per point of the branch, in its order; a point whose measuring run failed has NaN
    /// measures and its error in [`failures`](Self::failures).
    pub points: Vec<RubPoint>,
    /// The points whose measuring run failed: (index, error).
    pub failures: Vec<(usize, StabilityError)>,
}

/// The rub map of the period-`period` orbit through `guess` at `from`, continued towards `to`
/// ([`continue_orbit_with_progress`]: pseudo-arclength through folds, every special point
/// located) and measured at the ring: each orbit run once over its period from its point,
/// with [`RubMapOptions::samples`] dense samples and its events, read by `read` at each sample
/// and event state (`in_contact`: the mode label is not 1, the free flight).
///
/// `build` makes the model at a parameter, as for [`continue_orbit`](super::continue_orbit);
/// for a finite-element rotor the speed enters the gyroscopic matrix, the out-of-balance and
/// the speed-dependent bearings there.
///
/// # Errors
/// Those of [`continue_orbit`](super::continue_orbit); [`StabilityError::InvalidOption`] for
/// fewer than 4 samples. A measuring run that fails is reported with its point
/// ([`RubMap::failures`]), not as an error.
#[allow(clippy::too_many_arguments)] // continue_orbit's arguments, the reader and the observer
pub fn rub_map<M, B, E, R, F>(
    build: B,
    (from, to): (f64, f64),
    guess: &OVector<f64, M::Dim>,
    period: u64,
    opts: &RubMapOptions,
    read: R,
    progress: &dyn Progress,
) -> Result<RubMap, StabilityError>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
    R: Fn(&M, &OVector<f64, M::Dim>, bool) -> Result<RingReading, F>,
    F: std::fmt::Display,
{
    if opts.samples < 4 {
        return Err(StabilityError::InvalidOption {
            field: "samples",
            value: opts.samples as f64,
            hint: "at least 4 samples a period",
        });
    }
    let branch = continue_orbit_with_progress(
        &build,
        from,
        to,
        guess,
        period,
        &opts.continuation,
        progress,
    )?;
    let (mut points, mut failures) = (Vec::with_capacity(branch.points.len()), Vec::new());
    for (i, p) in branch.points.iter().enumerate() {
        let mut state = guess.clone_owned();
        state.copy_from_slice(&p.state);
        let measured = super::continuation::model(&build, p.parameter)
            .and_then(|m| measure(&m, (&state, p.parameter), period, opts, &read));
        let (amplitude, contact_fraction, peak_force) = match measured {
            Ok(m) => m,
            Err(e) => {
                failures.push((i, e));
                (f64::NAN, f64::NAN, f64::NAN)
            }
        };
        points.push(RubPoint {
            parameter: p.parameter,
            amplitude,
            contact_fraction,
            peak_force,
            stable: p.stable,
            contacts: p.contacts,
            grazing: p.grazing,
        });
    }
    Ok(RubMap {
        branch,
        points,
        failures,
    })
}

/// One orbit of `model` (at `parameter`) from `state` at $t = 0$ over `period` forcing
/// periods: its largest station radius, fraction in contact and largest normal force.
fn measure<M, R, F>(
    model: &M,
    (state, parameter): (&OVector<f64, M::Dim>, f64),
    period: u64,
    opts: &RubMapOptions,
    read: &R,
) -> Result<(f64, f64, f64), StabilityError>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
    R: Fn(&M, &OVector<f64, M::Dim>, bool) -> Result<RingReading, F>,
    F: std::fmt::Display,
{
    let t_end = model.strobe_time(period);
    let plan = OutputPlan {
        t_end,
        strobe: Some(StrobeRange {
            first: 0,
            last: period,
        }),
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: t_end / opts.samples as f64,
        }),
        events: true,
    };
    let mut traj = Trajectory::default();
    simulate(model, 0.0, state, &plan, &opts.continuation.sim, &mut traj).map_err(|e| {
        StabilityError::Simulation {
            t: e.t,
            kind: e.kind,
        }
    })?;
    let fail = |e: F| StabilityError::Model {
        parameter,
        reason: e.to_string(),
    };
    let station = |y: &OVector<f64, M::Dim>| read(model, y, false).map(|r| r.station);
    // `per_revolution` takes an infallible reader: a failed reading is kept and returned.
    let first_error = std::cell::RefCell::new(None);
    let revolutions = per_revolution(&traj, period as usize, |y| {
        station(y).unwrap_or_else(|e| {
            first_error.borrow_mut().get_or_insert(e.to_string());
            Kinematics::new([f64::NAN; 2], [f64::NAN; 2])
        })
    })
    .map_err(|e| StabilityError::Model {
        parameter,
        reason: e.to_string(),
    })?;
    if let Some(reason) = first_error.into_inner() {
        return Err(StabilityError::Model { parameter, reason });
    }
    let orbit = revolutions
        .first()
        .ok_or(StabilityError::NoStroboscopicPoint { periods: period })?;
    let mut peak: f64 = 0.0;
    let samples = traj.samples.iter().map(|s| (&s.y, s.label));
    let events = traj
        .events
        .iter()
        .flat_map(|e| [(&e.before, e.from), (&e.after, e.to)]);
    for (y, label) in samples.chain(events) {
        if label != 1 {
            peak = peak.max(read(model, y, true).map_err(fail)?.normal_force);
        }
    }
    Ok((
        orbit.max_radius,
        orbit.contact_time / (orbit.t_end - orbit.t_start),
        peak,
    ))
}
