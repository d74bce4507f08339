//! The hybrid simulation of the paper's model: convergence, determinism, events, grazing,
//! starts in contact, and failures that keep what was computed.

use jeffcott::hybrid::{
    DenseSampling, OutputPlan, SimErrorKind, SimOptions, StrobePoint, StrobeRange,
};
use jeffcott::ode::{Dop853, Integrator, Options};
use jeffcott::paper::{guard, JeffcottModel, State};
use jeffcott::params::{Params, Preset};
use nalgebra::{SVector, Vector2, U6};

fn opts(rtol: f64) -> SimOptions {
    SimOptions::default().with_rtol(rtol).with_atol(rtol * 1e-2)
}

fn end_state(model: &JeffcottModel, periods: u64, o: &SimOptions) -> State {
    let (traj, _) = model
        .strobe_range(&State::zeros(), periods, periods, o)
        .unwrap();
    traj.strobe[0].y
}

#[test]
fn error_falls_as_the_tolerance_tightens() {
    // Period-2 scene with preload (regime changes inside contact), 12 periods from rest.
    let model = JeffcottModel::new(Preset::Fig8b.params().with_eta(3.0)).unwrap();
    let reference = end_state(&model, 12, &opts(1e-13));
    let errs: Vec<f64> = [1e-5, 1e-7, 1e-9, 1e-11]
        .iter()
        .map(|&tol| (end_state(&model, 12, &opts(tol)) - reference).norm())
        .collect();
    println!("errors: {errs:?}");
    for w in errs.windows(2) {
        assert!(w[1] < w[0] * 0.5, "{errs:?}");
    }
    assert!(errs[3] < 1e-8, "{errs:?}");
}

#[test]
fn reruns_are_bitwise_identical() {
    let model = JeffcottModel::new(Preset::Fig9d.params()).unwrap();
    let plan = OutputPlan {
        t_end: 40.0 * model.params().forcing_period(),
        strobe: Some(StrobeRange { first: 0, last: 40 }),
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: 0.05,
        }),
        events: true,
    };
    let a = model.run(0.0, &State::zeros(), &plan, &opts(1e-9)).unwrap();
    let b = model.run(0.0, &State::zeros(), &plan, &opts(1e-9)).unwrap();
    assert_eq!(a, b);
    assert!(a.0.events.len() > 10);
}

#[test]
fn exact_free_flight_agrees_with_dop853() {
    // An orbit far from the ring: the whole run is exact free flight.
    let p = Params {
        beta: 0.01,
        ex: 0.1,
        ..Preset::Fig8a.params().with_eta(1.3)
    };
    let model = JeffcottModel::new(p).unwrap();
    let y0 = model.state_at([0.2, -0.1], [0.3, 0.1]).unwrap();
    let (traj, stats) = model.strobe_range(&y0, 0, 8, &opts(1e-10)).unwrap();
    assert_eq!(stats.steps, 0, "no integrated phase expected");
    let sys = |t: f64, y: &SVector<f64, 4>, dy: &mut SVector<f64, 4>| {
        let th = p.phi0 + p.eta * t;
        let b = p.forcing_amplitude();
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = b * th.cos() - 2.0 * p.nu1 * y[2] - (y[0] - p.ex);
        dy[3] = b * th.sin() - 2.0 * p.nu1 * y[3] - (y[1] - p.ey);
    };
    let mut integ = Dop853::new(Options::with_tol(1e-13, 1e-15)).unwrap();
    let mut y = SVector::<f64, 4>::new(0.2, -0.1, 0.3, 0.1);
    integ.reset(&sys, 0.0, &y, false).unwrap();
    for StrobePoint {
        t, y: ye, label, ..
    } in &traj.strobe[1..]
    {
        while integ.t() < *t {
            integ.step(&sys, *t).unwrap();
        }
        y.copy_from(integ.y());
        for i in 0..4 {
            assert!(
                (ye[i] - y[i]).abs() < 1e-11,
                "t = {t}: {} vs {}",
                ye[i],
                y[i]
            );
        }
        assert_eq!(*label, 1);
    }
}

