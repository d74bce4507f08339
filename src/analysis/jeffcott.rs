//! Analyses of rotor simulations: stroboscopic Poincaré maps with period detection, phase
//! portraits with the ring's velocity jumps, bifurcation sweeps and a bifurcation-point locator.
//!
//! The first two work for any [`RotorModel`] (they only need the driver and the forcing period);
//! the sweep and the locator build a [`JeffcottModel`] per parameter value.
//!
//! # Conventions
//!
//! * Time starts at $\tau = 0$ with the forcing phase $\varphi_0$; stroboscopic point `k` is the
//!   state at $\tau_k = 2\pi k/\eta$ (one forcing period $P = 2\pi/\eta$ per step).
//! * "`transient` periods discarded, `record` periods kept" means the run covers
//!   `transient + record` periods and keeps the points `k = transient + 1 ..= transient + record`
//!   (the state at the *end* of each recorded period). The state handed on to the next parameter
//!   value of a carry-over sweep is the last one, at `k = transient + record`.
//! * Because every run starts at $\tau = 0$, the forcing phase at the start of a run is always
//!   $\varphi_0$, and the phase at every stroboscopic point is $\varphi_0$ too: a state carried
//!   from one value of $\eta$ to the next is taken at the same forcing phase, as in a physical
//!   run-up where the speed is changed slowly.
//!
//! # Period detection
//!
//! [`PeriodTest`] wraps [`detect_period`]: the recorded points (whole state vectors) have
//! period `p` if every point is within `tol · max(1, extent)` (max norm) of the point `p`
//! earlier, `extent` being the largest side of the orbit's bounding box. The default is
//! `tol = 1e-6` and periods up to 16. Near a bifurcation the transient decays slowly, so a
//! periodic orbit may still be reported as "not periodic" after a short transient: the locator
//! ([`locate_period_change`]) therefore takes its own, longer transient.

use std::ops::Range;

use nalgebra::SVector;
use thiserror::Error;

use super::{detect_period, sweep, AnalysisError, Periodicity, Progress, SweepConfig};
use crate::hybrid::{
    simulate, EventRecord, ModelError, OutputPlan, RotorModel, Sample, SimError, SimOptions,
    SimStats, Trajectory,
};
use crate::jeffcott::{JeffcottModel, State};
use crate::params::{ParamError, Params};

/// How a stroboscopic orbit is tested for periodicity (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeriodTest {
    /// Largest period tested (at least 1; the orbit needs `2 · max_period` points).
    pub max_period: usize,
    /// Relative tolerance (see [`detect_period`]). Default `1e-6`.
    pub tol: f64,
}

impl Default for PeriodTest {
    fn default() -> Self {
        PeriodTest {
            max_period: 16,
            tol: 1e-6,
        }
    }
}

impl PeriodTest {
    /// Tests `points`, lowering `max_period` to `points.len() / 2` if there are too few points
    /// for it (but at least 1).
    ///
    /// # Errors
    /// [`AnalysisError`] from [`detect_period`] (invalid tolerance, fewer than 2 points,
    /// non-finite points).
    pub fn detect<const N: usize>(
        &self,
        points: &[SVector<f64, N>],
    ) -> Result<Periodicity, AnalysisError> {
        let arrays: Vec<[f64; N]> = points.iter().map(|y| y.data.0[0]).collect();
        let max_period = self.max_period.min(points.len() / 2).max(1);
        detect_period(&arrays, max_period, self.tol)
    }
}

/// One stroboscopic point: index `k`, time $\tau_k = kP$, state, mode label (for the
/// Jeffcott model the regime, 1..5 for I..V).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StrobePoint<const N: usize> {
    /// Forcing periods since $\tau = 0$.
    pub k: u64,
    /// Time $\tau_k = 2\pi k/\eta$.
    pub t: f64,
    /// State at $\tau_k$ (its left limit if an event falls exactly there).
    pub y: SVector<f64, N>,
    /// Mode label at $\tau_k$.
    pub label: u8,
}

