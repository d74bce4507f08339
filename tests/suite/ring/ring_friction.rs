//! The ring with friction (`ring::friction`) against forward constructions (a ring position
//! whose slip law holds by construction, and the rotor position it implies), a scan of the
//! contact direction, central differences, the frictionless solver and typed errors.

use jeffcott::ring::{
    Branches, ContactStart, FrictionRing, RingAxis, RingError, RollContact, Slip, SnubberRing,
};
use nalgebra::{Matrix2, Vector2};
use proptest::prelude::*;
use proptest::test_runner::FileFailurePersistence;

fn ring(kx: f64, dx: f64, ky: f64, dy: f64, gap: f64) -> SnubberRing {
    SnubberRing::new(RingAxis::new(kx, dx), RingAxis::new(ky, dy), 0.002, gap).unwrap()
}

/// The inverse of one axis' elastic force law: `s` with `g(s) = f` (MODEL.md's table: `2Ks`
/// inside the preload, `sign(s) K (|s| + D)` beyond it).
fn inverse_force(axis: &RingAxis, f: f64) -> f64 {
    let (k, d) = (axis.stiffness, axis.preload);
    if f.abs() <= 2.0 * k * d {
        f / (2.0 * k)
    } else {
        f.signum() * (f.abs() / k - d)
    }
}

/// A slipping contact by construction: the contact direction `theta`, the elastic normal force
/// `n_force` and `kappa = mu sigma` give `g(s) = N (n + kappa t)`, hence `s`, hence
/// `r = s + gap n`. Returns `(r, s)`.
fn constructed(
    ring: &SnubberRing,
    theta: f64,
    n_force: f64,
    kappa: f64,
) -> (Vector2<f64>, Vector2<f64>) {
    let n = Vector2::new(theta.cos(), theta.sin());
    let t = Vector2::new(-n.y, n.x);
    let g = (n + t * kappa) * n_force;
    let s = Vector2::new(inverse_force(&ring.x, g.x), inverse_force(&ring.y, g.y));
    (s + n * ring.gap, s)
}

/// A slipping contact constructed for a property case: the sense from `forward`, the normal
/// force `10^load max K gap`; the rotor position, the constructed ring position, the ring with
/// friction and the located contact.
struct Case {
    slip: Slip,
    n_force: f64,
    r: Vector2<f64>,
    s: Vector2<f64>,
    rub: FrictionRing,
    c: jeffcott::ring::SlipContact,
}

fn case(ring: SnubberRing, mu: f64, theta: f64, load: f64, forward: bool) -> Case {
    let slip = if forward {
        Slip::Forward
    } else {
        Slip::Backward
    };
    let n_force = 10f64.powf(load) * ring.x.stiffness.max(ring.y.stiffness) * ring.gap;
    let (r, s) = constructed(&ring, theta, n_force, mu * slip.sign());
    let rub = FrictionRing::new(ring, mu).unwrap();
    let c = rub.locate_slipping(&r, slip).unwrap();
    Case {
        slip,
        n_force,
        r,
        s,
        rub,
        c,
    }
}

fn cases() -> ProptestConfig {
    ProptestConfig {
        cases: 2000,
        failure_persistence: Some(Box::new(FileFailurePersistence::Off)),
        ..crate::rng::proptest_defaults()
    }
}

/// A ring and a friction coefficient below its uniqueness bound.
fn ring_and_friction() -> impl Strategy<Value = (SnubberRing, f64)> {
    rings(prop_oneof![Just(0.0), 0.0f64..1.5])
}

/// As [`ring_and_friction`], with preloads (in gaps) drawn from `preload`.
fn rings(preload: impl Strategy<Value = f64> + Clone) -> impl Strategy<Value = (SnubberRing, f64)> {
    (
        -1.0f64..3.0,
        -1.0f64..3.0,
        preload.clone(),
        preload,
        prop_oneof![Just(1.0), 1e-4f64..10.0],
        0.0f64..0.999,
    )
        .prop_map(|(lx, ly, dx, dy, gap, frac)| {
            let r = ring(10f64.powf(lx), dx * gap, 10f64.powf(ly), dy * gap, gap);
            let limit = FrictionRing::limit(&r).min(2.0);
            (r, frac * limit)
        })
}

