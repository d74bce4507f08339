use nalgebra::{DMatrix, DVector, DefaultAllocator, OVector};

use super::augmented::{event_structure, LinearEvent};
use super::error::StabilityError;
use super::floquet::{multipliers, Multiplier};
use super::map::{Linearization, StroboscopicMap};
use super::newton::{newton_fixed_point, MapValue, NewtonError, NewtonOptions};
use super::saltation::GRAZING_MARGIN;
use crate::hybrid::{
    simulate, DenseSampling, EventRecord, HybridObserver, OutputPlan, Sample, SimOptions,
    Variational, VariationalAlloc,
};

/// Options of [`periodic_orbit`]. Start from `Default` and change fields with the `with_` builders.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct OrbitOptions {
    /// Newton's options (tolerance on $P^n(z) - z$ relative to the model's
    /// [`state_scale`](crate::hybrid::RotorModel::state_scale), default `1e-11`).
    pub newton: NewtonOptions,
    /// Simulation options of every run.
    pub sim: SimOptions,
}

/// Builders: each returns the options with one field changed.
impl OrbitOptions {
    /// With [`newton`](Self::newton) = `value`.
    #[must_use]
    pub fn with_newton(mut self, value: NewtonOptions) -> Self {
        self.newton = value;
        self
    }

    /// With [`sim`](Self::sim) = `value`.
    #[must_use]
    pub fn with_sim(mut self, value: SimOptions) -> Self {
        self.sim = value;
        self
    }
}

/// How far a periodic orbit is from grazing (module docs).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct OrbitMargins {
    /// Contact phases per orbit (consecutive contact modes, e.g. across a preload crossing,
    /// count once).
    pub contacts: usize,
    /// The smallest, over the contact phases, of the largest penetration depth; `None`
    /// without contact or without [`Variational::contact_depth`].
    pub min_depth: Option<f64>,
    /// The closest approach to contact in free flight: the smallest clearance at an interior
    /// maximum of the contact depth in a free phase (a near miss); `None` if no free phase
    /// has one.
    pub clearance: Option<f64>,
    /// The smallest crossing margin of the events' saltation matrices (1 without events).
    pub min_event_margin: f64,
    /// The events' labels in order over the orbit: its event structure.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::serde_util::labels")
    )]
    pub structure: Vec<&'static str>,
}

/// A periodic orbit of the stroboscopic map.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct PeriodicOrbit<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The period $n$ in forcing periods.
    pub period: u64,
    /// The full state at the periodic point (at $\tau = 0$).
    pub state: OVector<f64, D>,
    /// The periodic point $z^{\ast}$ (the non-algebraic components).
    pub point: DVector<f64>,
    /// $\lVert P^n(z^{\ast}) - z^{\ast}\rVert_\infty$.
    pub residual: f64,
    /// Newton iterations.
    pub iterations: u32,
    /// The monodromy matrix $DP^n(z^{\ast})$.
    pub monodromy: DMatrix<f64>,
    /// Its eigenvalues, the Floquet multipliers, largest modulus first.
    pub multipliers: Vec<Multiplier>,
    /// The events over one orbit with their crossing margins.
    pub events: Vec<LinearEvent>,
    /// Grazing margins.
    pub margins: OrbitMargins,
    /// Whether an event of the orbit is grazing: crossed at a margin
    /// ([`OrbitMargins::min_event_margin`], the smallest crossing rate relative to its scale)
    /// below [`GRAZING_MARGIN`]. The map is then not differentiable at the orbit and the
    /// multipliers are those of one side of it, through a saltation matrix that may be
    /// unbounded there ([`LinearEvent::saltation_norm`] of the grazing events says how large
    /// it is): do not read them as the orbit's stability without looking.
    pub grazing: bool,
    /// How far the section is from closing the map on $z$ (0 for a closed map:
    /// [`Linearization::openness`]).
    pub openness: f64,
    /// The smallest $m$ dividing the period with $\lVert P^m(z^{\ast}) - z^{\ast}\rVert_\infty \le
    /// 10^{-8}(1 + \lVert z^{\ast}\rVert_\infty)$, components in units of the model's
    /// [`RotorModel::state_scale`](crate::hybrid::RotorModel::state_scale): less than the
    /// period when Newton found an orbit of a shorter period (a fixed point of $P$ is one of
    /// $P^n$ too).
    pub minimal_period: u64,
}

