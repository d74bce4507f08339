//! The declared forcing's exact response over part of a step, from the $\varphi$-functions the
//! step has already computed.

use nalgebra::Complex;

use super::super::linear_part::{phi_functions_to, BlockResponse, Forcing};

/// Where $|s(\lambda - \mu)|$ is at least this, $I(\mu, s)$ is taken in closed form,
/// $(e^{s\lambda} - e^{\mu s})/(\lambda - \mu)$: its cancellation costs a relative error of
/// about $4\varepsilon/|s(\lambda - \mu)|$, at most $32\varepsilon = 7\times10^{-15}$, below the
/// $\varphi$-functions' own near $|z| = 1$ ([`phi_functions_to`]). Nearer resonance the series
/// $s\thinspace e^{\mu s}\varphi_1(s(\lambda - \mu))$, of 11 terms there.
const CLOSED_FORM_FROM: f64 = 0.125;

/// The forcing's harmonics over one length $s$, shared by every block: $\mu = i\omega$ and
/// $e^{\mu s}$.
#[derive(Clone, Copy)]
pub(super) struct Harmonics {
    s: f64,
    mu: Complex<f64>,
    rotation: Complex<f64>,
}

impl Harmonics {
    /// For the forcing of angular frequency `omega` over a length `s`.
    pub(super) fn new(omega: f64, s: f64) -> Self {
        Harmonics {
            s,
            mu: Complex::new(0.0, omega),
            rotation: unit(omega * s),
        }
    }

    /// $[I(i\omega, s), I(-i\omega, s)]$ of a block of eigenvalue `lambda`, with
    /// $I(\mu, s) = \int_0^s e^{(s - r)\lambda}e^{\mu r}\thinspace dr$ and `e_lambda`
    /// $= e^{s\lambda}$: $(e^{s\lambda} - e^{\mu s})/(\lambda - \mu)$ where
    /// $s|\lambda - \mu| \ge$ [`CLOSED_FORM_FROM`], else $s\thinspace e^{\mu s}
    /// \varphi_1(s(\lambda - \mu))$, exact at resonance ($\mu = \lambda$ gives $s e^{\mu s}$).
    /// No $e^{s\lambda}$ apart from the integrator's own, which underflows harmlessly for a
    /// stiff $\lambda$.
    #[inline(always)]
    pub(super) fn of(
        &self,
        lambda: Complex<f64>,
        e_lambda: Complex<f64>,
        block: &BlockResponse,
    ) -> [Complex<f64>; 2] {
        let rotations = [self.rotation, self.rotation.conj()];
        let mus = [self.mu, -self.mu];
        std::array::from_fn(|k| {
            if self.s * block.modulus[k] >= CLOSED_FORM_FROM {
                (e_lambda - rotations[k]) * block.inverse[k]
            } else {
                rotations[k] * phi_functions_to::<2>((lambda - mus[k]) * self.s)[1] * self.s
            }
        })
    }
}

/// $e^{i x}$.
pub(super) fn unit(x: f64) -> Complex<f64> {
    let (sin, cos) = x.sin_cos();
    Complex::new(cos, sin)
}

/// A block's exact response from zero over $[t_0, t_0 + s]$,
/// $F = A_+e^{i\omega t_0}I(i\omega, s) + A_-e^{-i\omega t_0}I(-i\omega, s) + c\thinspace
/// I(0, s)$, from `phase` $= e^{i\omega t_0}$, its [`Harmonics::of`] and `constant`
/// $= I(0, s) = s\varphi_1(s\lambda)$.
#[inline(always)]
pub(super) fn combine(
    block: &BlockResponse,
    phase: Complex<f64>,
    [plus, minus]: [Complex<f64>; 2],
    constant: Complex<f64>,
) -> Complex<f64> {
    let [ap, am, c] = block.amplitudes;
    ap * phase * plus + am * phase.conj() * minus + c * constant
}

/// The responses of every forced block over $[t_0, t_0 + s]$ at one $\theta$ of a dense output:
/// the harmonics and the phase, computed once for all blocks.
#[derive(Clone, Copy)]
pub(super) struct Window<'a> {
    forcing: &'a Forcing,
    harmonics: Harmonics,
    phase: Complex<f64>,
}

impl<'a> Window<'a> {
    /// Over $[t_0, t_0 + s]$.
    pub(super) fn new(forcing: &'a Forcing, t0: f64, s: f64) -> Self {
        Window {
            forcing,
            harmonics: Harmonics::new(forcing.frequency, s),
            phase: unit(forcing.frequency * t0),
        }
    }

    /// Block `i`'s response (0 for an unforced block), from `phi0` $= e^{s\lambda}$ and
    /// `phi1` $= \varphi_1(s\lambda)$.
    #[inline(always)]
    pub(super) fn at(
        &self,
        i: usize,
        lambda: Complex<f64>,
        phi0: Complex<f64>,
        phi1: Complex<f64>,
    ) -> Complex<f64> {
        match &self.forcing.responses[i] {
            Some(block) => {
                let harmonics = self.harmonics.of(lambda, phi0, block);
                combine(block, self.phase, harmonics, phi1 * self.harmonics.s)
            }
            None => Complex::new(0.0, 0.0),
        }
    }
}
