use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, OVector};

use crate::analysis::{PeriodTest, Periodicity};
use crate::hybrid::{
    simulate, EventRecord, HybridObserver, OutputPlan, RotorModel, SimError, SimErrorKind,
    SimOptions, StrobePoint, StrobeRange,
};

/// Settings of [`find_attractor`].
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub struct AttractorOptions {
    /// Forcing periods discarded before the first recording. Default 500.
    pub transient: u64,
    /// Stroboscopic points recorded and tested (at least `2 · period_test.max_period`).
    /// Default 64.
    pub record: u64,
    /// Largest total transient: a run without a period is continued until its transients add
    /// up to this (at least `transient`). Default 4000.
    pub max_transient: u64,
    /// Integration options. Default [`SimOptions::default`].
    pub opts: SimOptions,
    /// The period test (largest period and tolerance). Default: periods up to 16, `tol` 1e-6.
    pub period_test: PeriodTest,
    /// The mode label of free flight ([`RotorModel::mode_label`]); a transition out of it is
    /// a contact. Default 1 (regime I of the paper's model and of [`crate::rotor::RingedRotor`]).
    pub free_label: u8,
}

/// Builders: each returns the options with one field changed.
impl AttractorOptions {
    /// With [`transient`](Self::transient) = `value`.
    #[must_use]
    pub fn with_transient(mut self, value: u64) -> Self {
        self.transient = value;
        self
    }

    /// With [`record`](Self::record) = `value`.
    #[must_use]
    pub fn with_record(mut self, value: u64) -> Self {
        self.record = value;
        self
    }

    /// With [`max_transient`](Self::max_transient) = `value`.
    #[must_use]
    pub fn with_max_transient(mut self, value: u64) -> Self {
        self.max_transient = value;
        self
    }

    /// With [`opts`](Self::opts) = `value`.
    #[must_use]
    pub fn with_opts(mut self, value: SimOptions) -> Self {
        self.opts = value;
        self
    }

    /// With [`period_test`](Self::period_test) = `value`.
    #[must_use]
    pub fn with_period_test(mut self, value: PeriodTest) -> Self {
        self.period_test = value;
        self
    }

    /// With [`free_label`](Self::free_label) = `value`.
    #[must_use]
    pub fn with_free_label(mut self, value: u8) -> Self {
        self.free_label = value;
        self
    }
}

impl Default for AttractorOptions {
    fn default() -> Self {
        AttractorOptions {
            transient: 500,
            record: 64,
            max_transient: 4000,
            opts: SimOptions::default(),
            period_test: PeriodTest::default(),
            free_label: 1,
        }
    }
}

/// Statistics of the recorded window of a run (see the [module docs](super)).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct OrbitStats {
    /// Forcing periods run in all, transients included.
    pub periods_run: u64,
    /// Forcing periods of the recorded window.
    pub window: u64,
    /// Contacts (transitions out of free flight) per forcing period, over the window.
    pub contacts_per_period: f64,
    /// Fraction of the window's time outside free flight.
    pub contact_fraction: f64,
    /// `(mode label, fraction of the window's time)` for each mode visited, by label.
    pub occupancy: Vec<(u8, f64)>,
    /// Smallest value of each state component over the recorded stroboscopic points.
    pub lo: Vec<f64>,
    /// Largest value of each state component over the recorded stroboscopic points.
    pub hi: Vec<f64>,
}

/// The attractor a run settled on (see the [module docs](super)).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Attractor {
    /// The detected period of the stroboscopic map.
    pub periodicity: Periodicity,
    /// Periodic: the cycle's states, starting at the canonical point; otherwise empty.
    pub cycle: Vec<Vec<f64>>,
    /// Contact and mode statistics of the recorded window.
    pub stats: OrbitStats,
    /// The model's [`RotorModel::state_scale`], one entry per component: the units of the
    /// matching tolerances (see the [module docs](super)). Empty (and left out of the record)
    /// when the scale is 1 for every component, as for the paper's model; a missing entry
    /// counts as 1.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub scale: Vec<f64>,
}

/// Tolerances of [`Attractor::matches`] (see the [module docs](super)), in units of the
/// model's scale ([`Attractor::scale`]; the paper's: gap = 1).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct MatchOptions {
    /// Periodic attractors: largest difference of a state component between matched cycle
    /// points. Default 1e-3 (runs converge to ~1e-6; coexisting orbits differ by ~0.1).
    pub state: f64,
    /// Non-periodic attractors: largest difference of contacts per period. Default 0.1.
    pub contacts: f64,
    /// Non-periodic attractors: largest difference of a side of the bounding boxes.
    /// Default 0.05.
    pub extent: f64,
}

