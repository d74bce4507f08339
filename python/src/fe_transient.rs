//! The transient of a finite-element rotor on the ring at constant speed, from rest: in its
//! physical (or reduced) coordinates, or in its modal coordinates (where ETD4 steps).

use jeffcott::hybrid::{SimOptions, SimStats, Trajectory};
use jeffcott::nalgebra::{DVector, Dyn};
use jeffcott::rotor::{LinearRotor, ModalRotor, RingedRotor, RubbingRotor, SmoothRotor};
use pyo3::prelude::*;

use crate::errors::value_error;
use crate::fe::{
    default_method, lateral_matrices, rotor_of, system_at, ArrayLike, Margin, Modes, ModesArg,
    Probes, Reduction, RingAt,
};
use crate::fe_run::{fe_run, FeRun, RunFacts, RunModel};
use crate::options::{coulomb, sim_options};
use crate::paper::dense_output;
use crate::runs;

/// What a transient needs besides its model: the speed, the samples, the options, what the
/// reduction kept, the probes, and the friction at the ring with the shaft's radius there.
struct Plan<'a> {
    speed: f64,
    /// Coulomb friction at the ring: (mu, the shaft's radius in m).
    friction: Option<(f64, f64)>,
    t_end: f64,
    samples: u64,
    opts: SimOptions,
    /// The method's name, as asked for or picked.
    method: &'a str,
    reduction: Reduction,
    probes: (&'a [usize], &'a Probes),
}

/// The run of `model` from rest (q = q' = 0, the ring consistent) as an ``FeRun``.
fn transient_of<M: RunModel>(
    py: Python<'_>,
    model: &M,
    displacement: &dyn Fn(&DVector<f64>) -> [f64; 2],
    dofs: usize,
    plan: Plan<'_>,
) -> PyResult<FeRun> {
    // From the closed form the model prepared: no second eigen-decomposition.
    let margin = Margin::of(model.closed_form());
    margin.warn(py)?;
    if plan.samples == 0 {
        return Err(value_error("samples must be at least 1"));
    }
    let output = dense_output(plan.t_end, plan.t_end / plan.samples as f64)?.with_strobes();
    let mut y0 = DVector::zeros(model.smooth().dim().0);
    model.make_consistent(&mut y0).map_err(value_error)?;
    let speed = plan.speed;
    let facts = RunFacts {
        model,
        displacement,
        speed: &|_, _| speed,
        phase: &|t, _| speed * t,
        dofs,
        reduction: plan.reduction,
        margin,
        probes: plan.probes,
        method: plan.method,
    };
    let result =
        |py: Python<'_>, traj: &Trajectory<Dyn>, stats: &SimStats| fe_run(py, &facts, traj, stats);
    runs::run_into(py, model, y0, output, &plan.opts, result)
}

/// The run of the rotor on the ring, with friction at the ring when the plan has some (the
/// crate's ``RubbingRotor``), else without (``RingedRotor``, as before).
fn run_form<R>(
    py: Python<'_>,
    model: RingedRotor<R>,
    displacement: fn(&R, &DVector<f64>) -> [f64; 2],
    dofs: usize,
    plan: Plan<'_>,
) -> PyResult<FeRun>
where
    R: SmoothRotor<Dim = Dyn> + Sync,
{
    match plan.friction {
        None => {
            let at = |y: &DVector<f64>| displacement(model.rotor(), y);
            transient_of(py, &model, &at, dofs, plan)
        }
        Some((mu, radius)) => {
            let model = RubbingRotor::new(model, mu, radius).map_err(value_error)?;
            let at = |y: &DVector<f64>| displacement(model.ringed().rotor(), y);
            transient_of(py, &model, &at, dofs, plan)
        }
    }
}

