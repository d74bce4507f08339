//! Dense LU factorisation with partial pivoting, in place on preallocated storage.
//!
//! nalgebra's `LU` allocates its result for [`Dyn`](nalgebra::Dyn) sizes; the implicit
//! integrators factor a matrix per step size and may not allocate while stepping, so they
//! factor into buffers they own. One implementation, generic over the scalar: `f64` for the
//! real system of RADAU5 and `Complex<f64>` for its complex one.
//!
//! The matrix is an $n\times n$ slice in column-major order (entry $(i, j)$ at `i + j * n`,
//! nalgebra's layout). [`lu_factor`] overwrites it with $L$ (unit lower, below the diagonal)
//! and $U$ (on and above it) of $P A = L U$, and records the row swaps in `piv`;
//! [`lu_solve`] then solves $A x = b$ in place with two triangular sweeps.

use nalgebra::ComplexField;

/// The scalar of a factorisation: `f64` or `Complex<f64>`.
pub(crate) trait LuScalar: ComplexField<RealField = f64> + Copy {}
impl<T: ComplexField<RealField = f64> + Copy> LuScalar for T {}

/// Factors the column-major $n\times n$ matrix `a` in place ($P A = L U$, partial pivoting on
/// the largest $|\mathrm{re}| + |\mathrm{im}|$ of the column). `piv[k]` is the row swapped
/// with row `k` at elimination step `k`. Returns `Err(k)` when the pivot of column `k` is
/// zero or not finite (the matrix is singular to working precision; `a` is then unusable).
pub(crate) fn lu_factor<T: LuScalar>(
    a: &mut [T],
    n: usize,
    piv: &mut [usize],
) -> Result<(), usize> {
    debug_assert!(a.len() >= n * n && piv.len() >= n);
    for k in 0..n {
        let col = k * n;
        let mut p = k;
        let mut best = a[col + k].norm1();
        for i in k + 1..n {
            let v = a[col + i].norm1();
            if v > best {
                best = v;
                p = i;
            }
        }
        piv[k] = p;
        if !(best > 0.0 && best.is_finite()) {
            return Err(k);
        }
        if p != k {
            for j in 0..n {
                a.swap(j * n + k, j * n + p);
            }
        }
        let inv = T::one() / a[col + k];
        for i in k + 1..n {
            a[col + i] *= inv;
        }
        // Right-looking update of the trailing columns (contiguous axpys).
        let (left, right) = a.split_at_mut((k + 1) * n);
        let lk = &left[col + k + 1..col + n];
        for j in 0..n - k - 1 {
            let cj = &mut right[j * n..(j + 1) * n];
            let ukj = cj[k];
            if ukj != T::zero() {
                for (x, &l) in cj[k + 1..].iter_mut().zip(lk) {
                    *x -= l * ukj;
                }
            }
        }
    }
    Ok(())
}