/// Builders: each returns the options with one field changed.
impl MatchOptions {
    /// With [`state`](Self::state) = `value`.
    #[must_use]
    pub fn with_state(mut self, value: f64) -> Self {
        self.state = value;
        self
    }

    /// With [`contacts`](Self::contacts) = `value`.
    #[must_use]
    pub fn with_contacts(mut self, value: f64) -> Self {
        self.contacts = value;
        self
    }

    /// With [`extent`](Self::extent) = `value`.
    #[must_use]
    pub fn with_extent(mut self, value: f64) -> Self {
        self.extent = value;
        self
    }
}

impl Default for MatchOptions {
    fn default() -> Self {
        MatchOptions {
            state: 1e-3,
            contacts: 0.1,
            extent: 0.05,
        }
    }
}

/// Whether every component of `a` and `b` agrees to `tol` times its scale (1 where `scale`
/// has no entry).
fn within(a: &[f64], b: &[f64], scale: &[f64], tol: f64) -> bool {
    a.iter()
        .zip(b)
        .enumerate()
        .all(|(c, (u, v))| (u - v).abs() <= tol * scale.get(c).copied().unwrap_or(1.0))
}

/// The larger of two attractors' scales, per component (empty if both are).
fn joint_scale(a: &[f64], b: &[f64]) -> Vec<f64> {
    let n = a.len().max(b.len());
    let get = |s: &[f64], c: usize| s.get(c).copied().unwrap_or(1.0);
    (0..n).map(|c| get(a, c).max(get(b, c))).collect()
}

impl Attractor {
    /// The period, if periodic.
    pub fn period(&self) -> Option<usize> {
        self.periodicity.period()
    }

    /// The canonical periodic point (the cycle's first state), if periodic.
    pub fn canonical(&self) -> Option<&[f64]> {
        self.cycle.first().map(Vec::as_slice)
    }

    /// The cycle reduced to its shortest period at tolerance `tol` (in units of
    /// [`Attractor::scale`]): the first `q` states, `q` the smallest divisor of the period
    /// with every state within `tol` of the one `q` later.
    pub fn reduced_cycle(&self, tol: f64) -> &[Vec<f64>] {
        self.reduced_with(tol, &self.scale)
    }

    fn reduced_with(&self, tol: f64, scale: &[f64]) -> &[Vec<f64>] {
        let p = self.cycle.len();
        for q in 1..p {
            if p.is_multiple_of(q)
                && (q..p).all(|i| within(&self.cycle[i], &self.cycle[i - q], scale, tol))
            {
                return &self.cycle[..q];
            }
        }
        &self.cycle
    }

    /// Whether `self` and `other` are the same attractor within `tol` (see the
    /// [module docs](super)).
    pub fn matches(&self, other: &Attractor, tol: &MatchOptions) -> bool {
        let scale = joint_scale(&self.scale, &other.scale);
        match (self.period(), other.period()) {
            (Some(_), Some(_)) => {
                let a = self.reduced_with(tol.state, &scale);
                let b = other.reduced_with(tol.state, &scale);
                let p = a.len();
                p == b.len()
                    && (0..p)
                        .any(|s| (0..p).all(|i| within(&a[i], &b[(i + s) % p], &scale, tol.state)))
            }
            (None, None) => {
                let (s, o) = (&self.stats, &other.stats);
                (s.contacts_per_period - o.contacts_per_period).abs() <= tol.contacts
                    && within(&s.lo, &o.lo, &scale, tol.extent)
                    && within(&s.hi, &o.hi, &scale, tol.extent)
                    && s.lo.len() == o.lo.len()
            }
            _ => false,
        }
    }

    /// A one-line description: `period 3 at (0.3062, …), 0.67 contacts/period, 12 % of the
    /// time in contact` or `not periodic up to 16, 0.97 contacts/period, …, first component
    /// in [0.210, 0.680]`.
    pub fn describe(&self) -> String {
        let cpp = format!(
            "{:.2} contacts/period, {:.0} % of the time in contact",
            self.stats.contacts_per_period,
            100.0 * self.stats.contact_fraction
        );
        match (self.period(), self.canonical()) {
            (Some(p), Some(z)) => {
                let head: Vec<String> = z.iter().take(4).map(|v| format!("{v:.4}")).collect();
                format!("period {p} at ({}), {cpp}", head.join(", "))
            }
            _ => {
                let (lo, hi) = (
                    self.stats.lo.first().copied().unwrap_or(f64::NAN),
                    self.stats.hi.first().copied().unwrap_or(f64::NAN),
                );
                format!(
                    "{}, {cpp}, first component in [{lo:.3}, {hi:.3}]",
                    self.periodicity
                )
            }
        }
    }
}

