//! Integrator benchmarks.
//!
//! * Generic: DOP853 (and DOPRI5 for comparison) on a harmonic oscillator and
//!   on the Arenstorf orbit; throughput in accepted steps per second.
//! * The rotor: the hybrid loop's integrated steps per second in contact
//!   phases, and the cost of ten forcing periods (throughput: periods per
//!   second) of a periodic and a chaotic scene, with and without preload,
//!   started on the attractor (after 300 periods from rest).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use jeffcott::hybrid::{OutputPlan, SimOptions};
use jeffcott::numeric::Direction;
use jeffcott::ode::{
    find_first_event, AnyIntegrator, EventOptions, EventSet, EventState, Integrator, Method,
    OdeSystem, Options,
};
use jeffcott::paper::{JeffcottModel, State};
use jeffcott::params::Preset;
use nalgebra::{Const, SVector, U2, U4};
use std::hint::black_box;

type V2 = SVector<f64, 2>;
type V4 = SVector<f64, 4>;

fn oscillator(_t: f64, y: &V2, dy: &mut V2) {
    dy[0] = y[1];
    dy[1] = -y[0];
}

struct Arenstorf;
const MU: f64 = 0.012277471;
const T_ARENSTORF: f64 = 17.065_216_560_157_96;

impl OdeSystem<U4> for Arenstorf {
    fn rhs(&self, _t: f64, y: &V4, dy: &mut V4) {
        let mu1 = 1.0 - MU;
        let d1 = ((y[0] + MU).powi(2) + y[1] * y[1]).powf(1.5);
        let d2 = ((y[0] - mu1).powi(2) + y[1] * y[1]).powf(1.5);
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = y[0] + 2.0 * y[3] - mu1 * (y[0] + MU) / d1 - MU * (y[0] - mu1) / d2;
        dy[3] = y[1] - 2.0 * y[2] - mu1 * y[1] / d1 - MU * y[1] / d2;
    }
}

struct X0;
impl EventSet<U2> for X0 {
    fn len(&self) -> usize {
        1
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Either
    }
    fn terminal(&self, _i: usize) -> bool {
        false
    }
    fn value(&self, _i: usize, _t: f64, y: &V2) -> f64 {
        y[0]
    }
}

/// Integrates to `t_end`, returning the number of accepted steps.
fn run<const N: usize, S: OdeSystem<Const<N>>>(
    integ: &mut AnyIntegrator<Const<N>>,
    sys: &S,
    y0: &SVector<f64, N>,
    t_end: f64,
) -> u64 {
    integ.reset(sys, 0.0, y0, false).unwrap();
    let s0 = integ.stats().steps;
    while integ.t() < t_end {
        integ.step(sys, t_end).unwrap();
    }
    integ.stats().steps - s0
}

fn bench(c: &mut Criterion) {
    let y_osc = V2::new(1.0, 0.0);
    let y_are = V4::new(0.994, 0.0, 0.0, -2.001_585_106_379_082_5);
    for method in [Method::Dop853, Method::Dopri5] {
        let mut integ = AnyIntegrator::new(method, Options::with_tol(1e-10, 1e-10)).unwrap();
        let steps = run(&mut integ, &oscillator, &y_osc, 100.0);
        let mut g = c.benchmark_group(format!("{}/oscillator", method.name()));
        g.throughput(Throughput::Elements(steps));
        g.bench_function("t=100,tol=1e-10", |b| {
            b.iter(|| black_box(run(&mut integ, &oscillator, black_box(&y_osc), 100.0)))
        });
        g.finish();

        let mut integ = AnyIntegrator::new(method, Options::with_tol(1e-10, 1e-10)).unwrap();
        let steps = run(&mut integ, &Arenstorf, &y_are, T_ARENSTORF);
        let mut g = c.benchmark_group(format!("{}/arenstorf", method.name()));
        g.throughput(Throughput::Elements(steps));
        g.bench_function("one period,tol=1e-10", |b| {
            b.iter(|| black_box(run(&mut integ, &Arenstorf, black_box(&y_are), T_ARENSTORF)))
        });
        g.finish();
    }

    // Cost of event detection on every step (DOP853, oscillator).
    let mut integ = AnyIntegrator::new(Method::Dop853, Options::with_tol(1e-10, 1e-10)).unwrap();
    let steps = run(&mut integ, &oscillator, &y_osc, 100.0);
    let opts = EventOptions::default();
    let mut g = c.benchmark_group("DOP853/oscillator+events");
    g.throughput(Throughput::Elements(steps));
    g.bench_function("t=100,tol=1e-10", |b| {
        b.iter(|| {
            integ.reset(&oscillator, 0.0, &y_osc, false).unwrap();
            let mut st = EventState::new();
            let mut hits = 0u32;
            while integ.t() < 100.0 {
                integ.step(&oscillator, 100.0).unwrap();
                while find_first_event(&mut integ, &oscillator, &X0, &opts, &mut st)
                    .unwrap()
                    .is_some()
                {
                    hits += 1;
                }
            }
            black_box(hits)
        })
    });
    g.finish();
}

fn rotor(c: &mut Criterion) {
    let opts = SimOptions::default().with_rtol(1e-9).with_atol(1e-12);
    let scenes = [
        ("periodic, D=0 (fig8a, eta=2)", Preset::Fig8a.params()),
        ("periodic, D=0.1 (fig8b, eta=2)", Preset::Fig8b.params()),
        ("chaotic, D=0 (fig9c, eta=2.442)", Preset::Fig9c.params()),
        ("chaotic, D=0.1 (fig9d, eta=2.442)", Preset::Fig9d.params()),
    ];
    let mut g = c.benchmark_group("rotor/10 forcing periods");
    g.sample_size(20);
    for (name, p) in scenes {
        let model = JeffcottModel::new(p).unwrap();
        let period = p.forcing_period();
        let (warm, _) = model
            .strobe_range(&State::zeros(), 300, 300, &opts)
            .unwrap();
        let (t0, y0) = (warm.strobe[0].t, warm.strobe[0].y);
        let plan = OutputPlan {
            t_end: t0 + 10.0 * period,
            strobe: None,
            dense: None,
            events: false,
        };
        g.throughput(Throughput::Elements(10));
        g.bench_function(name, |b| {
            b.iter(|| black_box(model.run(t0, black_box(&y0), &plan, &opts).unwrap().1))
        });
    }
    g.finish();

    // Integrated steps per second: a contact-rich scene (two preloaded axes crossed).
    let p = Preset::Fig10b.params();
    let model = JeffcottModel::new(p).unwrap();
    let plan = OutputPlan {
        t_end: 20.0 * p.forcing_period(),
        strobe: None,
        dense: None,
        events: false,
    };
    let steps = model
        .run(0.0, &State::zeros(), &plan, &opts)
        .unwrap()
        .1
        .steps;
    let mut g = c.benchmark_group("rotor/contact steps (fig10b, 20 periods)");
    g.sample_size(20);
    g.throughput(Throughput::Elements(steps));
    g.bench_function("DOP853 rtol 1e-9", |b| {
        b.iter(|| black_box(model.run(0.0, &State::zeros(), &plan, &opts).unwrap().1))
    });
    g.finish();
}

criterion_group!(benches, bench, rotor);
criterion_main!(benches);
