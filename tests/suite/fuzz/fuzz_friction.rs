//! Fuzzing friction at the ring (issue 33): the paper's rotor with Coulomb friction
//! (`paper::rub::rubbing_model`) over the paper fuzzer's parameter draws (wide stiffnesses,
//! dampings, preloads, eccentricities, speeds), friction from 0 to 1 (and beyond the ring's
//! bound of uniqueness), shaft radii from 1e-3 to 1e3 gaps, the adaptive methods and
//! tolerances from 1e-12 to 1e-6, and starts at rest, inside the gap and beyond it.
//!
//! **What must hold.** No panic, no hang; a friction coefficient at or beyond
//! `FrictionRing::limit` refused as `FrictionBeyondUniqueness` and every other one taken; a run
//! that ends in success or in one of the typed run-time errors (counted by kind: a failed
//! transition names why); every sample and both sides of every event finite; at every sample in
//! contact the ring on the circle $|r - s| = 1$ and the elastic force inside the friction cone,
//! $|F_t| \le \mu N$ (slipping: on its edge in the slip's sense), each to the resolution of
//! the run ($10^4$ rtol of the scale, as samples interpolate the ring between steps).
//!
//! `cargo test --test suite fuzz::fuzz_friction::` runs a short version (100 cases, the seed
//! of `FUZZ_SEED`, a fixed one by default, `FUZZ_SEED=clock` for a new one; printed); the long
//! one counts outcomes without stopping:
//!
//! ```text
//! FUZZ_CASES=20000 nice cargo test --test suite fuzz::fuzz_friction:: -- --ignored --nocapture
//! ```

use super::fuzz::params;
use super::harness::{env, fuzz, log_uniform, long_seeds, short_seed};

use jeffcott::hybrid::{
    simulate, DenseSampling, ModelError, OutputPlan, SimErrorKind, SimOptions, Trajectory,
};
use jeffcott::nalgebra::{DVector, Dyn, Vector2};
use jeffcott::ode::{Method, OdeError};
use jeffcott::paper::rub::rubbing_model;
use jeffcott::params::Params;
use jeffcott::ring::{FrictionRing, RingAxis, RingError, SnubberRing};
use jeffcott::rotor::RotorError;
use proptest::prelude::*;

/// Where failing cases are saved (and replayed from).
const REGRESSIONS: &str = "proptest-regressions/fuzz_friction.txt";

#[derive(Debug, Clone)]
struct Case {
    p: Params,
    friction: f64,
    shaft_radius: f64,
    method: Method,
    rtol: f64,
    /// The rotor's start: position radius and angle, velocity size and direction.
    start: [f64; 4],
    periods: u32,
}

fn case() -> impl Strategy<Value = Case> {
    let friction =
        prop_oneof![1 => Just(0.0), 2 => 0.0f64..0.3, 4 => 0.3f64..1.0, 1 => 1.0f64..5.0];
    let radius = prop_oneof![1 => log_uniform(1e-3, 1.0), 4 => log_uniform(1.0, 1e3)];
    let method = prop_oneof![
        Just(Method::Dop853),
        Just(Method::Dopri5),
        Just(Method::Radau5)
    ];
    let start = (
        prop_oneof![2 => Just(0.0), 2 => 0.0f64..1.0, 2 => 1.0f64..1.5, 1 => 1.5f64..5.0],
        -std::f64::consts::PI..std::f64::consts::PI,
        prop_oneof![2 => Just(0.0), 3 => 0.0f64..3.0],
        -std::f64::consts::PI..std::f64::consts::PI,
    );
    (
        params(),
        friction,
        radius,
        method,
        log_uniform(1e-12, 1e-6),
        start,
        1u32..20,
    )
        .prop_map(
            |(p, friction, shaft_radius, method, rtol, (rad, ang, speed, dir), periods)| Case {
                p,
                friction,
                shaft_radius,
                method,
                rtol,
                start: [rad, ang, speed, dir],
                periods,
            },
        )
}