/// Counts contacts and time per mode over the recorded window, and keeps its stroboscopic
/// states.
struct WindowObserver<D: nalgebra::Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Index of the stroboscopic point that opens the window.
    first_k: u64,
    free_label: u8,
    /// Window start time, once reached.
    t0: Option<f64>,
    /// End of the run.
    t_end: f64,
    last_t: f64,
    label: u8,
    time_in: [f64; 256],
    onsets: u64,
    strobe: Vec<OVector<f64, D>>,
}

impl<D: nalgebra::Dim> HybridObserver<D> for WindowObserver<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn on_strobe(&mut self, point: &StrobePoint<D>) {
        if point.k == self.first_k {
            self.t0 = Some(point.t);
            self.last_t = point.t;
            self.label = point.label;
        } else {
            self.strobe.push(point.y.clone());
        }
    }

    fn on_event(&mut self, event: &EventRecord<D>) {
        if self.t0.is_some_and(|t0| event.t > t0) {
            self.time_in[usize::from(self.label)] += event.t - self.last_t;
            self.last_t = event.t;
            if event.from == self.free_label && event.to != self.free_label {
                self.onsets += 1;
            }
        }
        self.label = event.to;
    }
}

/// One window: discard `transient`, record `record` periods from `y0` at $t = 0$.
fn window<M: RotorModel>(
    model: &M,
    y0: &OVector<f64, M::Dim>,
    transient: u64,
    record: u64,
    config: &AttractorOptions,
) -> Result<WindowObserver<M::Dim>, SimError<M::Dim>>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    let period = model.forcing_period();
    let last = transient + record;
    let plan = OutputPlan {
        t_end: period * last as f64,
        strobe: Some(StrobeRange {
            first: transient,
            last,
        }),
        dense: None,
        events: true,
    };
    let mut obs = WindowObserver {
        first_k: transient,
        free_label: config.free_label,
        t0: None,
        t_end: plan.t_end,
        last_t: 0.0,
        label: config.free_label,
        time_in: [0.0; 256],
        onsets: 0,
        strobe: Vec::with_capacity(record as usize),
    };
    simulate(model, 0.0, y0, &plan, &config.opts, &mut obs)?;
    obs.time_in[usize::from(obs.label)] += obs.t_end - obs.last_t;
    Ok(obs)
}

/// Runs `model` from `y0` and identifies the attractor it settles on (see the
/// [module docs](super)).
///
/// # Errors
/// The driver's [`SimError`] (with the last good state) if a run fails; invalid settings
/// (`record < 2 · max_period`, `max_transient < transient`, a period bound of 0, an invalid
/// period tolerance) are [`SimErrorKind::InvalidOption`].
///
/// # Example
///
/// ```
/// use jeffcott::global::{find_attractor, AttractorOptions};
/// use jeffcott::params::Preset;
/// use jeffcott::JeffcottModel;
///
/// let model = JeffcottModel::new(Preset::Fig8a.params().with_eta(2.0))?;
/// let y0 = model.state_at([0.0, 0.0], [0.0, 0.0])?;
/// let config = AttractorOptions::default().with_transient(300).with_record(32);
/// let a = find_attractor(&model, &y0, &config)?;
/// assert_eq!(a.period(), Some(1));
/// assert!((a.canonical().unwrap()[0] - 0.5781094858).abs() < 1e-6);
/// assert_eq!(a.stats.contacts_per_period, 1.0);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn find_attractor<M: RotorModel>(
    model: &M,
    y0: &OVector<f64, M::Dim>,
    config: &AttractorOptions,
) -> Result<Attractor, SimError<M::Dim>>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    if let Some((field, value, hint)) = invalid_setting(config) {
        return Err(SimError {
            kind: SimErrorKind::InvalidOption { field, value, hint },
            t: 0.0,
            y: y0.clone(),
            stats: Box::default(),
        });
    }
    let test = config.period_test;
    let scale = model.state_scale();
    let mut start = y0.clone();
    let mut transient_done = 0u64;
    let mut periods_run = 0u64;
    loop {
        let obs = window(model, &start, config.transient, config.record, config)?;
        let t_end = obs.t_end;
        transient_done += config.transient;
        periods_run += config.transient + config.record;
        // The sizes and settings are checked above: the test fails only on a non-finite
        // state, i.e. a diverged run.
        let periodicity = test
            .detect_scaled(&obs.strobe, &scale)
            .map_err(|_| SimError {
                kind: SimErrorKind::NonFinite,
                t: t_end,
                y: obs.strobe.last().cloned().unwrap_or_else(|| start.clone()),
                stats: Box::default(),
            })?;
        let more = transient_done + config.transient <= config.max_transient;
        if periodicity.period().is_some() || !more || config.transient == 0 {
            let scale = record_scale(scale.as_slice());
            return Ok(summarise(
                obs,
                periodicity,
                periods_run,
                config.record,
                scale,
            ));
        }
        // Slowly attracting or not periodic: go on from the last state.
        start = obs.strobe.last().cloned().unwrap_or(start);
    }
}

