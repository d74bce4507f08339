use nalgebra::{DMatrix, DVector, DefaultAllocator, OVector};

use super::error::StabilityError;
use super::map::StroboscopicMap;
use super::saltation::GRAZING_MARGIN;
use super::statistics::{qr_step, BatchEstimate, BatchMeans};
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
    if opts.periods == 0 || opts.batch == 0 || opts.batch > opts.periods {
        return Err(StabilityError::InvalidOption {
            field: "batch",
            value: opts.batch as f64,
            hint: "periods >= 1 and 1 <= batch <= periods (at least 20 batches for an error)",
        });
    }
    if let Some(d0) = opts.separation {
        if !(d0.is_finite() && d0 > 0.0) {
            return Err(StabilityError::InvalidOption {
                field: "separation",
                value: d0,
                hint: "a finite separation > 0, e.g. 1e-8",
            });
        }
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
    let mut qr_stats = BatchMeans::new(p, opts.batch as usize);
    let mut sections = std::collections::VecDeque::with_capacity(opts.keep);
    let mut two_stats = BatchMeans::new(1, opts.batch as usize);
    let mut u = unit(d);
    // The second trajectory's separation is measured in units of the model's scale.
    let scale = map.reduce(&model.state_scale());
    let (mut grazing_events, mut min_margin, mut open_sections) = (0, 1.0f64, 0);
    for k in 0..opts.align + opts.periods {
        let record = k >= opts.align;
        let lin = map.linearize_along(&y, &q)?;
        // Second trajectory from the same section, d0 along u.
        if let Some(d0) = opts.separation {
            let z = map.reduce(&y);
            let zp = &z + (&u * d0).component_mul(&scale);
            let yp = map.state(&y, &zp);
            let end = map.advance(&yp)?;
            let diff = (map.reduce(&end.y) - &lin.value).component_div(&scale);
            let dist = diff.norm();
            if record {
                two_stats.push(&[(dist / d0).ln()]);
            }
            if dist > 0.0 && dist.is_finite() {
                u = diff / dist;
            }
        }
        let (qn, logs) = qr_step(lin.jacobian);
        if record {
            qr_stats.push(logs.as_slice());
            for e in &lin.events {
                min_margin = min_margin.min(e.margin);
                if e.margin < GRAZING_MARGIN {
                    grazing_events += 1;
                }
            }
            if lin.openness[0] > 0.0 {
                open_sections += 1;
            }
            if opts.keep > 0 {
                if sections.len() == opts.keep {
                    sections.pop_front();
                }
                sections.push_back(lin.value.iter().copied().collect::<Vec<f64>>());
            }
        }
        q = qn;
        y = lin.y;
    }
    let per_period = qr_stats.estimate();
    let period = model.forcing_period();
    let two_trajectory = opts.separation.map(|d0| {
        let e = two_stats.estimate();
        TwoTrajectory {
            lambda: e.mean[0],
            stderr: e.stderr[0],
            separation: d0,
        }
    });
    Ok(LyapunovSpectrum {
        per_time: per_period.mean.iter().map(|l| l / period).collect(),
        per_time_stderr: per_period.stderr.iter().map(|s| s / period).collect(),
        per_period,
        forcing_period: period,
        two_trajectory,
        grazing_events,
        min_margin,
        open_sections,
        end: y.iter().copied().collect(),
        sections: sections.into(),
    })
}

/// $(1, 1, \dots)/\sqrt d$: the first direction of the second trajectory.
fn unit(d: usize) -> DVector<f64> {
    DVector::from_element(d, 1.0 / (d as f64).sqrt())
}