/// A stroboscopic orbit after a transient: a Poincaré map of the forcing phase.
#[derive(Debug, Clone, PartialEq)]
pub struct StrobeOrbit<const N: usize> {
    /// The recorded points, `k = transient + 1 ..= transient + record`.
    pub points: Vec<StrobePoint<N>>,
    /// The state at the end of the run (`k = transient + record`), to continue from.
    pub last: SVector<f64, N>,
    /// Work done by the run.
    pub stats: SimStats,
}

impl<const N: usize> StrobeOrbit<N> {
    /// The recorded states.
    pub fn states(&self) -> Vec<SVector<f64, N>> {
        self.points.iter().map(|p| p.y).collect()
    }

    /// The points as `(component i, component j)` pairs, e.g. `(0, 2)` for $(x, x')$.
    /// Components out of range give NaN.
    pub fn pairs(&self, i: usize, j: usize) -> Vec<(f64, f64)> {
        let get = |y: &SVector<f64, N>, c: usize| y.get(c).copied().unwrap_or(f64::NAN);
        self.points
            .iter()
            .map(|p| (get(&p.y, i), get(&p.y, j)))
            .collect()
    }

    /// The period of the recorded states under `test`.
    ///
    /// # Errors
    /// As [`PeriodTest::detect`].
    pub fn period(&self, test: &PeriodTest) -> Result<Periodicity, AnalysisError> {
        test.detect(&self.states())
    }
}

/// Runs `model` from `y0` at $\tau = 0$ for `transient + record` forcing periods and keeps the
/// stroboscopic points of the last `record` periods (see the [module docs](self)).
///
/// # Errors
/// The driver's [`SimError`]; `record = 0` is an invalid option
/// ([`crate::hybrid::SimErrorKind::InvalidOption`]).
pub fn strobe_orbit<const N: usize, M: RotorModel<N>>(
    model: &M,
    y0: &SVector<f64, N>,
    transient: u64,
    record: u64,
    opts: &SimOptions,
) -> Result<StrobeOrbit<N>, SimError<N>> {
    if record == 0 {
        return Err(SimError {
            kind: crate::hybrid::SimErrorKind::InvalidOption {
                field: "record",
                value: 0.0,
                hint: "record at least one forcing period",
            },
            t: 0.0,
            y: *y0,
            stats: SimStats::default(),
        });
    }
    let last_k = transient.saturating_add(record);
    let plan = OutputPlan::strobe(model.forcing_period(), transient.saturating_add(1), last_k);
    let mut traj = Trajectory::default();
    let stats = simulate(model, 0.0, y0, &plan, opts, &mut traj)?;
    let last = traj.strobe.last().map_or(*y0, |s| s.2);
    let points = traj
        .strobe
        .into_iter()
        .map(|(k, t, y, label)| StrobePoint { k, t, y, label })
        .collect();
    Ok(StrobeOrbit {
        points,
        last,
        stats,
    })
}

/// Dense samples of a run and its event log: a phase portrait that knows where it jumps.
#[derive(Debug, Clone, PartialEq)]
pub struct PhasePortrait<const N: usize> {
    /// Samples every `dt` in `[t_start, t_end]`, with the state's derivative (for the
    /// Jeffcott model `dy[4]`, `dy[5]` are the ring's velocity).
    pub samples: Vec<Sample<N>>,
    /// Every transition in `[0, t_end]` (mode changes; the ring's velocity jumps there).
    pub events: Vec<EventRecord<N>>,
    /// Work done by the run.
    pub stats: SimStats,
}