/// The first invalid setting of [`find_attractor`] (field, value, hint), if any.
fn invalid_setting(config: &AttractorOptions) -> Option<(&'static str, f64, &'static str)> {
    let test = config.period_test;
    if test.max_period == 0 {
        return Some((
            "period_test.max_period",
            0.0,
            "test periods up to at least 1",
        ));
    }
    if !(test.tol.is_finite() && test.tol >= 0.0) {
        return Some(("period_test.tol", test.tol, "a finite tolerance >= 0"));
    }
    if config.record < 2 * test.max_period as u64 {
        return Some((
            "record",
            config.record as f64,
            "record at least 2 * period_test.max_period points",
        ));
    }
    if config.max_transient < config.transient {
        return Some((
            "max_transient",
            config.max_transient as f64,
            "max_transient must be at least transient",
        ));
    }
    None
}

/// [`Attractor::scale`] from the model's: empty for a scale of 1 everywhere (the paper's
/// model), whose records are then unchanged.
fn record_scale(scale: &[f64]) -> Vec<f64> {
    if scale.iter().all(|&s| s == 1.0) {
        Vec::new()
    } else {
        scale.to_vec()
    }
}

fn summarise<D: nalgebra::Dim>(
    obs: WindowObserver<D>,
    periodicity: Periodicity,
    periods_run: u64,
    window: u64,
    scale: Vec<f64>,
) -> Attractor
where
    DefaultAllocator: Allocator<D>,
{
    let span = obs.t_end - obs.t0.unwrap_or(0.0);
    let dim = obs.strobe.first().map_or(0, |y| y.len());
    let mut lo = vec![f64::INFINITY; dim];
    let mut hi = vec![f64::NEG_INFINITY; dim];
    for y in &obs.strobe {
        for (c, v) in y.iter().enumerate() {
            lo[c] = lo[c].min(*v);
            hi[c] = hi[c].max(*v);
        }
    }
    let occupancy: Vec<(u8, f64)> = obs
        .time_in
        .iter()
        .enumerate()
        .filter(|&(_, &t)| t > 0.0)
        .map(|(label, &t)| (label as u8, t / span))
        .collect();
    let free = obs.time_in[usize::from(obs.free_label)];
    let cycle = match periodicity.period() {
        Some(p) => {
            let n = obs.strobe.len();
            let last: Vec<Vec<f64>> = obs.strobe[n - p..]
                .iter()
                .map(|y| y.iter().copied().collect())
                .collect();
            let start = (0..p)
                .min_by(|&a, &b| lex_cmp(&last[a], &last[b]))
                .unwrap_or(0);
            (0..p).map(|i| last[(start + i) % p].clone()).collect()
        }
        None => Vec::new(),
    };
    Attractor {
        periodicity,
        cycle,
        scale,
        stats: OrbitStats {
            periods_run,
            window,
            contacts_per_period: obs.onsets as f64 / window as f64,
            contact_fraction: 1.0 - free / span,
            occupancy,
            lo,
            hi,
        },
    }
}

fn lex_cmp(a: &[f64], b: &[f64]) -> std::cmp::Ordering {
    for (u, v) in a.iter().zip(b) {
        match u.total_cmp(v) {
            std::cmp::Ordering::Equal => continue,
            other => return other,
        }
    }
    a.len().cmp(&b.len())
}
