//! The coefficients of the three-stage Radau IIA method and of RADAU5's transformation.
//!
//! Butcher tableau (nodes $c_i$, matrix $A$, weights $b = $ the last row of $A$):
//! $$\begin{array}{c|ccc}
//! \frac{4-\sqrt6}{10} & \frac{88-7\sqrt6}{360} & \frac{296-169\sqrt6}{1800} & \frac{-2+3\sqrt6}{225}\\\\
//! \frac{4+\sqrt6}{10} & \frac{296+169\sqrt6}{1800} & \frac{88+7\sqrt6}{360} & \frac{-2-3\sqrt6}{225}\\\\
//! 1 & \frac{16-\sqrt6}{36} & \frac{16+\sqrt6}{36} & \frac19
//! \end{array}$$
//! $A^{-1}$ has one real eigenvalue $\gamma$ and a complex pair $\alpha \pm i\beta$; with the
//! real matrix $T$ of its (real and complex) eigenvectors,
//! $T^{-1} A^{-1} T = \begin{pmatrix}\gamma & 0 & 0\\\\ 0 & \alpha & -\beta\\\\ 0 & \beta & \alpha\end{pmatrix}$.
//! The digits of $T$ and $T^{-1}$ are those published with Hairer and Wanner's RADAU5; the
//! unit tests check both identities above to rounding.

// Kept with every published digit; Rust rounds them correctly.
#![allow(clippy::excessive_precision)]

/// $\sqrt 6$.
const SQ6: f64 = 2.449489742783178098197284074705891;
/// Nodes $c_1, c_2$ ($c_3 = 1$).
pub(super) const C1: f64 = (4.0 - SQ6) / 10.0;
pub(super) const C2: f64 = (4.0 + SQ6) / 10.0;

/// The real eigenvalue $\gamma$ of $A^{-1}$: $1/\gamma = (6 + 81^{1/3} - 9^{1/3})/30$.
pub(super) fn gamma() -> f64 {
    30.0 / (6.0 + 81f64.cbrt() - 9f64.cbrt())
}

/// The complex eigenvalues $\alpha \pm i\beta$ of $A^{-1}$ (the inverses of those of $A$,
/// $(12 - 81^{1/3} + 9^{1/3})/60 \pm i\thinspace(81^{1/3} + 9^{1/3})\sqrt3/60$).
pub(super) fn alpha_beta() -> (f64, f64) {
    let a = (12.0 - 81f64.cbrt() + 9f64.cbrt()) / 60.0;
    let b = (81f64.cbrt() + 9f64.cbrt()) * 3f64.sqrt() / 60.0;
    let n = a * a + b * b;
    (a / n, b / n)
}

/// Coefficients of the embedded error estimate, $\gamma_0$ times RADAU5's $e_i$:
/// $\mathrm{err} = (\tfrac{\gamma}{h} I - J)^{-1}\big(f(t, y) + \tfrac1h\sum_i d_i Z_i\big)$.
pub(super) const DD1: f64 = -(13.0 + 7.0 * SQ6) / 3.0;
pub(super) const DD2: f64 = (-13.0 + 7.0 * SQ6) / 3.0;
pub(super) const DD3: f64 = -1.0 / 3.0;

/// $T$ (row-major); $T_{32} = 1$, $T_{33} = 0$.
pub(super) const T: [[f64; 3]; 3] = [
    [
        9.1232394870892942792e-02,
        -0.14125529502095420843,
        -3.0029194105147424492e-02,
    ],
    [
        0.24171793270710701896,
        0.20412935229379993199,
        0.38294211275726193779,
    ],
    [0.96604818261509293619, 1.0, 0.0],
];

/// $T^{-1}$ (row-major).
pub(super) const TI: [[f64; 3]; 3] = [
    [
        4.3255798900631553510,
        0.33919925181580986954,
        0.54177053993587487119,
    ],
    [
        -4.1787185915519047273,
        -0.32768282076106238708,
        0.47662355450055045196,
    ],
    [
        -0.50287263494578687595,
        2.5719269498556054292,
        -0.59603920482822492497,
    ],
];

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;

    fn a_matrix() -> Matrix3<f64> {
        Matrix3::new(
            (88.0 - 7.0 * SQ6) / 360.0,
            (296.0 - 169.0 * SQ6) / 1800.0,
            (-2.0 + 3.0 * SQ6) / 225.0,
            (296.0 + 169.0 * SQ6) / 1800.0,
            (88.0 + 7.0 * SQ6) / 360.0,
            (-2.0 - 3.0 * SQ6) / 225.0,
            (16.0 - SQ6) / 36.0,
            (16.0 + SQ6) / 36.0,
            1.0 / 9.0,
        )
    }

    fn m(rows: [[f64; 3]; 3]) -> Matrix3<f64> {
        Matrix3::from_fn(|i, j| rows[i][j])
    }

    /// $T^{-1} T = I$ and $T^{-1} A^{-1} T$ is the block form, from the tableau's closed form.
    #[test]
    fn transformation_diagonalises_a_inverse() {
        let (t, ti) = (m(T), m(TI));
        assert!((ti * t - Matrix3::identity()).amax() < 1e-14);
        let (al, be) = alpha_beta();
        let want = Matrix3::new(gamma(), 0.0, 0.0, 0.0, al, -be, 0.0, be, al);
        let got = ti * a_matrix().try_inverse().unwrap() * t;
        assert!((got - want).amax() < 1e-12, "{got} vs {want}");
    }

    /// The error estimate's right-hand side $hf + \sum_i d_i Z_i$ is the collocation cubic's
    /// slope mismatch at the start, $hf - u^\prime(0)$ (what the dense output's order-raising
    /// term uses): $d_i = -\ell_i^\prime(0)$ for the Lagrange basis $\ell_i$ over the nodes
    /// $0, c_1, c_2, 1$ (the cubic through $0$ and the $Z_i$).
    #[test]
    fn error_estimate_is_the_cubics_slope_mismatch() {
        let x = [C1, C2, 1.0];
        for (i, want) in [DD1, DD2, DD3].into_iter().enumerate() {
            let (mut num, mut den) = (1.0, x[i]);
            for j in (0..3).filter(|&j| j != i) {
                num *= -x[j];
                den *= x[i] - x[j];
            }
            assert!(
                (want + num / den).abs() < 1e-13,
                "{i}: {want} vs {}",
                -num / den
            );
        }
    }

    /// The collocation conditions $\sum_j a_{ij} c_j^{k-1} = c_i^k / k$, $k = 1, 2, 3$.
    #[test]
    fn tableau_is_the_collocation_method() {
        let a = a_matrix();
        let c = [C1, C2, 1.0];
        for i in 0..3 {
            for k in 1..=3 {
                let s: f64 = (0..3).map(|j| a[(i, j)] * c[j].powi(k - 1)).sum();
                assert!((s - c[i].powi(k) / k as f64).abs() < 1e-15);
            }
        }
    }
}
