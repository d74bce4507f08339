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
            t_prev,
            h,
        }
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
