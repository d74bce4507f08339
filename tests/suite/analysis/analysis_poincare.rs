//! Section crossings by linear and Hermite interpolation.

use jeffcott::analysis::{section_crossings, section_crossings_hermite, AnalysisError};
use jeffcott::numeric::Direction;
use std::f64::consts::PI;

/// A unit circle x = cos t, y = sin t sampled every `dt` on [0, 4π + 0.1].
fn circle(dt: f64) -> (Vec<f64>, Vec<[f64; 2]>, Vec<[f64; 2]>) {
    let n = ((4.0 * PI + 0.1) / dt) as usize;
    let times: Vec<f64> = (0..=n).map(|k| k as f64 * dt).collect();
    let states = times.iter().map(|t| [t.cos(), t.sin()]).collect();
    let derivs = times.iter().map(|t| [-t.sin(), t.cos()]).collect();
    (times, states, derivs)
}

#[test]
fn linear_and_hermite_find_the_crossings() {
    let (t, x, d) = circle(0.1);
    // Section y = 0, rising: t = 2π, 4π (t = 0 itself starts on the section and is not counted).
    let lin = section_crossings(&t, &x, |_, s| s[1], Direction::Rising).unwrap();
    let her = section_crossings_hermite(&t, &x, &d, |_, s| s[1], Direction::Rising).unwrap();
    assert_eq!(lin.len(), 2);
    assert_eq!(her.len(), 2);
    for (k, (l, h)) in lin.iter().zip(&her).enumerate() {
        let exact = 2.0 * PI * (k + 1) as f64;
        assert!(l.rising && h.rising);
        assert!((l.t - exact).abs() < 1e-3, "linear {}", l.t);
        assert!((h.t - exact).abs() < 1e-6, "hermite {}", h.t);
        assert!((h.state[0] - 1.0).abs() < 1e-6 && h.state[1].abs() < 1e-6);
        assert!(t[l.interval] <= l.t && l.t <= t[l.interval + 1]);
    }
    let fall = section_crossings(&t, &x, |_, s| s[1], Direction::Falling).unwrap();
    assert_eq!(fall.len(), 2);
    assert!(fall.iter().all(|c| !c.rising));
    assert!((fall[0].t - PI).abs() < 1e-3);
    let fall_h = section_crossings_hermite(&t, &x, &d, |_, s| s[1], Direction::Falling).unwrap();
    assert_eq!(fall_h.len(), 2);
    assert!((fall_h[0].t - PI).abs() < 1e-6 && (fall_h[1].t - 3.0 * PI).abs() < 1e-6);
    assert!((fall_h[0].state[0] + 1.0).abs() < 1e-6);
    let both = section_crossings(&t, &x, |_, s| s[1], Direction::Either).unwrap();
    assert_eq!(both.len(), 4);
    assert!(both.windows(2).all(|w| w[0].t < w[1].t));
}

#[test]
fn hermite_error_falls_fast() {
    let exact = 2.0 * PI;
    let err = |dt: f64| {
        let (t, x, d) = circle(dt);
        let c = section_crossings_hermite(&t, &x, &d, |_, s| s[1], Direction::Rising).unwrap();
        (c[0].t - exact).abs().max((c[0].state[0] - 1.0).abs())
    };
    let (e1, e2) = (err(0.4), err(0.2));
    assert!(e2 < e1 / 8.0, "e(0.4) = {e1}, e(0.2) = {e2}");
}

#[test]
fn time_dependent_section_and_exact_hits() {
    // h = t - 1.05 on samples every 0.1: crossing at t = 1.05.
    let t: Vec<f64> = (0..20).map(|k| k as f64 * 0.1).collect();
    let x: Vec<Vec<f64>> = t.iter().map(|&s| vec![2.0 * s]).collect();
    let c = section_crossings(&t, &x, |s, _| s - 1.05, Direction::Either).unwrap();
    assert_eq!(c.len(), 1);
    assert!((c[0].state[0] - 2.1).abs() < 1e-12);
    // Samples exactly on the section count once, in the interval that ends on them.
    let h = [-1.0, 0.0, 1.0, 0.0, -1.0];
    let t: Vec<f64> = (0..5).map(|k| k as f64).collect();
    let x: Vec<[f64; 1]> = h.iter().map(|&v| [v]).collect();
    let c = section_crossings(&t, &x, |_, s| s[0], Direction::Either).unwrap();
    let at: Vec<(f64, bool)> = c.iter().map(|c| (c.t, c.rising)).collect();
    assert_eq!(at, vec![(1.0, true), (3.0, false)]);
}

#[test]
fn bad_inputs_are_typed_errors() {
    let t = [0.0, 1.0, 2.0];
    let x = [[0.0], [1.0]];
    assert!(matches!(
        section_crossings(&t, &x, |_, s| s[0], Direction::Either),
        Err(AnalysisError::LengthMismatch {
            first_len: 3,
            second_len: 2,
            ..
        })
    ));
    let x = [[0.0], [1.0], [2.0]];
    assert!(matches!(
        section_crossings(&[0.0, 2.0, 1.0], &x, |_, s| s[0], Direction::Either),
        Err(AnalysisError::TimesNotIncreasing { index: 2, .. })
    ));
    assert!(matches!(
        section_crossings(&t, &x, |_, _| f64::NAN, Direction::Either),
        Err(AnalysisError::NonFiniteSample { index: 0, .. })
    ));
    let d = [vec![0.0], vec![1.0, 2.0], vec![0.0]];
    assert!(matches!(
        section_crossings_hermite(&t, &x, &d, |_, s| s[0], Direction::Either),
        Err(AnalysisError::DimensionMismatch { index: 1, .. })
    ));
    let none: [[f64; 1]; 0] = [];
    assert!(
        section_crossings(&[], &none, |_, s| s[0], Direction::Either)
            .unwrap()
            .is_empty()
    );
}
