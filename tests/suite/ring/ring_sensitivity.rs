//! The ring's analytic derivatives (`ring` (derivatives)) against central finite differences of
//! the quantities they differentiate, on every branch combination (the smooth extension of each
//! contact regime), isotropic and anisotropic rings, with and without preload.
//!
//! Central differences with step `h` have a truncation error ~ h^2 |f'''|/6 and a rounding
//! error ~ eps |f|/h; at h = 1e-5 both are near 1e-10 relative for these O(1)..O(100)
//! quantities. The margins below are stated per check, a few times above what was measured.

use jeffcott::ring::{
    Axis, Branch, Branches, Kinematics, Relaxation, RingAxis, RingCache, RingGuard, RingMode,
    SnubberRing,
};
use nalgebra::{Matrix2, Vector2};

const H: f64 = 1e-5;

fn rings() -> Vec<SnubberRing> {
    let a = |k, d| RingAxis::new(k, d);
    vec![
        SnubberRing::isotropic(30.0, 0.0, 0.002).unwrap(),
        SnubberRing::isotropic(30.0, 0.1, 0.002).unwrap(),
        SnubberRing::new(a(30.0, 0.1), a(12.0, 0.3), 0.2, 1.0).unwrap(),
        SnubberRing::new(a(30.0, 0.05), a(60.0, 0.0), 3.0, 1.0).unwrap(),
        SnubberRing::new(a(30.0, 0.05), a(30.0, 0.1), 0.02, 1.3).unwrap(),
    ]
}

/// Every branch combination the ring has (outer sides from the sign of the rotor coordinate).
fn branch_sets(ring: &SnubberRing, r: &Vector2<f64>) -> Vec<Branches> {
    let options = |axis: &RingAxis, ri: f64| {
        let side = if ri >= 0.0 { 1 } else { -1 };
        if axis.preload == 0.0 {
            vec![Branch::Outer(0)]
        } else {
            vec![Branch::Inner, Branch::Outer(side)]
        }
    };
    let mut out = Vec::new();
    for bx in options(&ring.x, r.x) {
        for by in options(&ring.y, r.y) {
            out.push(Branches { x: bx, y: by });
        }
    }
    out
}

/// Rotor positions and velocities around the circle, slightly to well beyond it.
fn kinematics(gap: f64) -> Vec<Kinematics> {
    (0..24)
        .map(|i| {
            let ang = 0.3 + i as f64 * 0.27;
            let rad = gap * (1.0 + 0.01 * (1 + i % 5) as f64);
            let v =
                Vector2::new((1.7 * ang).cos(), (0.9 * ang).sin()) * (0.2 + 0.1 * (i % 4) as f64);
            Kinematics {
                r: Vector2::new(rad * ang.cos(), rad * ang.sin()),
                v,
            }
        })
        .collect()
}

/// Central difference of `f` along each rotor coordinate.
fn fd_columns<T: Fn(&Vector2<f64>) -> Vector2<f64>>(f: T, r: &Vector2<f64>) -> Matrix2<f64> {
    let col = |k: usize| {
        let (mut p, mut m) = (*r, *r);
        p[k] += H;
        m[k] -= H;
        (f(&p) - f(&m)) / (2.0 * H)
    };
    Matrix2::from_columns(&[col(0), col(1)])
}

fn fd_gradient<T: Fn(&Vector2<f64>) -> f64>(f: T, x: &Vector2<f64>) -> Vector2<f64> {
    let d = |k: usize| {
        let (mut p, mut m) = (*x, *x);
        p[k] += H;
        m[k] -= H;
        (f(&p) - f(&m)) / (2.0 * H)
    };
    Vector2::new(d(0), d(1))
}

/// Runs `check(ring, branches, kinematics)` on every case; returns the number of cases.
fn for_each_case(mut check: impl FnMut(&SnubberRing, Branches, &Kinematics)) -> usize {
    let mut n = 0;
    for ring in rings() {
        for k in kinematics(ring.gap) {
            for b in branch_sets(&ring, &k.r) {
                if ring.locate_on(&k.r, b, f64::NAN).is_ok() {
                    check(&ring, b, &k);
                    n += 1;
                }
            }
        }
    }
    n
}

#[test]
fn hessian_of_the_located_ring_matches_finite_differences_of_its_jacobian() {
    let mut worst = (0.0f64, 0.0f64);
    let n = for_each_case(|ring, b, k| {
        let c = ring.locate_on(&k.r, b, f64::NAN).unwrap();
        let hess = ring.contact_hessian(&c);
        let at = |r: &Vector2<f64>| ring.locate_on(r, b, f64::NAN).unwrap();
        // dJ/dr_k against differences of J, column by column.
        for j in 0..2 {
            let fd = fd_columns(|r| at(r).jacobian.column(j).into_owned(), &k.r);
            for kk in 0..2 {
                let an = hess.jacobian_derivative[kk].column(j).into_owned();
                let scale = 1.0 + an.norm();
                worst.0 = worst.0.max((an - fd.column(kk)).norm() / scale);
            }
        }
        // dmu/dr and its Hessian against differences of mu and of the analytic gradient.
        let g = fd_gradient(|r| at(r).mu, &k.r);
        worst.1 = worst
            .1
            .max((g - hess.mu_gradient).norm() / (1.0 + g.norm()));
        let dg = fd_columns(|r| ring.contact_hessian(&at(r)).mu_gradient, &k.r);
        worst.1 = worst
            .1
            .max((dg - hess.mu_hessian).norm() / (1.0 + dg.norm()));
    });
    assert!(n > 300, "{n} cases");
    eprintln!("hessian: {worst:?}, {n} cases");
    // Measured: 1.0e-9 / 5.1e-10 (relative to 1 + |value|).
    assert!(worst.0 < 5e-9 && worst.1 < 5e-9, "{worst:?}");
}

