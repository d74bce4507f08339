//! Craig-Bampton reduction of a finite-element rotor that keeps the ring's DOFs physical.

use nalgebra::{Cholesky, ComplexField, DMatrix, DVector, SymmetricEigen};

use super::matrices::{check_mass, check_matrix};
use super::{BearingTable, RotorError, RotorMatrices};

mod response;

pub use response::ResponseError;

/// Which fixed-interface modes a [`CraigBampton`] reduction keeps (always the lowest ones).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum ModeSelection {
    /// The lowest `n` modes; `Count(0)` is Guyan's static condensation.
    Count(usize),
    /// Every mode whose fixed-interface natural frequency is below this cut-off, in rad/s
    /// (`f64::INFINITY` keeps all; a cut-off below the lowest keeps none).
    Below(f64),
}

/// A Craig-Bampton reduction basis $T$ of a rotor, reduced coordinates ordered
/// `[boundary DOFs (physical, in the order given), fixed-interface modal coordinates
/// (by increasing frequency)]`.
///
/// The contact sees the displacement of one node, so that node's `x` and `y` (the *boundary*
/// DOFs, index set $b$) stay physical coordinates and the rest (the *interior*, $i$) is
/// described by the static shapes they impose plus a few of its own vibration modes:
///
/// $$q = T \begin{bmatrix} q_b \\\\ \eta \end{bmatrix}, \qquad
/// T = \begin{bmatrix} I & 0 \\\\ \Psi & \Phi_i \end{bmatrix}, \qquad
/// \Psi = -K_{ii}^{-1} K_{ib},$$
///
/// (rows shown in the order $[b, i]$; [`CraigBampton::basis`] keeps the rotor's own DOF order)
/// where $\Psi$ are the *constraint modes* (the rotor's static deflection under a unit
/// displacement of one boundary DOF, the others held at zero) and $\Phi_i$ the lowest
/// *fixed-interface modes*, $K_{ii}\phi = \omega^2 M_{ii}\phi$ with the boundary held,
/// mass-normalised ($\Phi_i^{\mathsf T} M_{ii} \Phi_i = I$). With no fixed-interface mode kept
/// it is Guyan's static condensation; with all of them $T$ is square and the reduction exact.
///
/// **Non-symmetric stiffness.** A rotordynamics code's `K` at speed holds the bearings'
/// cross-coupling ($k_{xy} \ne k_{yx}$) and need not be symmetric; `M` is. The constraint modes
/// use the full $K$ (a linear solve), so that a static force on the boundary DOFs is reproduced
/// exactly at every mode count; the fixed-interface modes come from the symmetric parts
/// $\tfrac12(K_{ii} + K_{ii}^{\mathsf T})$, $\tfrac12(M_{ii} + M_{ii}^{\mathsf T})$, by a
/// Cholesky factor $M_{ii} = L L^{\mathsf T}$ and the symmetric eigenproblem of
/// $L^{-1} K_{ii} L^{-\mathsf T}$ (real, mass-orthogonal modes; any vectors spanning the
/// interior make a valid basis, so with all modes kept the reduction stays exact whatever the
/// asymmetry; with fewer, [`CraigBampton::response_error`] measures what truncation costs).
/// The projection itself uses the full
/// matrices, $T^{\mathsf T} A\thinspace T$ for $A$ in $M$, $C$, $G$, $K$, so nothing of the
/// cross-coupling, the damping or the gyroscopic terms is lost in the retained coordinates.
///
/// **Using it.** [`CraigBampton::reduce`] projects a [`LinearSystem`](crate::rotor::LinearSystem)
/// (matrices and forces); with the ring's node as the boundary, the ring sits at reduced
/// coordinates 0 and 1 of a [`LinearRotor`](crate::rotor::LinearRotor). The reduced model is
/// far less stiff: on ROSS's 204-DOF rub-example rotor the lateral state matrix's largest
/// |eigenvalue| is 7.3e6 rad/s in full and 2.6e4 rad/s with 24 modes.
///
/// **Choosing the number of modes.** [`CraigBampton::response_error`] gives the reduction's
/// relative error on the steady harmonic response at the boundary DOFs (e.g. the unbalance
/// response at the running speed), [`CraigBampton::response_error_sweep`] its worst over a
/// list of speeds, and [`CraigBampton::fewest_modes`] the fewest modes within a tolerance.
/// The error is not monotone mode by mode but falls fast overall; on the 204-DOF rotor with
/// the ring at node 12, at 1200 rpm: 2.2e-2 with no mode (Guyan), 6.7e-6 with 12, 1.5e-7
/// with 24, 1.8e-9 with 48; the contact transient of case S1 (`tests/suite/fe/fe_reduction_s1.rs`)
/// is then within 6.6e-4, 4.7e-5 and 1.0e-6 of the gap.
///
/// # Example
///
/// ```
/// use jeffcott::nalgebra::DMatrix;
/// use jeffcott::rotor::{CraigBampton, ModeSelection};
/// // A chain of three unit masses between two walls, springs k = 1; boundary: the middle mass.
/// let m = DMatrix::<f64>::identity(3, 3);
/// let k = DMatrix::from_row_slice(3, 3, &[2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0]);
/// let cb = CraigBampton::new(&m, &k, &[1], ModeSelection::Count(1))?;
/// assert_eq!(cb.basis().shape(), (3, 2));
/// // Held middle mass: each outer mass on two springs, omega = sqrt(2).
/// assert!((cb.frequencies()[0] - 2f64.sqrt()).abs() < 1e-12);
/// let k_reduced = cb.project(&k)?;
/// assert!((k_reduced[(0, 0)] - 1.0).abs() < 1e-12); // two springs of 1/2 each to the walls
/// # Ok::<(), jeffcott::rotor::RotorError>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CraigBampton {
    boundary: Vec<usize>,
    basis: DMatrix<f64>,
    frequencies: Vec<f64>,
}

