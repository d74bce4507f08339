//! The generic saltation matrix against central finite differences of event maps known in
//! closed form (or to rounding): a bouncing ball (reset, autonomous guard), a ball on a moving
//! wall (time-dependent guard and reset), the same with a dynamic dimension; and the grazing
//! flag.

use jeffcott::stability::{saltation, EventLinearization, SaltationError, GRAZING_MARGIN};
use nalgebra::{DMatrix, DVector, Matrix2, Vector2};

const GRAVITY: f64 = 9.81;

/// Free fall over a time `u`: the state-transition matrix.
fn fall_stm(u: f64) -> Matrix2<f64> {
    Matrix2::new(1.0, u, 0.0, 1.0)
}

fn fall(x: &Vector2<f64>, u: f64) -> Vector2<f64> {
    Vector2::new(x[0] + x[1] * u - 0.5 * GRAVITY * u * u, x[1] - GRAVITY * u)
}

/// Bouncing ball with restitution `e`: the state at time `t_end` from `x0` at time 0, with one
/// impact at `x = 0` in between; returns it and the impact time.
fn ball_map(x0: &Vector2<f64>, e: f64, t_end: f64) -> (Vector2<f64>, f64) {
    let (p, v) = (x0[0], x0[1]);
    let te = (v + (v * v + 2.0 * GRAVITY * p).sqrt()) / GRAVITY;
    let minus = fall(x0, te);
    let plus = Vector2::new(0.0, -e * minus[1]);
    (fall(&plus, t_end - te), te)
}

/// Central differences of a map of the plane.
fn fd_jacobian(
    f: impl Fn(&Vector2<f64>) -> Vector2<f64>,
    x: &Vector2<f64>,
    h: f64,
) -> Matrix2<f64> {
    let col = |k: usize| {
        let (mut p, mut m) = (*x, *x);
        p[k] += h;
        m[k] -= h;
        (f(&p) - f(&m)) / (2.0 * h)
    };
    Matrix2::from_columns(&[col(0), col(1)])
}

#[test]
fn bouncing_ball_saltation_matches_finite_differences_and_the_classical_form() {
    let (x0, e, t_end) = (Vector2::new(1.2, 0.7), 0.8, 0.9);
    let (_, te) = ball_map(&x0, e, t_end);
    let minus = fall(&x0, te);
    let plus = Vector2::new(0.0, -e * minus[1]);
    let (f_minus, f_plus) = (
        Vector2::new(minus[1], -GRAVITY),
        Vector2::new(plus[1], -GRAVITY),
    );
    let reset = Matrix2::new(1.0, 0.0, 0.0, -e);
    let grad = Vector2::new(1.0, 0.0);
    let s = saltation(
        &EventLinearization {
            field_before: &f_minus,
            field_after: &f_plus,
            guard_gradient: &grad,
            guard_time_derivative: 0.0,
            reset_jacobian: Some(&reset),
            reset_time_derivative: None,
            state_scale: None,
        },
        GRAZING_MARGIN,
    )
    .unwrap();
    // The classical form [[-e, 0], [-(1 + e) g / v, -e]].
    let classical = Matrix2::new(-e, 0.0, -(1.0 + e) * GRAVITY / minus[1], -e);
    assert!((s.matrix - classical).norm() < 1e-14 * classical.norm());
    // The margin of a guard on the position alone is judged against the velocity: 1 here.
    assert_eq!(s.margin(), 1.0);
    let composed = fall_stm(t_end - te) * s.matrix * fall_stm(te);
    let fd = fd_jacobian(|x| ball_map(x, e, t_end).0, &x0, 1e-6);
    // The map is smooth (square roots away from zero): central differences at h = 1e-6 are
    // good to ~1e-9.
    let err = (composed - fd).norm();
    eprintln!("bouncing ball: |S composed - FD| = {err:e}");
    // Measured 1.1e-9.
    assert!(err < 3e-9, "{err:e}");
    // The event time's gradient.
    let dte = fd_jacobian(|x| Vector2::new(ball_map(x, e, t_end).1, 0.0), &x0, 1e-6)
        .row(0)
        .into_owned();
    let err_t = (dte - s.time_gradient.transpose() * fall_stm(te)).norm();
    eprintln!("bouncing ball: event time gradient vs FD {err_t:e}");
    // Measured 5.6e-11.
    assert!(err_t < 2e-10, "{err_t:e}");
}