/// The outcome's name in the counts; `None` for an error a valid case must never give.
fn outcome(kind: &SimErrorKind) -> Option<String> {
    Some(match kind {
        SimErrorKind::Model(
            ModelError::Transition { reason, .. } | ModelError::InvalidState { reason, .. },
        ) if reason.contains("below the resolution") => "preload below the resolution".into(),
        // A start beyond the gap that the onset rule cannot decide (both slips consistent):
        // the typed refusal of RingError::SlipAmbiguous.
        SimErrorKind::Model(ModelError::InvalidState { reason, .. })
            if reason.contains("contact start is ambiguous") =>
        {
            "start refused: ambiguous slip".into()
        }
        SimErrorKind::Model(ModelError::Transition { reason, .. }) => {
            format!(
                "transition failed: {}",
                reason.split(':').next().unwrap_or(reason)
            )
        }
        SimErrorKind::Integrator(OdeError::StepSizeUnderflow { .. }) => {
            "step-size underflow".into()
        }
        SimErrorKind::Integrator(OdeError::TooManySteps { .. })
        | SimErrorKind::TooManySteps { .. } => "too many steps".into(),
        SimErrorKind::Integrator(OdeError::NonFiniteRhs { .. }) => "non-finite rhs".into(),
        SimErrorKind::Chattering { .. } => "chattering".into(),
        SimErrorKind::Stalled { .. } => "stalled".into(),
        SimErrorKind::NonFinite => "non-finite state".into(),
        _ => return None,
    })
}

fn check(c: Case) -> Result<String, String> {
    let p = c.p;
    let ring = SnubberRing::new(
        RingAxis::new(p.kx, p.dx),
        RingAxis::new(p.ky, p.dy),
        p.nu2,
        1.0,
    )
    .map_err(|e| format!("ring: {e}"))?;
    let limit = FrictionRing::limit(&ring);
    let model = match rubbing_model(&p, c.friction, c.shaft_radius) {
        Ok(m) if c.friction < limit => m,
        Err(RotorError::Ring(RingError::FrictionBeyondUniqueness { .. }))
            if c.friction >= limit =>
        {
            return Ok("refused: beyond the bound of uniqueness".into())
        }
        Ok(_) => {
            return Err(format!(
                "friction {} taken at or beyond its bound {limit}",
                c.friction
            ))
        }
        Err(e) => return Err(format!("rubbing_model refused a valid case: {e}")),
    };
    let [rad, ang, speed, dir] = c.start;
    let r0 = Vector2::new(rad * ang.cos(), rad * ang.sin());
    // With friction a start beyond the gap takes the onset rule's mode and the ring is placed
    // for it; without, the model is the frictionless one, which asks for a consistent ring
    // (its minimum-energy position).
    let s0 = if c.friction == 0.0 {
        ring.consistent_position(&r0)
            .map_err(|e| format!("consistent_position: {e}"))?
    } else {
        Vector2::zeros()
    };
    let y0 = DVector::from_vec(vec![
        r0.x,
        r0.y,
        speed * dir.cos(),
        speed * dir.sin(),
        s0.x,
        s0.y,
    ]);
    let period = p.forcing_period();
    let plan = OutputPlan {
        t_end: f64::from(c.periods) * period,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: period / 16.0,
        }),
        events: true,
    };
    let opts = SimOptions::default()
        .with_method(c.method)
        .with_rtol(c.rtol)
        .with_atol(c.rtol)
        .with_max_steps(200_000);
    let mut traj: Trajectory<Dyn> = Trajectory::default();
    let label = match simulate(&model, 0.0, &y0, &plan, &opts, &mut traj) {
        Ok(_) => "ok".to_string(),
        Err(e) => {
            outcome(&e.kind).ok_or_else(|| format!("an error a valid case must not give: {e}"))?
        }
    };
    for e in &traj.events {
        if !(e.t.is_finite() && e.before.iter().chain(e.after.iter()).all(|v| v.is_finite())) {
            return Err(format!("a non-finite event record at t = {}", e.t));
        }
    }
    let mut contact = false;
    for s in &traj.samples {
        if !s.y.iter().chain(s.dy.iter()).all(|v| v.is_finite()) {
            return Err(format!("a non-finite sample at t = {}", s.t));
        }
        if s.label < 6 {
            continue;
        }
        contact = true;
        let (r, ring_s) = (Vector2::new(s.y[0], s.y[1]), Vector2::new(s.y[4], s.y[5]));
        let n = r - ring_s;
        let scale = 1.0 + r.norm();
        let resolution = 1e4 * c.rtol * scale + 1e-12 * scale;
        if (n.norm() - 1.0).abs() > resolution {
            return Err(format!("t = {}: |r - s| = {} in contact", s.t, n.norm()));
        }
        let g = ring.elastic_force(&ring_s);
        let t = Vector2::new(-n.y, n.x) / n.norm();
        let (normal, tangential) = (n.dot(&g) / n.norm(), t.dot(&g));
        let slack = resolution * (1.0 + g.norm() + p.kx.max(p.ky) * scale);
        let edge = match s.label {
            6 => Some(1.0),
            7 => Some(-1.0),
            _ => None,
        };
        let off = match edge {
            Some(sigma) => (tangential - sigma * c.friction * normal).abs(),
            None => (tangential.abs() - c.friction * normal).max(0.0),
        };
        if off > slack {
            return Err(format!(
                "t = {}: label {}, F_t {tangential}, N {normal}, mu {}: {off} off the law",
                s.t, s.label, c.friction
            ));
        }
    }
    Ok(format!(
        "{label}{}",
        if contact { " (contact)" } else { "" }
    ))
}

