//! The ring as a contact element: the loss rule keeps the parting consistent in every regime,
//! a touch places the ring and starts contact only under load, transitions flip the right
//! branches, and the branch solver either converges to its stated tolerance or says why not.

use jeffcott::ring::{
    Axis, Branch, Branches, Kinematics, Regime, RingAxis, RingCache, RingError, RingGuard,
    RingMode, SnubberRing,
};
use nalgebra::Vector2;
use proptest::prelude::*;

/// The ring solver's iteration limit, as docs/ring.md states it (`RingError::NotConverged`
/// after 100 steps; the constant itself is internal).
const SOLVER_MAX_ITERATIONS: u32 = 100;

fn ring(kx: f64, dx: f64, ky: f64, dy: f64, nu2: f64) -> SnubberRing {
    SnubberRing::new(RingAxis::new(kx, dx), RingAxis::new(ky, dy), nu2, 1.0).unwrap()
}

/// The branch a property test draws for an axis with preload `d`: the one branch of an
/// unpreloaded axis, else inner or either outer side by `seed` (0, 1, 2).
fn drawn_branch(d: f64, seed: usize) -> Branch {
    if d == 0.0 {
        Branch::Outer(0)
    } else {
        [Branch::Inner, Branch::Outer(1), Branch::Outer(-1)][seed]
    }
}

/// Deterministic pseudo-random numbers in [0, 1) (SplitMix64).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        (z ^ (z >> 31)) as f64 / 2f64.powi(64)
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
}

/// The rate at which the freed ring and the rotor part right after the ring is released at
/// `s` with the rotor moving at `v`: $h^\prime = 2 (r - s)\cdot(r^\prime - s^\prime_{free})$.
fn parting_rate(ring: &SnubberRing, r: Vector2<f64>, v: Vector2<f64>, s: Vector2<f64>) -> f64 {
    let s_dot = ring.relax_velocity(&s);
    2.0 * (r - s).dot(&(v - s_dot))
}

/// Finds the normal velocity `w` at which `force(v_t + w n)` crosses zero (falling with `w`
/// decreasing): the loss manifold through a given tangential velocity.
fn on_loss_manifold(f: impl Fn(f64) -> f64) -> f64 {
    let (mut lo, mut hi) = (-1e9, 1e9);
    assert!(f(lo) < 0.0 && f(hi) > 0.0);
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if f(m) > 0.0 {
            hi = m;
        } else {
            lo = m;
        }
    }
    hi
}

/// At contact loss the freed ring never moves into the rotor: after a loss by the crate's rule
/// `h' <= 0` (to rounding) in every regime, while the paper's criterion `N = 0` alone gives
/// `h' > 0` in regimes III and IV for some states (so it could not be the rule).
#[test]
fn released_ring_parts_from_the_rotor_in_every_regime() {
    let rings = [
        ring(30.0, 0.1, 30.0, 0.1, 0.002),
        ring(30.0, 0.05, 30.0, 0.05, 20.0),
        ring(30.0, 0.3, 12.0, 0.05, 3.0),
        ring(5.0, 0.0, 40.0, 0.2, 0.5),
    ];
    let mut rng = Rng(7);
    let (mut seen, mut worst_rule, mut worst_n) = ([0usize; 6], f64::NEG_INFINITY, 0.0f64);
    for ring in rings {
        for _ in 0..4000 {
            let rad = rng.range(1.0005, 1.6);
            let ang = rng.range(0.0, std::f64::consts::TAU);
            let r = Vector2::new(rad * ang.cos(), rad * ang.sin());
            let c = ring.locate(&r).unwrap();
            let n = c.normal;
            let tangent = Vector2::new(-n.y, n.x) * rng.range(-3.0, 3.0);
            let vel = |w: f64| tangent + n * w;
            // The crate's rule: max(N, lambda) falls through zero.
            let w = on_loss_manifold(|w| c.loss_force(&vel(w)));
            let v = vel(w);
            // h' is rounded relative to |r - s| (|r'| + |s'|).
            let scale = 2.0 * (v.norm() + ring.relax_velocity(&c.s).norm() + 1.0);
            let k = Kinematics { r, v };
            let next = ring
                .transition(
                    &RingMode::Contact(c.branches),
                    RingGuard::Loss,
                    0.0,
                    &k,
                    |f| -f,
                )
                .unwrap();
            let RingMode::Free {
                relax, separating, ..
            } = next.mode
            else {
                panic!("a loss must free the ring");
            };
            assert!(separating);
            let rate = parting_rate(&ring, r, v, relax.s0) / scale;
            // The onset guard's own rate agrees.
            let g = ring
                .guard_rate(&next.mode, RingGuard::Onset, 0.0, &k, &RingCache::default())
                .unwrap();
            assert!((g / scale - rate).abs() <= 1e-12);
            worst_rule = worst_rule.max(rate);
            seen[c.regime().number() as usize] += 1;
            // The paper's N alone.
            let w_n = on_loss_manifold(|w| c.normal_force(&vel(w)));
            let v_n = vel(w_n);
            let scale_n = 2.0 * (v_n.norm() + ring.relax_velocity(&c.s).norm() + 1.0);
            worst_n = worst_n.max(parting_rate(&ring, r, v_n, c.s) / scale_n);
        }
    }
    println!(
        "regimes II..V seen {:?}; worst relative parting rate after loss: rule {worst_rule:.2e}, N alone {worst_n:.2e}",
        &seen[2..]
    );
    assert!(seen[3] > 100 && seen[4] > 100, "III and IV sampled");
    assert!(
        worst_rule <= 1e-12,
        "freed ring moves into the rotor: {worst_rule:e}"
    );
    assert!(worst_n > 1e-3, "N alone should be inconsistent in III/IV");
}

