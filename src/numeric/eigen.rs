//! Eigen-decomposition of a real non-symmetric matrix ([`eigen_decomposition`]).

use faer::linalg::solvers::DenseSolveCore;
use faer::{Mat, MatRef};
use nalgebra::{Complex, DMatrix, DVector};

use super::NumericError;

/// $A = D V \Lambda V^{-1} D^{-1}$ ([`eigen_decomposition`]).
#[derive(Debug, Clone, PartialEq)]
pub struct EigenDecomposition {
    /// The balancing scales $D$ (powers of 2).
    pub scale: DVector<f64>,
    /// The eigenvalues $\lambda_k$ (complex pairs of a real matrix in either order).
    pub values: DVector<Complex<f64>>,
    /// The eigenvectors of the balanced matrix, columns of unit 2-norm.
    pub vectors: DMatrix<Complex<f64>>,
    /// $V^{-1}$.
    pub inverse: DMatrix<Complex<f64>>,
    /// $\kappa_1(V) = |V|_1 |V^{-1}|_1$.
    pub condition: f64,
    /// $|A_b V - V\Lambda|_1 / (|A_b|_1 |V|_1)$: the eigenpairs' backward error.
    pub residual: f64,
    /// $|V\Lambda V^{-1} - A_b|_1 / |A_b|_1$: how well the decomposition rebuilds the matrix.
    pub reconstruction: f64,
}

/// The eigenvalues, eigenvectors and inverse eigenvector matrix of the real square matrix `a`.
///
/// The matrix is balanced (a diagonal similarity $A_b = D^{-1} A D$ by powers of 2, Parlett and
/// Reinsch, as LAPACK's `gebal` does before `geev`: a state matrix
/// $\begin{pmatrix}0 & I\\\\ -M^{-1}K & -M^{-1}D\end{pmatrix}$ has blocks of sizes 1 and
/// $\omega_\text{max}^2$, and without balancing the Schur form's backward error
/// $\varepsilon|A|$ would swamp the low modes), then decomposed by faer as a complex matrix
/// (the blocked Hessenberg reduction, the complex Schur form $A_b = QTQ^{\mathsf H}$ by
/// multishift QR and the eigenvectors of $T$ by back-substitution, as LAPACK's `zgeev`:
/// $O(n^3)$ in level-3 kernels), the eigenvector columns scaled to unit 2-norm, and $V^{-1}$
/// found by faer's LU with partial pivoting. Complex, not the real Schur form: the real
/// path's quasi-triangular back-substitution returns nearly parallel vectors for a repeated
/// complex pair (measured: $\kappa_1(V) = 8.6\times10^{19}$ on an 8-DOF rotor whose pair is
/// 7-fold, $10^3$ from the complex form), and every pair of an isotropic rotor without
/// gyroscopic coupling is double. The complex form costs about 2.5 times as much (0.75 s against 0.30 s at 672 states).
///
/// Everything is returned **in balanced coordinates**: $A = D V \Lambda V^{-1} D^{-1}$. The
/// condition number $\kappa_1(V) = |V|_1|V^{-1}|_1$ measures how much rounding the modal
/// coordinates $w = V^{-1} z$ amplify (about $\kappa\varepsilon$ relative); a near-defective
/// matrix (two modes close to coalescing, e.g. a mode near critical damping) has a large
/// $\kappa$, a defective one an infinite or enormous one. The backward errors are measured,
/// not assumed: the residual $|A_b V - V\Lambda|_1$ and the reconstruction
/// $|V\Lambda V^{-1} - A_b|_1$, each relative. What to accept is the caller's decision; the
/// decomposition only reports.
///
/// # Errors
/// [`NumericError::NotSquare`], [`NumericError::NonFiniteMatrix`],
/// [`NumericError::NoConvergence`] (the QR iteration), [`NumericError::SingularEigenvectors`]
/// (a defective matrix whose eigenvectors are dependent to working precision).
pub fn eigen_decomposition(a: &DMatrix<f64>) -> Result<EigenDecomposition, NumericError> {
    let n = a.nrows();
    if a.ncols() != n || n == 0 {
        return Err(NumericError::NotSquare {
            rows: n,
            cols: a.ncols(),
        });
    }
    if let Some(&value) = a.iter().find(|v| !v.is_finite()) {
        return Err(NumericError::NonFiniteMatrix { value });
    }
    let decomposition = decompose(a);
    clear_upper_state();
    decomposition
}

