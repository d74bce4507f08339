//! The run-up: the paper's rotor at a speed ramped at a constant rate (the crate's
//! ``rotor::SpeedProfile::ramp`` and ``rotor::ProfiledJeffcott``) or driven by a motor
//! (``rotor::DrivenJeffcott``), on the ring or off it.

use jeffcott::hybrid::{SimOptions, SimStats, Trajectory};
use jeffcott::nalgebra::allocator::Allocator;
use jeffcott::nalgebra::{DefaultAllocator, Dim, OVector, SVector, U6, U8};
use jeffcott::params::Params;
use jeffcott::rotor::{
    DrivenJeffcott, ProfiledJeffcott, RingedRotor, RubbingRotor, SmoothRotor, SpeedProfile, ETA,
    PHASE,
};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::array;
use crate::errors::value_error;
use crate::motor::Motor;
use crate::options::{coulomb, sim_options};
use crate::paper::{dense_output, start_state, states};
use crate::params::PyParams;
use crate::runs::{self, stats_dict, Output};

/// Dense samples of a run-up at t_i = i dt (non-dimensional time tau), and its events.
#[pyclass(name = "RunUp", module = "jeffcott", frozen, get_all)]
pub struct RunUp {
    /// Sample times tau (in 1/omega_n), float64, shape (N,).
    pub tau: Py<PyArray1<f64>>,
    /// The speed ratio eta(tau) = Omega / omega_n at the samples, float64, shape (N,).
    pub eta: Py<PyArray1<f64>>,
    /// The forcing phase phi(tau) (rad) at the samples: phi0 + the integral of eta (a drive's:
    /// its state), float64, shape (N,).
    pub phase: Py<PyArray1<f64>>,
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
    /// The ramp's duration (eta_to - eta_from) / rate, in tau (NaN on a drive).
    pub ramp_time: f64,
    /// The work done (as ``StrobeRun.stats``).
    pub stats: Py<PyDict>,
}

/// A quantity at a sample: its time and state.
type AtSample<'a, D> = dyn Fn(f64, &OVector<f64, D>) -> f64 + 'a;

/// The run-up's result from its trajectory; `speed` and `phase` at a sample (the profile's,
/// or the driven rotor's state).
fn run_up_of<D: Dim>(
    py: Python<'_>,
    (speed, phase): (&AtSample<'_, D>, &AtSample<'_, D>),
    ramp_time: f64,
    traj: &Trajectory<D>,
    stats: &SimStats,
) -> PyResult<RunUp>
where
    DefaultAllocator: Allocator<D>,
{
    let s = &traj.samples;
    let column = |c: usize| array(py, s.iter().map(|p| p.y[c]));
    let e = &traj.events;
    Ok(RunUp {
        tau: array(py, s.iter().map(|p| p.t)),
        eta: array(py, s.iter().map(|p| speed(p.t, &p.y))),
        phase: array(py, s.iter().map(|p| phase(p.t, &p.y))),
        x: column(0),
        y: column(1),
        states: states(py, s.iter().map(|p| &p.y))?,
        regimes: array(py, s.iter().map(|p| p.label)),
        event_t: array(py, e.iter().map(|v| v.t)),
        event_kind: e.iter().map(|v| v.kind.to_string()).collect(),
        ramp_time,
        stats: stats_dict(py, stats)?.unbind(),
    })
}

/// Run-up (or run-down) of the paper's rotor, prescribed or driven.
///
/// Prescribed (``eta_to`` and ``rate``): the speed ratio eta goes from ``eta_from`` to
/// ``eta_to`` at the constant rate ``rate`` = d eta / d tau (> 0 up, < 0 down), then holds;
/// the out-of-balance force includes the tangential term of the accelerating mass
/// (beta eta'), the phase is phi0 + the integral of eta (``params.eta`` is not used).
///
/// Driven (``motor`` and ``inertia`` instead; the non-ideal drive, ``rotor::DrivenJeffcott``):
/// j eta' = t(eta) + beta (x'' sin phi - y'' cos phi) (the out-of-balance's reaction torque;
/// with ``friction``, minus the rub torque), phi' = eta, from eta = ``eta_from`` and phi =
/// phi0; ``motor`` a ``jeffcott.Motor`` in the paper's units (torque over k_r gap^2 against
/// eta), ``inertia`` j = J_p / (M gap^2) (above beta^2); ``t_end`` required. The reference
/// speed (``params.eta`` is replaced by it: the forcing period of the step bound and the
/// chattering window) is the larger of ``eta_from`` and the motor's ``no_load_speed``.
///
/// Samples at tau_i = i dt up to ``t_end`` (default: the ramp's end), from ``state0``
/// (default rest; [x, y, x', y', x_s, y_s]) at tau = 0. ``ring=False`` puts the ring out of
/// reach (the linear rotor). ``friction`` > 0: Coulomb friction between the ring and a shaft of
/// radius ``shaft_radius`` (in gaps; required then) whose surface moves at eta times it
/// (``rotor::RubbingRotor``, docs/friction.md); ``regimes`` 6, 7, 8 are slipping forward,
/// backward and rolling.
///
/// Units: tau in 1/omega_n, rate in omega_n^2 (d eta per unit tau), lengths in gaps.
/// Options, Ctrl-C and errors as ``simulate``; ``ValueError`` for a bad profile, drive or
/// friction; ``SimulationError``'s ``partial`` is a ``RunUp``.
#[pyfunction]
#[pyo3(signature = (params, eta_from, eta_to=None, rate=None, *, motor=None, inertia=None, t_end=None, dt=0.05, ring=true, state0=None, rtol=None, atol=None, method=None, friction=0.0, shaft_radius=None))]
#[allow(clippy::too_many_arguments)] // Python keywords
pub fn run_up(
    py: Python<'_>,
    params: PyRef<'_, PyParams>,
    eta_from: f64,
    eta_to: Option<f64>,
    rate: Option<f64>,
    motor: Option<PyRef<'_, Motor>>,
    inertia: Option<f64>,
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
    let opts = sim_options(rtol, atol, method)?;
    let friction = coulomb(friction, shaft_radius, "in gaps")?;
    let plan = Plan {
        y0: start_state(state0)?,
        opts,
        dt,
        t_end,
        ring,
        friction,
    };
    match ((eta_to, rate), (motor, inertia)) {
        ((Some(eta_to), Some(rate)), (None, None)) => {
            let profile = SpeedProfile::ramp(eta_from, eta_to, rate).map_err(value_error)?;
            plan.ramp(py, params.checked()?, profile)
        }
        ((None, None), (Some(motor), Some(inertia))) => {
            plan.drive(py, params.checked()?, (&motor, inertia), eta_from)
        }
        ((None, None), _) => Err(value_error(
            "a drive needs motor and inertia (or give eta_to and rate for a ramp)",
        )),
        ((Some(_), Some(_)), _) => Err(value_error(
            "give eta_to and rate (a ramp) or motor and inertia (a drive), not both",
        )),
        _ => Err(value_error("eta_to and rate go together")),
    }
}