impl CraigBampton {
    /// The reduction of the rotor with mass `mass` and stiffness `stiffness` (square, of the
    /// same size) keeping the DOFs `boundary` physical (distinct indices, any order: the reduced
    /// coordinate `j` is `boundary[j]`) and the fixed-interface modes chosen by `modes`.
    ///
    /// Errors: a matrix not square or of another size ([`RotorError::MatrixShape`]), a
    /// non-finite entry ([`RotorError::MatrixEntry`]), a mass matrix that is not symmetric
    /// positive definite as a whole ([`RotorError::NotSymmetric`],
    /// [`RotorError::MassNotPositiveDefinite`]), a boundary DOF out of range or repeated
    /// ([`RotorError::DofOutOfRange`], [`RotorError::DuplicateBoundaryDof`]), an interior mass
    /// that is not positive definite ([`RotorError::InteriorMass`]), an interior stiffness
    /// that does not hold the rotor, e.g. rigid-body or axial/torsional DOFs left free
    /// ([`RotorError::InteriorStiffness`]), more modes than interior DOFs
    /// ([`RotorError::ModeCount`]), a cut-off that is NaN or negative
    /// ([`RotorError::ModeCutoff`]), nothing kept at all ([`RotorError::EmptyReduction`]).
    pub fn new(
        mass: &DMatrix<f64>,
        stiffness: &DMatrix<f64>,
        boundary: &[usize],
        modes: ModeSelection,
    ) -> Result<Self, RotorError> {
        let n = mass.nrows();
        check_matrix("M", mass, n)?;
        check_matrix("K", stiffness, n)?;
        check_mass(mass)?;
        if let ModeSelection::Below(cutoff) = modes
            && (cutoff.is_nan() || cutoff < 0.0)
        {
            return Err(RotorError::ModeCutoff { cutoff });
        }
        let interior = interior_dofs(n, boundary)?;
        let pick = |a: &DMatrix<f64>, rows: &[usize], cols: &[usize]| {
            DMatrix::from_fn(rows.len(), cols.len(), |r, c| a[(rows[r], cols[c])])
        };
        let k_ii = pick(stiffness, &interior, &interior);
        let (frequencies, phi) = fixed_interface_modes(&pick(mass, &interior, &interior), &k_ii)?;
        let kept = match modes {
            ModeSelection::Count(count) if count > frequencies.len() => {
                return Err(RotorError::ModeCount {
                    requested: count,
                    available: frequencies.len(),
                })
            }
            ModeSelection::Count(count) => count,
            ModeSelection::Below(cutoff) => frequencies.iter().take_while(|w| **w < cutoff).count(),
        };
        if boundary.len() + kept == 0 {
            return Err(RotorError::EmptyReduction);
        }
        let k_ib = pick(stiffness, &interior, boundary);
        // nalgebra's LU panics on an empty system (every DOF on the boundary).
        let psi = if interior.is_empty() {
            k_ib
        } else {
            // Unreachable once K_ii's symmetric part is positive definite (x^T K_ii x > 0).
            k_ii.lu()
                .solve(&(-k_ib))
                .ok_or(RotorError::InteriorStiffness { eigenvalue: 0.0 })?
        };
        let mut basis = DMatrix::zeros(n, boundary.len() + kept);
        for (j, &b) in boundary.iter().enumerate() {
            basis[(b, j)] = 1.0;
        }
        for (r, &i) in interior.iter().enumerate() {
            for j in 0..boundary.len() {
                basis[(i, j)] = psi[(r, j)];
            }
            for k in 0..kept {
                basis[(i, boundary.len() + k)] = phi[(r, k)];
            }
        }
        Ok(Self {
            boundary: boundary.to_vec(),
            basis,
            frequencies: frequencies[..kept].to_vec(),
        })
    }

