//! The piecewise and user-law speed profiles ([`SpeedProfile::piecewise`],
//! [`SpeedProfile::from_fn`]) driving the linear rotor without contact, against the Duhamel
//! integral of the forcing written here from the profiles' closed forms (an up-then-down ramp;
//! a sinusoidal speed whose phase is integrated by the crate and known in closed form here),
//! and a slow ramp against the steady amplitude in closed form (the quasi-static limit).

use jeffcott::hybrid::{simulate, OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::{SVector, U6};
use jeffcott::params::{Params, Preset};
use jeffcott::rotor::{ProfiledJeffcott, Segment, SpeedProfile};

use crate::duhamel::gauss_legendre;

/// The largest difference between the strobes of `profile`'s run and the Duhamel integral of
/// `force` (its pieces split at `breaks`), over the strobes from `from`, and the peak radius.
fn worst_against_duhamel(
    profile: SpeedProfile,
    force: impl Fn(f64) -> [f64; 2],
    breaks: &[f64],
    from: usize,
) -> (f64, f64) {
    let p = Params {
        nu1: 0.05,
        ex: 0.0,
        ey: 0.0,
        phi0: 0.3,
        ..Preset::Fig8a.params()
    };
    let rotor = ProfiledJeffcott::new(p, profile.clone())
        .unwrap()
        .with_strobes_per_revolution(4)
        .unwrap();
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-13);
    let plan = OutputPlan::every_strobe(profile.ramp_time());
    let mut traj = Trajectory::<U6>::default();
    let model = rotor.off_ring().unwrap();
    simulate(&model, 0.0, &SVector::zeros(), &plan, &opts, &mut traj).expect("run");
    let wd = (1.0 - p.nu1 * p.nu1).sqrt();
    let mut worst = 0.0f64;
    let mut peak = 0.0f64;
    for s in traj.strobe.iter().skip(from).step_by(7) {
        peak = peak.max(s.y[0].hypot(s.y[1]));
        for c in 0..2 {
            let f = |u: f64| (-p.nu1 * (s.t - u)).exp() * (wd * (s.t - u)).sin() / wd * force(u)[c];
            // The forcing jumps at the breaks: integrate each smooth piece on its own.
            let mut ends: Vec<f64> = breaks.iter().copied().filter(|&b| b < s.t).collect();
            ends.insert(0, 0.0);
            ends.push(s.t);
            let q: f64 = ends
                .windows(2)
                .map(|w| gauss_legendre(f, w[0], w[1], ((w[1] - w[0]) * 100.0).ceil() as usize))
                .sum();
            worst = worst.max((s.y[c] - q).abs());
        }
    }
    (worst, peak)
}

/// The out-of-balance force for the speed `eta`, its rate and the phase (written from the
/// formula of `rotor::run_up`'s docs).
fn force(beta: f64, eta: f64, rate: f64, phase: f64) -> [f64; 2] {
    let (sin, cos) = (0.3 + phase).sin_cos();
    let (a, b) = (beta * eta * eta, beta * rate);
    [a * cos + b * sin, a * sin - b * cos]
}

#[test]
fn up_then_down_matches_the_duhamel_integral() {
    let beta = Preset::Fig8a.params().beta;
    let segments = [
        Segment::Ramp {
            to: 1.3,
            rate: 0.05,
        },
        Segment::Ramp {
            to: 0.8,
            rate: -0.05,
        },
    ];
    let profile = SpeedProfile::piecewise(0.5, &segments).unwrap();
    // Up for 16, down for 10: the closed forms of the speed and phase.
    let closed = |u: f64| {
        if u < 16.0 {
            force(beta, 0.5 + 0.05 * u, 0.05, 0.5 * u + 0.025 * u * u)
        } else {
            let s = u - 16.0;
            force(beta, 1.3 - 0.05 * s, -0.05, 14.4 + 1.3 * s - 0.025 * s * s)
        }
    };
    let (worst, peak) = worst_against_duhamel(profile, closed, &[16.0], 0);
    println!(
        "up then down: worst |sim - Duhamel| {worst:.2e} ({:.2e} of the peak {peak:.4})",
        worst / peak
    );
    assert!(worst <= 1e-9 * peak, "{worst:e}");
}

