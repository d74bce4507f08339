//! Per-revolution outputs (`analysis::per_revolution`) on a trajectory built by hand, whose
//! revolutions, contact intervals and radii are known by construction, and on a run of the
//! paper's rotor through its critical speed on the ring (the occupancy adds up, and the time
//! in contact is the sum of the onset-to-loss intervals of the event log).

use jeffcott::analysis::{per_revolution, AnalysisError, Revolution};
use jeffcott::hybrid::{
    simulate, DenseSampling, EventRecord, OutputPlan, SimOptions, StrobePoint, Trajectory,
};
use jeffcott::nalgebra::{SVector, Vector2, U2, U6};
use jeffcott::params::Preset;
use jeffcott::ring::Kinematics;
use jeffcott::rotor::{ProfiledJeffcott, SmoothRotor, SpeedProfile};

fn strobe(k: u64, t: f64, r: f64, label: u8) -> StrobePoint<U2> {
    StrobePoint {
        k,
        t,
        y: Vector2::new(r, 0.0),
        label,
    }
}

fn event(t: f64, r: f64, from: u8, to: u8) -> EventRecord<U2> {
    EventRecord {
        t,
        kind: "made up",
        before: Vector2::new(0.0, r),
        after: Vector2::new(0.0, r),
        from,
        to,
    }
}