/// A rotor started on its steady circular orbit, whose outermost point is at radius
/// `1 + depth` from the ring's centre.
fn grazing_scene(depth: f64) -> (JeffcottModel, State) {
    let base = Preset::Fig8a.params().with_eta(1.5);
    let b = base.forcing_amplitude();
    let den = Vector2::new(1.0 - base.eta * base.eta, 2.0 * base.nu1 * base.eta);
    let z = b / den.norm();
    let p = Params {
        ex: 1.0 + depth - z,
        ey: 0.0,
        ..base
    };
    let model = JeffcottModel::new(p).unwrap();
    // Particular solution at t = 0: r = e + Z, v = i eta Z, Z = b / (den_re + i den_im).
    let zc = Vector2::new(b * den.x, -b * den.y) / den.norm_squared();
    let y0 = model
        .state_at([p.ex + zc.x, p.ey + zc.y], [-p.eta * zc.y, p.eta * zc.x])
        .unwrap();
    (model, y0)
}

#[test]
fn a_contact_one_micron_of_the_gap_deep_is_found() {
    for (depth, expect_contact) in [(1e-6, true), (-1e-6, false), (1e-9, true)] {
        let (model, y0) = grazing_scene(depth);
        let plan = OutputPlan {
            t_end: 5.0 * model.params().forcing_period(),
            strobe: None,
            dense: None,
            events: true,
        };
        let (traj, _) = model.run(0.0, &y0, &plan, &opts(1e-10)).unwrap();
        let onsets = traj
            .events
            .iter()
            .filter(|e| e.kind == guard::ONSET)
            .count();
        if expect_contact {
            assert!(onsets >= 4, "depth {depth}: {onsets} onsets");
            for e in traj.events.iter().filter(|e| e.kind == guard::ONSET) {
                let r = Vector2::new(e.before[0], e.before[1]);
                let s = Vector2::new(e.before[4], e.before[5]);
                assert!(((r - s).norm() - 1.0).abs() < 1e-13);
            }
        } else {
            assert_eq!(onsets, 0, "depth {depth}");
        }
    }
}

#[test]
fn events_alternate_and_sit_on_their_surfaces() {
    // Fig. 10b: preload 0.05 on both axes, crossed on both.
    let model = JeffcottModel::new(Preset::Fig10b.params()).unwrap();
    let plan = OutputPlan {
        t_end: 30.0 * model.params().forcing_period(),
        strobe: None,
        dense: None,
        events: true,
    };
    let (traj, _) = model
        .run(0.0, &State::zeros(), &plan, &opts(1e-10))
        .unwrap();
    let mut in_contact = false;
    let mut regime_changes = 0;
    for e in &traj.events {
        match e.kind {
            guard::ONSET => {
                assert!(!in_contact);
                in_contact = true;
                assert_eq!(e.from, 1);
                assert!(e.to >= 2);
            }
            guard::LOSS | guard::GAP => {
                assert!(in_contact);
                in_contact = false;
                assert_eq!(e.to, 1);
            }
            _ => {
                assert!(in_contact);
                regime_changes += 1;
                // On a preload boundary: |x_s| = 0.05 or |y_s| = 0.05.
                let (sx, sy) = (e.before[4].abs(), e.before[5].abs());
                let off = (sx - 0.05).abs().min((sy - 0.05).abs());
                assert!(off < 1e-12, "{e:?}");
            }
        }
    }
    assert!(regime_changes > 0, "this scene crosses the preload");
}

#[test]
fn zero_preload_has_only_regimes_one_and_five() {
    let model = JeffcottModel::new(Preset::Fig9c.params()).unwrap();
    let plan = OutputPlan {
        t_end: 20.0 * model.params().forcing_period(),
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: 0.01,
        }),
        events: true,
    };
    let (traj, _) = model.run(0.0, &State::zeros(), &plan, &opts(1e-9)).unwrap();
    assert!(traj.samples.iter().all(|s| s.label == 1 || s.label == 5));
    assert!(traj
        .events
        .iter()
        .all(|e| e.kind == guard::ONSET || e.kind == guard::LOSS || e.kind == guard::GAP));
    assert!(traj.samples.iter().any(|s| s.label == 5));
}

