//! Criterion benchmarks of the hybrid simulation (fixed inputs, modest run time).
//!
//! * `period/*`: one forcing period from a state on the attractor (reached by 300 periods from
//!   rest beforehand) for each kind of scene: no contact, contact without preload, with preload
//!   (0.1), stiff ring (K = 1000); Fig. 8 values at eta = 2.0, default options (DOP853,
//!   rtol 1e-10, atol 1e-12).
//! * `contact_hot_loop`: 10 periods of permanent contact (rest position ex = 3 beyond the gap,
//!   preload 0.1), throughput in integrator steps.
//! * `sweep/*`: a reduced bifurcation sweep, 20 eta values in [2, 5] x 50 periods (Fig. 8b,
//!   each value from rest), and 20 values x 200 periods, each with 1 and 2 worker threads.
//!
//! Run: `cargo bench --bench simulation`.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use jeffcott::analysis::{sweep, SweepConfig};
use jeffcott::hybrid::SimOptions;
use jeffcott::paper::{JeffcottModel, State};
use jeffcott::params::{Params, Preset};

/// The model and a state on its attractor at a stroboscopic time (phase 0).
fn on_attractor(p: Params) -> (JeffcottModel, State) {
    let m = JeffcottModel::new(p).expect("params");
    let (t, _) = m
        .stroboscopic(&State::zeros(), 300, 300, &SimOptions::default())
        .expect("transient");
    let y = t.strobe[0].y;
    (m, y)
}

fn one_period(c: &mut Criterion) {
    let fig8 = Preset::Fig8a.params();
    let scenes = [
        ("no_contact", Params { beta: 0.02, ..fig8 }),
        ("contact_no_preload", fig8),
        ("contact_preload", fig8.with_preload(0.1)),
        ("stiff_ring_k1000", fig8.with_stiffness(1000.0)),
    ];
    let opts = SimOptions::default();
    let mut g = c.benchmark_group("period");
    for (name, p) in scenes {
        let (m, y) = on_attractor(p);
        g.bench_function(name, |b| {
            b.iter(|| m.stroboscopic(black_box(&y), 1, 1, &opts).expect("run"))
        });
    }
    g.finish();
}

fn contact_hot_loop(c: &mut Criterion) {
    let p = Params {
        ex: 3.0,
        ..Preset::Fig8b.params()
    };
    let (m, y) = on_attractor(p);
    let opts = SimOptions::default();
    let (_, stats) = m.stroboscopic(&y, 10, 10, &opts).expect("run");
    assert_eq!(
        stats.transitions, 0,
        "the hot-loop scene must stay in one contact regime"
    );
    let mut g = c.benchmark_group("contact_hot_loop");
    g.throughput(Throughput::Elements(stats.steps));
    g.bench_function("10_periods_steps", |b| {
        b.iter(|| m.stroboscopic(black_box(&y), 10, 10, &opts).expect("run"))
    });
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
            .stroboscopic(&State::zeros(), periods, periods, &opts)
            .map_err(|f| f.error.to_string())?;
        Ok((t.strobe[0].y[0], ()))
    };
    let r = sweep(
        &etas,
        &SweepConfig::reset().with_threads(threads),
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
    targets = one_period, contact_hot_loop, sweeps
}
criterion_main!(benches);
