//! The rub map (`stability::rub_map`) of the shared 204-DOF ROSS rotor with case S1's ring,
//! reduced to 8 Craig-Bampton modes, from below its first contact. Truth: where the steady
//! unbalance response of the same reduced rotor reaches the gap (`LinearSystem::steady_response`,
//! the complex solve of the dynamic stiffness that `fe_steady` checks against ROSS's
//! `run_unbalance_response` to 1e-10), the ellipse's semi-major axis bisected here in the speed.

use jeffcott::hybrid::{ModelError, SimOptions};
use jeffcott::nalgebra::{Complex, DVector};
use jeffcott::numeric::ArnoldiOptions;
use jeffcott::ode::Method;
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{CraigBampton, LinearRotor, RingedRotor, RotorMatrices, SmoothRotor};
use jeffcott::stability::{
    dominant_multipliers, multipliers, rub_map, RingReading, RubMapOptions, SpecialKind,
    StroboscopicMap,
};

use super::fe_reduction_s1::reduction;
use super::fe_run_up::reduced_at;
use super::fe_s1::S1;

const MODES: usize = 8;

/// S1's rotor reduced, built at any speed by one basis.
struct Rotor {
    s1: S1,
    lateral: RotorMatrices,
    cb: CraigBampton,
    ring: SnubberRing,
}

impl Rotor {
    fn new(modes: usize) -> Self {
        let s1 = S1::load();
        let (cb, model) = reduction(&s1, modes);
        // S1's ring is centred and the rotor has no constant force: the orbits are centred.
        assert_eq!(model.rotor().ring_offset(), [0.0, 0.0]);
        let ring = *model.ring();
        Rotor {
            lateral: s1.lateral(),
            s1,
            cb,
            ring,
        }
    }

    fn at(&self, speed: f64) -> LinearRotor {
        let kc = (self.lateral.stiffness(), self.lateral.damping());
        reduced_at(&self.s1, &self.lateral, (&self.cb, [0.0, 0.0]), speed, kc)
    }

    /// The semi-major axis of the ring node's steady orbit at `speed`.
    fn steady_radius(&self, speed: f64) -> f64 {
        let x = self.at(speed).system().steady_response().unwrap();
        let (a, b): (Complex<f64>, Complex<f64>) = (x[0], x[1]);
        ((a.norm_sqr() + b.norm_sqr() + (a * a + b * b).norm()) / 2.0).sqrt()
    }
}

/// The first contact of the rub map, continued from 77 rad/s, is where the steady response
/// reaches the gap, to 1e-8 rad/s.
#[test]
fn the_first_contact_of_the_ross_rotor_is_where_its_unbalance_response_reaches_the_gap() {
    let rotor = Rotor::new(MODES);
    let gap = rotor.s1.gap;
    let (mut lo, mut hi) = (77.0, 78.0);
    assert!(rotor.steady_radius(lo) < gap && rotor.steady_radius(hi) > gap);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if rotor.steady_radius(mid) < gap {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let graze = 0.5 * (lo + hi);
    let build = |speed: f64| rotor.at(speed).ringed(rotor.ring);
    let guess = build(77.0).unwrap().rotor().steady_state().unwrap();
    let read = |m: &RingedRotor<LinearRotor>, y: &DVector<f64>, contact: bool| {
        Ok::<_, ModelError>(RingReading {
            station: m.rotor().station(y),
            normal_force: m.normal_force(y, contact)?,
        })
    };
    let sim = SimOptions::default()
        .with_method(Method::Dop853)
        .with_rtol(1e-11)
        .with_atol(1e-11);
    let base = RubMapOptions::default();
    let opts = base.with_continuation(base.continuation.with_sim(sim).with_max_points(60));
    let map = rub_map(build, (77.0, 77.8), &guess, 1, &opts, read, &()).unwrap();
    let first = map
        .branch
        .specials
        .iter()
        .find(|s| s.kind == SpecialKind::Grazing)
        .expect("a grazing");
    println!(
        "first contact {:.10} rad/s (steady response {graze:.10}), {} orbits",
        first.parameter,
        map.points.len()
    );
    assert!(first.converged, "{:?}", first.unconverged);
    assert!((first.parameter - graze).abs() <= 1e-8);
}

/// The dominant Floquet multipliers by Arnoldi on Jacobian-vector products
/// (`dominant_multipliers`) against the eigenvalues of the dense Jacobian of the same map
/// (`StroboscopicMap::linearize`, then `multipliers`), on S1's rotor reduced to 24 modes at
/// 100 rad/s, over the revolution after two from rest, in which it bounces into a permanent
/// contact (5 events, each with its saltation in both paths): each to 1e-8, in fewer actions
/// than the map has components.
#[test]
fn arnoldis_dominant_multipliers_are_the_dense_monodromys() {
    let rotor = Rotor::new(24);
    let model = rotor.at(100.0).ringed(rotor.ring).unwrap();
    let sim = SimOptions::default()
        .with_method(Method::Dop853)
        .with_rtol(1e-12)
        .with_atol(1e-12);
    let mut y = model.rotor().rest_state();
    model.make_consistent(&mut y).unwrap();
    let y = StroboscopicMap::new(&model, 2, sim)
        .unwrap()
        .advance(&y)
        .unwrap()
        .y;
    let dense = StroboscopicMap::new(&model, 1, sim)
        .unwrap()
        .linearize(&y)
        .unwrap();
    let components = dense.jacobian.nrows();
    assert!(dense.events.len() >= 3, "{} events", dense.events.len());
    let reference = multipliers(&dense.jacobian).unwrap();
    let opts = ArnoldiOptions {
        count: 6,
        max_dim: 60,
        tol: 1e-10,
    };
    let found = dominant_multipliers(&model, &y, 1, sim, &opts).unwrap();
    println!(
        "{components} components, {} events; {} actions, residuals up to {:.1e}",
        dense.events.len(),
        found.actions,
        found.residuals.iter().fold(0.0f64, |a, &b| a.max(b))
    );
    assert!(found.converged && found.actions < components);
    assert_eq!(found.multipliers.len(), 6);
    // Matched to the nearest dense one (a conjugate pair's order is rounding's).
    for m in &found.multipliers {
        let err = reference
            .iter()
            .map(|r| (m.re - r.re).hypot(m.im - r.im))
            .fold(f64::INFINITY, f64::min);
        println!("{:.12} {:+.12}i: {err:.1e} from the dense one", m.re, m.im);
        assert!(err <= 1e-8);
    }
    // And they are the dense ones of largest modulus.
    let smallest = found
        .multipliers
        .iter()
        .map(|m| m.modulus())
        .fold(f64::INFINITY, f64::min);
    assert!(reference[6].modulus() <= smallest + 1e-8);
}
