//! Friction at the ring on a non-ideal drive: the rub torque brakes the spin. Its energy is
//! checked in `ring::rub_energy`; here the two driven rotors the crate has (the paper's
//! [`DrivenJeffcott`] and the finite-element [`DrivenLinearRotor`](jeffcott::rotor::DrivenLinearRotor),
//! with its matrices, coupling and torque coded apart) give the same run on the paper's rotor,
//! and Radau5 (finite differences for the Jacobian in contact) the same as DOP853.

use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, RotorModel, SimOptions, Trajectory};
use jeffcott::nalgebra::{Complex, DMatrix, DVector};
use jeffcott::ode::Method;
use jeffcott::params::Params;
use jeffcott::ring::{RingAxis, SnubberRing};
use jeffcott::rotor::{DrivenJeffcott, LinearRotor, LinearSystem, MotorTorque, RubbingRotor};

/// The Fig. 8 rotor on a preloaded anisotropic ring (`ring::rub_energy`'s scene).
fn scene() -> Params {
    super::rub_energy::scene(3.0, [0.05, 0.02])
}

const MU: f64 = 0.5;
const SHAFT: f64 = 0.2;
const INERTIA: f64 = 1.0;

fn motor() -> MotorTorque {
    MotorTorque::linear(2.0, 3.2).unwrap()
}

/// The paper's rotor as a 2-DOF linear system (unit mass and stiffness, damping $2\nu_1$,
/// the out-of-balance $\beta\eta^2$ at the reference speed, the constant force $e$) on a
/// non-ideal drive, with friction at the paper's ring.
fn linear_model(p: &Params) -> RubbingRotor<jeffcott::rotor::DrivenLinearRotor> {
    let eye = DMatrix::<f64>::identity(2, 2);
    let force = Complex::new(p.beta * p.eta * p.eta, 0.0);
    let system = LinearSystem::new(eye.clone(), &eye * (2.0 * p.nu1), eye, p.eta)
        .unwrap()
        .with_harmonic_force(0, force)
        .unwrap()
        .with_harmonic_force(1, force * Complex::new(0.0, -1.0))
        .unwrap()
        .with_constant_force(0, p.ex)
        .unwrap()
        .with_constant_force(1, p.ey)
        .unwrap();
    let ring = SnubberRing::new(
        RingAxis::new(p.kx, p.dx),
        RingAxis::new(p.ky, p.dy),
        p.nu2,
        1.0,
    )
    .unwrap();
    let driven = LinearRotor::new(system, [0, 1], [0.0, 0.0])
        .unwrap()
        .with_drive(&DMatrix::zeros(2, 2), INERTIA, motor())
        .unwrap()
        .ringed(ring)
        .unwrap();
    RubbingRotor::new(driven, MU, SHAFT).unwrap()
}

/// The run's samples every 0.01 over 10 forcing periods, as plain vectors, and its events'
/// times and kinds.
fn run<M: RotorModel>(
    model: &M,
    y0: &jeffcott::nalgebra::OVector<f64, M::Dim>,
    opts: &SimOptions,
) -> (Vec<Vec<f64>>, Vec<(f64, &'static str)>)
where
    jeffcott::nalgebra::DefaultAllocator: jeffcott::nalgebra::allocator::Allocator<M::Dim>,
{
    let plan = OutputPlan {
        t_end: 10.0 * std::f64::consts::TAU / 3.0,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: 0.01,
        }),
        events: true,
    };
    let mut traj: Trajectory<M::Dim> = Trajectory::default();
    simulate(model, 0.0, y0, &plan, opts, &mut traj).unwrap();
    let samples = traj
        .samples
        .iter()
        .map(|s| s.y.iter().copied().collect())
        .collect();
    (samples, traj.events.iter().map(|e| (e.t, e.kind)).collect())
}

