use std::collections::VecDeque;

use nalgebra::{DMatrix, DVector, DefaultAllocator, OVector};

use super::augmented::LinearEvent;
use super::error::StabilityError;
use super::map::StroboscopicMap;
use super::saltation::GRAZING_MARGIN;
use super::statistics::{qr_step, BatchEstimate, BatchMeans};
use crate::analysis::Progress;
use crate::hybrid::{SimOptions, Variational, VariationalAlloc};

/// Options of [`lyapunov_exponents`]. Start from `Default` and change fields with the `with_` builders.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct LyapunovOptions {
    /// Forcing periods run (plain simulation) before anything, to reach the attractor.
    /// Default 300.
    pub transient: u64,
    /// Periods of QR (and renormalisation of the second trajectory) before recording, to align
    /// the frame. Default 100.
    pub align: u64,
    /// Recorded periods. Default 2000.
    pub periods: u64,
    /// Batch length of the batch means (periods). Default 100; use at least 20 batches.
    pub batch: u64,
    /// Initial separation of the two-trajectory method, in units of the model's
    /// [`RotorModel::state_scale`](crate::hybrid::RotorModel::state_scale) (the distance is
    /// the Euclidean norm of the scaled non-algebraic components); `None` skips it. Default
    /// `Some(1e-8)`.
    pub separation: Option<f64>,
    /// How many exponents, the largest first: `None` (default) for all; fewer carry fewer
    /// directions (one: a Jacobian-vector product per period).
    pub exponents: Option<usize>,
    /// The last this many recorded sections' states (the non-algebraic components) are kept in
    /// [`LyapunovSpectrum::sections`], e.g. for a bifurcation diagram. Default 0.
    pub keep: usize,
    /// Simulation options of every run.
    pub sim: SimOptions,
}

/// Builders: each returns the options with one field changed.
impl LyapunovOptions {
    /// With [`transient`](Self::transient) = `value`.
    #[must_use]
    pub fn with_transient(mut self, value: u64) -> Self {
        self.transient = value;
        self
    }

    /// With [`align`](Self::align) = `value`.
    #[must_use]
    pub fn with_align(mut self, value: u64) -> Self {
        self.align = value;
        self
    }

    /// With [`periods`](Self::periods) = `value`.
    #[must_use]
    pub fn with_periods(mut self, value: u64) -> Self {
        self.periods = value;
        self
    }

    /// With [`batch`](Self::batch) = `value`.
    #[must_use]
    pub fn with_batch(mut self, value: u64) -> Self {
        self.batch = value;
        self
    }

    /// With [`separation`](Self::separation) = `value`.
    #[must_use]
    pub fn with_separation(mut self, value: Option<f64>) -> Self {
        self.separation = value;
        self
    }

    /// With [`exponents`](Self::exponents) = `Some(value)`.
    #[must_use]
    pub fn with_exponents(mut self, value: usize) -> Self {
        self.exponents = Some(value);
        self
    }

    /// With [`keep`](Self::keep) = `value`.
    #[must_use]
    pub fn with_keep(mut self, value: usize) -> Self {
        self.keep = value;
        self
    }

    /// With [`sim`](Self::sim) = `value`.
    #[must_use]
    pub fn with_sim(mut self, value: SimOptions) -> Self {
        self.sim = value;
        self
    }
}

impl Default for LyapunovOptions {
    fn default() -> Self {
        Self {
            transient: 300,
            align: 100,
            periods: 2000,
            batch: 100,
            separation: Some(1e-8),
            exponents: None,
            keep: 0,
            sim: SimOptions::default(),
        }
    }
}

/// The largest exponent by the two-trajectory method.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct TwoTrajectory {
    /// $\lambda_1$ per forcing period.
    pub lambda: f64,
    /// Its batch-means standard error.
    pub stderr: f64,
    /// The initial separation $d_0$.
    pub separation: f64,
}

