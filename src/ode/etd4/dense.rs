//! ETD4's dense output: the variation-of-constants formula with the quartic through five
//! nodes of $N$ on an accepted step ([`DenseStep`]), and the stages' interpolant that places
//! two of those nodes ([`quadratic_middle`]).

use nalgebra::allocator::Allocator;
use nalgebra::{Complex, DefaultAllocator, Dim, OVector};

use super::super::linear_part::{phi_functions_to, DiagonalLinearPart};
use super::forcing::Window;
use super::{for_blocks, get, put, DenseSets, Increments, Stages};

/// The stages' interpolant at the middle of a half step of length `tau` from `u0` into `out`:
/// the quadrature of the quadratic through the half step's stages ($N_a$,
/// $N_m = (N_b + N_c)/2$, $N_d$) to $\tau/2$, with the coefficients' $\varphi$-functions at
/// $\tau\lambda/2$ (`sets[i][0]`) and the forcing's increment over $[t_j, t_j + \tau/2]$
/// (`increments[i][0]`, zero without a forcing). Its local error is $O(\tau^4)$, one order
/// short of the step's (the stages are of order 4 only in the step's weights): it places the
/// dense output's nodes ([`super::Etd4::prepare_dense`]), which need no more.
pub(super) fn quadratic_middle<D: Dim>(
    lp: &DiagonalLinearPart,
    (stages, u0): (&Stages<D>, &[f64]),
    (sets, increments): (&[DenseSets], &[Increments]),
    tau: f64,
    out: &mut [f64],
) where
    DefaultAllocator: Allocator<D>,
{
    let theta = 0.5;
    let [na, nb, nc, nd] = stages.n.each_ref().map(|v| v.as_slice());
    for_blocks(lp.slots(), |i, p| {
        let phi = &sets[i][0];
        let a = get(na, i, p);
        let m = (get(nb, i, p) + get(nc, i, p)) * 0.5;
        let d = get(nd, i, p);
        let p2 = m * 4.0 - a * 3.0 - d;
        let p3 = (a - m * 2.0 + d) * 4.0;
        let value = phi[0] * get(u0, i, p)
            + (phi[1] * a + phi[2] * p2 * theta + phi[3] * p3 * (theta * theta)) * (theta * tau)
            + increments[i][0];
        put(out, i, p, value);
    });
}

/// Six times the coefficients of the quartic through the dense output's nodes of $N$ at
/// $0, \tau/2, \tau, 3\tau/2, 2\tau$ (an accepted step of two half steps of length $\tau$), in
/// powers of $\theta$ on the first half step ($t = t_{\text{prev}} + \theta\tau$, `[0]`) and
/// on the second ($t = t_{\text{prev}} + (1 + \theta)\tau$, `[1]`): row $k$ gives the
/// coefficient of $\theta^k$, column $j$ the weight of node $j$ (Lagrange's basis on the
/// nodes $0, 1/2, 1, 3/2, 2$ in units of $\tau$, shifted by 0 or 1; exact rationals).
const QUARTIC: [[[f64; 5]; 5]; 2] = [
    [
        [6.0, 0.0, 0.0, 0.0, 0.0],
        [-25.0, 48.0, -36.0, 16.0, -3.0],
        [35.0, -104.0, 114.0, -56.0, 11.0],
        [-20.0, 72.0, -96.0, 56.0, -12.0],
        [4.0, -16.0, 24.0, -16.0, 4.0],
    ],
    [
        [0.0, 0.0, 6.0, 0.0, 0.0],
        [1.0, -8.0, 0.0, 8.0, -1.0],
        [-1.0, 16.0, -30.0, 16.0, -1.0],
        [-4.0, 8.0, 0.0, -8.0, 4.0],
        [4.0, -16.0, 24.0, -16.0, 4.0],
    ],
];

/// $k!/6$ for $k < 5$: the factor of $\theta^k$'s coefficient in [`QUARTIC`] in the dense
/// output ($\int_0^{\theta\tau} e^{(\theta\tau - r)\lambda}(r/\tau)^k\thinspace dr =
/// k!\thinspace\theta^{k+1}\tau\thinspace\varphi_{k+1}(\theta\tau\lambda)$).
const FACTORIAL_SIXTH: [f64; 5] = [1.0 / 6.0, 1.0 / 6.0, 2.0 / 6.0, 1.0, 4.0];

