//! Parameter sets, options and results serialize and read back unchanged (feature `serde`).
#![cfg(feature = "serde")]

use std::fmt::Debug;

use jeffcott::analysis::{
    BifurcationOptions, LocatorOptions, PeriodTest, Periodicity, SweepMode, SweepOptions,
};
use jeffcott::global::{find_attractor, AttractorOptions};
use jeffcott::hybrid::{DenseSampling, OutputPlan, SimOptions, StrobeRange};
use jeffcott::nalgebra::U6;
use jeffcott::ode::{EventOptions, Method, Options, Tolerance};
use jeffcott::paper::{ParamSweep, RotorStart, SweepParameter};
use jeffcott::params::{Params, Preset, Scales};
use jeffcott::stability::{
    continue_orbit, locate_loss, periodic_orbit, ContinuationOptions, LossOptions, LyapunovOptions,
    NewtonOptions, OrbitOptions, RubMap, RubMapOptions, RubPoint, SpecialKind, StroboscopicMap,
};
use jeffcott::JeffcottModel;
use serde::{de::DeserializeOwned, Serialize};

#[test]
fn params_round_trip_through_json() {
    for preset in Preset::ALL {
        let p = preset.params();
        let text = serde_json::to_string(&p).unwrap();
        let back: Params = serde_json::from_str(&text).unwrap();
        assert_eq!(p, back, "{preset}: {text}");
    }
    let scales = Scales {
        rotor_mass: 12.0,
        rotor_stiffness: 3.0e5,
        gap: 2.0e-4,
        unbalance_radius: 0.05,
    };
    let d = Preset::Fig8b.params().to_dimensional(&scales).unwrap();
    let text = serde_json::to_string(&d).unwrap();
    assert_eq!(
        serde_json::from_str::<jeffcott::params::DimensionalParams>(&text).unwrap(),
        d
    );
}

// Options and results of short runs of the paper's model, read back bit for bit.

/// `x` written to JSON and read back: equal, and written again to the same text (so every f64
/// came back with its bits: `float_roundtrip` reads the shortest representation exactly, and
/// the text tells -0.0 from 0.0).
fn round_trip<T: Serialize + DeserializeOwned + PartialEq + Debug>(x: &T) -> T {
    let text = serde_json::to_string(x).unwrap();
    let back: T = serde_json::from_str(&text).unwrap();
    assert_eq!(&back, x, "{text}");
    assert_eq!(serde_json::to_string(&back).unwrap(), text);
    back
}

/// The bits of every number of a JSON value, in order.
fn bits(v: &serde_json::Value, out: &mut Vec<u64>) {
    match v {
        serde_json::Value::Number(n) => out.push(n.as_f64().unwrap().to_bits()),
        serde_json::Value::Array(a) => a.iter().for_each(|x| bits(x, out)),
        serde_json::Value::Object(o) => o.values().for_each(|x| bits(x, out)),
        _ => {}
    }
}

