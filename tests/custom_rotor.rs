//! `examples/custom_rotor`: a rotor written by a user on the public API, on the crate's ring.
//! With `q = k3 = 0` it is the paper's model with an integrated (instead of closed-form) free
//! flight: the two must agree over 300 forcing periods with the same contacts.

#[allow(dead_code)]
#[path = "../examples/custom_rotor/rotor.rs"]
mod rotor;

use jeffcott::hybrid::{simulate, OutputPlan, RotorModel, SimOptions, Trajectory};
use jeffcott::nalgebra::{SVector, U6};
use jeffcott::params::Preset;
use jeffcott::JeffcottModel;

/// Strobes k = 0..=300 and the event log of a run from rest.
fn run<M: RotorModel<Dim = U6>>(model: &M, period: f64) -> Trajectory<U6> {
    let opts = SimOptions {
        rtol: 1e-12,
        atol: 1e-14,
        ..SimOptions::default()
    };
    let plan = OutputPlan {
        events: true,
        ..OutputPlan::strobe(period, 0, 300)
    };
    let mut traj = Trajectory::default();
    simulate(model, 0.0, &SVector::zeros(), &plan, &opts, &mut traj).expect("run");
    traj
}

#[test]
fn without_cross_coupling_and_cubic_term_it_is_the_paper_model() {
    for (preset, eta) in [
        (Preset::Fig8a, 2.0),
        (Preset::Fig8b, 2.0),
        (Preset::Fig8b, 3.0),
    ] {
        let p = preset.params().with_eta(eta);
        let paper = run(&JeffcottModel::new(p).unwrap(), p.forcing_period());
        let custom = run(&rotor::on_ring(p, 0.0, 0.0).unwrap(), p.forcing_period());
        assert_eq!(paper.strobe.len(), 301);
        assert_eq!(custom.strobe.len(), 301);
        let worst = paper
            .strobe
            .iter()
            .zip(&custom.strobe)
            .map(|(a, b)| (a.y - b.y).amax())
            .fold(0.0f64, f64::max);
        let contacts = |t: &Trajectory<U6>| {
            t.events
                .iter()
                .filter(|e| e.kind == "contact onset")
                .count()
        };
        println!(
            "{preset:?} eta {eta}: max strobe difference {worst:.2e}, contacts {} / {}",
            contacts(&paper),
            contacts(&custom)
        );
        assert!(worst <= 1e-10, "{preset:?} eta {eta}: {worst:e}");
        assert_eq!(contacts(&paper), contacts(&custom));
        assert!(contacts(&paper) > 100);
    }
}

/// Without contact and cubic term the rotor is linear: with $z = u_x + i u_y$,
/// $z'' + 2\nu_1 z' + (1 - iq) z = B e^{i(\varphi_0 + \eta\tau)}$, whose steady orbit is
/// $z = Z e^{i(\varphi_0 + \eta\tau)}$ with $Z = B/(1 - \eta^2 - iq + 2i\nu_1\eta)$.
#[test]
fn cross_coupled_steady_orbit_matches_the_harmonic_solution() {
    let mut p = Preset::Fig8a.params().with_eta(1.3);
    p.beta = 0.05;
    p.ex = 0.1;
    let q = 0.08;
    let (b, nu, eta) = (p.forcing_amplitude(), p.nu1, p.eta);
    // Z = b / (re + i im)
    let (re, im) = (1.0 - eta * eta, 2.0 * nu * eta - q);
    let den = re * re + im * im;
    let z = (b * re / den, -b * im / den);
    assert!(p.ex + z.0.hypot(z.1) < 0.9, "must stay out of contact");
    let traj = run(&rotor::on_ring(p, q, 0.0).unwrap(), p.forcing_period());
    // The transient decays like exp(-nu1 tau): after 300 periods it is below rounding.
    let y = traj.strobe[300].y;
    let (c, s) = (p.phi0.cos(), p.phi0.sin());
    let expect = [
        p.ex + z.0 * c - z.1 * s,
        p.ey + z.0 * s + z.1 * c,
        -eta * (z.0 * s + z.1 * c),
        eta * (z.0 * c - z.1 * s),
    ];
    let err = (0..4).map(|i| (y[i] - expect[i]).abs()).fold(0.0, f64::max);
    println!("steady orbit vs harmonic solution: {err:.2e}");
    assert!(err <= 1e-10, "{err:e}");
    assert!(traj.events.is_empty());
}

#[test]
fn cross_coupling_and_cubic_bearing_change_the_orbit() {
    let p = Preset::Fig8a.params().with_eta(2.0);
    let plain = run(&rotor::on_ring(p, 0.0, 0.0).unwrap(), p.forcing_period());
    let coupled = run(&rotor::on_ring(p, 0.05, 0.5).unwrap(), p.forcing_period());
    let d = (plain.strobe[300].y - coupled.strobe[300].y).amax();
    assert!(d > 1e-3, "{d:e}");
    assert!(coupled
        .strobe
        .iter()
        .all(|s| s.y.iter().all(|v| v.is_finite())));
}
