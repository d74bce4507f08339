//! Bearings whose stiffness and damping follow the speed, for ``fe_run_up`` and ``fe_rub_map``: the full
//! matrices on a grid of speeds, cut to the lateral DOFs as the run's matrices are and
//! projected by the run's reduction (the crate's ``rotor::BearingTable``).

use jeffcott::nalgebra::DMatrix;
use jeffcott::rotor::{BearingTable, CraigBampton, RotorMatrices};
use numpy::{AllowTypeChange, PyArrayLike1, PyArrayLike3};
use pyo3::prelude::*;

use crate::errors::value_error;
use crate::fe::{layout, matrix, ArrayLike};

/// A stack of matrices, one per grid speed, from any array-like numpy reads as 3-D numbers.
pub type Stack<'py> = PyArrayLike3<'py, f64, AllowTypeChange>;

/// The keywords ``bearing_speeds``, ``bearing_K``, ``bearing_C``.
pub type BearingArgs<'a, 'py> = (
    Option<PyArrayLike1<'py, f64, AllowTypeChange>>,
    Option<&'a Stack<'py>>,
    Option<&'a Stack<'py>>,
);

/// The table of the lateral matrices (the full model's lateral DOFs).
pub struct Bearings {
    table: BearingTable,
}

/// The stack's matrix `i`.
fn slice(stack: &Stack<'_>, i: usize) -> DMatrix<f64> {
    let v = stack.as_array();
    let (_, r, c) = v.dim();
    DMatrix::from_fn(r, c, |a, b| v[(i, a, b)])
}

impl Bearings {
    /// The table from the keywords (all three or none), each grid point's matrices with the
    /// run's ``M`` and ``G`` cut to the lateral DOFs of ``layout_name``.
    pub fn from_args(
        (m, g): (&ArrayLike<'_>, &ArrayLike<'_>),
        layout_name: &str,
        (speeds, k, c): BearingArgs<'_, '_>,
    ) -> PyResult<Option<Self>> {
        let (speeds, k, c) = match (speeds, k, c) {
            (None, None, None) => return Ok(None),
            (Some(s), Some(k), Some(c)) => (s, k, c),
            _ => {
                return Err(value_error(
                    "bearing_speeds, bearing_K and bearing_C go together: give all three or none",
                ));
            }
        };
        let speeds: Vec<f64> = speeds.as_array().to_vec();
        let (m, g) = (matrix("M", m)?, matrix("G", g)?);
        let n = m.nrows();
        for (name, stack) in [("bearing_K", k), ("bearing_C", c)] {
            let (count, r, cols) = stack.as_array().dim();
            if count != speeds.len() || r != n || cols != n {
                return Err(value_error(format!(
                    "{name} must have shape ({}, {n}, {n}) (one matrix like M per bearing speed), got ({count}, {r}, {cols})",
                    speeds.len()
                )));
            }
        }
        let (mut ks, mut cs) = (Vec::new(), Vec::new());
        for i in 0..speeds.len() {
            let full = RotorMatrices::new(
                m.clone(),
                slice(c, i),
                g.clone(),
                slice(k, i),
                layout(layout_name)?,
            )
            .and_then(|full| full.lateral())
            .map_err(|e| value_error(format!("bearing matrices at bearing_speeds[{i}]: {e}")))?;
            ks.push(full.stiffness().clone());
            cs.push(full.damping().clone());
        }
        let table = BearingTable::new(speeds, ks, cs).map_err(value_error)?;
        Ok(Some(Self { table }))
    }

    /// The lateral matrices `lateral` with the table's K and C at `speed` (the run's reference).
    pub fn lateral_at(&self, lateral: &RotorMatrices, speed: f64) -> PyResult<RotorMatrices> {
        self.table.matrices_at(lateral, speed).map_err(value_error)
    }

    /// The table of the lateral matrices (for a closure run without the GIL).
    pub fn table(&self) -> &BearingTable {
        &self.table
    }

    /// The table in the run's coordinates: as it is, or projected by the reduction `cb`.
    pub fn in_run(&self, cb: Option<&CraigBampton>) -> PyResult<BearingTable> {
        match cb {
            None => Ok(self.table.clone()),
            Some(cb) => cb.project_table(&self.table).map_err(value_error),
        }
    }
}
