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

/// The linear part $L$ of a right-hand side $f(t, y) = L y + g(t) + N(t, y)$, block-diagonal
/// in the system's own coordinates ([`OdeSystem::linear_part`](super::OdeSystem::linear_part)),
/// with an optional forcing $g$ of the blocks at one angular frequency
/// ([`DiagonalLinearPart::with_forcing`]):
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
/// The forcing of a block (at its first component, [`BlockForcing`]) is
/// $g(t) = a\cos\omega t + b\sin\omega t + c$, the same $\omega$ for every block; a real
/// block's $a$, $b$, $c$ are real, a complex block's the complex numbers of its pair. The
/// system's right-hand side still returns the whole $f$: $N$ is what is left,
/// $N = f - Ly - g(t)$.
///
/// A linear system's modal coordinates (the eigen-decomposition of its state matrix) have this
/// form, its unbalance and constant loads a forcing; the exponential integrator
/// [`Etd4`](super::Etd4) treats $L$ and $g$ exactly and only $N$ (a contact force) by
/// quadrature, at $O(N)$ a step. Any split is *correct* ($N$ is computed as
/// $f - Ly - g$, whatever $L$ and $g$ were declared); it is *efficient* when what is left in
/// $N$ is smooth and slow.
#[derive(Debug, Clone, PartialEq)]
pub struct DiagonalLinearPart {
    values: Vec<Complex<f64>>,
    slots: Vec<Slot>,
    forcing: Option<Forcing>,
}

/// The forcing $g(t) = a\cos\omega t + b\sin\omega t + c$ of one block of a
/// [`DiagonalLinearPart`] ([`DiagonalLinearPart::with_forcing`]): for a complex block, $a$, $b$,
/// $c$ are the complex amplitudes of its pair $u = y_i + i\thinspace y_{i+1}$ (so
/// $a = A$, $b = iA$ is the rotating forcing $A e^{i\omega t}$); for a real block, real
/// numbers (imaginary parts 0).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct BlockForcing {
    /// $a$, the amplitude of $\cos\omega t$.
    pub cos: Complex<f64>,
    /// $b$, the amplitude of $\sin\omega t$.
    pub sin: Complex<f64>,
    /// $c$, the constant.
    pub constant: Complex<f64>,
}

/// The declared forcing: its angular frequency and, per component (at a block's first, zero
/// elsewhere), the block's amplitudes.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Forcing {
    pub(crate) frequency: f64,
    pub(crate) blocks: Vec<BlockForcing>,
    /// The components that carry a forcing (a block's first), in order.
    pub(crate) forced: Vec<usize>,
    /// Per component, what the exact response of a forced block needs besides
    /// $e^{s\lambda}$ ([`BlockResponse`]); `None` for the unforced.
    pub(crate) responses: Vec<Option<BlockResponse>>,
}

/// A forced block's forcing in exponential form and its eigenvalue's detunings
/// $\lambda \mp i\omega$ from the forcing's two exponentials, set up once: the exact
/// response to $e^{\pm i\omega t}$ over a length $s$ is then
/// $(e^{s\lambda} - e^{\pm i\omega s})/(\lambda \mp i\omega)$ away from resonance, with
/// $e^{s\lambda}$ the integrator's own $\varphi_0$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct BlockResponse {
    /// $[A_+, A_-, c]$ ([`BlockForcing::exponential`]).
    pub(crate) amplitudes: [Complex<f64>; 3],
    /// $1/(\lambda - i\omega)$, $1/(\lambda + i\omega)$; 0 where it is not finite (at or
    /// within $10^{-154}$ of resonance), with the modulus 0 too, so that the series is taken
    /// and the declaration still equals itself.
    pub(crate) inverse: [Complex<f64>; 2],
    /// $|\lambda - i\omega|$, $|\lambda + i\omega|$.
    pub(crate) modulus: [f64; 2],
}

impl BlockResponse {
    fn new(lambda: Complex<f64>, omega: f64, block: &BlockForcing) -> Self {
        let detuning = [-1.0, 1.0].map(|sign| lambda + Complex::new(0.0, sign * omega));
        let inverse = detuning.map(|d| d.inv());
        let finite = inverse.map(|v| v.re.is_finite() && v.im.is_finite());
        let zero = Complex::new(0.0, 0.0);
        BlockResponse {
            amplitudes: block.exponential(),
            inverse: std::array::from_fn(|k| if finite[k] { inverse[k] } else { zero }),
            modulus: std::array::from_fn(|k| if finite[k] { detuning[k].norm() } else { 0.0 }),
        }
    }
}

