//! The ring's force on the rotor (`RingedRotor::contact_force`) read from a run's samples,
//! checked against Newton's law: the station's acceleration in the run (the sample's
//! derivative, the driver's field with the ring) minus the rotor's own field without the ring
//! is the force times the station's compliance $A$ (the acceleration a unit force gives it,
//! from `SmoothRotor::add_station_force`). Case: ROSS's 42-DOF rotor on a preloaded,
//! eccentric ring (`fe_eccentric`), so that contacts cross the preload's branches.

use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::{DVector, Dyn, Matrix2, Vector2};
use jeffcott::rotor::{LinearRotor, RingedRotor, SmoothRotor};

use super::fe_eccentric::rotor_42;

const GAP: f64 = 1.5e-6;

/// The station's acceleration per unit force: column i for a unit force along axis i.
fn compliance(model: &RingedRotor<LinearRotor>, y: &DVector<f64>) -> Matrix2<f64> {
    let rotor = model.rotor();
    let column = |f: Vector2<f64>| {
        let mut dy = DVector::zeros(y.len());
        rotor.add_station_force(y, &f, &mut dy);
        rotor.station(&dy).v
    };
    Matrix2::from_columns(&[column(Vector2::x()), column(Vector2::y())])
}

#[test]
fn the_contact_force_is_the_one_that_accelerates_the_rotor() {
    let model = rotor_42(5e6, 50.0, [2e-7, 1e-7], GAP, [2e-7, -1e-7]);
    let mut y0: DVector<f64> = model.rotor().rest_state();
    model.make_consistent(&mut y0).unwrap();
    let plan = OutputPlan {
        t_end: 0.04,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: 1e-4,
        }),
        events: true,
    };
    let opts = SimOptions::default().with_rtol(1e-10).with_atol(1e-10);
    let mut traj = Trajectory::<Dyn>::default();
    simulate(&model, 0.0, &y0, &plan, &opts, &mut traj).unwrap();
    let (mut in_contact, mut largest, mut worst, mut off_normal) = (0, 0.0_f64, 0.0_f64, 0.0_f64);
    for p in &traj.samples {
        let force = model.contact_force(&p.y, p.label != 1).unwrap();
        let mut free = DVector::zeros(p.y.len());
        model.rotor().rhs(p.t, &p.y, &mut free);
        let pushed = model.rotor().station(&p.dy).v - model.rotor().station(&free).v;
        let newton = compliance(&model, &p.y).try_inverse().unwrap() * pushed;
        worst = worst.max((force - newton).norm());
        largest = largest.max(newton.norm());
        if p.label != 1 {
            in_contact += 1;
            // Pressing along the normal n = (r - s)/gap (N = -n . F >= 0); off it only by the
            // damping of an anisotropic branch pair (the paper's model: the ring is located by
            // its elastic energy alone).
            let r = model.rotor().station(&p.y).r;
            let [i, j] = model.rotor().ring_slots();
            let n = (r - Vector2::new(p.y[i], p.y[j])) / GAP;
            off_normal = off_normal.max((force.x * n.y - force.y * n.x).abs() / force.norm());
            assert!(
                -n.dot(&force) >= -1e-9 * force.norm(),
                "pulling at t = {}",
                p.t
            );
        }
    }
    println!("{in_contact} samples in contact, largest force {largest:.3e} N, off by {worst:.2e} N, off normal {off_normal:.1e}");
    assert!(
        in_contact > 20,
        "the case must touch: {in_contact} samples in contact"
    );
    assert!(worst <= 1e-7 * largest, "off by {worst:e} of {largest:e}");
}
