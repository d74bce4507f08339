//! Period detection for sampled (stroboscopic) orbits, and counting distinct values.
//!
//! # The test
//!
//! Let `x_0, …, x_{n-1}` be the samples (state vectors of equal length `d`, taken once per
//! forcing period after the transient). Define
//!
//! * the *extent* `E = max_c (max_i x_i[c] − min_i x_i[c])`, the largest side of the orbit's
//!   bounding box;
//! * the *scale* `S = max(1, E)`;
//! * the *threshold* `θ = tol · S`.
//!
//! The orbit has period `p` if **every** sample `i ≥ p` satisfies
//! `‖x_i − x_{i−p}‖∞ ≤ θ`. [`detect_period`] reports the smallest such `p` with
//! `1 ≤ p ≤ max_period`, or [`Periodicity::NotPeriodic`] if there is none.
//!
//! So `tol` is relative to the orbit's size for large orbits and absolute for orbits smaller
//! than 1 (in the non-dimensional units of the model the gap is 1, so a fixed point with
//! `tol = 1e-6` is resolved to 1e-6 gap). Because every sample is checked, a single outlier
//! (for example a transient not fully discarded) rejects the period: this is deliberate.
//! A period `p` is only tested with at least `p` comparisons, which is why at least
//! `2 · max_period` samples are required.
//!
//! A multiple of the period also passes the test; the smallest passing `p` is the period.
//! Quasi-periodic and chaotic orbits pass for no `p` (up to the tolerance: a quasi-periodic
//! orbit whose rotation number is close to `q/p` may pass for `p` if `tol` is loose).

use std::fmt;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

use super::AnalysisError;

/// The outcome of [`detect_period`]. Displays as `period 3` or `not periodic up to 16`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum Periodicity {
    /// The orbit repeats after this many samples (the smallest such number; at least 1).
    Period(usize),
    /// No period up to and including `up_to` passes the test (quasi-periodic, chaotic, or a
    /// period longer than `up_to`, or a transient still present).
    NotPeriodic {
        /// The largest period that was tested.
        up_to: usize,
    },
}

impl Periodicity {
    /// The period, if one was found.
    pub fn period(&self) -> Option<usize> {
        match *self {
            Periodicity::Period(p) => Some(p),
            Periodicity::NotPeriodic { .. } => None,
        }
    }
}

impl fmt::Display for Periodicity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Periodicity::Period(p) => write!(f, "period {p}"),
            Periodicity::NotPeriodic { up_to } => write!(f, "not periodic up to {up_to}"),
        }
    }
}

/// How a stroboscopic orbit of state vectors is tested for periodicity: [`detect_period`]
/// with a period bound that adapts to the number of points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PeriodTest {
    /// Largest period tested (at least 1; the orbit needs `2 · max_period` points). Default 16.
    pub max_period: usize,
    /// Relative tolerance (see the [module docs](self)). Default `1e-6`.
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

    pub(super) fn detect_slices(&self, points: &[&[f64]]) -> Result<Periodicity, AnalysisError> {
        let max_period = self.max_period.min(points.len() / 2).max(1);
        detect_period(points, max_period, self.tol)
    }
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

/// Finds the period of a sampled orbit (see the [module docs](self) for the exact test).
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
    for p in 1..=max_period {
        if max_lag_distance(samples, p, threshold) <= threshold {
            return Ok(Periodicity::Period(p));
        }
    }
    Ok(Periodicity::NotPeriodic { up_to: max_period })
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
    if p == 0 {
        return Err(AnalysisError::InvalidCount {
            name: "p",
            value: 0,
            expected: "at least 1",
        });
    }
    let needed = p.saturating_mul(2);
    if samples.len() < needed {
        return Err(AnalysisError::TooFewSamples {
            got: samples.len(),
            needed,
            why: "a lag of p needs 2p samples",
        });
    }
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
