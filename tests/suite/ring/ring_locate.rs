//! The contact solver against brute-force minimisation, closed forms, finite differences,
//! symmetry, the zero-preload limit and typed errors.

use approx::assert_relative_eq;
use jeffcott::ring::{
    regime_ii_position, regime_v_position, Regime, RingAxis, RingError, SnubberRing,
};
use nalgebra::Vector2;
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;

fn ring(kx: f64, dx: f64, ky: f64, dy: f64, gap: f64) -> SnubberRing {
    SnubberRing::new(RingAxis::new(kx, dx), RingAxis::new(ky, dy), 0.002, gap).unwrap()
}

/// Brute force: `s(theta) = r - gap (cos theta, sin theta)`; scan `theta`, then bisect the
/// derivative `dE/dtheta = gap g(s) . (sin theta, -cos theta)` around the best sample.
fn brute_force(ring: &SnubberRing, r: &Vector2<f64>) -> Vector2<f64> {
    let gap = ring.gap;
    let s_of = |t: f64| r - gap * Vector2::new(t.cos(), t.sin());
    let n = 4096;
    let h = std::f64::consts::TAU / n as f64;
    let (mut best, mut best_e) = (0.0, f64::INFINITY);
    for i in 0..n {
        let t = i as f64 * h;
        let e = ring.energy(&s_of(t));
        if e < best_e {
            best_e = e;
            best = t;
        }
    }
    let deriv = |t: f64| {
        let s = s_of(t);
        ring.elastic_force(&s).dot(&Vector2::new(t.sin(), -t.cos()))
    };
    let (mut a, mut b) = (best - h, best + h);
    assert!(
        deriv(a) <= 0.0 && deriv(b) >= 0.0,
        "no sign change around the minimum"
    );
    for _ in 0..200 {
        let m = 0.5 * (a + b);
        if m <= a || m >= b {
            break;
        }
        if deriv(m) < 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
    s_of(0.5 * (a + b))
}

/// Max of (constraint error relative to gap, distance to the brute-force minimiser) over points.
fn check_against_brute(ring: &SnubberRing, r: &Vector2<f64>) -> (f64, f64) {
    let c = ring.locate(r).unwrap();
    let constraint = ((r - c.s).norm() - ring.gap).abs() / ring.gap;
    let bf = brute_force(ring, r);
    let dist = (c.s - bf).norm();
    assert!(
        constraint <= 1e-12,
        "constraint {constraint:e} at r = {r:?}, ring {ring:?}"
    );
    assert!(
        dist <= 1e-10 * r.norm().max(1.0),
        "distance to brute force {dist:e} at r = {r:?} ({}), ring {ring:?}",
        c.regime()
    );
    // The warm start gives the same point.
    let w = ring.locate_from(r, c.mu * 1.01).unwrap();
    assert!((w.s - c.s).norm() <= 1e-12 * r.norm().max(1.0));
    (constraint, dist)
}

#[test]
fn sweep_against_brute_force_reports_accuracy() {
    let rings = [
        ("isotropic paper Fig7", ring(30.0, 1.5, 30.0, 1.1, 1.0)),
        ("isotropic D=0.1", ring(30.0, 0.1, 30.0, 0.1, 1.0)),
        ("no preload", ring(30.0, 0.0, 30.0, 0.0, 1.0)),
        ("anisotropic", ring(30.0, 0.4, 5.0, 0.7, 1.0)),
        ("anisotropic gap 0.3", ring(2.0, 0.05, 80.0, 0.2, 0.3)),
        ("one preload", ring(30.0, 0.0, 30.0, 0.5, 1.0)),
    ];
    let (mut worst_c, mut worst_d) = (0.0f64, 0.0f64);
    for (name, ring) in rings {
        let mut seen = [0usize; 6];
        let mut iters = (0u32, 0u64, 0u64);
        let (mut wc, mut wd) = (0.0f64, 0.0f64);
        for i in 0..120 {
            let theta = std::f64::consts::TAU * (i as f64 + 0.37) / 120.0;
            for j in 0..=25 {
                let rad = ring.gap
                    * (1.0 + 1e-9 + 0.0064 * (j * j) as f64 * (1.0 + 0.1 * (i % 3) as f64));
                let r = Vector2::new(rad * theta.cos(), rad * theta.sin());
                let (c, d) = check_against_brute(&ring, &r);
                seen[ring.regime(&r).unwrap().number() as usize] += 1;
                let it = ring.locate(&r).unwrap().iterations;
                iters = (iters.0.max(it), iters.1 + u64::from(it), iters.2 + 1);
                wc = wc.max(c);
                wd = wd.max(d);
            }
        }
        println!("{name:>22}: max ||r-s|-gap|/gap = {wc:.2e}, max |s - s_bf| = {wd:.2e}, regimes II..V seen {:?}, Newton iterations max {} mean {:.2}", &seen[2..], iters.0, iters.1 as f64 / iters.2 as f64);
        if ring.x.preload > 0.0 && ring.y.preload > 0.0 {
            assert!(
                seen[2..].iter().all(|&n| n > 0),
                "{name}: not all regimes hit"
            );
        }
        worst_c = worst_c.max(wc);
        worst_d = worst_d.max(wd);
    }
    println!("overall: constraint {worst_c:.2e}, brute force {worst_d:.2e}");
}

fn arb_ring() -> impl Strategy<Value = SnubberRing> {
    (
        0.5f64..100.0,
        0.0f64..2.0,
        0.5f64..100.0,
        0.0f64..2.0,
        0.3f64..2.0,
        any::<bool>(),
        prop::bool::weighted(0.15),
    )
        .prop_map(|(kx, dx, ky, dy, gap, iso, zero)| {
            let (ky, dy) = if iso { (kx, dy) } else { (ky, dy) };
            let (dx, dy) = if zero { (0.0, dy) } else { (dx, dy) };
            ring(kx, dx, ky, dy, gap)
        })
}

fn arb_point(gap: f64) -> impl Strategy<Value = Vector2<f64>> {
    (1e-9f64..5.0, 0.0f64..std::f64::consts::TAU).prop_map(move |(e, t)| {
        let rad = gap * (1.0 + e);
        Vector2::new(rad * t.cos(), rad * t.sin())
    })
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 400,
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(
            "proptest-regressions/ring_locate.txt"
        ))),
        ..crate::rng::proptest_defaults()
    })]

    #[test]
    fn solver_matches_brute_force((ring, r) in arb_ring().prop_flat_map(|ring| (Just(ring), arb_point(ring.gap)))) {
        check_against_brute(&ring, &r);
    }

    #[test]
    fn mirror_symmetry((ring, r) in arb_ring().prop_flat_map(|ring| (Just(ring), arb_point(ring.gap)))) {
        let c = ring.locate(&r).unwrap();
        for (sx, sy) in [(-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
            let m = ring.locate(&Vector2::new(sx * r.x, sy * r.y)).unwrap();
            prop_assert_eq!(m.s, Vector2::new(sx * c.s.x, sy * c.s.y));
            prop_assert_eq!(m.regime(), c.regime());
            prop_assert_eq!(m.mu, c.mu);
            // J transforms as M J M with M = diag(sx, sy).
            prop_assert_eq!(m.jacobian[(0, 1)], sx * sy * c.jacobian[(0, 1)]);
            prop_assert_eq!(m.jacobian[(0, 0)], c.jacobian[(0, 0)]);
        }
    }

    #[test]
    fn jacobian_matches_finite_differences((ring, r) in arb_ring().prop_flat_map(|ring| (Just(ring), arb_point(ring.gap)))) {
        let h = 1e-6 * r.norm();
        let c = ring.locate(&r).unwrap();
        let mut fd = nalgebra::Matrix2::zeros();
        for j in 0..2 {
            let mut e = Vector2::zeros();
            e[j] = h;
            let (p, m) = (r + e, r - e);
            if p.norm() <= ring.gap * (1.0 + 1e-9) || m.norm() <= ring.gap * (1.0 + 1e-9) {
                return Ok(());
            }
            let (cp, cm) = (ring.locate(&p).unwrap(), ring.locate(&m).unwrap());
            // Skip points next to a regime boundary: J jumps there.
            if cp.regime() != c.regime() || cm.regime() != c.regime() {
                return Ok(());
            }
            let col = (cp.s - cm.s) / (2.0 * h);
            fd.set_column(j, &col);
        }
        // Accuracy of the central difference: curvature is ~1/(|r| - gap) near grazing.
        let scale = 1.0 + 1e-6 / ((r.norm() - ring.gap) / ring.gap).powi(2);
        let err = (fd - c.jacobian).abs().max();
        prop_assert!(err <= 2e-7 * scale, "J error {err:e} at {r:?} ({})", c.regime());
    }
}

