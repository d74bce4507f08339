//! Regime boundaries: continuity of `s*`, `E`, `g(s*)` across them, the measured jumps of the
//! Jacobian and of the damping force, and the analytic curves (eqs. 23-27) against the classifier.

use jeffcott::ring::boundaries::{Boundary, RegionBoundaries};
use jeffcott::ring::{Regime, RingAxis, SnubberRing};
use nalgebra::{Matrix2, Vector2};

fn ring(kx: f64, dx: f64, ky: f64, dy: f64, gap: f64) -> SnubberRing {
    SnubberRing::new(RingAxis::new(kx, dx), RingAxis::new(ky, dy), 0.002, gap).unwrap()
}

fn rings() -> Vec<(&'static str, SnubberRing)> {
    vec![
        ("paper Fig7", ring(30.0, 1.5, 30.0, 1.1, 1.0)),
        ("D=0.1", ring(30.0, 0.1, 30.0, 0.1, 1.0)),
        ("anisotropic", ring(30.0, 0.4, 5.0, 0.7, 1.0)),
        ("anisotropic gap 0.5", ring(3.0, 0.2, 40.0, 0.1, 0.5)),
        ("Dx = 0", ring(30.0, 0.0, 30.0, 0.6, 1.0)),
    ]
}

/// Ring state as seen from the rotor at `r`: contact position, or the rest position 0.
fn state(ring: &SnubberRing, r: &Vector2<f64>) -> (Regime, Vector2<f64>) {
    match ring.locate(r) {
        Ok(c) => (c.regime(), c.s),
        Err(_) => (Regime::I, Vector2::zeros()),
    }
}

/// Points on regime boundaries found by bisection along rays: `(point, regime inside, regime outside)`.
fn boundary_points(ring: &SnubberRing, rays: usize) -> Vec<(Vector2<f64>, Regime, Regime)> {
    let mut out = Vec::new();
    for k in 0..rays {
        let t = std::f64::consts::TAU * (k as f64 + 0.213) / rays as f64;
        let dir = Vector2::new(t.cos(), t.sin());
        out.push((
            dir * ring.gap,
            Regime::I,
            state(ring, &(dir * ring.gap * 1.0001)).0,
        ));
        let mut prev_r = ring.gap * (1.0 + 1e-9);
        let mut prev = state(ring, &(dir * prev_r)).0;
        for i in 1..=600 {
            let rad = ring.gap * (1.0 + 1e-9) + 0.01 * i as f64;
            let reg = state(ring, &(dir * rad)).0;
            if reg != prev {
                let (mut a, mut b) = (prev_r, rad);
                for _ in 0..80 {
                    let m = 0.5 * (a + b);
                    if state(ring, &(dir * m)).0 == prev {
                        a = m;
                    } else {
                        b = m;
                    }
                }
                out.push((dir * (0.5 * (a + b)), prev, reg));
            }
            prev = reg;
            prev_r = rad;
        }
    }
    out
}

#[test]
fn position_energy_and_elastic_force_are_continuous_across_boundaries() {
    for (name, ring) in rings() {
        let pts = boundary_points(&ring, 90);
        let mut kinds = std::collections::BTreeSet::new();
        let mut worst = [0.0f64; 3];
        for (n, (p, _, _)) in pts.iter().enumerate() {
            let mut crossed_any = false;
            for (m, delta) in [1e-3, 1e-5, 1e-7].into_iter().enumerate() {
                // A pseudo-random direction, kept away from the tangent by requiring a crossing.
                let a = 0.7 + 2.3 * ((n * 7 + m * 3) as f64).sin();
                let v = Vector2::new(a.cos(), a.sin());
                let (rp, rm) = (p + v * delta, p - v * delta);
                let (gp, sp) = state(&ring, &rp);
                let (gm, sm) = state(&ring, &rm);
                if gp == gm {
                    continue;
                }
                crossed_any = true;
                kinds.insert((gp.min(gm), gp.max(gm)));
                let js = (sp - sm).norm() / delta;
                let je = (ring.energy(&sp) - ring.energy(&sm)).abs() / delta;
                let jg = (ring.elastic_force(&sp) - ring.elastic_force(&sm)).norm() / delta;
                let kmax = ring.x.stiffness.max(ring.y.stiffness);
                // Jumps proportional to the distance: bounded ratio (J is O(1), g' is O(K)).
                assert!(js <= 10.0, "{name}: |ds|/delta = {js} at {p:?} ({gm}/{gp})");
                assert!(je <= 50.0 * kmax, "{name}: |dE|/delta = {je} at {p:?}");
                assert!(jg <= 50.0 * kmax, "{name}: |dg|/delta = {jg} at {p:?}");
                worst[0] = worst[0].max(js);
                worst[1] = worst[1].max(je / kmax);
                worst[2] = worst[2].max(jg / kmax);
            }
            let _ = crossed_any;
        }
        println!(
            "{name:>20}: boundaries crossed {:?}; max |ds|/delta = {:.3}, max |dE|/(K delta) = {:.3}, max |dg|/(K delta) = {:.3}",
            kinds.iter().map(|(a, b)| format!("{a}/{b}")).collect::<Vec<_>>(),
            worst[0], worst[1], worst[2]
        );
        if ring.x.preload > 0.0 && ring.y.preload > 0.0 {
            assert!(kinds.len() >= 5, "{name}: only {kinds:?}");
        }
    }
}