impl BlockForcing {
    /// The exponential amplitudes $[A_+, A_-, c]$ of
    /// $g(t) = A_+ e^{i\omega t} + A_- e^{-i\omega t} + c$: $A_\pm = (a \mp i b)/2$.
    fn exponential(&self) -> [Complex<f64>; 3] {
        let ib = Complex::new(-self.sin.im, self.sin.re);
        [(self.cos - ib) * 0.5, (self.cos + ib) * 0.5, self.constant]
    }

    /// $g$ with $(\cos\omega t, \sin\omega t)$ given.
    #[inline(always)]
    fn at(&self, cos: f64, sin: f64) -> Complex<f64> {
        self.cos * cos + self.sin * sin + self.constant
    }
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
        Ok(Self {
            values,
            slots,
            forcing: None,
        })
    }

    /// The same linear part with the forcing $g(t) = a\cos\omega t + b\sin\omega t + c$ of
    /// the blocks in `blocks` (first component of the block, its [`BlockForcing`]), at the
    /// angular frequency `frequency` $= \omega$ (rad per unit of time; any finite value, 0
    /// included); the other blocks unforced. Replaces any forcing declared before. A
    /// component outside every block ($\lambda = 0$) may be forced too (a constant there
    /// grows linearly, and is integrated exactly all the same).
    ///
    /// # Errors
    /// [`OdeError::InvalidForcing`] naming the field and value: a `frequency` or an amplitude
    /// that is not finite; a component out of range, forced twice or inside a pair (the
    /// second component of a complex block); an imaginary part on a real block.
    pub fn with_forcing(
        mut self,
        frequency: f64,
        blocks: &[(usize, BlockForcing)],
    ) -> Result<Self, OdeError> {
        let invalid = |field, component, value, hint| OdeError::InvalidForcing {
            field,
            component,
            value,
            hint,
        };
        if !frequency.is_finite() {
            return Err(invalid(
                "frequency",
                None,
                frequency,
                "give a finite angular frequency",
            ));
        }
        let dim = self.dim();
        let mut table = vec![BlockForcing::default(); dim];
        let mut taken = vec![false; dim];
        let mut forced = Vec::with_capacity(blocks.len());
        for &(i, block) in blocks {
            let placed = i < dim && self.slots[i] != Slot::PairIm && !taken[i];
            if !placed {
                return Err(invalid(
                    "component",
                    Some(i),
                    i as f64,
                    "name each block once, by its first component, within the dimension",
                ));
            }
            let parts = [
                ("cos", block.cos),
                ("sin", block.sin),
                ("constant", block.constant),
            ];
            for (field, a) in parts {
                if let Some(value) = [a.re, a.im].into_iter().find(|v| !v.is_finite()) {
                    return Err(invalid(field, Some(i), value, "give finite amplitudes"));
                }
                if self.slots[i] == Slot::Scalar && a.im != 0.0 {
                    return Err(invalid(
                        field,
                        Some(i),
                        a.im,
                        "a real block's amplitudes are real (imaginary part 0)",
                    ));
                }
            }
            table[i] = block;
            taken[i] = true;
            forced.push(i);
        }
        forced.sort_unstable();
        let mut responses = vec![None; dim];
        for &i in &forced {
            responses[i] = Some(BlockResponse::new(self.values[i], frequency, &table[i]));
        }
        self.forcing = Some(Forcing {
            frequency,
            blocks: table,
            forced,
            responses,
        });
        Ok(self)
    }

    /// The forcing's angular frequency $\omega$, `None` without a forcing.
    pub fn forcing_frequency(&self) -> Option<f64> {
        self.forcing.as_ref().map(|f| f.frequency)
    }

    /// The forcing of the block whose first component is `i`, `None` if it has none (or
    /// `i` is not a block's first component).
    pub fn block_forcing(&self, i: usize) -> Option<BlockForcing> {
        let f = self.forcing.as_ref()?;
        f.forced.binary_search(&i).ok().map(|_| f.blocks[i])
    }

    pub(crate) fn forcing(&self) -> Option<&Forcing> {
        self.forcing.as_ref()
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

    /// `out` $= g(t)$, the declared forcing (zero where none is declared; $O(N)$).
    ///
    /// # Errors
    /// [`OdeError::DimensionMismatch`] for an `out` of another length than [`Self::dim`].
    pub fn forcing_at(&self, t: f64, out: &mut [f64]) -> Result<(), OdeError> {
        if out.len() != self.dim() {
            return Err(OdeError::DimensionMismatch {
                field: "out",
                expected: self.dim(),
                found: out.len(),
            });
        }
        out.fill(0.0);
        self.each_forced(t, |i, pair, g| {
            out[i] = g.re;
            if pair {
                out[i + 1] = g.im;
            }
        });
        Ok(())
    }

    /// `out -= g(t)` at the forced components (nothing without a forcing).
    pub(crate) fn subtract_forcing(&self, t: f64, out: &mut [f64]) {
        self.each_forced(t, |i, pair, g| {
            out[i] -= g.re;
            if pair {
                out[i + 1] -= g.im;
            }
        });
    }

    /// Calls `op(i, pair, g_i(t))` for each forced block (its first component, whether it
    /// is a complex pair, its forcing at `t`).
    fn each_forced(&self, t: f64, mut op: impl FnMut(usize, bool, Complex<f64>)) {
        let Some(f) = &self.forcing else { return };
        let (sin, cos) = (f.frequency * t).sin_cos();
        for &i in &f.forced {
            op(i, self.slots[i] == Slot::PairRe, f.blocks[i].at(cos, sin));
        }
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

/// $1/k!$ for $k \le 24$.
const INV_FACTORIAL: [f64; 25] = {
    let mut a = [1.0; 25];
    let mut k = 1;
    while k < 25 {
        a[k] = a[k - 1] / k as f64;
        k += 1;
    }
    a
};

/// $[e^z, \varphi_1(z), \varphi_2(z), \varphi_3(z)]$ with $\varphi_0 = e^z$,
/// $\varphi_{k+1}(z) = (\varphi_k(z) - 1/k!)/z$, $\varphi_k(0) = 1/k!$: the Taylor series of
/// $\varphi_3$ for $|z| < 1$ (11 to 18 terms, then the recurrence upwards, without cancellation),
/// the recurrence downwards from $e^z$ beyond (relative cancellation at most a factor 10 at
/// $|z| = 1$). The first four of [`phi_functions_to`].
pub fn phi_functions(z: Complex<f64>) -> [Complex<f64>; 4] {
    phi_functions_to::<4>(z)
}

/// $[\varphi_0(z), \dots, \varphi_{K-1}(z)]$ for $1 \le K \le 7$, as [`phi_functions`]: the
/// Taylor series of $\varphi_{K-1}$ for $|z| < 1$ (11 terms below $|z| = 1/8$, 15 below $1/2$,
/// 18 beyond: the tail $|z|^n/n!$ at most $2.9\times10^{-18}$, $2.3\times10^{-17}$,
/// $1.6\times10^{-16}$) and the recurrence upwards, the
/// recurrence downwards from $e^z$ beyond (its relative cancellation grows with $k$ near
/// $|z| = 1$: a relative error up to $3.7\times10^{-14}$ for $\varphi_0$ to $\varphi_5$,
/// measured by `tests/suite/ode/ode_etd4.rs`). `K = 6` is the dense output of [`Etd4`](super::Etd4).
pub fn phi_functions_to<const K: usize>(z: Complex<f64>) -> [Complex<f64>; K] {
    const { assert!(K >= 1 && K <= 7, "phi_functions_to: 1 <= K <= 7") };
    let mut p = [Complex::new(0.0, 0.0); K];
    let r2 = z.norm_sqr();
    if r2 < 1.0 {
        // phi_{K-1} = sum_k z^k / (k + K - 1)!, Horner from the highest term; fewer terms
        // for a smaller |z|, the tail |z|^n / n! at most 2.9e-18, 2.3e-17, 1.6e-16.
        let terms = if r2 < 1.0 / 64.0 {
            11
        } else if r2 < 0.25 {
            15
        } else {
            18
        };
        let mut last = Complex::new(0.0, 0.0);
        for k in (0..terms).rev() {
            last = last * z + Complex::new(INV_FACTORIAL[k + K - 1], 0.0);
        }
        p[K - 1] = last;
        for k in (0..K - 1).rev() {
            p[k] = z * p[k + 1] + Complex::new(INV_FACTORIAL[k], 0.0);
        }
    } else {
        p[0] = z.exp();
        let inv = Complex::new(1.0, 0.0) / z;
        for k in 1..K {
            p[k] = (p[k - 1] - Complex::new(INV_FACTORIAL[k - 1], 0.0)) * inv;
        }
    }
    p
}