#[test]
fn a_user_law_matches_the_duhamel_integral() {
    let beta = Preset::Fig8a.params().beta;
    let profile = SpeedProfile::from_fn(
        60.0,
        |t| 1.0 + 0.3 * (0.1 * t).sin(),
        |t| 0.03 * (0.1 * t).cos(),
    )
    .unwrap();
    // The phase in closed form: t + 3 (1 - cos 0.1 t).
    let closed = |u: f64| {
        let eta = 1.0 + 0.3 * (0.1 * u).sin();
        force(
            beta,
            eta,
            0.03 * (0.1 * u).cos(),
            u + 3.0 * (1.0 - (0.1 * u).cos()),
        )
    };
    let (worst, peak) = worst_against_duhamel(profile, closed, &[], 0);
    println!(
        "user law: worst |sim - Duhamel| {worst:.2e} ({:.2e} of the peak {peak:.4})",
        worst / peak
    );
    assert!(worst <= 1e-9 * peak, "{worst:e}");
}

/// The worst relative difference between the radius at each strobe on a slow ramp of `rate`
/// from 0.3 to 0.7 (no contact, rest at the ring's centre, started on the steady orbit at 0.3:
/// a circular whirl) and the steady amplitude at the strobe's speed in closed form,
/// $A(\eta) = \beta\eta^2/\sqrt{(1 - \eta^2)^2 + (2\nu_1\eta)^2}$.
fn quasi_static_error(rate: f64) -> f64 {
    let p = Params {
        ex: 0.0,
        ey: 0.0,
        phi0: 0.0,
        ..Preset::Fig8a.params()
    };
    let (eta0, s) = (0.3, 16);
    let profile = SpeedProfile::ramp(eta0, 0.7, rate).unwrap();
    let rotor = ProfiledJeffcott::new(p, profile.clone())
        .unwrap()
        .with_strobes_per_revolution(s as u32)
        .unwrap();
    let amplitude = |eta: f64| {
        p.beta * eta * eta / ((1.0 - eta * eta).powi(2) + (2.0 * p.nu1 * eta).powi(2)).sqrt()
    };
    // The steady orbit at eta0: z = H e^{i phi}, H = beta eta^2 / (1 - eta^2 + 2 i nu eta).
    let (re, im) = (1.0 - eta0 * eta0, 2.0 * p.nu1 * eta0);
    let scale = p.beta * eta0 * eta0 / (re * re + im * im);
    let (hx, hy) = (scale * re, -scale * im);
    let start = SVector::<f64, 6>::from([hx, hy, -eta0 * hy, eta0 * hx, 0.0, 0.0]);
    let opts = SimOptions::default().with_rtol(1e-10).with_atol(1e-12);
    let plan = OutputPlan::every_strobe(profile.ramp_time());
    let mut traj = Trajectory::<U6>::default();
    let model = rotor.off_ring().unwrap();
    simulate(&model, 0.0, &start, &plan, &opts, &mut traj).expect("run");
    traj.strobe
        .iter()
        .map(|q| {
            let a = amplitude(profile.eta(q.t));
            (q.y[0].hypot(q.y[1]) - a).abs() / a
        })
        .fold(0.0, f64::max)
}

#[test]
fn a_slow_ramp_follows_the_steady_amplitude() {
    let errors: Vec<f64> = [4e-4, 2e-4, 1e-4]
        .into_iter()
        .map(quasi_static_error)
        .collect();
    println!("quasi-static: worst relative error at R = 4e-4, 2e-4, 1e-4: {errors:?}");
    // First order in the rate: halving it halves the error.
    for w in errors.windows(2) {
        assert!((w[0] / w[1] - 2.0).abs() < 0.2, "{errors:?}");
    }
    // Extrapolated to R -> 0 (Richardson, first order) the steady amplitude is met.
    let limit = (2.0 * errors[2] - errors[1]).abs();
    println!("extrapolated to R -> 0: {limit:.2e}");
    assert!(limit < 1e-4, "{limit:e}");
}
