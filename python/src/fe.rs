//! A finite-element rotor on the snubber ring from numpy matrices, as a ROSS user has them
//! (``rotor.M()``, ``rotor.K(w)``, ``rotor.C(w)``, ``rotor.G()``): the transient from rest at
//! constant speed (`fe_transient`), in SI units; what a run-up shares with it (the rotor, the
//! ring, the reduction, the stability warning).

use std::ffi::CString;

use jeffcott::hybrid::{SimStats, Trajectory};
use jeffcott::nalgebra::{DMatrix, DVector, Dyn};
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{
    CraigBampton, DofLayout, LinearClosedForm, LinearRotor, LinearSystem, ModeSelection,
    RotorError, RotorMatrices,
};
use numpy::{AllowTypeChange, PyArrayLike2};
use pyo3::exceptions::PyRuntimeWarning;
use pyo3::prelude::*;

use crate::errors::value_error;
use crate::fe_run::{fe_run, FeRun, RunFacts};
use crate::options::sim_options;
use crate::paper::dense_output;
use crate::runs;

/// A matrix from any array-like that numpy reads as 2-D numbers (arrays of any float or int
/// type, any memory order, nested lists), as float64.
pub type ArrayLike<'py> = PyArrayLike2<'py, f64, AllowTypeChange>;

fn matrix(name: &str, a: &ArrayLike<'_>) -> PyResult<DMatrix<f64>> {
    let v = a.as_array();
    let (r, c) = v.dim();
    if r != c {
        return Err(value_error(format!(
            "{name} must be square, got shape ({r}, {c})"
        )));
    }
    Ok(DMatrix::from_fn(r, c, |i, j| v[(i, j)]))
}

fn layout(name: &str) -> PyResult<DofLayout> {
    match name {
        "ross6" => Ok(DofLayout::Ross6),
        "lateral4" => Ok(DofLayout::Lateral4),
        other => Err(value_error(format!(
            "layout '{other}' is not ross6 or lateral4"
        ))),
    }
}

