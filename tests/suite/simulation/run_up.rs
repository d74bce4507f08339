//! Run-up at a prescribed speed ([`ProfiledJeffcott`], [`SpeedProfile`]), checked against
//! truths independent of the crate's integrators:
//!
//! * the linear rotor without contact through its resonance at constant acceleration against
//!   the Duhamel integral of the same forcing, evaluated by composite 5-point Gauss-Legendre
//!   quadrature written here (its own convergence shown by halving the panels);
//! * the stroboscopic outputs at the phases $\varphi_0 + 2\pi k/S$ (the phase's closed form);
//! * the onset of a touch $10^{-9}$ of the gap deep in integrated free flight, on an undamped
//!   circular orbit whose largest radius is known exactly.

use jeffcott::hybrid::{simulate, OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::{SVector, U6};
use jeffcott::params::{Params, Preset};
use jeffcott::rotor::{ProfiledJeffcott, SpeedProfile};

use crate::duhamel::{duhamel, ramp_force};

fn strobes(model: &impl jeffcott::hybrid::RotorModel<Dim = U6>, t_end: f64) -> Trajectory<U6> {
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-13);
    let plan = OutputPlan::every_strobe(t_end);
    let mut traj = Trajectory::default();
    simulate(model, 0.0, &SVector::zeros(), &plan, &opts, &mut traj).expect("run");
    traj
}

#[test]
fn linear_run_up_through_resonance_matches_the_duhamel_integral() {
    // Fig. 8a's rotor (nu1 = 0.125 ... use a lighter damping for a sharper peak), rest at the
    // ring's centre so that the response from rest is the Duhamel integral alone.
    let p = Params {
        nu1: 0.05,
        ex: 0.0,
        ey: 0.0,
        phi0: 0.3,
        ..Preset::Fig8a.params()
    };
    let (eta0, eta1, rate) = (0.3, 2.0, 0.02);
    let profile = SpeedProfile::ramp(eta0, eta1, rate).unwrap();
    let samples = 16;
    let rotor = ProfiledJeffcott::new(p, profile.clone())
        .unwrap()
        .with_strobes_per_revolution(samples)
        .unwrap();
    let traj = strobes(&rotor.off_ring().unwrap(), profile.ramp_time());
    assert!(traj.events.is_empty(), "the ring is out of reach");
    let radius = |i: usize| traj.strobe[i].y[0].hypot(traj.strobe[i].y[1]);
    let peak = (0..traj.strobe.len())
        .max_by(|&a, &b| radius(a).total_cmp(&radius(b)))
        .unwrap();
    let amplitude = radius(peak);
    let (mut worst, mut without_tangential) = (0.0f64, 0.0f64);
    for i in [peak - 20, peak - 5, peak, peak + 5, peak + 20] {
        let s = &traj.strobe[i];
        let fine = |c: usize, panels| {
            duhamel(
                p.nu1,
                |u| ramp_force(p.beta, p.phi0, eta0, rate, u, true)[c],
                s.t,
                panels,
            )
        };
        let panels = (s.t * 100.0).ceil() as usize;
        for c in 0..2 {
            let (q, q2) = (fine(c, panels), fine(c, 2 * panels));
            assert!(
                (q - q2).abs() < 1e-13 * amplitude,
                "quadrature: {q} vs {q2}"
            );
            worst = worst.max((s.y[c] - q2).abs());
            // The same integral without the eta' terms: the check must tell them apart.
            let radial = |u: f64| ramp_force(p.beta, p.phi0, eta0, rate, u, false)[c];
            let q0 = duhamel(p.nu1, radial, s.t, panels);
            without_tangential = without_tangential.max((s.y[c] - q0).abs());
        }
    }
    println!(
        "peak radius {amplitude:.6} at tau {:.3} (eta {:.4}), {} strobes; worst |sim - Duhamel| = {worst:.2e} ({:.2e} of the peak)",
        traj.strobe[peak].t,
        profile.eta(traj.strobe[peak].t),
        traj.strobe.len(),
        worst / amplitude
    );
    println!("without the eta' terms the Duhamel integral differs by {without_tangential:.2e}");
    assert!(worst <= 1e-9 * amplitude, "{worst:e}");
    assert!(without_tangential > 1e-4 * amplitude);
}

#[test]
fn strobes_fall_on_the_phases_of_the_revolution() {
    let p = Preset::Fig8a.params();
    for (eta0, eta1, rate) in [(0.3, 3.0, 0.05), (3.0, 0.3, -0.05), (0.0, 1.0, 0.01)] {
        let profile = SpeedProfile::ramp(eta0, eta1, rate).unwrap();
        let rotor = ProfiledJeffcott::new(p, profile.clone())
            .unwrap()
            .with_strobes_per_revolution(7)
            .unwrap();
        let traj = strobes(&rotor.on_ring().unwrap(), profile.ramp_time());
        // The phase's closed form eta0 t + R t^2 / 2 (written here), at each strobe time.
        let turns = (eta0 + eta1) / 2.0 * profile.ramp_time() / std::f64::consts::TAU;
        assert_eq!(traj.strobe.len() as f64, (7.0 * turns).floor() + 1.0);
        for s in &traj.strobe {
            let phase = eta0 * s.t + 0.5 * rate * s.t * s.t;
            let want = std::f64::consts::TAU * s.k as f64 / 7.0;
            assert!(
                (phase - want).abs() <= 1e-12 * want.max(1.0),
                "{phase} {want}"
            );
        }
    }
}

/// The rotor without damping or forcing on the circle $e + a(-\cos\tau, -\sin\tau)$, whose
/// largest radius from the ring's centre is $|e| + a$ at $\tau = \pi$.
fn touch_run(depth: f64) -> usize {
    let p = Params {
        nu1: 0.0,
        beta: 0.0,
        ex: 0.5,
        ey: 0.0,
        ..Preset::Fig8a.params()
    };
    let a = 0.5 + depth;
    let rotor = ProfiledJeffcott::new(p, SpeedProfile::constant(2.0).unwrap()).unwrap();
    let model = rotor.on_ring().unwrap();
    let y0 = SVector::<f64, 6>::from([0.5 - a, 0.0, 0.0, -a, 0.0, 0.0]);
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-13);
    let plan = OutputPlan {
        events: true,
        ..OutputPlan::strobe(std::f64::consts::TAU, 0, 1)
    };
    let mut traj = Trajectory::<U6>::default();
    simulate(&model, 0.0, &y0, &plan, &opts, &mut traj).expect("run");
    for e in &traj.events {
        assert!(
            (e.t - std::f64::consts::PI).abs() < 1e-3,
            "event at {}",
            e.t
        );
    }
    traj.events.len()
}

#[test]
fn a_touch_of_a_billionth_of_the_gap_is_found_in_integrated_free_flight() {
    assert!(touch_run(1e-9) > 0, "a touch 1e-9 deep was missed");
    assert_eq!(touch_run(-1e-9), 0, "a miss by 1e-9 was taken for a touch");
    let found: Vec<_> = (9..=13)
        .map(|e| (e, touch_run(10f64.powi(-e)) > 0))
        .collect();
    println!("touch depth 1e-N found (rtol 1e-12): {found:?}");
}
