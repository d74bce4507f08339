//! Eigen-decomposition of a real non-symmetric matrix ([`eigen_decomposition`]).

use nalgebra::{Complex, DMatrix, DVector, Schur};

use super::lu::{lu_factor, lu_solve};
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
/// nalgebra computes the Schur form but no eigenvectors of a non-symmetric matrix. Here the
/// matrix is balanced (a diagonal similarity $A_b = D^{-1} A D$ by powers of 2, Parlett and
/// Reinsch, as LAPACK's `gebal` does before `geev`: a state matrix
/// $\begin{pmatrix}0 & I\\\\ -M^{-1}K & -M^{-1}D\end{pmatrix}$ has blocks of sizes 1 and
/// $\omega_\text{max}^2$, and without balancing the Schur form's backward error
/// $\varepsilon|A|$ would swamp the low modes), reduced to the *complex* Schur form
/// $A_b = Q T Q^{\mathsf H}$ (nalgebra's [`Schur`] over `Complex<f64>`: $T$ upper
/// triangular), and the eigenvectors of $T$ are found by back-substitution (LAPACK's `trevc`,
/// with its guard on tiny divisors), $V = Q Y$, columns scaled to unit 2-norm. The inverse
/// comes from the crate's LU.
///
/// Everything is returned **in balanced coordinates**: $A = D V \Lambda V^{-1} D^{-1}$. The
/// condition number $\kappa_1(V) = |V|_1|V^{-1}|_1$ measures how much rounding the modal
/// coordinates $w = V^{-1} z$ amplify (about $\kappa\varepsilon$ relative); a near-defective
/// matrix (two modes close to coalescing, e.g. a mode near critical damping) has a large
/// $\kappa$, a defective one an infinite or enormous one. What to accept is the caller's
/// decision; the decomposition only reports.
///
/// # Errors
/// [`NumericError::NotSquare`], [`NumericError::NonFiniteMatrix`],
/// [`NumericError::NoConvergence`] (the Schur iteration), [`NumericError::SingularEigenvectors`]
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
    let (ab, scale) = balance(a);
    let ac = ab.map(|v| Complex::new(v, 0.0));
    let iterations = 100 * n;
    let schur = Schur::try_new(ac.clone(), f64::EPSILON, iterations)
        .ok_or(NumericError::NoConvergence { iterations })?;
    let (q, t) = schur.unpack();
    let values = DVector::from_fn(n, |i, _| t[(i, i)]);
    let mut vectors = q * triangular_eigenvectors(&t);
    for mut col in vectors.column_iter_mut() {
        let norm = col.norm();
        col /= Complex::new(norm, 0.0);
    }
    let inverse = invert(&vectors)?;
    let norm1 = |m: &DMatrix<Complex<f64>>| {
        m.column_iter()
            .map(|c| c.iter().map(|v| v.norm()).sum::<f64>())
            .fold(0.0, f64::max)
    };
    let lambda = DMatrix::from_diagonal(&values);
    let a_norm = norm1(&ac).max(f64::MIN_POSITIVE);
    let v_norm = norm1(&vectors);
    let av = &ac * &vectors;
    let residual = norm1(&(&av - &vectors * &lambda)) / (a_norm * v_norm);
    let reconstruction = norm1(&(&vectors * &lambda * &inverse - &ac)) / a_norm;
    Ok(EigenDecomposition {
        scale,
        condition: v_norm * norm1(&inverse),
        values,
        vectors,
        inverse,
        residual,
        reconstruction,
    })
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

/// Eigenvectors $Y$ of the upper triangular `t` ($T y_k = t_{kk} y_k$, $y_{kk} = 1$, zero
/// below), by back-substitution; a divisor $t_{ii} - t_{kk}$ below
/// $\varepsilon\max(|t_{kk}|, |T|)$ is replaced by that size (LAPACK `ztrevc`): a repeated
/// eigenvalue then gives nearly parallel vectors, which the condition number reports.
fn triangular_eigenvectors(t: &DMatrix<Complex<f64>>) -> DMatrix<Complex<f64>> {
    let n = t.nrows();
    let t_norm = t.iter().map(|v| v.norm()).fold(0.0, f64::max);
    let mut y = DMatrix::from_element(n, n, Complex::new(0.0, 0.0));
    for k in 0..n {
        let tkk = t[(k, k)];
        let smin = (f64::EPSILON * tkk.norm().max(t_norm * f64::EPSILON)).max(f64::MIN_POSITIVE);
        y[(k, k)] = Complex::new(1.0, 0.0);
        for i in (0..k).rev() {
            let mut sum = Complex::new(0.0, 0.0);
            for j in i + 1..=k {
                sum += t[(i, j)] * y[(j, k)];
            }
            let mut den = t[(i, i)] - tkk;
            if den.norm() < smin {
                den = Complex::new(smin, 0.0);
            }
            y[(i, k)] = -sum / den;
        }
    }
    y
}

/// $V^{-1}$ by LU with partial pivoting (the crate's one LU).
fn invert(v: &DMatrix<Complex<f64>>) -> Result<DMatrix<Complex<f64>>, NumericError> {
    let n = v.nrows();
    let mut lu = v.clone();
    let mut piv = vec![0; n];
    lu_factor(lu.as_mut_slice(), n, &mut piv)
        .map_err(|column| NumericError::SingularEigenvectors { column })?;
    let mut inv = DMatrix::identity(n, n);
    for mut col in inv.column_iter_mut() {
        lu_solve(lu.as_slice(), n, &piv, col.as_mut_slice());
    }
    Ok(inv)
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
