//! Criterion benchmarks of the hybrid simulation (fixed inputs, modest run time).
//!
//! * `period/*`: one forcing period from a state on the attractor (reached by 300 periods from
//!   rest beforehand), one scene per feature of the model, Fig. 8 values at eta = 2.0 unless
//!   said otherwise, default options (DOP853, rtol 1e-10, atol 1e-12):
//!   - `free_flight_no_contact`: beta = 0.02, the rotor never reaches the ring (exact free
//!     flight and its onset search only);
//!   - `contact_no_preload`: Fig. 8a, one contact per period (regime V, closed-form ring);
//!   - `contact_preload`: Fig. 8b (preload 0.1), one contact per period inside the preload
//!     (regime II: the preload guards are carried but never cross);
//!   - `contact_preload_crossed`: Fig. 10b (eta = 2.5, preload 0.05), the ring crosses its
//!     preload in most contacts (regimes II and III, branch switches);
//!   - `contact_anisotropic`: Fig. 8a with K_y = 15 (K_x = 30): the ring located by the
//!     safeguarded Newton iteration instead of the closed form;
//!   - `stiff_ring_k1000`: Fig. 8a with K = 1000.
//! * `unused/*`: what carrying a feature that the scene does not use costs. Fig. 8b at
//!   eta = 2.0 never crosses its preload: the same run with the two preload guards hidden from
//!   the driver (a wrapper model reporting the loss and gap guards only) gives bitwise the same
//!   trajectory (asserted), so the difference of the two is the cost of the unused guards.
//! * `contact_hot_loop`: 10 periods of permanent contact (rest position ex = 3 beyond the gap,
//!   preload 0.1), throughput in integrator steps.
//! * `sweep/*`: a reduced bifurcation sweep, 20 eta values in [2, 5] x 50 periods (Fig. 8b,
//!   each value from rest), and 20 values x 200 periods, each with 1 and 2 worker threads.
//! * `python_baseline/*`: 1000 forcing periods from rest, all 1001 stroboscopic states
//!   recorded, default options: Fig. 8b (eta = 2, one contact a period) and Fig. 9c (chaotic).
//!   The bindings' overhead against the same run (issue 22: at most 5 %) is measured by
//!   `python/benches/overhead.py`, with the Rust runs of `benches/python_overhead.rs`
//!   interleaved with the Python ones.
//!
//! Run: `cargo bench --bench simulation` (on a quiet machine; `uptime` for the load).

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use jeffcott::analysis::{sweep, SweepOptions};
use jeffcott::hybrid::{
    simulate, Flow, ModelError, OutputPlan, RotorModel, SimOptions, Trajectory,
};
use jeffcott::nalgebra::U6;
use jeffcott::numeric::Direction;
use jeffcott::paper::{Cache, FreeSegment, JeffcottModel, Mode, State};
use jeffcott::params::{Params, Preset};

/// The model and a state on its attractor at a stroboscopic time (phase 0).
fn on_attractor(p: Params) -> (JeffcottModel, State) {
    let m = JeffcottModel::new(p).expect("params");
    let (t, _) = m
        .strobe_range(&State::zeros(), 300, 300, &SimOptions::default())
        .expect("transient");
    let y = t.strobe[0].y;
    (m, y)
}

/// The paper's model with only its first `guards` guards shown to the driver (the loss and
/// gap guards in contact): for a scene whose preload is never crossed the run is the same.
struct HiddenGuards {
    inner: JeffcottModel,
    guards: usize,
}

impl RotorModel for HiddenGuards {
    type Dim = U6;
    type Mode = Mode;
    type Segment = FreeSegment;
    type Cache = Cache;