impl<D: nalgebra::Dim> PeriodicOrbit<D>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The largest multiplier modulus (the spectral radius): stable below 1.
    pub fn spectral_radius(&self) -> f64 {
        super::floquet::spectral_radius(&self.multipliers)
    }
}

/// Newton's method on $P^n(z) - z$ from the full state `guess` (a point of a simulated orbit,
/// at a section), then the multipliers and margins of the orbit found. Newton's tolerance is
/// relative to the model's [`state_scale`](crate::hybrid::RotorModel::state_scale).
///
/// # Errors
/// [`StabilityError::NotConverged`] with the last iterate and its residual,
/// [`StabilityError::Singular`] (a multiplier at 1), a simulation or multiplier error.
///
/// # Example
///
/// ```
/// use jeffcott::hybrid::SimOptions;
/// use jeffcott::paper::{JeffcottModel, State};
/// use jeffcott::params::Preset;
/// use jeffcott::stability::{periodic_orbit, OrbitOptions};
///
/// // The paper's Fig. 8a scene at eta = 2 settles on a period-1 orbit: start Newton from
/// // the point a simulation from rest reaches after 300 forcing periods.
/// let model = JeffcottModel::new(Preset::Fig8a.params().with_eta(2.0))?;
/// let (run, _) = model.strobe_range(&State::zeros(), 300, 300, &SimOptions::default())?;
/// let orbit = periodic_orbit(&model, &run.strobe[0].y, 1, &OrbitOptions::default())?;
/// // Four multipliers (x, y, x', y'); reached by simulation, so an attractor: all inside
/// // the unit circle.
/// assert_eq!(orbit.multipliers.len(), 4);
/// assert!(orbit.spectral_radius() < 1.0);
/// // The simulated point was already on the orbit, to the simulation's tolerance.
/// assert!((orbit.state - run.strobe[0].y).amax() < 1e-6);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn periodic_orbit<M>(
    model: &M,
    guess: &OVector<f64, M::Dim>,
    period: u64,
    opts: &OrbitOptions,
) -> Result<PeriodicOrbit<M::Dim>, StabilityError>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let map = StroboscopicMap::new(model, period, opts.sim)?;
    let template = guess.clone_owned();
    let z0 = map.reduce(guess);
    let eval = |z: &DVector<f64>| -> Result<MapValue<Linearization<M::Dim>>, StabilityError> {
        let y = map.state(&template, z);
        let lin = map.linearize(&y)?;
        Ok(MapValue {
            value: lin.value.clone(),
            jacobian: lin.jacobian.clone(),
            extra: lin,
        })
    };
    let scale = map.reduce(&model.state_scale());
    let fp = newton_fixed_point(&z0, eval, Some(&scale), &opts.newton).map_err(newton_error)?;
    let state = map.state(&template, &fp.point);
    let multipliers = multipliers(&fp.map.jacobian)?;
    let lin = fp.map.extra;
    let margins = orbit_margins(model, &state, period, &lin.events, &opts.sim)?;
    let minimal_period = minimal_period(model, &state, &fp.point, period, &opts.sim)?;
    Ok(PeriodicOrbit {
        period,
        state,
        point: fp.point,
        residual: fp.residual,
        iterations: fp.iterations,
        monodromy: fp.map.jacobian,
        multipliers,
        events: lin.events,
        grazing: margins.min_event_margin < GRAZING_MARGIN,
        margins,
        openness: lin.openness[0].max(lin.openness[1]),
        minimal_period,
    })
}

/// The smallest divisor $m$ of `period` with $P^m(z) = z$ to $10^{-8}(1 + |z|)$, in units of
/// the model's [`RotorModel::state_scale`](crate::hybrid::RotorModel::state_scale).
fn minimal_period<M>(
    model: &M,
    state: &OVector<f64, M::Dim>,
    point: &DVector<f64>,
    period: u64,
    sim: &SimOptions,
) -> Result<u64, StabilityError>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let scale = StroboscopicMap::new(model, 1, *sim)?.reduce(&model.state_scale());
    let size = point.component_div(&scale).amax();
    for m in (1..period).filter(|&m| period.is_multiple_of(m)) {
        let map = StroboscopicMap::new(model, m, *sim)?;
        let end = map.reduce(&map.advance(state)?.y);
        if (end - point).component_div(&scale).amax() <= 1e-8 * (1.0 + size) {
            return Ok(m);
        }
    }
    Ok(period)
}