#[test]
fn jacobian_and_damping_force_jump_across_preload_boundaries() {
    // Paper Fig. 7 ring; cross each boundary along the ray through it, delta = 1e-9.
    let ring = SnubberRing::isotropic(30.0, 1.5, 0.002).unwrap();
    let ring = SnubberRing::new(ring.x, RingAxis::new(30.0, 1.1), 0.002, 1.0).unwrap();
    println!("ray angle | boundary | J inside | J outside | ||dJ||/||J_in|| | damping force jump (r' = n)");
    for deg in [10.0f64, 20.0, 30.0, 45.0, 60.0, 80.0] {
        let dir = Vector2::new(deg.to_radians().cos(), deg.to_radians().sin());
        let pts = boundary_points_on_ray(&ring, &dir);
        for (rad, from, to) in pts {
            let rin = dir * (rad - 1e-9);
            let rout = dir * (rad + 1e-9);
            let (ci, co) = (ring.locate(&rin).unwrap(), ring.locate(&rout).unwrap());
            assert_eq!((ci.regime(), co.regime()), (from, to));
            let rel = (co.jacobian - ci.jacobian).norm() / ci.jacobian.norm();
            let fi = damping_force(&ring, &ci.s, &ci.jacobian, &ci.normal);
            let fo = damping_force(&ring, &co.s, &co.jacobian, &co.normal);
            println!(
                "{deg:>5} | {from}/{to} | {} | {} | {rel:.3} | {:.3e} -> {:.3e}",
                fmt(&ci.jacobian),
                fmt(&co.jacobian),
                fi.norm(),
                fo.norm()
            );
            // The position is continuous, the Jacobian is not.
            assert!((ci.s - co.s).norm() < 1e-8);
            assert!(rel > 1e-3, "J should jump across {from}/{to}: {rel}");
        }
    }
}

fn damping_force(
    ring: &SnubberRing,
    s: &Vector2<f64>,
    j: &Matrix2<f64>,
    n: &Vector2<f64>,
) -> Vector2<f64> {
    ring.damping_coefficients(s).component_mul(&(j * n))
}

fn fmt(j: &Matrix2<f64>) -> String {
    format!(
        "[{:.4} {:.4}; {:.4} {:.4}]",
        j[(0, 0)],
        j[(0, 1)],
        j[(1, 0)],
        j[(1, 1)]
    )
}

fn boundary_points_on_ray(ring: &SnubberRing, dir: &Vector2<f64>) -> Vec<(f64, Regime, Regime)> {
    let mut out = Vec::new();
    let mut prev_r = ring.gap * (1.0 + 1e-9);
    let mut prev = state(ring, &(dir * prev_r)).0;
    for i in 1..=800 {
        let rad = ring.gap * (1.0 + 1e-9) + 0.005 * i as f64;
        let reg = state(ring, &(dir * rad)).0;
        if reg != prev {
            let (mut a, mut b) = (prev_r, rad);
            for _ in 0..80 {
                let m = 0.5 * (a + b);
                if state(ring, &(dir * m)).0 == prev {
                    a = m;
                } else {
                    b = m;
                }
            }
            out.push((0.5 * (a + b), prev, reg));
        }
        prev = reg;
        prev_r = rad;
    }
    out
}

#[test]
fn contact_onset_ring_moves_proportionally_to_penetration() {
    for (name, ring) in rings() {
        for k in 0..36 {
            let t = (10.0 * k as f64 + 3.0).to_radians();
            let dir = Vector2::new(t.cos(), t.sin());
            let ratios: Vec<f64> = [1e-3, 1e-5, 1e-7]
                .iter()
                .map(|&e| ring.locate(&(dir * (ring.gap + e))).unwrap().s.norm() / e)
                .collect();
            // |s*| ~ c * (|r| - gap): first order (c = 1 for an isotropic ring, an oblique
            // projection's norm for an anisotropic one).
            assert!(ratios.iter().all(|&q| q <= 3.0), "{name}: {ratios:?}");
            if ring.is_isotropic() {
                assert!(
                    ratios.iter().all(|&q| q <= 1.0 + 1e-6),
                    "{name}: {ratios:?}"
                );
            }
            assert!(
                (ratios[1] - ratios[2]).abs() <= 0.05 * ratios[2] + 1e-9,
                "{name}: {ratios:?}"
            );
        }
    }
}

