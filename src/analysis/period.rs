use std::fmt;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

use super::AnalysisError;

/// Most windows a record is cut into for [`window_residuals`].
pub const MAX_WINDOWS: usize = 4;

/// The residual of one lag over consecutive windows of a record (see the
/// [module docs](super)): in window `w`, the largest `‖x_i − x_{i−lag}‖∞ / S`.
// serde always, not only with the feature: the sweeps of `global` record it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LagResiduals {
    /// The lag, in samples.
    pub lag: usize,
    values: [f64; MAX_WINDOWS],
    #[serde(deserialize_with = "crate::serde_util::count_at_most::<_, MAX_WINDOWS>")]
    windows: usize,
    span: f64,
}

impl LagResiduals {
    /// Residuals from their parts (e.g. read back from a record): `None` unless `lag ≥ 1`,
    /// there are 1 to [`MAX_WINDOWS`] windows, every residual is finite and `≥ 0`, and `span`
    /// is finite and `≥ 0`.
    pub fn from_parts(lag: usize, per_window: &[f64], span: f64) -> Option<Self> {
        let ok = lag >= 1
            && (1..=MAX_WINDOWS).contains(&per_window.len())
            && per_window.iter().all(|v| v.is_finite() && *v >= 0.0)
            && span.is_finite()
            && span >= 0.0;
        ok.then(|| {
            let mut values = [0.0; MAX_WINDOWS];
            values[..per_window.len()].copy_from_slice(per_window);
            LagResiduals {
                lag,
                values,
                windows: per_window.len(),
                span,
            }
        })
    }

    /// Distance in samples between the centres of the first and the last window.
    pub fn span(&self) -> f64 {
        self.span
    }

    /// The residual of each window, in order (relative to the orbit's scale `S`).
    pub fn per_window(&self) -> &[f64] {
        &self.values[..self.windows]
    }

    /// The first window's residual.
    pub fn first(&self) -> f64 {
        self.values[0]
    }

    /// The last window's residual.
    pub fn last(&self) -> f64 {
        self.values[self.windows.max(1) - 1]
    }

    /// Whether the last window's residual is at most `fraction` times the first's (and the
    /// first is not 0), over at least two windows.
    fn falls_below(&self, fraction: f64) -> bool {
        self.windows >= 2 && self.first() > 0.0 && self.last() <= fraction * self.first()
    }

    /// Whether every window's residual is below the previous window's.
    fn decreasing(&self) -> bool {
        self.per_window().windows(2).all(|w| w[1] < w[0])
    }

    /// How far the points still have to move if the residual keeps decaying geometrically as
    /// it did from the first to the last window (relative to `S`); 0 if it does not decay.
    pub fn extrapolated_drift(&self) -> f64 {
        if !(self.windows >= 2 && self.first() > 0.0 && self.last() < self.first()) {
            return 0.0;
        }
        let s = (self.last() / self.first()).powf(self.lag as f64 / self.span.max(1.0));
        if s >= 1.0 {
            f64::INFINITY
        } else {
            self.last() * s / (1.0 - s)
        }
    }
}

impl fmt::Display for LagResiduals {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let values: Vec<String> = self
            .per_window()
            .iter()
            .map(|v| format!("{v:.2e}"))
            .collect();
        write!(
            f,
            "lag {} (residual per window {})",
            self.lag,
            values.join(", ")
        )
    }
}

/// The outcome of [`detect_period`]. Displays as `period 3`, `not periodic up to 16` or
/// `not converged: lag 8 (residual per window …) within tolerance, lag 1 (…) still shrinking`.
// serde always, not only with the feature: the sweeps of `global` record it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub enum Periodicity {
    /// The orbit repeats after this many samples (the smallest such number; at least 1), and
    /// has converged (see the [module docs](super)).
    Period(usize),
    /// No period up to and including `up_to` passes the test (quasi-periodic, chaotic, or a
    /// period longer than `up_to`, or a transient still present).
    NotPeriodic {
        /// The largest period that was tested.
        up_to: usize,
    },
    /// A lag passes the tolerance but the orbit is still converging: a shorter period may
    /// explain the points, or the cycle itself still moves by more than the tolerance (see the
    /// [module docs](super)). Not a period.
    NotConverged {
        /// The smallest lag within tolerance, with its residual per window.
        passed: LagResiduals,
        /// The lag whose residual was still shrinking: a proper divisor of `passed.lag` (the
        /// points may be converging to that shorter period), or `passed.lag` itself (its
        /// extrapolated drift exceeds the tolerance).
        shrinking: LagResiduals,
    },
}