/// The largest difference of the rotor's position (in gaps) and of the speed between two
/// runs' samples.
fn distance(a: &[Vec<f64>], b: &[Vec<f64>]) -> (f64, f64) {
    assert_eq!(a.len(), b.len());
    a.iter().zip(b).fold((0.0f64, 0.0f64), |(r, w), (u, v)| {
        let dr = (u[0] - v[0]).hypot(u[1] - v[1]);
        (r.max(dr), w.max((u[6] - v[6]).abs()))
    })
}

/// The two driven rotors with friction agree on a run with slip, the friction cone's edge and
/// preload crossings, through which the rub torque changes the speed by several percent.
#[test]
fn the_driven_fe_rotor_with_friction_is_the_driven_paper_rotor() {
    let p = scene();
    let paper = DrivenJeffcott::new(p, INERTIA, motor()).unwrap();
    let paper_model = RubbingRotor::new(paper.on_ring().unwrap(), MU, SHAFT).unwrap();
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-13);
    let y0 = paper.state_at([0.0, 0.0], [0.0, 0.0], p.eta);
    let (a, events_a) = run(&paper_model, &y0, &opts);
    let linear = linear_model(&p);
    let y0 = DVector::from_iterator(8, y0.iter().copied());
    let (b, events_b) = run(&linear, &y0, &opts);
    let (dr, dw) = distance(&a, &b);
    let speeds = a.iter().map(|y| y[6]);
    let (lo, hi) = speeds.fold((f64::INFINITY, 0.0f64), |(l, h), w| (l.min(w), h.max(w)));
    println!(
        "{} events (kinds {:?}); speed {lo:.4}..{hi:.4}; paper vs FE drive: position {dr:.1e} gaps, speed {dw:.1e}",
        events_a.len(),
        events_a.iter().map(|e| e.1).collect::<std::collections::BTreeSet<_>>()
    );
    assert_eq!(events_a.len(), events_b.len());
    for ((ta, ka), (tb, kb)) in events_a.iter().zip(&events_b) {
        assert_eq!(ka, kb);
        assert!((ta - tb).abs() < 1e-8, "{ka} at {ta} and {tb}");
    }
    assert!(hi - lo > 0.05 * p.eta, "the speed must move");
    assert!(dr < 1e-8 && dw < 1e-8);
}

/// Radau5 on the finite-element drive with friction (its Jacobian by finite differences in
/// contact) agrees with DOP853 to its tolerance.
#[test]
fn radau5_on_the_driven_fe_rotor_with_friction_agrees_with_dop853() {
    let p = scene();
    let model = linear_model(&p);
    let mut y0 = DVector::zeros(8);
    y0[6] = p.eta;
    let tight = SimOptions::default().with_rtol(1e-12).with_atol(1e-13);
    let (a, events_a) = run(&model, &y0, &tight);
    let radau = SimOptions::default()
        .with_method(Method::Radau5)
        .with_rtol(1e-9)
        .with_atol(1e-10);
    let (b, events_b) = run(&model, &y0, &radau);
    let (dr, dw) = distance(&a, &b);
    println!("Radau5 rtol 1e-9 vs DOP853 rtol 1e-12: position {dr:.1e} gaps, speed {dw:.1e}; events {} and {}", events_a.len(), events_b.len());
    assert_eq!(events_a.len(), events_b.len());
    assert!(dr < 1e-6 && dw < 1e-6);
}

