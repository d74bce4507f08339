//! A finite-element rotor's matrices, as a rotordynamics code exports them.

use nalgebra::{Cholesky, DMatrix, SymmetricEigen};

use super::RotorError;

/// How the degrees of freedom of a [`RotorMatrices`] are laid out, node by node.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum DofLayout {
    /// ROSS's layout: six DOFs a node, `[x, y, z, alpha, beta, theta]`, global index
    /// `6 node + dir` (z the shaft axis, alpha and beta rotations about x and y, theta
    /// torsion).
    Ross6,
    /// The lateral DOFs only, four a node, `[x, y, alpha, beta]`, global index `4 node + dir`
    /// ([`RotorMatrices::lateral`]).
    Lateral4,
}

impl DofLayout {
    /// DOFs per node.
    pub fn per_node(self) -> usize {
        match self {
            DofLayout::Ross6 => 6,
            DofLayout::Lateral4 => 4,
        }
    }
}

/// The matrices of a linear rotor at one spin speed $\Omega$, in SI units:
///
/// $$M q^{\prime\prime} + (C + \Omega G)\thinspace q^\prime + K q = F(t),$$
///
/// ROSS's convention (`rotor.M()`, `rotor.C(W)`, `rotor.G()`, `rotor.K(W)`; `G` does not
/// depend on the speed and is multiplied by it). `C` and `K` hold the bearings' coefficients
/// at the speed they were evaluated at. Dense, any size known at run time; `q` in m and rad.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct RotorMatrices {
    mass: DMatrix<f64>,
    damping: DMatrix<f64>,
    gyroscopic: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    layout: DofLayout,
}

/// The lateral directions kept by [`RotorMatrices::lateral`], in ROSS's per-node order.
const LATERAL_OF_ROSS6: [usize; 4] = [0, 1, 3, 4];

impl RotorMatrices {
    /// The rotor from its mass, damping, gyroscopic and stiffness matrices (`M`, `C`, `G`,
    /// `K`), in the given layout. Errors: a matrix that is not square, of another size than
    /// `M`, not a whole number of nodes, or with a non-finite entry; an `M` that is not
    /// symmetric positive definite ([`RotorError::NotSymmetric`],
    /// [`RotorError::MassNotPositiveDefinite`]) or a `G` that is not skew-symmetric
    /// ([`RotorError::NotSkewSymmetric`]). `C` and `K` may be non-symmetric (cross-coupled
    /// bearings).
    pub fn new(
        mass: DMatrix<f64>,
        damping: DMatrix<f64>,
        gyroscopic: DMatrix<f64>,
        stiffness: DMatrix<f64>,
        layout: DofLayout,
    ) -> Result<Self, RotorError> {
        let n = mass.nrows();
        let per_node = layout.per_node();
        if n == 0 || !n.is_multiple_of(per_node) {
            return Err(RotorError::DofCount { dofs: n, per_node });
        }
        for (name, m) in [
            ("M", &mass),
            ("C", &damping),
            ("G", &gyroscopic),
            ("K", &stiffness),
        ] {
            check_matrix(name, m, n)?;
        }
        check_mass(&mass)?;
        check_gyroscopic(&gyroscopic)?;
        Ok(Self {
            mass,
            damping,
            gyroscopic,
            stiffness,
            layout,
        })
    }

    /// Mass matrix `M`.
    pub fn mass(&self) -> &DMatrix<f64> {
        &self.mass
    }
    /// Damping matrix `C` (at the speed the matrices were exported at).
    pub fn damping(&self) -> &DMatrix<f64> {
        &self.damping
    }
    /// Gyroscopic matrix `G` (multiplied by the spin speed in the equation of motion).
    pub fn gyroscopic(&self) -> &DMatrix<f64> {
        &self.gyroscopic
    }
    /// Stiffness matrix `K` (at the speed the matrices were exported at).
    pub fn stiffness(&self) -> &DMatrix<f64> {
        &self.stiffness
    }
    /// The DOF layout.
    pub fn layout(&self) -> DofLayout {
        self.layout
    }
    /// Number of DOFs.
    pub fn dofs(&self) -> usize {
        self.mass.nrows()
    }
    /// Number of nodes.
    pub fn nodes(&self) -> usize {
        self.dofs() / self.layout.per_node()
    }

    /// Global index of a node's x DOF (its y DOF is the next one). Error: a node out of range.
    pub fn x_dof(&self, node: usize) -> Result<usize, RotorError> {
        if node >= self.nodes() {
            return Err(RotorError::NodeOutOfRange {
                node,
                nodes: self.nodes(),
            });
        }
        Ok(self.layout.per_node() * node)
    }

