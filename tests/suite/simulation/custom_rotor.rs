//! `examples/custom_rotor`: a rotor written by a user on the public API, on the crate's ring.
//! With `q = k3 = 0` it is the paper's model with an integrated (instead of closed-form) free
//! flight: the two must agree over 300 forcing periods with the same contacts.

use crate::rotor;

use jeffcott::hybrid::{simulate, OutputPlan, RotorModel, SimOptions, Trajectory};
use jeffcott::nalgebra::{SVector, U6};
use jeffcott::params::Preset;
use jeffcott::JeffcottModel;

/// Strobes k = 0..=300 and the event log of a run from rest.
fn run<M: RotorModel<Dim = U6>>(model: &M, period: f64) -> Trajectory<U6> {
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-14);
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

/// The paper's rotor (`q = k3 = 0`) on its steady circular orbit about `e`, radius
/// $|Z| = B/|1 - \eta^2 + 2i\nu_1\eta|$, with `e` placed so that the orbit's outermost point is
/// `depth` beyond the gap circle: a touch of that depth once per period (closed form, the same
/// scene as `tests/suite/simulation/simulation.rs`'s grazing scene for the paper's model).
fn touch_scene(depth: f64) -> (jeffcott::params::Params, SVector<f64, 6>) {
    let base = Preset::Fig8a.params().with_eta(1.5);
    let b = base.forcing_amplitude();
    let (re, im) = (1.0 - base.eta * base.eta, 2.0 * base.nu1 * base.eta);
    let norm2 = re * re + im * im;
    let p = jeffcott::params::Params {
        ex: 1.0 + depth - b / norm2.sqrt(),
        ey: 0.0,
        ..base
    };
    // Particular solution at t = 0 (phi0 = 0): u = Z, u' = i eta Z, Z = b (re - i im) / norm2.
    let (zx, zy) = (b * re / norm2, -b * im / norm2);
    let y0 = SVector::<f64, 6>::from([p.ex + zx, p.ey + zy, -p.eta * zy, p.eta * zx, 0.0, 0.0]);
    (p, y0)
}

fn onsets_over_five_periods<M: RotorModel<Dim = U6>>(
    model: &M,
    p: f64,
    y0: &SVector<f64, 6>,
    rtol: f64,
) -> usize {
    let opts = SimOptions::default().with_rtol(rtol).with_atol(rtol * 1e-2);
    let plan = OutputPlan {
        t_end: 5.0 * p,
        strobe: None,
        dense: None,
        events: true,
    };
    let mut traj = Trajectory::default();
    simulate(model, 0.0, y0, &plan, &opts, &mut traj).expect("run");
    traj.events
        .iter()
        .filter(|e| e.kind == "contact onset")
        .count()
}

/// The onset guarantee of integrated free flight (docs/hybrid.md). With the rotor's free flight
/// integrated, the detector finds every touch of the *integrated* trajectory (its guarantee is
/// relative to the dense output); whether the exact orbit touches is then decided only to the
/// trajectory's own error. The paper's model, whose free flight is in closed form, decides it at
/// any depth. Truth: the closed-form steady orbit of `touch_scene`, touching (or missing) the
/// gap circle by `depth` once per period. Measured (printed): at rtol $10^{-8}$, $10^{-10}$,
/// $10^{-12}$ every touch or miss by a tenth of rtol or more is decided right; shallower ones
/// may go either way (at rtol $10^{-6}$ a miss by $10^{-9}$ counts 5 contacts).
#[test]
fn ringed_rotor_decides_touches_down_to_a_tenth_of_rtol() {
    let onsets = |depth: f64, rtol: f64| {
        let (p, y0) = touch_scene(depth);
        let period = p.forcing_period();
        let ringed =
            onsets_over_five_periods(&rotor::on_ring(p, 0.0, 0.0).unwrap(), period, &y0, rtol);
        let paper = onsets_over_five_periods(&JeffcottModel::new(p).unwrap(), period, &y0, rtol);
        println!(
            "rtol {rtol:e}, depth {depth:+e}: RingedRotor {ringed} onsets, JeffcottModel {paper}"
        );
        (ringed, paper)
    };
    for rtol in [1e-6, 1e-8, 1e-10, 1e-12] {
        for exp in 3..=13 {
            let depth = 10f64.powi(-exp);
            let (ringed, paper) = onsets(depth, rtol);
            assert_eq!(paper, 5, "closed-form free flight finds every touch");
            if depth >= 0.1 * rtol {
                assert_eq!(ringed, 5, "rtol {rtol:e}: touch {depth:e} deep");
            }
        }
        for miss in [1e-6, 1e-9, 1e-11] {
            let (ringed, paper) = onsets(-miss, rtol);
            assert_eq!(paper, 0, "closed-form free flight: no false touch");
            if miss >= 0.1 * rtol {
                assert_eq!(ringed, 0, "rtol {rtol:e}: a miss by {miss:e}");
            }
        }
    }
}