#[test]
fn contact_force_jacobian_matches_finite_differences() {
    let mut worst = 0.0f64;
    let n = for_each_case(|ring, b, k| {
        let c = ring.locate_on(&k.r, b, f64::NAN).unwrap();
        let jac = ring.force_jacobian(&c, &k.v);
        let force =
            |r: &Vector2<f64>, v: &Vector2<f64>| ring.locate_on(r, b, f64::NAN).unwrap().force(v);
        let dr = fd_columns(|r| force(r, &k.v), &k.r);
        let dv = fd_columns(|v| force(&k.r, v), &k.v);
        let scale = 1.0 + jac.position.norm();
        worst = worst
            .max((dr - jac.position).norm() / scale)
            .max((dv - jac.velocity).norm() / scale);
    });
    assert!(n > 300);
    eprintln!("force: {worst:e}");
    // Measured: 2.3e-10 relative to 1 + |dF/dr| (|dF/dr| up to ~200).
    assert!(worst < 3e-9, "{worst:e}");
}

#[test]
fn guard_gradients_match_finite_differences_of_the_guard_values() {
    let mut worst = 0.0f64;
    let mut separation_active = 0;
    let n = for_each_case(|ring, b, k| {
        let mode = RingMode::Contact(b);
        let mut guards = vec![RingGuard::Loss, RingGuard::Gap];
        for (axis, branch, d) in [
            (Axis::X, b.x, ring.x.preload),
            (Axis::Y, b.y, ring.y.preload),
        ] {
            if d > 0.0 {
                guards.push(RingGuard::Preload {
                    axis,
                    outward: branch == Branch::Inner,
                });
            }
        }
        let c = ring.locate_on(&k.r, b, f64::NAN).unwrap();
        if c.separation_force(&k.v) > c.normal_force(&k.v) {
            separation_active += 1;
        }
        for g in guards {
            let cache = RingCache::default();
            let an = ring.guard_gradient(&mode, g, 0.0, k, &cache).unwrap();
            let value = |r: &Vector2<f64>, v: &Vector2<f64>| {
                ring.guard_value(
                    &mode,
                    g,
                    0.0,
                    &Kinematics { r: *r, v: *v },
                    &RingCache::default(),
                )
            };
            let fr = fd_gradient(|r| value(r, &k.v), &k.r);
            let fv = fd_gradient(|v| value(&k.r, v), &k.v);
            // The loss force max(N, lambda) has a kink where N = lambda: skip points within
            // the difference step of it.
            if g == RingGuard::Loss {
                let gap = (c.normal_force(&k.v) - c.separation_force(&k.v)).abs();
                if gap != 0.0 && gap < 1e-3 {
                    continue;
                }
            }
            let scale = 1.0 + an.r.norm() + an.v.norm();
            worst = worst.max(((fr - an.r).norm() + (fv - an.v).norm()) / scale);
            assert_eq!(an.s, Vector2::zeros());
            assert_eq!(an.t, 0.0);
        }
    });
    assert!(n > 300);
    assert!(
        separation_active > 10,
        "the lambda branch must be exercised: {separation_active}"
    );
    eprintln!("guards: {worst:e}, lambda active {separation_active}");
    // Measured: 1.9e-10.
    assert!(worst < 3e-9, "{worst:e}");
}