#[test]
fn a_run_can_start_in_contact() {
    let model = JeffcottModel::new(Preset::Fig8b.params()).unwrap();
    let y0 = model.state_at([1.08, 0.3], [0.0, 0.5]).unwrap();
    assert!(((Vector2::new(y0[0] - y0[4], y0[1] - y0[5])).norm() - 1.0).abs() < 1e-14);
    let plan = OutputPlan {
        t_end: 3.0,
        strobe: None,
        dense: None,
        events: true,
    };
    let (traj, _) = model.run(0.0, &y0, &plan, &opts(1e-10)).unwrap();
    assert!(
        traj.events[0].from >= 2,
        "starts in contact: {:?}",
        traj.events[0]
    );
}

#[test]
fn a_rotor_beyond_the_ring_is_a_typed_error() {
    let model = JeffcottModel::new(Preset::Fig8a.params()).unwrap();
    let y0 = State::from([1.5, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let err = model.strobe_range(&y0, 0, 3, &opts(1e-9)).unwrap_err();
    assert!(matches!(err.error.kind, SimErrorKind::Model(_)), "{err}");
    assert_eq!(err.error.y, y0);
    let bad = State::from([f64::NAN, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let err = model.strobe_range(&bad, 0, 3, &opts(1e-9)).unwrap_err();
    assert!(matches!(err.error.kind, SimErrorKind::NonFinite));
}

#[test]
fn chattering_bound_ends_the_run_with_what_was_computed() {
    // About 3 transitions per period: a bound of 2 must stop the run.
    let model = JeffcottModel::new(Preset::Fig10b.params()).unwrap();
    let o = opts(1e-9).with_max_events_per_period(2);
    let err = model.strobe_range(&State::zeros(), 0, 50, &o).unwrap_err();
    assert!(
        matches!(err.error.kind, SimErrorKind::Chattering { .. }),
        "{err}"
    );
    assert!(!err.partial.strobe.is_empty());
    assert!(err.error.t > 0.0 && err.error.y.iter().all(|v| v.is_finite()));
}

#[test]
fn invalid_options_are_typed_errors() {
    let model = JeffcottModel::new(Preset::Fig8a.params()).unwrap();
    for o in [
        SimOptions::default().with_rtol(f64::NAN),
        SimOptions::default().with_rtol(0.0).with_atol(0.0),
        SimOptions::default().with_max_step_fraction(-1.0),
    ] {
        let err = model.strobe_range(&State::zeros(), 0, 3, &o).unwrap_err();
        assert!(
            matches!(err.error.kind, SimErrorKind::InvalidOption { .. }),
            "{err}"
        );
    }
}

#[test]
fn event_samples_out_of_range_is_a_typed_error_not_a_clamp() {
    let model = JeffcottModel::new(Preset::Fig8a.params()).unwrap();
    for n in [0, jeffcott::ode::MAX_SAMPLES + 1] {
        let o = SimOptions::default().with_event_samples(n);
        let err = model.strobe_range(&State::zeros(), 0, 3, &o).unwrap_err();
        assert!(
            matches!(
                err.error.kind,
                SimErrorKind::InvalidOption { field: "event_samples", value, .. } if value == n as f64
            ),
            "{err}"
        );
        assert!(err.partial.strobe.is_empty());
    }
    // The ends of the range run.
    for n in [1, jeffcott::ode::MAX_SAMPLES] {
        let o = SimOptions::default().with_event_samples(n);
        assert!(model.strobe_range(&State::zeros(), 0, 3, &o).is_ok(), "{n}");
    }
}

#[test]
fn reversed_output_ranges_are_typed_errors() {
    let model = JeffcottModel::new(Preset::Fig8a.params()).unwrap();
    let err = model
        .strobe_range(&State::zeros(), 5, 4, &SimOptions::default())
        .unwrap_err();
    assert!(
        matches!(
            err.error.kind,
            SimErrorKind::InvalidOption { field: "strobe.first", value, .. } if value == 5.0
        ),
        "{err}"
    );
    // A single point (first == last) is fine.
    let (t, _) = model
        .strobe_range(&State::zeros(), 4, 4, &SimOptions::default())
        .unwrap();
    assert_eq!(t.strobe.len(), 1);
    let bad_dense = OutputPlan {
        t_end: 1.0,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: f64::NAN,
            dt: 0.1,
        }),
        events: false,
    };
    let err = model
        .run(0.0, &State::zeros(), &bad_dense, &SimOptions::default())
        .unwrap_err();
    assert!(matches!(
        err.error.kind,
        SimErrorKind::InvalidOption {
            field: "dense.t_start",
            ..
        }
    ));
}

#[test]
fn both_preloads_crossed_at_once_at_the_corner() {
    // No forcing, rest position on the diagonal: a rotor launched along the diagonal stays on
    // it bit for bit, so it crosses both preloads at the same instant, out and back.
    let p = Params {
        beta: 0.0,
        ex: 0.3,
        ey: 0.3,
        nu2: 0.002,
        ..Preset::Fig8b.params()
    };
    let model = JeffcottModel::new(p).unwrap();
    let y0 = model.state_at([0.75, 0.75], [3.0, 3.0]).unwrap();
    let plan = OutputPlan {
        t_end: 2.0,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: 1e-3,
        }),
        events: true,
    };
    let (traj, _) = model.run(0.0, &y0, &plan, &opts(1e-10)).unwrap();
    let labels: Vec<u8> = traj.events.iter().map(|e| e.to).collect();
    println!(
        "{:?}",
        traj.events
            .iter()
            .map(|e| (e.t, e.kind, e.from, e.to))
            .collect::<Vec<_>>()
    );
    assert!(labels.contains(&5), "regime V reached: {labels:?}");
    // Never regime III or IV: the motion is symmetric.
    assert!(traj.samples.iter().all(|s| s.label != 3 && s.label != 4));
    // The ring never goes beyond its preload on one branch only.
    for s in &traj.samples {
        let (sx, sy) = (s.y[4], s.y[5]);
        assert_eq!(sx, sy);
        let beyond = sx.abs() > 0.1 + 1e-9;
        if beyond {
            assert_eq!(s.label, 5, "{s:?}");
        }
    }
}

