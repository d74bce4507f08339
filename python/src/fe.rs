//! A finite-element rotor on the snubber ring from numpy matrices, as a ROSS user has them
//! (``rotor.M()``, ``rotor.K(w)``, ``rotor.C(w)``, ``rotor.G()``), in SI units: what its runs
//! share (the matrices, the ring, the reduction and its error, the probes, the stability
//! warning).

use std::ffi::CString;

use jeffcott::nalgebra::{DMatrix, DVector};
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{
    CraigBampton, DofLayout, LinearClosedForm, LinearRotor, LinearSystem, ModeSelection,
    RotorError, RotorMatrices,
};
use numpy::{AllowTypeChange, PyArrayLike2};
use pyo3::exceptions::PyRuntimeWarning;
use pyo3::prelude::*;

use crate::errors::value_error;

/// A matrix from any array-like that numpy reads as 2-D numbers (arrays of any float or int
/// type, any memory order, nested lists), as float64.
pub type ArrayLike<'py> = PyArrayLike2<'py, f64, AllowTypeChange>;

pub(crate) fn matrix(name: &str, a: &ArrayLike<'_>) -> PyResult<DMatrix<f64>> {
    let v = a.as_array();
    let (r, c) = v.dim();
    if r != c {
        return Err(value_error(format!(
            "{name} must be square, got shape ({r}, {c})"
        )));
    }
    Ok(DMatrix::from_fn(r, c, |i, j| v[(i, j)]))
}

pub(crate) fn layout(name: &str) -> PyResult<DofLayout> {
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
    system_of(lateral, speed, unbalance).map_err(value_error)
}

/// [`system_at`] with the crate's error (for a closure run without the GIL).
pub fn system_of(
    lateral: &RotorMatrices,
    speed: f64,
    unbalance: &[(usize, f64, f64)],
) -> Result<LinearSystem, RotorError> {
    let mut system = LinearSystem::from_matrices(lateral, speed)?;
    for &(node, me, phase) in unbalance {
        system = system.with_unbalance(lateral.layout(), node, me, phase)?;
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
                None => DVector::from_fn(n, |i, _| if i == dof { 1.0 } else { 0.0 }),
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