proptest! {
    #![proptest_config(cases())]

    /// Every constructed contact is found again, in both slip senses, on every regime.
    #[test]
    fn finds_the_constructed_contact(
        (ring, mu) in ring_and_friction(),
        theta in -3.2f64..3.2,
        load in -4.0f64..1.0,
        forward in any::<bool>(),
    ) {
        let Case { slip, n_force, r, s, c, .. } = case(ring, mu, theta, load, forward);
        let scale = r.norm() + ring.gap;
        prop_assert!((c.s - s).norm() <= 1e-12 * scale, "s {:?} vs {:?}", c.s, s);
        prop_assert!(((r - c.s).norm() - ring.gap).abs() <= 4e-15 * scale);
        let (nf, ft) = (c.elastic_normal(), c.elastic_tangential());
        // Relative plus absolute: a light contact's N is as accurate as the position it is
        // read at (the elastic force of a position error of 1e-13 of the scale; a CI run
        // met N = 1.4e-3 K off by 2.2e-11 of itself, from a position 3.1e-14 off).
        let k_max = ring.x.stiffness.max(ring.y.stiffness);
        prop_assert!(
            (nf - n_force).abs() <= 1e-11 * n_force * scale / ring.gap + 1e-13 * k_max * scale,
            "N {nf} vs {n_force}"
        );
        prop_assert!((ft - mu * slip.sign() * nf).abs() <= 1e-12 * nf);
    }
}

/// Samples of the contact direction's scan in [`scanned_locations`].
const SCAN_STEPS: usize = 4096;

/// The contact directions `theta` on a scan of the circle where the slip law
/// `t.g - kappa n.g = 0` changes sign with `n.g > 0` (`g` at `s = r - gap n`): the slipping
/// locations (the end of the scan's step that holds each), found without the crate's solver.
fn scanned_locations(ring: &SnubberRing, r: &Vector2<f64>, kappa: f64) -> Vec<f64> {
    let law = |th: f64| {
        let n = Vector2::new(th.cos(), th.sin());
        let t = Vector2::new(-n.y, n.x);
        let g = ring.elastic_force(&(r - n * ring.gap));
        (t.dot(&g) - kappa * n.dot(&g), n.dot(&g))
    };
    let steps = SCAN_STEPS;
    let mut found = Vec::new();
    let mut prev = law(0.0);
    for i in 1..=steps {
        let th = i as f64 * std::f64::consts::TAU / steps as f64;
        let cur = law(th);
        if (prev.0 < 0.0) != (cur.0 < 0.0) && prev.1 > 0.0 && cur.1 > 0.0 {
            found.push(th);
        }
        prev = cur;
    }
    found
}