/// A run-up's plan besides its speed law.
struct Plan {
    y0: SVector<f64, 6>,
    opts: SimOptions,
    dt: f64,
    t_end: Option<f64>,
    ring: bool,
    /// Coulomb friction at the ring: (mu, the shaft's radius in gaps).
    friction: Option<(f64, f64)>,
}

impl Plan {
    /// The ramp `profile` of the rotor of `params`.
    fn ramp(self, py: Python<'_>, params: Params, profile: SpeedProfile) -> PyResult<RunUp> {
        let rotor = ProfiledJeffcott::new(params, profile.clone()).map_err(value_error)?;
        let ringed = if self.ring {
            rotor.on_ring()
        } else {
            rotor.off_ring()
        };
        let model = ringed.map_err(value_error)?;
        let output = dense_output(self.t_end.unwrap_or(profile.ramp_time()), self.dt)?;
        let speed = |t: f64, _: &SVector<f64, 6>| profile.eta(t);
        let phase = |t: f64, _: &SVector<f64, 6>| params.phi0 + profile.phase(t);
        let result = |py: Python<'_>, traj: &Trajectory<U6>, stats: &SimStats| {
            run_up_of(py, (&speed, &phase), profile.ramp_time(), traj, stats)
        };
        let y0 = self.y0;
        self.go(py, model, y0, output, result)
    }

    /// The rotor of `params` on the drive `motor` through the inertia `j` from the speed
    /// `eta_from`; the reference speed the larger of that and the motor's no-load speed.
    fn drive(
        self,
        py: Python<'_>,
        params: Params,
        (motor, j): (&Motor, f64),
        eta_from: f64,
    ) -> PyResult<RunUp> {
        let t_end = self
            .t_end
            .ok_or_else(|| value_error("a drive needs t_end"))?;
        let params = Params {
            eta: motor.no_load_speed().max(eta_from),
            ..params
        };
        let rotor = DrivenJeffcott::new(params, j, motor.torque.clone()).map_err(value_error)?;
        let ringed = if self.ring {
            rotor.on_ring()
        } else {
            rotor.off_ring()
        };
        let model = ringed.map_err(value_error)?;
        // The rotor's and the ring's six as given (the start places the ring, as the ramp's),
        // then the speed and the phase phi0.
        let y = &self.y0;
        let mut start = rotor.state_at([y[0], y[1]], [y[2], y[3]], eta_from);
        start
            .fixed_rows_mut::<2>(4)
            .copy_from(&y.fixed_rows::<2>(4));
        let output = dense_output(t_end, self.dt)?;
        let speed = |_: f64, y: &SVector<f64, 8>| y[ETA];
        let phase = |_: f64, y: &SVector<f64, 8>| y[PHASE];
        let result = |py: Python<'_>, traj: &Trajectory<U8>, stats: &SimStats| {
            run_up_of(py, (&speed, &phase), f64::NAN, traj, stats)
        };
        self.go(py, model, start, output, result)
    }

    /// Runs `model` from `y0` (with friction at the ring if asked for) into `result`.
    fn go<R, D, F>(
        self,
        py: Python<'_>,
        model: RingedRotor<R>,
        y0: OVector<f64, D>,
        output: Output,
        result: F,
    ) -> PyResult<RunUp>
    where
        R: SmoothRotor<Dim = D> + Sync,
        D: Dim,
        DefaultAllocator: Allocator<D>,
        OVector<f64, D>: Send + Sync,
        F: Fn(Python<'_>, &Trajectory<D>, &SimStats) -> PyResult<RunUp>,
    {
        match self.friction {
            None => runs::run_into(py, &model, y0, output, &self.opts, result),
            Some((mu, radius)) => {
                let model = RubbingRotor::new(model, mu, radius).map_err(value_error)?;
                runs::run_into(py, &model, y0, output, &self.opts, result)
            }
        }
    }
}
