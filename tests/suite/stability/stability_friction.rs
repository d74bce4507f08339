//! The linearisation with friction at the ring (`Variational` for `rotor::RubbingRotor`):
//! the stroboscopic map's Jacobian through slip reversals, rolling and the roll-slip
//! transitions against Richardson central differences of the map itself (the map's own runs,
//! perturbed: no linearisation), and the Floquet multipliers of a synchronous full annular rub.

use super::stability_models::fd_jacobian;
use crate::ring::rub_energy::scene;

use jeffcott::hybrid::{simulate, OutputPlan, RotorModel, SimOptions, Trajectory};
use jeffcott::nalgebra::{DVector, Dyn};
use jeffcott::paper::rub::rubbing_model;
use jeffcott::params::Params;
use jeffcott::rotor::{LinearRotor, RubbingRotor};
use jeffcott::stability::{periodic_orbit, OrbitOptions, StroboscopicMap};

fn tight() -> SimOptions {
    SimOptions::default().with_rtol(1e-13).with_atol(1e-15)
}

/// The attractor's stroboscopic states that fall in free flight (label 1), from one run of
/// `transient` + `count` periods from rest: a section inside a contact with friction is not a
/// function of the rotor's state (the slip's sense, the roll's direction are its history).
fn free_sections(
    model: &RubbingRotor<LinearRotor>,
    transient: u64,
    count: u64,
) -> Vec<DVector<f64>> {
    let period = model.forcing_period();
    let plan = OutputPlan::strobe(period, transient, transient + count);
    let mut run: Trajectory<Dyn> = Trajectory::default();
    simulate(model, 0.0, &DVector::zeros(6), &plan, &tight(), &mut run).unwrap();
    run.strobe
        .iter()
        .filter(|s| s.label == 1)
        .map(|s| s.y.clone())
        .collect()
}

/// Over forcing periods of the attractor between sections in free flight, the map's Jacobian
/// through onsets into slip and into rolling, slip stops, rolling, ends of rolling and preload
/// crossings is its central differences' to their accuracy.
#[test]
fn the_maps_jacobian_through_slip_and_roll_matches_differences() {
    for (mu, a, p) in [
        (0.3, 0.05, scene(2.5, [0.0, 0.0])),
        // At eta 3 the forcing phase 3 puts the sections in free flight (at 0, half of them
        // fall in contact): slip stops and rolling every period.
        (
            0.3,
            0.05,
            Params {
                phi0: 3.0,
                ..scene(3.0, [0.0, 0.0])
            },
        ),
        (
            0.3,
            0.05,
            Params {
                phi0: 3.0,
                ..scene(3.0, [0.05, 0.02])
            },
        ),
    ] {
        let model = rubbing_model(&p, mu, a).unwrap();
        let map = StroboscopicMap::new(&model, 1, tight()).unwrap();
        let (mut worst, mut size, mut kinds, mut checked) = (0.0f64, 0.0f64, Vec::new(), 0);
        for y in free_sections(&model, 100, 12) {
            let lin = map.linearize(&y).unwrap();
            if lin.openness != [0.0, 0.0] {
                continue;
            }
            let fd = fd_jacobian(&map, &y, 1e-4);
            worst = worst.max((&lin.jacobian - &fd).abs().max());
            size = size.max(fd.abs().max());
            kinds.extend(lin.events.iter().map(|e| e.kind));
            checked += 1;
        }
        kinds.sort();
        kinds.dedup();
        println!(
            "mu {mu}, a {a}, eta {}, D ({}, {}): {checked} periods, |DP - FD| = {worst:.1e} (|DP| up to {size:.1e}); events {kinds:?}",
            p.eta, p.dx, p.dy
        );
        assert!(checked >= 3, "{checked} periods between free sections");
        assert!(kinds.contains(&"friction cone's edge"));
        if p.eta == 3.0 {
            assert!(kinds.contains(&"slip velocity zero"));
        }
        if p.dx > 0.0 {
            assert!(kinds.iter().any(|k| k.contains("preload")));
        }
        assert!(worst <= 1e-8 * (1.0 + size), "{worst:e}");
    }
}

/// The period-2 orbit of the Fig. 8 rotor at eta 2.5 with friction (one period slips, the
/// next rolls first, then slips): Newton's orbit and its multipliers from the linearisation
/// against the eigenvalues of the differences' map Jacobian at the orbit.
#[test]
fn the_multipliers_of_a_rubbing_orbit_are_those_of_the_differenced_map() {
    let model = rubbing_model(&scene(2.5, [0.0, 0.0]), 0.3, 0.05).unwrap();
    let start = free_sections(&model, 100, 1).remove(0);
    let opts = OrbitOptions::default().with_sim(tight());
    let orbit = periodic_orbit(&model, &start, 2, &opts).unwrap();
    let map = StroboscopicMap::new(&model, 2, tight()).unwrap();
    let fd = fd_jacobian(&map, &orbit.state, 1e-4);
    let mut want: Vec<f64> = fd.complex_eigenvalues().iter().map(|z| z.norm()).collect();
    let mut got: Vec<f64> = orbit.multipliers.iter().map(|m| m.modulus()).collect();
    want.sort_by(f64::total_cmp);
    got.sort_by(f64::total_cmp);
    let kinds: std::collections::BTreeSet<_> = orbit.events.iter().map(|e| e.kind).collect();
    println!("period-2 rub orbit: |multipliers| {got:?} against {want:?}; events {kinds:?}");
    assert!(kinds.contains("friction cone's edge"));
    assert!(orbit.spectral_radius() < 1.0, "an attractor");
    for (g, w) in got.iter().zip(&want) {
        assert!((g - w).abs() < 1e-8, "{g} against {w}");
    }
}