impl Periodicity {
    /// The period, if one was found.
    pub fn period(&self) -> Option<usize> {
        match *self {
            Periodicity::Period(p) => Some(p),
            Periodicity::NotPeriodic { .. } | Periodicity::NotConverged { .. } => None,
        }
    }

    /// Whether two outcomes say the same thing: the same period, both not periodic up to the
    /// same bound, or both not converged with the same passing and shrinking lags (their
    /// residuals may differ). Bifurcation diagrams and the locator compare outcomes with this.
    pub fn agrees_with(&self, other: &Periodicity) -> bool {
        match (self, other) {
            (Periodicity::Period(a), Periodicity::Period(b)) => a == b,
            (Periodicity::NotPeriodic { up_to: a }, Periodicity::NotPeriodic { up_to: b }) => {
                a == b
            }
            (
                Periodicity::NotConverged {
                    passed: pa,
                    shrinking: sa,
                },
                Periodicity::NotConverged {
                    passed: pb,
                    shrinking: sb,
                },
            ) => pa.lag == pb.lag && sa.lag == sb.lag,
            _ => false,
        }
    }
}

impl fmt::Display for Periodicity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Periodicity::Period(p) => write!(f, "period {p}"),
            Periodicity::NotPeriodic { up_to } => write!(f, "not periodic up to {up_to}"),
            Periodicity::NotConverged { passed, shrinking } => write!(
                f,
                "not converged: {passed} within tolerance, {shrinking} still shrinking"
            ),
        }
    }
}

/// How a stroboscopic orbit of state vectors is tested for periodicity: [`detect_period`]
/// with a period bound that adapts to the number of points.
// serde always, not only with the feature: the sweeps of `global` record it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[non_exhaustive]
pub struct PeriodTest {
    /// Largest period tested (at least 1; the orbit needs `2 · max_period` points). Default 16.
    pub max_period: usize,
    /// Relative tolerance (see the [module docs](super)). Default `1e-6`.
    pub tol: f64,
}

/// Builders: each returns the options with one field changed.
impl PeriodTest {
    /// With [`max_period`](Self::max_period) = `value`.
    #[must_use]
    pub fn with_max_period(mut self, value: usize) -> Self {
        self.max_period = value;
        self
    }

    /// With [`tol`](Self::tol) = `value`.
    #[must_use]
    pub fn with_tol(mut self, value: f64) -> Self {
        self.tol = value;
        self
    }
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
    /// Tests `points` (whole state vectors), lowering `max_period` to `points.len() / 2` if
    /// there are too few points for it (but at least 1).
    ///
    /// # Errors
    /// [`AnalysisError`] from [`detect_period`] (invalid tolerance, fewer than 2 points,
    /// non-finite points).
    pub fn detect<D: Dim>(&self, points: &[OVector<f64, D>]) -> Result<Periodicity, AnalysisError>
    where
        DefaultAllocator: Allocator<D>,
    {
        let slices: Vec<&[f64]> = points.iter().map(|y| y.as_slice()).collect();
        self.detect_slices(&slices)
    }

    /// [`PeriodTest::detect`] with the components in units of `scale` (see the
    /// [module docs](super#units)), e.g. the model's [`RotorModel::state_scale`].
    ///
    /// # Errors
    /// As [`detect_period_scaled`].
    ///
    /// [`RotorModel::state_scale`]: crate::hybrid::RotorModel::state_scale
    pub fn detect_scaled<D: Dim>(
        &self,
        points: &[OVector<f64, D>],
        scale: &OVector<f64, D>,
    ) -> Result<Periodicity, AnalysisError>
    where
        DefaultAllocator: Allocator<D>,
    {
        let slices: Vec<&[f64]> = points.iter().map(|y| y.as_slice()).collect();
        self.detect_slices_scaled(&slices, scale.as_slice())
    }

