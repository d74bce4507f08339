//! What a run of a finite-element rotor on the ring gives back (`fe_transient`, `fe_run_up`):
//! the ring node's motion, the ring, the contact force at the samples; each contact episode;
//! each revolution's peak.

use jeffcott::hybrid::{EventRecord, ModelError, RotorModel, SimStats, Trajectory};
use jeffcott::nalgebra::{DVector, Dyn, Vector2};
use jeffcott::rotor::{LinearClosedForm, RingedRotor, RotorError, RubbingRotor, SmoothRotor};
use numpy::{PyArray1, PyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::{array, table};
use crate::errors::value_error;
use crate::fe::{Margin, Probes, Reduction};
use crate::revolutions::{revolutions, Revolutions};
use crate::runs::stats_dict;

/// The contact episodes of a run, one entry each, in time order.
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct ContactEpisodes {
    /// When each contact starts (s): its onset, or the run's start if it starts in contact.
    pub start: Py<PyArray1<f64>>,
    /// When each ends (s): its loss; NaN for a contact that lasts to the run's end.
    pub end: Py<PyArray1<f64>>,
    /// ``end - start`` (s); NaN where ``end`` is.
    pub duration: Py<PyArray1<f64>>,
    /// The largest normal force (N) at the samples and at the contact's onset and loss.
    pub peak_force: Py<PyArray1<f64>>,
    /// The normal force's integral over the contact (N s), by the trapezoidal rule on the
    /// samples and the onset and loss.
    pub impulse: Py<PyArray1<f64>>,
}

/// A run of a finite-element rotor on the ring: at uniform samples the ring node's
/// displacement and velocity, the ring and its force on the rotor; the contact events and
/// episodes; the revolutions.
#[pyclass(module = "jeffcott", frozen, get_all)]
pub struct FeRun {
    /// Sample times t_i = i dt (s), float64, shape (N,).
    pub t: Py<PyArray1<f64>>,
    /// The speed at the samples (rad/s), shape (N,).
    pub speed: Py<PyArray1<f64>>,
    /// The shaft's angle at the samples, the integral of the speed from t = 0 (rad), shape
    /// (N,): the phase ``order_track`` takes.
    pub phase: Py<PyArray1<f64>>,
    /// The ring node's x from its undeflected position (m), shape (N,).
    pub x: Py<PyArray1<f64>>,
    /// The ring node's y (m), shape (N,).
    pub y: Py<PyArray1<f64>>,
    /// The ring node's x velocity (m/s), shape (N,).
    pub vx: Py<PyArray1<f64>>,
    /// The ring node's y velocity (m/s), shape (N,).
    pub vy: Py<PyArray1<f64>>,
    /// The ring centre's x from its rest position (m), shape (N,).
    pub ring_x: Py<PyArray1<f64>>,
    /// The ring centre's y (m), shape (N,).
    pub ring_y: Py<PyArray1<f64>>,
    /// The ring's force on the rotor, x (N), shape (N,); zero out of contact.
    pub force_x: Py<PyArray1<f64>>,
    /// The ring's force on the rotor, y (N), shape (N,).
    pub force_y: Py<PyArray1<f64>>,
    /// The normal contact force (N, >= 0 in contact), pressing the rotor back towards the
    /// ring's centre, shape (N,).
    pub normal_force: Py<PyArray1<f64>>,
    /// The friction force (N): the ring's force on the rotor along the tangent (the contact
    /// normal turned by +90 degrees, counter-clockwise), shape (N,); zero out of contact, and
    /// without friction up to the ring dampers' tangential part.
    pub friction_force: Py<PyArray1<f64>>,
    /// The ring node's whirl rate about its undeflected position (rad/s): (x vy - y vx) /
    /// (x^2 + y^2), > 0 forward (with the spin), < 0 backward; NaN where x = y = 0, shape (N,).
    pub whirl_rate: Py<PyArray1<f64>>,
    /// The slip velocity at the contact (m/s): the shaft's surface over the ring along the
    /// tangent, (r' - s') . t + speed shaft_radius, > 0 where it slides forward; 0 while
    /// rolling; NaN out of contact and without friction, shape (N,).
    pub slip_velocity: Py<PyArray1<f64>>,
    /// The rub torque on the shaft (N m): shaft_radius times ``friction_force`` (< 0 brakes a
    /// shaft slipping forward); 0 without friction, shape (N,).
    pub rub_torque: Py<PyArray1<f64>>,
    /// The power friction dissipates (W): -``friction_force`` times ``slip_velocity`` (>= 0)
    /// while slipping, 0 otherwise, shape (N,).
    pub friction_power: Py<PyArray1<f64>>,
    /// The energy friction dissipated over the run (J): ``friction_power`` integrated by the
    /// trapezoidal rule on the samples (refine ``dt`` to converge it).
    pub friction_energy: f64,
    /// The probed nodes (``probe_nodes``), shape (P,).
    pub probe_nodes: Py<PyArray1<u64>>,
    /// Their x displacements (m), shape (N, P).
    pub probe_x: Py<PyArray2<f64>>,
    /// Their y displacements (m), shape (N, P).
    pub probe_y: Py<PyArray2<f64>>,
    /// Their x velocities (m/s), shape (N, P).
    pub probe_vx: Py<PyArray2<f64>>,
    /// Their y velocities (m/s), shape (N, P).
    pub probe_vy: Py<PyArray2<f64>>,
    /// Regime at the samples (1: no contact, 2..=5 contact), uint8, shape (N,).
    pub regimes: Py<PyArray1<u8>>,
    /// Times of the contact onsets (s).
    pub onsets: Py<PyArray1<f64>>,
    /// Times of the contact losses (s).
    pub losses: Py<PyArray1<f64>>,
    /// The contact episodes.
    pub contacts: Py<ContactEpisodes>,
    /// The revolutions.
    pub revolutions: Py<Revolutions>,
    /// Degrees of freedom integrated (after dropping z, theta and any reduction).
    pub dofs: usize,
    /// The Craig-Bampton modes kept (0: the full model).
    pub modes: usize,
    /// The reduction's worst relative error on the steady unbalance response at the ring node
    /// over the run's speeds (0 for the full model).
    pub mode_error: f64,
    /// The least damping ratio of the integrated rotor's modes without contact (at the
    /// reference speed: the run's, or a run-up's largest), min -Re(lambda)/|lambda| over its
    /// nonzero eigenvalues (NaN if the eigen-decomposition was refused as ill-conditioned).
    pub least_damping_ratio: f64,
    /// Whether a mode grows without contact beyond rounding (some eigenvalue's real part
    /// above the decomposition's rounding level: an undamped rotor, whose least damping ratio
    /// may come out -1e-14, is not unstable): the rotor is linearly unstable, its free
    /// response grows whatever the ring does (a RuntimeWarning says so when the run starts).
    pub linearly_unstable: bool,
    /// The integration method that ran, lower case: the one asked for, or the default picked
    /// (``fe_transient``: etd4 in modal form for the full model, radau5 where no modal form
    /// can be built or in physical form; ``fe_run_up``: radau5 for the full model; dop853 for
    /// a reduced one).
    pub method: String,
    /// The work done (steps, rejected, rhs_evals, ..., lu_decompositions).
    pub stats: Py<PyDict>,
}

/// A finite-element run's model: the frictionless composition ([`RingedRotor`]) or the one
/// with friction at the ring ([`RubbingRotor`]).
pub trait RunModel: RotorModel<Dim = Dyn> + Sync {
    /// The rotor without the ring.
    type Rotor: SmoothRotor<Dim = Dyn>;
    /// The rotor without the ring.
    fn smooth(&self) -> &Self::Rotor;
    /// The ring's force on the rotor at time `t` in a state `y` with the mode label `label`.
    fn force(&self, t: f64, y: &DVector<f64>, label: u8) -> Result<Vector2<f64>, ModelError>;
    /// The free flight's closed form, as [`RingedRotor::closed_form`].
    fn closed_form(&self) -> Option<Result<&LinearClosedForm, &RotorError>>;
    /// Writes the ring's position for the rotor's station into the state.
    fn make_consistent(&self, y: &mut DVector<f64>) -> Result<(), ModelError>;
    /// The slip velocity at the contact (m/s): NaN out of contact and without friction.
    fn slip_velocity(&self, t: f64, y: &DVector<f64>, label: u8) -> Result<f64, ModelError>;
    /// The shaft's radius at the ring (m), 0 without friction.
    fn shaft_radius(&self) -> f64;
}

impl<R: SmoothRotor<Dim = Dyn> + Sync> RunModel for RingedRotor<R> {
    type Rotor = R;
    fn smooth(&self) -> &R {
        self.rotor()
    }
    fn force(&self, _t: f64, y: &DVector<f64>, label: u8) -> Result<Vector2<f64>, ModelError> {
        self.contact_force(y, label != 1)
    }
    fn closed_form(&self) -> Option<Result<&LinearClosedForm, &RotorError>> {
        RingedRotor::closed_form(self)
    }
    fn make_consistent(&self, y: &mut DVector<f64>) -> Result<(), ModelError> {
        RingedRotor::make_consistent(self, y)
    }
    fn slip_velocity(&self, _t: f64, _y: &DVector<f64>, _label: u8) -> Result<f64, ModelError> {
        Ok(f64::NAN)
    }
    fn shaft_radius(&self) -> f64 {
        0.0
    }
}

impl<R: SmoothRotor<Dim = Dyn> + Sync> RunModel for RubbingRotor<R> {
    type Rotor = R;
    fn smooth(&self) -> &R {
        self.ringed().rotor()
    }
    fn force(&self, t: f64, y: &DVector<f64>, label: u8) -> Result<Vector2<f64>, ModelError> {
        self.contact_force(t, y, label)
    }
    fn closed_form(&self) -> Option<Result<&LinearClosedForm, &RotorError>> {
        self.ringed().closed_form()
    }
    fn make_consistent(&self, y: &mut DVector<f64>) -> Result<(), ModelError> {
        self.ringed().make_consistent(y)
    }
    fn slip_velocity(&self, t: f64, y: &DVector<f64>, label: u8) -> Result<f64, ModelError> {
        RubbingRotor::slip_velocity(self, t, y, label)
    }
    fn shaft_radius(&self) -> f64 {
        RubbingRotor::shaft_radius(self)
    }
}

/// What a run's result is made of besides its trajectory.
pub struct RunFacts<'a, M: RunModel> {
    /// The model that ran.
    pub model: &'a M,
    /// The ring node's displacement from its undeflected position in a state.
    pub displacement: &'a dyn Fn(&DVector<f64>) -> [f64; 2],
    /// The speed at a time and state (a driven rotor's is in its state).
    pub speed: &'a dyn Fn(f64, &DVector<f64>) -> f64,
    /// The shaft's angle at a time and state (the integral of the speed from 0).
    pub phase: &'a dyn Fn(f64, &DVector<f64>) -> f64,
    /// The degrees of freedom integrated.
    pub dofs: usize,
    /// The reduction kept.
    pub reduction: Reduction,
    /// The rotor's stability without contact.
    pub margin: Margin,
    /// The probed nodes and where they are in the state.
    pub probes: (&'a [usize], &'a Probes),
    /// The integration method's name, as asked for or picked.
    pub method: &'a str,
}