#[test]
fn analytic_curves_agree_with_classifier() {
    let cases = [
        (1.5, 1.1, 1.0),
        (0.1, 0.1, 1.0),
        (0.4, 0.9, 0.5),
        (0.0, 0.6, 1.0),
        (0.7, 0.0, 1.0),
    ];
    for (dx, dy, gap) in cases {
        let ring = ring(30.0, dx, 30.0, dy, gap);
        let b = RegionBoundaries::from_ring(&ring).unwrap();
        let eps = 1e-7;
        let mut checked = 0;
        for i in 1..400 {
            let theta = std::f64::consts::FRAC_PI_2 * i as f64 / 400.0;
            for which in Boundary::ALL {
                let Some(p) = b.point(which, theta) else {
                    continue;
                };
                if let Some(c) = b.corner()
                    && (p - c).norm() < 1e-4
                {
                    continue;
                }
                // Offset direction and expected regimes on the low / high side.
                let (off, low, high) = match which {
                    Boundary::IContact => (p.normalize(), Regime::I, None),
                    Boundary::IiIii => (Vector2::new(1.0, 0.0), Regime::II, Some(Regime::III)),
                    Boundary::IvV => (Vector2::new(1.0, 0.0), Regime::IV, Some(Regime::V)),
                    Boundary::IiIv => (Vector2::new(0.0, 1.0), Regime::II, Some(Regime::IV)),
                    Boundary::IiiV => (Vector2::new(0.0, 1.0), Regime::III, Some(Regime::V)),
                };
                let lo = ring.regime(&(p - off * eps)).unwrap();
                let hi = ring.regime(&(p + off * eps)).unwrap();
                // Near the ends of a curve the offset may leave the curve's neighbourhood
                // (e.g. close to the circle); require the regimes only where both sides are contact.
                if which != Boundary::IContact && (p - off * eps).norm() <= gap * 1.001 {
                    continue;
                }
                assert_eq!(lo, low, "{which:?} at {p:?} (low side), D = ({dx}, {dy})");
                if let Some(h) = high {
                    assert_eq!(hi, h, "{which:?} at {p:?} (high side), D = ({dx}, {dy})");
                } else {
                    assert!(hi.is_contact());
                }
                checked += 1;
            }
        }
        assert!(checked > 300, "{checked}");
        // Each curve's formula: on it, the ring sits exactly at the preload.
        for i in 1..100 {
            let theta = std::f64::consts::FRAC_PI_2 * i as f64 / 100.0;
            for which in [Boundary::IiIii, Boundary::IvV] {
                if let Some(p) = b.point(which, theta) {
                    let s = ring.locate(&p).unwrap().s;
                    assert!((s.x - dx).abs() < 1e-9, "{which:?}: s = {s:?}");
                }
            }
            for which in [Boundary::IiIv, Boundary::IiiV] {
                if let Some(p) = b.point(which, theta) {
                    let s = ring.locate(&p).unwrap().s;
                    assert!((s.y - dy).abs() < 1e-9, "{which:?}: s = {s:?}");
                }
            }
        }
    }
}

#[test]
fn corner_and_domains() {
    let b = RegionBoundaries::new(1.5, 1.1, 1.0).unwrap();
    let c = b.corner().unwrap();
    let ring =
        SnubberRing::new(RingAxis::new(30.0, 1.5), RingAxis::new(30.0, 1.1), 0.0, 1.0).unwrap();
    let s = ring.locate(&c).unwrap().s;
    assert!((s - Vector2::new(1.5, 1.1)).norm() < 1e-12);
    // The four curves meet at the corner.
    assert!((b.eq24(c.x).unwrap() - c.y).abs() < 1e-12);
    assert!((b.eq27(c.x).unwrap() - c.y).abs() < 1e-12);
    assert!((b.eq25(c.y).unwrap() - c.x).abs() < 1e-12);
    assert!((b.eq26(c.y).unwrap() - c.x).abs() < 1e-12);
    // Domains.
    assert_eq!(b.eq24(1.5), None);
    assert_eq!(b.eq24(2.6), None);
    assert_eq!(b.ii_iii(c.x - 0.01), None);
    assert!(b.ii_iii(c.x + 0.01).is_some());
    assert_eq!(b.iv_v(c.x + 0.01), None);
    assert!(b.iv_v(c.x - 0.01).is_some());
    assert_eq!(b.circle(1.2), None);
    let none = RegionBoundaries::new(0.0, 0.0, 1.0).unwrap();
    assert_eq!(none.corner(), None);
    assert_eq!(none.ii_iii(0.5), None);
    assert!(none.polyline(Boundary::IvV, 100, 5.0).is_empty());
    assert!(RegionBoundaries::new(-1.0, 0.0, 1.0).is_err());
    assert!(RegionBoundaries::new(0.0, 0.0, f64::NAN).is_err());
    let aniso =
        SnubberRing::new(RingAxis::new(30.0, 1.0), RingAxis::new(20.0, 1.0), 0.0, 1.0).unwrap();
    assert!(RegionBoundaries::from_ring(&aniso).is_err());
}
