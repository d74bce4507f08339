//! Simulations with friction at the ring (`rotor::RubbingRotor`) against the closed forms of
//! `paper::rub` (from a start on the orbit) and the frictionless composition (at zero friction).

use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::{Complex, DMatrix, DVector, Vector2};
use jeffcott::paper::rub::synchronous_rub;
use jeffcott::params::Params;
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{LinearRotor, LinearSystem, RingedRotor, RubbingRotor};

/// Runs `model` for three periods of `period` from the orbit's state at 0 (`rotor` gives the
/// rotor's position and velocity, `ring` the ring's, at a time), 64 samples a period; checks
/// that it slips forward throughout without an event, and returns the largest distance of the
/// rotor from the orbit.
fn follow<M>(
    model: &M,
    rotor: &dyn Fn(f64) -> (Vector2<f64>, Vector2<f64>),
    ring: &dyn Fn(f64) -> Vector2<f64>,
    period: f64,
) -> f64
where
    M: jeffcott::hybrid::RotorModel<Dim = jeffcott::nalgebra::Dyn>,
{
    let ((r, v), s) = (rotor(0.0), ring(0.0));
    let y0 = DVector::from_vec(vec![r.x, r.y, v.x, v.y, s.x, s.y]);
    let opts = SimOptions::default().with_rtol(1e-11).with_atol(1e-12);
    let mut traj = Trajectory::default();
    simulate(
        model,
        0.0,
        &y0,
        &plan(3.0 * period, period),
        &opts,
        &mut traj,
    )
    .unwrap();
    let first = traj.events.first().map(|e| (e.t, e.kind));
    assert!(first.is_none(), "an event on the orbit: {first:?}");
    let mut worst = 0f64;
    for smp in &traj.samples {
        assert_eq!(smp.label, 6, "slipping forward throughout");
        worst = worst.max((Vector2::new(smp.y[0], smp.y[1]) - rotor(smp.t).0).norm());
    }
    worst
}

/// Dense samples 64 a `period` up to `t_end`, with events.
fn plan(t_end: f64, period: f64) -> OutputPlan {
    OutputPlan {
        t_end,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: period / 64.0,
        }),
        events: true,
    }
}

/// Started on a synchronous full annular rub (`paper::rub`: 58 orbits at 40 speeds, radii
/// 1.002 to 1.09), the simulation stays on it for three periods, slipping forward without an event.
#[test]
fn a_start_on_the_synchronous_rub_stays_on_it() {
    let (mu, a) = (0.2, 5.0);
    let mut checked = 0;
    for i in 0..40 {
        let eta = 0.6 + 0.05 * i as f64;
        let p = Params {
            eta,
            nu1: 0.05,
            nu2: 0.002,
            kx: 30.0,
            ky: 30.0,
            beta: 0.5,
            dx: 0.0,
            dy: 0.0,
            ex: 0.0,
            ey: 0.0,
            phi0: 0.3,
        };
        for rub in synchronous_rub(&p, mu).unwrap() {
            let model = RubbingRotor::new(paper_rotor(&p), mu, a).unwrap();
            let period = std::f64::consts::TAU / eta;
            let worst = follow(&model, &|t| rub.rotor(t), &|t| rub.ring(t), period);
            assert!(
                worst <= 1e-8 * rub.radius,
                "eta {eta}: {worst:e} off the orbit"
            );
            checked += 1;
        }
    }
    assert!(checked > 0);
}

/// The paper's rotor at `p` (non-dimensional: M = I, K = I, C = 2 nu1 I, out-of-balance
/// beta eta^2 at phase phi0) in a ring of stiffness kx, ky and preloads dx, dy, its rest position at
/// the eccentricity e from the ring's centre.
fn paper_rotor(p: &Params) -> RingedRotor<LinearRotor> {
    let eye = DMatrix::<f64>::identity(2, 2);
    let f = p.beta * p.eta * p.eta;
    let phase = Complex::from_polar(f, p.phi0);
    let system = LinearSystem::new(eye.clone(), &eye * (2.0 * p.nu1), eye, p.eta)
        .unwrap()
        .with_harmonic_force(0, phase)
        .unwrap()
        .with_harmonic_force(1, phase * Complex::new(0.0, -1.0))
        .unwrap();
    let ring = SnubberRing::new(
        jeffcott::ring::RingAxis::new(p.kx, p.dx),
        jeffcott::ring::RingAxis::new(p.ky, p.dy),
        p.nu2,
        1.0,
    )
    .unwrap();
    // The station is q - offset: the ring's centre at -e from the rotor's rest.
    LinearRotor::new(system, [0, 1], [-p.ex, -p.ey])
        .unwrap()
        .ringed(ring)
        .unwrap()
}