impl<const N: usize> PhasePortrait<N> {
    /// The samples split into smooth pieces at the event times: no piece contains an event
    /// strictly between two of its samples, so a curve drawn through a piece never bridges a
    /// velocity jump. Empty pieces are dropped.
    pub fn pieces(&self) -> Vec<&[Sample<N>]> {
        let mut out = Vec::new();
        let mut start = 0;
        let mut ev = self.events.iter().map(|e| e.t).peekable();
        for i in 1..self.samples.len() {
            let (a, b) = (self.samples[i - 1].t, self.samples[i].t);
            let mut split = false;
            while let Some(&te) = ev.peek() {
                if te <= a {
                    ev.next();
                } else {
                    if te < b {
                        split = true;
                    }
                    break;
                }
            }
            if split {
                out.push(&self.samples[start..i]);
                start = i;
            }
        }
        if start < self.samples.len() {
            out.push(&self.samples[start..]);
        }
        out
    }

    /// A curve per smooth piece, mapping each sample with `f` (e.g. `|s| (s.y[4], s.dy[4])`
    /// for the ring's $(x_s, x_s')$).
    pub fn curves<F: Fn(&Sample<N>) -> (f64, f64)>(&self, f: F) -> Vec<Vec<(f64, f64)>> {
        self.pieces()
            .into_iter()
            .map(|p| p.iter().map(&f).collect())
            .collect()
    }

    /// All samples as one curve with a `(NaN, NaN)` point between smooth pieces (what line
    /// plotters that break at NaN expect).
    pub fn broken_curve<F: Fn(&Sample<N>) -> (f64, f64)>(&self, f: F) -> Vec<(f64, f64)> {
        let mut out = Vec::with_capacity(self.samples.len() + self.events.len());
        for (i, piece) in self.curves(f).into_iter().enumerate() {
            if i > 0 {
                out.push((f64::NAN, f64::NAN));
            }
            out.extend(piece);
        }
        out
    }
}

/// Runs `model` from `y0` at $\tau = 0$ to `t_end`, sampling every `dt` from `t_start` on, and
/// logging events.
///
/// # Errors
/// The driver's [`SimError`] (also for an invalid `dt`, `t_start` or `t_end`).
pub fn phase_portrait<const N: usize, M: RotorModel<N>>(
    model: &M,
    y0: &SVector<f64, N>,
    t_start: f64,
    t_end: f64,
    dt: f64,
    opts: &SimOptions,
) -> Result<PhasePortrait<N>, SimError<N>> {
    let bad = |field: &'static str, value: f64, hint: &'static str| SimError {
        kind: crate::hybrid::SimErrorKind::InvalidOption { field, value, hint },
        t: 0.0,
        y: *y0,
        stats: SimStats::default(),
    };
    if !(dt.is_finite() && dt > 0.0) {
        return Err(bad("dt", dt, "a finite sampling step > 0"));
    }
    if !(t_start.is_finite() && t_start >= 0.0) {
        return Err(bad("t_start", t_start, "a finite start time >= 0"));
    }
    if !(t_end.is_finite() && t_end >= t_start) {
        return Err(bad("t_end", t_end, "a finite end time >= t_start"));
    }
    let plan = OutputPlan {
        t_end,
        strobe: None,
        dense: Some((t_start, dt)),
        events: true,
    };
    let mut traj = Trajectory::default();
    let stats = simulate(model, 0.0, y0, &plan, opts, &mut traj)?;
    Ok(PhasePortrait {
        samples: traj.samples,
        events: traj.events,
        stats,
    })
}