#[test]
fn zero_ring_damping_runs_and_stays_close_to_tiny_damping() {
    let end = |nu2: f64| {
        let p = Params {
            nu2,
            ..Preset::Fig8b.params().with_eta(3.0)
        };
        let model = JeffcottModel::new(p).unwrap();
        let (traj, stats) = model
            .strobe_range(&State::zeros(), 0, 40, &opts(1e-10))
            .unwrap();
        assert!(stats.transitions > 10);
        assert!(traj
            .strobe
            .iter()
            .all(|s| s.y.iter().all(|v| v.is_finite())));
        traj.strobe.last().unwrap().y
    };
    let zero = end(0.0);
    let tiny = end(1e-9);
    // The ring damping enters the force linearly: 1e-9 of it moves the state very little.
    assert!((zero - tiny).norm() < 1e-5, "{}", (zero - tiny).norm());
}

#[test]
fn onsets_late_in_long_runs_resolve_at_the_time_resolution() {
    // Found by the figure examples: late in a long run one ulp of time is far above 1e-12
    // (4.7e-10 at t = 3e6), so an onset can only be placed some way inside the gap circle;
    // it must start contact, not loop. The steady orbit of `grazing_scene` is started at a
    // late time and enters the ring 1e-3 deep.
    let (model, _) = grazing_scene(1e-3);
    let p = *model.params();
    for t0 in [1e5, 3e6] {
        let b = p.forcing_amplitude();
        let den = Vector2::new(1.0 - p.eta * p.eta, 2.0 * p.nu1 * p.eta);
        let zc = Vector2::new(b * den.x, -b * den.y) / den.norm_squared();
        let (s, c) = (p.phi0 + p.eta * t0).sin_cos();
        let z = Vector2::new(zc.x * c - zc.y * s, zc.x * s + zc.y * c);
        let y0 = model
            .state_at([p.ex + z.x, p.ey + z.y], [-p.eta * z.y, p.eta * z.x])
            .unwrap();
        let plan = OutputPlan {
            t_end: t0 + 20.0 * p.forcing_period(),
            strobe: None,
            dense: None,
            events: true,
        };
        let (traj, _) = model
            .run(t0, &y0, &plan, &opts(1e-10))
            .unwrap_or_else(|f| panic!("t0 = {t0}: {}", f.error));
        let onsets = traj
            .events
            .iter()
            .filter(|e| e.kind == guard::ONSET)
            .count();
        assert!(onsets >= 18, "t0 = {t0}: {onsets} onsets");
    }
}

