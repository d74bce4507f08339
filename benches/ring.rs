//! Snubber-ring element: cost of locating the ring (per regime, cold and warm-started,
//! anisotropic), of the closed forms alone, of the force evaluation, and of the slipping ring
//! with friction (chosen branches, and warm on fixed branches as an integrator calls it).

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use jeffcott::ring::{
    regime_ii_position, regime_v_position, FrictionRing, Regime, RingAxis, Slip, SnubberRing,
};
use nalgebra::Vector2;

fn paper_ring() -> SnubberRing {
    SnubberRing::new(
        RingAxis::new(30.0, 1.5),
        RingAxis::new(30.0, 1.1),
        0.002,
        1.0,
    )
    .unwrap()
}

fn bench_locate(c: &mut Criterion) {
    let ring = paper_ring();
    // Fixed rotor positions, one per regime (checked below).
    let cases = [
        (Regime::II, Vector2::new(1.2, 0.9)),
        (Regime::III, Vector2::new(2.8, 0.6)),
        (Regime::IV, Vector2::new(0.5, 2.3)),
        (Regime::V, Vector2::new(2.6, 2.0)),
    ];
    let mut group = c.benchmark_group("ring_locate");
    for (regime, r) in cases {
        let contact = ring.locate(&r).unwrap();
        assert_eq!(contact.regime(), regime);
        group.bench_function(format!("cold/{regime}"), |b| {
            b.iter(|| ring.locate(black_box(&r)).unwrap())
        });
        // Warm start from the multiplier of a nearby point (one integrator step away).
        let hint = ring.locate(&(r * 0.999)).unwrap().mu;
        group.bench_function(format!("warm/{regime}"), |b| {
            b.iter(|| ring.locate_from(black_box(&r), black_box(hint)).unwrap())
        });
    }
    let aniso = SnubberRing::new(
        RingAxis::new(30.0, 0.4),
        RingAxis::new(5.0, 0.7),
        0.002,
        1.0,
    )
    .unwrap();
    for r in [Vector2::new(1.1, 0.4), Vector2::new(2.0, 1.5)] {
        let regime = aniso.locate(&r).unwrap().regime();
        group.bench_function(format!("anisotropic/{regime}"), |b| {
            b.iter(|| aniso.locate(black_box(&r)).unwrap())
        });
    }
    let unpreloaded = SnubberRing::isotropic(30.0, 0.0, 0.002).unwrap();
    let r = Vector2::new(1.1, 0.3);
    group.bench_function("no_preload/V", |b| {
        b.iter(|| unpreloaded.locate(black_box(&r)).unwrap())
    });
    group.finish();
}

fn bench_closed_forms(c: &mut Criterion) {
    let mut group = c.benchmark_group("ring_closed_form");
    let r2 = Vector2::new(1.2, 0.9);
    group.bench_function("II", |b| {
        b.iter(|| regime_ii_position(black_box(&r2), black_box(1.0)).unwrap())
    });
    let r5 = Vector2::new(2.6, 2.0);
    group.bench_function("V", |b| {
        b.iter(|| regime_v_position(black_box(&r5), black_box(1.5), black_box(1.1), 1.0).unwrap())
    });
    group.finish();
}

fn bench_force(c: &mut Criterion) {
    let ring = paper_ring();
    let r = Vector2::new(2.8, 0.6);
    let rd = Vector2::new(0.3, -0.7);
    let contact = ring.locate(&r).unwrap();
    let mut group = c.benchmark_group("ring_force");
    group.bench_function("force(s, s')", |b| {
        b.iter(|| ring.force(black_box(&contact.s), black_box(&rd)))
    });
    group.bench_function("contact.force(J r')", |b| {
        b.iter(|| black_box(&contact).force(black_box(&rd)))
    });
    group.bench_function("locate+normal_force", |b| {
        b.iter(|| {
            let c = ring.locate(black_box(&r)).unwrap();
            c.normal_force(black_box(&rd))
        })
    });
    let s0 = Vector2::new(2.0, -0.5);
    group.bench_function("relax", |b| {
        b.iter(|| ring.relax(black_box(&s0), black_box(0.01)))
    });
    group.finish();
}

/// The slipping ring at the paper's ring (friction 0.3) per regime: chosen branches (what a
/// transition calls) and on fixed branches from the multiplier one step away (what each step
/// of an integrator calls).
fn bench_friction(c: &mut Criterion) {
    let rub = FrictionRing::new(paper_ring(), 0.3).unwrap();
    let mut group = c.benchmark_group("ring_slipping");
    for r in [
        Vector2::new(1.2, 0.9),
        Vector2::new(2.8, 0.6),
        Vector2::new(0.5, 2.3),
        Vector2::new(2.6, 2.0),
    ] {
        let contact = rub.locate_slipping(&r, Slip::Forward).unwrap();
        let regime = contact.regime();
        group.bench_function(format!("chosen/{regime}"), |b| {
            b.iter(|| rub.locate_slipping(black_box(&r), Slip::Forward).unwrap())
        });
        let hint = rub
            .locate_slipping_on(&(r * 0.999), Slip::Forward, contact.branches, f64::NAN)
            .unwrap()
            .multiplier;
        group.bench_function(format!("warm/{regime}"), |b| {
            b.iter(|| {
                rub.locate_slipping_on(black_box(&r), Slip::Forward, contact.branches, hint)
                    .unwrap()
            })
        });
    }
    group.finish();
}

criterion_group!(
    benches,
    bench_locate,
    bench_closed_forms,
    bench_force,
    bench_friction
);
criterion_main!(benches);