/// Below the uniqueness bound a scan of the contact direction finds one slipping location at
/// every rotor position of a grid, the solver's; beyond it (here 1 against a bound of 0.202
/// for a stiffness ratio of 100) positions with three exist, which is why
/// `FrictionRing::new` refuses such a coefficient.
#[test]
fn one_location_below_the_bound_and_several_beyond_it() {
    let ring = ring(1.0, 0.0, 100.0, 0.0, 1.0);
    let limit = FrictionRing::limit(&ring);
    assert!((limit - 2.0 * 25f64.sqrt() / 49.5).abs() < 1e-15);
    let grid = (0..40).flat_map(|i| (0..40).map(move |j| (i, j)));
    let at = |(i, j): (i32, i32)| Vector2::new(-3.0 + 0.15 * i as f64, -3.0 + 0.15 * j as f64);
    let rub = FrictionRing::new(ring, 0.95 * limit).unwrap();
    for r in grid.clone().map(at).filter(|r| r.norm() > 1.01) {
        for slip in [Slip::Forward, Slip::Backward] {
            let found = scanned_locations(&ring, &r, rub.friction() * slip.sign());
            assert_eq!(found.len(), 1, "r = {r:?}: {found:?}");
            let n = rub.locate_slipping(&r, slip).unwrap().normal;
            let th = n.y.atan2(n.x).rem_euclid(std::f64::consts::TAU);
            let step = std::f64::consts::TAU / SCAN_STEPS as f64;
            assert!(
                (found[0] - step..=found[0]).contains(&th),
                "r = {r:?}: {th} vs {found:?}"
            );
        }
    }
    let several = grid
        .map(at)
        .filter(|r| r.norm() > 1.01 && scanned_locations(&ring, r, 1.0).len() > 1)
        .count();
    assert!(several > 0, "no position with several locations at mu = 1");
    assert_eq!(
        FrictionRing::new(ring, 1.0),
        Err(RingError::FrictionBeyondUniqueness {
            friction: 1.0,
            limit
        })
    );
}

proptest! {
    #![proptest_config(cases())]

    /// Without friction every field is the frictionless solver's, bit for bit, warm or cold,
    /// chosen branches or given ones.
    #[test]
    fn without_friction_it_is_the_frictionless_ring(
        (ring, _) in ring_and_friction(),
        x in -4.0f64..4.0,
        y in -4.0f64..4.0,
    ) {
        let r = Vector2::new(x, y) * ring.gap;
        prop_assume!(r.norm() > ring.gap);
        let rub = FrictionRing::new(ring, 0.0).unwrap();
        let plain = ring.locate(&r).unwrap();
        for slip in [Slip::Forward, Slip::Backward] {
            let c = rub.locate_slipping(&r, slip).unwrap();
            prop_assert_eq!((c.s, c.multiplier, c.jacobian), (plain.s, plain.mu, plain.jacobian));
            prop_assert_eq!((c.elastic, c.normal, c.branches), (plain.elastic, plain.normal, plain.branches));
            let near = r * 0.999;
            let on = rub.locate_slipping_on(&near, slip, plain.branches, plain.mu).unwrap();
            let e = ring.locate_on(&near, plain.branches, plain.mu).unwrap();
            prop_assert_eq!((on.s, on.multiplier, on.jacobian), (e.s, e.mu, e.jacobian));
        }
    }

    /// The ring's velocity `J r'` against central differences of the location on fixed
    /// branches, and the slip law along the way.
    #[test]
    fn jacobian_matches_central_differences(
        (ring, mu) in ring_and_friction(),
        theta in -3.2f64..3.2,
        load in -3.0f64..0.5,
        forward in any::<bool>(),
    ) {
        let Case { slip, r, rub, c, .. } = case(ring, mu, theta, load, forward);
        // Richardson's extrapolation of two central differences: error O(h^4). Near the
        // uniqueness bound J grows (to 220 in a case CI met, mu at 0.996 of its bound) and the
        // location curves on a scale shorter by as much: the step shrinks with it (a step of
        // 1e-6 |r| there left 2e-5 of J; 1e-8 agrees to 1e-8).
        let h = 1e-6 * (r.norm() + ring.gap) / (1.0 + c.jacobian.norm());
        let central = |k: usize, h: f64| {
            let mut e = Vector2::zeros();
            e[k] = h;
            let at = |x: Vector2<f64>| rub.locate_slipping_on(&x, slip, c.branches, c.multiplier).unwrap().s;
            (at(r + e) - at(r - e)) / (2.0 * h)
        };
        for k in 0..2 {
            let fd = (central(k, 0.5 * h) * 4.0 - central(k, h)) / 3.0;
            let col = c.jacobian.column(k).clone_owned();
            let scale = 1.0 + c.jacobian.norm();
            prop_assert!((fd - col).norm() <= 1e-7 * scale, "column {}: {:?} vs {:?}", k, fd, col);
        }
    }

    /// Across a preload the location is continuous: a contact constructed with the ring on an
    /// axis' preload, approached from both sides, moves by no more than its Jacobian allows.
    #[test]
    fn continuous_across_the_regime_boundaries(
        (ring, mu) in rings(1e-3f64..1.5),
        side in any::<bool>(),
        on_y in any::<bool>(),
        other in -1.0f64..1.0,
        angle in -3.2f64..3.2,
        forward in any::<bool>(),
    ) {
        let (axis, far) = if on_y { (ring.y, ring.x) } else { (ring.x, ring.y) };
        let slip = if forward { Slip::Forward } else { Slip::Backward };
        let kappa = mu * slip.sign();
        // The ring on the preload of one axis; the other axis anywhere; the normal from the
        // slip law g = N (n + kappa t) with N > 0: g's direction turned back by atan(kappa).
        let sign = if side { 1.0 } else { -1.0 };
        let on = sign * axis.preload;
        let free = other * 2.0 * (far.preload + ring.gap);
        let s = if on_y { Vector2::new(free, on) } else { Vector2::new(on, free) };
        let g = ring.elastic_force(&s);
        prop_assume!(g.norm() > 0.0);
        let dir = g.y.atan2(g.x) - kappa.atan();
        let r = s + Vector2::new(dir.cos(), dir.sin()) * ring.gap;
        let rub = FrictionRing::new(ring, mu).unwrap();
        let c = rub.locate_slipping(&r, slip).unwrap();
        let scale = r.norm() + ring.gap;
        prop_assert!((c.s - s).norm() <= 1e-11 * scale, "{:?} vs {:?}", c.s, s);
        let step = Vector2::new(angle.cos(), angle.sin()) * 1e-7 * scale;
        for r2 in [r + step, r - step] {
            let c2 = rub.locate_slipping(&r2, slip).unwrap();
            let bound = 2.0 * step.norm() * (1.0 + c.jacobian.norm().max(c2.jacobian.norm()));
            prop_assert!((c2.s - c.s).norm() <= bound, "jump {:e} > {:e}", (c2.s - c.s).norm(), bound);
        }
    }
}

