//! The dominant eigenvalues of a linear operator known only by its action ([`arnoldi`]).

use nalgebra::{Complex, DMatrix, DVector};

use super::{eigen_decomposition, ArnoldiInput, NumericError};

/// Options of [`arnoldi`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ArnoldiOptions {
    /// How many eigenvalues of largest modulus are wanted (at least 1).
    pub count: usize,
    /// The largest Krylov dimension (the number of actions at most, plus one): the iteration
    /// stops there, converged or not.
    pub max_dim: usize,
    /// The Ritz pairs' residual $|A x - \theta x|$ ($|x| = 1$) at which a wanted value is
    /// converged, relative to the largest Ritz value's modulus.
    pub tol: f64,
}

impl Default for ArnoldiOptions {
    /// Six values, dimension 100, residual $10^{-10}$.
    fn default() -> Self {
        ArnoldiOptions {
            count: 6,
            max_dim: 100,
            tol: 1e-10,
        }
    }
}

/// The Ritz values of [`arnoldi`].
#[derive(Debug, Clone, PartialEq)]
pub struct RitzValues {
    /// The `count` Ritz values of largest modulus (fewer if the space is smaller), largest
    /// first.
    pub values: Vec<Complex<f64>>,
    /// Each one's residual $|A x - \theta x|$ for its unit Ritz vector $x$, relative to the
    /// largest value's modulus.
    pub residuals: Vec<f64>,
    /// The Krylov dimension reached (the number of actions).
    pub dim: usize,
    /// Whether every residual is within the tolerance (or the space is invariant).
    pub converged: bool,
}