    fn dim(&self) -> U6 {
        U6
    }
    fn new_cache(&self) -> Self::Cache {
        self.inner.new_cache()
    }
    fn initial_mode(&self, t: f64, y: &State) -> Result<Mode, ModelError> {
        self.inner.initial_mode(t, y)
    }
    fn flow(&self, mode: Mode) -> Flow {
        self.inner.flow(mode)
    }
    fn rhs(&self, mode: Mode, t: f64, y: &State, dy: &mut State, cache: &Self::Cache) {
        self.inner.rhs(mode, t, y, dy, cache)
    }
    fn is_algebraic(&self, i: usize) -> bool {
        self.inner.is_algebraic(i)
    }
    fn guard_count(&self, mode: Mode) -> usize {
        self.inner.guard_count(mode).min(self.guards)
    }
    fn guard_direction(&self, mode: Mode, i: usize) -> Direction {
        self.inner.guard_direction(mode, i)
    }
    fn guard_value(&self, mode: Mode, i: usize, t: f64, y: &State, cache: &Self::Cache) -> f64 {
        self.inner.guard_value(mode, i, t, y, cache)
    }
    fn guard_derivative(
        &self,
        mode: Mode,
        i: usize,
        t: f64,
        y: &State,
        dy: &State,
        cache: &Self::Cache,
    ) -> Option<f64> {
        self.inner.guard_derivative(mode, i, t, y, dy, cache)
    }
    fn guard_derivative_needs_rhs(&self) -> bool {
        self.inner.guard_derivative_needs_rhs()
    }
    fn guard_derivative_needs_rhs_of(&self, mode: Mode, i: usize) -> bool {
        self.inner.guard_derivative_needs_rhs_of(mode, i)
    }
    fn guard_values(
        &self,
        mode: Mode,
        t: f64,
        y: &State,
        dy: &State,
        with_rates: bool,
        cache: &Self::Cache,
        out: &mut dyn FnMut(usize, f64, Option<f64>),
    ) {
        let n = self.guard_count(mode);
        self.inner
            .guard_values(mode, t, y, dy, with_rates, cache, &mut |i, g, d| {
                if i < n {
                    out(i, g, d)
                }
            });
    }
    fn guard_label(&self, mode: Mode, i: usize) -> &'static str {
        self.inner.guard_label(mode, i)
    }
    fn transition(
        &self,
        mode: Mode,
        guard: usize,
        t: f64,
        y: &mut State,
    ) -> Result<Mode, ModelError> {
        self.inner.transition(mode, guard, t, y)
    }
    fn start_segment(&self, mode: Mode, t: f64, y: &State) -> FreeSegment {
        self.inner.start_segment(mode, t, y)
    }
    fn project(&self, mode: Mode, t: f64, y: &mut State, cache: &Self::Cache) {
        self.inner.project(mode, t, y, cache)
    }
    fn mode_label(&self, mode: Mode) -> u8 {
        self.inner.mode_label(mode)
    }
    fn forcing_period(&self) -> f64 {
        self.inner.forcing_period()
    }
}

/// One forcing period of `model` from `y` at the attractor's stroboscopic time 300 P.
fn period_of<M: RotorModel<Dim = U6>>(model: &M, y: &State) -> Trajectory<U6> {
    let p = model.forcing_period();
    let plan = OutputPlan::strobe(p, 301, 301);
    let mut traj = Trajectory::default();
    simulate(
        model,
        300.0 * p,
        y,
        &plan,
        &SimOptions::default(),
        &mut traj,
    )
    .expect("run");
    traj
}

fn one_period(c: &mut Criterion) {
    let fig8 = Preset::Fig8a.params();
    let scenes = [
        ("free_flight_no_contact", Params { beta: 0.02, ..fig8 }),
        ("contact_no_preload", fig8),
        ("contact_preload", Preset::Fig8b.params()),
        ("contact_preload_crossed", Preset::Fig10b.params()),
        ("contact_anisotropic", Params { ky: 15.0, ..fig8 }),
        ("stiff_ring_k1000", fig8.with_stiffness(1000.0)),
    ];
    let mut g = c.benchmark_group("period");
    for (name, p) in scenes {
        let (m, y) = on_attractor(p);
        g.bench_function(name, |b| b.iter(|| period_of(&m, black_box(&y))));
    }
    g.finish();
}

