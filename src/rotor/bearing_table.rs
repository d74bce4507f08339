//! Stiffness and damping that depend on the speed ([`BearingTable`]): fluid-film bearings and
//! seals, whose coefficients follow the spin, given on a grid of speeds for a run-up
//! ([`ProfiledLinearRotor::with_bearing_table`](super::ProfiledLinearRotor::with_bearing_table)).

use nalgebra::{DMatrix, DVector, DVectorViewMut, Dyn};

use super::{LinearSystem, RotorError, RotorMatrices};
use crate::ode::JacobianMut;

/// A rotor's stiffness $K(\Omega)$ and damping $C(\Omega)$ on a grid of speeds
/// $\Omega_0 < \Omega_1 < \dots$ (rad/s), in the coordinates of the system they go with (the
/// full model's, or projected with [`CraigBampton::project`](super::CraigBampton::project)).
/// $C$ is without the gyroscopic term: $\Omega G$ is added with the speed, as ROSS's
/// `rotor.C(speed)` and `rotor.G()` are.
///
/// **The rule.** Between two grid speeds each entry is linear in $\Omega$; below the first and
/// above the last it is held at the end's matrix (not extrapolated: a stiffness extended along
/// its end slope can change sign). With $\Omega_i \le \Omega \le \Omega_{i+1}$ and
/// $w = (\Omega - \Omega_i)/(\Omega_{i+1} - \Omega_i)$,
///
/// $$K(\Omega) = (1 - w)\thinspace K_i + w\thinspace K_{i+1},$$
///
/// and the same for $C$. A law known at every speed (ROSS's own interpolation of a bearing's
/// table, a formula) is sampled on a grid fine enough for this rule to follow it.
///
/// ```
/// use jeffcott::rotor::BearingTable;
/// use nalgebra::DMatrix;
///
/// let k = |kb: f64| DMatrix::from_diagonal_element(2, 2, kb);
/// let table = BearingTable::new(
///     vec![100.0, 200.0],
///     vec![k(1e6), k(2e6)],
///     vec![k(10.0), k(10.0)],
/// )?;
/// assert_eq!(table.stiffness_at(150.0)[(0, 0)], 1.5e6);
/// assert_eq!(table.stiffness_at(50.0)[(0, 0)], 1e6); // held below the grid
/// # Ok::<(), jeffcott::rotor::RotorError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct BearingTable {
    speeds: Vec<f64>,
    stiffness: Vec<DMatrix<f64>>,
    damping: Vec<DMatrix<f64>>,
}

fn table_error(field: &'static str, index: usize, value: f64, reason: &'static str) -> RotorError {
    RotorError::BearingTable {
        field,
        index,
        value,
        reason,
    }
}

/// Checks one grid point's matrix: square, of the first matrix's size, finite.
fn check_grid_matrix(
    field: &'static str,
    index: usize,
    m: &DMatrix<f64>,
    n: usize,
) -> Result<(), RotorError> {
    if m.nrows() != n || m.ncols() != n {
        let reason = "not square or not of the first stiffness matrix's size (value: its rows)";
        return Err(table_error(field, index, m.nrows() as f64, reason));
    }
    match m.iter().find(|v| !v.is_finite()) {
        Some(&v) => Err(table_error(field, index, v, "a non-finite entry")),
        None => Ok(()),
    }
}

impl BearingTable {
    /// The table of `stiffness[i]` $= K(\Omega_i)$ and `damping[i]` $= C(\Omega_i)$ at
    /// `speeds[i]` $= \Omega_i$.
    ///
    /// # Errors
    /// [`RotorError::BearingTable`] naming the field and the grid point: no point, lists of
    /// other lengths, a speed not finite or not above the one before, a matrix not square, not
    /// of the others' size or with a non-finite entry.
    pub fn new(
        speeds: Vec<f64>,
        stiffness: Vec<DMatrix<f64>>,
        damping: Vec<DMatrix<f64>>,
    ) -> Result<Self, RotorError> {
        if speeds.is_empty() {
            return Err(table_error("speeds", 0, 0.0, "no grid point"));
        }
        for (field, len) in [("stiffness", stiffness.len()), ("damping", damping.len())] {
            if len != speeds.len() {
                let reason = "another count of matrices than of speeds (value: the count)";
                return Err(table_error(field, 0, len as f64, reason));
            }
        }
        for (i, &s) in speeds.iter().enumerate() {
            if !s.is_finite() {
                return Err(table_error("speeds", i, s, "not finite"));
            }
            if i > 0 && s <= speeds[i - 1] {
                return Err(table_error("speeds", i, s, "not above the speed before it"));
            }
        }
        let n = stiffness[0].nrows();
        for i in 0..speeds.len() {
            check_grid_matrix("stiffness", i, &stiffness[i], n)?;
            check_grid_matrix("damping", i, &damping[i], n)?;
        }
        Ok(Self {
            speeds,
            stiffness,
            damping,
        })
    }