/// Newton's error as the layer's error.
pub(crate) fn newton_error(e: NewtonError<StabilityError>) -> StabilityError {
    match e {
        NewtonError::NotConverged {
            last,
            residual,
            iterations,
            reason,
            ..
        } => StabilityError::NotConverged {
            last,
            residual,
            iterations,
            reason,
        },
        NewtonError::Singular { at, residual } => StabilityError::Singular { at, residual },
        NewtonError::Map { error, .. } => error,
        NewtonError::InvalidOption { field, value, hint } => {
            StabilityError::InvalidOption { field, value, hint }
        }
    }
}

/// Records events and dense samples.
struct Pieces<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    events: Vec<EventRecord<D>>,
    samples: Vec<Sample<D>>,
}

impl<D: nalgebra::Dim> HybridObserver<D> for Pieces<D>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    fn on_event(&mut self, e: &EventRecord<D>) {
        self.events.push(e.clone());
    }
    fn on_sample(&mut self, s: &Sample<D>) {
        self.samples.push(s.clone());
    }
}

/// One smooth piece's contact depth: whether it is a contact, its largest depth, and its
/// largest interior local maximum.
#[derive(Debug, Clone, Copy)]
struct PieceDepth {
    contact: bool,
    max: f64,
    interior_max: Option<f64>,
}

/// Samples per smooth piece for the margins.
const PIECE_SAMPLES: usize = 64;

/// The margins of the orbit through `state` (module docs).
fn orbit_margins<M>(
    model: &M,
    state: &OVector<f64, M::Dim>,
    period: u64,
    events: &[LinearEvent],
    sim: &SimOptions,
) -> Result<OrbitMargins, StabilityError>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let min_event_margin = events.iter().map(|e| e.margin).fold(1.0, f64::min);
    let label = model.initial_mode(0.0, state).map(|m| model.mode_label(m));
    let structure = event_structure(events, label.unwrap_or(0));
    let has_depth = model
        .initial_mode(0.0, state)
        .ok()
        .and_then(|m| model.contact_depth(m, 0.0, state))
        .is_some();
    let t_end = model.forcing_period() * period as f64;
    // The events of a plain run, then each piece between them sampled on its own.
    let starts = piece_starts(model, state, t_end, sim)?;
    if !has_depth {
        return Ok(OrbitMargins {
            contacts: 0,
            min_depth: None,
            clearance: None,
            min_event_margin,
            structure,
        });
    }
    let mut samples: Vec<Vec<f64>> = Vec::with_capacity(starts.len());
    for (i, (ta, ya)) in starts.iter().enumerate() {
        let tb = starts.get(i + 1).map_or(t_end, |s| s.0);
        if tb <= *ta {
            continue;
        }
        if let Some(depth) = piece_samples(model, (*ta, ya), tb, sim) {
            samples.push(depth);
        }
    }
    join_at_section(&mut samples);
    let pieces = samples.iter().map(|d| piece_depth(d)).collect();
    Ok(summarise(pieces, min_event_margin, structure))
}

/// A smooth piece's start: its time and state.
type PieceStart<D> = (f64, OVector<f64, D>);

/// The starts of the orbit's smooth pieces over `[0, t_end]`: the orbit's start and the state
/// after each event of a plain run.
fn piece_starts<M>(
    model: &M,
    state: &OVector<f64, M::Dim>,
    t_end: f64,
    sim: &SimOptions,
) -> Result<Vec<PieceStart<M::Dim>>, StabilityError>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let plan = OutputPlan {
        t_end,
        strobe: None,
        dense: None,
        events: true,
    };
    let mut rec = Pieces {
        events: Vec::new(),
        samples: Vec::new(),
    };
    let fail = |e: crate::hybrid::SimError<M::Dim>| StabilityError::Simulation {
        kind: e.kind,
        t: e.t,
    };
    simulate(model, 0.0, state, &plan, sim, &mut rec).map_err(fail)?;
    let mut starts: Vec<PieceStart<M::Dim>> = vec![(0.0, state.clone_owned())];
    for e in &rec.events {
        starts.push((e.t, e.after.clone()));
    }
    Ok(starts)
}