/// Options a user would save, with values other than the defaults.
#[test]
fn options_round_trip_through_json() {
    let sim = SimOptions::default()
        .with_method(Method::Dopri5)
        .with_rtol(3.3e-9)
        .with_atol(1.0 / 3.0)
        .with_steps_per_period(123)
        .with_event_samples(9);
    round_trip(&sim);
    let period_test = PeriodTest::default().with_max_period(7).with_tol(2.0e-7);
    round_trip(&period_test);
    let mut sweep = SweepOptions::default();
    sweep.mode = SweepMode::CarryOver { chunks: 3 };
    sweep.threads = Some(2);
    round_trip(
        &BifurcationOptions::default()
            .with_transient(17)
            .with_record(19)
            .with_sweep(sweep)
            .with_opts(sim)
            .with_period_test(period_test),
    );
    round_trip(&LocatorOptions::default().with_resolution(0.1 + 0.2));
    // JSON has no infinity (serde_json writes null and refuses to read it back): a finite
    // h_max here; formats with non-finite numbers take the default +inf as well.
    let ode = Options::<U6>::default()
        .with_rtol(Tolerance::PerComponent(jeffcott::State::from_fn(|i, _| {
            1e-9 * (i + 1) as f64
        })))
        .with_atol(Tolerance::Scalar(1e-13))
        .with_h_max(0.7)
        .with_beta(Some(0.04));
    round_trip(&ode);
    round_trip(
        &EventOptions::default()
            .with_samples_per_step(7)
            .with_root_tol(1e-14)
            .with_max_iter(33),
    );
    let newton = NewtonOptions::default()
        .with_atol(3e-12)
        .with_rtol(1e-13)
        .with_max_iterations(9)
        .with_max_halvings(4);
    let orbit = OrbitOptions::default().with_newton(newton).with_sim(sim);
    round_trip(&orbit);
    round_trip(
        &LossOptions::default()
            .with_step(0.003)
            .with_through_grazing(true)
            .with_orbit(orbit),
    );
    round_trip(
        &LyapunovOptions::default()
            .with_separation(None)
            .with_exponents(2)
            .with_keep(5)
            .with_sim(sim),
    );
    round_trip(
        &AttractorOptions::default()
            .with_transient(301)
            .with_period_test(period_test)
            .with_free_label(2),
    );
    round_trip(
        &ContinuationOptions::default()
            .with_ds(0.011)
            .with_rtol(1e-12)
            .with_param_scale(2.5),
    );
    round_trip(
        &ParamSweep::new(Preset::Fig8b.params(), SweepParameter::Nu2).with_start(RotorStart {
            position: [0.1, -0.2],
            velocity: [0.0, 0.3],
        }),
    );
}

/// Fig. 8a at eta = 2 (a period-1 orbit with one contact per period), from rest.
fn fig8a(eta: f64) -> JeffcottModel {
    JeffcottModel::new(Preset::Fig8a.params().with_eta(eta)).unwrap()
}

#[test]
fn a_trajectory_of_a_few_periods_round_trips_bit_for_bit() {
    let model = fig8a(2.0);
    let period = model.params().forcing_period();
    let plan = OutputPlan {
        t_end: 4.0 * period,
        strobe: Some(StrobeRange { first: 0, last: 4 }),
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: period / 16.0,
        }),
        events: true,
    };
    round_trip(&plan);
    let y0 = model.state_at([0.0, 0.0], [0.0, 0.0]).unwrap();
    let (traj, stats) = model.run(0.0, &y0, &plan, &SimOptions::default()).unwrap();
    assert_eq!(traj.strobe.len(), 5);
    assert_eq!(traj.samples.len(), 65);
    assert!(
        !traj.events.is_empty(),
        "contacts in four periods from rest"
    );
    round_trip(&stats);
    let back = round_trip(&traj);
    // Bit for bit, field by field (not through f64 equality, which takes -0.0 for 0.0).
    let f = |t: &jeffcott::hybrid::Trajectory<U6>| {
        let mut v = Vec::new();
        for p in &t.strobe {
            v.push(p.t.to_bits());
            v.extend(p.y.iter().map(|x| x.to_bits()));
        }
        for s in &t.samples {
            v.push(s.t.to_bits());
            v.extend(s.y.iter().chain(s.dy.iter()).map(|x| x.to_bits()));
        }
        for e in &t.events {
            v.push(e.t.to_bits());
            v.extend(e.before.iter().chain(e.after.iter()).map(|x| x.to_bits()));
        }
        v
    };
    assert_eq!(f(&back), f(&traj));
    // The JSON holds every one of those numbers as written (no rounding on the way out).
    let mut from_text = Vec::new();
    bits(&serde_json::to_value(&traj).unwrap(), &mut from_text);
    let mut want = f(&traj);
    want.sort_unstable();
    from_text.sort_unstable();
    assert!(want.iter().all(|b| from_text.binary_search(b).is_ok()));
    // The events' labels come back as the model's (interned, one copy per label).
    for (e, b) in traj.events.iter().zip(&back.events) {
        assert_eq!(e.kind, b.kind);
    }
    let again = round_trip(&traj);
    assert!(std::ptr::eq(again.events[0].kind, back.events[0].kind));
}

/// The period-1 orbit at eta = 2: its state from 300 periods of the stroboscopic map.
fn period_one_guess(eta: f64) -> jeffcott::State {
    let model = fig8a(eta);
    StroboscopicMap::new(&model, 300, SimOptions::default())
        .unwrap()
        .advance(&model.state_at([0.0, 0.0], [0.0, 0.0]).unwrap())
        .unwrap()
        .y
}