    pub(super) fn detect_slices(&self, points: &[&[f64]]) -> Result<Periodicity, AnalysisError> {
        let max_period = self.max_period.min(points.len() / 2).max(1);
        detect_period(points, max_period, self.tol)
    }

    pub(super) fn detect_slices_scaled(
        &self,
        points: &[&[f64]],
        scale: &[f64],
    ) -> Result<Periodicity, AnalysisError> {
        let max_period = self.max_period.min(points.len() / 2).max(1);
        detect_period_scaled(points, max_period, self.tol, scale)
    }
}

/// [`detect_period`] with component `c` of every sample in units of `scale[c]` (see the
/// [module docs](super#units)). A scale of 1 for every component gives bitwise the result
/// of [`detect_period`].
///
/// # Errors
///
/// As [`detect_period`]; [`AnalysisError::LengthMismatch`] if `scale` does not have one entry
/// per component, [`AnalysisError::InvalidValue`] (`"scale"`) for an entry that is not finite
/// and `> 0`.
pub fn detect_period_scaled<S: AsRef<[f64]>>(
    samples: &[S],
    max_period: usize,
    tol: f64,
    scale: &[f64],
) -> Result<Periodicity, AnalysisError> {
    match in_units(samples, scale)? {
        Some(scaled) => detect_period(&scaled, max_period, tol),
        None => detect_period(samples, max_period, tol),
    }
}

/// The samples in units of `scale` (`None` when every scale is 1: the samples as they are).
fn in_units<S: AsRef<[f64]>>(
    samples: &[S],
    scale: &[f64],
) -> Result<Option<Vec<Vec<f64>>>, AnalysisError> {
    let dim = samples.first().map_or(scale.len(), |s| s.as_ref().len());
    if scale.len() != dim {
        return Err(AnalysisError::LengthMismatch {
            first: "scale",
            first_len: scale.len(),
            second: "a sample",
            second_len: dim,
        });
    }
    if let Some(&bad) = scale.iter().find(|s| !(s.is_finite() && **s > 0.0)) {
        return Err(AnalysisError::InvalidValue {
            name: "scale",
            value: bad,
            expected: "a finite scale > 0 for every component",
        });
    }
    if scale.iter().all(|&s| s == 1.0) {
        return Ok(None);
    }
    let scaled = samples
        .iter()
        .map(|x| x.as_ref().iter().zip(scale).map(|(v, s)| v / s).collect())
        .collect();
    Ok(Some(scaled))
}

/// Checks the samples (equal lengths, all finite) and returns `(dimension, scale)`.
fn validate<S: AsRef<[f64]>>(samples: &[S]) -> Result<(usize, f64), AnalysisError> {
    let dim = samples.first().map_or(0, |s| s.as_ref().len());
    let mut lo = vec![f64::INFINITY; dim];
    let mut hi = vec![f64::NEG_INFINITY; dim];
    for (index, s) in samples.iter().enumerate() {
        let s = s.as_ref();
        if s.len() != dim {
            return Err(AnalysisError::DimensionMismatch {
                index,
                expected: dim,
                found: s.len(),
            });
        }
        for (component, &v) in s.iter().enumerate() {
            if !v.is_finite() {
                return Err(AnalysisError::NonFiniteSample {
                    index,
                    component,
                    value: v,
                });
            }
            lo[component] = lo[component].min(v);
            hi[component] = hi[component].max(v);
        }
    }
    let extent = lo
        .iter()
        .zip(&hi)
        .map(|(l, h)| h - l)
        .fold(0.0_f64, f64::max);
    Ok((dim, extent.max(1.0)))
}

fn check_tol(tol: f64) -> Result<(), AnalysisError> {
    if tol.is_finite() && tol >= 0.0 {
        Ok(())
    } else {
        Err(AnalysisError::InvalidValue {
            name: "tol",
            value: tol,
            expected: "a finite number >= 0",
        })
    }
}

/// Largest `‖x_i − x_{i−p}‖∞` over `i ≥ p`, stopping early once it exceeds `stop_above`.
fn max_lag_distance<S: AsRef<[f64]>>(samples: &[S], p: usize, stop_above: f64) -> f64 {
    let mut worst = 0.0_f64;
    for i in p..samples.len() {
        let a = samples[i].as_ref();
        let b = samples[i - p].as_ref();
        for (u, v) in a.iter().zip(b) {
            worst = worst.max((u - v).abs());
        }
        if worst > stop_above {
            break;
        }
    }
    worst
}