/// Rolling at the frictionless location: no tangential force, the frictionless normal force,
/// and no slip at the rolling ring's velocity.
#[test]
fn rolling_at_the_frictionless_direction_has_no_tangential_force() {
    let ring = ring(30.0, 0.1, 12.0, 0.05, 1.0);
    let rub = FrictionRing::new(ring, 0.3).unwrap();
    let r = Vector2::new(0.8, 0.75);
    let plain = ring.locate(&r).unwrap();
    let roll = rub
        .rolling(&r, plain.normal.y.atan2(plain.normal.x))
        .unwrap();
    let n_plain = 2.0 * plain.mu * ring.gap;
    assert!((roll.s - plain.s).norm() < 1e-15);
    assert!(roll.elastic_tangential().abs() < 1e-13 * n_plain);
    assert!((roll.elastic_normal() - n_plain).abs() < 1e-13 * n_plain);
    assert!(roll.stick_margin(0.3) > 0.0);
    // s' = r' + eta a t: the contact point does not slip.
    let (r_dot, surface) = (Vector2::new(0.4, -1.3), 2.5);
    let s_dot = roll.ring_velocity(&r_dot, surface);
    assert!(((r_dot - s_dot).dot(&roll.tangent) + surface).abs() < 1e-15);
    assert_eq!(RollContact::angle_rate(surface, ring.gap), -2.5);
    // Turned away from it, the tangential force grows and sets the sense of the release.
    let turned = rub.rolling(&r, roll.angle + 0.2).unwrap();
    assert!(turned.elastic_tangential().abs() > 0.0);
    assert_eq!(
        turned.release().map(Slip::sign),
        Some(turned.elastic_tangential().signum())
    );
}