/// The Fig. 8 rotor (anisotropic ring, eccentric) at `eta`.
fn fig8(eta: f64) -> Params {
    Params {
        eta,
        nu1: 0.125,
        nu2: 0.002,
        kx: 30.0,
        ky: 20.0,
        beta: 0.119,
        dx: 0.0,
        dy: 0.0,
        ex: 0.9,
        ey: 0.1,
        phi0: 0.0,
    }
}

/// Runs `model` from rest for `periods` forcing periods, 64 samples a period, with events.
fn run<M>(model: &M, eta: f64, periods: f64) -> Trajectory<jeffcott::nalgebra::Dyn>
where
    M: jeffcott::hybrid::RotorModel<Dim = jeffcott::nalgebra::Dyn>,
{
    let period = std::f64::consts::TAU / eta;
    let plan = plan(periods * period, period);
    let opts = SimOptions::default().with_rtol(1e-10).with_atol(1e-11);
    let mut traj = Trajectory::default();
    simulate(model, 0.0, &DVector::zeros(6), &plan, &opts, &mut traj).unwrap();
    traj
}

/// The scenes of the Coulomb check: (friction, shaft radius, the rotor), the Fig. 8 rotor
/// without preload and, anisotropic in stiffness and preload, with one.
fn coulomb_scenes() -> Vec<(f64, f64, Params)> {
    let preloaded = |eta| Params {
        dx: 0.05,
        dy: 0.02,
        ..fig8(eta)
    };
    vec![
        (0.2, 10.0, fig8(2.5)),
        (0.3, 0.05, fig8(2.5)),
        (0.5, 0.2, fig8(3.0)),
        (0.3, 0.05, preloaded(2.5)),
        (0.5, 0.2, preloaded(3.0)),
        (0.2, 10.0, preloaded(2.5)),
    ]
}

/// Along runs from rest with onsets, losses, slipping, rolling and preload crossings, every
/// sample obeys Coulomb's law as written in MODEL.md, checked here from the sample alone (the
/// rotor's and the ring's positions and velocities, the ring's force law at its position):
/// on the circle; slipping forward with `v >= 0` and `F_t = mu N`; rolling with `v = 0` and
/// `|F_t| <= mu N`; and the rotor's acceleration is the equation of motion's with the ring's
/// force `g(s) + C(s) s'`. `RubbingRotor::slip_velocity` is that `v` (NaN out of contact).
#[test]
fn every_sample_obeys_coulombs_law() {
    let mut seen = std::collections::BTreeMap::new();
    for (mu, a, p) in coulomb_scenes() {
        let eta = p.eta;
        let model = RubbingRotor::new(paper_rotor(&p), mu, a).unwrap();
        let ring = *model.friction_ring().ring();
        let traj = run(&model, eta, 60.0);
        for e in &traj.events {
            *seen.entry(e.kind).or_insert(0) += 1;
            // The slip velocity's jump at a crossing, turned against the slip: it rolls.
            if e.kind.contains("preload") && e.from == 6 && e.to == 8 {
                *seen.entry("preload crossing into rolling").or_insert(0) += 1;
            }
        }
        for smp in &traj.samples {
            let (y, dy) = (&smp.y, &smp.dy);
            let r = Vector2::new(y[0] + p.ex, y[1] + p.ey);
            let (r_dot, s) = (Vector2::new(y[2], y[3]), Vector2::new(y[4], y[5]));
            let s_dot = Vector2::new(dy[4], dy[5]);
            let in_contact = smp.label >= 6;
            let f = if in_contact {
                ring.elastic_force(&s) + ring.damping_coefficients(&s).component_mul(&s_dot)
            } else {
                Vector2::zeros()
            };
            // The equation of motion: r'' = F - 2 nu1 r' - q - f.
            let th = p.phi0 + eta * smp.t;
            let forcing = Vector2::new(th.cos(), th.sin()) * (p.beta * eta * eta);
            let accel = forcing - r_dot * (2.0 * p.nu1) - Vector2::new(y[0], y[1]) - f;
            let scale = 1.0 + f.norm() + forcing.norm();
            assert!(
                (Vector2::new(dy[2], dy[3]) - accel).norm() <= 1e-12 * scale,
                "t {}",
                smp.t
            );
            if !in_contact {
                assert!(model.slip_velocity(smp.t, y, smp.label).unwrap().is_nan());
                continue;
            }
            *seen
                .entry(["slip+", "slip-", "roll"][usize::from(smp.label - 6)])
                .or_insert(0) += 1;
            let n = r - s;
            assert!(
                (n.norm() - 1.0).abs() <= 1e-12,
                "t {}: |r - s| = {}",
                smp.t,
                n.norm()
            );
            let t = Vector2::new(-n.y, n.x);
            let g = ring.elastic_force(&s);
            let (normal, tangential) = (n.dot(&g), t.dot(&g));
            let v = (r_dot - s_dot).dot(&t) + eta * a;
            // The crate's own slip velocity (from the ring's location and its sensitivity,
            // not the field's s'): the same; 0 exactly while rolling.
            let crate_v = model.slip_velocity(smp.t, y, smp.label).unwrap();
            if smp.label == 8 {
                assert_eq!(crate_v, 0.0, "t {}", smp.t);
            } else {
                let scale = r_dot.norm() + eta * a;
                assert!(
                    (crate_v - v).abs() <= 1e-10 * scale,
                    "t {}: {crate_v} vs {v}",
                    smp.t
                );
            }
            let tol = 1e-9 * (1.0 + normal.abs());
            match smp.label {
                6 => assert!(
                    v >= -1e-9 && (tangential - mu * normal).abs() <= tol,
                    "t {}: v {v}, F_t {tangential}, N {normal}",
                    smp.t
                ),
                7 => assert!(
                    v <= 1e-9 && (tangential + mu * normal).abs() <= tol,
                    "t {}",
                    smp.t
                ),
                _ => assert!(
                    v.abs() <= 1e-9 * (1.0 + eta * a) && tangential.abs() <= mu * normal + tol,
                    "t {}: v {v}, F_t {tangential}, N {normal}",
                    smp.t
                ),
            }
        }
    }
    println!("events and samples seen: {seen:?}");
    for kind in [
        "slip+",
        "roll",
        "contact onset",
        "contact loss",
        "slip velocity zero",
        "friction cone's edge",
        "x_s beyond preload",
        "x_s within preload",
        "y_s beyond preload",
        "y_s within preload",
        "preload crossing into rolling",
    ] {
        assert!(seen.contains_key(kind), "{kind} never met: {seen:?}");
    }
}

