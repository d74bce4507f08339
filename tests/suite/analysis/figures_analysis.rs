//! The analyses behind the figures: bifurcation sweeps (thread independence, failures, carry
//! over), period detection on known cases, the bifurcation locator, phase portraits.

use jeffcott::analysis::{
    linspace, phase_portrait, strobe_orbit, Bifurcation, BifurcationOptions, LocatorOptions,
    OrbitError, PeriodTest, Periodicity, SweepOptions,
};
use jeffcott::hybrid::SimOptions;
use jeffcott::nalgebra::U6;
use jeffcott::paper::{poincare_map, ParamSweep, RotorStart, SweepParameter};
use jeffcott::params::{ParamError, Params, Preset};
use jeffcott::JeffcottModel;

fn bits(b: &Bifurcation<U6, ParamError>) -> Vec<Vec<u64>> {
    b.columns
        .iter()
        .map(|c| match c {
            Ok(col) => col
                .orbit
                .points
                .iter()
                .flat_map(|p| p.y.iter().map(|v| v.to_bits()).chain([p.t.to_bits(), p.k]))
                .collect(),
            Err(_) => vec![u64::MAX],
        })
        .collect()
}

fn eta_sweep(base: Params) -> ParamSweep {
    ParamSweep::new(base, SweepParameter::Eta)
}

fn small_config(sweep: SweepOptions) -> BifurcationOptions {
    BifurcationOptions::default()
        .with_transient(40)
        .with_record(12)
        .with_sweep(sweep)
}

#[test]
fn sweep_is_bitwise_identical_for_1_and_2_threads() {
    let base = Preset::Fig8b.params();
    let etas = linspace(2.0, 4.5, 6).unwrap();
    for mode in [SweepOptions::reset(), SweepOptions::carry_over(2)] {
        let one = eta_sweep(base)
            .bifurcation(&etas, &small_config(mode.with_threads(1)), None)
            .unwrap();
        let two = eta_sweep(base)
            .bifurcation(&etas, &small_config(mode.with_threads(2)), None)
            .unwrap();
        assert_eq!(one.threads, 1);
        assert_eq!(two.threads, 2);
        assert_eq!(one.failures().len(), 0);
        assert_eq!(bits(&one), bits(&two), "{mode:?}");
        assert_eq!(one.chains, two.chains);
    }
}

#[test]
fn carry_over_hands_the_state_on_within_a_chunk() {
    let base = Preset::Fig8a.params();
    let etas = [2.0, 2.01, 2.02, 2.03];
    let config = small_config(SweepOptions::carry_over(2).with_threads(2));
    let b = eta_sweep(base).bifurcation(&etas, &config, None).unwrap();
    let cols: Vec<_> = b.columns.iter().map(|c| c.as_ref().unwrap()).collect();
    assert_eq!(
        cols.iter().map(|c| c.from_reset).collect::<Vec<_>>(),
        [true, false, true, false]
    );
    // Value 1 continues from value 0's last state: the same as a run from that state.
    let model = JeffcottModel::new(base.with_eta(2.01)).unwrap();
    let direct = strobe_orbit(&model, &cols[0].orbit.last, 40, 12, &config.opts).unwrap();
    assert_eq!(direct.points, cols[1].orbit.points);
    // In reset mode value 1 starts from rest instead, and differs.
    let r = eta_sweep(base)
        .bifurcation(&etas, &small_config(SweepOptions::reset()), None)
        .unwrap();
    let r1 = r.columns[1].as_ref().unwrap();
    assert!(r1.from_reset);
    assert_ne!(r1.orbit.points, cols[1].orbit.points);
}

#[test]
fn a_failure_is_recorded_and_the_sweep_completes() {
    let base = Preset::Fig8a.params();
    // eta = -1 is an invalid parameter; the others are fine.
    let etas = [2.0, -1.0, 2.5, 3.0];
    for mode in [SweepOptions::reset(), SweepOptions::carry_over(1)] {
        let b = eta_sweep(base)
            .bifurcation(&etas, &small_config(mode.with_threads(2)), None)
            .unwrap();
        assert_eq!(b.columns.len(), 4);
        let failures = b.failures();
        assert_eq!(failures.len(), 1, "{mode:?}");
        assert_eq!(failures[0].value, -1.0);
        assert!(matches!(
            failures[0].error,
            OrbitError::Build(ParamError::NotPositive { field: "eta", .. })
        ));
        for i in [0, 2, 3] {
            let col = b.columns[i].as_ref().unwrap();
            assert_eq!(col.orbit.points.len(), 12);
        }
        // After a failure the chain restarts from rest.
        assert!(b.columns[2].as_ref().unwrap().from_reset);
    }
}

#[test]
fn progress_is_reported_once_per_value() {
    use std::sync::atomic::{AtomicUsize, Ordering};
    let calls = AtomicUsize::new(0);
    let progress = |_done: usize, total: usize| {
        assert_eq!(total, 3);
        calls.fetch_add(1, Ordering::Relaxed);
    };
    let etas = [2.0, 2.5, 3.0];
    let config = small_config(SweepOptions::reset());
    eta_sweep(Preset::Fig8a.params())
        .bifurcation(&etas, &config, Some(&progress))
        .unwrap();
    assert_eq!(calls.load(Ordering::Relaxed), 3);
}

fn period_of(preset: Preset, eta: f64) -> Periodicity {
    let params = preset.params().with_eta(eta);
    let map = poincare_map(
        &params,
        RotorStart::at_rest(),
        300,
        150,
        &SimOptions::default(),
        &PeriodTest::default(),
    )
    .unwrap();
    assert_eq!(map.orbit.points.len(), 150);
    assert_eq!(map.orbit.points[0].k, 301);
    assert_eq!(map.orbit.points[149].k, 450);
    map.periodicity
}

