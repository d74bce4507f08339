//! How many modes a finite-element rotor needs: the Craig-Bampton reduction's error on the
//! steady unbalance response at the ring node, and the fewest modes that meet a tolerance
//! (the crate's `CraigBampton::response_error_sweep` and `CraigBampton::fewest_modes`).

use jeffcott::nalgebra::{Complex, DVector};
use jeffcott::rotor::{CraigBampton, ModeSelection, RotorMatrices};
use pyo3::prelude::*;

use crate::errors::value_error;
use crate::fe::{lateral_matrices, system_at, ArrayLike};

/// The lateral matrices, the ring node's x DOF and the unbalance's harmonic force.
fn inputs(
    matrices: [&ArrayLike<'_>; 4],
    layout: &str,
    (ring_node, speeds): (usize, &[f64]),
    unbalance: &[(usize, f64, f64)],
) -> PyResult<(RotorMatrices, usize, DVector<Complex<f64>>)> {
    let lateral = lateral_matrices(matrices, layout)?;
    let x = lateral.x_dof(ring_node).map_err(value_error)?;
    let first = *speeds
        .first()
        .ok_or_else(|| value_error("speeds must not be empty"))?;
    let force = system_at(&lateral, first, unbalance)?
        .harmonic_force()
        .clone();
    Ok((lateral, x, force))
}

/// The fewest Craig-Bampton modes (the ring node's x, y kept physical) whose steady unbalance
/// response at the ring node is within ``tolerance`` (relative, 2-norm over x and y) of the
/// full model's at every speed of ``speeds`` (rad/s, > 0): ``(modes, worst_error)``. The
/// matrices, ``unbalance`` and ``layout`` as ``fe_transient``'s (``C`` and ``K`` held at every
/// speed, the damping C + speed G). ``ValueError`` for bad input, a singular dynamic
/// stiffness (an undamped rotor at a resonance) or no count that meets the tolerance.
#[pyfunction]
#[pyo3(signature = (M, K, C, G, speeds, *, ring_node, unbalance, tolerance=1e-3, layout="ross6"))]
#[allow(clippy::too_many_arguments, non_snake_case)] // Python keywords, ROSS's names
pub fn fewest_modes(
    py: Python<'_>,
    M: ArrayLike<'_>,
    K: ArrayLike<'_>,
    C: ArrayLike<'_>,
    G: ArrayLike<'_>,
    speeds: Vec<f64>,
    ring_node: usize,
    unbalance: Vec<(usize, f64, f64)>,
    tolerance: f64,
    layout: &str,
) -> PyResult<(usize, f64)> {
    let (lateral, x, force) = inputs([&M, &K, &C, &G], layout, (ring_node, &speeds), &unbalance)?;
    let found =
        py.detach(|| CraigBampton::fewest_modes(&lateral, &[x, x + 1], &force, &speeds, tolerance));
    let (cb, worst) = found.map_err(value_error)?;
    Ok((cb.modes(), worst.relative))
}

/// The worst relative error over ``speeds`` (rad/s, > 0) of the steady unbalance response at
/// the ring node of the rotor reduced to ``modes`` Craig-Bampton modes, against the full
/// model's, with the speed where it is worst: ``(error, speed)``. Inputs and errors as
/// ``fewest_modes``.
#[pyfunction]
#[pyo3(signature = (M, K, C, G, speeds, *, ring_node, unbalance, modes, layout="ross6"))]
#[allow(clippy::too_many_arguments, non_snake_case)] // Python keywords, ROSS's names
pub fn response_error(
    py: Python<'_>,
    M: ArrayLike<'_>,
    K: ArrayLike<'_>,
    C: ArrayLike<'_>,
    G: ArrayLike<'_>,
    speeds: Vec<f64>,
    ring_node: usize,
    unbalance: Vec<(usize, f64, f64)>,
    modes: usize,
    layout: &str,
) -> PyResult<(f64, f64)> {
    let (lateral, _, force) = inputs([&M, &K, &C, &G], layout, (ring_node, &speeds), &unbalance)?;
    let worst = py.detach(|| {
        CraigBampton::at_node(&lateral, ring_node, ModeSelection::Count(modes))
            .and_then(|cb| cb.response_error_sweep(&lateral, &force, &speeds))
    });
    let worst = worst.map_err(value_error)?;
    Ok((worst.relative, worst.speed))
}
