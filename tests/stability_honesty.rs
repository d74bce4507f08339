//! No silent wrong answer from the stability analyses (issue 16): a branch that ends by an
//! error is a failure carrying the error, not a bifurcation; located points say whether
//! their bracket converged; an orbit with a grazing event says so.

use jeffcott::paper::JeffcottModel;
use jeffcott::params::Preset;
use jeffcott::stability::{locate_loss, ContinuationOptions, StabilityError};

const CHECK: [f64; 4] = [0.5781094858, -0.0232587983, 0.0944197873, -0.3099208533];

fn guess(model: &JeffcottModel, z: [f64; 4]) -> jeffcott::paper::State {
    model.state_at([z[0], z[1]], [z[2], z[3]]).unwrap()
}

/// The case: the period-1 orbit of Fig. 8a (stable from 2.0 to its flip at 2.2348)
/// with a builder that fails beyond eta = 2.1. Nothing happens to the orbit at 2.1 (its
/// largest multiplier is about 0.76 there): the branch ends because the model cannot be
/// built, and that must be reported as such, with the builder's error.
#[test]
fn a_builder_that_fails_is_a_failure_not_a_grazing_or_a_fold() {
    let p = Preset::Fig8a.params();
    let build = |eta: f64| {
        if eta > 2.1 {
            Err(format!("no model beyond 2.1 (asked {eta})"))
        } else {
            JeffcottModel::new(p.with_eta(eta)).map_err(|e| e.to_string())
        }
    };
    let model = JeffcottModel::new(p.with_eta(2.0)).unwrap();
    let c = locate_loss(
        build,
        2.0,
        2.3,
        &guess(&model, CHECK),
        1,
        &ContinuationOptions::default(),
    )
    .unwrap();
    assert!(
        c.loss.is_none(),
        "a failure reported as a loss of stability: {:?} at {:?}",
        c.loss.as_ref().map(|l| l.kind),
        c.loss.as_ref().map(|l| l.parameter)
    );
    let f = c.failure.as_ref().expect("the branch ended by an error");
    // The error is the builder's, at a parameter beyond 2.1, and the last good orbit is at
    // or below 2.1, still stable with its largest multiplier well inside the circle.
    match &f.error {
        StabilityError::Model { parameter, reason } => {
            assert!(*parameter > 2.1, "{parameter}");
            assert!(reason.contains("no model beyond 2.1"), "{reason}");
        }
        other => panic!("expected the builder's error, got {other:?}"),
    }
    assert!(
        f.parameter > 2.1 && f.parameter - 2.1 < 0.01,
        "{}",
        f.parameter
    );
    assert!(
        f.last_parameter <= 2.1 && 2.1 - f.last_parameter < 0.01,
        "{}",
        f.last_parameter
    );
    let r = f.last_orbit.spectral_radius();
    assert!(r < 0.8, "{r}");
    // The path up to the failure is kept.
    assert!(c.path.last().unwrap().parameter <= f.last_parameter);
}

/// An exhausted step budget returns what was computed, with the error.
#[test]
fn an_exhausted_step_budget_returns_the_path_with_the_error() {
    let p = Preset::Fig8a.params();
    let model = JeffcottModel::new(p.with_eta(2.0)).unwrap();
    let opts = ContinuationOptions {
        max_steps: 3,
        ..ContinuationOptions::default()
    };
    let c = locate_loss(
        |eta| JeffcottModel::new(p.with_eta(eta)),
        2.0,
        2.3,
        &guess(&model, CHECK),
        1,
        &opts,
    )
    .expect("a budget exhausted part-way returns the path");
    assert!(c.loss.is_none());
    let f = c.failure.expect("the budget's error");
    assert!(
        matches!(
            f.error,
            StabilityError::Budget {
                field: "max_steps",
                ..
            }
        ),
        "{:?}",
        f.error
    );
    // Three steps of 0.005 from 2.0.
    assert_eq!(c.path.len(), 4);
    assert!(
        (f.last_parameter - 2.015).abs() < 1e-12,
        "{}",
        f.last_parameter
    );
}
