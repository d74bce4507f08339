//! Angle-domain records and order tracking (the analysis module's docs, "Spectra and order
//! tracking").

use super::order::{check_finite, same_length, whirl_spectrum, FullSpectrum, Window, MIN_SAMPLES};
use std::f64::consts::TAU;

use super::AnalysisError;

/// A record at equal steps of the shaft's angle: sample $k$ at the phase
/// $\varphi_0 + 2\pi k/S$ (its time in `times`).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct AngleSamples {
    /// The samples per revolution $S$.
    pub per_revolution: usize,
    /// The phase of sample 0, $\varphi_0$.
    pub phase0: f64,
    /// The time of each sample (increasing).
    pub times: Vec<f64>,
    /// The coordinate $x$ of each sample.
    pub x: Vec<f64>,
    /// The coordinate $y$ of each sample.
    pub y: Vec<f64>,
    /// The resampling's node constant $P = \max_k \prod_{i=1}^{6}|\varphi_k - \varphi_{k,i}|$
    /// over the resampled phases $\varphi_k$ and the six recorded phases each is interpolated
    /// from ([`AngleSamples::resample`]; 0 for a record taken as it is,
    /// [`AngleSamples::new`]). It sets [`AngleSamples::interpolation_error`]; equal steps $h$
    /// give $P = (15/8)^2 h^6 \approx 3.5 h^6$ where the resampled phase is centred among its
    /// six, more near the record's ends.
    #[cfg_attr(feature = "serde", serde(default))]
    pub node_constant: f64,
}

impl AngleSamples {
    /// A record already at the phases $\varphi_0 + 2\pi k/S$ (e.g. the strobes of a profiled
    /// rotor with $S$ strobes a revolution), taken as it is.
    ///
    /// # Errors
    /// `InvalidCount` for `per_revolution` < 4, `LengthMismatch`, `NonFiniteSample`,
    /// `TimesNotIncreasing`.
    pub fn new(
        per_revolution: usize,
        phase0: f64,
        times: Vec<f64>,
        x: Vec<f64>,
        y: Vec<f64>,
    ) -> Result<Self, AnalysisError> {
        if per_revolution < MIN_SAMPLES {
            return Err(AnalysisError::InvalidCount {
                name: "per_revolution",
                value: per_revolution,
                expected: "at least 4 samples a revolution",
            });
        }
        same_length(("times", &times), ("x", &x))?;
        same_length(("x", &x), ("y", &y))?;
        check_finite(&times, 0)?;
        check_finite(&x, 0)?;
        check_finite(&y, 1)?;
        if let Some(i) = times.windows(2).position(|w| w[1] <= w[0]) {
            return Err(AnalysisError::TimesNotIncreasing {
                index: i + 1,
                previous: times[i],
                time: times[i + 1],
            });
        }
        Ok(Self {
            per_revolution,
            phase0,
            times,
            x,
            y,
            node_constant: 0.0,
        })
    }

    /// The bound on the resampling's error for a whirl component of order `order`,
    /// $A e^{i m \varphi}$, relative to its amplitude $A$: the remainder of 6-point Lagrange
    /// interpolation, $|f^{(6)}| P/6!$ for the real and imaginary parts each, with
    /// $|f^{(6)}| \le m^6 A$:
    /// $$\epsilon_m = \sqrt2\thinspace m^6 P/720$$
    /// ([`AngleSamples::node_constant`] $P$). For a 1x whirl recorded at 4, 8 and 16 samples a
    /// revolution it is 0.50, 7.8e-3 and 1.2e-4 against resampling errors of 0.22, 4.9e-3 and
    /// 8.1e-5 (the test `a_coarse_record_is_refused_by_order_tracking_and_the_bound_holds`;
    /// the record's first and last samples, interpolated off-centre, set the largest): it falls
    /// as the phase step to the sixth power and rises as the order to the sixth. 0 for a record
    /// taken as it is.
    pub fn interpolation_error(&self, order: f64) -> f64 {
        std::f64::consts::SQRT_2 * order.abs().powi(6) * self.node_constant / 720.0
    }