/// Why an analysis of the Jeffcott model failed at one parameter value.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum OrbitError {
    /// The parameter set is invalid.
    #[error("invalid parameters: {0}")]
    Params(#[from] ParamError),
    /// The initial state is invalid.
    #[error("invalid initial state: {0}")]
    State(#[from] ModelError),
    /// The simulation failed.
    #[error("{0}")]
    Simulation(Box<SimError<6>>),
    /// The analysis of the orbit failed (e.g. non-finite points).
    #[error(transparent)]
    Analysis(#[from] AnalysisError),
    /// The locator's two ends have the same detected period: nothing to locate.
    #[error("no change of period between {from} ({at_from:?}) and {to} ({at_to:?})")]
    NoChange {
        /// Reference end.
        from: f64,
        /// Other end.
        to: f64,
        /// Periodicity at `from`.
        at_from: Periodicity,
        /// Periodicity at `to`.
        at_to: Periodicity,
    },
}

impl From<SimError<6>> for OrbitError {
    fn from(e: SimError<6>) -> Self {
        OrbitError::Simulation(Box::new(e))
    }
}

/// A parameter of [`Params`] that a sweep varies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
#[non_exhaustive]
pub enum SweepParameter {
    /// Frequency ratio $\eta$ (the default).
    #[default]
    Eta,
    /// Both preloads $D_x = D_y$.
    Preload,
    /// Preload $D_x$ only.
    PreloadX,
    /// Both ring stiffness ratios $K_x = K_y$.
    Stiffness,
    /// Rotor damping $\nu_1$.
    Nu1,
    /// Ring damping $\nu_2$.
    Nu2,
    /// Out-of-balance $\beta$.
    Beta,
    /// Eccentricity $e_x$.
    Ex,
    /// Eccentricity $e_y$.
    Ey,
    /// Initial phase $\varphi_0$.
    Phi0,
}

impl SweepParameter {
    /// `base` with this parameter set to `value` (not validated).
    pub fn apply(self, base: &Params, value: f64) -> Params {
        let mut p = *base;
        match self {
            SweepParameter::Eta => p.eta = value,
            SweepParameter::Preload => {
                p.dx = value;
                p.dy = value;
            }
            SweepParameter::PreloadX => p.dx = value,
            SweepParameter::Stiffness => {
                p.kx = value;
                p.ky = value;
            }
            SweepParameter::Nu1 => p.nu1 = value,
            SweepParameter::Nu2 => p.nu2 = value,
            SweepParameter::Beta => p.beta = value,
            SweepParameter::Ex => p.ex = value,
            SweepParameter::Ey => p.ey = value,
            SweepParameter::Phi0 => p.phi0 = value,
        }
        p
    }

    /// Its symbol, for labels: `"eta"`, `"D"`, `"Dx"`, `"K"`, `"nu1"`, ...
    pub fn symbol(self) -> &'static str {
        match self {
            SweepParameter::Eta => "eta",
            SweepParameter::Preload => "D",
            SweepParameter::PreloadX => "Dx",
            SweepParameter::Stiffness => "K",
            SweepParameter::Nu1 => "nu1",
            SweepParameter::Nu2 => "nu2",
            SweepParameter::Beta => "beta",
            SweepParameter::Ex => "ex",
            SweepParameter::Ey => "ey",
            SweepParameter::Phi0 => "phi0",
        }
    }

    /// Whether changing this parameter moves the ring's contact location, so that a carried
    /// state must have its ring re-placed ([`JeffcottModel::state_at`]).
    fn moves_ring(self) -> bool {
        matches!(
            self,
            SweepParameter::Preload | SweepParameter::PreloadX | SweepParameter::Stiffness
        )
    }
}

/// `n` evenly spaced values from `lo` to `hi` inclusive: value `i` is
/// `lo + (hi − lo) · i / (n − 1)` (exactly `lo` and `hi` at the ends; `[lo]` if `n = 1`).
///
/// # Errors
/// [`AnalysisError::InvalidValue`] for non-finite ends or `hi < lo`;
/// [`AnalysisError::InvalidCount`] for `n = 0`.
pub fn linspace(lo: f64, hi: f64, n: usize) -> Result<Vec<f64>, AnalysisError> {
    if !lo.is_finite() {
        return Err(AnalysisError::InvalidValue {
            name: "lo",
            value: lo,
            expected: "a finite number",
        });
    }
    if !(hi.is_finite() && hi >= lo) {
        return Err(AnalysisError::InvalidValue {
            name: "hi",
            value: hi,
            expected: "a finite number >= lo",
        });
    }
    if n == 0 {
        return Err(AnalysisError::InvalidCount {
            name: "n",
            value: 0,
            expected: "at least 1",
        });
    }
    if n == 1 {
        return Ok(vec![lo]);
    }
    let last = (n - 1) as f64;
    Ok((0..n)
        .map(|i| {
            if i == n - 1 {
                hi
            } else {
                lo + (hi - lo) * (i as f64 / last)
            }
        })
        .collect())
}

/// Settings of a [`bifurcation`] sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BifurcationConfig {
    /// The parameter varied. Default [`SweepParameter::Eta`].
    pub parameter: SweepParameter,
    /// Forcing periods discarded at each value. Default 300 (the paper's).
    pub transient: u64,
    /// Forcing periods recorded at each value. Default 150 (the paper's).
    pub record: u64,
    /// Reset mode or carry-over chunks, and threads. Default reset, global pool.
    pub sweep: SweepConfig,
    /// Integration options. Default: [`SimOptions::default`].
    pub opts: SimOptions,
    /// Period test of each column. Default [`PeriodTest::default`].
    pub period_test: PeriodTest,
    /// The rotor's reset state: position and velocity `([x, y], [x', y'])`, the ring placed
    /// consistently. Default at rest at the origin (the paper's zero initial conditions).
    pub reset_state: ([f64; 2], [f64; 2]),
}