#[test]
fn fuzz_friction_short() {
    let seed = short_seed();
    let again = format!(
        "FUZZ_SEED={seed:#x} cargo test --test suite fuzz::fuzz_friction::fuzz_friction_short -- --nocapture"
    );
    println!("fuzz_friction_short: seed {seed:#x} (to run it again: {again})");
    let runs = fuzz(REGRESSIONS, case(), 100, seed, true, check)
        .unwrap_or_else(|e| panic!("seed {seed:#x} ({again}): {e}"));
    println!("{}", runs.report(&format!("friction, seed {seed:#x}")));
}

/// A defect the long run found (1 case in 2000, docs/friction.md), fixed: a roll that starts
/// where the slip velocity reaches zero starts with its stick margin and the margin's rate
/// both zero to rounding; here the margin rises to 5.8e-7 and falls through zero 0.006 later,
/// inside the first sample interval. The event detector's grazing search probed next to the
/// start, read the margin as exactly zero there and stopped, leaving the falling root
/// unbracketed: the contact rolled on outside the friction cone (1.1e-2 of $N$ after 0.09).
/// `ode::ode_events::a_guard_leaving_zero_by_rounding_then_falling_through_it_is_found` is
/// the detector's own test.
#[test]
fn a_roll_that_leaves_the_cone_just_after_it_starts_is_seen() {
    let case = Case {
        p: Params {
            eta: 2.758493678707135,
            nu1: 0.1712194942419911,
            nu2: 0.0,
            kx: 9.081701436186801,
            ky: 9.081701436186801,
            beta: 0.17342641696086977,
            dx: 0.15838356768879783,
            dy: 0.15838356768879783,
            ex: 0.2994521217476875,
            ey: 0.0,
            phi0: -1.1556356319514278,
        },
        friction: 1.295052272756872,
        shaft_radius: 0.022460224079493978,
        method: Method::Dop853,
        rtol: 2.6399565788482488e-8,
        start: [
            3.106461554602514,
            2.420294002454372,
            1.3484434450841571,
            -0.1670652386210769,
        ],
        periods: 12,
    };
    check(case).unwrap();
}

#[test]
#[ignore = "long run: FUZZ_CASES=20000 nice cargo test --test suite fuzz::fuzz_friction:: -- --ignored --nocapture"]
fn fuzz_friction_long() {
    let mut summary = Vec::new();
    for seed in long_seeds() {
        let runs = fuzz(
            REGRESSIONS,
            case(),
            env("FUZZ_CASES", 20_000),
            seed,
            false,
            check,
        )
        .unwrap_or_else(|e| panic!("seed {seed:#x}: {e}"));
        println!("{}", runs.report(&format!("friction, seed {seed:#x}")));
        summary.push(format!(
            "seed {seed:#x}: {} cases, {} defects",
            runs.cases,
            runs.defects.len()
        ));
    }
    println!("fuzz_friction_long summary:\n  {}", summary.join("\n  "));
    assert!(
        summary.iter().all(|l| l.ends_with(", 0 defects")),
        "{summary:#?}"
    );
}
