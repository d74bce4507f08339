//! A preloaded, eccentric ring on ROSS's 42-DOF rotor (`rotor_example` at 1500 rpm, undamped:
//! only the ring dissipates), run by two integrators of different families (DOP853 and Radau5):
//! the same contacts, the same orbit. Once with the ring's centre within the gap of the
//! undeflected node, once beyond it (the rotor starts in contact: the rest state is made
//! consistent first).

use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::{DVector, Dyn};
use jeffcott::ode::Method;
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{LinearRotor, LinearSystem, RingedRotor, RotorMatrices};

const GAP: f64 = 1.5e-6;

fn model(offset: [f64; 2]) -> RingedRotor<LinearRotor> {
    rotor_42(5e6, 50.0, [2e-7, 1e-7], GAP, offset)
}

/// The 42-DOF ROSS rotor at 1500 rpm (unbalances at nodes 2 and 5) with the ring of unit
/// stiffness `ks`, unit damping `cs`, preloads and gap at node 4, its centre at `offset` (m).
pub fn rotor_42(
    ks: f64,
    cs: f64,
    preload: [f64; 2],
    gap: f64,
    offset: [f64; 2],
) -> RingedRotor<LinearRotor> {
    let path = format!(
        "{}/tests/data/rotors/rotor_example_1500rpm.mat",
        env!("CARGO_MANIFEST_DIR")
    );
    let lateral = RotorMatrices::from_ross_mat(path)
        .unwrap()
        .lateral()
        .unwrap();
    let speed = 1500.0 * std::f64::consts::TAU / 60.0;
    let system = LinearSystem::from_matrices(&lateral, speed)
        .unwrap()
        .with_unbalance(lateral.layout(), 2, 1e-4, 0.0)
        .unwrap()
        .with_unbalance(lateral.layout(), 5, 5e-5, 1.0)
        .unwrap();
    let x = lateral.x_dof(4).unwrap();
    let ring = SnubberRing::from_units(ks, cs, preload, gap).unwrap();
    LinearRotor::new(system, [x, x + 1], offset)
        .unwrap()
        .ringed(ring)
        .unwrap()
}

fn run(model: &RingedRotor<LinearRotor>, method: Method, rtol: f64) -> Trajectory<Dyn> {
    let mut y0: DVector<f64> = model.rotor().rest_state();
    model.make_consistent(&mut y0).unwrap();
    let plan = OutputPlan {
        t_end: 0.08,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: 1e-3,
        }),
        events: true,
    };
    let opts = SimOptions::default()
        .with_method(method)
        .with_rtol(rtol)
        .with_atol(rtol);
    let mut trajectory = Trajectory::default();
    let stats = simulate(model, 0.0, &y0, &plan, &opts, &mut trajectory).unwrap();
    println!("{method:?}: {stats:?}");
    trajectory
}

fn compare(offset: [f64; 2]) {
    let model = model(offset);
    let a = run(&model, Method::Dop853, 1e-10);
    let b = run(&model, Method::Radau5, 1e-9);
    let kinds = |t: &Trajectory<Dyn>| {
        t.events
            .iter()
            .filter(|e| e.from != e.to)
            .map(|e| (e.kind, e.from, e.to))
            .collect::<Vec<_>>()
    };
    assert_eq!(kinds(&a), kinds(&b));
    let transitions = kinds(&a).len();
    assert!(transitions >= 2, "{:?}", kinds(&a));
    let mut worst = 0.0f64;
    for (p, q) in a.samples.iter().zip(&b.samples) {
        let (u, v) = (
            model.rotor().station_displacement(&p.y),
            model.rotor().station_displacement(&q.y),
        );
        worst = worst.max(((u[0] - v[0]).powi(2) + (u[1] - v[1]).powi(2)).sqrt() / GAP);
    }
    let labels: std::collections::BTreeSet<_> = kinds(&a).iter().map(|k| k.0).collect();
    println!(
        "offset {offset:?}: {transitions} transitions {labels:?}, DOP853 vs Radau5 {worst:.2e} gap"
    );
    assert!(worst <= 1e-6, "{worst:e}");
}

#[test]
fn eccentric_preloaded_ring_within_the_gap() {
    compare([5e-7, -3e-7]);
}

#[test]
fn eccentric_preloaded_ring_beyond_the_gap() {
    compare([2e-6, 0.0]);
}