/// Without friction the composition is the frictionless one, bit for bit, with and without
/// preloads.
#[test]
fn without_friction_it_is_the_frictionless_rotor_bit_for_bit() {
    for preload in [0.0, 0.05] {
        let p = Params {
            dx: preload,
            dy: preload,
            ..fig8(2.5)
        };
        let plain = run(&paper_rotor(&p), 2.5, 40.0);
        let model = RubbingRotor::new(paper_rotor(&p), 0.0, 1.0).unwrap();
        let rub = run(&model, 2.5, 40.0);
        assert!(plain.events.len() > 10);
        assert_eq!(plain.samples.len(), rub.samples.len());
        for (a, b) in plain.samples.iter().zip(&rub.samples) {
            assert_eq!((a.t, &a.y, &a.dy, a.label), (b.t, &b.y, &b.dy, b.label));
        }
        let times = |t: &Trajectory<_>| t.events.iter().map(|e| (e.t, e.kind)).collect::<Vec<_>>();
        assert_eq!(times(&plain), times(&rub));
        if preload > 0.0 {
            let labels: std::collections::BTreeSet<u8> =
                plain.samples.iter().map(|s| s.label).collect();
            // Regimes II to IV exist only with a preload.
            assert!(labels.iter().any(|&l| (2..=4).contains(&l)), "{labels:?}");
        }
    }
}

/// Started on a dry whip orbit (no out-of-balance, a shaft surface faster than the whirl),
/// the simulation stays on it: a backward whirl slipping forward.
#[test]
fn a_start_on_dry_whip_stays_on_it() {
    let (mu, a) = (0.3, 1.0);
    let p = Params {
        beta: 0.0,
        ..fig8(8.0)
    };
    let p = Params {
        ky: p.kx,
        ex: 0.0,
        ey: 0.0,
        ..p
    };
    let whips = jeffcott::paper::rub::dry_whip(&p, mu).unwrap();
    assert!(!whips.is_empty());
    for whip in whips {
        assert!(whip.frequency < p.eta * a);
        let model = RubbingRotor::new(paper_rotor(&p), mu, a).unwrap();
        let period = std::f64::consts::TAU / whip.frequency;
        let worst = follow(&model, &|t| whip.rotor(t), &|t| whip.ring(t), period);
        println!(
            "dry whip w {:.5} radius {:.4}: {worst:.1e} off over three whirls",
            whip.frequency, whip.radius
        );
        assert!(worst <= 1e-8 * whip.radius);
    }
}

