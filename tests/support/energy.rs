//! Energy-balance helpers shared by the tests that close an energy balance with contact
//! (`tests/suite/fe/fe_energy.rs`, `tests/suite/simulation/drive_energy.rs`): the ring's laws written out
//! again from `../shared/MODEL.md` (not the crate's force), a local degree-5 quadrature of
//! sampled integrands, and the free ring's dissipation from its closed-form relaxation.

use jeffcott::nalgebra::Vector2;
use jeffcott::ring::{Branch, Branches, Relaxation, RingAxis, SnubberRing};

/// One axis' elastic force $g$, damping $c$ and energy $e$ on a branch (`../shared/MODEL.md`):
/// inner $2Ks$, $4\nu_2$, $Ks^2$; beyond the preload on side $\sigma$
/// $K(s + \sigma D)$, $2\nu_2$, $\frac K2((\sigma s + D)^2 - 2D^2)$.
pub fn axis_law(axis: &RingAxis, nu2: f64, branch: Branch, s: f64) -> (f64, f64, f64) {
    let (k, d) = (axis.stiffness, axis.preload);
    match branch {
        Branch::Inner => (2.0 * k * s, 4.0 * nu2, k * s * s),
        Branch::Outer(side) => {
            let sigma = if d > 0.0 { f64::from(side) } else { s.signum() };
            let a = sigma * s + d;
            (
                k * (s + sigma * d),
                2.0 * nu2,
                0.5 * k * (a * a - 2.0 * d * d),
            )
        }
    }
}

/// The branches of a contact regime's label (2..5: II..V), the side of an outer axis from
/// the ring's position; `None` in free flight (label 1).
pub fn contact_branches(ring: &SnubberRing, label: u8, s: &Vector2<f64>) -> Option<Branches> {
    let outer = |axis: &RingAxis, s: f64| {
        if axis.preload > 0.0 {
            Branch::Outer(if s > 0.0 { 1 } else { -1 })
        } else {
            Branch::Outer(0)
        }
    };
    let (x_out, y_out) = match label {
        2 => (false, false),
        3 => (true, false),
        4 => (false, true),
        5 => (true, true),
        _ => return None,
    };
    let pick = |out: bool, axis: &RingAxis, s: f64| {
        if out {
            outer(axis, s)
        } else {
            Branch::Inner
        }
    };
    Some(Branches {
        x: pick(x_out, &ring.x, s.x),
        y: pick(y_out, &ring.y, s.y),
    })
}

/// Gauss-Legendre, 3 points on [-1, 1]: exact for degree 5.
pub const GAUSS3: [(f64, f64); 3] = [
    (-0.774_596_669_241_483_4, 5.0 / 9.0),
    (0.0, 8.0 / 9.0),
    (0.774_596_669_241_483_4, 5.0 / 9.0),
];

/// $\int$ of each integrand over a piece given at its nodes (times strictly increasing): on
/// each interval, the interpolant through the 6 nearest nodes (fewer on a short piece),
/// integrated by 3-point Gauss (exact for it).
pub fn integrate_piece<const N: usize>(nodes: &[(f64, [f64; N])]) -> [f64; N] {
    let m = nodes.len();
    let mut sum = [0.0; N];
    if m < 2 {
        return sum;
    }
    let w = m.min(6);
    for k in 0..m - 1 {
        let lo = k.saturating_sub(w / 2 - 1).min(m - w);
        let window = &nodes[lo..lo + w];
        let (a, b) = (nodes[k].0, nodes[k + 1].0);
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        for &(xi, wg) in &GAUSS3 {
            let t = mid + half * xi;
            for (j, (tj, fj)) in window.iter().enumerate() {
                let basis: f64 = window
                    .iter()
                    .enumerate()
                    .filter(|&(i, _)| i != j)
                    .map(|(_, (ti, _))| (t - ti) / (tj - ti))
                    .product();
                for p in 0..N {
                    sum[p] += wg * half * basis * fj[p];
                }
            }
        }
    }
    sum
}

/// Gauss-Legendre, 5 points on [-1, 1].
pub const GAUSS5: [(f64, f64); 5] = [
    (-0.906_179_845_938_664, 0.236_926_885_056_189_08),
    (-0.538_469_310_105_683_1, 0.478_628_670_499_366_47),
    (0.0, 0.568_888_888_888_888_9),
    (0.538_469_310_105_683_1, 0.478_628_670_499_366_47),
    (0.906_179_845_938_664, 0.236_926_885_056_189_08),
];

/// The free ring's dissipation $\int s^{\prime\mathsf T}Cs^\prime$ from `a` to `b`, relaxing
/// from `s0` at `a` ([`SnubberRing::relax`]): 5-point Gauss on panels of a quarter of the
/// shortest time constant, cut at the preload crossings, up to 80 time constants (then
/// $e^{-160}$ of it is left).
pub fn free_ring_dissipation(ring: &SnubberRing, s0: Vector2<f64>, a: f64, b: f64) -> f64 {
    if s0 == Vector2::zeros() || ring.damping == 0.0 {
        return 0.0;
    }
    let tc = ring.relaxation_time();
    let end = b.min(a + 80.0 * tc.max());
    let mut cuts: Vec<f64> = Relaxation { t0: a, s0 }
        .preload_crossings(ring)
        .iter()
        .copied()
        .filter(|&t| t > a && t < end)
        .collect();
    let panel = 0.25 * tc.min();
    let panels = ((end - a) / panel).ceil() as usize;
    cuts.extend((0..=panels).map(|i| (a + i as f64 * panel).min(end)));
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let rate = |t: f64| {
        let s = ring.relax(&s0, t - a);
        let s_dot = ring.relax_velocity(&s);
        let c = ring.damping_coefficients(&s);
        s_dot.dot(&c.component_mul(&s_dot))
    };
    cuts.windows(2)
        .map(|w| {
            let (mid, half) = (0.5 * (w[0] + w[1]), 0.5 * (w[1] - w[0]));
            GAUSS5
                .iter()
                .map(|&(x, wg)| wg * half * rate(mid + half * x))
                .sum::<f64>()
        })
        .sum()
}