/// The start rule against slip velocities computed from central differences of the two slip
/// locations along the rotor's motion (not the crate's Jacobian): forward if `v+ > 0`,
/// backward if `v- < 0`, rolling otherwise, an error if both.
#[test]
fn a_contact_starts_by_the_sign_of_the_slip_velocities() {
    let ring = ring(30.0, 0.05, 20.0, 0.0, 1.0);
    let rub = FrictionRing::new(ring, 0.4).unwrap();
    let r = Vector2::new(0.6, 0.8) * (1.0 + 1e-3);
    let n = r.normalize();
    let t = Vector2::new(-n.y, n.x);
    let velocity = |slip: Slip, r_dot: &Vector2<f64>, surface: f64| {
        let h = 1e-7;
        let c = rub.locate_slipping(&r, slip).unwrap();
        let plus = rub.locate_slipping(&(r + r_dot * h), slip).unwrap();
        let minus = rub.locate_slipping(&(r - r_dot * h), slip).unwrap();
        let s_dot = (plus.s - minus.s) / (2.0 * h);
        (r_dot - s_dot).dot(&c.tangent) + surface
    };
    let mut seen = [false; 4];
    for radial in [1.0, -1.0] {
        for tangential in [-2.0, -0.5, 0.0, 0.5, 2.0] {
            for surface in [-1.0, -0.2, 0.0, 0.3, 1.5] {
                let r_dot = n * radial + t * tangential;
                let (vp, vm) = (
                    velocity(Slip::Forward, &r_dot, surface),
                    velocity(Slip::Backward, &r_dot, surface),
                );
                if vp.abs() < 1e-6 || vm.abs() < 1e-6 {
                    continue; // too near a decision for differences to decide
                }
                let start = rub.start(&r, &r_dot, surface);
                let case = format!("r' = {r_dot:?}, eta a = {surface}: v+ {vp}, v- {vm}");
                match start {
                    Ok(ContactStart::Slipping(c)) if vp > 0.0 && vm >= 0.0 => {
                        assert_eq!(c.friction, 0.4, "{case}");
                        seen[0] = true;
                    }
                    Ok(ContactStart::Slipping(c)) if vm < 0.0 && vp <= 0.0 => {
                        assert_eq!(c.friction, -0.4, "{case}");
                        seen[1] = true;
                    }
                    Ok(ContactStart::Rolling(roll)) if vp <= 0.0 && vm >= 0.0 => {
                        assert!(roll.stick_margin(0.4) >= 0.0, "{case}");
                        seen[2] = true;
                    }
                    Err(RingError::SlipAmbiguous { .. }) if vp > 0.0 && vm < 0.0 => {
                        assert!(radial < 0.0, "ambiguous moving outward: {case}");
                        seen[3] = true;
                    }
                    other => panic!("{case}: {other:?}"),
                }
            }
        }
    }
    assert_eq!(seen, [true; 4], "every outcome met");
}

/// Bad input is named.
#[test]
fn bad_input_is_a_typed_error() {
    let ring = ring(30.0, 0.1, 30.0, 0.1, 1.0);
    for (mu, field) in [(f64::NAN, "friction"), (-0.1, "friction")] {
        let e = FrictionRing::new(ring, mu).unwrap_err();
        assert!(
            matches!(e, RingError::NonFinite { field: f, .. } | RingError::Negative { field: f, .. } if f == field),
            "{e:?}"
        );
    }
    assert!(matches!(
        FrictionRing::new(ring, 3.0),
        Err(RingError::FrictionBeyondUniqueness { .. })
    ));
    let rub = FrictionRing::new(ring, 0.3).unwrap();
    assert!(matches!(
        rub.locate_slipping(&Vector2::new(0.5, 0.5), Slip::Forward),
        Err(RingError::InsideGap { .. })
    ));
    assert!(matches!(
        rub.locate_slipping(&Vector2::new(f64::NAN, 2.0), Slip::Forward),
        Err(RingError::NonFinite { .. })
    ));
    assert!(matches!(
        rub.rolling(&Vector2::new(1.2, 0.0), f64::INFINITY),
        Err(RingError::NonFinite { field: "angle", .. })
    ));
    let deep = rub.locate_slipping_on(
        &Vector2::new(0.01, 0.0),
        Slip::Forward,
        Branches::of(&ring, &Vector2::new(0.5, 0.0)),
        f64::NAN,
    );
    assert!(
        matches!(deep, Err(RingError::NoPlacement { .. })),
        "{deep:?}"
    );
}