#[test]
fn onset_gradient_matches_finite_differences_in_rotor_ring_and_time() {
    let mut worst = 0.0f64;
    for ring in rings() {
        // Start at t0 = 0: differences in time of a few 1e-10 need t itself at that scale.
        let relax = Relaxation {
            t0: 0.0,
            s0: Vector2::new(0.3 * ring.gap, -0.25 * ring.gap),
        };
        let mode = RingMode::free(relax);
        let tc = ring.relaxation_time().max();
        for k in kinematics(ring.gap) {
            for frac in [0.3, 1.0, 3.0] {
                let t = relax.t0 + frac * tc;
                let cache = RingCache::default();
                let an = ring
                    .guard_gradient(&mode, RingGuard::Onset, t, &k, &cache)
                    .unwrap();
                let value = |r: &Vector2<f64>, t: f64| {
                    ring.guard_value(
                        &mode,
                        RingGuard::Onset,
                        t,
                        &Kinematics { r: *r, v: k.v },
                        &cache,
                    )
                };
                let fr = fd_gradient(|r| value(r, t), &k.r);
                // Richardson-extrapolated central differences in time (truncation O(ht^4)):
                // h is O(1) while its time derivative can be small, so the step must be large
                // against the rounding of h (eps/ht).
                let central = |ht: f64| (value(&k.r, t + ht) - value(&k.r, t - ht)) / (2.0 * ht);
                let ht = 1e-3 * tc;
                let ft = (4.0 * central(0.5 * ht) - central(ht)) / 3.0;
                // d/ds at fixed r: h = |r - s|^2 - gap^2.
                let (s, _) = relax.at(&ring, t);
                let fs = fd_gradient(|s| (k.r - s).norm_squared() - ring.gap * ring.gap, &s);
                let scale = 1.0 + an.r.norm() + an.t.abs();
                worst = worst
                    .max((fr - an.r).norm() / scale)
                    .max((fs - an.s).norm() / scale)
                    .max((ft - an.t).abs() / scale);
                assert_eq!(an.v, Vector2::zeros());
            }
        }
    }
    eprintln!("onset gradient: {worst:e}");
    // Measured: 1.2e-9 (the time derivative, rounding of h over the step: eps/ht).
    assert!(worst < 5e-9, "{worst:e}");
}

#[test]
fn relaxation_sensitivities_match_finite_differences_before_and_after_the_preload_crossing() {
    let mut worst = 0.0f64;
    let mut halved = 0;
    for ring in rings() {
        let tc = ring.relaxation_time();
        for s0 in [
            Vector2::new(0.03, -0.02),
            Vector2::new(0.45, -0.2),
            Vector2::new(-0.6, 0.35),
            Vector2::new(0.0, 0.5),
        ] {
            let relax = Relaxation { t0: 0.0, s0 };
            for frac in [0.05, 0.4, 1.0, 2.5, 7.0] {
                let t = relax.t0 + frac * tc.max();
                let an = relax.sensitivity(&ring, t);
                let an_t = relax.start_time_sensitivity(&ring, t);
                let crossings = ring.time_to_preload(&s0);
                for i in 0..2 {
                    // Skip points within the difference steps of a crossing (a kink in t and s0).
                    let u = t - relax.t0;
                    if (u - crossings[i]).abs() < 1e-3 * tc[i] {
                        continue;
                    }
                    let hs = 1e-6 * (s0[i].abs() + 0.01);
                    let at = |s: f64, t0: f64| {
                        let mut s0 = s0;
                        s0[i] = s;
                        ring.relax(&s0, t - t0)[i]
                    };
                    let fd = (at(s0[i] + hs, relax.t0) - at(s0[i] - hs, relax.t0)) / (2.0 * hs);
                    let ht = 1e-6 * tc[i];
                    let fd_t = (at(s0[i], relax.t0 + ht) - at(s0[i], relax.t0 - ht)) / (2.0 * ht);
                    worst = worst.max((fd - an[i]).abs());
                    worst = worst.max((fd_t - an_t[i]).abs() / (1.0 + an_t[i].abs()));
                    let expect = (-(u / tc[i])).exp();
                    if ring.damping > 0.0 && (an[i] - 0.5 * expect).abs() < 1e-15 {
                        halved += 1;
                    }
                }
            }
        }
    }
    assert!(
        halved >= 8,
        "the factor 1/2 after a crossing must be exercised: {halved}"
    );
    eprintln!("relaxation: {worst:e}, {halved} halved");
    // Measured: 3.0e-10 (absolute; the sensitivity is at most 1).
    assert!(worst < 2e-9, "{worst:e}");
}

#[test]
fn relaxation_sensitivity_without_ring_damping_is_zero_after_the_start() {
    let ring = SnubberRing::isotropic(30.0, 0.1, 0.0).unwrap();
    let relax = Relaxation {
        t0: 1.0,
        s0: Vector2::new(0.3, 0.05),
    };
    assert_eq!(relax.sensitivity(&ring, 1.0 + 1e-12), Vector2::zeros());
    assert_eq!(relax.sensitivity(&ring, 1.0), Vector2::new(1.0, 1.0));
    assert_eq!(relax.start_time_sensitivity(&ring, 2.0), Vector2::zeros());
}

#[test]
fn hessian_of_the_located_ring_is_symmetric() {
    for_each_case(|ring, b, k| {
        let c = ring.locate_on(&k.r, b, f64::NAN).unwrap();
        let h = ring.contact_hessian(&c);
        for j in 0..2 {
            for kk in 0..2 {
                let (a, bb) = (
                    h.jacobian_derivative[kk].column(j).into_owned(),
                    h.jacobian_derivative[j].column(kk).into_owned(),
                );
                assert!((a - bb).norm() <= 1e-12 * (1.0 + a.norm()), "{a} {bb}");
            }
        }
        assert!(
            (h.mu_hessian - h.mu_hessian.transpose()).norm() <= 1e-12 * (1.0 + h.mu_hessian.norm())
        );
    });
}