#[test]
fn known_periods() {
    // Fig. 8a at eta = 2: period 1 after 300 periods from rest.
    assert_eq!(period_of(Preset::Fig8a, 2.0), Periodicity::Period(1));
    // Fig. 8a at eta = 3: period 2 (the branch between 2.72 and 3.80).
    assert_eq!(period_of(Preset::Fig8a, 3.0), Periodicity::Period(2));
    // Fig. 8b at eta = 3.5: period 2.
    assert_eq!(period_of(Preset::Fig8b, 3.5), Periodicity::Period(2));
    // Fig. 8a at eta = 2.181: period 3 (the window after the first bifurcation, Fig. 9a).
    assert_eq!(period_of(Preset::Fig8a, 2.181), Periodicity::Period(3));
    // Fig. 9c (eta = 2.442, D = 0): chaotic, no period up to 16.
    assert_eq!(
        period_of(Preset::Fig8a, 2.442),
        Periodicity::NotPeriodic { up_to: 16 }
    );
}

#[test]
fn locator_finds_the_first_bifurcation_of_fig8a() {
    let config = LocatorOptions::default().with_resolution(2e-3);
    let family = eta_sweep(Preset::Fig8a.params());
    let c = family.locate_period_change(2.1, 2.2, &config).unwrap();
    assert_eq!(c.bracket.at_from, Periodicity::Period(1));
    assert_eq!(c.bracket.at_to, Periodicity::Period(3));
    assert!(c.bracket.to > c.bracket.from && c.bracket.to - c.bracket.from <= 2e-3);
    // The paper reports 2.165; the model gives 2.164 (docs/reproduction.md).
    assert!((c.value() - 2.164).abs() < 3e-3, "{c:?}");
    // Same period at both ends: an error, not a guess.
    let e = family.locate_period_change(2.0, 2.05, &config).unwrap_err();
    assert!(matches!(e, OrbitError::NoChange { .. }), "{e}");
    // From above: where period 3 ends going down is the same point.
    let d = family.locate_period_change(2.18, 2.1, &config).unwrap();
    assert_eq!(d.bracket.at_from, Periodicity::Period(3));
    assert!(
        d.bracket.to < d.bracket.from && (d.value() - c.value()).abs() < 3e-3,
        "{d:?}"
    );
}

#[test]
fn ring_phase_portrait_breaks_at_velocity_jumps() {
    let params = Preset::Fig10d.params();
    let model = JeffcottModel::new(params).unwrap();
    let y0 = model.state_at([0.0; 2], [0.0; 2]).unwrap();
    let period = params.forcing_period();
    let (t0, t1) = (50.0 * period, 53.0 * period);
    let pp = phase_portrait(&model, &y0, t0, t1, period / 500.0, &SimOptions::default()).unwrap();
    let in_window = pp.events.iter().filter(|e| e.t > t0 && e.t < t1).count();
    assert!(in_window >= 3, "{in_window}");
    let pieces = pp.pieces();
    assert_eq!(pieces.len(), in_window + 1);
    assert_eq!(
        pieces.iter().map(|p| p.len()).sum::<usize>(),
        pp.samples.len()
    );
    // No event strictly inside a piece; the ring's velocity jumps between pieces somewhere.
    let mut biggest_jump = 0.0_f64;
    for w in pieces.windows(2) {
        let (a, b) = (w[0].last().unwrap(), w[1][0]);
        assert!(pp.events.iter().any(|e| e.t > a.t && e.t < b.t));
        biggest_jump = biggest_jump.max((b.dy[4] - a.dy[4]).abs());
    }
    for p in &pieces {
        let (a, b) = (p[0].t, p[p.len() - 1].t);
        assert!(!pp.events.iter().any(|e| e.t > a && e.t < b));
    }
    assert!(biggest_jump > 0.1, "{biggest_jump}");
    let broken = pp.broken_curve(|s| (s.y[4], s.dy[4]));
    assert_eq!(
        broken.iter().filter(|p| p.0.is_nan()).count(),
        pieces.len() - 1
    );
}

#[test]
fn grids_and_parameters() {
    let g = linspace(2.0, 5.0, 3001).unwrap();
    assert_eq!((g[0], g[3000], g.len()), (2.0, 5.0, 3001));
    assert!(g.windows(2).all(|w| w[1] > w[0]));
    assert_eq!(linspace(1.0, 1.0, 1).unwrap(), vec![1.0]);
    assert!(linspace(2.0, 1.0, 3).is_err());
    assert!(linspace(f64::NAN, 1.0, 3).is_err());
    assert!(linspace(0.0, 1.0, 0).is_err());
    let base = Preset::Fig8a.params();
    let p = SweepParameter::Preload.apply(&base, 0.1);
    assert_eq!((p.dx, p.dy), (0.1, 0.1));
    assert_eq!(SweepParameter::default(), SweepParameter::Eta);
    assert_eq!(SweepParameter::Eta.apply(&base, 3.0).eta, 3.0);
    // A sweep over the preload, carrying the state (the ring is re-placed at each value).
    let config = small_config(SweepOptions::carry_over(1));
    let b = ParamSweep::new(base.with_eta(3.0), SweepParameter::Preload)
        .bifurcation(&[0.0, 0.05, 0.1], &config, None)
        .unwrap();
    assert_eq!(b.failures().len(), 0);
    assert_eq!(b.points(0).len(), 36);
}