/// The accuracy and iterations over 1e5 constructed contacts (random rings as in the property
/// tests, gap 1), printed for docs/friction.md
/// (`cargo test --test suite ring::ring_friction::accuracy -- --nocapture`).
#[test]
fn accuracy_over_constructed_contacts() {
    let mut state = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let (mut worst_s, mut worst_law, mut cold, mut warm, mut most) = (0f64, 0f64, 0u64, 0u64, 0);
    let cases = 100_000;
    for _ in 0..cases {
        let preload = |u: f64| (u - 0.3).max(0.0) * 1.5;
        let (kx, ky) = (
            10f64.powf(4.0 * next() - 1.0),
            10f64.powf(4.0 * next() - 1.0),
        );
        let ring = ring(kx, preload(next()), ky, preload(next()), 1.0);
        let mu = 0.999 * next() * FrictionRing::limit(&ring).min(2.0);
        let slip = if next() < 0.5 {
            Slip::Forward
        } else {
            Slip::Backward
        };
        let n_force = 10f64.powf(5.0 * next() - 4.0) * kx.max(ky);
        let (r, s) = constructed(&ring, 7.0 * next(), n_force, mu * slip.sign());
        let rub = FrictionRing::new(ring, mu).unwrap();
        let c = rub.locate_slipping(&r, slip).unwrap();
        worst_s = worst_s.max((c.s - s).norm() / (r.norm() + 1.0));
        let law = (c.elastic_tangential() - mu * slip.sign() * c.elastic_normal()).abs();
        worst_law = worst_law.max(law / c.elastic_normal());
        cold += u64::from(c.iterations);
        let near = r + Vector2::new(1e-3, -1e-3);
        if let Ok(w) = rub.locate_slipping_on(&near, slip, c.branches, c.multiplier) {
            warm += u64::from(w.iterations);
            most = most.max(w.iterations);
        }
    }
    println!(
        "{cases} constructed contacts: |s - s_true|/(|r| + gap) <= {worst_s:.1e}, \
         |F_t - mu sigma N|/N <= {worst_law:.1e}; iterations: {:.2} cold, {:.2} warm (at most {most})",
        cold as f64 / cases as f64,
        warm as f64 / cases as f64
    );
    assert!(worst_s <= 1e-12 && worst_law <= 1e-12);
}