#[test]
fn closed_forms_agree_with_solver() {
    let mut n = [0usize; 2];
    for (dx, dy) in [(1.5, 1.1), (0.1, 0.1), (0.0, 0.0), (0.3, 0.9)] {
        for gap in [1.0, 0.4] {
            let ring = ring(30.0, dx, 30.0, dy, gap);
            for i in 0..360 {
                let t = (i as f64 + 0.5).to_radians();
                for j in 1..40 {
                    let rad = gap * (1.0 + 0.1 * j as f64);
                    let r = Vector2::new(rad * t.cos(), rad * t.sin());
                    let c = ring.locate(&r).unwrap();
                    match c.regime() {
                        Regime::II => {
                            let s = regime_ii_position(&r, gap).unwrap();
                            assert!((s - c.s).norm() <= 1e-13 * rad, "II at {r:?}");
                            assert_eq!(c.iterations, 0);
                            n[0] += 1;
                        }
                        Regime::V => {
                            let s = regime_v_position(&r, dx, dy, gap).unwrap();
                            assert!((s - c.s).norm() <= 1e-13 * rad, "V at {r:?}");
                            assert_eq!(c.iterations, 0);
                            n[1] += 1;
                        }
                        Regime::III => {
                            // Table 3 (III): x_s = sign(x_r)[2 y_s (|x_r| + Dx)/(y_r + y_s) - Dx]
                            // and (y_r - y_s)^2 ((|x_r| + Dx)^2 + (y_r + y_s)^2) = gap^2 (y_r + y_s)^2,
                            // written on |y_r|, |y_s| (they share the sign).
                            let (yr, ys) = (r.y.abs(), c.s.y.abs());
                            if yr > 0.0 {
                                let xs =
                                    (2.0 * ys * (r.x.abs() + dx) / (yr + ys) - dx) * r.x.signum();
                                assert_relative_eq!(xs, c.s.x, epsilon = 1e-12);
                                let lhs = (yr - ys).powi(2)
                                    * ((r.x.abs() + dx).powi(2) + (yr + ys).powi(2));
                                let rhs = gap * gap * (yr + ys).powi(2);
                                assert_relative_eq!(lhs, rhs, max_relative = 1e-12);
                            }
                        }
                        _ => {}
                    }
                }
            }
        }
    }
    assert!(n[0] > 100 && n[1] > 100, "{n:?}");
}