/// A relaxed ring touched on the circle by a rotor moving outward starts contact, with and
/// without ring damping; moving inward (a touch without load) it does not.
#[test]
fn touch_on_the_circle_starts_contact_when_moving_outward() {
    for nu2 in [0.002, 0.0, 5.0] {
        let ring = ring(30.0, 0.1, 30.0, 0.1, nu2);
        for ang in [0.0, 0.3, 1.2, 2.5] {
            let n = Vector2::new(f64::cos(ang), f64::sin(ang));
            let t_dir = Vector2::new(-n.y, n.x);
            let free = RingMode::free(jeffcott::ring::Relaxation::at_rest(0.0));
            for (w, expect) in [(0.3, true), (1e-9, true), (-0.3, false)] {
                let k = Kinematics {
                    r: n,
                    v: n * w + t_dir * 0.7,
                };
                let tr = ring
                    .transition(&free, RingGuard::Onset, 3.0, &k, |f| -f)
                    .unwrap();
                assert_eq!(
                    tr.mode.is_contact(),
                    expect,
                    "nu2 {nu2}, angle {ang}, normal speed {w}: {:?}",
                    tr.mode
                );
                assert!(tr.s.norm() <= 1e-12);
            }
        }
    }
}

/// An unrelaxed ring that meets the rotor without load is placed at its minimum and the two
/// part at once (h' < 0), so time advances; inside the gap circle the ring goes to its centre.
#[test]
fn touch_without_load_places_the_ring_and_parts() {
    let ring = ring(30.0, 0.05, 30.0, 0.05, 20.0);
    let cache = RingCache::default();
    let mut rng = Rng(11);
    let (mut rejected, mut accepted) = (0, 0);
    for _ in 0..5000 {
        let rad = rng.range(1.0, 1.3);
        let ang = rng.range(0.0, std::f64::consts::TAU);
        let r = Vector2::new(rad * ang.cos(), rad * ang.sin());
        let v = Vector2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let k = Kinematics { r, v };
        let free = RingMode::free(jeffcott::ring::Relaxation::at_rest(0.0));
        let tr = ring
            .transition(&free, RingGuard::Onset, 1.0, &k, |f| -f)
            .unwrap();
        match tr.mode {
            RingMode::Contact(b) => {
                accepted += 1;
                let c = ring.locate_on(&r, b, f64::NAN).unwrap();
                assert!((c.s - tr.s).norm() == 0.0);
            }
            RingMode::Free {
                relax, separating, ..
            } => {
                rejected += 1;
                assert!(separating);
                assert_eq!(relax.s0, tr.s);
                let h = (r - tr.s).norm_squared() - 1.0;
                assert!(h.abs() <= 1e-14, "placed ring touches: h = {h:e}");
                let rate = ring
                    .guard_rate(&tr.mode, RingGuard::Onset, 1.0, &k, &cache)
                    .unwrap();
                assert!(rate <= 0.0, "a rejected touch must part: h' = {rate:e}");
            }
            _ => unreachable!(),
        }
    }
    assert!(rejected > 100 && accepted > 100, "{rejected} / {accepted}");
    // Inside the gap circle the ring goes to its centre.
    let k = Kinematics::new([0.5, 0.1], [0.1, 0.0]);
    let free = RingMode::free(jeffcott::ring::Relaxation {
        t0: 0.0,
        s0: Vector2::new(-0.49, -0.09),
    });
    let tr = ring
        .transition(&free, RingGuard::Onset, 0.0, &k, |f| -f)
        .unwrap();
    assert_eq!(tr.s, Vector2::zeros());
    assert!(!tr.mode.is_contact());
}