#[test]
fn the_first_output_is_the_initial_state_exactly() {
    let model = JeffcottModel::new(Preset::Fig8a.params()).unwrap();
    let y0 = model.state_at([0.1, -0.2], [0.3, 0.05]).unwrap();
    let (traj, _) = model.strobe_range(&y0, 0, 2, &opts(1e-9)).unwrap();
    assert_eq!(traj.strobe[0].y, y0);
    let (traj, _) = model
        .strobe_range(&State::zeros(), 0, 0, &opts(1e-9))
        .unwrap();
    assert_eq!(traj.strobe[0].y, State::zeros());
}

/// Grazing inside contact, where guards are located on the integrator's dense output by the
/// samples: the ring's x coordinate reaching its preload by only $10^{-6}$ or
/// $10^{-9}$ of the gap in one contact gives both crossings (beyond, and back within); stopping
/// $10^{-6}$ short of it gives none. The scene is Fig. 8b at eta = 2.0 on its period-1
/// attractor, whose contacts stay inside the preload (0.1); the largest $|x_s|$ of a contact,
/// $S^*$, is measured on the dense output (a parabola through the top three samples
/// $10^{-6}$ apart), and $D_x$ is then set to $S^* \mp$ depth: the motion up to the graze is
/// the same (the preload enters only once crossed), so the graze depth is exact to the
/// parabola's error ($\sim 10^{-18}$).
#[test]
fn a_preload_graze_one_nanometre_of_the_gap_deep_is_found_in_contact() {
    let base = Preset::Fig8b.params().with_eta(2.0);
    let o = SimOptions::default();
    let (traj, _) = JeffcottModel::new(base)
        .unwrap()
        .strobe_range(&State::zeros(), 300, 300, &o)
        .unwrap();
    let (t0, y0) = (traj.strobe[0].t, traj.strobe[0].y);
    let period = base.forcing_period();
    let run = |p: Params, t_end: f64, dense: Option<DenseSampling>| {
        JeffcottModel::new(p)
            .unwrap()
            .run(
                t0,
                &y0,
                &OutputPlan {
                    t_end,
                    strobe: None,
                    dense,
                    events: true,
                },
                &o,
            )
            .unwrap()
            .0
    };
    let peak = |samples: &[jeffcott::hybrid::Sample<U6>]| {
        let (i, _) = samples
            .iter()
            .enumerate()
            .filter(|(_, s)| s.label > 1)
            .map(|(i, s)| (i, s.y[4].abs()))
            .fold((0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a });
        i
    };
    let dt = period / 4000.0;
    let coarse = run(base, t0 + period, Some(DenseSampling { t_start: t0, dt }));
    assert_eq!(coarse.events.len(), 2, "one contact, inside the preload");
    let tp = coarse.samples[peak(&coarse.samples)].t;
    let h = 1e-6;
    let fine = run(
        base,
        tp + dt,
        Some(DenseSampling {
            t_start: tp - dt,
            dt: h,
        }),
    );
    let k = peak(&fine.samples);
    let (a, b, c) = (
        fine.samples[k - 1].y[4].abs(),
        fine.samples[k].y[4].abs(),
        fine.samples[k + 1].y[4].abs(),
    );
    let s_star = b + (c - a) * (c - a) / (8.0 * (2.0 * b - a - c));
    assert!(s_star > 0.01 && s_star < base.dx, "S* = {s_star}");
    for (depth, expect) in [(1e-6, 2), (1e-9, 2), (-1e-6, 0)] {
        let p = Params {
            dx: s_star - depth,
            ..base
        };
        let t = run(p, t0 + period, None);
        let crossings: Vec<&str> = t
            .events
            .iter()
            .map(|e| e.kind)
            .filter(|k| *k == guard::X_OUT || *k == guard::X_IN)
            .collect();
        assert_eq!(crossings.len(), expect, "depth {depth}: {crossings:?}");
        if expect == 2 {
            assert_eq!(crossings, [guard::X_OUT, guard::X_IN], "depth {depth}");
        }
    }
}