/// A profiled rotor gives its spin too: the paper's rotor at a constant profile with friction
/// is [`rubbing_model`](jeffcott::paper::rub::rubbing_model) (the constant speed's
/// `LinearRotor`, coded apart) on a run with slip stops, rolling and preload crossings.
#[test]
fn a_constant_profile_with_friction_is_the_constant_speed_rotor() {
    use jeffcott::rotor::{ProfiledJeffcott, SpeedProfile};
    let p = Params {
        eta: 2.5,
        ..scene()
    };
    let (mu, a) = (0.3, 0.05);
    let profiled = ProfiledJeffcott::new(p, SpeedProfile::constant(p.eta).unwrap()).unwrap();
    let model = RubbingRotor::new(profiled.on_ring().unwrap(), mu, a).unwrap();
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-13);
    let y0 = jeffcott::nalgebra::SVector::<f64, 6>::zeros();
    let reference = jeffcott::paper::rub::rubbing_model(&p, mu, a).unwrap();
    let plan = OutputPlan {
        t_end: 10.0 * std::f64::consts::TAU / p.eta,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: 0.01,
        }),
        events: true,
    };
    let mut run_a = Trajectory::default();
    simulate(&model, 0.0, &y0, &plan, &opts, &mut run_a).unwrap();
    let mut run_b = Trajectory::default();
    simulate(
        &reference,
        0.0,
        &DVector::zeros(6),
        &plan,
        &opts,
        &mut run_b,
    )
    .unwrap();
    let kinds: std::collections::BTreeSet<_> = run_a.events.iter().map(|e| e.kind).collect();
    let worst = run_a
        .samples
        .iter()
        .zip(&run_b.samples)
        .map(|(u, v)| (u.y[0] - v.y[0]).hypot(u.y[1] - v.y[1]))
        .fold(0.0f64, f64::max);
    println!(
        "{} events {kinds:?}; profiled vs constant speed: {worst:.1e} gaps",
        run_a.events.len()
    );
    assert!(kinds.contains("slip velocity zero") && kinds.contains("friction cone's edge"));
    assert_eq!(run_a.events.len(), run_b.events.len());
    assert_eq!(run_a.samples.len(), run_b.samples.len());
    assert!(worst < 1e-8);
}

/// A rotor whose spin is a state but that does not take the rub torque is refused with
/// friction (its drive would run on unbraked) and taken without.
#[test]
fn a_drive_that_ignores_the_rub_torque_is_refused() {
    use jeffcott::nalgebra::{SVector, Vector2, U8};
    use jeffcott::ring::Kinematics;
    use jeffcott::rotor::{RotorError, SmoothRotor};

    /// [`DrivenJeffcott`] without its `add_shaft_torque`.
    #[derive(Debug, Clone)]
    struct Deaf(DrivenJeffcott);
    impl SmoothRotor for Deaf {
        type Dim = U8;
        fn dim(&self) -> U8 {
            U8
        }
        fn rhs(&self, t: f64, y: &SVector<f64, 8>, dy: &mut SVector<f64, 8>) {
            self.0.rhs(t, y, dy)
        }
        fn station(&self, y: &SVector<f64, 8>) -> Kinematics {
            self.0.station(y)
        }
        fn add_station_force(
            &self,
            y: &SVector<f64, 8>,
            f: &Vector2<f64>,
            dy: &mut SVector<f64, 8>,
        ) {
            self.0.add_station_force(y, f, dy)
        }
        fn ring_slots(&self) -> [usize; 2] {
            self.0.ring_slots()
        }
        fn forcing_period(&self) -> f64 {
            self.0.forcing_period()
        }
        fn spin(&self, t: f64, y: &SVector<f64, 8>) -> Option<jeffcott::rotor::Spin> {
            self.0.spin(t, y)
        }
        fn spin_speed_index(&self) -> Option<usize> {
            self.0.spin_speed_index()
        }
    }
    let p = scene();
    let rotor = Deaf(DrivenJeffcott::new(p, INERTIA, motor()).unwrap());
    let ring = *DrivenJeffcott::new(p, INERTIA, motor())
        .unwrap()
        .on_ring()
        .unwrap()
        .ring();
    let ringed = || jeffcott::rotor::RingedRotor::new(rotor.clone(), ring).unwrap();
    let err = RubbingRotor::new(ringed(), MU, SHAFT).unwrap_err();
    assert!(
        matches!(
            err,
            RotorError::Friction {
                field: "spin_speed_index",
                ..
            }
        ),
        "{err}"
    );
    assert!(RubbingRotor::new(ringed(), 0.0, SHAFT).is_ok());
}