    /// Resamples a record at any `times` with the shaft's `phases` there (increasing) at the
    /// phases $2\pi k/S$ within the record, by 6-point Lagrange interpolation in the phase
    /// (the module's docs); the times are interpolated alike. The result carries the
    /// interpolation's error bound ([`AngleSamples::interpolation_error`]), which
    /// [`order_track`] checks against its tolerance.
    ///
    /// # Errors
    /// `InvalidCount` for `per_revolution` < 4, `TooFewSamples` for fewer than 6 samples,
    /// `LengthMismatch`, `NonFiniteSample`, [`AnalysisError::PhaseNotIncreasing`].
    pub fn resample(
        times: &[f64],
        phases: &[f64],
        x: &[f64],
        y: &[f64],
        per_revolution: usize,
    ) -> Result<Self, AnalysisError> {
        for (name, v) in [("phases", phases), ("x", x), ("y", y)] {
            same_length(("times", times), (name, v))?;
        }
        if times.len() < POINTS {
            return Err(AnalysisError::TooFewSamples {
                got: times.len(),
                needed: POINTS,
                why: "the angle resampling interpolates on 6 samples",
            });
        }
        for (c, v) in [phases, x, y, times].into_iter().enumerate() {
            check_finite(v, c)?;
        }
        if let Some(i) = phases.windows(2).position(|w| w[1] <= w[0]) {
            return Err(AnalysisError::PhaseNotIncreasing {
                index: i + 1,
                previous: phases[i],
                phase: phases[i + 1],
            });
        }
        let step = TAU / per_revolution as f64;
        let first = (phases[0] / step).ceil() as i64;
        let last = (phases[phases.len() - 1] / step).floor() as i64;
        let (mut t, mut xs, mut ys) = (Vec::new(), Vec::new(), Vec::new());
        let mut j = 0;
        let mut node_constant = 0.0f64;
        for k in first..=last {
            let target = k as f64 * step;
            while j + 2 < phases.len() && phases[j + 1] <= target {
                j += 1;
            }
            let lo = j.saturating_sub(2).min(phases.len() - POINTS);
            let at = &phases[lo..lo + POINTS];
            node_constant = node_constant.max(at.iter().map(|p| (target - p).abs()).product());
            t.push(lagrange(at, &times[lo..lo + POINTS], target));
            xs.push(lagrange(at, &x[lo..lo + POINTS], target));
            ys.push(lagrange(at, &y[lo..lo + POINTS], target));
        }
        let mut samples = Self::new(per_revolution, first as f64 * step, t, xs, ys)?;
        samples.node_constant = node_constant;
        Ok(samples)
    }

    /// The full spectrum of the whole record in shaft orders (the frequency axis in cycles
    /// per revolution): a stationary run's spectrum.
    ///
    /// # Errors
    /// `TooFewSamples` for fewer than 4 samples.
    pub fn order_spectrum(&self, window: Window) -> Result<FullSpectrum, AnalysisError> {
        if self.x.len() < MIN_SAMPLES {
            return Err(AnalysisError::TooFewSamples {
                got: self.x.len(),
                needed: MIN_SAMPLES,
                why: "a spectrum needs a record of several samples",
            });
        }
        let step = 1.0 / self.per_revolution as f64;
        Ok(whirl_spectrum(&self.x, &self.y, step, window))
    }
}

/// The points of the angle interpolation.
const POINTS: usize = 6;

/// The Lagrange polynomial through `(at[i], values[i])` at `target`.
fn lagrange(at: &[f64], values: &[f64], target: f64) -> f64 {
    let mut sum = 0.0;
    for (i, (&xi, &vi)) in at.iter().zip(values).enumerate() {
        let mut basis = 1.0;
        for (j, &xj) in at.iter().enumerate() {
            if j != i {
                basis *= (target - xj) / (xi - xj);
            }
        }
        sum += basis * vi;
    }
    sum
}

/// The settings of [`order_track`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct OrderTrackOptions {
    /// The orders tracked (multiples of $1/W$, below $S/2$). Default 1/2, 1, 3/2, 2, 3.
    pub orders: Vec<f64>,
    /// The window's length $W$ in revolutions. Default 8.
    pub revolutions_per_window: usize,
    /// The revolutions from one window to the next. Default 2.
    pub hop_revolutions: usize,
    /// The window. Default Hann.
    pub window: Window,
    /// The largest resampling error accepted for the highest tracked order, relative to its
    /// amplitude ([`AngleSamples::interpolation_error`]). Default 0.01 (0.09 dB).
    pub max_interpolation_error: f64,
}

impl Default for OrderTrackOptions {
    fn default() -> Self {
        Self {
            orders: vec![0.5, 1.0, 1.5, 2.0, 3.0],
            revolutions_per_window: 8,
            hop_revolutions: 2,
            window: Window::Hann,
            max_interpolation_error: 1e-2,
        }
    }
}