impl Default for BifurcationConfig {
    fn default() -> Self {
        BifurcationConfig {
            parameter: SweepParameter::Eta,
            transient: 300,
            record: 150,
            sweep: SweepConfig::reset(),
            opts: SimOptions::default(),
            period_test: PeriodTest::default(),
            reset_state: ([0.0; 2], [0.0; 2]),
        }
    }
}

/// One column of a bifurcation diagram: the orbit recorded at one parameter value.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// The parameter value.
    pub value: f64,
    /// Whether this value started from the reset state (chunk start, reset mode, or after a
    /// failure) rather than from the previous value's final state.
    pub from_reset: bool,
    /// The recorded stroboscopic orbit.
    pub orbit: StrobeOrbit<6>,
    /// Its detected period.
    pub periodicity: Periodicity,
}

/// A bifurcation diagram: one column (or the error that prevented it) per parameter value.
#[derive(Debug, Clone, PartialEq)]
pub struct Bifurcation {
    /// The parameter varied.
    pub parameter: SweepParameter,
    /// The parameter values, in order.
    pub values: Vec<f64>,
    /// One entry per value: the column, or why it failed.
    pub columns: Vec<Result<Column, OrbitError>>,
    /// The chains of carried state (one per value in reset mode).
    pub chains: Vec<Range<usize>>,
    /// Worker threads used (does not affect the results).
    pub threads: usize,
}

impl Bifurcation {
    /// `(value, component c)` for every recorded point of every successful column (e.g.
    /// `c = 0` for the paper's $x_r$).
    pub fn points(&self, c: usize) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        for col in self.columns.iter().flatten() {
            out.extend(
                col.orbit
                    .points
                    .iter()
                    .map(|p| (col.value, p.y.get(c).copied().unwrap_or(f64::NAN))),
            );
        }
        out
    }

    /// The failed values, as `(value, error)`.
    pub fn failures(&self) -> Vec<(f64, &OrbitError)> {
        self.values
            .iter()
            .zip(&self.columns)
            .filter_map(|(v, c)| c.as_ref().err().map(|e| (*v, e)))
            .collect()
    }

    /// Values where the detected periodicity differs from the previous successful value's, as
    /// `(previous value, value, before, after)`: a coarse map of the bifurcations, to refine
    /// with [`locate_period_change`].
    pub fn period_changes(&self) -> Vec<(f64, f64, Periodicity, Periodicity)> {
        let mut out = Vec::new();
        let mut prev: Option<(f64, Periodicity)> = None;
        for col in self.columns.iter().flatten() {
            if let Some((v, p)) = prev {
                if p != col.periodicity {
                    out.push((v, col.value, p, col.periodicity));
                }
            }
            prev = Some((col.value, col.periodicity));
        }
        out
    }
}