/// Lyapunov exponents of a trajectory.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LyapunovSpectrum {
    /// The exponents per forcing period, largest first (QR method), with their batch-means
    /// errors and running estimate.
    pub per_period: BatchEstimate,
    /// The exponents per unit $\tau$ (per period divided by the forcing period).
    pub per_time: Vec<f64>,
    /// Their standard errors per unit $\tau$.
    pub per_time_stderr: Vec<f64>,
    /// The forcing period.
    pub forcing_period: f64,
    /// The largest exponent by the two-trajectory method, if asked for.
    pub two_trajectory: Option<TwoTrajectory>,
    /// Events crossed at a margin below [`GRAZING_MARGIN`] (recorded periods).
    pub grazing_events: usize,
    /// The smallest event margin met (recorded periods).
    pub min_margin: f64,
    /// Sections (recorded periods) at which the map on $z$ was not closed (openness > 0).
    pub open_sections: usize,
    /// The state at the end.
    pub end: Vec<f64>,
    /// The last [`LyapunovOptions::keep`] recorded sections (non-algebraic components), in
    /// order.
    pub sections: Vec<Vec<f64>>,
}

impl LyapunovSpectrum {
    /// $\sum_i\lambda_i$ per period.
    pub fn sum(&self) -> f64 {
        self.per_period.mean.iter().sum()
    }
}

/// Lyapunov exponents of `model`'s stroboscopic map along the trajectory from `y0` (module
/// docs).
///
/// # Errors
/// [`StabilityError::InvalidOption`] for zero periods or a batch longer than the recorded
/// periods; a simulation error (with the time of the period that failed).
pub fn lyapunov_exponents<M>(
    model: &M,
    y0: &OVector<f64, M::Dim>,
    opts: &LyapunovOptions,
) -> Result<LyapunovSpectrum, StabilityError>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    lyapunov_exponents_with_progress(model, y0, opts, &())
}

/// [`lyapunov_exponents`] with an observer: `progress` is told `(k, align + periods)` after
/// each period `k` of the alignment and the recording, and asked
/// ([`Progress::should_stop`]) before the transient and before each of those periods whether
/// to stop. The transient is one run, not asked inside: run a long one first and start from
/// its end. The results are those of [`lyapunov_exponents`], bit for bit.
///
/// # Errors
/// Those of [`lyapunov_exponents`], and [`StabilityError::Stopped`] when `progress` asks to
/// stop, with the exponents of the periods recorded by then in `partial` (`None` before the
/// first; its [`BatchEstimate::samples`] counts them).
pub fn lyapunov_exponents_with_progress<M>(
    model: &M,
    y0: &OVector<f64, M::Dim>,
    opts: &LyapunovOptions,
    progress: &dyn Progress,
) -> Result<LyapunovSpectrum, StabilityError>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    check(opts)?;
    let total = opts.align + opts.periods;
    let stopped = |done, partial| StabilityError::Stopped {
        done,
        total,
        partial,
    };
    if progress.should_stop() {
        return Err(stopped(0, None));
    }
    let mut y = y0.clone_owned();
    if opts.transient > 0 {
        y = StroboscopicMap::new(model, opts.transient, opts.sim)?
            .advance(&y)?
            .y;
    }
    let map = StroboscopicMap::new(model, 1, opts.sim)?;
    let d = map.components().len();
    let p = opts.exponents.unwrap_or(d).clamp(1, d);
    let mut q = DMatrix::identity(d, p);
    let mut record = Record::new(p, opts);
    let mut second = opts.separation.map(|d0| SecondTrajectory {
        d0,
        u: unit(d),
        // The second trajectory's separation is measured in units of the model's scale.
        scale: map.reduce(&model.state_scale()),
    });
    for k in 0..total {
        if progress.should_stop() {
            let partial = (k > opts.align)
                .then(|| Box::new(record.spectrum(model.forcing_period(), opts.separation, &y)));
            return Err(stopped(k, partial));
        }
        let recording = k >= opts.align;
        let lin = map.linearize_along(&y, &q)?;
        if let Some(second) = second.as_mut() {
            let log = second.step(&map, &y, &lin.value)?;
            if recording {
                record.two_stats.push(&[log]);
            }
        }
        let (qn, logs) = qr_step(lin.jacobian);
        if recording {
            record.period(&lin.events, lin.openness[0], logs.as_slice(), &lin.value);
        }
        q = qn;
        y = lin.y;
        progress.update(units(k + 1), units(total));
    }
    Ok(record.spectrum(model.forcing_period(), opts.separation, &y))
}

/// A count of periods as the observer's `usize` (saturating on a 32-bit target).
fn units(n: u64) -> usize {
    usize::try_from(n).unwrap_or(usize::MAX)
}