    /// The grid's speeds (rad/s).
    pub fn speeds(&self) -> &[f64] {
        &self.speeds
    }

    /// $K(\Omega_i)$ at the grid's speeds.
    pub fn stiffness(&self) -> &[DMatrix<f64>] {
        &self.stiffness
    }

    /// $C(\Omega_i)$ at the grid's speeds.
    pub fn damping(&self) -> &[DMatrix<f64>] {
        &self.damping
    }

    /// The matrices' size.
    pub fn dofs(&self) -> usize {
        self.stiffness[0].nrows()
    }

    /// $K(\Omega)$ by the table's rule.
    pub fn stiffness_at(&self, speed: f64) -> DMatrix<f64> {
        interpolate(&self.speeds, &self.stiffness, speed)
    }

    /// $C(\Omega)$ by the table's rule.
    pub fn damping_at(&self, speed: f64) -> DMatrix<f64> {
        interpolate(&self.speeds, &self.damping, speed)
    }

    /// `matrices` with their stiffness and damping replaced by the table's at `speed` (mass,
    /// gyroscopic matrix and layout kept): the rotor at one speed, e.g. for its modes.
    ///
    /// # Errors
    /// As [`RotorMatrices::new`] (a table of another size than `matrices`).
    pub fn matrices_at(
        &self,
        matrices: &RotorMatrices,
        speed: f64,
    ) -> Result<RotorMatrices, RotorError> {
        RotorMatrices::new(
            matrices.mass().clone(),
            self.damping_at(speed),
            matrices.gyroscopic().clone(),
            self.stiffness_at(speed),
            matrices.layout(),
        )
    }
}

/// Where `speed` falls on the grid: the point $i$ and the weight $w$ of point $i + 1$ (0 at a
/// grid point and beyond the ends, where the end's matrix holds).
fn bracket(speeds: &[f64], speed: f64) -> (usize, f64) {
    let last = speeds.len() - 1;
    if speed <= speeds[0] {
        return (0, 0.0);
    }
    if speed >= speeds[last] {
        return (last, 0.0);
    }
    // speeds[i] < speed < speeds[i + 1] (the first point above `speed` is i + 1 >= 1).
    let i = speeds.partition_point(|&s| s <= speed) - 1;
    (i, (speed - speeds[i]) / (speeds[i + 1] - speeds[i]))
}

fn interpolate(speeds: &[f64], values: &[DMatrix<f64>], speed: f64) -> DMatrix<f64> {
    let (i, w) = bracket(speeds, speed);
    if w == 0.0 {
        values[i].clone()
    } else {
        &values[i] * (1.0 - w) + &values[i + 1] * w
    }
}

/// A [`BearingTable`] as a correction of a [`LinearSystem`]'s field at the speed $\Omega$:
/// the acceleration $-M^{-1}\big((K(\Omega) - K_r)\thinspace q + (C(\Omega) + \Omega_r G -
/// D_r)\thinspace q^\prime\big)$, $K_r$, $D_r$ the system's (at its speed $\Omega_r$), so that
/// with the profile's $-(\Omega - \Omega_r)M^{-1}G q^\prime$ the field is that of
/// $K(\Omega)$ and $C(\Omega) + \Omega G$.
///
/// Bearings change a few DOFs: only the state's columns where some grid point differs from the
/// system are kept, so a step costs $O(n m)$ for $m$ such columns, and nothing where the table
/// equals the system.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct SpeedCorrection {
    speeds: Vec<f64>,
    /// The state's columns ($q$: $0..n$, $q^\prime$: $n..2n$) that some grid point changes.
    columns: Vec<usize>,
    /// Per grid point, $-M^{-1}[K_i - K_r \mid C_i + \Omega_r G - D_r]$ at those columns.
    blocks: Vec<DMatrix<f64>>,
    /// The largest row sums of the blocks' $|K|$ and $|C|$ parts over the grid.
    row_bounds: [f64; 2],
}