/// [`eigen_decomposition`] of a checked matrix.
fn decompose(a: &DMatrix<f64>) -> Result<EigenDecomposition, NumericError> {
    let n = a.nrows();
    let (ab, scale) = balance(a);
    let ac = Mat::<Complex<f64>>::from_fn(n, n, |i, j| Complex::new(ab[(i, j)], 0.0));
    let evd = ac
        .eigen()
        .map_err(|_| NumericError::NoConvergence { size: n })?;
    let values: Vec<Complex<f64>> = (0..n).map(|k| evd.S()[k]).collect();
    let mut vectors = evd.U().to_owned();
    for k in 0..n {
        let norm = vectors.col(k).norm_l2();
        for i in 0..n {
            vectors[(i, k)] /= norm;
        }
    }
    let inverse = invert(vectors.as_ref())?;
    let scaled = Mat::<Complex<f64>>::from_fn(n, n, |i, k| vectors[(i, k)] * values[k]);
    let a_norm = norm1(ac.as_ref()).max(f64::MIN_POSITIVE);
    let v_norm = norm1(vectors.as_ref());
    let residual = norm1((&ac * &vectors - &scaled).as_ref()) / (a_norm * v_norm);
    let reconstruction = norm1((&scaled * &inverse - &ac).as_ref()) / a_norm;
    Ok(EigenDecomposition {
        scale,
        condition: v_norm * norm1(inverse.as_ref()),
        values: DVector::from_vec(values),
        vectors: DMatrix::from_fn(n, n, |i, j| vectors[(i, j)]),
        inverse: DMatrix::from_fn(n, n, |i, j| inverse[(i, j)]),
        residual,
        reconstruction,
    })
}

/// Clears the upper halves of the vector registers, by returning from a 256-bit operation
/// (the compiler ends such a function with `vzeroupper`). faer's assembly matrix kernels return
/// with them dirty, and on x86 every later non-VEX instruction (the crate's scalar code, built
/// for baseline x86-64) then waits on them: measured, $\varphi$-functions took 370 ns instead
/// of 21 ns after a decomposition until this ran, and S1's modal ETD4 run 5.3 s instead of
/// 0.68 s. A no-op where no such state exists.
fn clear_upper_state() {
    struct Touch(f64);
    impl pulp::WithSimd for Touch {
        type Output = f64;
        #[inline(always)]
        fn with_simd<S: pulp::Simd>(self, simd: S) -> f64 {
            let v = simd.splat_f64s(std::hint::black_box(self.0));
            simd.reduce_sum_f64s(simd.mul_add_f64s(v, v, v))
        }
    }
    std::hint::black_box(pulp::Arch::new().dispatch(Touch(0.0)));
}

/// $|M|_1$, the largest column sum of moduli.
fn norm1(m: MatRef<'_, Complex<f64>>) -> f64 {
    (0..m.ncols())
        .map(|j| (0..m.nrows()).map(|i| m[(i, j)].norm()).sum::<f64>())
        .fold(0.0, f64::max)
}

/// $D^{-1} A D$ with $D$ of powers of 2 making each row's and column's off-diagonal 1-norms
/// comparable (Parlett and Reinsch; LAPACK `gebal` without the permutations). Exact in
/// floating point: only exponents change.
fn balance(a: &DMatrix<f64>) -> (DMatrix<f64>, DVector<f64>) {
    let n = a.nrows();
    let mut b = a.clone();
    let mut d = DVector::from_element(n, 1.0);
    for _sweep in 0..200 {
        let mut done = true;
        for i in 0..n {
            let mut c: f64 = (0..n).filter(|&j| j != i).map(|j| b[(j, i)].abs()).sum();
            let r: f64 = (0..n).filter(|&j| j != i).map(|j| b[(i, j)].abs()).sum();
            if c == 0.0 || r == 0.0 {
                continue;
            }
            let s = c + r;
            let mut f = 1.0;
            while c < r / 2.0 {
                f *= 2.0;
                c *= 4.0;
            }
            while c > r * 2.0 {
                f /= 2.0;
                c /= 4.0;
            }
            if (c + r) / f < 0.95 * s {
                done = false;
                d[i] *= f;
                b.row_mut(i).scale_mut(1.0 / f);
                b.column_mut(i).scale_mut(f);
            }
        }
        if done {
            break;
        }
    }
    (b, d)
}