/// Finds the period of a sampled orbit (see the [module docs](super) for the exact test).
///
/// `samples` can be a slice of arrays (`&[[f64; 2]]`), of vectors (`&[Vec<f64>]`), or of any
/// `AsRef<[f64]>`; for scalar samples use [`detect_period_scalar`].
///
/// # Errors
///
/// * [`AnalysisError::InvalidCount`] if `max_period` is 0;
/// * [`AnalysisError::InvalidValue`] if `tol` is negative, NaN or infinite;
/// * [`AnalysisError::TooFewSamples`] if there are fewer than `2 · max_period` samples;
/// * [`AnalysisError::DimensionMismatch`] if the samples differ in length;
/// * [`AnalysisError::NonFiniteSample`] if a sample holds NaN or an infinity.
///
/// # Example
///
/// ```
/// use jeffcott::analysis::{detect_period, Periodicity};
/// let orbit: Vec<[f64; 1]> = (0..40).map(|i| [[0.1, 0.7, 0.4][i % 3]]).collect();
/// assert_eq!(detect_period(&orbit, 8, 1e-9).unwrap(), Periodicity::Period(3));
/// ```
pub fn detect_period<S: AsRef<[f64]>>(
    samples: &[S],
    max_period: usize,
    tol: f64,
) -> Result<Periodicity, AnalysisError> {
    if max_period == 0 {
        return Err(AnalysisError::InvalidCount {
            name: "max_period",
            value: 0,
            expected: "at least 1",
        });
    }
    check_tol(tol)?;
    let needed = max_period.saturating_mul(2);
    if samples.len() < needed {
        return Err(AnalysisError::TooFewSamples {
            got: samples.len(),
            needed,
            why: "testing period p needs 2p samples",
        });
    }
    let (_, scale) = validate(samples)?;
    let threshold = tol * scale;
    let Some(p) = (1..=max_period).find(|&p| max_lag_distance(samples, p, threshold) <= threshold)
    else {
        return Ok(Periodicity::NotPeriodic { up_to: max_period });
    };
    Ok(check_converged(samples, p, tol, scale))
}

/// The residual fall over the record that counts as "still shrinking" for a proper divisor of
/// the passing lag (see the [module docs](super)).
const SHORTER_LAG_FALL: f64 = 0.9;
/// The same for the passing lag itself, whose residual is at the noise level of the samples.
const OWN_LAG_FALL: f64 = 0.5;

/// The two convergence checks of the [module docs](super) on the smallest passing lag `p`.
fn check_converged<S: AsRef<[f64]>>(samples: &[S], p: usize, tol: f64, scale: f64) -> Periodicity {
    let passed = lag_windows(samples, p, scale);
    for q in (1..p).filter(|&q| p.is_multiple_of(q)) {
        let shorter = lag_windows(samples, q, scale);
        if shorter.falls_below(SHORTER_LAG_FALL) {
            return Periodicity::NotConverged {
                passed,
                shrinking: shorter,
            };
        }
    }
    if passed.falls_below(OWN_LAG_FALL) && passed.decreasing() && passed.extrapolated_drift() > tol
    {
        return Periodicity::NotConverged {
            passed,
            shrinking: passed,
        };
    }
    Periodicity::Period(p)
}

/// The residual of lag `p` per window (`1 ≤ p < samples.len()`; validated samples).
fn lag_windows<S: AsRef<[f64]>>(samples: &[S], p: usize, scale: f64) -> LagResiduals {
    let m = samples.len().saturating_sub(p);
    let windows = m.min(MAX_WINDOWS);
    let mut values = [0.0; MAX_WINDOWS];
    let bound = |w: usize| p + w * m / windows.max(1);
    for (w, value) in values.iter_mut().enumerate().take(windows) {
        let window = &samples[bound(w) - p..bound(w + 1)];
        *value = max_lag_distance(window, p, f64::INFINITY) / scale;
    }
    let centre = |w: usize| 0.5 * (bound(w) + bound(w + 1) - 1) as f64;
    let span = if windows >= 2 {
        centre(windows - 1) - centre(0)
    } else {
        0.0
    };
    LagResiduals {
        lag: p,
        values,
        windows,
        span,
    }
}