impl SpeedCorrection {
    /// The correction of `system` (whose gyroscopic matrix is `gyroscopic`) by `table`.
    ///
    /// # Errors
    /// [`RotorError::BearingTable`] for a table of another size than the system,
    /// [`RotorError::Singular`] for a singular mass matrix.
    pub(super) fn new(
        table: &BearingTable,
        system: &LinearSystem,
        gyroscopic: &DMatrix<f64>,
    ) -> Result<Self, RotorError> {
        let n = system.dofs();
        if table.dofs() != n {
            let reason = "matrices of another size than the system's (value: their rows)";
            return Err(table_error("stiffness", 0, table.dofs() as f64, reason));
        }
        // The same expression as `LinearSystem::from_matrices`' D = C + G Ω: where the table's
        // C is the system's, the difference is exactly zero.
        let differences: Vec<DMatrix<f64>> = (0..table.speeds.len())
            .map(|i| {
                let mut d = DMatrix::zeros(n, 2 * n);
                d.columns_mut(0, n)
                    .copy_from(&(&table.stiffness[i] - system.stiffness()));
                let damping = &table.damping[i] + gyroscopic * system.speed();
                d.columns_mut(n, n).copy_from(&(damping - system.damping()));
                d
            })
            .collect();
        let columns: Vec<usize> = (0..2 * n)
            .filter(|&c| {
                differences
                    .iter()
                    .any(|d| d.column(c).iter().any(|&v| v != 0.0))
            })
            .collect();
        let mut blocks = Vec::with_capacity(differences.len());
        let mut row_bounds = [0.0_f64; 2];
        for d in &differences {
            let picked = DMatrix::from_fn(n, columns.len(), |r, k| d[(r, columns[k])]);
            let block = -system.solve_mass(&picked)?;
            for r in 0..n {
                let mut sums = [0.0; 2];
                for (k, &c) in columns.iter().enumerate() {
                    sums[usize::from(c >= n)] += block[(r, k)].abs();
                }
                row_bounds = [row_bounds[0].max(sums[0]), row_bounds[1].max(sums[1])];
            }
            blocks.push(block);
        }
        Ok(Self {
            speeds: table.speeds.clone(),
            columns,
            blocks,
            row_bounds,
        })
    }

    /// Adds the correction at `speed` to `accel` ($q^{\prime\prime}$), from the state `y`
    /// ($[q, q^\prime, \dots]$). No allocation.
    pub(super) fn add_acceleration(
        &self,
        speed: f64,
        y: &DVector<f64>,
        accel: &mut DVectorViewMut<'_, f64>,
    ) {
        let (i, w) = bracket(&self.speeds, speed);
        for (k, &c) in self.columns.iter().enumerate() {
            let v = y[c];
            if w == 0.0 {
                accel.axpy(v, &self.blocks[i].column(k), 1.0);
            } else {
                accel.axpy((1.0 - w) * v, &self.blocks[i].column(k), 1.0);
                accel.axpy(w * v, &self.blocks[i + 1].column(k), 1.0);
            }
        }
    }

    /// Adds the correction's derivative at `speed` to the acceleration rows ($n..2n$) of
    /// `jac`.
    pub(super) fn add_jacobian(&self, speed: f64, n: usize, jac: &mut JacobianMut<'_, Dyn>) {
        let (i, w) = bracket(&self.speeds, speed);
        for (k, &c) in self.columns.iter().enumerate() {
            for r in 0..n {
                let mut v = self.blocks[i][(r, k)];
                if w != 0.0 {
                    v = (1.0 - w) * v + w * self.blocks[i + 1][(r, k)];
                }
                jac[(n + r, c)] += v;
            }
        }
    }

    /// Adds the correction's derivative by the speed at `speed`, applied to the state `y`,
    /// to `out` (the acceleration rows of the speed's column, for a rotor whose speed is a
    /// state): $(B_{i+1} - B_i)\thinspace y/(\Omega_{i+1} - \Omega_i)$ on the grid's interval
    /// $i$ (the one above at a grid point), nothing beyond the grid (held there).
    pub(super) fn add_speed_derivative(
        &self,
        speed: f64,
        y: &DVector<f64>,
        out: &mut DVectorViewMut<'_, f64>,
    ) {
        let last = self.speeds.len() - 1;
        if speed < self.speeds[0] || speed >= self.speeds[last] {
            return;
        }
        // On the grid, `bracket` gives the interval above the point (its weight 0).
        let (i, _) = bracket(&self.speeds, speed);
        let width = self.speeds[i + 1] - self.speeds[i];
        for (k, &c) in self.columns.iter().enumerate() {
            let v = y[c] / width;
            out.axpy(v, &self.blocks[i + 1].column(k), 1.0);
            out.axpy(-v, &self.blocks[i].column(k), 1.0);
        }
    }

    /// A bound of the rate the correction adds ([`super::SmoothRotor::max_rate`]): the root of
    /// the added stiffness's row bound plus the added damping's (a convex combination of the
    /// grid's blocks is bounded by their largest).
    pub(super) fn rate_bound(&self) -> f64 {
        self.row_bounds[0].sqrt() + self.row_bounds[1]
    }
}