/// One value of a sweep: builds the model, picks the start state, records the orbit.
fn run_value(
    base: &Params,
    value: f64,
    config: &BifurcationConfig,
    carried: Option<State>,
) -> Result<(Column, State), OrbitError> {
    let params = config.parameter.apply(base, value);
    let model = JeffcottModel::new(params)?;
    let from_reset = carried.is_none();
    let y0 = match carried {
        Some(y) if config.parameter.moves_ring() => model.state_at([y[0], y[1]], [y[2], y[3]])?,
        Some(y) => y,
        None => model.state_at(config.reset_state.0, config.reset_state.1)?,
    };
    let orbit = strobe_orbit(&model, &y0, config.transient, config.record, &config.opts)?;
    let periodicity = orbit.period(&config.period_test)?;
    let last = orbit.last;
    Ok((
        Column {
            value,
            from_reset,
            orbit,
            periodicity,
        },
        last,
    ))
}

/// A bifurcation diagram of the Jeffcott model: for each of `values` (of `config.parameter`,
/// the other parameters from `base`), discard `config.transient` periods, record
/// `config.record` stroboscopic points and detect their period.
///
/// Runs on [`sweep()`]: in reset mode every value starts from `config.reset_state`; in
/// carry-over mode the final state at one value starts the next, within contiguous chunks
/// that each start from the reset state and run in parallel. The chunking depends only on the
/// number of values and `chunks`, never on the thread count, so **the results are bitwise
/// identical for any number of threads** (with `chunks = 1` the whole sweep is one serial
/// chain, as in the paper). A failure at one value (an invalid parameter, a failed run) is
/// recorded in its column and the sweep goes on; in carry-over mode the next value starts from
/// the reset state. `progress` is called once per value.
///
/// # Errors
/// Only for a bad sweep configuration ([`AnalysisError`] from [`sweep()`]).
pub fn bifurcation(
    base: &Params,
    values: &[f64],
    config: &BifurcationConfig,
    progress: Option<&dyn Progress>,
) -> Result<Bifurcation, AnalysisError> {
    let runner = |v: &f64, carried: Option<State>| -> Result<(Column, State), OrbitError> {
        run_value(base, *v, config, carried)
    };
    let out = sweep(values, &config.sweep, runner, progress)?;
    Ok(Bifurcation {
        parameter: config.parameter,
        values: values.to_vec(),
        columns: out.results,
        chains: out.chains,
        threads: out.threads,
    })
}

/// The Poincaré map of the Jeffcott model at `params`: from the rotor state `([x, y], [x', y'])`
/// (ring placed consistently), discard `transient` periods, record `record`, detect the period.
///
/// # Errors
/// [`OrbitError`] for invalid parameters or state, a failed run, or a failed period test.
pub fn poincare_map(
    params: &Params,
    start: ([f64; 2], [f64; 2]),
    transient: u64,
    record: u64,
    opts: &SimOptions,
    test: &PeriodTest,
) -> Result<(StrobeOrbit<6>, Periodicity), OrbitError> {
    let model = JeffcottModel::new(*params)?;
    let y0 = model.state_at(start.0, start.1)?;
    let orbit = strobe_orbit(&model, &y0, transient, record, opts)?;
    let p = orbit.period(test)?;
    Ok((orbit, p))
}

/// Settings of [`locate_period_change`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LocatorConfig {
    /// The parameter varied. Default [`SweepParameter::Eta`].
    pub parameter: SweepParameter,
    /// Forcing periods discarded at each evaluation. Default 2000 (longer than a diagram's,
    /// because transients decay slowly near a bifurcation).
    pub transient: u64,
    /// Forcing periods recorded for the period test. Default 200.
    pub record: u64,
    /// Stop when the bracket is narrower than this. Default `5e-4` (3 decimals).
    pub resolution: f64,
    /// Integration options. Default [`SimOptions::default`].
    pub opts: SimOptions,
    /// The period test. Default [`PeriodTest::default`].
    pub period_test: PeriodTest,
    /// Rotor state `([x, y], [x', y'])` each evaluation starts from. Default at rest at the
    /// origin.
    pub start: ([f64; 2], [f64; 2]),
}

