//! Criterion benchmark of a finite-element rotor's modal set-up against its size (issue 32).
//!
//! * `modal_setup/<dofs>`: `ModalRotor::new` of a synthetic shaft of `dofs` lateral DOFs (8 to
//!   512, i.e. 16 to 1024 states): the state matrix, its balanced eigen-decomposition
//!   (`numeric::eigen_decomposition`: faer's complex Schur form, eigenvectors, $V^{-1}$ and the
//!   measured backward errors) and the modal inputs and station rows. The shaft: a chain of
//!   `dofs / 2` nodes with x and y each, stiffness varying along it, anisotropic bearings at
//!   both ends, Rayleigh damping, and a gyroscopic coupling of each node's x and y at 1200 rpm
//!   (no repeated eigenvalues, a spread of decades as a real shaft's).
//!
//! * `phi_functions/{first,after_setup}`: 1000 $\varphi$-functions (`ode::phi_functions`, the
//!   exponential integrator's scalar work) before any decomposition ran in the process, and
//!   after one: equal when `numeric::eigen_decomposition` clears the vector registers that
//!   faer's assembly kernels leave dirty (without that, the second was 9 times the first on
//!   an x86 Xeon: docs/performance.md).
//!
//! * `modal_step/<dofs>`: one revolution of the same shaft in modal form on a snubber ring,
//!   driven by an out-of-balance at the ring's node into a steady full annular rub (the
//!   contact lasts the whole revolution), from a state after 8 revolutions: the modal form's
//!   ETD4 at `rtol` = `atol` = $10^{-6}$ (the state's scale in the gap's units), the stepping in
//!   contact that a rub study spends its time in. The set-up is outside the timer; the steps
//!   a revolution are printed once a size.
//!
//! Run: `cargo bench --bench modal_setup` (on a quiet machine; `uptime` for the load). The
//! times against size and their fitted exponent are in docs/performance.md.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use jeffcott::hybrid::{simulate, OutputPlan, RotorModel, SimOptions, Trajectory};
use jeffcott::nalgebra::{Complex, DMatrix, DVector, Dyn};
use jeffcott::ode::{phi_functions, Method};
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{LinearRotor, LinearSystem, ModalRotor, RingedRotor};

/// The synthetic shaft of `dofs` lateral DOFs (x of node i at 2i, y at 2i + 1), ring station at
/// its middle node.
fn shaft(dofs: usize) -> LinearRotor {
    shaft_forced(dofs, 0.0)
}

/// [`shaft`] with a forward rotating force of `force` N at the station's node (an
/// out-of-balance at the shaft's speed).
fn shaft_forced(dofs: usize, force: f64) -> LinearRotor {
    let nodes = dofs / 2;
    let speed = 1200.0 * std::f64::consts::TAU / 60.0;
    let mut k = DMatrix::<f64>::zeros(dofs, dofs);
    let mut m = DMatrix::<f64>::zeros(dofs, dofs);
    let mut g = DMatrix::<f64>::zeros(dofs, dofs);
    for i in 0..nodes {
        m[(2 * i, 2 * i)] = 2.0 + (i as f64 * 1.3).cos().abs();
        m[(2 * i + 1, 2 * i + 1)] = m[(2 * i, 2 * i)];
        let inertia = 0.01 * (1.0 + (i as f64 * 0.7).sin().abs());
        g[(2 * i, 2 * i + 1)] = inertia;
        g[(2 * i + 1, 2 * i)] = -inertia;
        if i + 1 < nodes {
            let s = 1e6 * (1.0 + 20.0 * (i as f64 * 0.7).sin().abs());
            for axis in 0..2 {
                let (a, b) = (2 * i + axis, 2 * i + 2 + axis);
                k[(a, a)] += s;
                k[(b, b)] += s;
                k[(a, b)] -= s;
                k[(b, a)] -= s;
            }
        }
    }
    for node in [0, nodes - 1] {
        k[(2 * node, 2 * node)] += 1e7;
        k[(2 * node + 1, 2 * node + 1)] += 1.5e7;
    }
    let damping = &m * 2.0 + &k * 1e-5 + &g * speed;
    let station = 2 * (nodes / 2);
    let system = LinearSystem::new(m, damping, k, speed)
        .and_then(|s| s.with_harmonic_force(station, Complex::new(force, 0.0)))
        .and_then(|s| s.with_harmonic_force(station + 1, Complex::new(0.0, -force)))
        .expect("a valid shaft");
    LinearRotor::new(system, [station, station + 1], [0.0, 0.0]).expect("a station on the shaft")
}