fn check(opts: &LyapunovOptions) -> Result<(), StabilityError> {
    if opts.periods == 0 || opts.batch == 0 || opts.batch > opts.periods {
        return Err(StabilityError::InvalidOption {
            field: "batch",
            value: opts.batch as f64,
            hint: "periods >= 1 and 1 <= batch <= periods (at least 20 batches for an error)",
        });
    }
    if let Some(d0) = opts.separation
        && !(d0.is_finite() && d0 > 0.0)
    {
        return Err(StabilityError::InvalidOption {
            field: "separation",
            value: d0,
            hint: "a finite separation > 0, e.g. 1e-8",
        });
    }
    Ok(())
}

/// The second trajectory of the two-trajectory method: its separation $d_0$ along the unit
/// direction `u`, in units of `scale`.
struct SecondTrajectory {
    d0: f64,
    u: DVector<f64>,
    scale: DVector<f64>,
}

impl SecondTrajectory {
    /// Runs the second trajectory one period from the section `y`, $d_0$ along `u`, against the
    /// fiducial end `end` ($z$): returns $\ln(d_1/d_0)$ and renormalises `u` along the new
    /// separation.
    fn step<M>(
        &mut self,
        map: &StroboscopicMap<'_, M>,
        y: &OVector<f64, M::Dim>,
        end: &DVector<f64>,
    ) -> Result<f64, StabilityError>
    where
        M: Variational,
        DefaultAllocator: VariationalAlloc<M::Dim>,
    {
        let z = map.reduce(y);
        let zp = &z + (&self.u * self.d0).component_mul(&self.scale);
        let yp = map.state(y, &zp);
        let after = map.advance(&yp)?;
        let diff = (map.reduce(&after.y) - end).component_div(&self.scale);
        let dist = diff.norm();
        if dist > 0.0 && dist.is_finite() {
            self.u = diff / dist;
        }
        Ok((dist / self.d0).ln())
    }
}

/// What the recorded periods accumulate.
struct Record {
    qr_stats: BatchMeans,
    two_stats: BatchMeans,
    sections: VecDeque<Vec<f64>>,
    keep: usize,
    grazing_events: usize,
    min_margin: f64,
    open_sections: usize,
}

impl Record {
    fn new(p: usize, opts: &LyapunovOptions) -> Self {
        Record {
            qr_stats: BatchMeans::new(p, opts.batch as usize),
            two_stats: BatchMeans::new(1, opts.batch as usize),
            sections: VecDeque::with_capacity(opts.keep),
            keep: opts.keep,
            grazing_events: 0,
            min_margin: 1.0,
            open_sections: 0,
        }
    }

    /// One recorded period: the QR's logarithms, its events, its openness, its section `z`.
    fn period(&mut self, events: &[LinearEvent], openness: f64, logs: &[f64], z: &DVector<f64>) {
        self.qr_stats.push(logs);
        for e in events {
            self.min_margin = self.min_margin.min(e.margin);
            if e.margin < GRAZING_MARGIN {
                self.grazing_events += 1;
            }
        }
        if openness > 0.0 {
            self.open_sections += 1;
        }
        if self.keep > 0 {
            if self.sections.len() == self.keep {
                self.sections.pop_front();
            }
            self.sections
                .push_back(z.iter().copied().collect::<Vec<f64>>());
        }
    }

    /// The spectrum from the records, the forcing `period` and the end state `y`.
    fn spectrum<D: nalgebra::Dim>(
        self,
        period: f64,
        separation: Option<f64>,
        y: &OVector<f64, D>,
    ) -> LyapunovSpectrum
    where
        DefaultAllocator: VariationalAlloc<D>,
    {
        let per_period = self.qr_stats.estimate();
        let two_trajectory = separation.map(|d0| {
            let e = self.two_stats.estimate();
            TwoTrajectory {
                lambda: e.mean[0],
                stderr: e.stderr[0],
                separation: d0,
            }
        });
        LyapunovSpectrum {
            per_time: per_period.mean.iter().map(|l| l / period).collect(),
            per_time_stderr: per_period.stderr.iter().map(|s| s / period).collect(),
            per_period,
            forcing_period: period,
            two_trajectory,
            grazing_events: self.grazing_events,
            min_margin: self.min_margin,
            open_sections: self.open_sections,
            end: y.iter().copied().collect(),
            sections: self.sections.into(),
        }
    }
}

/// $(1, 1, \dots)/\sqrt d$: the first direction of the second trajectory.
fn unit(d: usize) -> DVector<f64> {
    DVector::from_element(d, 1.0 / (d as f64).sqrt())
}