/// $V^{-1}$ by faer's LU with partial pivoting; a zero pivot (dependent eigenvectors to working
/// precision) is an error naming its column.
fn invert(v: MatRef<'_, Complex<f64>>) -> Result<Mat<Complex<f64>>, NumericError> {
    let lu = v.partial_piv_lu();
    let u = lu.U();
    if let Some(column) = (0..v.ncols()).find(|&k| u[(k, k)].norm() == 0.0) {
        return Err(NumericError::SingularEigenvectors { column });
    }
    Ok(lu.inverse())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_with_decay() {
        // [[a, b], [-b, a]]: eigenvalues a +- i b (the closed form).
        let (a, b) = (-0.3, 2.0);
        let m = DMatrix::from_row_slice(2, 2, &[a, b, -b, a]);
        let e = eigen_decomposition(&m).unwrap();
        let mut ims: Vec<f64> = e.values.iter().map(|v| v.im).collect();
        ims.sort_by(f64::total_cmp);
        assert!((ims[0] + b).abs() < 1e-15 && (ims[1] - b).abs() < 1e-15);
        assert!(e.values.iter().all(|v| (v.re - a).abs() < 1e-15));
        assert!(e.residual < 1e-15 && e.reconstruction < 1e-15, "{e:?}");
    }

    #[test]
    fn similar_block_diagonal_matrix_has_its_known_eigenvalues() {
        // A = S B S^{-1}, B block-diagonal with 2x2 blocks [[a, b], [-b, a]] (eigenvalues
        // a +- i b) over six decades of |lambda| and two real ones; S a fixed well-conditioned
        // matrix. The eigenvalues are known exactly; the Schur form's are within its backward
        // error eps |A| (measured: 4e-11 relative for the slowest pair, as the dense S mixes
        // the scales that balancing would otherwise separate, 1e-15 for the fast ones).
        let pairs = [
            (-0.01, 1.0),
            (-3.0, 40.0),
            (-50.0, 2e3),
            (-2e3, 1e5),
            (-4e4, 1e6),
        ];
        let n = 2 * pairs.len() + 2;
        let mut b = DMatrix::zeros(n, n);
        let mut want = Vec::new();
        for (k, &(re, im)) in pairs.iter().enumerate() {
            let i = 2 * k;
            b[(i, i)] = re;
            b[(i + 1, i + 1)] = re;
            b[(i, i + 1)] = im;
            b[(i + 1, i)] = -im;
            want.push(Complex::new(re, im));
            want.push(Complex::new(re, -im));
        }
        b[(n - 2, n - 2)] = -7.0;
        b[(n - 1, n - 1)] = -3e5;
        want.push(Complex::new(-7.0, 0.0));
        want.push(Complex::new(-3e5, 0.0));
        let s = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                2.0
            } else {
                0.3 * ((1 + i * n + j) as f64).sin()
            }
        });
        let a = &s * b * s.clone().try_inverse().unwrap();
        let e = eigen_decomposition(&a).unwrap();
        for w in &want {
            let nearest = e
                .values
                .iter()
                .map(|v| (v - w).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < 1e-10 * w.norm(), "{w}: {nearest:e}");
        }
        assert!(e.residual < 1e-13 && e.reconstruction < 1e-12, "{e:?}");
        assert!(e.condition < 1e3, "{}", e.condition);
    }

    #[test]
    fn defective_jordan_block_is_reported_ill_conditioned() {
        // [[1, 1], [0, 1]] has one eigenvector: V is singular or its condition enormous.
        let m = DMatrix::from_row_slice(2, 2, &[1.0, 1.0, 0.0, 1.0]);
        match eigen_decomposition(&m) {
            Err(NumericError::SingularEigenvectors { .. }) => {}
            Ok(e) => assert!(e.condition > 1e12, "{}", e.condition),
            Err(e) => panic!("{e}"),
        }
    }
}