    /// The reduction of a rotor's matrices ([`CraigBampton::new`] on its `M` and `K`): give the
    /// lateral rotor ([`RotorMatrices::lateral`]), whose stiffness holds every DOF (ROSS's
    /// axial and torsional DOFs have none to ground).
    pub fn from_rotor(
        rotor: &RotorMatrices,
        boundary: &[usize],
        modes: ModeSelection,
    ) -> Result<Self, RotorError> {
        Self::new(rotor.mass(), rotor.stiffness(), boundary, modes)
    }

    /// The reduction keeping a node's `x` and `y` physical (reduced coordinates 0 and 1), the
    /// ring's node. Error: a node out of range ([`RotorError::NodeOutOfRange`]), or those of
    /// [`CraigBampton::new`].
    pub fn at_node(
        rotor: &RotorMatrices,
        node: usize,
        modes: ModeSelection,
    ) -> Result<Self, RotorError> {
        let x = rotor.x_dof(node)?;
        Self::from_rotor(rotor, &[x, x + 1], modes)
    }

    /// The basis $T$, full DOFs by reduced coordinates (boundary first, then modes).
    pub fn basis(&self) -> &DMatrix<f64> {
        &self.basis
    }
    /// The boundary DOFs (full indices); the reduced coordinate `j` is `boundary()[j]`.
    pub fn boundary(&self) -> &[usize] {
        &self.boundary
    }
    /// The reduced coordinate of a full DOF if it is a boundary DOF.
    pub fn boundary_index(&self, dof: usize) -> Option<usize> {
        self.boundary.iter().position(|&b| b == dof)
    }
    /// Natural frequencies (rad/s) of the kept fixed-interface modes, increasing; the modal
    /// coordinate `k` (reduced coordinate `boundary().len() + k`) belongs to `frequencies()[k]`.
    pub fn frequencies(&self) -> &[f64] {
        &self.frequencies
    }
    /// Number of kept fixed-interface modes.
    pub fn modes(&self) -> usize {
        self.frequencies.len()
    }
    /// Number of full DOFs.
    pub fn full_dofs(&self) -> usize {
        self.basis.nrows()
    }
    /// Number of reduced coordinates (boundary DOFs plus kept modes).
    pub fn reduced_dofs(&self) -> usize {
        self.basis.ncols()
    }

    /// $T^{\mathsf T} A\thinspace T$: the reduced counterpart of a full matrix ($M$, $C$, $G$,
    /// $K$, or $C + \Omega G$). Error: `a` not of the full size ([`RotorError::MatrixShape`]).
    pub fn project(&self, a: &DMatrix<f64>) -> Result<DMatrix<f64>, RotorError> {
        check_matrix("projected", a, self.full_dofs())?;
        Ok(self.basis.tr_mul(&(a * &self.basis)))
    }

    /// A [`BearingTable`] of the full model in the reduced coordinates: each grid point's
    /// stiffness and damping projected ([`CraigBampton::project`]), the speeds as they are.
    /// Linear interpolation commutes with the projection, so the reduced table at any speed
    /// is the projection of the full one there.
    ///
    /// # Errors
    /// [`RotorError::MatrixShape`] for a table of another size than the full model.
    pub fn project_table(&self, table: &BearingTable) -> Result<BearingTable, RotorError> {
        let project = |matrices: &[DMatrix<f64>]| -> Result<Vec<DMatrix<f64>>, RotorError> {
            matrices.iter().map(|a| self.project(a)).collect()
        };
        let (ks, cs) = (project(table.stiffness())?, project(table.damping())?);
        BearingTable::new(table.speeds().to_vec(), ks, cs)
    }

    /// $T^{\mathsf T} f$: the reduced counterpart of a full force vector, real (`f64`) or
    /// complex (a harmonic amplitude). Error: `f` not of the full length
    /// ([`RotorError::VectorLength`]).
    pub fn project_force<T: ComplexField<RealField = f64>>(
        &self,
        f: &DVector<T>,
    ) -> Result<DVector<T>, RotorError> {
        check_length("f", f.len(), self.full_dofs())?;
        Ok(DVector::from_fn(self.reduced_dofs(), |j, _| {
            self.basis
                .column(j)
                .iter()
                .zip(f.iter())
                .fold(T::zero(), |s, (t, fi)| s + T::from_real(*t) * fi.clone())
        }))
    }