/// The ring's force on the rotor, its normal part N = n . f (n from the ring's centre to the
/// station) and its friction part t . f (t, n turned by +90 degrees) in a state of the run at
/// time `t` with mode label `label`.
fn force_of<M: RunModel>(
    model: &M,
    t: f64,
    y: &DVector<f64>,
    label: u8,
) -> PyResult<(Vector2<f64>, f64, f64)> {
    let force = model.force(t, y, label).map_err(value_error)?;
    if label == 1 {
        return Ok((force, 0.0, 0.0));
    }
    let r = model.smooth().station(y).r;
    let [i, j] = model.smooth().ring_slots();
    let n = r - Vector2::new(y[i], y[j]);
    let tangent = Vector2::new(-n.y, n.x);
    Ok((
        force,
        -n.dot(&force) / n.norm(),
        tangent.dot(&force) / n.norm(),
    ))
}

/// The run's result from its trajectory (samples with strobes once a revolution, events).
pub fn fe_run<M: RunModel>(
    py: Python<'_>,
    facts: &RunFacts<'_, M>,
    traj: &Trajectory<Dyn>,
    stats: &SimStats,
) -> PyResult<FeRun> {
    let model = facts.model;
    let s = &traj.samples;
    let forces = s
        .iter()
        .map(|p| force_of(model, p.t, &p.y, p.label))
        .collect::<PyResult<Vec<_>>>()?;
    let at = |p: &DVector<f64>| (facts.displacement)(p);
    let velocity: Vec<_> = s.iter().map(|p| model.smooth().station(&p.y).v).collect();
    let rub = rub_outputs(model, traj, &forces)?;
    let [i, j] = model.smooth().ring_slots();
    let changes = |onset: bool| {
        let e = traj
            .events
            .iter()
            // Contact starts out of free flight and ends into it (a change of regime within
            // a contact, or of the friction's mode, is neither).
            .filter(|e| e.from != e.to && if onset { e.from == 1 } else { e.to == 1 });
        array(py, e.map(|e| e.t))
    };
    Ok(FeRun {
        t: array(py, s.iter().map(|p| p.t)),
        speed: array(py, s.iter().map(|p| (facts.speed)(p.t, &p.y))),
        phase: array(py, s.iter().map(|p| (facts.phase)(p.t, &p.y))),
        x: array(py, s.iter().map(|p| at(&p.y)[0])),
        y: array(py, s.iter().map(|p| at(&p.y)[1])),
        vx: array(py, velocity.iter().map(|v| v.x)),
        vy: array(py, velocity.iter().map(|v| v.y)),
        ring_x: array(py, s.iter().map(|p| p.y[i])),
        ring_y: array(py, s.iter().map(|p| p.y[j])),
        force_x: array(py, forces.iter().map(|f| f.0.x)),
        force_y: array(py, forces.iter().map(|f| f.0.y)),
        normal_force: array(py, forces.iter().map(|f| f.1)),
        friction_force: array(py, forces.iter().map(|f| f.2)),
        whirl_rate: array(
            py,
            s.iter().zip(&velocity).map(|(p, v)| {
                let [x, y] = at(&p.y);
                (x * v.y - y * v.x) / (x * x + y * y)
            }),
        ),
        slip_velocity: array(py, rub.iter().map(|r| r.0)),
        rub_torque: array(py, forces.iter().map(|f| model.shaft_radius() * f.2)),
        friction_power: array(py, rub.iter().map(|r| r.1)),
        friction_energy: s
            .windows(2)
            .zip(rub.windows(2))
            .map(|(p, r)| 0.5 * (p[1].t - p[0].t) * (r[0].1 + r[1].1))
            .sum(),
        probe_nodes: array(py, facts.probes.0.iter().map(|&n| n as u64)),
        probe_x: probed(py, facts.probes.1, traj, [false, false])?,
        probe_y: probed(py, facts.probes.1, traj, [false, true])?,
        probe_vx: probed(py, facts.probes.1, traj, [true, false])?,
        probe_vy: probed(py, facts.probes.1, traj, [true, true])?,
        regimes: array(py, s.iter().map(|p| p.label)),
        onsets: changes(true),
        losses: changes(false),
        contacts: Py::new(py, episodes(py, model, traj, &forces)?)?,
        revolutions: Py::new(py, revolutions(py, facts, traj)?)?,
        dofs: facts.dofs,
        modes: facts.reduction.modes,
        mode_error: facts.reduction.error,
        least_damping_ratio: facts.margin.zeta,
        linearly_unstable: facts.margin.unstable,
        method: facts.method.to_ascii_lowercase(),
        stats: stats_dict(py, stats)?.unbind(),
    })
}

