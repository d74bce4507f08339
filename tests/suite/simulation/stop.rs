//! A run stopped by its observer (`HybridObserver::should_stop`, how a caller honours a
//! Ctrl-C): it ends with `SimErrorKind::Stopped` at the last good point, what it recorded up
//! to then is the same as the uninterrupted run's, and an observer that never stops changes
//! nothing. Both kinds of mode: the paper's model (integrated) and a finite-element rotor in
//! closed form between contacts.

use jeffcott::hybrid::{
    simulate, DenseSampling, HybridObserver, OutputPlan, RotorModel, Sample, SimErrorKind,
    SimOptions, StrobePoint, Trajectory,
};
use jeffcott::nalgebra::allocator::Allocator;
use jeffcott::nalgebra::{DefaultAllocator, Dim, OVector};
use jeffcott::paper::JeffcottModel;
use jeffcott::params::Preset;

use crate::fe::fe_eccentric::rotor_42;

/// Records into a trajectory and asks to stop once it holds `limit` samples.
struct StopAfter<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    traj: Trajectory<D>,
    limit: usize,
}

impl<D: Dim> HybridObserver<D> for StopAfter<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn on_strobe(&mut self, point: &StrobePoint<D>) {
        self.traj.on_strobe(point);
    }
    fn on_sample(&mut self, sample: &Sample<D>) {
        self.traj.on_sample(sample);
    }
    fn should_stop(&mut self) -> bool {
        self.traj.samples.len() >= self.limit
    }
}

fn stops_where_asked<M: RotorModel>(model: &M, y0: &OVector<f64, M::Dim>, dt: f64, t_end: f64)
where
    DefaultAllocator: Allocator<M::Dim>,
{
    let plan = OutputPlan {
        t_end,
        strobe: None,
        dense: Some(DenseSampling { t_start: 0.0, dt }),
        events: false,
    };
    let opts = SimOptions::default();
    let mut whole = Trajectory::default();
    let stats = simulate(model, 0.0, y0, &plan, &opts, &mut whole).unwrap();
    let mut never = StopAfter {
        traj: Trajectory::default(),
        limit: usize::MAX,
    };
    assert_eq!(
        simulate(model, 0.0, y0, &plan, &opts, &mut never).unwrap(),
        stats
    );
    assert_eq!(never.traj.samples, whole.samples);
    let mut stopped = StopAfter {
        traj: Trajectory::default(),
        limit: 40,
    };
    let e = simulate(model, 0.0, y0, &plan, &opts, &mut stopped).unwrap_err();
    assert!(matches!(e.kind, SimErrorKind::Stopped), "{e}");
    let got = &stopped.traj.samples;
    assert!(got.len() >= 40 && got.len() < whole.samples.len());
    assert_eq!(got[..], whole.samples[..got.len()]);
    // The last good point is at or after the last sample, before the next.
    let last = got.last().unwrap().t;
    assert!(
        e.t >= last && e.t < last + dt + 1e-12,
        "stopped at {} after {last}",
        e.t
    );
    assert!(e.stats.steps + e.stats.exact_evals > 0 && e.stats.steps <= stats.steps);
}

#[test]
fn the_paper_model_stops_when_its_observer_asks() {
    let model = JeffcottModel::new(Preset::Fig8b.params()).unwrap();
    let period = model.forcing_period();
    stops_where_asked(
        &model,
        &jeffcott::nalgebra::SVector::zeros(),
        period / 8.0,
        50.0 * period,
    );
}

#[test]
fn a_rotor_in_closed_form_stops_when_its_observer_asks() {
    let model = rotor_42(5e6, 50.0, [2e-7, 1e-7], 1.5e-6, [0.0; 2]);
    let mut y0 = model.rotor().rest_state();
    model.make_consistent(&mut y0).unwrap();
    stops_where_asked(&model, &y0, 1e-4, 0.02);
}