/// The contact guards' rates (`guard_derivative`, which event location and grazing detection
/// read) against central differences of the guards along the flow, at contact samples of runs
/// without and with preloads (slipping forward on the sample's branches, rolling from the
/// sample's contact direction): loss, gap, friction and the preload crossings.
#[test]
fn contact_guard_rates_match_differences_along_the_flow() {
    use jeffcott::hybrid::RotorModel;
    use jeffcott::ring::{Branches, Slip};
    use jeffcott::rotor::RubMode;
    let (mu, a, eta) = (0.3, 0.05, 2.5);
    let mut checked = [0; 5];
    for preload in [0.0, 0.05] {
        let p = Params {
            dx: preload,
            dy: 2.0 * preload,
            ..fig8(eta)
        };
        let model = RubbingRotor::new(paper_rotor(&p), mu, a).unwrap();
        let ring = *model.friction_ring().ring();
        let traj = run(&model, eta, 20.0);
        let cache = model.new_cache();
        for smp in traj.samples.iter().filter(|s| s.label >= 6) {
            let (y, t) = (&smp.y, smp.t);
            let s = Vector2::new(y[4], y[5]);
            let n = Vector2::new(y[0] + p.ex, y[1] + p.ey) - s;
            let branches = Branches::of(&ring, &s);
            for mode in [
                RubMode::Slip {
                    sense: Slip::Forward,
                    branches,
                },
                RubMode::Roll {
                    angle: n.y.atan2(n.x),
                    shaft: eta * t,
                    branches,
                },
            ] {
                let mut dy = y.clone();
                model.rhs(mode, t, y, &mut dy, &cache);
                let h = 1e-6;
                for i in 0..model.guard_count(mode) {
                    let g = |s: f64| model.guard_value(mode, i, t + s, &(y + &dy * s), &cache);
                    let fd = (g(h) - g(-h)) / (2.0 * h);
                    let rate = model.guard_derivative(mode, i, t, y, &dy, &cache).unwrap();
                    assert!(
                        (fd - rate).abs() <= 1e-5 * (1.0 + rate.abs()),
                        "t {t}, {mode:?}, guard {i}: rate {rate} vs differences {fd}"
                    );
                    checked[i] += 1;
                }
            }
        }
    }
    println!("rates checked per guard: {checked:?}");
    assert!(checked.iter().all(|&n| n > 100), "{checked:?}");
}

/// `paper::rub::rubbing_model` without friction is the paper's model: on every preset of the
/// paper (preloads, anisotropy, eccentricity), from rest for 10 forcing periods, its events
/// are `JeffcottModel`'s (kinds and regimes, times within 1e-7) and its samples within 1e-7 of
/// the gap: two implementations of the same equations (the 2-DOF `LinearRotor` with the
/// frictionless composition, and the paper's own model with its closed-form free flight).
#[test]
fn the_paper_rotor_written_as_a_rubbing_model_is_the_papers_model() {
    use jeffcott::paper::rub::rubbing_model;
    use jeffcott::params::Preset;
    use jeffcott::JeffcottModel;
    let opts = SimOptions::default().with_rtol(1e-11).with_atol(1e-12);
    for preset in Preset::ALL {
        let p = preset.params();
        let period = std::f64::consts::TAU / p.eta;
        let plan = plan(10.0 * period, period);
        let paper = JeffcottModel::new(p).unwrap();
        let (reference, _) = paper
            .run(0.0, &jeffcott::nalgebra::SVector::zeros(), &plan, &opts)
            .unwrap();
        let model = rubbing_model(&p, 0.0, 1.0).unwrap();
        let mut run = Trajectory::default();
        simulate(&model, 0.0, &DVector::zeros(6), &plan, &opts, &mut run).unwrap();
        assert_eq!(
            run.events.len(),
            reference.events.len(),
            "{}",
            preset.name()
        );
        for (a, b) in run.events.iter().zip(&reference.events) {
            assert_eq!((a.kind, a.from, a.to), (b.kind, b.from, b.to));
            assert!(
                (a.t - b.t).abs() <= 1e-7,
                "{}: {} vs {}",
                preset.name(),
                a.t,
                b.t
            );
        }
        assert_eq!(run.samples.len(), reference.samples.len());
        let worst = run
            .samples
            .iter()
            .zip(&reference.samples)
            .map(|(a, b)| (0..6).map(|i| (a.y[i] - b.y[i]).abs()).fold(0.0, f64::max))
            .fold(0.0, f64::max);
        println!(
            "{}: {} events, samples within {worst:.1e}",
            preset.name(),
            run.events.len()
        );
        assert!(worst <= 1e-7, "{}: {worst}", preset.name());
    }
}