/// The slip velocity and the power friction dissipates at each sample (NaN and 0 out of
/// contact or without friction; 0 and 0 rolling).
fn rub_outputs<M: RunModel>(
    model: &M,
    traj: &Trajectory<Dyn>,
    forces: &[(Vector2<f64>, f64, f64)],
) -> PyResult<Vec<(f64, f64)>> {
    traj.samples
        .iter()
        .zip(forces)
        .map(|(p, f)| {
            let v = model
                .slip_velocity(p.t, &p.y, p.label)
                .map_err(value_error)?;
            let power = if v.is_nan() { 0.0 } else { -f.2 * v };
            Ok((v, power))
        })
        .collect()
}

/// The probed nodes' x (`[velocity, y]` = `[false, false]`), y, x' or y' at the samples,
/// (N, P).
fn probed(
    py: Python<'_>,
    probes: &Probes,
    traj: &Trajectory<Dyn>,
    [velocity, y]: [bool; 2],
) -> PyResult<Py<PyArray2<f64>>> {
    let rows = traj.samples.iter().map(|p| {
        let all = probes.read(&p.y, velocity);
        all.into_iter().skip(usize::from(y)).step_by(2)
    });
    table(py, rows, probes.count())
}

/// One contact episode: its start and end and the normal force at its knots.
struct Episode {
    start: f64,
    end: f64,
    knots: Vec<(f64, f64)>,
}