#[test]
fn zero_preload_limit_is_linear() {
    let base = ring(30.0, 0.0, 30.0, 0.0, 1.0);
    for i in 0..50 {
        let t = (7.3 * i as f64 + 1.0).to_radians();
        let rad = 1.05 + 0.05 * i as f64;
        let r = Vector2::new(rad * t.cos(), rad * t.sin());
        let s0 = base.locate(&r).unwrap().s;
        let errs: Vec<f64> = [1e-3, 1e-4, 1e-5]
            .iter()
            .map(|&d| {
                let ring = ring(30.0, d, 30.0, 0.7 * d, 1.0);
                (ring.locate(&r).unwrap().s - s0).norm() / d
            })
            .collect();
        // err/D tends to a constant (first-order convergence).
        assert!(errs[0] < 5.0, "{errs:?}");
        assert_relative_eq!(errs[1], errs[2], max_relative = 0.05, epsilon = 1e-6);
    }
}

#[test]
fn normal_force_elastic_part_is_two_mu_gap() {
    let ring = ring(30.0, 0.4, 12.0, 0.2, 0.8);
    for i in 0..100 {
        let t = (3.7 * i as f64).to_radians();
        let r = Vector2::new(1.7 * t.cos(), 1.3 * t.sin());
        let c = ring.locate(&r).unwrap();
        let zero = Vector2::zeros();
        assert_relative_eq!(
            c.normal_force(&zero),
            2.0 * c.mu * ring.gap,
            max_relative = 1e-12
        );
        // Elastic force is parallel to the normal: g = 2 mu d.
        let g = ring.elastic_force(&c.s);
        assert!((g - c.normal * (2.0 * c.mu * ring.gap)).norm() <= 1e-11 * g.norm());
        // Force with velocity equals g + C J r'.
        let rd = Vector2::new(0.3, -1.1);
        let f = c.force(&rd);
        let expect = g + ring
            .damping_coefficients(&c.s)
            .component_mul(&(c.jacobian * rd));
        assert!((f - expect).norm() <= 1e-12 * f.norm());
    }
}

#[test]
fn ring_velocity_keeps_contact() {
    // d/dt |r - s|^2 = 2 d . (I - J) r' = 0: J preserves the constraint to first order.
    let ring = ring(30.0, 1.5, 30.0, 1.1, 1.0);
    for i in 0..200 {
        let t = (1.9 * i as f64).to_radians();
        let r = Vector2::new(
            (1.01 + 0.02 * i as f64) * t.cos(),
            (1.01 + 0.02 * i as f64) * t.sin(),
        );
        let c = ring.locate(&r).unwrap();
        for rd in [Vector2::new(1.0, 0.0), Vector2::new(0.0, 1.0)] {
            let v = rd - c.ring_velocity(&rd);
            assert!(c.normal.dot(&v).abs() <= 1e-12, "{}", c.normal.dot(&v));
        }
    }
}

