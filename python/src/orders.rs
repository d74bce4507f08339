//! Spectra and order tracking of any record (the crate's `analysis::order`): the whirl
//! spectrum of an orbit, the amplitude spectrum of a signal, the orders of a run-up and its
//! waterfall.

use jeffcott::analysis::{
    amplitude_spectrum as amplitude, full_spectrum as whirl, order_track as track, AngleSamples,
    OrderTrackOptions, Window,
};
use numpy::{AllowTypeChange, PyArray1, PyArray2, PyArrayLike1};
use pyo3::prelude::*;

use crate::arrays::{array, table};
use crate::errors::value_error;

/// A 1-D array-like of numbers, as float64.
type Column<'py> = PyArrayLike1<'py, f64, AllowTypeChange>;

/// Two arrays of the same length (the bins and their values).
type Pair = (Py<PyArray1<f64>>, Py<PyArray1<f64>>);

fn window(name: &str) -> PyResult<Window> {
    match name {
        "hann" => Ok(Window::Hann),
        "rectangular" => Ok(Window::Rectangular),
        other => Err(value_error(format!(
            "window '{other}' is not hann or rectangular"
        ))),
    }
}

fn values(a: &Column<'_>) -> Vec<f64> {
    a.as_array().iter().copied().collect()
}

/// A full (whirl) spectrum: the radii of the forward and backward circular whirls at each
/// frequency.
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct WhirlSpectrum {
    /// The bins' frequencies k / (N dt), 0 <= k < N/2 (cycles per unit of ``t``: Hz for s),
    /// shape (B,).
    pub frequency: Py<PyArray1<f64>>,
    /// The forward whirl's radius at each bin (the units of ``x``, ``y``), shape (B,).
    pub forward: Py<PyArray1<f64>>,
    /// The backward whirl's radius at each bin, shape (B,).
    pub backward: Py<PyArray1<f64>>,
}

/// The full (whirl) spectrum of the orbit x + i y sampled at the equally spaced times ``t``
/// (to 1e-6 of the step): for each frequency f the radii of the forward (with the rotation,
/// x + i y = r e^{2 pi i f t}) and backward circular whirls, corrected for the window's
/// coherent gain (``window`` "hann" or "rectangular"). ``ValueError`` for fewer than 4
/// samples, unequal lengths, non-finite values or unequal steps.
#[pyfunction]
#[pyo3(signature = (t, x, y, *, window="hann"))]
pub fn full_spectrum(
    py: Python<'_>,
    t: Column<'_>,
    x: Column<'_>,
    y: Column<'_>,
    window: &str,
) -> PyResult<WhirlSpectrum> {
    let s =
        whirl(&values(&t), &values(&x), &values(&y), self::window(window)?).map_err(value_error)?;
    Ok(WhirlSpectrum {
        frequency: array(py, s.frequency),
        forward: array(py, s.forward),
        backward: array(py, s.backward),
    })
}

/// The one-sided amplitude spectrum of the real record ``x`` at the equally spaced times
/// ``t``: ``(frequency, amplitude)``, the amplitude A of A cos(2 pi f t + psi) at each bin.
/// Errors as ``full_spectrum``.
#[pyfunction]
#[pyo3(signature = (t, x, *, window="hann"))]
pub fn amplitude_spectrum(
    py: Python<'_>,
    t: Column<'_>,
    x: Column<'_>,
    window: &str,
) -> PyResult<Pair> {
    let s = amplitude(&values(&t), &values(&x), self::window(window)?).map_err(value_error)?;
    Ok((array(py, s.frequency), array(py, s.amplitude)))
}

/// The orders of a record through a speed change, one row a window of revolutions.
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct OrderTrack {
    /// The tracked orders, shape (K,).
    pub orders: Py<PyArray1<f64>>,
    /// The time of each window's centre, shape (W,).
    pub time: Py<PyArray1<f64>>,
    /// The speed at each window's centre (rad per unit of ``t``), shape (W,).
    pub speed: Py<PyArray1<f64>>,
    /// The forward whirl radius of each order in each window, shape (W, K).
    pub forward: Py<PyArray2<f64>>,
    /// The backward whirl radius, shape (W, K).
    pub backward: Py<PyArray2<f64>>,
    /// The waterfall's order axis: the bins k / revolutions_per_window, shape (B,).
    pub waterfall_orders: Py<PyArray1<f64>>,
    /// Each window's forward whirl spectrum in orders, shape (W, B).
    pub waterfall_forward: Py<PyArray2<f64>>,
    /// Each window's backward whirl spectrum in orders, shape (W, B).
    pub waterfall_backward: Py<PyArray2<f64>>,
}

/// Order tracking of the orbit x + i y recorded at the times ``t`` with the shaft's phase
/// ``phase`` (rad, increasing: e.g. an ``FeRun``'s ``phase``): the record is resampled at
/// ``per_revolution`` equal steps of the phase (6-point Lagrange interpolation in the phase),
/// cut into windows of ``revolutions_per_window`` revolutions every ``hop_revolutions``, and
/// each window's whirl spectrum read at the ``orders`` (multiples of
/// 1/revolutions_per_window, below per_revolution/2). ``ValueError`` for bad input or a
/// record too coarse for the highest order (its resampling error bound above
/// ``max_interpolation_error`` of the amplitude: record more samples a revolution).
#[pyfunction]
#[pyo3(
    signature = (t, phase, x, y, *, orders=vec![0.5, 1.0, 1.5, 2.0, 3.0], per_revolution=32, revolutions_per_window=8, hop_revolutions=2, window="hann", max_interpolation_error=0.01),
    text_signature = "(t, phase, x, y, *, orders=[0.5, 1.0, 1.5, 2.0, 3.0], per_revolution=32, revolutions_per_window=8, hop_revolutions=2, window='hann', max_interpolation_error=0.01)"
)]
#[allow(clippy::too_many_arguments)] // Python keywords
pub fn order_track(
    py: Python<'_>,
    t: Column<'_>,
    phase: Column<'_>,
    x: Column<'_>,
    y: Column<'_>,
    orders: Vec<f64>,
    per_revolution: usize,
    revolutions_per_window: usize,
    hop_revolutions: usize,
    window: &str,
    max_interpolation_error: f64,
) -> PyResult<OrderTrack> {
    let (t, phase, x, y) = (values(&t), values(&phase), values(&x), values(&y));
    let options = OrderTrackOptions {
        orders: orders.clone(),
        revolutions_per_window,
        hop_revolutions,
        window: self::window(window)?,
        max_interpolation_error,
    };
    let rows = py
        .detach(|| {
            let samples = AngleSamples::resample(&t, &phase, &x, &y, per_revolution)?;
            track(&samples, &options)
        })
        .map_err(value_error)?;
    let k = orders.len();
    let bins = rows.first().map_or(0, |r| r.spectrum.frequency.len());
    let axis = rows
        .first()
        .map_or(Vec::new(), |r| r.spectrum.frequency.clone());
    Ok(OrderTrack {
        orders: array(py, orders),
        time: array(py, rows.iter().map(|r| r.time)),
        speed: array(py, rows.iter().map(|r| r.speed)),
        forward: table(py, rows.iter().map(|r| r.forward.clone()), k)?,
        backward: table(py, rows.iter().map(|r| r.backward.clone()), k)?,
        waterfall_orders: array(py, axis),
        waterfall_forward: table(py, rows.iter().map(|r| r.spectrum.forward.clone()), bins)?,
        waterfall_backward: table(py, rows.iter().map(|r| r.spectrum.backward.clone()), bins)?,
    })
}