impl Episode {
    fn peak(&self) -> f64 {
        self.knots.iter().map(|k| k.1).fold(0.0, f64::max)
    }

    fn impulse(&self) -> f64 {
        let panels = self.knots.windows(2);
        panels
            .map(|w| 0.5 * (w[1].0 - w[0].0) * (w[0].1 + w[1].1))
            .sum()
    }
}

/// The normal force in an event's state before (`before`) or after it, in contact.
fn event_force<M: RunModel>(model: &M, e: &EventRecord<Dyn>, before: bool) -> PyResult<f64> {
    let (y, label) = if before {
        (&e.before, e.from)
    } else {
        (&e.after, e.to)
    };
    Ok(force_of(model, e.t, y, label)?.1)
}

/// The contact episodes: from each onset (or a start in contact) to the next loss, the normal
/// force at the onset, the samples in contact between, and the loss.
fn episodes<M: RunModel>(
    py: Python<'_>,
    model: &M,
    traj: &Trajectory<Dyn>,
    forces: &[(Vector2<f64>, f64, f64)],
) -> PyResult<ContactEpisodes> {
    let mut all: Vec<Episode> = Vec::new();
    let mut open: Option<Episode> = match traj.samples.first() {
        Some(p) if p.label != 1 => Some(Episode {
            start: p.t,
            end: f64::NAN,
            knots: Vec::new(),
        }),
        _ => None,
    };
    let mut samples = traj.samples.iter().zip(forces).peekable();
    for e in traj.events.iter().filter(|e| e.from != e.to) {
        // The samples before the event belong to the open episode, if any.
        while let Some((p, f)) = samples.next_if(|(p, _)| p.t < e.t) {
            if let Some(ep) = open.as_mut().filter(|_| p.label != 1) {
                ep.knots.push((p.t, f.1));
            }
        }
        if e.from == 1 {
            let start = event_force(model, e, false)?;
            open = Some(Episode {
                start: e.t,
                end: f64::NAN,
                knots: vec![(e.t, start)],
            });
        } else if e.to == 1 {
            if let Some(mut ep) = open.take() {
                ep.knots.push((e.t, event_force(model, e, true)?));
                ep.end = e.t;
                all.push(ep);
            }
        }
    }
    if let Some(mut ep) = open {
        ep.knots.extend(
            samples
                .filter(|(p, _)| p.label != 1)
                .map(|(p, f)| (p.t, f.1)),
        );
        all.push(ep);
    }
    Ok(ContactEpisodes {
        start: array(py, all.iter().map(|e| e.start)),
        end: array(py, all.iter().map(|e| e.end)),
        duration: array(py, all.iter().map(|e| e.end - e.start)),
        peak_force: array(py, all.iter().map(Episode::peak)),
        impulse: array(py, all.iter().map(Episode::impulse)),
    })
}
