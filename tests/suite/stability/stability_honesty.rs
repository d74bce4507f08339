//! No silent wrong answer from the stability analyses (issue 16): a branch that ends by an
//! error is a failure carrying the error, not a bifurcation; located points say whether
//! their bracket converged; an orbit with a grazing event says so.

use jeffcott::hybrid::SimOptions;
use jeffcott::paper::JeffcottModel;
use jeffcott::params::Preset;
use jeffcott::stability::{
    locate_loss, LossOptions, SpecialKind, StabilityError, StroboscopicMap, GRAZING_MARGIN,
};

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
        &LossOptions::default(),
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
    let opts = LossOptions::default().with_max_steps(3);
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

/// Radius of the steady orbit without contact and its phase lag (closed form of the linear
/// oscillator: A = beta eta^2 / |1 - eta^2 + 2 i nu1 eta|).
fn amplitude(p: &jeffcott::params::Params, eta: f64) -> (f64, f64) {
    let (re, im) = (1.0 - eta * eta, 2.0 * p.nu1 * eta);
    (p.beta * eta * eta / re.hypot(im), im.atan2(re))
}

/// The eta in (lo, hi) where the orbit without contact touches the gap: |e| + A(eta) = 1,
/// by bisection of the closed form to rounding.
fn grazing_eta(p: &jeffcott::params::Params, mut lo: f64, mut hi: f64) -> f64 {
    let e = p.ex.hypot(p.ey);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if e + amplitude(p, mid).0 < 1.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The period-1 orbit of Fig. 8a at `eta`, from the closed-form orbit without contact.
fn free_orbit(eta: f64) -> jeffcott::stability::PeriodicOrbit<nalgebra::U6> {
    let base = Preset::Fig8a.params();
    let model = JeffcottModel::new(base.with_eta(eta)).unwrap();
    let (a, psi) = amplitude(&base, eta);
    let start = model
        .state_at(
            [base.ex + a * psi.cos(), base.ey - a * psi.sin()],
            [a * eta * psi.sin(), a * eta * psi.cos()],
        )
        .unwrap();
    jeffcott::stability::periodic_orbit(&model, &start, 1, &Default::default()).unwrap()
}

/// The orbit without contact of Fig. 8a touches the gap circle at eta_g (closed form). Just
/// past it the orbit has a contact of depth ~ (eta - eta_g), entered and left at a normal
/// speed ~ sqrt(depth): both events are grazing, and the orbit must say so. Away from eta_g
/// (no contact below, an established contact above) it must not.
#[test]
fn an_orbit_with_a_grazing_contact_is_flagged() {
    let base = Preset::Fig8a.params();
    let eta_g = grazing_eta(&base, 0.4, 0.8);
    let near = free_orbit(eta_g + 1e-8);
    assert!(near.grazing, "{:?}", near.events);
    assert_eq!(near.events.len(), 2, "{:?}", near.events);
    assert!(near.events.iter().all(|e| e.margin < GRAZING_MARGIN));
    assert_eq!(
        near.margins.min_event_margin,
        near.events.iter().map(|e| e.margin).fold(1.0, f64::min)
    );
    // The onset's margin goes to 0 like sqrt(eta - eta_g) (a parabolic approach to the gap
    // circle, the normal speed ~ sqrt(depth)): 100 times closer, 10 times smaller, to 10 %.
    // (The loss's margin falls too, but not by this law: the loss force of so shallow a
    // contact is not the elastic one alone.)
    let nearer = free_orbit(eta_g + 1e-10);
    assert!(nearer.grazing);
    assert_eq!(near.events[0].kind, "contact onset");
    let ratio = near.events[0].margin / nearer.events[0].margin;
    assert!((ratio - 10.0).abs() < 1.0, "{ratio}");
    assert!(nearer.events[1].margin < near.events[1].margin);
    for (a, b) in near.events.iter().zip(&nearer.events) {
        // The onset's and this loss's saltations stay bounded at grazing (docs/stability.md
        // 1.3: the onset's is independent of the approach speed; the contact force, which
        // the loss's jump is, vanishes with the contact): no growth like 1/margin.
        assert!(
            a.saltation_norm < 3.0 && b.saltation_norm < 3.0,
            "{a:?} {b:?}"
        );
    }
    // No contact below, a contact crossed at a margin far from 0 above: not flagged.
    let below = free_orbit(eta_g - 1e-3);
    assert!(below.events.is_empty() && !below.grazing);
    let above = free_orbit(eta_g + 1e-2);
    assert_eq!(above.events.len(), 2);
    assert!(!above.grazing, "{:?}", above.events);
}

/// The flag travels with the located points: a grazing located by a change of event
/// structure has, 1e-8 beyond it, an orbit whose new events are crossed almost tangentially
/// (margin ~ sqrt(1e-8)); a flip has none on either side.
#[test]
fn located_points_say_whether_their_orbits_graze() {
    // D = 0.1, period 2: the ring starts crossing its preload at 3.1028052
    // (docs/stability.md).
    let p = Preset::Fig8b.params();
    let model = JeffcottModel::new(p.with_eta(3.0)).unwrap();
    let start = StroboscopicMap::new(&model, 300, SimOptions::default())
        .unwrap()
        .advance(&jeffcott::paper::State::zeros())
        .unwrap()
        .y;
    let build = |eta: f64| JeffcottModel::new(p.with_eta(eta));
    let c = locate_loss(build, 3.0, 3.2, &start, 2, &LossOptions::default()).unwrap();
    let loss = c.loss.expect("the grazing");
    assert_eq!(loss.kind, SpecialKind::Grazing);
    assert!(!loss.orbit.grazing, "{:?}", loss.orbit.events);
    assert!(loss.beyond_grazing, "the preload crossings just appeared");
    assert!(c.path.iter().all(|q| !q.grazing));
    // D = 0, period 1: the flip at 2.2348 (multipliers through -1, no event near tangency).
    let p = Preset::Fig8a.params();
    let model = JeffcottModel::new(p.with_eta(2.22)).unwrap();
    let c = locate_loss(
        |eta| JeffcottModel::new(p.with_eta(eta)),
        2.22,
        2.24,
        &guess(&model, CHECK),
        1,
        &LossOptions::default(),
    )
    .unwrap();
    let loss = c.loss.expect("the flip");
    assert_eq!(loss.kind, SpecialKind::Flip);
    assert!(!loss.orbit.grazing && !loss.beyond_grazing);
}
