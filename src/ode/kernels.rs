//! Component-wise vector kernels of the Runge–Kutta formulas.
//!
//! Loops over slices that write into preallocated vectors, so that nothing
//! is allocated for [`Dyn`](nalgebra::Dyn) and fixed sizes unroll. Each
//! kernel performs, component by component, exactly the floating-point
//! operations of the vector expression in its doc, in the same order (Rust
//! does not contract `a * b + c` into a fused multiply-add), so its results
//! are bitwise identical to that expression evaluated with nalgebra
//! temporaries.

/// $\text{out} = y + (k_1 a_1 + k_2 a_2 + \dots + k_M a_M)\thinspace h$,
/// summed left to right.
#[inline(always)]
pub(crate) fn lin_comb<const M: usize>(
    out: &mut [f64],
    y: &[f64],
    h: f64,
    ks: [&[f64]; M],
    a: [f64; M],
) {
    let n = out.len();
    let y = &y[..n];
    let ks = ks.map(|k| &k[..n]);
    for i in 0..n {
        let mut acc = ks[0][i] * a[0];
        for j in 1..M {
            acc += ks[j][i] * a[j];
        }
        out[i] = y[i] + acc * h;
    }
}

/// $\text{out} = y + k\thinspace c$.
#[inline(always)]
pub(crate) fn axpy(out: &mut [f64], y: &[f64], k: &[f64], c: f64) {
    let n = out.len();
    let (y, k) = (&y[..n], &k[..n]);
    for i in 0..n {
        out[i] = y[i] + k[i] * c;
    }
}

/// Whether every component is finite.
#[inline]
pub(crate) fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// `combo!(out, y, h, [k[0] => A1, k[3] => A4])` calls [`lin_comb`] on the
/// slices of nalgebra vectors.
macro_rules! combo {
    ($out:expr, $y:expr, $h:expr, [$($k:expr => $a:expr),+ $(,)?]) => {
        $crate::ode::kernels::lin_comb(
            $out.as_mut_slice(),
            $y.as_slice(),
            $h,
            [$($k.as_slice()),+],
            [$($a),+],
        )
    };
}
pub(crate) use combo;