/// `max_steps` bounds a run's work, however many contacts split it into phases (the fuzzer's
/// seed 777 found runs whose every phase kept under the bound while the run took hours). Before
/// the bound counted the whole run, this run of many short contact phases finished.
#[test]
fn max_steps_bounds_the_whole_run_not_one_phase() {
    let model = JeffcottModel::new(Preset::Fig8a.params()).unwrap();
    let o = opts(1e-9);
    let (_, stats) = model.strobe_range(&State::zeros(), 0, 40, &o).unwrap();
    // Each contact phase takes far fewer steps than a quarter of the run's.
    let bound = stats.steps / 4;
    let err = model
        .strobe_range(&State::zeros(), 0, 40, &o.with_max_steps(bound))
        .unwrap_err();
    match err.error.kind {
        SimErrorKind::TooManySteps {
            attempts,
            max_steps,
        } => {
            assert_eq!(max_steps, bound);
            assert_eq!(attempts, bound);
        }
        other => panic!("expected the run's step budget, got {other}"),
    }
    // What was computed before the budget ran out is kept.
    assert!(!err.partial.strobe.is_empty());
    assert!(err.error.t > 0.0);
}

/// The paper's model computes its guards' rates from the state alone (the event detector
/// evaluates no right-hand side at its samples): the loss guard's rate is bitwise the ring's
/// rate given the acceleration of the model's own `rhs`, by the one-guard method and by the
/// batched one, whatever `dy` is passed; the other guards' rates ignore it too. Checked on
/// Fig. 8b with an anisotropic ring (Newton placements) and the isotropic one (closed form),
/// on every branch pair and at random states and times.
#[test]
fn guard_rates_need_no_rhs_and_equal_the_rhs_acceleration_bitwise() {
    use jeffcott::hybrid::RotorModel;
    use jeffcott::ring::{Branch, Branches, Kinematics, RingCache, RingMode};
    let mut seed = 0x5EED_u64;
    let mut next = move || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (seed >> 11) as f64 / 2f64.powi(53)
    };
    for params in [
        Preset::Fig8b.params(),
        Params {
            ky: 12.0,
            ..Preset::Fig8b.params()
        },
    ] {
        let model = JeffcottModel::new(params).unwrap();
        assert!(!model.guard_derivative_needs_rhs());
        let ring = model.ring();
        for (bx, by) in [
            (Branch::Inner, Branch::Inner),
            (Branch::Outer(1), Branch::Outer(-1)),
            (Branch::Inner, Branch::Outer(1)),
        ] {
            let mode = RingMode::Contact(Branches { x: bx, y: by });
            for _ in 0..50 {
                let (rad, ang) = (1.0 + 0.5 * next(), std::f64::consts::TAU * next());
                let y = State::from([
                    rad * ang.cos(),
                    rad * ang.sin(),
                    4.0 * next() - 2.0,
                    4.0 * next() - 2.0,
                    0.0,
                    0.0,
                ]);
                let t = 20.0 * next();
                let mut dy = State::zeros();
                model.rhs(mode, t, &y, &mut dy, &model.new_cache());
                let k = Kinematics::new([y[0], y[1]], [y[2], y[3]]);
                let accel = Vector2::new(dy[2], dy[3]);
                let junk = State::repeat(1e3);
                let mut batched = Vec::new();
                model.guard_values(
                    mode,
                    t,
                    &y,
                    &junk,
                    true,
                    &model.new_cache(),
                    &mut |i, _, r| {
                        batched.push((i, r));
                    },
                );
                assert_eq!(batched.len(), model.guard_count(mode));
                for (i, rate) in batched {
                    let guard = ring.guard(&mode, i).unwrap();
                    let expected = ring.guard_rate_with_accel(
                        &mode,
                        guard,
                        t,
                        &k,
                        &accel,
                        &RingCache::default(),
                    );
                    let single = model.guard_derivative(mode, i, t, &y, &junk, &model.new_cache());
                    assert_eq!(
                        rate.map(f64::to_bits),
                        expected.map(f64::to_bits),
                        "{guard:?} at {y:?}"
                    );
                    assert_eq!(
                        single.map(f64::to_bits),
                        expected.map(f64::to_bits),
                        "{guard:?} at {y:?}"
                    );
                }
            }
        }
    }
}
