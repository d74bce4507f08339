//! Exact free relaxation of the ring: ODE, force balance, continuity at the preload,
//! monotonicity, the `nu2 = 0` limit, and the energy/force helpers.

use approx::assert_relative_eq;
use jeffcott::ring::{Regime, RingAxis, SnubberRing};
use nalgebra::Vector2;
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;

fn ring(kx: f64, dx: f64, ky: f64, dy: f64, nu2: f64) -> SnubberRing {
    SnubberRing::new(RingAxis::new(kx, dx), RingAxis::new(ky, dy), nu2, 1.0).unwrap()
}

fn arb_case() -> impl Strategy<Value = (SnubberRing, Vector2<f64>)> {
    (
        1.0f64..100.0,
        0.0f64..1.0,
        1.0f64..100.0,
        0.0f64..1.0,
        1e-3f64..0.1,
        -3.0f64..3.0,
        -3.0f64..3.0,
    )
        .prop_map(|(kx, dx, ky, dy, nu, sx, sy)| (ring(kx, dx, ky, dy, nu), Vector2::new(sx, sy)))
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 300,
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(
            "proptest-regressions/ring_relax.txt"
        ))),
        ..crate::rng::proptest_defaults()
    })]

    #[test]
    fn exact_solution_satisfies_the_ode((ring, s0) in arb_case(), frac in 0.01f64..5.0) {
        let tmax = ring.relaxation_time().max();
        let t = frac * tmax;
        let h = 1e-5 * tmax;
        let t1 = ring.time_to_preload(&s0);
        // Stay away from the switching times, where s' jumps.
        prop_assume!((t - t1.x).abs() > 10.0 * h && (t - t1.y).abs() > 10.0 * h);
        let fd = (ring.relax(&s0, t + h) - ring.relax(&s0, t - h)) / (2.0 * h);
        let s = ring.relax(&s0, t);
        let v = ring.relax_velocity(&s);
        let scale = ring.relax_velocity(&s0).norm() + 1e-12;
        prop_assert!((fd - v).norm() <= 1e-6 * scale, "fd {fd:?} v {v:?}");
        // Force balance: the free ring carries no force.
        let f = ring.force(&s, &v);
        prop_assert!(f.norm() <= 1e-10 * (1.0 + ring.elastic_force(&s0).norm()), "f = {f:?}");
    }

    #[test]
    fn position_and_speed_are_monotone((ring, s0) in arb_case()) {
        let tmax = ring.relaxation_time().max();
        let mut prev = s0;
        let mut prev_v = ring.relax_velocity(&s0);
        for i in 1..400 {
            let t = tmax * 10.0 * i as f64 / 400.0;
            let s = ring.relax(&s0, t);
            let v = ring.relax_velocity_at(&s0, t);
            for k in 0..2 {
                prop_assert!(s[k].abs() <= prev[k].abs() * (1.0 + 1e-14) + 1e-300);
                prop_assert!(s[k] * s0[k] >= 0.0, "sign change");
                prop_assert!(v[k].abs() <= prev_v[k].abs() * (1.0 + 1e-12) + 1e-300);
            }
            let (lo, hi) = ring.relax_bounds(&s0, t);
            for k in 0..2 {
                prop_assert!(lo[k] <= s[k] && s[k] <= hi[k] && lo[k] <= prev[k] && prev[k] <= hi[k]);
            }
            prev = s;
            prev_v = v;
        }
    }
}

#[test]
fn continuity_at_the_preload() {
    let ring = ring(30.0, 0.1, 30.0, 0.05, 0.002);
    let s0 = Vector2::new(0.8, -0.3);
    let t1 = ring.time_to_preload(&s0);
    for (k, d) in [(0, 0.1), (1, 0.05)] {
        for eps in [1e-9, 1e-12] {
            let before = ring.relax(&s0, t1[k] - eps * t1[k]);
            let after = ring.relax(&s0, t1[k] + eps * t1[k]);
            assert_relative_eq!(before[k].abs(), d, max_relative = 1e-6);
            assert_relative_eq!(after[k].abs(), d, max_relative = 1e-6);
        }
        // Speed drops by 2 at t1: 2D/T -> D/T.
        let tc = ring.relaxation_time()[k];
        let vb = ring.relax_velocity(&Vector2::new(d * 1.000001, d * 1.000001))[k].abs();
        let va = ring.relax_velocity(&Vector2::new(d, d))[k].abs();
        assert_relative_eq!(vb, 2.0 * d / tc, max_relative = 1e-5);
        assert_relative_eq!(va, d / tc, max_relative = 1e-12);
    }
    // Closed-form t1 = T ln((|s0| + D)/(2D)).
    let tc = ring.relaxation_time();
    assert_relative_eq!(
        t1.x,
        tc.x * ((0.8 + 0.1) / 0.2f64).ln(),
        max_relative = 1e-14
    );
    assert_relative_eq!(
        t1.y,
        tc.y * ((0.3 + 0.05) / 0.1f64).ln(),
        max_relative = 1e-14
    );
}

