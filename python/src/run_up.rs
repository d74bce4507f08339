//! The run-up: the paper's rotor at a speed ramped at a constant rate (the crate's
//! ``rotor::SpeedProfile::ramp`` and ``rotor::ProfiledJeffcott``), on the ring or off it.

use jeffcott::hybrid::{SimStats, Trajectory};
use jeffcott::nalgebra::U6;
use jeffcott::rotor::{ProfiledJeffcott, RubbingRotor, SpeedProfile};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::array;
use crate::errors::value_error;
use crate::options::sim_options;
use crate::paper::{dense_output, start_state, states};
use crate::params::PyParams;
use crate::runs::{self, stats_dict};

/// Dense samples of a run-up at t_i = i dt (non-dimensional time tau), and its events.
#[pyclass(name = "RunUp", module = "jeffcott", frozen, get_all)]
pub struct RunUp {
    /// Sample times tau (in 1/omega_n), float64, shape (N,).
    pub tau: Py<PyArray1<f64>>,
    /// The speed ratio eta(tau) = Omega / omega_n at the samples, float64, shape (N,).
    pub eta: Py<PyArray1<f64>>,
    /// The rotor's x (gaps), float64, shape (N,).
    pub x: Py<PyArray1<f64>>,
    /// The rotor's y (gaps), float64, shape (N,).
    pub y: Py<PyArray1<f64>>,
    /// The states [x, y, x', y', x_s, y_s], float64, shape (N, 6).
    pub states: Py<PyArray2<f64>>,
    /// Regimes 1..=5 at the samples (with friction 6, 7, 8: slipping forward, backward,
    /// rolling), uint8, shape (N,).
    pub regimes: Py<PyArray1<u8>>,
    /// Event times tau, float64, shape (E,).
    pub event_t: Py<PyArray1<f64>>,
    /// Event kinds (onset, loss, ...), a list of E str.
    pub event_kind: Vec<String>,
    /// The ramp's duration (eta_to - eta_from) / rate, in tau.
    pub ramp_time: f64,
    /// The work done (as ``StrobeRun.stats``).
    pub stats: Py<PyDict>,
}

fn run_up_of(
    py: Python<'_>,
    profile: &SpeedProfile,
    traj: &Trajectory<U6>,
    stats: &SimStats,
) -> PyResult<RunUp> {
    let s = &traj.samples;
    let column = |c: usize| array(py, s.iter().map(|p| p.y[c]));
    let e = &traj.events;
    Ok(RunUp {
        tau: array(py, s.iter().map(|p| p.t)),
        eta: array(py, s.iter().map(|p| profile.eta(p.t))),
        x: column(0),
        y: column(1),
        states: states(py, s.iter().map(|p| &p.y))?,
        regimes: array(py, s.iter().map(|p| p.label)),
        event_t: array(py, e.iter().map(|v| v.t)),
        event_kind: e.iter().map(|v| v.kind.to_string()).collect(),
        ramp_time: profile.ramp_time(),
        stats: stats_dict(py, stats)?.unbind(),
    })
}

/// Run-up (or run-down) of the paper's rotor: the speed ratio eta goes from ``eta_from`` to
/// ``eta_to`` at the constant rate ``rate`` = d eta / d tau (> 0 up, < 0 down), then holds;
/// the out-of-balance force includes the tangential term of the accelerating mass
/// (beta eta'), the phase is phi0 + the integral of eta (``params.eta`` is not used).
/// Samples at tau_i = i dt up to ``t_end`` (default: the ramp's end), from ``state0``
/// (default rest) at tau = 0. ``ring=False`` puts the ring out of reach (the linear rotor).
/// ``friction`` > 0: Coulomb friction between the ring and a shaft of radius ``shaft_radius``
/// (in gaps; required then) whose surface moves at eta(tau) times it (``rotor::RubbingRotor``,
/// docs/friction.md); ``regimes`` 6, 7, 8 are slipping forward, backward and rolling.
///
/// Units: tau in 1/omega_n, rate in omega_n^2 (d eta per unit tau), lengths in gaps.
/// Options, Ctrl-C and errors as ``simulate``;
/// ``ValueError`` for a bad profile or friction; ``SimulationError``'s ``partial`` is a ``RunUp``.
#[pyfunction]
#[pyo3(signature = (params, eta_from, eta_to, rate, *, t_end=None, dt=0.05, ring=true, state0=None, rtol=None, atol=None, method=None, friction=0.0, shaft_radius=None))]
#[allow(clippy::too_many_arguments)] // Python keywords
pub fn run_up(
    py: Python<'_>,
    params: PyRef<'_, PyParams>,
    eta_from: f64,
    eta_to: f64,
    rate: f64,
    t_end: Option<f64>,
    dt: f64,
    ring: bool,
    state0: Option<Vec<f64>>,
    rtol: Option<f64>,
    atol: Option<f64>,
    method: Option<&str>,
    friction: f64,
    shaft_radius: Option<f64>,
) -> PyResult<RunUp> {
    let profile = SpeedProfile::ramp(eta_from, eta_to, rate).map_err(value_error)?;
    let rotor = ProfiledJeffcott::new(params.checked()?, profile.clone()).map_err(value_error)?;
    let model = if ring {
        rotor.on_ring()
    } else {
        rotor.off_ring()
    }
    .map_err(value_error)?;
    let y0 = start_state(state0)?;
    let opts = sim_options(rtol, atol, method)?;
    let t_end = t_end.unwrap_or(profile.ramp_time());
    let output = dense_output(t_end, dt)?;
    let result = |py: Python<'_>, traj: &Trajectory<U6>, stats: &SimStats| {
        run_up_of(py, &profile, traj, stats)
    };
    if friction == 0.0 {
        return runs::run_into(py, &model, y0, output, &opts, result);
    }
    let radius = shaft_radius.ok_or_else(|| {
        value_error("friction needs shaft_radius: the shaft's radius at the ring, in gaps")
    })?;
    let model = RubbingRotor::new(model, friction, radius).map_err(value_error)?;
    runs::run_into(py, &model, y0, output, &opts, result)
}