/// 1000 phi-functions over a spread of arguments (the series and the exponential branches).
fn phis() -> Complex<f64> {
    (0..1000).fold(Complex::new(0.0, 0.0), |acc, k| {
        let z = Complex::new(-3.0 + k as f64 * 3e-3, 2.0 - k as f64 * 2e-3);
        acc + phi_functions(black_box(z))[1]
    })
}

fn bench_phi_after_setup(c: &mut Criterion) {
    let mut group = c.benchmark_group("phi_functions");
    group.bench_function("first", |b| b.iter(phis));
    black_box(ModalRotor::new(&shaft(64)).expect("modal form"));
    group.bench_function("after_setup", |b| b.iter(phis));
    group.finish();
}

fn bench_setup(c: &mut Criterion) {
    let mut group = c.benchmark_group("modal_setup");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    for dofs in [8, 16, 32, 64, 128, 256, 512] {
        let rotor = shaft(dofs);
        group.bench_with_input(BenchmarkId::from_parameter(dofs), &rotor, |b, rotor| {
            b.iter(|| black_box(ModalRotor::new(black_box(rotor)).expect("modal form")));
        });
    }
    group.finish();
}

/// The forced shaft of `dofs` DOFs in modal form on a ring (gap 20 µm, 1e6 N/m, 100 N s/m)
/// that its steady whirl (about 0.1 mm free) presses into, and the state after 8 revolutions
/// from rest.
fn rubbing(dofs: usize, opts: &SimOptions) -> (RingedRotor<ModalRotor>, DVector<f64>) {
    let ring = SnubberRing::from_units(1e6, 100.0, [0.0, 0.0], 2e-5).expect("a ring");
    let model = ModalRotor::new(&shaft_forced(dofs, 2e3))
        .and_then(|m| m.ringed(ring))
        .expect("the modal rotor on the ring");
    let mut y = model.rotor().rest_state();
    model.make_consistent(&mut y).expect("the ring placed");
    let plan = OutputPlan::strobe(model.forcing_period(), 8, 8);
    let mut traj = Trajectory::<Dyn>::default();
    simulate(&model, 0.0, &y, &plan, opts, &mut traj).expect("the transient");
    let last = traj.strobe.pop().expect("the 8th strobe").y;
    (model, last)
}

fn bench_step(c: &mut Criterion) {
    let mut group = c.benchmark_group("modal_step");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(500));
    let opts = SimOptions::default()
        .with_method(Method::Etd4)
        .with_rtol(1e-6)
        .with_atol(1e-6);
    for dofs in [8, 16, 32, 64, 128, 256, 512] {
        let (model, y0) = rubbing(dofs, &opts);
        let period = model.forcing_period();
        let t0 = 8.0 * period;
        let plan = OutputPlan {
            events: true,
            ..OutputPlan::strobe(period, 8, 9)
        };
        let mut traj = Trajectory::<Dyn>::default();
        let stats = simulate(&model, t0, &y0, &plan, &opts, &mut traj).expect("a revolution");
        let in_contact = traj.events.is_empty() && traj.strobe.iter().all(|p| p.label != 1);
        eprintln!(
            "modal_step/{dofs}: {} steps ({} rejected), {} events a revolution; in contact throughout: {in_contact}",
            stats.steps,
            stats.rejected,
            traj.events.len()
        );
        group.bench_with_input(BenchmarkId::from_parameter(dofs), &y0, |b, y0| {
            b.iter(|| {
                let stats = simulate(&model, t0, y0, &plan, &opts, &mut ());
                black_box(stats.expect("a revolution"))
            });
        });
    }
    group.finish();
}

criterion_group!(benches, bench_phi_after_setup, bench_setup, bench_step);
criterion_main!(benches);