impl Default for LocatorConfig {
    fn default() -> Self {
        LocatorConfig {
            parameter: SweepParameter::Eta,
            transient: 2000,
            record: 200,
            resolution: 5e-4,
            opts: SimOptions::default(),
            period_test: PeriodTest::default(),
            start: ([0.0; 2], [0.0; 2]),
        }
    }
}

/// The bracket found by [`locate_period_change`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeriodChange {
    /// The end of the final bracket on the reference side (it has the periodicity `at_from`).
    pub from: f64,
    /// The other end (its periodicity differs from `at_from`); `|to − from| ≤ resolution`.
    pub to: f64,
    /// Periodicity at `from` (the same as at the initial `from`).
    pub at_from: Periodicity,
    /// Periodicity at `to`.
    pub at_to: Periodicity,
    /// Simulations run.
    pub evaluations: usize,
}

impl PeriodChange {
    /// The midpoint of the bracket, the located bifurcation value.
    pub fn value(&self) -> f64 {
        0.5 * (self.from + self.to)
    }
}

/// Locates by bisection where the detected period changes between `from` and `to`.
///
/// Each evaluation runs the model at one value of `config.parameter` from `config.start`
/// (every evaluation independent: the "reset" reading), discards `config.transient` periods and
/// tests the next `config.record`. The periodicity at `from` is the reference: the bracket is
/// halved, keeping the half whose `from` end has the reference periodicity and whose `to` end
/// does not, until it is narrower than `config.resolution`. `to` may lie below or above
/// `from`, so the search can find where a periodicity ends when coming from either side. If
/// several changes lie between the ends, one of them is found (not necessarily the nearest).
///
/// # Errors
/// [`OrbitError::NoChange`] if `from` and `to` have the same periodicity; the errors of
/// [`poincare_map`] at any evaluation; [`OrbitError::Analysis`] for equal or non-finite ends
/// or a bad resolution.
pub fn locate_period_change(
    base: &Params,
    from: f64,
    to: f64,
    config: &LocatorConfig,
) -> Result<PeriodChange, OrbitError> {
    if !(from.is_finite() && to.is_finite() && from != to) {
        return Err(AnalysisError::InvalidValue {
            name: "to",
            value: to,
            expected: "finite and different from a finite `from`",
        }
        .into());
    }
    if !(config.resolution.is_finite() && config.resolution > 0.0) {
        return Err(AnalysisError::InvalidValue {
            name: "resolution",
            value: config.resolution,
            expected: "a finite number > 0",
        }
        .into());
    }
    let mut evaluations = 0;
    let mut classify = |v: f64| -> Result<Periodicity, OrbitError> {
        evaluations += 1;
        let p = config.parameter.apply(base, v);
        poincare_map(
            &p,
            config.start,
            config.transient,
            config.record,
            &config.opts,
            &config.period_test,
        )
        .map(|(_, per)| per)
    };
    let at_from = classify(from)?;
    let mut at_to = classify(to)?;
    if at_from == at_to {
        return Err(OrbitError::NoChange {
            from,
            to,
            at_from,
            at_to,
        });
    }
    let (mut a, mut b) = (from, to);
    while (b - a).abs() > config.resolution {
        let m = 0.5 * (a + b);
        if m == a || m == b {
            break;
        }
        let pm = classify(m)?;
        if pm == at_from {
            a = m;
        } else {
            b = m;
            at_to = pm;
        }
    }
    Ok(PeriodChange {
        from: a,
        to: b,
        at_from,
        at_to,
        evaluations,
    })
}
