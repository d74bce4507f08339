//! A user's station map is checked when the model is built (issue 16, item 8):
//! `RingedRotor::new` probes `SmoothRotor::station`, `rhs`, `add_station_force` and
//! `ring_slots`, and refuses a rotor that breaks their contract with an error naming the
//! method and the values. Before, each of these rotors was accepted and failed later, far from
//! the cause, or not at all (a silently different model): the failure of each, measured
//! before the fix, is in its test's comment. The crate's example rotors are still accepted,
//! and a station with a constant position offset (an eccentric ring, as in the flexible
//! shaft) is a valid station whose stability analysis now works.

use crate::rotor as custom;
use crate::shaft;

use jeffcott::hybrid::SimOptions;
use jeffcott::nalgebra::{DVector, SVector, Vector2, U6};
use jeffcott::params::Preset;
use jeffcott::ring::{Kinematics, SnubberRing};
use jeffcott::rotor::{RingedRotor, RotorError, SmoothRotor};
use jeffcott::stability::{periodic_orbit, OrbitOptions};

/// One mistake a user can make in a `SmoothRotor`.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Fault {
    None,
    /// The station's velocity with the wrong sign.
    VelocitySign,
    /// The force added with the wrong sign.
    ForceSign,
    /// A constant added to the station's velocity.
    VelocityOffset,
    /// A station position that is not a fixed combination of the state.
    Nonlinear,
    /// A ring slot outside the state.
    Slots,
    /// The station's position offset by a constant (a valid, eccentric, station).
    PositionOffset,
}

/// The doc example's Jeffcott rotor (unit mass, rest position (0.9, 0)), with `fault`.
#[derive(Debug, Clone)]
struct Rotor {
    fault: Fault,
    eta: f64,
}

impl SmoothRotor for Rotor {
    type Dim = U6;
    fn dim(&self) -> U6 {
        U6
    }
    fn rhs(&self, t: f64, y: &SVector<f64, 6>, dy: &mut SVector<f64, 6>) {
        let (ux, uy) = (y[0] - 0.9, y[1]);
        let b = 0.119 * self.eta * self.eta;
        let (sin, cos) = (self.eta * t).sin_cos();
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = b * cos - 0.25 * y[2] - ux;
        dy[3] = b * sin - 0.25 * y[3] - uy;
    }
    fn station(&self, y: &SVector<f64, 6>) -> Kinematics {
        let (r, v) = ([y[0], y[1]], [y[2], y[3]]);
        match self.fault {
            Fault::VelocitySign => Kinematics::new(r, [-v[0], -v[1]]),
            Fault::VelocityOffset => Kinematics::new(r, [v[0] + 0.3, v[1]]),
            Fault::Nonlinear => Kinematics::new([r[0] + 0.5 * r[0].powi(3), r[1]], v),
            Fault::PositionOffset => Kinematics::new([r[0] + 0.3, r[1]], v),
            _ => Kinematics::new(r, v),
        }
    }
    fn add_station_force(&self, _y: &SVector<f64, 6>, f: &Vector2<f64>, dy: &mut SVector<f64, 6>) {
        let sign = if self.fault == Fault::ForceSign {
            -1.0
        } else {
            1.0
        };
        dy[2] += sign * f.x;
        dy[3] += sign * f.y;
    }
    fn ring_slots(&self) -> [usize; 2] {
        if self.fault == Fault::Slots {
            [4, 6]
        } else {
            [4, 5]
        }
    }
    fn forcing_period(&self) -> f64 {
        std::f64::consts::TAU / self.eta
    }
}

fn build(fault: Fault) -> Result<RingedRotor<Rotor>, RotorError> {
    let ring = SnubberRing::isotropic(30.0, 0.0, 0.002).unwrap();
    RingedRotor::new(Rotor { fault, eta: 2.0 }, ring)
}

#[test]
fn a_velocity_of_the_wrong_sign_is_refused() {
    // Before: accepted; a run from rest failed at t = 1.62 with "chattering: 1001 transitions
    // within one forcing period (bound 1000); raise SimOptions::max_events_per_period".
    let err = build(Fault::VelocitySign).unwrap_err();
    match err {
        // The probe's velocity and derivative are opposite (the closed form of the fault).
        RotorError::StationVelocity {
            velocity,
            derivative,
            ..
        } => {
            assert!(velocity[0] != 0.0 && velocity[1] != 0.0);
            assert_eq!(velocity, [-derivative[0], -derivative[1]]);
        }
        other => panic!("{other:?}"),
    }
    assert!(err.to_string().starts_with("SmoothRotor::station"), "{err}");
}