#[test]
fn zero_damping_relaxes_instantly() {
    let ring = ring(30.0, 0.1, 30.0, 0.1, 0.0);
    let s0 = Vector2::new(0.5, -0.05);
    assert_eq!(ring.relax(&s0, 0.0), s0);
    assert_eq!(ring.relax(&s0, 1e-300), Vector2::zeros());
    assert_eq!(ring.relaxation_time(), Vector2::zeros());
    let v = ring.relax_velocity(&s0);
    assert_eq!(v, Vector2::new(f64::NEG_INFINITY, f64::INFINITY));
    assert_eq!(ring.relax_velocity(&Vector2::zeros()), Vector2::zeros());
    assert_eq!(ring.time_to_preload(&s0), Vector2::zeros());
}

#[test]
fn odd_times() {
    let ring = ring(30.0, 0.1, 30.0, 0.0, 0.002);
    let s0 = Vector2::new(0.5, -0.05);
    assert_eq!(ring.relax(&s0, -1.0), s0);
    assert!(ring.relax(&s0, f64::NAN).x.is_nan());
    assert_eq!(ring.relax(&s0, f64::INFINITY), Vector2::zeros());
    // Zero preload axis: pure exponential, never "inside".
    let tc = ring.relaxation_time().y;
    assert_relative_eq!(
        ring.relax(&s0, tc).y,
        -0.05 * (-1.0f64).exp(),
        max_relative = 1e-14
    );
    assert_eq!(ring.time_to_preload(&s0).y, f64::INFINITY);
}

#[test]
fn energy_force_and_damping_tables() {
    let ring = ring(30.0, 0.2, 10.0, 0.0, 0.002);
    // Inside on x: 2Ks and Ks^2; y has no preload: K s, (K/2) s^2.
    let s = Vector2::new(0.1, 0.3);
    assert_relative_eq!(ring.elastic_force(&s).x, 6.0, max_relative = 1e-15);
    assert_relative_eq!(ring.elastic_force(&s).y, 3.0, max_relative = 1e-15);
    assert_relative_eq!(
        ring.energy(&s),
        30.0 * 0.01 + 5.0 * 0.09,
        max_relative = 1e-15
    );
    assert_eq!(ring.damping_coefficients(&s), Vector2::new(0.008, 0.004));
    assert_eq!(ring.regime_of_ring(&s), Regime::IV);
    // Beyond on x: sign(s) K (|s| + D), continuous at |s| = D.
    let s = Vector2::new(-0.5, 0.0);
    assert_relative_eq!(ring.elastic_force(&s).x, -30.0 * 0.7, max_relative = 1e-15);
    let at = ring.elastic_force(&Vector2::new(0.2, 0.0)).x;
    let beyond = ring.elastic_force(&Vector2::new(0.2 + 1e-12, 0.0)).x;
    assert_relative_eq!(at, beyond, max_relative = 1e-10);
    // Energy is the integral of the force (check the gradient numerically).
    for x in [-0.7, -0.2, -0.1, 0.0, 0.15, 0.2, 0.35] {
        let s = Vector2::new(x, 0.4 * x);
        let h = 1e-6;
        let gx = (ring.energy(&(s + Vector2::new(h, 0.0)))
            - ring.energy(&(s - Vector2::new(h, 0.0))))
            / (2.0 * h);
        let gy = (ring.energy(&(s + Vector2::new(0.0, h)))
            - ring.energy(&(s - Vector2::new(0.0, h))))
            / (2.0 * h);
        let g = ring.elastic_force(&s);
        assert!(
            (gx - g.x).abs() < 5e-5 && (gy - g.y).abs() < 5e-5,
            "{x}: {gx} {gy} {g:?}"
        );
    }
    assert!(ring.has_preload());
    assert!(!ring.is_isotropic());
    assert!(SnubberRing::isotropic(30.0, 0.1, 0.0)
        .unwrap()
        .is_isotropic());
    assert!(!SnubberRing::isotropic(30.0, 0.0, 0.0)
        .unwrap()
        .has_preload());
}
