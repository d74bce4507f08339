//! A motor's torque characteristic for the non-ideal drive (the crate's
//! ``rotor::MotorTorque``), in SI units: N m against rad/s.

use jeffcott::rotor::MotorTorque;
use numpy::{AllowTypeChange, PyArrayLike1};
use pyo3::prelude::*;

use crate::errors::value_error;

/// A 1-D array-like of numbers, as float64.
type Column<'py> = PyArrayLike1<'py, f64, AllowTypeChange>;

/// A motor's torque T(Omega) (N m) against the shaft's speed Omega (rad/s), for the non-ideal
/// drive of ``fe_run_up(..., motor=...)``: ``Motor.linear`` (a DC motor) or ``Motor.table``
/// (a measured characteristic).
#[pyclass(module = "jeffcott", frozen)]
#[derive(Clone)]
pub struct Motor {
    pub(crate) torque: MotorTorque,
    /// Where the torque first falls to zero from above (rad/s), or the table's last speed.
    no_load: f64,
    description: String,
}

#[pymethods]
impl Motor {
    /// The DC motor T = stall_torque (1 - Omega / no_load_speed): ``stall_torque`` in N m (any
    /// sign, finite), ``no_load_speed`` in rad/s (finite, > 0).
    #[staticmethod]
    fn linear(stall_torque: f64, no_load_speed: f64) -> PyResult<Self> {
        let torque = MotorTorque::linear(stall_torque, no_load_speed).map_err(value_error)?;
        Ok(Self {
            torque,
            no_load: no_load_speed,
            description: format!(
                "Motor.linear(stall_torque={stall_torque}, no_load_speed={no_load_speed})"
            ),
        })
    }

    /// The characteristic through the points (``speeds[i]`` rad/s, ``torques[i]`` N m),
    /// linear between them and held at the end values beyond them: at least two points,
    /// speeds increasing, every value finite.
    #[staticmethod]
    fn table(speeds: Column<'_>, torques: Column<'_>) -> PyResult<Self> {
        let (w, t) = (speeds.as_array().to_vec(), torques.as_array().to_vec());
        if w.len() != t.len() || w.len() < 2 {
            return Err(value_error(format!(
                "speeds and torques must be as long as each other, with at least 2 points, \
                 got {} and {}",
                w.len(),
                t.len()
            )));
        }
        if let Some(i) = (0..w.len()).find(|&i| !(w[i].is_finite() && t[i].is_finite())) {
            return Err(value_error(format!(
                "speeds[{i}] = {} and torques[{i}] = {} must be finite",
                w[i], t[i]
            )));
        }
        if let Some(i) = (1..w.len()).find(|&i| w[i] <= w[i - 1]) {
            return Err(value_error(format!(
                "speeds must increase: speeds[{i}] = {} after {}",
                w[i],
                w[i - 1]
            )));
        }
        let no_load = first_zero(&w, &t);
        let description = format!(
            "Motor.table({} points, {} to {} rad/s)",
            w.len(),
            w[0],
            w[w.len() - 1]
        );
        let torque = MotorTorque::user(move |speed| interpolate(&w, &t, speed));
        Ok(Self {
            torque,
            no_load,
            description,
        })
    }

    /// The torque (N m) at ``speed`` (rad/s).
    fn torque(&self, speed: f64) -> f64 {
        self.torque.torque(speed)
    }

    /// The speed (rad/s) where the torque first falls to zero from above (a linear motor's
    /// no-load speed); a table whose torque never does: its last speed.
    #[getter]
    pub fn no_load_speed(&self) -> f64 {
        self.no_load
    }

    fn __repr__(&self) -> String {
        self.description.clone()
    }
}

/// The table's value at `x`: linear between the points, held beyond them.
fn interpolate(xs: &[f64], ys: &[f64], x: f64) -> f64 {
    let last = xs.len() - 1;
    if x <= xs[0] {
        return ys[0];
    }
    if x >= xs[last] {
        return ys[last];
    }
    let i = xs.partition_point(|&v| v <= x).clamp(1, last);
    let s = (x - xs[i - 1]) / (xs[i] - xs[i - 1]);
    ys[i - 1] + s * (ys[i] - ys[i - 1])
}

/// Where the table's torque first falls from > 0 to <= 0 (linear between the points), or its
/// last speed.
fn first_zero(w: &[f64], t: &[f64]) -> f64 {
    for i in 1..w.len() {
        if t[i - 1] > 0.0 && t[i] <= 0.0 {
            return w[i - 1] + (w[i] - w[i - 1]) * t[i - 1] / (t[i - 1] - t[i]);
        }
    }
    w[w.len() - 1]
}