/// The residual of lag `p` per window of the record (see the [module docs](super)): the
/// comparisons `i = p, …, n−1` cut into `min(4, n − p)` consecutive windows, each window's
/// largest `‖x_i − x_{i−p}‖∞` divided by the scale `S`.
///
/// # Errors
///
/// As [`recurrence_residual`].
pub fn window_residuals<S: AsRef<[f64]>>(
    samples: &[S],
    p: usize,
) -> Result<LagResiduals, AnalysisError> {
    check_lag(samples.len(), p)?;
    let (_, scale) = validate(samples)?;
    Ok(lag_windows(samples, p, scale))
}

fn check_lag(n: usize, p: usize) -> Result<(), AnalysisError> {
    if p == 0 {
        return Err(AnalysisError::InvalidCount {
            name: "p",
            value: 0,
            expected: "at least 1",
        });
    }
    let needed = p.saturating_mul(2);
    if n < needed {
        return Err(AnalysisError::TooFewSamples {
            got: n,
            needed,
            why: "a lag of p needs 2p samples",
        });
    }
    Ok(())
}

/// [`detect_period`] for scalar samples (for example the rotor's `x` alone).
///
/// # Errors
///
/// As [`detect_period`].
pub fn detect_period_scalar(
    samples: &[f64],
    max_period: usize,
    tol: f64,
) -> Result<Periodicity, AnalysisError> {
    let wrapped: Vec<[f64; 1]> = samples.iter().map(|&v| [v]).collect();
    detect_period(&wrapped, max_period, tol)
}

/// How far the orbit is from repeating after `p` samples, relative to its scale:
/// `max_{i ≥ p} ‖x_i − x_{i−p}‖∞ / S` with `S = max(1, extent)` as in the module docs.
///
/// [`detect_period`] accepts `p` exactly when this is `≤ tol`, so this tells how loose the
/// tolerance would need to be.
///
/// # Errors
///
/// [`AnalysisError::InvalidCount`] if `p` is 0, [`AnalysisError::TooFewSamples`] if there are
/// fewer than `2p` samples, and the sample errors of [`detect_period`].
pub fn recurrence_residual<S: AsRef<[f64]>>(samples: &[S], p: usize) -> Result<f64, AnalysisError> {
    check_lag(samples.len(), p)?;
    let (_, scale) = validate(samples)?;
    Ok(max_lag_distance(samples, p, f64::INFINITY) / scale)
}

/// Groups scalar values into clusters and returns the mean of each cluster, in increasing order.
///
/// The values are sorted, and two neighbours in sorted order belong to the same cluster when
/// they differ by at most `tol` (an absolute tolerance). Clusters chain: values spread evenly
/// with spacing below `tol` form one cluster however wide it is. This is what a bifurcation
/// diagram needs: a period-`p` orbit gives `p` clusters (or fewer if branches coincide within
/// `tol`), a quasi-periodic or chaotic one gives many.
///
/// The result depends only on the multiset of values, not on their order.
///
/// # Errors
///
/// [`AnalysisError::InvalidValue`] if `tol` is negative or not finite;
/// [`AnalysisError::NonFiniteSample`] if a value is NaN or infinite (`component` is 0).
pub fn distinct_values(values: &[f64], tol: f64) -> Result<Vec<f64>, AnalysisError> {
    check_tol(tol)?;
    if let Some((index, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(AnalysisError::NonFiniteSample {
            index,
            component: 0,
            value,
        });
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let mut means = Vec::new();
    let mut start = 0;
    for i in 1..=sorted.len() {
        if i == sorted.len() || sorted[i] - sorted[i - 1] > tol {
            let cluster = &sorted[start..i];
            if !cluster.is_empty() {
                means.push(cluster.iter().sum::<f64>() / cluster.len() as f64);
            }
            start = i;
        }
    }
    Ok(means)
}

/// The number of clusters [`distinct_values`] finds.
///
/// # Errors
///
/// As [`distinct_values`].
pub fn count_distinct(values: &[f64], tol: f64) -> Result<usize, AnalysisError> {
    distinct_values(values, tol).map(|v| v.len())
}
