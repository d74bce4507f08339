//! Determinism (bitwise identical reruns) and property tests.

use jeffcott::numeric::Direction;
use jeffcott::ode::{
    solve, AnyIntegrator, EventSet, Integrator, Method, OdeSystem, Options, Recorder, Stats,
};
use nalgebra::{SVector, U2};
use proptest::prelude::*;

type V2 = SVector<f64, 2>;

/// Duffing oscillator $x'' + 0.1 x' + x + x^3 = 0.5\cos(1.2 t)$ (chaotic-ish,
/// so that any non-determinism would be amplified).
struct Duffing;
impl OdeSystem<U2> for Duffing {
    fn rhs(&self, t: f64, y: &V2, dy: &mut V2) {
        dy[0] = y[1];
        dy[1] = -0.1 * y[1] - y[0] - y[0].powi(3) + 0.5 * (1.2 * t).cos();
    }
}

/// Zero crossings of x (non-terminal) and of the velocity (non-terminal,
/// with derivative for grazing detection).
struct Crossings;
impl EventSet<U2> for Crossings {
    fn len(&self) -> usize {
        2
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Either
    }
    fn terminal(&self, _i: usize) -> bool {
        false
    }
    fn value(&self, i: usize, _t: f64, y: &V2) -> f64 {
        y[i]
    }
    fn derivative(&self, i: usize, _t: f64, _y: &V2, dy: &V2) -> Option<f64> {
        Some(dy[i])
    }
}

/// Bit patterns of `(t, y)` points.
type Points = Vec<(u64, Vec<u64>)>;

fn run(method: Method) -> (Points, Vec<(usize, u64)>, Stats) {
    let opts = if method == Method::Rk4 {
        Options::fixed(0.01)
    } else {
        Options::with_tol(1e-9, 1e-11)
    };
    let mut integ = AnyIntegrator::new(method, opts).unwrap();
    let grid: Vec<f64> = (0..=400).map(|i| i as f64 * 0.25).collect();
    let mut rec = Recorder::with_grid(grid);
    rec.record_steps = true;
    let rep = solve(
        &mut integ,
        &Duffing,
        0.0,
        &V2::new(1.0, 0.0),
        100.0,
        &Crossings,
        &mut rec,
    )
    .unwrap();
    let bits = |v: &V2| v.iter().map(|x| x.to_bits()).collect::<Vec<u64>>();
    let mut out: Points = rec
        .outputs
        .iter()
        .map(|(t, y)| (t.to_bits(), bits(y)))
        .collect();
    out.extend(rec.steps.iter().map(|(t, y)| (t.to_bits(), bits(y))));
    let ev = rec
        .events
        .iter()
        .map(|h| (h.index, h.t.to_bits()))
        .collect();
    (out, ev, rep.stats)
}

#[test]
fn reruns_are_bitwise_identical() {
    for method in Method::ALL {
        let a = run(method);
        let b = run(method);
        assert!(!a.1.is_empty());
        assert_eq!(a.0, b.0, "{}: outputs differ", method.name());
        assert_eq!(a.1, b.1, "{}: events differ", method.name());
        assert_eq!(a.2, b.2, "{}: stats differ", method.name());
        println!("{}: {} events, {:?}", method.name(), a.1.len(), a.2);
    }
}

#[test]
fn reusing_an_integrator_is_identical_to_a_fresh_one() {
    // solve() resets the integrator: a second run on the same object gives
    // the same trajectory as a fresh object (apart from cumulative stats).
    let opts = Options::with_tol(1e-9, 1e-11);
    let mut integ = AnyIntegrator::new(Method::Dop853, opts).unwrap();
    let mut r1 = Recorder::with_grid(vec![10.0, 20.0]);
    solve(
        &mut integ,
        &Duffing,
        0.0,
        &V2::new(1.0, 0.0),
        20.0,
        &Crossings,
        &mut r1,
    )
    .unwrap();
    let mut r2 = Recorder::with_grid(vec![10.0, 20.0]);
    solve(
        &mut integ,
        &Duffing,
        0.0,
        &V2::new(1.0, 0.0),
        20.0,
        &Crossings,
        &mut r2,
    )
    .unwrap();
    assert_eq!(r1.outputs, r2.outputs);
    assert_eq!(r1.events, r2.events);
}

/// Harmonic oscillator.
fn osc(_t: f64, y: &V2, dy: &mut V2) {
    dy[0] = y[1];
    dy[1] = -y[0];
}

struct X0;
impl EventSet<U2> for X0 {
    fn len(&self) -> usize {
        1
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Either
    }
    fn value(&self, _i: usize, _t: f64, y: &V2) -> f64 {
        y[0]
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 64,
        failure_persistence: None,
        ..crate::rng::proptest_defaults()
    })]

    /// x = A cos(t - phi) first crosses zero at phi + pi/2 (mod pi) after t = 0.
    #[test]
    fn first_crossing_of_random_oscillation(a in 0.1f64..10.0, phi in 0.05f64..3.0) {
        let y0 = V2::new(a * (-phi).cos(), -a * (-phi).sin());
        let mut t_exact = phi + std::f64::consts::FRAC_PI_2;
        while t_exact > std::f64::consts::PI { t_exact -= std::f64::consts::PI; }
        let mut integ = AnyIntegrator::new(Method::Dop853, Options::with_tol(1e-12, 1e-12 * a)).unwrap();
        let mut rec = Recorder::default();
        let rep = solve(&mut integ, &osc, 0.0, &y0, 10.0, &X0, &mut rec).unwrap();
        prop_assert_eq!(rec.events.len(), 1);
        prop_assert!((rep.t - t_exact).abs() < 1e-10, "{} vs {}", rep.t, t_exact);
    }

    /// Arbitrary option values never panic: they are accepted or rejected
    /// with a typed error, and stepping with any bound never panics.
    #[test]
    fn arbitrary_options_never_panic(
        rtol in prop::num::f64::ANY, atol in prop::num::f64::ANY,
        h_max in prop::num::f64::ANY, h_min in prop::num::f64::ANY,
        safety in prop::num::f64::ANY, fac_min in prop::num::f64::ANY,
        fac_max in prop::num::f64::ANY, bound in prop::num::f64::ANY,
        fixed in prop::option::of(prop::num::f64::ANY),
    ) {
        let opts = Options::<U2>::default()
            .with_rtol(rtol).with_atol(atol).with_h_max(h_max).with_h_min(h_min)
            .with_safety(safety).with_fac_min(fac_min).with_fac_max(fac_max)
            .with_fixed_step(fixed).with_max_steps(1000);
        for method in Method::ALL {
            if let Ok(mut integ) = AnyIntegrator::new(method, opts)
                && integ.reset(&osc, 0.0, &V2::new(1.0, 0.0), false).is_ok() {
                    let _ = integ.step(&osc, bound);
                    let mut out = V2::zeros();
                    integ.dense(&osc, bound, &mut out);
                    let _ = integ.truncate(&osc, bound);
                }
        }
    }
}