#[test]
fn a_force_of_the_wrong_sign_is_refused() {
    // Before: accepted; a run from rest grew to 1e146 and failed at t = 69 with "right-hand
    // side returned NaN/inf".
    let err = build(Fault::ForceSign).unwrap_err();
    match err {
        // Unit mass: the acceleration is minus the force (x axis first).
        RotorError::StationForce {
            force,
            accel,
            along,
        } => {
            assert_eq!(accel, [-force[0], -force[1]]);
            assert_eq!(along, -force[0]);
            assert!(force[0] > 0.0 && force[1] == 0.0);
        }
        other => panic!("{other:?}"),
    }
    assert!(
        err.to_string()
            .starts_with("SmoothRotor::add_station_force"),
        "{err}"
    );
}

#[test]
fn a_velocity_offset_is_refused() {
    // Before: accepted, and a run from rest went through 300 periods without a sign of
    // trouble: a silently different model (the acceptance test reads a wrong acceleration).
    match build(Fault::VelocityOffset).unwrap_err() {
        RotorError::StationVelocityOffset { velocity } => assert_eq!(velocity, [0.3, 0.0]),
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_station_that_is_not_affine_is_refused() {
    // Before: accepted, and run silently (the stability tools linearise it wrongly).
    match build(Fault::Nonlinear).unwrap_err() {
        RotorError::StationNotAffine { got, want, .. } => {
            // Only r.x is cubic: the other three components agree, r.x does not.
            assert_eq!(got[1..], want[1..]);
            assert!((got[0] - want[0]).abs() > 0.1, "{got:?} {want:?}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn ring_slots_outside_the_state_are_refused() {
    // Before: accepted; `simulate` panicked with "Matrix index out of bounds".
    assert_eq!(
        build(Fault::Slots).unwrap_err(),
        RotorError::RingSlots {
            slots: [4, 6],
            dim: 6
        }
    );
}

#[test]
fn sound_rotors_are_accepted() {
    build(Fault::None).unwrap();
    // An eccentric ring: a constant in the station's position is valid.
    build(Fault::PositionOffset).unwrap();
    for preset in [Preset::Fig8a, Preset::Fig8b] {
        let p = preset.params().with_eta(2.0);
        custom::on_ring(p, 0.0, 0.0).unwrap();
        custom::on_ring(p, 0.08, 0.5).unwrap();
        shaft::on_ring(p, shaft::Layout::jeffcott()).unwrap();
        shaft::on_ring(
            p,
            shaft::Layout {
                modes: 4,
                stations: 4,
                unbalance: 2,
                ring: 3,
            },
        )
        .unwrap();
    }
}

#[test]
fn an_eccentric_station_has_the_paper_models_multipliers() {
    // The flexible shaft in one mode is the paper's model, its station offset by the
    // eccentricity (tests/suite/simulation/flexible_shaft.rs). Before, the stability tools took the
    // station map for linear and misplaced the ring: `periodic_orbit` failed with "cannot tell where
    // the ring was placed at s = (1e-16, -3e-17): no contact branch puts it there".
    // The reference: the paper model's multipliers (tests/suite/stability/stability_models.rs, from the
    // closed-form model).
    let p = Preset::Fig8a.params().with_eta(2.0);
    assert!(p.ex != 0.0);
    let model = shaft::on_ring(p, shaft::Layout::jeffcott()).unwrap();
    let point = [0.5781094858, -0.0232587983, 0.0944197873, -0.3099208533];
    let y0 = DVector::from_column_slice(&[
        point[0] - p.ex,
        point[1] - p.ey,
        point[2],
        point[3],
        0.0,
        0.0,
    ]);
    let opts =
        OrbitOptions::default().with_sim(SimOptions::default().with_rtol(1e-13).with_atol(1e-15));
    let orbit = periodic_orbit(&model, &y0, 1, &opts).unwrap();
    let want = [0.7311493467, 0.6746058590, 0.6746058590, 0.6235630128];
    for (m, w) in orbit.multipliers.iter().zip(want) {
        assert!((m.modulus() - w).abs() < 1e-8, "{} vs {w}", m.modulus());
    }
}
