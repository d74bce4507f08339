//! `--motor T0,OMEGA0,INERTIA`: the paper's rotor on a non-ideal drive
//! (`rotor::DrivenJeffcott`), the speed driven by a DC motor through the polar inertia; with
//! `--friction`, Coulomb friction at the ring whose rub torque brakes it
//! (`rotor::RubbingRotor`).

use std::f64::consts::TAU;
use std::path::Path;

use jeffcott::analysis::per_revolution;
use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, StrobeRange, Trajectory};
use jeffcott::nalgebra::{SVector, U8};
use jeffcott::ring::Kinematics;
use jeffcott::rotor::{DrivenJeffcott, MotorTorque, RubbingRotor, ETA};

use crate::common::cli::fail;
use crate::common::or_exit;
use crate::common::plot::{self, Figure, Series};
use crate::common::scene::Scene;

/// Runs the drive `motor` = `[T0, OMEGA0, INERTIA]` from `eta_from` for `duration`, sampled
/// `samples` times per revolution at the no-load speed, with `friction` = (mu, a) at the ring
/// if given; prints the speed and a summary, and draws in `out`.
#[allow(clippy::too_many_arguments)]
pub fn run(
    motor: &[f64],
    friction: Option<(f64, f64)>,
    eta_from: f64,
    duration: f64,
    no_ring: bool,
    scene: &Scene,
    samples: usize,
    out: Option<&Path>,
) {
    let &[stall, no_load, inertia] = motor else {
        fail("--motor takes three numbers: T0,OMEGA0,INERTIA");
    };
    let torque =
        MotorTorque::linear(stall, no_load).unwrap_or_else(|e| fail(format!("--motor: {e}")));
    let params = jeffcott::params::Params {
        eta: no_load,
        ..scene.params
    };
    let rotor = DrivenJeffcott::new(params, inertia, torque)
        .unwrap_or_else(|e| fail(format!("--motor: {e}")));
    let model = if no_ring {
        rotor.off_ring()
    } else {
        rotor.on_ring()
    }
    .unwrap_or_else(|e| fail(e));
    let [x0, y0, vx0, vy0] = scene.start;
    let mut start = rotor.state_at([x0, y0], [vx0, vy0], eta_from);
    or_exit(model.make_consistent(&mut start));
    // Strobes at the shaft's turns (the phase state's): the revolutions' bounds.
    let plan = OutputPlan {
        t_end: duration,
        strobe: Some(StrobeRange {
            first: 0,
            last: u64::MAX,
        }),
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: TAU / (no_load * samples as f64),
        }),
        events: true,
    };
    let mut traj = Trajectory::<U8>::default();
    let error = match friction {
        None => simulate(&model, 0.0, &start, &plan, &scene.opts, &mut traj).err(),
        Some((mu, a)) => {
            let rub = RubbingRotor::new(model, mu, a)
                .unwrap_or_else(|e| fail(format!("--friction: {e}")));
            simulate(&rub, 0.0, &start, &plan, &scene.opts, &mut traj).err()
        }
    };
    summary(&traj, duration);
    if let Some(dir) = out {
        or_exit(std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display())));
        or_exit(draw(dir, &traj, (stall, no_load, inertia), no_ring));
    }
    if let Some(e) = error {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

/// The speed at every tenth of the run, then the mean and largest speed of its last third.
fn summary(traj: &Trajectory<U8>, duration: f64) {
    let mut next = 0.0;
    for s in &traj.samples {
        if s.t >= next {
            println!("tau {:.1}: eta {:.5}", s.t, s.y[ETA]);
            next += 0.1 * duration;
        }
    }
    let late: Vec<f64> = traj
        .samples
        .iter()
        .filter(|s| s.t >= 2.0 * duration / 3.0)
        .map(|s| s.y[ETA])
        .collect();
    let mean = late.iter().sum::<f64>() / late.len().max(1) as f64;
    let max = late.iter().copied().fold(0.0, f64::max);
    let count = |kind: &str| traj.events.iter().filter(|e| e.kind == kind).count();
    let contacts = count("contact onset");
    print!("last third: mean eta {mean:.5}, largest {max:.5}; {contacts} contacts");
    let (stops, rolls) = (count("slip velocity zero"), count("friction cone's edge"));
    if traj.samples.iter().any(|s| s.label >= 6) {
        print!(" ({stops} slip stops, {rolls} ends of rolling)");
    }
    println!();
}

/// Per turn of the shaft (between the strobes, which the driven rotor puts at its turns): its
/// mean speed and the largest radius, located on the interpolant through the samples
/// ([`per_revolution`]).
fn revolutions(traj: &Trajectory<U8>) -> Vec<(f64, f64)> {
    let station = |y: &SVector<f64, 8>| Kinematics::new([y[0], y[1]], [y[2], y[3]]);
    match per_revolution(traj, 1, station) {
        Ok(revs) => revs.iter().map(|r| (r.speed, r.max_radius)).collect(),
        Err(e) => fail(format!("per revolution: {e}")),
    }
}

fn draw(
    dir: &Path,
    traj: &Trajectory<U8>,
    (stall, no_load, inertia): (f64, f64, f64),
    no_ring: bool,
) -> Result<(), String> {
    let ring = if no_ring {
        "without the ring"
    } else {
        "on the ring"
    };
    let name = format!("motor T0 = {stall}, Ω0 = {no_load}, j = {inertia}, {ring}");
    let speed = Figure::new(&format!("{name}: speed"), "τ", "η").with_columns("tau", "eta");
    let series = [Series::new(
        "η(τ)",
        traj.samples.iter().map(|s| (s.t, s.y[ETA])).collect(),
    )];
    plot::lines(dir.join("speed.png"), &speed, &series).map_err(|e| e.to_string())?;
    let env = Figure::new(
        &format!("{name}: envelope"),
        "η",
        "largest |r| per revolution",
    )
    .with_columns("eta", "radius");
    let series = [Series::new("driven", revolutions(traj))];
    plot::lines(dir.join("drive_envelope.png"), &env, &series).map_err(|e| e.to_string())
}
