//! A system's linear part, diagonal in real and complex blocks ([`DiagonalLinearPart`]), the
//! diagonal springs and dampers of a second-order system ([`DiagonalSprings`]), and the
//! $\varphi$-functions of the exponential integrator ([`phi_functions`]).

use nalgebra::Complex;

use super::OdeError;

/// How one state component takes part in the linear part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Slot {
    /// $L_{ii} = \lambda$ real, or a component outside every block ($\lambda = 0$).
    Scalar,
    /// The real part of a complex coordinate $u = y_i + i\thinspace y_{i+1}$.
    PairRe,
    /// Its imaginary part (handled with the real part).
    PairIm,
}

/// The linear part $L$ of a right-hand side $f(t, y) = L y + N(t, y)$, block-diagonal in the
/// system's own coordinates ([`OdeSystem::linear_part`](super::OdeSystem::linear_part)):
///
/// with $\ell = L y$:
///
/// * a **real** block at component $i$: $\ell_i = \lambda y_i$, $\lambda \in \mathbb R$;
/// * a **complex** block at components $(i, i + 1)$: the pair is the complex number
///   $u = y_i + i\thinspace y_{i+1}$ and $\ell_i + i\thinspace\ell_{i+1} = \lambda u$,
///   $\lambda \in \mathbb C$, i.e. the real $2\times 2$ block
///   $\begin{pmatrix}\operatorname{Re}\lambda & -\operatorname{Im}\lambda\\\\
///   \operatorname{Im}\lambda & \operatorname{Re}\lambda\end{pmatrix}$;
/// * every other component has $L_{ii} = 0$ (the rest of its right-hand side is $N$).
///
/// A linear system's modal coordinates (the eigen-decomposition of its state matrix) have this
/// form; the exponential integrator [`Etd4`](super::Etd4) treats $L$ exactly and only $N$
/// (the forcing, a contact force) by quadrature, at $O(N)$ a step.
#[derive(Debug, Clone, PartialEq)]
pub struct DiagonalLinearPart {
    values: Vec<Complex<f64>>,
    slots: Vec<Slot>,
}

impl DiagonalLinearPart {
    /// The linear part of a system of dimension `dim`, with real blocks `real` (component,
    /// $\lambda$) and complex blocks `complex` (first component $i$ of the pair $(i, i+1)$,
    /// $\lambda$).
    ///
    /// # Errors
    /// [`OdeError::InvalidLinearPart`] naming the component: out of range, in two blocks, or
    /// with a non-finite $\lambda$.
    pub fn new(
        dim: usize,
        real: &[(usize, f64)],
        complex: &[(usize, Complex<f64>)],
    ) -> Result<Self, OdeError> {
        let mut values = vec![Complex::new(0.0, 0.0); dim];
        let mut slots = vec![Slot::Scalar; dim];
        let mut taken = vec![false; dim];
        let mut take = |i: usize, value: f64| -> Result<(), OdeError> {
            if i >= dim || taken[i] || !value.is_finite() {
                return Err(OdeError::InvalidLinearPart {
                    component: i,
                    value,
                });
            }
            taken[i] = true;
            Ok(())
        };
        for &(i, rate) in real {
            take(i, rate)?;
            values[i] = Complex::new(rate, 0.0);
        }
        for &(i, lambda) in complex {
            take(i, lambda.re)?;
            take(i + 1, lambda.im)?;
            values[i] = lambda;
            values[i + 1] = lambda.conj();
            slots[i] = Slot::PairRe;
            slots[i + 1] = Slot::PairIm;
        }
        Ok(Self { values, slots })
    }

    /// The state's dimension.
    pub fn dim(&self) -> usize {
        self.values.len()
    }

    /// Component `i`'s eigenvalue: $\lambda$ of its block (the conjugate for the imaginary
    /// part of a pair), 0 outside every block. `None` out of range.
    pub fn value(&self, i: usize) -> Option<Complex<f64>> {
        self.values.get(i).copied()
    }

    pub(crate) fn slots(&self) -> &[Slot] {
        &self.slots
    }

    pub(crate) fn values(&self) -> &[Complex<f64>] {
        &self.values
    }

    /// `out = L y` ($O(N)$).
    pub fn apply(&self, y: &[f64], out: &mut [f64]) {
        let n = self.values.len();
        let mut i = 0;
        while i < n {
            let l = self.values[i];
            match self.slots[i] {
                Slot::PairRe => {
                    let u = l * Complex::new(y[i], y[i + 1]);
                    out[i] = u.re;
                    out[i + 1] = u.im;
                    i += 2;
                }
                _ => {
                    out[i] = l.re * y[i];
                    i += 1;
                }
            }
        }
    }
}

/// The diagonal springs $k_i$ and dampers $d_i$ of a second-order system's Jacobian
/// ([`OdeSystem::diagonal_springs`](super::OdeSystem::diagonal_springs)): coordinate $i$'s
/// velocity row holds $-k_i$ at its position and $-d_i$ at its velocity, apart from a part of
/// low rank. For a modal model (unit modal masses) $k_i = \omega_i^2$, $d_i = 2\zeta_i\omega_i$.
/// Both slices have the length $p$ of [`OdeSystem::second_order`](super::OdeSystem::second_order)
/// (other lengths: the declaration is ignored).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiagonalSprings<'a> {
    /// $k_i$, the negated $\partial f_{p+i}/\partial q_i$.
    pub stiffness: &'a [f64],
    /// $d_i$, the negated $\partial f_{p+i}/\partial v_i$.
    pub damping: &'a [f64],
}

impl DiagonalSprings<'_> {
    /// The largest rank of the rest of the Newton matrix that [`Radau5`](super::Radau5)
    /// handles by the Woodbury formula (a force through a station and the ring's two slots
    /// need 4).
    pub const MAX_RANK: usize = 8;
}

/// $1/k!$ for $k \le 20$.
const INV_FACTORIAL: [f64; 21] = {
    let mut a = [1.0; 21];
    let mut k = 1;
    while k < 21 {
        a[k] = a[k - 1] / k as f64;
        k += 1;
    }
    a
};

/// $[e^z, \varphi_1(z), \varphi_2(z), \varphi_3(z)]$ with $\varphi_0 = e^z$,
/// $\varphi_{k+1}(z) = (\varphi_k(z) - 1/k!)/z$, $\varphi_k(0) = 1/k!$: the Taylor series of
/// $\varphi_3$ for $|z| < 1$ (18 terms, then the recurrence upwards, without cancellation),
/// the recurrence downwards from $e^z$ beyond (relative cancellation at most a factor 10 at
/// $|z| = 1$).
pub fn phi_functions(z: Complex<f64>) -> [Complex<f64>; 4] {
    let one = Complex::new(1.0, 0.0);
    if z.norm_sqr() < 1.0 {
        // phi_3 = sum_k z^k / (k + 3)!, Horner from the highest term.
        let mut p3 = Complex::new(0.0, 0.0);
        for k in (0..18).rev() {
            p3 = p3 * z + Complex::new(INV_FACTORIAL[k + 3], 0.0);
        }
        let p2 = z * p3 + Complex::new(0.5, 0.0);
        let p1 = z * p2 + one;
        let e = z * p1 + one;
        [e, p1, p2, p3]
    } else {
        let e = z.exp();
        let inv = one / z;
        let p1 = (e - one) * inv;
        let p2 = (p1 - one) * inv;
        let p3 = (p2 - Complex::new(0.5, 0.0)) * inv;
        [e, p1, p2, p3]
    }
}