/// Wall position and its derivatives.
const AMP: f64 = 0.3;
const OMEGA: f64 = 2.3;
fn wall(t: f64) -> (f64, f64, f64) {
    let (s, c) = (OMEGA * t).sin_cos();
    (AMP * s, AMP * OMEGA * c, -AMP * OMEGA * OMEGA * s)
}

/// A ball falling on a wall moving as `wall(t)`, bouncing elastically relative to it
/// (`v+ = 2 w'(t) - v-`): the state at `t_end` and the impact time.
fn moving_wall_map(x0: &Vector2<f64>, t_end: f64) -> (Vector2<f64>, f64) {
    let gap = |t: f64| fall(x0, t)[0] - wall(t).0;
    // Bisection to rounding on the first crossing (the gap is positive at 0 and falls).
    let (mut lo, mut hi) = (0.0, 0.05);
    while gap(hi) > 0.0 {
        lo = hi;
        hi += 0.05;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid == lo || mid == hi {
            break;
        }
        if gap(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    // Newton polish from the bracket (the gap is smooth).
    let mut te = 0.5 * (lo + hi);
    for _ in 0..3 {
        let x = fall(x0, te);
        te -= (x[0] - wall(te).0) / (x[1] - wall(te).1);
    }
    let minus = fall(x0, te);
    let plus = Vector2::new(minus[0], 2.0 * wall(te).1 - minus[1]);
    (fall(&plus, t_end - te), te)
}

fn moving_wall_saltation<D: nalgebra::Dim>(
    f_minus: &nalgebra::OVector<f64, D>,
    f_plus: &nalgebra::OVector<f64, D>,
    grad: &nalgebra::OVector<f64, D>,
    gt: f64,
    reset: &nalgebra::OMatrix<f64, D, D>,
    rt: &nalgebra::OVector<f64, D>,
) -> jeffcott::stability::Saltation<D>
where
    nalgebra::DefaultAllocator:
        nalgebra::allocator::Allocator<D> + nalgebra::allocator::Allocator<D, D>,
{
    saltation(
        &EventLinearization {
            field_before: f_minus,
            field_after: f_plus,
            guard_gradient: grad,
            guard_time_derivative: gt,
            reset_jacobian: Some(reset),
            reset_time_derivative: Some(rt),
            state_scale: None,
        },
        GRAZING_MARGIN,
    )
    .unwrap()
}

#[test]
fn time_dependent_guard_and_reset_match_finite_differences_for_fixed_and_dynamic_dimensions() {
    let (x0, t_end) = (Vector2::new(0.9, 0.4), 1.1);
    let (_, te) = moving_wall_map(&x0, t_end);
    let minus = fall(&x0, te);
    let (_, wv, wa) = wall(te);
    let plus = Vector2::new(minus[0], 2.0 * wv - minus[1]);
    let f_minus = Vector2::new(minus[1], -GRAVITY);
    let f_plus = Vector2::new(plus[1], -GRAVITY);
    // Guard x - w(t): gradient (1, 0), g_t = -w'. Reset (x, 2 w'(t) - v): R_t = (0, 2 w'').
    let grad = Vector2::new(1.0, 0.0);
    let reset = Matrix2::new(1.0, 0.0, 0.0, -1.0);
    let rt = Vector2::new(0.0, 2.0 * wa);
    let s = moving_wall_saltation(&f_minus, &f_plus, &grad, -wv, &reset, &rt);
    let composed = fall_stm(t_end - te) * s.matrix * fall_stm(te);
    let fd = fd_jacobian(|x| moving_wall_map(x, t_end).0, &x0, 1e-6);
    let err = (composed - fd).norm();
    eprintln!("moving wall: |S composed - FD| = {err:e}");
    // Measured 7.0e-10.
    assert!(err < 2e-9, "{err:e}: {composed} vs {fd}");
    // Leaving out R_t or g_t is wrong by O(1): the check can fail.
    let zero = Vector2::zeros();
    let without_rt = moving_wall_saltation(&f_minus, &f_plus, &grad, -wv, &reset, &zero);
    assert!((fall_stm(t_end - te) * without_rt.matrix * fall_stm(te) - fd).norm() > 1e-2);
    let without_gt = moving_wall_saltation(&f_minus, &f_plus, &grad, 0.0, &reset, &rt);
    assert!((fall_stm(t_end - te) * without_gt.matrix * fall_stm(te) - fd).norm() > 1e-2);

    // The same event with a dynamic dimension gives the same matrix.
    let dynamic = |v: &Vector2<f64>| DVector::from_column_slice(v.as_slice());
    let sd = moving_wall_saltation(
        &dynamic(&f_minus),
        &dynamic(&f_plus),
        &dynamic(&grad),
        -wv,
        &DMatrix::from_column_slice(2, 2, reset.as_slice()),
        &dynamic(&rt),
    );
    assert_eq!(sd.matrix.as_slice(), s.matrix.as_slice());
    assert_eq!(sd.denominator, s.denominator);
}

#[test]
fn grazing_events_are_refused_with_their_margin() {
    // A ball meeting the floor with a tiny normal speed: the denominator is -1e-7 against a
    // scale of about g.
    let f_minus = Vector2::new(-1e-7, -GRAVITY);
    let f_plus = Vector2::new(1e-7, -GRAVITY);
    let grad = Vector2::new(1.0, 0.0);
    let event = EventLinearization {
        field_before: &f_minus,
        field_after: &f_plus,
        guard_gradient: &grad,
        guard_time_derivative: 0.0,
        reset_jacobian: None,
        reset_time_derivative: None,
        state_scale: None,
    };
    // The gradient's support is the position: the scale is |v| = 1e-7 and the margin 1 (a
    // guard on positions crossed along its normal, however slowly).
    assert_eq!(saltation(&event, GRAZING_MARGIN).unwrap().margin(), 1.0);
    // A guard mixing position and velocity, crossed almost tangentially.
    let grad = Vector2::new(1.0, 1e-9);
    let event = EventLinearization {
        guard_gradient: &grad,
        ..event
    };
    match saltation(&event, GRAZING_MARGIN) {
        Err(SaltationError::Grazing {
            margin,
            threshold,
            denominator,
            scale,
        }) => {
            assert_eq!(threshold, GRAZING_MARGIN);
            assert!((denominator - (-1e-7 - 9.81e-9)).abs() < 1e-20);
            assert!((scale - GRAVITY).abs() < 1e-6);
            assert!((margin - denominator.abs() / scale).abs() < 1e-22);
        }
        other => panic!("expected grazing, got {other:?}"),
    }
    // With threshold 0 the matrix is returned, and reports its margin.
    let s = saltation(&event, 0.0).unwrap();
    assert!(s.is_grazing(GRAZING_MARGIN) && s.margin() < 2e-8);
    // Exactly tangential: refused even at threshold 0.
    let f_minus = Vector2::new(0.0, -GRAVITY);
    let grad = Vector2::new(1.0, 0.0);
    let tangential = EventLinearization {
        field_before: &f_minus,
        guard_gradient: &grad,
        ..event
    };
    assert!(matches!(
        saltation(&tangential, 0.0),
        Err(SaltationError::Grazing { margin, .. }) if margin == 0.0
    ));
}

#[test]
fn invalid_inputs_are_typed_errors() {
    let f = DVector::from_vec(vec![1.0, 0.0, 0.0]);
    let g2 = DVector::from_vec(vec![1.0, 0.0]);
    let event = EventLinearization {
        field_before: &f,
        field_after: &f,
        guard_gradient: &g2,
        guard_time_derivative: 0.0,
        reset_jacobian: None,
        reset_time_derivative: None,
        state_scale: None,
    };
    assert!(matches!(
        saltation(&event, GRAZING_MARGIN),
        Err(SaltationError::DimensionMismatch {
            field: "guard_gradient",
            expected: 3,
            found: 2
        })
    ));
    let nan = DVector::from_vec(vec![f64::NAN, 0.0, 0.0]);
    let event = EventLinearization {
        guard_gradient: &f,
        field_after: &nan,
        ..event
    };
    assert!(matches!(
        saltation(&event, GRAZING_MARGIN),
        Err(SaltationError::NonFinite {
            field: "field_after"
        })
    ));
    let event = EventLinearization {
        field_after: &f,
        ..event
    };
    assert!(matches!(
        saltation(&event, 2.0),
        Err(SaltationError::InvalidThreshold { value }) if value == 2.0
    ));
    // Identity reset, no jump: S = I.
    let s = saltation(&event, GRAZING_MARGIN).unwrap();
    assert_eq!(s.matrix, DMatrix::identity(3, 3));
    // A state scale must be positive in every component.
    let bad = DVector::from_vec(vec![1.0, 0.0, 1.0]);
    let scaled = EventLinearization {
        state_scale: Some(&bad),
        ..event
    };
    assert!(matches!(
        saltation(&scaled, GRAZING_MARGIN),
        Err(SaltationError::InvalidScale { component: 1, value }) if value == 0.0
    ));
}