/// Solves $A x = b$ in place (`b` becomes $x$) with the factors left in `a` and `piv` by
/// [`lu_factor`].
pub(crate) fn lu_solve<T: LuScalar>(a: &[T], n: usize, piv: &[usize], b: &mut [T]) {
    for k in 0..n {
        b.swap(k, piv[k]);
    }
    // L y = P b (unit diagonal), column by column.
    for k in 0..n {
        let bk = b[k];
        if bk != T::zero() {
            for (x, &l) in b[k + 1..n].iter_mut().zip(&a[k * n + k + 1..(k + 1) * n]) {
                *x -= l * bk;
            }
        }
    }
    // U x = y, column by column from the last.
    for k in (0..n).rev() {
        let xk = b[k] / a[k * n + k];
        b[k] = xk;
        if xk != T::zero() {
            for (x, &u) in b[..k].iter_mut().zip(&a[k * n..k * n + k]) {
                *x -= u * xk;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Complex, DMatrix, DVector};

    /// Against nalgebra's own LU (an independent implementation) on a matrix that needs pivoting.
    #[test]
    fn real_solve_matches_nalgebra() {
        let n = 5;
        let m = DMatrix::from_fn(n, n, |i, j| {
            if i == j {
                1e-3
            } else {
                ((i * 7 + j * 3) % 5) as f64 - 2.0
            }
        });
        let b = DVector::from_fn(n, |i, _| i as f64 + 1.0);
        let want = m.clone().lu().solve(&b).unwrap();
        let mut a = m.as_slice().to_vec();
        let mut piv = vec![0; n];
        lu_factor(&mut a, n, &mut piv).unwrap();
        let mut x = b.as_slice().to_vec();
        lu_solve(&a, n, &piv, &mut x);
        for i in 0..n {
            assert!(
                (x[i] - want[i]).abs() < 1e-12 * want.amax(),
                "{i}: {} {}",
                x[i],
                want[i]
            );
        }
    }

    /// The residual of a complex solve is at rounding level.
    #[test]
    fn complex_residual_is_small() {
        let n = 4;
        let m = DMatrix::from_fn(n, n, |i, j| {
            Complex::new(
                (i + 2 * j) as f64 % 3.0 - 1.0,
                if i == j { 2.0 } else { 0.5 },
            )
        });
        let b = DVector::from_fn(n, |i, _| Complex::new(1.0, i as f64));
        let mut a = m.as_slice().to_vec();
        let mut piv = vec![0; n];
        lu_factor(&mut a, n, &mut piv).unwrap();
        let mut x = b.as_slice().to_vec();
        lu_solve(&a, n, &piv, &mut x);
        let r = &m * DVector::from_vec(x) - b;
        assert!(r.iter().all(|v| v.norm() < 1e-13), "{r}");
    }

    /// A singular matrix is reported with the column of its zero pivot.
    #[test]
    fn singular_is_reported() {
        let mut a = vec![1.0, 2.0, 2.0, 4.0];
        let mut piv = vec![0; 2];
        assert_eq!(lu_factor(&mut a, 2, &mut piv), Err(1));
    }
}

#[cfg(test)]
mod bench {
    use super::*;
    use nalgebra::Complex;
    use std::time::Instant;

    fn matrix<T: LuScalar>(n: usize, entry: impl Fn(usize, usize) -> T) -> Vec<T> {
        (0..n * n).map(|k| entry(k % n, k / n)).collect()
    }

    /// GFlop/s of the factorisation against $\tfrac23 n^3$ (real) and $\tfrac83 n^3$ real
    /// flops (complex); run with `--ignored --nocapture` in release.
    #[test]
    #[ignore]
    fn lu_speed() {
        for n in [137, 274] {
            let re = |i: usize, j: usize| {
                ((i * 7 + j * 13) % 17) as f64 - 8.0 + if i == j { 40.0 } else { 0.0 }
            };
            let a0 = matrix(n, re);
            let c0 = matrix(n, |i, j| Complex::new(re(i, j), ((i + 3 * j) % 5) as f64));
            let mut piv = vec![0; n];
            let reps = 20;
            let (mut a, mut c) = (a0.clone(), c0.clone());
            let t = Instant::now();
            for _ in 0..reps {
                a.copy_from_slice(&a0);
                lu_factor(&mut a, n, &mut piv).unwrap();
            }
            let real = t.elapsed().as_secs_f64() / reps as f64;
            let t = Instant::now();
            for _ in 0..reps {
                c.copy_from_slice(&c0);
                lu_factor(&mut c, n, &mut piv).unwrap();
            }
            let cplx = t.elapsed().as_secs_f64() / reps as f64;
            let flops = 2.0 / 3.0 * (n as f64).powi(3);
            println!(
                "n = {n}: real {:.2} ms {:.2} GFlop/s, complex {:.2} ms {:.2} GFlop/s (real flops)",
                real * 1e3,
                flops / real * 1e-9,
                cplx * 1e3,
                4.0 * flops / cplx * 1e-9
            );
        }
    }
}
