//! Spectra: windows, whole-record whirl and amplitude spectra (the analysis module's docs,
//! "Spectra and order tracking").

use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

use super::AnalysisError;

/// A spectral window (weighting of the record before the transform).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Window {
    /// No weighting: exact on the bins, but leakage over the whole spectrum off them.
    Rectangular,
    /// The periodic Hann window $\frac12(1 - \cos(2\pi n/N))$ (the module's docs).
    #[default]
    Hann,
}

impl Window {
    /// The weight of sample `n` of `len`.
    pub fn weight(&self, n: usize, len: usize) -> f64 {
        match self {
            Window::Rectangular => 1.0,
            Window::Hann => 0.5 * (1.0 - (std::f64::consts::TAU * n as f64 / len as f64).cos()),
        }
    }

    /// The coherent gain $G = \frac1N\sum_n w_n$ (exact for the periodic windows, $N \ge 2$).
    pub fn coherent_gain(&self) -> f64 {
        match self {
            Window::Rectangular => 1.0,
            Window::Hann => 0.5,
        }
    }

    /// The largest relative loss of amplitude of a component half a bin off (large $N$):
    /// $1 - 2/\pi$ rectangular, $1 - \frac{8}{3\pi}$ Hann.
    pub fn scalloping_loss(&self) -> f64 {
        let pi = std::f64::consts::PI;
        match self {
            Window::Rectangular => 1.0 - 2.0 / pi,
            Window::Hann => 1.0 - 8.0 / (3.0 * pi),
        }
    }
}

/// A one-sided amplitude spectrum of a real record ([`amplitude_spectrum`]).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Spectrum {
    /// The bins' frequencies $k/(N\Delta)$, $0 \le k < N/2$ (cycles per unit of the step).
    pub frequency: Vec<f64>,
    /// The amplitude $A$ of $A\cos(2\pi f t + \psi)$ at each bin.
    pub amplitude: Vec<f64>,
}

/// A full (whirl) spectrum of an orbit $x + iy$ (the module's docs).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct FullSpectrum {
    /// The bins' frequencies $k/(N\Delta)$, $0 \le k < N/2$ (cycles per unit of the step: per
    /// unit time, or shaft orders for [`AngleSamples`](super::AngleSamples)).
    pub frequency: Vec<f64>,
    /// The radius of the forward (with the rotation) circular whirl at each frequency.
    pub forward: Vec<f64>,
    /// The radius of the backward circular whirl at each frequency.
    pub backward: Vec<f64>,
}

/// The fewest samples a spectrum takes.
pub(super) const MIN_SAMPLES: usize = 4;

/// The mean step of `times`, checked: increasing, equally spaced to $10^{-6}$ of the step.
pub(super) fn uniform_step(times: &[f64]) -> Result<f64, AnalysisError> {
    if times.len() < 2 {
        return Err(AnalysisError::TooFewSamples {
            got: times.len(),
            needed: MIN_SAMPLES,
            why: "a spectrum needs a record of several samples",
        });
    }
    check_finite(times, 0)?;
    for (i, w) in times.windows(2).enumerate() {
        if w[1] <= w[0] {
            return Err(AnalysisError::TimesNotIncreasing {
                index: i + 1,
                previous: w[0],
                time: w[1],
            });
        }
    }
    let step = (times[times.len() - 1] - times[0]) / (times.len() - 1) as f64;
    for (index, w) in times.windows(2).enumerate() {
        // Rounding of times of size |t| allows a few ulp of |t| besides the relative slack.
        let slack = 1e-6 * step + 8.0 * f64::EPSILON * w[1].abs();
        if (w[1] - w[0] - step).abs() > slack {
            return Err(AnalysisError::NonUniformSamples {
                index,
                step: w[1] - w[0],
                expected: step,
            });
        }
    }
    Ok(step)
}

/// `NonFiniteSample` for the first value of `values` that is not finite.
pub(super) fn check_finite(values: &[f64], component: usize) -> Result<(), AnalysisError> {
    match values.iter().position(|v| !v.is_finite()) {
        Some(index) => Err(AnalysisError::NonFiniteSample {
            index,
            component,
            value: values[index],
        }),
        None => Ok(()),
    }
}

pub(super) fn same_length(
    first: (&'static str, &[f64]),
    second: (&'static str, &[f64]),
) -> Result<(), AnalysisError> {
    if first.1.len() == second.1.len() {
        return Ok(());
    }
    Err(AnalysisError::LengthMismatch {
        first: first.0,
        first_len: first.1.len(),
        second: second.0,
        second_len: second.1.len(),
    })
}

/// The full spectrum of `x + i y` at the step `step` (checked by the callers).
pub(super) fn whirl_spectrum(x: &[f64], y: &[f64], step: f64, window: Window) -> FullSpectrum {
    let n = x.len();
    let mut buffer: Vec<Complex<f64>> = x
        .iter()
        .zip(y)
        .enumerate()
        .map(|(i, (&re, &im))| Complex::new(re, im) * window.weight(i, n))
        .collect();
    FftPlanner::new().plan_fft_forward(n).process(&mut buffer);
    let scale = 1.0 / (n as f64 * window.coherent_gain());
    let half = n.div_ceil(2);
    let forward = (0..half).map(|k| buffer[k].norm() * scale).collect();
    let backward = (0..half)
        .map(|k| {
            if k == 0 {
                0.0
            } else {
                buffer[n - k].norm() * scale
            }
        })
        .collect();
    FullSpectrum {
        frequency: (0..half).map(|k| k as f64 / (n as f64 * step)).collect(),
        forward,
        backward,
    }
}

/// The full (whirl) spectrum of the orbit $x + iy$ sampled at the equally spaced `times`.
///
/// # Errors
/// [`AnalysisError::TooFewSamples`] for fewer than 4 samples, `LengthMismatch`,
/// `NonFiniteSample`, `TimesNotIncreasing`, or [`AnalysisError::NonUniformSamples`] for
/// steps that differ from the mean by more than $10^{-6}$ of it.
pub fn full_spectrum(
    times: &[f64],
    x: &[f64],
    y: &[f64],
    window: Window,
) -> Result<FullSpectrum, AnalysisError> {
    same_length(("times", times), ("x", x))?;
    same_length(("x", x), ("y", y))?;
    if x.len() < MIN_SAMPLES {
        return Err(AnalysisError::TooFewSamples {
            got: x.len(),
            needed: MIN_SAMPLES,
            why: "a spectrum needs a record of several samples",
        });
    }
    let step = uniform_step(times)?;
    check_finite(x, 0)?;
    check_finite(y, 1)?;
    Ok(whirl_spectrum(x, y, step, window))
}

/// The one-sided amplitude spectrum of the real record `x` at the equally spaced `times`.
///
/// # Errors
/// As [`full_spectrum`].
pub fn amplitude_spectrum(
    times: &[f64],
    x: &[f64],
    window: Window,
) -> Result<Spectrum, AnalysisError> {
    let zeros = vec![0.0; x.len()];
    let full = full_spectrum(times, x, &zeros, window)?;
    let amplitude = full
        .forward
        .iter()
        .zip(&full.backward)
        .map(|(f, b)| f + b)
        .collect();
    Ok(Spectrum {
        frequency: full.frequency,
        amplitude,
    })
}