/// The contact depth at [`PIECE_SAMPLES`] points of the piece from `(ta, ya)` to `tb`, `None`
/// when fewer than 3 have a depth.
fn piece_samples<M>(
    model: &M,
    (ta, ya): (f64, &OVector<f64, M::Dim>),
    tb: f64,
    sim: &SimOptions,
) -> Option<Vec<f64>>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let dt = (tb - ta) / PIECE_SAMPLES as f64;
    let plan = OutputPlan {
        t_end: tb,
        strobe: None,
        dense: Some(DenseSampling { t_start: ta, dt }),
        events: false,
    };
    let mut piece = Pieces {
        events: Vec::new(),
        samples: Vec::new(),
    };
    // The piece is cut where the full run found its end; a restarted run may meet the event a
    // rounding earlier: what it records up to a failure is kept.
    let _ = simulate(model, ta, ya, &plan, sim, &mut piece);
    let depth: Vec<f64> = piece
        .samples
        .iter()
        .filter(|s| s.t <= tb)
        .filter_map(|s| {
            // The mode of each sample from the sample itself: the piece's start may sit on
            // the boundary between two modes.
            let mode = model.initial_mode(s.t, &s.y).ok()?;
            model.contact_depth(mode, s.t, &s.y)
        })
        .collect();
    (depth.len() >= 3).then_some(depth)
}

/// The section cuts one piece in two (the first and the last, when they are of the same
/// kind): joins them, so that an extremum at the section is interior.
fn join_at_section(samples: &mut Vec<Vec<f64>>) {
    if samples.len() > 1 {
        let (first, last) = (&samples[0], &samples[samples.len() - 1]);
        if (first[first.len() / 2] > 0.0) == (last[last.len() / 2] > 0.0) {
            let mut joined = samples.pop().unwrap_or_default();
            joined.extend_from_slice(&samples[0]);
            samples[0] = joined;
        }
    }
}

/// The depth statistics of one piece's samples.
fn piece_depth(depth: &[f64]) -> PieceDepth {
    let n = depth.len();
    let mid = depth[n / 2];
    let (imax, &max) = depth
        .iter()
        .enumerate()
        .max_by(|a, b| a.1.total_cmp(b.1))
        .unwrap_or((0, &f64::NAN));
    let interior_max = (1..n - 1)
        .filter(|&i| depth[i] >= depth[i - 1] && depth[i] >= depth[i + 1])
        .map(|i| parabola_peak(depth[i - 1], depth[i], depth[i + 1]))
        .fold(None, |acc: Option<f64>, v| {
            Some(acc.map_or(v, |a| a.max(v)))
        });
    let refined = if imax > 0 && imax < n - 1 {
        parabola_peak(depth[imax - 1], max, depth[imax + 1])
    } else {
        max
    };
    PieceDepth {
        contact: mid > 0.0,
        max: refined,
        interior_max,
    }
}

/// The peak of the parabola through three equally spaced values, the middle one the largest.
fn parabola_peak(a: f64, b: f64, c: f64) -> f64 {
    let curv = a - 2.0 * b + c;
    if curv < 0.0 {
        b - (c - a) * (c - a) / (8.0 * curv)
    } else {
        b
    }
}

/// Merges consecutive pieces of the same kind into phases and takes the margins.
fn summarise(
    pieces: Vec<PieceDepth>,
    min_event_margin: f64,
    structure: Vec<&'static str>,
) -> OrbitMargins {
    let mut phases: Vec<PieceDepth> = Vec::new();
    for p in pieces {
        match phases.last_mut() {
            Some(last) if last.contact == p.contact => {
                last.max = last.max.max(p.max);
                last.interior_max = match (last.interior_max, p.interior_max) {
                    (Some(a), Some(b)) => Some(a.max(b)),
                    (a, b) => a.or(b),
                };
            }
            _ => phases.push(p),
        }
    }
    let contacts: Vec<&PieceDepth> = phases.iter().filter(|p| p.contact).collect();
    let min_depth = contacts.iter().map(|p| p.max).reduce(f64::min);
    let clearance = phases
        .iter()
        .filter(|p| !p.contact)
        .filter_map(|p| p.interior_max)
        .map(|m| -m)
        .reduce(f64::min);
    OrbitMargins {
        contacts: contacts.len(),
        min_depth,
        clearance,
        min_event_margin,
        structure,
    }
}