/// The lateral matrices of `M, K, C, G` in `layout` (z and theta dropped after the check).
pub fn lateral_matrices(
    [m, k, c, g]: [&ArrayLike<'_>; 4],
    layout: &str,
) -> PyResult<RotorMatrices> {
    let (m, k, c, g) = (
        matrix("M", m)?,
        matrix("K", k)?,
        matrix("C", c)?,
        matrix("G", g)?,
    );
    let full = RotorMatrices::new(m, c, g, k, self::layout(layout)?).map_err(value_error)?;
    full.lateral().map_err(value_error)
}

/// The system at `speed` (rad/s) with the out-of-balances (node, m e in kg m, phase in rad).
pub fn system_at(
    lateral: &RotorMatrices,
    speed: f64,
    unbalance: &[(usize, f64, f64)],
) -> PyResult<LinearSystem> {
    let mut system = LinearSystem::from_matrices(lateral, speed).map_err(value_error)?;
    for &(node, me, phase) in unbalance {
        system = system
            .with_unbalance(lateral.layout(), node, me, phase)
            .map_err(value_error)?;
    }
    Ok(system)
}

/// The ring and where it sits: node, gap (m), unit stiffness (N/m), unit damping (N s/m),
/// preloads and rest-centre offset (m).
pub struct RingAt {
    pub node: usize,
    pub ring: SnubberRing,
    pub offset: [f64; 2],
}

impl RingAt {
    /// The ring from the keywords, as ``fe_transient`` names them.
    pub fn new(
        node: usize,
        [gap, stiffness, damping]: [f64; 3],
        preload: (f64, f64),
        offset: (f64, f64),
    ) -> PyResult<Self> {
        let ring = SnubberRing::from_units(stiffness, damping, [preload.0, preload.1], gap)
            .map_err(value_error)?;
        Ok(Self {
            node,
            ring,
            offset: [offset.0, offset.1],
        })
    }
}

/// How many Craig-Bampton modes: a count (0: the full model) or the fewest that meet a
/// tolerance on the steady unbalance response at the ring node over the run's speeds.
#[derive(Debug, Clone, Copy)]
pub enum Modes {
    Count(usize),
    Auto { tolerance: f64 },
}

/// The keyword ``modes`` as given: an int or a name.
#[derive(Debug, Clone, FromPyObject)]
pub enum ModesArg {
    Count(usize),
    Name(String),
}

impl Modes {
    /// From the keywords ``modes`` (an int or "auto") and ``mode_tolerance``.
    pub fn new(modes: ModesArg, tolerance: f64) -> PyResult<Self> {
        match modes {
            ModesArg::Count(count) => Ok(Modes::Count(count)),
            ModesArg::Name(name) if name == "auto" => Ok(Modes::Auto {
                tolerance: crate::options::positive("mode_tolerance", tolerance)?,
            }),
            ModesArg::Name(other) => Err(value_error(format!(
                "modes = '{other}' is not an int or 'auto'"
            ))),
        }
    }

    /// Whether the rotor is reduced.
    pub fn reduces(&self) -> bool {
        !matches!(self, Modes::Count(0))
    }
}

/// What a reduction kept: its modes (0: none, the full model) and its worst relative error on
/// the steady unbalance response at the ring node over the run's speeds (0 for the full
/// model).
#[derive(Debug, Clone, Copy)]
pub struct Reduction {
    pub modes: usize,
    pub error: f64,
}

/// The rotor, full or reduced (`modes`), and the reduction for the matrices a run-up projects;
/// `speeds` (rad/s, > 0) are the run's, where the reduction's error is measured.
pub fn rotor_of(
    lateral: &RotorMatrices,
    system: LinearSystem,
    at: &RingAt,
    (modes, speeds): (Modes, &[f64]),
) -> PyResult<(LinearRotor, Option<CraigBampton>, Reduction)> {
    let x = lateral.x_dof(at.node).map_err(value_error)?;
    let force = system.harmonic_force().clone();
    let (cb, error) = match modes {
        Modes::Count(0) => {
            let rotor = LinearRotor::new(system, [x, x + 1], at.offset).map_err(value_error)?;
            let none = Reduction {
                modes: 0,
                error: 0.0,
            };
            return Ok((rotor, None, none));
        }
        Modes::Count(count) => {
            let cb = CraigBampton::at_node(lateral, at.node, ModeSelection::Count(count))
                .map_err(value_error)?;
            let worst = cb.response_error_sweep(lateral, &force, speeds);
            (cb, worst.map_err(value_error)?.relative)
        }
        Modes::Auto { tolerance } => {
            let found = CraigBampton::fewest_modes(lateral, &[x, x + 1], &force, speeds, tolerance);
            let (cb, worst) = found.map_err(value_error)?;
            (cb, worst.relative)
        }
    };
    // The reduced coordinates 0 and 1 are the ring node's x and y.
    let reduced = cb.reduce(&system).map_err(value_error)?;
    let rotor = LinearRotor::new(reduced, [0, 1], at.offset).map_err(value_error)?;
    let kept = Reduction {
        modes: cb.modes(),
        error,
    };
    Ok((rotor, Some(cb), kept))
}

/// Where the probed nodes' x and y are in the integrated coordinates: a row each, applied to
/// the state's q (displacements) and q' (velocities).
pub struct Probes {
    rows: Vec<[DVector<f64>; 2]>,
}

impl Probes {
    /// The rows of `nodes` in the full model, or through the reduction's basis.
    pub fn new(
        lateral: &RotorMatrices,
        cb: Option<&CraigBampton>,
        nodes: &[usize],
    ) -> PyResult<Self> {
        let n = lateral.dofs();
        let mut rows = Vec::with_capacity(nodes.len());
        for &node in nodes {
            let x = lateral.x_dof(node).map_err(value_error)?;
            let row = |dof: usize| match cb {
                Some(cb) => cb.basis().row(dof).transpose(),
                None => DVector::from_fn(n, |i, _| f64::from(u8::from(i == dof))),
            };
            rows.push([row(x), row(x + 1)]);
        }
        Ok(Self { rows })
    }

    /// How many nodes are probed.
    pub fn count(&self) -> usize {
        self.rows.len()
    }

    /// The probed x and y displacements (`velocity` false) or velocities of a state
    /// `[q, q', s]`, node by node: `[x_0, y_0, x_1, y_1, ...]`.
    pub fn read(&self, y: &DVector<f64>, velocity: bool) -> Vec<f64> {
        let n = self.rows.first().map_or(0, |r| r[0].len());
        let q = y.rows(if velocity { n } else { 0 }, n);
        self.rows
            .iter()
            .flat_map(|r| [r[0].dot(&q), r[1].dot(&q)])
            .collect()
    }
}

/// The rotor's stability without contact, from its free flight's closed form: the least
/// damping ratio and whether a mode grows beyond rounding (NaN and false where the closed
/// form was refused as ill-conditioned or not made).
#[derive(Debug, Clone, Copy)]
pub struct Margin {
    pub zeta: f64,
    pub unstable: bool,
}

impl Margin {
    pub fn of(form: Option<Result<&LinearClosedForm, &RotorError>>) -> Self {
        match form {
            Some(Ok(form)) => Self {
                zeta: form.least_damping_ratio(),
                unstable: form.is_linearly_unstable(),
            },
            _ => Self {
                zeta: f64::NAN,
                unstable: false,
            },
        }
    }

    /// A RuntimeWarning if the rotor is linearly unstable.
    pub fn warn(&self, py: Python<'_>) -> PyResult<()> {
        if !self.unstable {
            return Ok(());
        }
        let message = format!(
            "the rotor is linearly unstable without contact (least damping ratio {:.3} %): \
             its free response grows whatever the ring does; check the bearings' \
             cross-coupling",
            100.0 * self.zeta
        );
        let message = CString::new(message).map_err(value_error)?;
        PyErr::warn(py, &py.get_type::<PyRuntimeWarning>(), &message, 1)
    }
}

/// The default method: Radau5 for the full model (stiff), DOP853 for a reduced one.
pub fn default_method(modes: Modes) -> &'static str {
    if modes.reduces() {
        "dop853"
    } else {
        "radau5"
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
/// ``mode_error`` say what was kept and its error). Method: radau5 for the full model, dop853 for a reduced
/// one, unless given; ``atol`` defaults to ``rtol``. Runs with the GIL released; Ctrl-C stops
/// it. ``ValueError`` for bad input (the
/// crate's message), ``SimulationError`` (``partial``: an ``FeRun``) for a failed run.
/// Returns an ``FeRun``: the ring node's motion, the ring and its force at the samples, the
/// contact episodes and the revolutions.
#[pyfunction]
#[pyo3(
    signature = (M, K, C, G, speed, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, t_end, samples, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=ModesArg::Count(0), mode_tolerance=1e-3, probe_nodes=vec![], rtol=1e-8, atol=None, method=None, layout="ross6"),
    // Written out: pyo3 shows a tuple default as `...` (Python's Ellipsis) in help().
    text_signature = "(M, K, C, G, speed, *, ring_node, gap, ring_stiffness, ring_damping, unbalance, t_end, samples, preload=(0.0, 0.0), ring_offset=(0.0, 0.0), modes=0, mode_tolerance=0.001, probe_nodes=[], rtol=1e-08, atol=None, method=None, layout='ross6')"
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
    rtol: f64,
    atol: Option<f64>,
    method: Option<&str>,
    layout: &str,
) -> PyResult<FeRun> {
    let modes = Modes::new(modes, mode_tolerance)?;
    let lateral = lateral_matrices([&M, &K, &C, &G], layout)?;
    let system = system_at(&lateral, speed, &unbalance)?;
    let at = RingAt::new(
        ring_node,
        [gap, ring_stiffness, ring_damping],
        preload,
        ring_offset,
    )?;
    let ring = at.ring;
    let (model, reduction, probes) = py.detach(|| {
        let (rotor, cb, reduction) = rotor_of(&lateral, system, &at, (modes, &[speed]))?;
        let probes = Probes::new(&lateral, cb.as_ref(), &probe_nodes)?;
        PyResult::Ok((rotor.ringed(ring).map_err(value_error)?, reduction, probes))
    })?;
    // From the closed form the model prepared: no second eigen-decomposition.
    let margin = Margin::of(model.closed_form());
    margin.warn(py)?;
    let opts = sim_options(
        Some(rtol),
        Some(atol.unwrap_or(rtol)),
        Some(method.unwrap_or(default_method(modes))),
    )?
    .with_max_events_per_period(u32::MAX);
    if samples == 0 {
        return Err(value_error("samples must be at least 1"));
    }
    let dt = t_end / samples as f64;
    let output = dense_output(t_end, dt)?.with_strobes();
    let mut y0 = model.rotor().rest_state();
    model.make_consistent(&mut y0).map_err(value_error)?;
    let displacement = |y: &DVector<f64>| model.rotor().station_displacement(y);
    let facts = RunFacts {
        model: &model,
        displacement: &displacement,
        speed: &|_| speed,
        phase: &|t| speed * t,
        dofs: model.rotor().system().dofs(),
        reduction,
        margin,
        probes: (&probe_nodes, &probes),
    };
    let result =
        |py: Python<'_>, traj: &Trajectory<Dyn>, stats: &SimStats| fe_run(py, &facts, traj, stats);
    runs::run_into(py, &model, y0, output, &opts, result)
}