/// Transient of a finite-element rotor on the snubber ring, from rest (q = q' = 0, the ring at
/// its centre) at t = 0 to ``t_end`` (s), sampled ``samples`` + 1 times (every t_end/samples).
///
/// ``M, K, C, G``: square float64 arrays in SI units as ROSS gives them (``rotor.M(w)``,
/// ``rotor.K(w)``, ``rotor.C(w)``, ``rotor.G()``) for M q'' + (C + speed G) q' + K q = F,
/// layout ``"ross6"`` (6 DOFs a node: x, y, z, alpha, beta, theta; z and theta are dropped
/// after checking they are uncoupled) or ``"lateral4"``. ``speed`` in rad/s. ``unbalance``:
/// a list of (node, m e in kg m, phase in rad). The ring at ``ring_node`` (0-based): radial
/// ``gap`` (m), unit stiffness ``ring_stiffness`` (N/m), unit damping ``ring_damping``
/// (N s/m), ``preload`` (Delta_x, Delta_y) (m), rest centre at ``ring_offset`` (m) from the
/// undeflected node. ``modes`` > 0 reduces the rotor to that many Craig-Bampton modes (the
/// ring node's x, y kept physical); ``modes="auto"`` to the fewest whose steady unbalance
/// response at the ring node is within ``mode_tolerance`` (relative) of the full model's at
/// the run's speed (the crate's ``CraigBampton::fewest_modes``; the result's ``modes`` and
/// ``mode_error`` say what was kept and its error). ``probe_nodes``: nodes whose x, y
/// displacements and velocities the result records too (through the reduction's basis).
/// ``form="modal"`` runs the (full or reduced) rotor in its modal coordinates (the crate's
/// ``ModalRotor``: free flight exact, and the method ``etd4``, exponential, its default);
/// ``form="physical"`` in its physical (or reduced) coordinates; ``probe_nodes`` need the
/// physical form. By default (``form=None``, ``method=None``) the fastest path measured to
/// the requested accuracy (docs/fe-rotors.md): the full model in modal form with etd4
/// (physical with radau5 where the modal form cannot be built, or with ``probe_nodes``), a
/// reduced one in physical form with dop853; the result's ``method`` says which ran. A method
/// given without a form: etd4 in modal form, the others in physical form (dop853, dopri5,
/// radau5 in either form; etd4 in modal form only; radau5 in modal form is slow, its Jacobian
/// not analytic there: S1's 0.5 s took 345 s, where the physical form takes 3 s); ``atol``
/// defaults to ``rtol``.
/// ``friction`` > 0: Coulomb friction at the ring (the crate's ``RubbingRotor``; docs/friction.md)
/// between the ring and a shaft of radius ``shaft_radius`` (m, required then) spinning
/// counter-clockwise: contacts slip forward (``regimes`` 6), backward (7) or roll (8), and
/// ``friction_force`` records the tangential force; a preloaded ring takes a friction
/// coefficient below its bound of uniqueness (docs/friction.md; above it, a ``ValueError``).
/// Runs with the GIL released; Ctrl-C stops it.
/// ``ValueError`` for bad input (the crate's message), ``SimulationError`` (``partial``: an
/// ``FeRun``) for a failed run. Returns an ``FeRun``: the ring node's motion, the ring and its
/// force at the samples, the contact episodes and the revolutions.
#[pyfunction]
#[pyo3(
    signature = (M, K, C, G, speed, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, t_end, samples, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=ModesArg::Count(0), mode_tolerance=1e-3, probe_nodes=vec![], form=None, friction=0.0, shaft_radius=None, rtol=1e-8, atol=None, method=None, layout="ross6"),
    // Written out: pyo3 shows a tuple default as `...` (Python's Ellipsis) in help().
    text_signature = "(M, K, C, G, speed, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, t_end, samples, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=0, mode_tolerance=0.001, probe_nodes=[], form=None, friction=0.0, shaft_radius=None, rtol=1e-08, atol=None, method=None, layout='ross6')"
)]
#[allow(clippy::too_many_arguments, non_snake_case)] // Python keywords, ROSS's names
pub fn fe_transient(
    py: Python<'_>,
    M: ArrayLike<'_>,
    K: ArrayLike<'_>,
    C: ArrayLike<'_>,
    G: ArrayLike<'_>,
    speed: f64,
    ring_node: usize,
    gap: f64,
    ring_stiffness: f64,
    ring_damping: f64,
    unbalance: Vec<(usize, f64, f64)>,
    t_end: f64,
    samples: u64,
    preload: (f64, f64),
    ring_offset: (f64, f64),
    modes: ModesArg,
    mode_tolerance: f64,
    probe_nodes: Vec<usize>,
    form: Option<&str>,
    friction: f64,
    shaft_radius: Option<f64>,
    rtol: f64,
    atol: Option<f64>,
    method: Option<&str>,
    layout: &str,
) -> PyResult<FeRun> {
    let modes = Modes::new(modes, mode_tolerance)?;
    // The default path: the full model in modal form with ETD4, unless a probe or another
    // method asks for the physical form.
    let auto = form.is_none()
        && !modes.reduces()
        && probe_nodes.is_empty()
        && method.is_none_or(|m| m.eq_ignore_ascii_case("etd4"));
    let modal = match form {
        None => auto || method.is_some_and(|m| m.eq_ignore_ascii_case("etd4")),
        Some("physical") => false,
        Some("modal") => true,
        Some(other) => {
            return Err(value_error(format!(
                "form '{other}' is not physical or modal"
            )))
        }
    };
    let mut method = method.unwrap_or(if modal { "etd4" } else { default_method(modes) });
    if method.eq_ignore_ascii_case("etd4") && !modal {
        return Err(value_error(format!(
            "method '{method}' with form 'physical': etd4 steps the modal form only (form='modal')"
        )));
    }
    if modal && !probe_nodes.is_empty() {
        return Err(value_error("probe_nodes need form='physical'"));
    }
    let options = |method| {
        sim_options(Some(rtol), Some(atol.unwrap_or(rtol)), Some(method))
            .map(|o| o.with_max_events_per_period(u32::MAX))
    };
    let mut opts = options(method)?;
    let lateral = lateral_matrices([&M, &K, &C, &G], layout)?;
    let system = system_at(&lateral, speed, &unbalance)?;
    let at = RingAt::new(
        ring_node,
        [gap, ring_stiffness, ring_damping],
        preload,
        ring_offset,
    )?;
    let (rotor, reduction, probes) = py.detach(|| {
        let (rotor, cb, reduction) = rotor_of(&lateral, system, &at, (modes, &[speed]))?;
        let probes = Probes::new(&lateral, cb.as_ref(), &probe_nodes)?;
        PyResult::Ok((rotor, reduction, probes))
    })?;
    let dofs = rotor.system().dofs();
    let modal_form = if modal {
        match py.detach(|| ModalRotor::new(&rotor).and_then(|m| m.ringed(at.ring))) {
            Ok(model) => Some(model),
            // The default's fallback: the physical form with its default method.
            Err(_) if auto => {
                method = default_method(modes);
                opts = options(method)?;
                None
            }
            Err(e) => return Err(value_error(e)),
        }
    } else {
        None
    };
    let plan = Plan {
        speed,
        friction: coulomb(friction, shaft_radius, "in m")?,
        t_end,
        samples,
        opts,
        method,
        reduction,
        probes: (&probe_nodes, &probes),
    };
    if let Some(model) = modal_form {
        run_form(py, model, ModalRotor::station_displacement, dofs, plan)
    } else {
        let model = py.detach(|| rotor.ringed(at.ring)).map_err(value_error)?;
        run_form(py, model, LinearRotor::station_displacement, dofs, plan)
    }
}