#[test]
fn a_built_trajectory_reads_as_built() {
    // Two strobes a revolution; revolutions [0, 2], [2, 3], [3, 4.5]: contact (regime II)
    // from 1.5 to 2.5, regime III from 2.5 to 2.75, free again; a touch at radius 1.2.
    let traj = Trajectory {
        strobe: vec![
            strobe(0, 0.0, 0.5, 1),
            strobe(1, 1.0, 0.8, 1),
            strobe(2, 2.0, 1.0, 2),
            strobe(3, 2.5, 1.05, 3),
            strobe(4, 3.0, 0.9, 1),
            strobe(5, 3.7, 0.7, 1),
            strobe(6, 4.5, 0.6, 1),
            strobe(7, 5.0, 0.6, 1),
        ],
        samples: Vec::new(),
        events: vec![
            event(1.5, 1.2, 1, 2),
            event(2.5, 1.0, 2, 3),
            event(2.75, 1.0, 3, 1),
        ],
    };
    // States are positions alone (velocity 0: each piece between knots keeps to the chord).
    let at = |y: &Vector2<f64>| Kinematics::new([y[0], y[1]], [0.0; 2]);
    let revs = per_revolution(&traj, 2, at).unwrap();
    assert_eq!(revs.len(), 3);
    let tau = std::f64::consts::TAU;
    assert_eq!(
        (revs[0].t_start, revs[0].t_end, revs[0].speed),
        (0.0, 2.0, tau / 2.0)
    );
    assert_eq!((revs[0].max_radius, revs[0].contact_time), (1.2, 0.5));
    assert_eq!(
        revs[0].occupancy,
        [0.75, 0.25, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    );
    assert_eq!((revs[1].max_radius, revs[1].contact_time), (1.05, 0.75));
    assert_eq!(
        revs[1].occupancy,
        [0.25, 0.5, 0.25, 0.0, 0.0, 0.0, 0.0, 0.0]
    );
    assert!(!revs[2].touched() && revs[2].max_radius == 0.9);
    let mut bad = traj.clone();
    bad.strobe[0].label = 9; // no mode of the ring or the friction
    assert!(matches!(
        per_revolution(&bad, 2, at),
        Err(AnalysisError::InvalidValue { name: "label", .. })
    ));
}

#[test]
fn a_run_up_on_the_ring_adds_up() {
    let profile = SpeedProfile::ramp(1.2, 2.0, 0.02).unwrap();
    let rotor = ProfiledJeffcott::new(Preset::Fig8a.params(), profile.clone())
        .unwrap()
        .with_strobes_per_revolution(8)
        .unwrap();
    let model = rotor.on_ring().unwrap();
    let plan = OutputPlan::every_strobe(profile.ramp_time());
    let mut traj = Trajectory::<U6>::default();
    let start = SVector::<f64, 6>::from([0.9, 0.0, 0.0, 0.0, 0.0, 0.0]);
    simulate(
        &model,
        0.0,
        &start,
        &plan,
        &SimOptions::default(),
        &mut traj,
    )
    .expect("run");
    let revs = per_revolution(&traj, 8, |y| model.rotor().station(y)).unwrap();
    // The contact intervals of the event log within the whole revolutions.
    let end = revs.last().unwrap().t_end;
    let mut in_contact = 0.0;
    let mut onset = None;
    for e in traj.events.iter().filter(|e| e.t < end) {
        match (e.from, e.to) {
            (1, 2..=5) => onset = Some(e.t),
            (2..=5, 1) => in_contact += e.t - onset.take().unwrap_or(revs[0].t_start),
            _ => {}
        }
    }
    in_contact += onset.map_or(0.0, |t| end - t);
    let total: f64 = revs.iter().map(|r| r.contact_time).sum();
    let touched = revs.iter().filter(|r| r.touched()).count();
    println!(
        "{} revolutions, {touched} touched; in contact {total:.6} (event log {in_contact:.6})",
        revs.len()
    );
    assert!(touched > 0);
    assert!((total - in_contact).abs() <= 1e-12 * end);
    for r in &revs {
        assert!((r.occupancy.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        assert_eq!(r.touched(), r.max_radius >= 1.0 - 1e-9, "{r:?}");
    }
}

/// Fig. 8a's rotor ramped from 0.6 to 1.6 through its resonance and its contacts with the
/// ring, 32 strobes a revolution and, if given, dense samples `dense` a revolution at the top
/// speed: the rotor, the run and its revolutions.
fn located_peaks(dense: Option<f64>) -> (ProfiledJeffcott, Trajectory<U6>, Vec<Revolution>) {
    let (from, to) = (0.6, 1.6);
    let profile = SpeedProfile::ramp(from, to, 0.01).unwrap();
    let rotor = ProfiledJeffcott::new(Preset::Fig8a.params(), profile.clone())
        .unwrap()
        .with_strobes_per_revolution(32)
        .unwrap();
    let model = rotor.clone().on_ring().unwrap();
    let mut plan = OutputPlan::every_strobe(profile.ramp_time());
    plan.dense = dense.map(|n| DenseSampling {
        t_start: 0.0,
        dt: std::f64::consts::TAU / to / n,
    });
    let mut traj = Trajectory::<U6>::default();
    let opts = SimOptions::default().with_rtol(1e-10).with_atol(1e-12);
    simulate(&model, 0.0, &SVector::zeros(), &plan, &opts, &mut traj).expect("run");
    let revs = per_revolution(&traj, 32, |y| model.rotor().station(y)).unwrap();
    (rotor, traj, revs)
}

#[test]
fn the_peak_is_located_between_the_strobes() {
    // The truth: the largest radius, relative to the ring's centre, of dense samples of the
    // same run every 1/4096 of its shortest revolution and of its strobes (the samples' own
    // error at a smooth peak at most (2 pi / 4096)^2 / 8 = 3e-7 of the radius). The peak is
    // located with the strobes and events as knots, and with dense samples 256 a revolution
    // as knots too.
    let (rotor, truth, revs) = located_peaks(Some(4096.0));
    let (_, _, strobes_only) = located_peaks(None);
    let (_, _, with_samples) = located_peaks(Some(256.0));
    let radius = |y: &SVector<f64, 6>| rotor.station(y).r.norm();
    let largest = |r: &Revolution, points: &mut dyn Iterator<Item = (f64, f64)>| {
        points
            .filter(|(t, _)| *t >= r.t_start && *t <= r.t_end)
            .fold(0.0f64, |m, (_, r)| m.max(r))
    };
    let (mut sampled, mut located, mut resolved, mut touched) = (0.0f64, 0.0f64, 0.0f64, 0);
    assert!(revs.len() > 10 && strobes_only.len() == revs.len());
    for (i, r) in revs.iter().enumerate() {
        // The samples, and the revolution's ends (the strobes: where the radius still grows
        // at a revolution's end, the last sample falls short of it).
        let fine = largest(
            r,
            &mut (truth.samples.iter().map(|p| (p.t, radius(&p.y))))
                .chain(truth.strobe.iter().map(|p| (p.t, radius(&p.y)))),
        );
        let strobes = largest(r, &mut truth.strobe.iter().map(|p| (p.t, radius(&p.y))));
        sampled = sampled.max((fine - strobes) / fine);
        located = located.max((strobes_only[i].max_radius - fine).abs() / fine);
        resolved = resolved.max((with_samples[i].max_radius - fine).abs() / fine);
        touched += usize::from(r.touched());
    }
    println!(
        "{} revolutions ({touched} touched), peak radius off the dense truth by: strobes \
         {sampled:.2e}, located on strobes and events {located:.2e}, and on samples 256 a \
         revolution {resolved:.2e}",
        revs.len()
    );
    assert!(touched > 0);
    assert!(sampled >= 1e-2, "{sampled:e}");
    assert!(located <= 0.2 * sampled, "{located:e}");
    assert!(resolved <= 1e-6, "{resolved:e}");
}