    /// $T q$: the full displacement of reduced coordinates `q`, real or complex. Error: `q`
    /// not of the reduced length ([`RotorError::VectorLength`]).
    pub fn expand<T: ComplexField<RealField = f64>>(
        &self,
        q: &DVector<T>,
    ) -> Result<DVector<T>, RotorError> {
        check_length("q", q.len(), self.reduced_dofs())?;
        Ok(DVector::from_fn(self.full_dofs(), |i, _| {
            self.basis
                .row(i)
                .iter()
                .zip(q.iter())
                .fold(T::zero(), |s, (t, qj)| s + T::from_real(*t) * qj.clone())
        }))
    }
}

/// The fixed-interface modes of $(K_{ii}, M_{ii})$ from their symmetric parts: frequencies
/// (rad/s, increasing) and the mass-normalised modes as columns.
fn fixed_interface_modes(
    m_ii: &DMatrix<f64>,
    k_ii: &DMatrix<f64>,
) -> Result<(Vec<f64>, DMatrix<f64>), RotorError> {
    let n = m_ii.nrows();
    if n == 0 {
        return Ok((Vec::new(), DMatrix::zeros(0, 0)));
    }
    let m_s = symmetric_part(m_ii);
    let mass_error = || RotorError::InteriorMass {
        eigenvalue: m_s.symmetric_eigenvalues().min(),
    };
    let l = Cholesky::new(m_s.clone()).ok_or_else(mass_error)?.unpack();
    // L^{-1} K L^{-T} = L^{-1} (L^{-1} K)^T for a symmetric K.
    let half = l
        .solve_lower_triangular(&symmetric_part(k_ii))
        .ok_or_else(mass_error)?;
    let a = l
        .solve_lower_triangular(&half.transpose())
        .ok_or_else(mass_error)?;
    if a.iter().any(|v| !v.is_finite()) {
        // Finite but huge entries overflowed: no eigenvalue to trust.
        return Err(RotorError::InteriorStiffness {
            eigenvalue: f64::NAN,
        });
    }
    let eigen = SymmetricEigen::new(symmetric_part(&a));
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| eigen.eigenvalues[i].total_cmp(&eigen.eigenvalues[j]));
    let (lowest, highest) = (eigen.eigenvalues[order[0]], eigen.eigenvalues[order[n - 1]]);
    // A singular K_ii leaves an eigenvalue at rounding level of the largest, either sign.
    if lowest.is_nan() || lowest <= n as f64 * f64::EPSILON * highest {
        return Err(RotorError::InteriorStiffness { eigenvalue: lowest });
    }
    let mut v = DMatrix::from_fn(n, n, |r, c| eigen.eigenvectors[(r, order[c])]);
    for mut column in v.column_iter_mut() {
        // A fixed sign (largest component positive) makes the basis reproducible.
        if column
            .iter()
            .fold(0.0, |m: f64, x| if x.abs() > m.abs() { *x } else { m })
            < 0.0
        {
            column.neg_mut();
        }
    }
    let phi = l
        .transpose()
        .solve_upper_triangular(&v)
        .ok_or_else(mass_error)?;
    let frequencies = order.iter().map(|&i| eigen.eigenvalues[i].sqrt()).collect();
    Ok((frequencies, phi))
}

fn symmetric_part(a: &DMatrix<f64>) -> DMatrix<f64> {
    (a + a.transpose()) * 0.5
}

/// The interior DOFs (those not in `boundary`, increasing); refuses an index out of range or
/// repeated.
fn interior_dofs(n: usize, boundary: &[usize]) -> Result<Vec<usize>, RotorError> {
    let mut is_boundary = vec![false; n];
    for &dof in boundary {
        if dof >= n {
            return Err(RotorError::DofOutOfRange {
                field: "boundary DOF",
                index: dof,
                dofs: n,
            });
        }
        if is_boundary[dof] {
            return Err(RotorError::DuplicateBoundaryDof { dof });
        }
        is_boundary[dof] = true;
    }
    Ok((0..n).filter(|&i| !is_boundary[i]).collect())
}

fn check_length(vector: &'static str, len: usize, expected: usize) -> Result<(), RotorError> {
    if len != expected {
        return Err(RotorError::VectorLength {
            vector,
            len,
            expected,
        });
    }
    Ok(())
}