proptest! {
    #![proptest_config(cases())]

    /// The loss force of a slipping or rolling contact: where it is negative the ring, released
    /// now, parts from the rotor (the contact distance of the relaxing ring, `SnubberRing::relax`,
    /// and the rotor moving on at `r'`, falls: measured by a difference here); where the
    /// normal force alone is negative but the loss force is not (anisotropic damping), the
    /// released ring would move back into the rotor. For isotropic damping it is `n . f`.
    #[test]
    fn a_ring_released_at_a_negative_loss_force_parts(
        (ring, mu) in rings(prop_oneof![Just(0.0), 0.01f64..1.5]),
        theta in -3.2f64..3.2,
        load in -3.0f64..0.5,
        forward in any::<bool>(),
        (vx, vy) in (-3.0f64..3.0, -3.0f64..3.0),
        surface in -2.0f64..2.0,
    ) {
        let ring = SnubberRing { damping: 0.05, ..ring };
        let Case { n_force, r, rub, c, .. } = case(ring, mu, theta, load, forward);
        let r_dot = Vector2::new(vx, vy) * ring.gap;
        let roll = rub.rolling(&r, c.normal.y.atan2(c.normal.x)).unwrap();
        let cases = [
            (c.loss_force(&r_dot), c.normal_force(&r_dot), c.damping),
            (roll.loss_force(&r_dot, surface), roll.normal.dot(&roll.force(&r_dot, surface)), roll.damping),
        ];
        // The contact distance h = |r - s|^2 - gap^2 of the released ring, at a small time.
        let dt = 1e-7 * ring.gap / (1.0 + r_dot.norm());
        let h = |t: f64| (r + r_dot * t - ring.relax(&c.s, t)).norm_squared() - ring.gap * ring.gap;
        let rate = (h(dt) - h(0.0)) / dt;
        let scale = ring.gap * (r_dot.norm() + n_force / ring.damping);
        for (loss, normal, damping) in cases {
            prop_assert!(loss >= normal);
            if damping.x == damping.y {
                prop_assert_eq!(loss, normal);
            }
            if loss < -1e-6 * n_force {
                prop_assert!(rate < 1e-6 * scale, "loss {:e}, yet parting rate {:e}", loss, rate);
            }
            if normal < -1e-6 * n_force && loss > 1e-6 * n_force {
                prop_assert!(rate > -1e-6 * scale, "separation {:e} without the ring returning", loss);
            }
        }
    }
}