/// Guards: order, directions, labels; preload crossings flip the right axis, and a corner
/// flips both.
#[test]
fn preload_crossings_flip_branches_and_corners_flip_both() {
    let ring = ring(30.0, 0.1, 30.0, 0.1, 0.002);
    let inner = Branches {
        x: Branch::Inner,
        y: Branch::Inner,
    };
    let mode = RingMode::Contact(inner);
    assert_eq!(ring.guard_count(&mode), 4);
    let guards: Vec<_> = (0..4).map(|i| ring.guard(&mode, i).unwrap()).collect();
    assert_eq!(guards[0], RingGuard::Loss);
    assert_eq!(guards[1], RingGuard::Gap);
    assert_eq!(
        guards[2],
        RingGuard::Preload {
            axis: Axis::X,
            outward: true
        }
    );
    assert_eq!(guards[3].label(), "y_s beyond preload");
    assert!(ring.guard(&mode, 4).is_none());
    // The corner r_c = D + D/|D| (s* = (D_x, D_y)), moving outward along the diagonal.
    let d = 0.1f64;
    let q = 1.0 + 1.0 / (d * 2f64.sqrt());
    let k = Kinematics::new([d * q, d * q], [0.5, 0.5]);
    let cache = RingCache::default();
    let gx = ring.guard_value(&mode, guards[2], 0.0, &k, &cache);
    assert!(gx.abs() < 1e-12, "{gx:e}");
    let tr = ring.transition(&mode, guards[2], 0.0, &k, |f| -f).unwrap();
    assert_eq!(tr.mode.regime(), Regime::V, "{:?}", tr.mode);
    // Off the corner only x flips: at the x crossing on the line y = 0.05 (by bisection).
    let c = ring.locate(&Vector2::new(1.2, 0.05)).unwrap();
    let on_branches = RingMode::Contact(c.branches);
    let x_guard = RingGuard::Preload {
        axis: Axis::X,
        outward: c.branches.x == Branch::Inner,
    };
    let gx_at = |x: f64| {
        let k = Kinematics::new([x, 0.05], [1.0, 0.0]);
        ring.guard_value(&on_branches, x_guard, 0.0, &k, &cache)
    };
    let (mut lo, mut hi) = (1.0f64, 1.2f64);
    assert!(gx_at(lo) * gx_at(hi) < 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if gx_at(mid) * gx_at(lo) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let r = Vector2::new(hi, 0.05);
    let tr = ring
        .transition(
            &RingMode::Contact(c.branches),
            RingGuard::Preload {
                axis: Axis::X,
                outward: c.branches.x == Branch::Inner,
            },
            0.0,
            &Kinematics {
                r,
                // Moving across the preload the way the guard fires.
                v: Vector2::new(
                    if c.branches.x == Branch::Inner {
                        1.0
                    } else {
                        -1.0
                    },
                    0.0,
                ),
            },
            |f| -f,
        )
        .unwrap();
    let RingMode::Contact(b) = tr.mode else {
        panic!()
    };
    assert_ne!(b.x, c.branches.x);
    assert_eq!(b.y, c.branches.y);
}

/// Starting states: free, contact, tensile contact (separating), and typed errors for a
/// rotor beyond the ring or a ring away from its minimum.
#[test]
fn initial_modes_and_their_errors() {
    let ring = ring(30.0, 0.1, 30.0, 0.1, 0.002);
    let k = Kinematics::new([0.3, 0.2], [1.0, 0.0]);
    assert!(!ring
        .initial_mode(0.0, &k, &Vector2::zeros())
        .unwrap()
        .is_contact());
    let r = Vector2::new(1.1, 0.2);
    let s = ring.consistent_position(&r).unwrap();
    let out = Kinematics {
        r,
        v: r.normalize(),
    };
    assert!(ring.initial_mode(0.0, &out, &s).unwrap().is_contact());
    // A heavily damped ring pushed inward fast: the contact would pull.
    let damped = SnubberRing {
        damping: 5.0,
        ..ring
    };
    let inward = Kinematics { r, v: -r * 10.0 };
    match damped.initial_mode(0.0, &inward, &s).unwrap() {
        RingMode::Free { separating, .. } => assert!(separating),
        m => panic!("{m:?}"),
    }
    assert!(matches!(
        ring.initial_mode(0.0, &out, &Vector2::zeros()),
        Err(RingError::BeyondRing { .. })
    ));
    let off = s + Vector2::new(1e-3, 0.0);
    let shifted = Kinematics {
        r: r + Vector2::new(1e-3, 0.0),
        v: out.v,
    };
    assert!(matches!(
        ring.initial_mode(0.0, &shifted, &off),
        Err(RingError::RingOffMinimum { .. })
    ));
}

fn arb_branch(preload: f64) -> impl Strategy<Value = Branch> {
    prop_oneof![
        Just(Branch::Inner),
        Just(Branch::Outer(1)),
        Just(Branch::Outer(-1))
    ]
    .prop_map(move |b| if preload == 0.0 { Branch::Outer(0) } else { b })
}

proptest! {
    #![proptest_config(crate::rng::proptest_cases(2000))]

    /// The branch solver, over extreme anisotropy and the smooth extension of every branch
    /// (rotor inside or outside the circle): either a typed error, or a placement that meets
    /// the constraint and the Lagrange conditions to rounding.
    #[test]
    fn branch_solver_converges_or_says_why(
        kx in 1e-3f64..1e4, ky in 1e-3f64..1e4,
        dx in prop_oneof![Just(0.0), 1e-4f64..2.0], dy in prop_oneof![Just(0.0), 1e-4f64..2.0],
        rad in 0.9f64..6.0, ang in 0.0f64..std::f64::consts::TAU,
        bx_seed in 0usize..3, by_seed in 0usize..3,
    ) {
        let ring = ring(kx, dx, ky, dy, 0.01);
        let b = Branches { x: drawn_branch(dx, bx_seed), y: drawn_branch(dy, by_seed) };
        let r = Vector2::new(rad * ang.cos(), rad * ang.sin());
        match ring.locate_on(&r, b, f64::NAN) {
            Ok(c) => {
                let d = r - c.s;
                prop_assert!((d.norm() - 1.0).abs() <= 1e-13, "constraint {}", d.norm() - 1.0);
                // g_i(s) = 2 mu d_i on the branch formulas.
                let g = |axis: &RingAxis, branch: Branch, s: f64| match branch {
                    Branch::Inner => 2.0 * axis.stiffness * s,
                    Branch::Outer(sg) => axis.stiffness * (s + f64::from(sg) * axis.preload),
                };
                let scale = (kx.max(ky)) * (rad + dx.max(dy) + 1.0);
                let ex = (g(&ring.x, b.x, c.s.x) - 2.0 * c.mu * d.x).abs();
                let ey = (g(&ring.y, b.y, c.s.y) - 2.0 * c.mu * d.y).abs();
                prop_assert!(ex.max(ey) <= 1e-11 * scale, "Lagrange residual {ex:e} {ey:e}");
                prop_assert!(c.jacobian.iter().all(|v| v.is_finite()));
                prop_assert!(c.iterations < SOLVER_MAX_ITERATIONS);
            }
            Err(RingError::NoPlacement { .. }) => {}
            Err(e) => prop_assert!(false, "unexpected error {e}"),
        }
    }

    /// The batched guard evaluation (`guard_values`, one ring placement for every guard) gives
    /// bitwise the numbers of the one-guard methods (`guard_value`, `guard_rate_with_accel`),
    /// over random rings, rotor states (inside and outside the gap circle, so also the no
    /// placement path), free modes (a relaxing ring, an onset margin) and contact modes on
    /// every branch, with and without the acceleration, from a fresh or a warm cache.
    #[test]
    fn batched_guards_equal_single_guards_bitwise(
        kx in 1e-2f64..1e3, ky in 1e-2f64..1e3,
        dx in prop_oneof![Just(0.0), 1e-3f64..1.5], dy in prop_oneof![Just(0.0), 1e-3f64..1.5],
        nu2 in prop_oneof![Just(0.0), 1e-4f64..0.1],
        rad in 0.5f64..4.0, ang in 0.0f64..std::f64::consts::TAU,
        vx in -5.0f64..5.0, vy in -5.0f64..5.0, acc in prop::option::of((-50.0f64..50.0, -50.0f64..50.0)),
        free in any::<bool>(), s0 in (-2.0f64..2.0, -2.0f64..2.0), t0 in -1.0f64..1.0, dt in 0.0f64..10.0,
        margin in prop_oneof![Just(0.0), 0.0f64..1e-6],
        bx_seed in 0usize..3, by_seed in 0usize..3, warm in prop::option::of((1.0f64..3.0, 0.0f64..6.3)),
    ) {
        let ring = ring(kx, dx, ky, dy, nu2);
        let mode = if free {
            RingMode::Free {
                relax: jeffcott::ring::Relaxation { t0, s0: Vector2::new(s0.0, s0.1) },
                separating: false,
                onset_margin: margin,
            }
        } else {
            RingMode::Contact(Branches { x: drawn_branch(dx, bx_seed), y: drawn_branch(dy, by_seed) })
        };
        let t = t0 + dt;
        let k = Kinematics::new([rad * ang.cos(), rad * ang.sin()], [vx, vy]);
        let accel = acc.map(|(x, y)| Vector2::new(x, y));
        let (batched_cache, single_cache) = (RingCache::default(), RingCache::default());
        if let Some((wr, wa)) = warm {
            // The same earlier evaluation in both caches: a warm start for the next placement.
            let kw = Kinematics::new([wr * wa.cos(), wr * wa.sin()], [vx, vy]);
            for cache in [&batched_cache, &single_cache] {
                ring.guard_values(&mode, t, &kw, None, cache, &mut |_, _, _| {});
            }
        }
        let mut batched = Vec::new();
        ring.guard_values(&mode, t, &k, accel.as_ref(), &batched_cache, &mut |i, v, r| {
            batched.push((i, v, r));
        });
        prop_assert_eq!(batched.len(), ring.guard_count(&mode));
        for (n, (i, value, rate)) in batched.into_iter().enumerate() {
            prop_assert_eq!(i, n);
            let guard = ring.guard(&mode, i).unwrap();
            let single = ring.guard_value(&mode, guard, t, &k, &single_cache);
            let single_rate = accel
                .and_then(|a| ring.guard_rate_with_accel(&mode, guard, t, &k, &a, &single_cache));
            prop_assert_eq!(value.to_bits(), single.to_bits(), "{:?}: {} vs {}", guard, value, single);
            prop_assert_eq!(
                rate.map(f64::to_bits), single_rate.map(f64::to_bits),
                "{:?}: {:?} vs {:?}", guard, rate, single_rate
            );
            if accel.is_none() {
                prop_assert_eq!(rate, None);
            }
        }
    }

    /// `guard_values_with`, the acceleration from the ring's force at the contact the guards
    /// locate, gives bitwise the rates of the one-guard methods given the acceleration a
    /// right-hand side computes, $a - f$ with $f$ the force of `ring_state` (without a
    /// placement: $a$), and asks for the force at most once a point.
    #[test]
    fn guards_with_the_acceleration_from_the_ring_force_equal_single_guards_bitwise(
        kx in 1e-2f64..1e3, ky in 1e-2f64..1e3,
        dx in prop_oneof![Just(0.0), 1e-3f64..1.5], dy in prop_oneof![Just(0.0), 1e-3f64..1.5],
        nu2 in prop_oneof![Just(0.0), 1e-4f64..0.1],
        rad in 0.5f64..4.0, ang in 0.0f64..std::f64::consts::TAU,
        vx in -5.0f64..5.0, vy in -5.0f64..5.0, off_ring in (-50.0f64..50.0, -50.0f64..50.0),
        bx_seed in 0usize..3, by_seed in 0usize..3,
    ) {
        let ring = ring(kx, dx, ky, dy, nu2);
        let mode = RingMode::Contact(Branches { x: drawn_branch(dx, bx_seed), y: drawn_branch(dy, by_seed) });
        let t = 0.5;
        let k = Kinematics::new([rad * ang.cos(), rad * ang.sin()], [vx, vy]);
        let off_ring = Vector2::new(off_ring.0, off_ring.1);
        let (with_cache, single_cache) = (RingCache::default(), RingCache::default());
        let calls = std::cell::Cell::new(0);
        let accel_of = |f: &Vector2<f64>| {
            calls.set(calls.get() + 1);
            off_ring - f
        };
        let mut batched = Vec::new();
        ring.guard_values_with(&mode, t, &k, Some(&accel_of), &with_cache, &mut |i, v, r| {
            batched.push((i, v, r));
        });
        prop_assert!(calls.get() <= 1, "the force asked for {} times", calls.get());
        let accel = match ring.ring_state(&mode, t, &k, &single_cache) {
            Ok(state) => off_ring - state.force,
            Err(_) => off_ring,
        };
        prop_assert_eq!(batched.len(), ring.guard_count(&mode));
        for (i, value, rate) in batched {
            let guard = ring.guard(&mode, i).unwrap();
            let single = ring.guard_value(&mode, guard, t, &k, &single_cache);
            let single_rate = ring.guard_rate_with_accel(&mode, guard, t, &k, &accel, &single_cache);
            prop_assert_eq!(value.to_bits(), single.to_bits(), "{:?}: {} vs {}", guard, value, single);
            prop_assert_eq!(
                rate.map(f64::to_bits), single_rate.map(f64::to_bits),
                "{:?}: {:?} vs {:?}", guard, rate, single_rate
            );
        }
    }

    /// The chosen branches of the true minimiser are consistent with where the ring is.
    #[test]
    fn located_branches_match_the_ring_position(
        dx in 1e-3f64..1.0, dy in 1e-3f64..1.0,
        rad in 1.0001f64..4.0, ang in 0.0f64..std::f64::consts::TAU,
        b in arb_branch(1.0),
    ) {
        let _ = b;
        let ring = ring(30.0, dx, 7.0, dy, 0.01);
        let r = Vector2::new(rad * ang.cos(), rad * ang.sin());
        let c = ring.locate(&r).unwrap();
        let by_position = Branches::of(&ring, &c.s);
        let near = |s: f64, d: f64| (s.abs() - d).abs() <= 1e-9 * d;
        prop_assert!(c.branches.x == by_position.x || near(c.s.x, dx));
        prop_assert!(c.branches.y == by_position.y || near(c.s.y, dy));
    }
}

/// The analytic derivative of the loss force along a motion $r(t) = r_0 + v t + a t^2/2$ agrees
/// with a central difference of the loss force on the same branches, in every regime, for
/// isotropic and anisotropic rings (the anisotropic damping of regimes III and IV takes the
/// larger of $N$ and $\lambda$).
#[test]
fn loss_force_derivative_matches_finite_differences() {
    let rings = [
        ring(30.0, 0.0, 30.0, 0.0, 0.002),
        ring(30.0, 0.1, 30.0, 0.1, 0.002),
        ring(30.0, 0.1, 12.0, 0.3, 0.02),
        ring(1000.0, 0.05, 1000.0, 0.0, 0.01),
    ];
    let mut rng = Rng(7);
    let mut worst = 0.0f64;
    let mut cases = 0;
    for ring in rings {
        for _ in 0..400 {
            let ang = rng.range(0.0, std::f64::consts::TAU);
            let rad = rng.range(1.001, 1.3);
            let r0 = Vector2::new(rad * ang.cos(), rad * ang.sin());
            let v = Vector2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            let a = Vector2::new(rng.range(-5.0, 5.0), rng.range(-5.0, 5.0));
            let b = ring.locate(&r0).unwrap().branches;
            let load = |t: f64| {
                let r = r0 + v * t + a * (0.5 * t * t);
                let c = ring.locate_on(&r, b, f64::NAN).unwrap();
                (
                    c.normal_force(&(v + a * t)),
                    c.separation_force(&(v + a * t)),
                )
            };
            let c = ring.locate_on(&r0, b, f64::NAN).unwrap();
            let (n0, l0) = load(0.0);
            if n0 != l0 && (n0 - l0).abs() < 1e-3 * (1.0 + n0.abs()) {
                continue; // at the kink of max(N, lambda) the derivative is one-sided
            }
            let h = 1e-5;
            let pick = |(n, l): (f64, f64)| if n0 >= l0 { n } else { l };
            let fd = (pick(load(h)) - pick(load(-h))) / (2.0 * h);
            let exact = ring.loss_force_derivative(&c, &v, &a);
            let err = (exact - fd).abs() / (1.0 + fd.abs());
            worst = worst.max(err);
            cases += 1;
            assert!(
                err < 1e-6,
                "{ring:?} r {r0:?} v {v:?} a {a:?}: {exact} vs {fd}"
            );
        }
    }
    assert!(cases > 1000, "{cases} cases");
    println!("loss force derivative: worst relative error {worst:.1e} over {cases} cases");
}