    /// The lateral DOFs only (`x, y, alpha, beta` of every node, [`DofLayout::Lateral4`]):
    /// in ROSS's export the axial and torsional DOFs (`z`, `theta`) are exactly uncoupled from
    /// them and have no stiffness to ground (`K` is singular), so a lateral contact leaves them
    /// at rest and they are dropped. Error: a non-zero coupling entry (named), which would make
    /// dropping them wrong. A [`DofLayout::Lateral4`] rotor is returned as it is.
    pub fn lateral(&self) -> Result<Self, RotorError> {
        if self.layout == DofLayout::Lateral4 {
            return Ok(self.clone());
        }
        let keep: Vec<usize> = (0..self.nodes())
            .flat_map(|node| LATERAL_OF_ROSS6.map(|d| 6 * node + d))
            .collect();
        let is_kept = |i: usize| LATERAL_OF_ROSS6.contains(&(i % 6));
        for (name, m) in self.named() {
            for j in 0..m.ncols() {
                for i in 0..m.nrows() {
                    if is_kept(i) != is_kept(j) && m[(i, j)] != 0.0 {
                        return Err(RotorError::LateralCoupling {
                            matrix: name,
                            row: i,
                            col: j,
                            value: m[(i, j)],
                        });
                    }
                }
            }
        }
        let pick = |m: &DMatrix<f64>| {
            DMatrix::from_fn(keep.len(), keep.len(), |i, j| m[(keep[i], keep[j])])
        };
        Ok(Self {
            mass: pick(&self.mass),
            damping: pick(&self.damping),
            gyroscopic: pick(&self.gyroscopic),
            stiffness: pick(&self.stiffness),
            layout: DofLayout::Lateral4,
        })
    }

    fn named(&self) -> [(&'static str, &DMatrix<f64>); 4] {
        [
            ("M", &self.mass),
            ("C", &self.damping),
            ("G", &self.gyroscopic),
            ("K", &self.stiffness),
        ]
    }
}

/// Checks that `m` is `n` x `n` ([`RotorError::MatrixShape`]) with finite entries
/// ([`RotorError::MatrixEntry`]), naming it `name`: the rotor layer's one shape check.
pub(super) fn check_matrix(
    name: &'static str,
    m: &DMatrix<f64>,
    n: usize,
) -> Result<(), RotorError> {
    if m.nrows() != n || m.ncols() != n {
        return Err(RotorError::MatrixShape {
            matrix: name,
            rows: m.nrows(),
            cols: m.ncols(),
            expected: n,
        });
    }
    match m.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        Some((i, v)) => Err(RotorError::MatrixEntry {
            matrix: name,
            row: i % n,
            col: i / n,
            value: *v,
        }),
        None => Ok(()),
    }
}

/// Relative tolerance of the symmetry checks: far above the rounding of an assembled or
/// projected matrix ($T^{\mathsf T} M T$: about $10^{-16}$ of its entries), far below a
/// modelling mistake.
const SYMMETRY_RTOL: f64 = 1e-10;

/// Checks that the mass matrix `m` (square, finite: [`check_matrix`] first) is symmetric,
/// each pair to [`SYMMETRY_RTOL`] of $\sqrt{|m_{ii} m_{jj}|}$ (the bound of $|m_{ij}|$ for a
/// positive definite matrix, in the units of the pair's DOFs) or of the pair itself
/// ([`RotorError::NotSymmetric`]), and positive definite: a Cholesky factorisation, and on
/// failure the lowest eigenvalue and the DOF where its mode is largest
/// ([`RotorError::MassNotPositiveDefinite`]).
pub(super) fn check_mass(m: &DMatrix<f64>) -> Result<(), RotorError> {
    let n = m.nrows();
    for j in 0..n {
        for i in j + 1..n {
            let (value, transposed) = (m[(i, j)], m[(j, i)]);
            let size = (m[(i, i)] * m[(j, j)])
                .abs()
                .sqrt()
                .max(value.abs())
                .max(transposed.abs());
            if (value - transposed).abs() > SYMMETRY_RTOL * size {
                return Err(RotorError::NotSymmetric {
                    matrix: "M",
                    row: i,
                    col: j,
                    value,
                    transposed,
                });
            }
        }
    }
    if Cholesky::new(m.clone()).is_some() {
        return Ok(());
    }
    let eigen = SymmetricEigen::new(m.clone());
    let lowest = eigen.eigenvalues.imin();
    Err(RotorError::MassNotPositiveDefinite {
        eigenvalue: eigen.eigenvalues[lowest],
        dof: eigen.eigenvectors.column(lowest).iamax(),
    })
}

/// Checks that the gyroscopic matrix `g` (square, finite) is skew-symmetric, each pair to
/// [`SYMMETRY_RTOL`] of the pair's larger entry plus $10^{-14}$ of the largest entry
/// ([`RotorError::NotSkewSymmetric`]; the diagonal must then vanish to the same tolerance).
pub(super) fn check_gyroscopic(g: &DMatrix<f64>) -> Result<(), RotorError> {
    let floor = 1e-14 * g.amax();
    for j in 0..g.ncols() {
        for i in j..g.nrows() {
            let (value, transposed) = (g[(i, j)], g[(j, i)]);
            if (value + transposed).abs()
                > SYMMETRY_RTOL * value.abs().max(transposed.abs()) + floor
            {
                return Err(RotorError::NotSkewSymmetric {
                    row: i,
                    col: j,
                    value,
                    transposed,
                });
            }
        }
    }
    Ok(())
}