fn unused_features(c: &mut Criterion) {
    let p = Preset::Fig8b.params();
    let (m, y) = on_attractor(p);
    let hidden = HiddenGuards {
        inner: m.clone(),
        guards: 2,
    };
    let (a, b) = (period_of(&m, &y), period_of(&hidden, &y));
    assert_eq!(a.strobe, b.strobe, "the preload must not be crossed");
    let mut g = c.benchmark_group("unused");
    g.bench_function("preload_guards_carried", |b| {
        b.iter(|| period_of(&m, black_box(&y)))
    });
    g.bench_function("preload_guards_hidden", |b| {
        b.iter(|| period_of(&hidden, black_box(&y)))
    });
    g.finish();
}

fn contact_hot_loop(c: &mut Criterion) {
    let p = Params {
        ex: 3.0,
        ..Preset::Fig8b.params()
    };
    let (m, y) = on_attractor(p);
    let opts = SimOptions::default();
    let (_, stats) = m.strobe_range(&y, 10, 10, &opts).expect("run");
    assert_eq!(
        stats.transitions, 0,
        "the hot-loop scene must stay in one contact regime"
    );
    let mut g = c.benchmark_group("contact_hot_loop");
    g.throughput(Throughput::Elements(stats.steps));
    g.bench_function("10_periods_steps", |b| {
        b.iter(|| m.strobe_range(black_box(&y), 10, 10, &opts).expect("run"))
    });
    g.finish();
}

fn python_baseline(c: &mut Criterion) {
    let mut g = c.benchmark_group("python_baseline");
    g.sample_size(20);
    let opts = SimOptions::default();
    for (name, preset) in [("fig8b", Preset::Fig8b), ("fig9c", Preset::Fig9c)] {
        let m = JeffcottModel::new(preset.params()).expect("preset");
        g.bench_function(format!("strobe_1000_{name}"), |b| {
            b.iter(|| {
                m.strobe_range(black_box(&State::zeros()), 0, 1000, &opts)
                    .expect("run")
            })
        });
    }
    g.finish();
}

/// One reset-mode sweep over `values` eta values of Fig. 8b with `periods` periods each;
/// returns the number of points.
fn run_sweep(values: usize, periods: u64, threads: usize) -> usize {
    let etas: Vec<f64> = (0..values)
        .map(|i| 2.0 + 3.0 * i as f64 / (values - 1) as f64)
        .collect();
    let base = Preset::Fig8b.params();
    let opts = SimOptions::default();
    let runner = |eta: &f64, _: Option<()>| -> Result<(f64, ()), String> {
        let m = JeffcottModel::new(base.with_eta(*eta)).map_err(|e| e.to_string())?;
        let (t, _) = m
            .strobe_range(&State::zeros(), periods, periods, &opts)
            .map_err(|f| f.error.to_string())?;
        Ok((t.strobe[0].y[0], ()))
    };
    let r = sweep(
        &etas,
        &SweepOptions::reset().with_threads(threads),
        runner,
        None,
    )
    .expect("sweep config");
    assert_eq!(r.failure_count(), 0);
    r.results.len()
}

fn sweeps(c: &mut Criterion) {
    let mut g = c.benchmark_group("sweep");
    g.sample_size(10);
    for (threads, periods) in [(1, 50), (2, 50), (1, 200), (2, 200)] {
        g.bench_with_input(
            BenchmarkId::new(format!("20_etas_{periods}_periods_threads"), threads),
            &threads,
            |b, &t| b.iter(|| run_sweep(20, black_box(periods), t)),
        );
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    targets = one_period, unused_features, contact_hot_loop, sweeps, python_baseline
}
criterion_main!(benches);