/// Per block, $k!\thinspace c_k$ for $k = 0, \dots, 4$, with $c_k$ the coefficient of
/// $\theta^k$ of the quartic of $N$ on one half step ([`QUARTIC`] times [`FACTORIAL_SIXTH`]):
/// set once per step, so that a dense output costs five products a block.
pub(super) type Quartic = [Complex<f64>; 5];

/// The quartic's coefficients on both half steps for every block ([`Quartic`]), from the
/// dense output's five nodes of $N$ at $0, \tau/2, \tau, 3\tau/2, 2\tau$.
pub(super) fn quartic_coefficients(
    lp: &DiagonalLinearPart,
    nodes: [&[f64]; 5],
    out: &mut [Vec<Quartic>; 2],
) {
    let zero = Complex::new(0.0, 0.0);
    for_blocks(lp.slots(), |i, p| {
        let v = nodes.map(|n| get(n, i, p));
        for (rows, half) in QUARTIC.iter().zip(out.iter_mut()) {
            half[i] = std::array::from_fn(|k| {
                let c = rows[k].iter().zip(&v).fold(zero, |a, (w, x)| a + x * *w);
                c * FACTORIAL_SIXTH[k]
            });
        }
    });
}

/// The dense output's data of one accepted step of length `h` from `t_prev`: the quartic's
/// coefficients on each half step ([`quartic_coefficients`]), the states at the half steps'
/// starts, and, once computed, the half steps' jumps.
#[derive(Clone, Copy)]
pub(super) struct DenseStep<'a> {
    quartic: [&'a [Quartic]; 2],
    starts: [&'a [f64]; 2],
    jumps: Option<[&'a [f64]; 2]>,
    /// The accepted trial's $\varphi$-functions and forcing increments, when they are this
    /// step's: the output at a half step's middle or end reuses them.
    cached: Option<(&'a [DenseSets], [&'a [Increments]; 2])>,
    t_prev: f64,
    h: f64,
}

impl<'a> DenseStep<'a> {
    /// The dense output's data from the accepted step's quartic and starts, without jumps.
    pub(super) fn new<D: Dim>(
        quartic: &'a [Vec<Quartic>; 2],
        starts: [&'a OVector<f64, D>; 2],
        t_prev: f64,
        h: f64,
    ) -> Self
    where
        DefaultAllocator: Allocator<D>,
    {
        DenseStep {
            quartic: [quartic[0].as_slice(), quartic[1].as_slice()],
            starts: starts.map(|u| u.as_slice()),
            jumps: None,
            cached: None,
            t_prev,
            h,
        }
    }

    /// With the last trial's $\varphi$-functions at $h\lambda/4$ and $h\lambda/2$ and its half
    /// steps' forcing increments, if that trial, at `(t, h)`, is this step (a later trial that
    /// failed overwrites them).
    pub(super) fn reusing(
        self,
        trial: (f64, f64),
        sets: &'a [DenseSets],
        increments: [&'a [Increments]; 2],
    ) -> Self {
        let cached = (trial == (self.t_prev, self.h)).then_some((sets, increments));
        DenseStep { cached, ..self }
    }

    /// With the half steps' jumps.
    pub(super) fn with_jumps<D: Dim>(self, jumps: &'a [OVector<f64, D>; 2]) -> Self
    where
        DefaultAllocator: Allocator<D>,
    {
        DenseStep {
            jumps: Some([jumps[0].as_slice(), jumps[1].as_slice()]),
            ..self
        }
    }

    /// The dense output at `t` into `out` (extrapolated outside the step): on the half step
    /// that holds it, with $\varphi_0, \dots, \varphi_5$ at $\theta\tau\lambda$ and the
    /// forcing's exact response ([`Window`]) computed here.
    pub(super) fn at(&self, lp: &DiagonalLinearPart, t: f64, out: &mut [f64]) {
        if let Some((sets, increments)) = self.cached
            && let Some((half, end)) = self.quarter_point(t)
        {
            // The half step's middle (theta = 1/2) or end (theta = 1): the trial's sets.
            let (theta, set, part) = if end { (1.0, 1, 2) } else { (0.5, 0, 0) };
            let increments = increments[half];
            self.on_half(lp, half, theta, out, |i| {
                (sets[i][set], increments[i][part])
            });
            return;
        }
        let tau = 0.5 * self.h;
        let s = (t - self.t_prev) / tau;
        let half = usize::from(s > 1.0);
        let theta = s - half as f64;
        let length = theta * tau;
        let window = lp
            .forcing()
            .map(|f| Window::new(f, self.t_prev + half as f64 * tau, length));
        let values = lp.values();
        self.on_half(lp, half, theta, out, |i| {
            let phi = phi_functions_to::<6>(values[i] * length);
            let forced = window.map_or(Complex::new(0.0, 0.0), |w| {
                w.at(i, values[i], phi[0], phi[1])
            });
            (phi, forced)
        });
    }

    /// Which point of the step `t` is within rounding of, if one the trial's
    /// $\varphi$-functions serve: `(half, end)` for the middle (`end` false) or the end of half
    /// step `half`, at $t_{\text{prev}} + (2\thinspace\text{half} + 1 + \text{end})\thinspace h/4$.
    /// Within rounding: $4\varepsilon$ of the larger of $|t_{\text{prev}}|$ and $|t_{\text{prev}} +
    /// h|$ (the event detector's samples at the step's quarters, computed from the step's ends,
    /// fall there), so the output is the one at that point, off by less than the detector's
    /// time tolerance.
    fn quarter_point(&self, t: f64) -> Option<(usize, bool)> {
        let slack = 4.0 * f64::EPSILON * self.t_prev.abs().max((self.t_prev + self.h).abs());
        let quarters = (t - self.t_prev) / (0.25 * self.h);
        let k = quarters.round();
        if !(1.0..=4.0).contains(&k) || (t - (self.t_prev + k * 0.25 * self.h)).abs() > slack {
            return None;
        }
        let k = k as usize;
        Some(((k - 1) / 2, k % 2 == 0))
    }

    /// The end of half step `half` without its jump into `out`, from the coefficients'
    /// $\varphi$-functions at $\tau\lambda$ (`sets[i][1]`) and the forcing's increment over
    /// the half step (`increments[i][2]`).
    pub(super) fn half_end(
        &self,
        lp: &DiagonalLinearPart,
        half: usize,
        (sets, increments): (&[DenseSets], &[Increments]),
        out: &mut [f64],
    ) {
        self.on_half(lp, half, 1.0, out, |i| (sets[i][1], increments[i][2]));
    }

    /// The dense output at $\theta$ of half step `half` into `out`: from its start $u_j$,
    /// $e^{\theta\tau L}u_j + F(t_j, \theta\tau) + \theta\tau\sum_k k!\thinspace c_k\theta^k
    /// \varphi_{k+1}(\theta\tau L) + \theta^3\delta_j$ with $c_k$ the quartic's coefficients
    /// ([`Quartic`]), $\delta_j$ the half step's jump (if known), and `block(i)` giving block
    /// `i`'s $\varphi_0, \dots, \varphi_5$ at $\theta\tau\lambda$ and its $F(t_j, \theta\tau)$.
    fn on_half(
        &self,
        lp: &DiagonalLinearPart,
        half: usize,
        theta: f64,
        out: &mut [f64],
        mut block: impl FnMut(usize) -> ([Complex<f64>; 6], Complex<f64>),
    ) {
        let tau = 0.5 * self.h;
        let (u0, quartic) = (self.starts[half], self.quartic[half]);
        for_blocks(lp.slots(), |i, p| {
            let (phi, forced) = block(i);
            let c = &quartic[i];
            // Horner in theta over sum_k phi_{k+1} c_k theta^k.
            let mut sum = phi[5] * c[4];
            for k in (0..4).rev() {
                sum = sum * theta + phi[k + 1] * c[k];
            }
            let mut value = phi[0] * get(u0, i, p) + sum * (theta * tau);
            if let Some(jumps) = self.jumps {
                value += get(jumps[half], i, p) * (theta * theta * theta);
            }
            put(out, i, p, value + forced);
        });
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::Complex;

    use super::super::{coefficients, forcing_increments, Coefficients, DenseSets, Increments};
    use super::{DenseStep, Quartic};
    use crate::ode::linear_part::{BlockForcing, DiagonalLinearPart};

    /// At a step's quarters the output from the trial's $\varphi$-functions and increments is
    /// the computed one, bit for bit (on a step from 0 of length 1, where the quarters and
    /// each $\theta$ are exact): stiff, slow, oscillating and near-resonant blocks, real and
    /// complex, forced and not.
    #[test]
    fn the_cached_quarters_are_the_computed_output_bitwise() {
        let (w, dim) = (3.0, 9);
        let lp = DiagonalLinearPart::new(
            dim,
            &[(0, -2.0e4), (1, -0.3), (8, 0.0)],
            &[
                (2, Complex::new(-0.01, 3.0)),
                (4, Complex::new(-5.0, 40.0)),
                (6, Complex::new(-0.2, -1.0)),
            ],
        )
        .unwrap()
        .with_forcing(
            w,
            &[
                (1, forced([(0.7, 0.0), (0.1, 0.0), (-0.2, 0.0)])),
                (2, forced([(1.0, 0.5), (-0.5, 1.0), (0.0, 1.0)])),
                (6, forced([(-0.4, 0.1), (0.2, 0.3), (0.3, 0.2)])),
                (8, forced([(0.0, 0.0), (0.0, 0.0), (0.5, 0.0)])),
            ],
        )
        .unwrap();
        let h = 1.0;
        let zero = Complex::new(0.0, 0.0);
        let (mut full, mut half): (Vec<Coefficients>, Vec<Coefficients>) =
            (vec![[zero; 7]; dim], vec![[zero; 7]; dim]);
        let mut sets: Vec<DenseSets> = vec![[[zero; 6]; 2]; dim];
        coefficients(&lp, h, &mut full, &mut half, &mut sets);
        let mut increments: [Vec<Increments>; 3] = std::array::from_fn(|_| vec![[zero; 3]; dim]);
        forcing_increments(
            &lp,
            lp.forcing().unwrap(),
            (&full, &half),
            0.0,
            h,
            &mut increments,
        );
        // Any quartic, starts and jumps: the two paths share them.
        let value = |k: usize| Complex::new((k as f64 * 0.37).sin(), (k as f64 * 0.61).cos());
        let quartic: [Vec<Quartic>; 2] = std::array::from_fn(|j| {
            (0..dim)
                .map(|i| std::array::from_fn(|k| value(i * 11 + k + 5 * j)))
                .collect()
        });
        let starts: [nalgebra::DVector<f64>; 2] =
            std::array::from_fn(|j| nalgebra::DVector::from_fn(dim, |i, _| value(3 * i + j).re));
        let jumps: [nalgebra::DVector<f64>; 2] = std::array::from_fn(|j| {
            nalgebra::DVector::from_fn(dim, |i, _| 1e-3 * value(7 * i + j).im)
        });
        let plain = DenseStep::new(&quartic, [&starts[0], &starts[1]], 0.0, h).with_jumps(&jumps);
        let cached = plain.reusing((0.0, h), &sets, [&increments[1], &increments[2]]);
        let stale = plain.reusing((0.0, 0.5), &sets, [&increments[1], &increments[2]]);
        assert!(stale.cached.is_none(), "another trial's sets taken");
        for k in 1..=4 {
            let t = k as f64 * 0.25;
            assert!(
                cached.quarter_point(t).is_some(),
                "quarter {k} not recognised"
            );
            let (mut a, mut b) = (vec![0.0; dim], vec![0.0; dim]);
            plain.at(&lp, t, &mut a);
            cached.at(&lp, t, &mut b);
            let bits = |v: Vec<f64>| v.into_iter().map(f64::to_bits).collect::<Vec<_>>();
            let (a, b) = (bits(a), bits(b));
            assert_eq!(a, b, "at t = {t}");
        }
        // Off the quarters (beyond rounding) nothing is taken from the cache.
        for t in [0.1, 0.25 + 1e-12, 0.5 - 1e-9, 0.9] {
            assert!(cached.quarter_point(t).is_none(), "t = {t}");
        }
    }

    /// A block's forcing from its amplitudes' (re, im): cos, sin, constant.
    fn forced(amplitudes: [(f64, f64); 3]) -> BlockForcing {
        let [cos, sin, constant] = amplitudes.map(|(re, im)| Complex::new(re, im));
        BlockForcing { cos, sin, constant }
    }
}
