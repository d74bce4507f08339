//! `--fe --fe-rub-map`: the rub map of the sweep's rotor (the same reduction, ring and
//! out-of-balance, the bearings at each speed), its steady orbits on the ring continued in
//! speed from `--fe-from` to `--fe-to` (`stability::rub_map`: through folds, every grazing,
//! fold, flip and Neimark-Sacker point located), drawn over the run-up's and run-down's
//! envelopes: where the ramps follow the map's stable orbits, where they jump, and where the
//! ramp rate moves the jump.

use std::path::Path;
use std::time::Instant;

use jeffcott::analysis::StderrProgress;
use jeffcott::hybrid::SimOptions;
use jeffcott::nalgebra::DVector;
use jeffcott::ode::Method;
use jeffcott::rotor::{LinearRotor, RingedRotor, SmoothRotor};
use jeffcott::stability::{rub_map, RingReading, RubMap, RubMapOptions};

use super::fe::{ring_of, Rotor, Setup};
use crate::common::plot::Series;

/// The rub map from `from` to `to` (rad/s), starting at the rotor's linear steady orbit at
/// `from` (which must clear the ring); prints its special points and its time.
pub fn compute(mat: &Path, setup: &Setup, (from, to): (f64, f64)) -> Result<RubMap, String> {
    let rotor = Rotor::new(mat, setup, from.max(to))?;
    let ring = ring_of(setup, true)?;
    let build = |speed: f64| -> Result<RingedRotor<LinearRotor>, String> {
        let system = rotor.system(setup, speed)?;
        LinearRotor::new(system, [0, 1], [0.0; 2])
            .and_then(|r| r.ringed(ring))
            .map_err(|e| e.to_string())
    };
    let start = build(from)?;
    let guess = start.rotor().steady_state().map_err(|e| e.to_string())?;
    let radius = start.rotor().station(&guess).r.norm();
    if radius >= setup.gap {
        return Err(format!(
            "--fe-rub-map starts at the rotor's orbit without the ring at --fe-from = {from} rad/s, \
             which reaches {:.2} gaps there: start below the first contact",
            radius / setup.gap
        ));
    }
    let read = |m: &RingedRotor<LinearRotor>, y: &DVector<f64>, contact: bool| {
        let normal_force = m.normal_force(y, contact)?;
        Ok::<_, jeffcott::hybrid::ModelError>(RingReading {
            station: m.rotor().station(y),
            normal_force,
        })
    };
    // The runs' integration (DOP853 at 1e-9, as the sweeps'), steps of at most 0.2 in the
    // scaled coordinates (the station moves at most a fifth of the gap a step): with 1, S1's
    // rotor at 24 modes steps over its Neimark-Sacker pair 0.076 rad/s apart.
    let sim = SimOptions::default()
        .with_method(Method::Dop853)
        .with_rtol(1e-9)
        .with_atol(1e-9);
    let base = RubMapOptions::default();
    // Orbits converged to 1e-8 of the gap: above the runs' noise at 1e-9.
    let continuation = base
        .continuation
        .with_sim(sim)
        .with_ds_max(0.2)
        .with_atol(1e-8);
    let opts = base.with_continuation(continuation.with_max_points(5000));
    let clock = Instant::now();
    let progress = StderrProgress::new("rub map (thousandths of the way)");
    let map =
        rub_map(build, (from, to), &guess, 1, &opts, read, &progress).map_err(|e| e.to_string())?;
    println!(
        "fe rub map: {} orbits from {from} to {to} rad/s in {:.1} s, {} special points, ended {:?}",
        map.points.len(),
        clock.elapsed().as_secs_f64(),
        map.branch.specials.len(),
        map.branch.end
    );
    for s in &map.branch.specials {
        println!(
            "  {} at {:.6} rad/s{}, contacts a revolution {} -> {}",
            s.kind.name(),
            s.parameter,
            if s.converged { "" } else { " (not located)" },
            s.contacts.0,
            s.contacts.1
        );
    }
    Ok(map)
}

/// The map as two series (radius in µm against speed), its stable and its unstable orbits,
/// each broken where the other takes over.
pub fn series(map: &RubMap) -> [Series; 2] {
    let part = |stable: bool| {
        let pick = |p: &jeffcott::stability::RubPoint| {
            let y = if p.stable == stable {
                p.amplitude * 1e6
            } else {
                f64::NAN
            };
            (p.parameter, y)
        };
        map.points.iter().map(pick).collect()
    };
    [
        Series::new("rub map: stable orbits", part(true)),
        Series::new("rub map: unstable orbits", part(false)),
    ]
}