#[test]
fn typed_errors_name_the_field() {
    let ok = RingAxis::new(30.0, 0.1);
    let e = SnubberRing::new(RingAxis::new(f64::NAN, 0.1), ok, 0.0, 1.0).unwrap_err();
    assert!(matches!(
        e,
        RingError::NonFinite {
            field: "x.stiffness",
            ..
        }
    ));
    let e = SnubberRing::new(ok, RingAxis::new(30.0, -0.1), 0.0, 1.0).unwrap_err();
    assert_eq!(
        e,
        RingError::Negative {
            field: "y.preload",
            value: -0.1
        }
    );
    let e = SnubberRing::new(ok, RingAxis::new(0.0, 0.1), 0.0, 1.0).unwrap_err();
    assert!(matches!(
        e,
        RingError::NotPositive {
            field: "y.stiffness",
            ..
        }
    ));
    let e = SnubberRing::new(ok, ok, -1.0, 1.0).unwrap_err();
    assert!(matches!(
        e,
        RingError::Negative {
            field: "damping",
            ..
        }
    ));
    let e = SnubberRing::new(ok, ok, 0.0, 0.0).unwrap_err();
    assert!(matches!(e, RingError::NotPositive { field: "gap", .. }));
    let e = SnubberRing::new(ok, ok, f64::INFINITY, 1.0).unwrap_err();
    assert!(matches!(
        e,
        RingError::NonFinite {
            field: "damping",
            ..
        }
    ));
    let e = SnubberRing::isotropic(30.0, f64::NAN, 0.0).unwrap_err();
    assert!(matches!(
        e,
        RingError::NonFinite {
            field: "x.preload",
            ..
        }
    ));
    assert!(e.to_string().contains("x.preload"));

    let ring = SnubberRing::isotropic(30.0, 0.1, 0.002).unwrap();
    let e = ring.locate(&Vector2::new(0.5, 0.5)).unwrap_err();
    assert!(matches!(e, RingError::InsideGap { .. }));
    let e = ring.locate(&Vector2::new(1.0, 0.0)).unwrap_err();
    assert!(
        matches!(e, RingError::InsideGap { .. }),
        "|r| = gap is not contact"
    );
    let e = ring.locate(&Vector2::new(f64::NAN, 2.0)).unwrap_err();
    assert!(matches!(e, RingError::NonFinite { field: "r.x", .. }));
    let e = ring
        .regime(&Vector2::new(0.0, f64::NEG_INFINITY))
        .unwrap_err();
    assert!(matches!(e, RingError::NonFinite { field: "r.y", .. }));
    assert_eq!(ring.regime(&Vector2::new(0.5, 0.5)).unwrap(), Regime::I);

    // A ring edited into an invalid state errors instead of panicking.
    let mut bad = ring;
    bad.x.stiffness = 0.0;
    assert!(bad.locate(&Vector2::new(3.0, 0.0)).is_err());
    // Bad hints are ignored.
    for hint in [f64::NAN, -1.0, f64::INFINITY, 1e300] {
        let a = ring.locate_from(&Vector2::new(1.4, 0.7), hint).unwrap();
        let b = ring.locate(&Vector2::new(1.4, 0.7)).unwrap();
        assert!((a.s - b.s).norm() < 1e-14);
    }
    assert!(regime_ii_position(&Vector2::new(0.1, 0.1), 1.0).is_err());
    assert!(matches!(
        regime_v_position(&Vector2::new(2.0, 0.1), -1.0, 0.0, 1.0),
        Err(RingError::Negative { field: "dx", .. })
    ));
}

#[test]
fn regime_display_and_numbers() {
    let all = [Regime::I, Regime::II, Regime::III, Regime::IV, Regime::V];
    let names: Vec<String> = all.iter().map(|r| r.to_string()).collect();
    assert_eq!(names, ["I", "II", "III", "IV", "V"]);
    assert_eq!(all.map(|r| r.number()), [1, 2, 3, 4, 5]);
}

#[test]
fn extreme_inputs_do_not_panic() {
    let ring = ring(1e6, 1e-8, 1e-3, 10.0, 1.0);
    for r in [
        Vector2::new(1.0 + 1e-15, 0.0),
        Vector2::new(1e8, -1e8),
        Vector2::new(0.0, -1e3),
        Vector2::new(-1e-300, 1.0000001),
    ] {
        let c = ring.locate(&r).unwrap();
        assert!(c.s.iter().all(|v| v.is_finite()), "{r:?}: {c:?}");
        assert!(
            ((r - c.s).norm() - 1.0).abs() <= 1e-12 * r.norm().max(1.0),
            "{r:?}"
        );
    }
}
