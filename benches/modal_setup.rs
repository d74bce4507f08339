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
//! Run: `cargo bench --bench modal_setup` (on a quiet machine; `uptime` for the load). The
//! times against size and their fitted exponent are in docs/performance.md.

use std::hint::black_box;
use std::time::Duration;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use jeffcott::nalgebra::{Complex, DMatrix};
use jeffcott::ode::phi_functions;
use jeffcott::rotor::{LinearRotor, LinearSystem, ModalRotor};

/// The synthetic shaft of `dofs` lateral DOFs (x of node i at 2i, y at 2i + 1), ring station at
/// its middle node.
fn shaft(dofs: usize) -> LinearRotor {
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
    let system = LinearSystem::new(m, damping, k, speed).expect("a valid shaft");
    let station = 2 * (nodes / 2);
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

criterion_group!(benches, bench_phi_after_setup, bench_setup);
criterion_main!(benches);
