use super::*;

#[test]
fn the_phase_inverse_is_the_phase_s_inverse() {
    for (a, b, r) in [
        (0.3, 3.0, 0.01),
        (3.0, 0.3, -0.05),
        (0.0, 2.0, 1.0),
        (2.0, 0.0, -0.5),
    ] {
        let p = SpeedProfile::ramp(a, b, r).unwrap();
        let end = p.phase(p.ramp_time());
        // The phase's closed form at the ramp's end: the mean speed times the duration.
        assert!((end - 0.5 * (a + b) * p.ramp_time()).abs() <= 1e-13 * end);
        for i in 0..=100 {
            let phase = end * 1.2 * f64::from(i) / 100.0;
            match p.time_of_phase(phase) {
                Some(t) => assert!((p.phase(t) - phase).abs() <= 1e-13 * end, "{phase}"),
                None => assert!(b == 0.0 && phase > end, "{phase}"),
            }
        }
    }
}

#[test]
fn a_ramp_the_rate_cannot_make_is_refused() {
    for (a, b, r) in [
        (0.3, 3.0, -0.01),
        (0.3, 3.0, 0.0),
        (0.0, 0.0, 1.0),
        (-1.0, 1.0, 1.0),
    ] {
        assert!(matches!(
            SpeedProfile::ramp(a, b, r),
            Err(RotorError::SpeedProfile { .. })
        ));
    }
    assert!(SpeedProfile::ramp(0.3, 3.0, f64::NAN).is_err());
    assert!(SpeedProfile::constant(0.0).is_err());
    let c = SpeedProfile::constant(2.0).unwrap();
    assert_eq!(
        (c.eta(5.0), c.eta_rate(5.0), c.phase(5.0)),
        (2.0, 0.0, 10.0)
    );
}

/// Up, hold, down: the speed, rate and phase against their closed forms written here.
#[test]
fn up_hold_down_has_the_closed_form_phase() {
    let segments = [
        Segment::Ramp { to: 3.0, rate: 0.5 },
        Segment::Hold { duration: 2.0 },
        Segment::Ramp {
            to: 1.0,
            rate: -0.25,
        },
    ];
    let p = SpeedProfile::piecewise(1.0, &segments).unwrap();
    // Up for 4, hold for 2, down for 8.
    assert_eq!(p.breaks(), vec![4.0, 6.0, 14.0]);
    assert_eq!((p.ramp_time(), p.eta_max(), p.eta_to()), (14.0, 3.0, 1.0));
    let closed = |t: f64| -> (f64, f64, f64) {
        if t < 4.0 {
            (1.0 + 0.5 * t, 0.5, t + 0.25 * t * t)
        } else if t < 6.0 {
            (3.0, 0.0, 8.0 + 3.0 * (t - 4.0))
        } else if t < 14.0 {
            let s = t - 6.0;
            (3.0 - 0.25 * s, -0.25, 14.0 + 3.0 * s - 0.125 * s * s)
        } else {
            (1.0, 0.0, 30.0 + (t - 14.0))
        }
    };
    for i in 1..=200 {
        let t = 0.1 * f64::from(i) - 1e-9;
        let (eta, rate, phase) = closed(t);
        assert!((p.eta(t) - eta).abs() <= 1e-14 * eta, "{t}");
        assert_eq!(p.eta_rate(t), rate, "{t}");
        assert!((p.phase(t) - phase).abs() <= 1e-14 * phase, "{t}");
        let back = p.time_of_phase(phase).unwrap();
        assert!((back - t).abs() <= 1e-12 * t.max(1.0), "{t} {back}");
    }
}

/// A run-down to rest, a hold at rest, and a run-up again: the phase stands still on the hold
/// and its inverse gives the hold's first instant.
#[test]
fn a_hold_at_rest_keeps_the_phase() {
    let segments = [
        Segment::Ramp {
            to: 0.0,
            rate: -1.0,
        },
        Segment::Hold { duration: 5.0 },
        Segment::Ramp { to: 2.0, rate: 1.0 },
    ];
    let p = SpeedProfile::piecewise(2.0, &segments).unwrap();
    assert_eq!(p.phase(2.0), 2.0);
    assert_eq!(p.phase(6.0), 2.0);
    assert_eq!(p.time_of_phase(2.0), Some(2.0));
    // Phase 2 + 1/2 again after 1 time unit of the ramp up that starts at 7.
    assert!((p.time_of_phase(2.5).unwrap() - 8.0).abs() < 1e-14);
    assert!(SpeedProfile::piecewise(0.0, &[Segment::Hold { duration: 1.0 }]).is_err());
    assert!(SpeedProfile::piecewise(1.0, &[Segment::Hold { duration: 0.0 }]).is_err());
    assert!(SpeedProfile::piecewise(
        1.0,
        &[Segment::Ramp {
            to: 2.0,
            rate: -1.0
        }]
    )
    .is_err());
}

/// A user law against its phase's closed form:
/// $\eta = 1.5 + \sin(0.3t)$, $\Phi = 1.5t + (1 - \cos 0.3t)/0.3$.
#[test]
fn a_user_law_integrates_its_phase() {
    let p =
        SpeedProfile::from_fn(400.0, |t| 1.5 + (0.3 * t).sin(), |t| 0.3 * (0.3 * t).cos()).unwrap();
    let closed = |t: f64| 1.5 * t + (1.0 - (0.3 * t).cos()) / 0.3;
    let (mut worst, mut worst_inverse) = (0.0f64, 0.0f64);
    for i in 0..4000 {
        let t = 0.1 * f64::from(i) + 0.0123;
        let want = closed(t);
        worst = worst.max((p.phase(t) - want).abs() / want);
        let back = p.time_of_phase(want).unwrap();
        worst_inverse = worst_inverse.max((back - t).abs() / t);
    }
    println!("user law: phase {worst:.2e} relative, its inverse {worst_inverse:.2e}");
    assert!(worst <= 1e-14, "{worst:e}");
    assert!(worst_inverse <= 1e-13, "{worst_inverse:e}");
    assert_eq!(p.eta_rate(401.0), 0.0);
    assert!((p.eta_max() - 2.5).abs() < 1e-3);
    assert!(SpeedProfile::from_fn(1.0, |t| 1.0 - 2.0 * t, |_| -2.0).is_err());
    assert!(SpeedProfile::from_fn(f64::NAN, |_| 1.0, |_| 0.0).is_err());
}