/// The eigenvalues of largest modulus of the real $n \times n$ operator $A$ whose action `apply`
/// ($v \mapsto Av$) is all that is known: the Arnoldi iteration from `start`.
///
/// The Krylov basis $V_m$ is built by classical Gram-Schmidt applied twice (orthogonal to
/// working precision), $A V_m = V_m H_m + h_{m+1,m} v_{m+1} e_m^{\mathsf T}$; the Ritz values are
/// the eigenvalues $\theta$ of the Hessenberg $H_m$ ([`eigen_decomposition`]) and the residual of
/// the Ritz pair $(\theta, V_m y)$, $|y| = 1$, is $|h_{m+1,m}|\thinspace|e_m^{\mathsf T} y|$
/// without another action. Every 4 actions once $m \ge$ `count` $+ 4$, the iteration stops when
/// the `count` largest are converged, or when $h_{m+1,m}$ vanishes (an invariant subspace: its
/// Ritz values are eigenvalues), or at `max_dim` (then `converged` is false and the values are
/// the best found). No restarts: the dominant values of a contracting map (Floquet
/// multipliers of a damped orbit, most of them near zero) converge in a few dozen actions.
///
/// ```
/// use jeffcott::nalgebra::{DMatrix, DVector};
/// use jeffcott::numeric::{arnoldi, ArnoldiInput, ArnoldiOptions, NumericError};
///
/// // 200 x 200: a quarter-turn rotation scaled by 0.9 (eigenvalues +-0.9i), then 1/4, 1/5, ...
/// let n = 200;
/// let mut a = DMatrix::from_fn(n, n, |i, j| if i == j { 1.0 / (i + 2) as f64 } else { 0.0 });
/// (a[(0, 0)], a[(0, 1)], a[(1, 0)], a[(1, 1)]) = (0.0, -0.9, 0.9, 0.0);
/// let start = DVector::from_element(n, 1.0);
/// let opts = ArnoldiOptions { count: 3, ..ArnoldiOptions::default() };
/// let ritz = arnoldi(&start, |v| Ok::<_, NumericError>(&a * v), &opts)?;
/// assert!(ritz.converged && ritz.dim < 40);
/// assert!((ritz.values[0].im.abs() - 0.9).abs() < 1e-10 && ritz.values[0].re.abs() < 1e-10);
/// assert!((ritz.values[2].re - 0.25).abs() < 1e-10);
/// // No eigenvalue asked for: a typed error naming the option.
/// let none = ArnoldiOptions { count: 0, ..opts };
/// let err = arnoldi(&start, |v| Ok::<_, NumericError>(&a * v), &none).unwrap_err();
/// assert!(matches!(err, NumericError::InvalidArnoldi { field: ArnoldiInput::Count, .. }));
/// # Ok::<(), NumericError>(())
/// ```
///
/// # Errors
/// The error of `apply`, or a [`NumericError`] (converted) for a `start` of another size or
/// zero, an action of another size or non-finite, options out of range, or an eigenvalue
/// problem of $H_m$ that fails.
pub fn arnoldi<E: From<NumericError>>(
    start: &DVector<f64>,
    mut apply: impl FnMut(&DVector<f64>) -> Result<DVector<f64>, E>,
    opts: &ArnoldiOptions,
) -> Result<RitzValues, E> {
    let n = start.len();
    let bad = |field: ArnoldiInput, value: f64| NumericError::InvalidArnoldi { field, value };
    if opts.count == 0 || opts.count > n {
        return Err(bad(ArnoldiInput::Count, opts.count as f64).into());
    }
    if !(opts.tol > 0.0 && opts.tol.is_finite()) {
        return Err(bad(ArnoldiInput::Tol, opts.tol).into());
    }
    let norm = start.norm();
    if !(norm > 0.0 && norm.is_finite()) {
        return Err(bad(ArnoldiInput::Start, norm).into());
    }
    let max_dim = opts.max_dim.min(n).max(opts.count);
    let mut basis: Vec<DVector<f64>> = vec![start / norm];
    let mut h = DMatrix::<f64>::zeros(max_dim + 1, max_dim);
    for m in 1..=max_dim {
        let mut w = apply(&basis[m - 1])?;
        if w.len() != n || w.iter().any(|x| !x.is_finite()) {
            return Err(bad(ArnoldiInput::Action, w.len() as f64).into());
        }
        // Classical Gram-Schmidt, twice.
        for _ in 0..2 {
            for (i, v) in basis.iter().enumerate() {
                let c = v.dot(&w);
                h[(i, m - 1)] += c;
                w.axpy(-c, v, 1.0);
            }
        }
        let beta = w.norm();
        h[(m, m - 1)] = beta;
        let invariant = beta <= f64::EPSILON * h.column(m - 1).norm();
        let check = invariant || m == max_dim || (m >= opts.count + 4 && m % 4 == 0);
        if check {
            let ritz = ritz(&h, m, opts)?;
            if ritz.converged || invariant || m == max_dim {
                return Ok(RitzValues {
                    converged: ritz.converged || invariant,
                    ..ritz
                });
            }
        }
        basis.push(w / beta);
    }
    unreachable!("the loop returns at max_dim")
}

/// The Ritz values of $H_m$ and their residuals.
fn ritz(h: &DMatrix<f64>, m: usize, opts: &ArnoldiOptions) -> Result<RitzValues, NumericError> {
    let hm = h.view((0, 0), (m, m)).into_owned();
    let beta = h[(m, m - 1)];
    let evd = eigen_decomposition(&hm)?;
    let mut pairs: Vec<(Complex<f64>, f64)> = (0..m)
        .map(|k| {
            // The eigenvector of H_m: the balanced one scaled back, then made unit.
            let y = DVector::from_fn(m, |i, _| evd.vectors[(i, k)] * evd.scale[i]);
            (evd.values[k], beta * y[m - 1].norm() / y.norm())
        })
        .collect();
    pairs.sort_by(|a, b| {
        b.0.norm()
            .total_cmp(&a.0.norm())
            .then(b.0.im.total_cmp(&a.0.im))
    });
    pairs.truncate(opts.count);
    let largest = pairs[0].0.norm().max(f64::MIN_POSITIVE);
    let residuals: Vec<f64> = pairs.iter().map(|p| p.1 / largest).collect();
    Ok(RitzValues {
        values: pairs.iter().map(|p| p.0).collect(),
        converged: residuals.iter().all(|&r| r <= opts.tol),
        residuals,
        dim: m,
    })
}
