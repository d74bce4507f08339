//! The revolutions of a finite-element rotor's run: per turn of the shaft, its speed, the ring
//! node's located peak radius, the time in contact, and the forward 1x whirl.

use jeffcott::analysis::per_revolution;
use jeffcott::hybrid::Trajectory;
use jeffcott::nalgebra::{Complex, DVector, Dyn};
use jeffcott::rotor::SmoothRotor;
use numpy::PyArray1;
use pyo3::prelude::*;

use crate::arrays::array;
use crate::errors::value_error;
use crate::fe_run::{RunFacts, RunModel};

/// The revolutions of a run, one entry each: from one revolution of the forcing phase to the
/// next (the first starts at t = 0).
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct Revolutions {
    /// When each starts (s).
    pub start: Py<PyArray1<f64>>,
    /// When each ends (s).
    pub end: Py<PyArray1<f64>>,
    /// Its mean speed 2 pi / (end - start) (rad/s).
    pub speed: Py<PyArray1<f64>>,
    /// The ring node's largest distance from the ring's rest centre in it (m), located on the
    /// cubic Hermite interpolant of position and velocity through the samples, the revolution
    /// starts and the events (the crate's ``analysis::per_revolution``).
    pub peak_radius: Py<PyArray1<f64>>,
    /// The time in contact in it (s).
    pub contact_time: Py<PyArray1<f64>>,
    /// The radius of the ring node's forward 1x whirl in it (m): |c| of
    /// c = (1/2 pi) of the integral of (x + i y) e^{-i phase} d phase over the turn (the
    /// trapezoidal rule in the phase, on the samples and the turn's ends).
    pub amplitude_1x: Py<PyArray1<f64>>,
    /// Its phase arg c (rad): x + i y ~ |c| e^{i (phase + arg c)}, against the shaft's angle
    /// ``FeRun.phase``.
    pub phase_1x: Py<PyArray1<f64>>,
}

/// The revolutions from the strobes (one a revolution, revolution i from strobe i to i + 1).
pub fn revolutions<M: RunModel>(
    py: Python<'_>,
    facts: &RunFacts<'_, M>,
    traj: &Trajectory<Dyn>,
) -> PyResult<Revolutions> {
    let model = facts.model;
    let revs = per_revolution(traj, 1, |y| model.smooth().station(y)).map_err(value_error)?;
    let whirl: Vec<Complex<f64>> = traj
        .strobe
        .windows(2)
        .take(revs.len())
        .map(|w| first_order(facts, traj, (w[0].t, w[1].t), (&w[0].y, &w[1].y)))
        .collect();
    Ok(Revolutions {
        start: array(py, revs.iter().map(|r| r.t_start)),
        end: array(py, revs.iter().map(|r| r.t_end)),
        speed: array(py, revs.iter().map(|r| r.speed)),
        peak_radius: array(py, revs.iter().map(|r| r.max_radius)),
        contact_time: array(py, revs.iter().map(|r| r.contact_time)),
        amplitude_1x: array(py, whirl.iter().map(|c| c.norm())),
        phase_1x: array(py, whirl.iter().map(|c| c.arg())),
    })
}

/// The forward 1x whirl coefficient of the ring node over the turn from `a` to `b` (the
/// states `ya`, `yb` there): the trapezoidal rule in the phase on the ends and the samples
/// between.
fn first_order<M: RunModel>(
    facts: &RunFacts<'_, M>,
    traj: &Trajectory<Dyn>,
    (a, b): (f64, f64),
    (ya, yb): (&DVector<f64>, &DVector<f64>),
) -> Complex<f64> {
    let s = &traj.samples;
    let inner = &s[s.partition_point(|p| p.t <= a)..s.partition_point(|p| p.t < b)];
    let term = |t: f64, y: &DVector<f64>| {
        let [x, yy] = (facts.displacement)(y);
        let phase = (facts.phase)(t, y);
        (
            phase,
            Complex::new(x, yy) * Complex::from_polar(1.0, -phase),
        )
    };
    let knots = std::iter::once(term(a, ya))
        .chain(inner.iter().map(|p| term(p.t, &p.y)))
        .chain(std::iter::once(term(b, yb)));
    let mut sum = Complex::new(0.0, 0.0);
    let mut last: Option<(f64, Complex<f64>)> = None;
    for (phase, f) in knots {
        if let Some((p0, f0)) = last {
            sum += (f0 + f) * (0.5 * (phase - p0));
        }
        last = Some((phase, f));
    }
    sum / std::f64::consts::TAU
}