/// One window of [`order_track`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct OrderRow {
    /// The time of the window's centre sample $N/2$.
    pub time: f64,
    /// The phase of the centre sample.
    pub phase: f64,
    /// The angular speed at the centre sample (the analysis module's docs).
    pub speed: f64,
    /// The forward whirl radius of each tracked order.
    pub forward: Vec<f64>,
    /// The backward whirl radius of each tracked order.
    pub backward: Vec<f64>,
    /// The window's full spectrum in orders (for a waterfall).
    pub spectrum: FullSpectrum,
}

/// Tracks the orders of `options` through the record `samples`: one [`OrderRow`] a window.
///
/// # Errors
/// `InvalidCount` for a window or hop of 0 revolutions; `InvalidValue` (`"orders"`) for an
/// order that is not a multiple of $1/W$ or not in $[0, S/2)$, or for a
/// `max_interpolation_error` that is NaN or not positive; `OrderUnresolved` for a record
/// resampled too coarsely for the highest order; `TooFewSamples` for a record shorter than
/// one window.
pub fn order_track(
    samples: &AngleSamples,
    options: &OrderTrackOptions,
) -> Result<Vec<OrderRow>, AnalysisError> {
    let (w, s) = (options.revolutions_per_window, samples.per_revolution);
    for (name, value) in [
        ("revolutions_per_window", w),
        ("hop_revolutions", options.hop_revolutions),
    ] {
        if value == 0 {
            return Err(AnalysisError::InvalidCount {
                name,
                value,
                expected: "at least 1 revolution",
            });
        }
    }
    let bins = order_bins(&options.orders, w, s)?;
    check_resolution(samples, options)?;
    let n = w * s;
    if n < 8 {
        return Err(AnalysisError::InvalidCount {
            name: "revolutions_per_window",
            value: w,
            expected: "a window of at least 8 samples",
        });
    }
    if samples.x.len() < n {
        return Err(AnalysisError::TooFewSamples {
            got: samples.x.len(),
            needed: n,
            why: "one window of revolutions_per_window revolutions",
        });
    }
    let step = 1.0 / s as f64;
    let hop = options.hop_revolutions * s;
    let rows = (0..=(samples.x.len() - n) / hop)
        .map(|i| {
            let range = i * hop..i * hop + n;
            let spectrum = whirl_spectrum(
                &samples.x[range.clone()],
                &samples.y[range.clone()],
                step,
                options.window,
            );
            let t = &samples.times[range.start + n / 2 - 2..=range.start + n / 2 + 2];
            // dt/dphi at the centre by the fourth-order central difference.
            let dt_dphi = (-t[4] + 8.0 * t[3] - 8.0 * t[1] + t[0]) / (12.0 * step * TAU);
            OrderRow {
                time: t[2],
                phase: samples.phase0 + TAU * (range.start + n / 2) as f64 * step,
                speed: 1.0 / dt_dphi,
                forward: bins.iter().map(|&k| spectrum.forward[k]).collect(),
                backward: bins.iter().map(|&k| spectrum.backward[k]).collect(),
                spectrum,
            }
        })
        .collect();
    Ok(rows)
}

/// The resampling's error bound for the highest tracked order against the tolerance.
fn check_resolution(
    samples: &AngleSamples,
    options: &OrderTrackOptions,
) -> Result<(), AnalysisError> {
    let tolerance = options.max_interpolation_error;
    if tolerance.is_nan() || tolerance <= 0.0 {
        return Err(AnalysisError::InvalidValue {
            name: "max_interpolation_error",
            value: tolerance,
            expected: "a relative error > 0",
        });
    }
    let order = options.orders.iter().fold(0.0, |m: f64, o| m.max(o.abs()));
    let bound = samples.interpolation_error(order);
    if bound > tolerance {
        return Err(AnalysisError::OrderUnresolved {
            order,
            bound,
            tolerance,
        });
    }
    Ok(())
}

/// The bin of each order, checked: a multiple of $1/W$ in $[0, S/2)$.
fn order_bins(orders: &[f64], w: usize, s: usize) -> Result<Vec<usize>, AnalysisError> {
    orders
        .iter()
        .map(|&order| {
            let bin = order * w as f64;
            let k = bin.round();
            if order.is_finite()
                && (bin - k).abs() <= 1e-9 * bin.abs().max(1.0)
                && k >= 0.0
                && 2.0 * order < s as f64
            {
                Ok(k as usize)
            } else {
                Err(AnalysisError::InvalidValue {
                    name: "orders",
                    value: order,
                    expected: "a multiple of 1/revolutions_per_window in [0, per_revolution / 2)",
                })
            }
        })
        .collect()
}