proptest! {
    #![proptest_config(cases())]

    /// The slipping ring's second derivatives, its force's Jacobian and the slip velocity's
    /// gradient against Richardson-extrapolated central differences of the location on fixed
    /// branches.
    #[test]
    fn second_derivatives_match_differences(
        (ring, mu) in rings(prop_oneof![Just(0.0), 0.01f64..1.5]),
        theta in -3.2f64..3.2,
        load in -2.0f64..0.5,
        forward in any::<bool>(),
        (vx, vy) in (-3.0f64..3.0, -3.0f64..3.0),
    ) {
        let ring = SnubberRing { damping: 0.05, ..ring };
        let Case { slip, r, rub, c, .. } = case(ring, mu, theta, load, forward);
        let v = Vector2::new(vx, vy) * ring.gap;
        let hess = rub.slip_hessian(&c);
        let jac = rub.slip_force_jacobian(&c, &v);
        let grad = rub.slip_velocity_gradient(&c, &v);
        let at = |x: Vector2<f64>| rub.locate_slipping_on(&x, slip, c.branches, c.multiplier).unwrap();
        // The location curves on the gap's scale, whatever |r| (a soft axis under a large
        // load puts the rotor thousands of gaps out): a step of 1e-5 |r| there left a
        // Richardson error of 5e-6 (a CI run met it), 1e-5 of the gap leaves 1e-10.
        let h = 1e-5 * ring.gap;
        // Richardson on a vector-valued central difference of `f` along axis k.
        let diff = |k: usize, f: &dyn Fn(&jeffcott::ring::SlipContact) -> Vec<f64>| {
            let central = |h: f64| {
                let mut e = Vector2::zeros();
                e[k] = h;
                let (p, m) = (f(&at(r + e)), f(&at(r - e)));
                p.iter().zip(&m).map(|(a, b)| (a - b) / (2.0 * h)).collect::<Vec<_>>()
            };
            let (coarse, fine) = (central(h), central(0.5 * h));
            fine.iter().zip(&coarse).map(|(f, c)| (4.0 * f - c) / 3.0).collect::<Vec<_>>()
        };
        let size = |x: &[f64]| x.iter().fold(0f64, |a, b| a.max(b.abs()));
        for k in 0..2 {
            let dj = diff(k, &|c| c.jacobian.iter().copied().collect());
            let got: Vec<f64> = hess.jacobian_derivative[k].iter().copied().collect();
            let scale = 1.0 + size(&got) + c.jacobian.norm();
            prop_assert!(dj.iter().zip(&got).all(|(a, b)| (a - b).abs() <= 1e-6 * scale), "dJ/dr_{}: {:?} vs {:?}", k, dj, got);
            let dm = diff(k, &|c| vec![c.multiplier]);
            let m_scale = 1.0 + hess.mu_gradient.norm() + c.multiplier.abs();
            prop_assert!((dm[0] - hess.mu_gradient[k]).abs() <= 1e-6 * m_scale);
            let dmg = diff(k, &|c| rub.slip_hessian(c).mu_gradient.iter().copied().collect());
            let hm = hess.mu_hessian.column(k);
            prop_assert!((dmg[0] - hm[0]).abs().max((dmg[1] - hm[1]).abs()) <= 1e-6 * (1.0 + hess.mu_hessian.norm() + m_scale));
            let df = diff(k, &|c| c.force(&v).iter().copied().collect());
            let col = jac.position.column(k);
            let f_scale = 1.0 + jac.position.norm();
            prop_assert!((df[0] - col[0]).abs().max((df[1] - col[1]).abs()) <= 1e-6 * f_scale);
            let dv = diff(k, &|c| vec![c.slip_velocity(&v, 0.7)]);
            prop_assert!((dv[0] - grad.r[k]).abs() <= 1e-6 * (1.0 + grad.r.norm()));
        }
        // Linear in v: the velocity parts exactly.
        prop_assert!((jac.velocity - Matrix2::from_diagonal(&c.damping) * c.jacobian).norm() <= 1e-15 * jac.velocity.norm());
        let (e1, e2) = (Vector2::x(), Vector2::y());
        let lin = Vector2::new(
            c.slip_velocity(&(v + e1), 0.7) - c.slip_velocity(&v, 0.7),
            c.slip_velocity(&(v + e2), 0.7) - c.slip_velocity(&v, 0.7),
        );
        prop_assert!((lin - grad.v).norm() <= 1e-12 * (1.0 + v.norm()) * (1.0 + c.jacobian.norm()));
        if mu == 0.0 {
            let plain = ring.locate(&r).unwrap();
            prop_assert_eq!(hess, ring.contact_hessian(&plain));
        }
    }

    /// The rolling contact's stick margin gradient against central differences in the rotor's
    /// position and the contact direction.
    #[test]
    fn stick_margin_gradient_matches_differences(
        (ring, mu) in rings(prop_oneof![Just(0.0), 0.01f64..1.5]),
        (x, y) in (-3.0f64..3.0, -3.0f64..3.0),
        angle in -3.2f64..3.2,
    ) {
        let r = Vector2::new(x, y) * ring.gap;
        let rub = FrictionRing::new(ring, mu).unwrap();
        let roll = rub.rolling(&r, angle).unwrap();
        prop_assume!(roll.elastic_tangential().abs() > 1e-6 * roll.elastic.norm());
        let (grad_r, grad_angle) = rub.stick_margin_gradient(&roll);
        let h = 1e-7 * (r.norm() + ring.gap);
        let margin = |x: Vector2<f64>, a: f64| rub.rolling(&x, a).unwrap().stick_margin(mu);
        // Only where no preload lies within the difference's reach (the force's slope jumps).
        let same = |x: Vector2<f64>, a: f64| rub.rolling(&x, a).unwrap().branches == roll.branches;
        for k in 0..2 {
            let mut e = Vector2::zeros();
            e[k] = h;
            if same(r + e, angle) && same(r - e, angle) {
                let fd = (margin(r + e, angle) - margin(r - e, angle)) / (2.0 * h);
                prop_assert!((fd - grad_r[k]).abs() <= 1e-6 * (1.0 + grad_r.norm()));
            }
        }
        let ha = 1e-7;
        if same(r, angle + ha) && same(r, angle - ha) {
            let fd = (margin(r, angle + ha) - margin(r, angle - ha)) / (2.0 * ha);
            prop_assert!((fd - grad_angle).abs() <= 1e-6 * (1.0 + grad_angle.abs() + roll.elastic.norm() * ring.gap));
        }
    }
}
