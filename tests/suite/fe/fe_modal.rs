//! `ModalRotor` (a linear rotor in the modal coordinates of its state matrix) and the
//! exponential integrator `Etd4` on case S1. The modal form is checked against the physical
//! `LinearRotor` it comes from (its field and station through the change of coordinates), and
//! S1 against the shared independent reference (see `fe_s1`).

use jeffcott::hybrid::{simulate, OutputPlan, SimOptions};
use jeffcott::nalgebra::{DVector, Vector2};
use jeffcott::ode::Method;
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{LinearRotor, ModalRotor, RingedRotor, SmoothRotor};

use super::fe_reduction_s1::reduced_model;
use super::fe_s1::{contact_events, event_error, run_sampled, Run, S1};

/// S1's rotor (full, or reduced to `modes` Craig-Bampton modes) in modal form, with the ring.
pub fn modal_model(s1: &S1, modes: Option<usize>) -> RingedRotor<ModalRotor> {
    let physical = match modes {
        None => s1.model(1.0),
        Some(m) => reduced_model(s1, m),
    };
    let ring: SnubberRing = *physical.ring();
    ModalRotor::new(physical.rotor())
        .unwrap()
        .ringed(ring)
        .unwrap()
}

/// One S1 run of a modal model with `method` at `rtol` (= atol), sampled as the reference;
/// the run and its largest sample error in gaps.
pub fn run_modal(
    s1: &S1,
    model: &RingedRotor<ModalRotor>,
    method: Method,
    rtol: f64,
    t_end: f64,
) -> (Run, f64) {
    let y0 = model.rotor().rest_state();
    let displacement = |y: &DVector<f64>| model.rotor().station_displacement(y);
    run_sampled(s1, (model, &y0), displacement, (method, rtol), t_end)
}

/// The modal field is the physical one in other coordinates: at a few states $x$,
/// $T^{-1} f_\text{phys}(t, x) = f_\text{modal}(t, T^{-1}x)$ (both with a force at the
/// station), the station agrees, and $x \to w \to x$ is the identity, each to $10^{-9}$ of the
/// terms' size (the modes' condition number times rounding).
#[test]
fn the_modal_form_is_the_physical_rotor_in_other_coordinates() {
    let s1 = S1::load();
    let physical = reduced_model(&s1, 24);
    let linear: &LinearRotor = physical.rotor();
    let modal = ModalRotor::new(linear).unwrap();
    let n2 = linear.rest_state().len() - 2;
    let force = Vector2::new(40.0, -25.0);
    for (m, t) in [(0usize, 0.0), (1, 0.0123)] {
        let x = DVector::from_fn(n2 + 2, |i, _| {
            let q = 1e-5 * ((i * 7 + m * 3) as f64).sin();
            if (n2 / 2..n2).contains(&i) {
                q * 300.0
            } else {
                q
            }
        });
        let w = modal.modal_state(&x).unwrap();
        let back = modal.physical_state(&w).unwrap();
        let size = x.amax();
        assert!(
            (&back - &x).amax() <= 1e-9 * size,
            "round trip {:e}",
            (&back - &x).amax()
        );
        let (kp, km) = (linear.station(&x), modal.station(&w));
        assert!((kp.r - km.r).norm() <= 1e-9 * kp.r.norm().max(s1.gap));
        assert!((kp.v - km.v).norm() <= 1e-9 * kp.v.norm());
        let mut dp = linear.rest_state();
        linear.rhs(t, &x, &mut dp);
        linear.add_station_force(&x, &force, &mut dp);
        let mut dm = modal.rest_state();
        modal.rhs(t, &w, &mut dm);
        modal.add_station_force(&w, &force, &mut dm);
        // Compare in physical coordinates (the ring's slots are not the rotor's).
        let dm_phys = modal.physical_state(&dm).unwrap();
        for half in [0..n2 / 2, n2 / 2..n2] {
            let scale = half.clone().map(|i| dp[i].abs()).fold(0.0, f64::max);
            for i in half {
                assert!(
                    (dm_phys[i] - dp[i]).abs() <= 1e-9 * scale,
                    "component {i}: {} against {}",
                    dm_phys[i],
                    dp[i]
                );
            }
        }
    }
}

/// A system without a diagonal linear part is refused by ETD4 with the typed error.
#[test]
fn etd4_refuses_a_physical_rotor() {
    let s1 = S1::load();
    let model = reduced_model(&s1, 8);
    let y0 = model.rotor().rest_state();
    let plan = OutputPlan {
        t_end: 0.01,
        strobe: None,
        dense: None,
        events: false,
    };
    let opts = SimOptions::default().with_method(Method::Etd4);
    let err = simulate(&model, 0.0, &y0, &plan, &opts, &mut ()).unwrap_err();
    assert!(err.to_string().contains("linear part"), "{err}");
}

/// S1 on the full model in modal form with ETD4: within 1e-6 of the gap at every sample, the
/// reference's 7 onsets and 6 losses.
#[test]
fn s1_full_model_in_modal_form_with_etd4() {
    let (s1, t_end) = (S1::load(), 0.5);
    let model = modal_model(&s1, None);
    let (run, err) = run_modal(&s1, &model, Method::Etd4, 1e-8, t_end);
    let dt_event = event_error(&run, t_end);
    let s = &run.stats;
    println!(
        "S1 full, modal, ETD4 rtol 1e-8: {:.2} s, {} steps, {} rejected, {} rhs, {} transitions; {err:.2e} of the gap, events within {dt_event:.1e} s",
        run.seconds, s.steps, s.rejected, s.rhs_evals, s.transitions
    );
    let events = contact_events(&run);
    assert_eq!(events.iter().filter(|e| e.0 == "onset").count(), 7);
    assert_eq!(events.iter().filter(|e| e.0 == "loss").count(), 6);
    assert!(err <= 1e-6, "{err:e}");
}

/// S1's cost per revolution and error against the modes kept, ETD4 on the modal form at rtol
/// 1e-6 (the settings of docs/fe-rotors.md's table for DOP853 and Radau5); the wall time the
/// least of 3 runs (a shared machine).
#[test]
#[ignore = "a measurement: cargo test --release --test suite fe::fe_modal -- --ignored --nocapture"]
fn s1_cost_against_modes_with_etd4() {
    let (s1, t_end) = (S1::load(), 0.5);
    let revolutions = t_end * s1.params["speed_rad_s"].as_f64().unwrap() / std::f64::consts::TAU;
    println!(
        "modes | states | steps (rejected) | transitions | µs per revolution | max error / gap"
    );
    for modes in [Some(8), Some(16), Some(32), Some(64), Some(96), None] {
        let model = modal_model(&s1, modes);
        let (run, err) = run_modal(&s1, &model, Method::Etd4, 1e-6, t_end);
        let mut seconds = run.seconds;
        for _ in 0..2 {
            seconds = seconds.min(run_modal(&s1, &model, Method::Etd4, 1e-6, t_end).0.seconds);
        }
        let s = &run.stats;
        println!(
            "{} | {} | {} ({}) | {} | {:.0} | {err:.1e}",
            modes.map_or("full".to_string(), |m| m.to_string()),
            model.rotor().rest_state().len(),
            s.steps,
            s.rejected,
            s.transitions,
            1e6 * seconds / revolutions
        );
    }
}