#[test]
fn a_periodic_orbit_round_trips() {
    let model = fig8a(2.0);
    let orbit =
        periodic_orbit(&model, &period_one_guess(2.0), 1, &OrbitOptions::default()).unwrap();
    assert_eq!(orbit.margins.structure, ["contact onset", "contact loss"]);
    let back = round_trip(&orbit);
    assert_eq!(back.events.len(), 2);
    let mut a = Vec::new();
    let mut b = Vec::new();
    bits(&serde_json::to_value(&orbit).unwrap(), &mut a);
    bits(&serde_json::to_value(&back).unwrap(), &mut b);
    assert_eq!(a, b);
    assert_eq!(back.monodromy, orbit.monodromy);
    assert_eq!(back.point, orbit.point);
}

#[test]
fn a_bifurcation_of_three_values_round_trips_with_a_failed_column() {
    let sweep = ParamSweep::new(Preset::Fig8a.params(), SweepParameter::Eta);
    let config = BifurcationOptions::default()
        .with_transient(100)
        .with_record(32);
    // Three values, and a fourth the model refuses (a negative frequency ratio): its column
    // is the build error, which is saved too.
    let diagram = sweep
        .bifurcation(&[1.9, 2.0, 2.1, -1.0], &config, None)
        .unwrap();
    assert!(diagram.columns[..3].iter().all(Result::is_ok));
    assert!(diagram.columns[3].is_err());
    let back = round_trip(&diagram);
    let col = back.columns[1].as_ref().unwrap();
    assert_eq!(col.orbit.points.len(), 32);
    assert!(matches!(col.periodicity, Periodicity::Period(_)));
}

#[test]
fn an_attractor_round_trips() {
    let model = fig8a(2.0);
    let y0 = model.state_at([0.0, 0.0], [0.0, 0.0]).unwrap();
    let config = AttractorOptions::default()
        .with_transient(300)
        .with_record(32);
    let a = find_attractor(&model, &y0, &config).unwrap();
    assert_eq!(a.period(), Some(1));
    round_trip(&a);
}

/// Across the flip of the period-1 orbit near eta = 2.2348 (docs/global.md): the stability
/// continuation's points and loss, and the arclength continuation's points and special point.
#[test]
fn continuation_points_round_trip() {
    let guess = period_one_guess(2.2);
    let build = |eta: f64| JeffcottModel::new(Preset::Fig8a.params().with_eta(eta));
    let c = locate_loss(build, 2.2, 2.25, &guess, 1, &LossOptions::default()).unwrap();
    assert!(c.path.len() >= 2);
    let loss = c.loss.as_ref().expect("the flip");
    assert_eq!(loss.kind, SpecialKind::Flip);
    let back = round_trip(&c);
    assert_eq!(back.path, c.path);
    let branch =
        continue_orbit(build, 2.2, 2.25, &guess, 1, &ContinuationOptions::default()).unwrap();
    assert!(!branch.specials.is_empty());
    let back = round_trip(&branch);
    assert_eq!(back.points[0].structure, ["contact onset", "contact loss"]);
    // A rub map holds the branch and one measure per point.
    let map = RubMap {
        points: (branch.points.iter())
            .map(|p| RubPoint {
                parameter: p.parameter,
                amplitude: 1.0 + p.parameter / 3.0,
                contact_fraction: 0.1,
                peak_force: 0.7,
                stable: p.stable,
                contacts: p.contacts,
                grazing: p.grazing,
            })
            .collect(),
        branch,
        failures: vec![],
    };
    assert_eq!(round_trip(&map), map);
    round_trip(&RubMapOptions::default());
}

/// Values a run cannot produce but a file may hold: a count above its array is refused.
#[test]
fn lag_residuals_with_too_many_windows_are_refused() {
    use jeffcott::analysis::LagResiduals;
    let r = LagResiduals::from_parts(2, &[1e-3, 1e-4], 40.0).unwrap();
    let text = serde_json::to_string(&r).unwrap();
    assert!(text.contains("\"windows\":2"), "{text}");
    let bad = text.replace("\"windows\":2", "\"windows\":5");
    assert!(serde_json::from_str::<LagResiduals>(&bad).is_err());
    round_trip(&r);
}
