//! Period detection and distinct-value counting on synthetic orbits.

use jeffcott::analysis::{
    count_distinct, detect_period, detect_period_scalar, distinct_values, recurrence_residual,
    AnalysisError, Periodicity,
};
use proptest::prelude::*;

/// A small deterministic generator of noise in [-1, 1] (no RNG dependency, fixed seed).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }
}

/// `n` samples cycling through `base`, each component perturbed by at most `noise`.
fn orbit(base: &[[f64; 2]], n: usize, noise: f64, seed: u64) -> Vec<[f64; 2]> {
    let mut rng = Lcg(seed);
    (0..n)
        .map(|i| {
            let b = base[i % base.len()];
            [b[0] + noise * rng.next(), b[1] + noise * rng.next()]
        })
        .collect()
}

const BASES: [&[[f64; 2]]; 4] = [
    &[[0.3, -0.2]],
    &[[0.5, 0.1], [-0.4, 0.2]],
    &[[0.1, 0.0], [0.7, 0.3], [0.4, -0.6]],
    &[[0.9, 0.0], [0.2, 0.1], [0.8, 0.05], [0.25, 0.1]],
];

#[test]
fn exact_periods_one_to_four() {
    for (k, base) in BASES.iter().enumerate() {
        let o = orbit(base, 150, 0.0, 1);
        assert_eq!(
            detect_period(&o, 16, 1e-9).unwrap(),
            Periodicity::Period(k + 1)
        );
    }
}

#[test]
fn noise_within_tolerance_is_accepted() {
    let tol = 1e-4;
    for (k, base) in BASES.iter().enumerate() {
        // Each component moves by at most 0.4 tol, so differences stay below 0.8 tol.
        let o = orbit(base, 150, 0.4 * tol, 7 + k as u64);
        assert_eq!(
            detect_period(&o, 16, tol).unwrap(),
            Periodicity::Period(k + 1)
        );
    }
}

#[test]
fn noise_beyond_tolerance_is_rejected() {
    let tol = 1e-4;
    let o = orbit(BASES[1], 150, 5.0 * tol, 3);
    assert_eq!(
        detect_period(&o, 16, tol).unwrap(),
        Periodicity::NotPeriodic { up_to: 16 }
    );
}

#[test]
fn tolerance_scales_with_large_orbits() {
    // Extent 100: tol 1e-4 allows differences up to 1e-2.
    let base = [[0.0, 0.0], [100.0, 50.0]];
    let o = orbit(&base, 100, 4e-3, 11);
    assert_eq!(detect_period(&o, 8, 1e-4).unwrap(), Periodicity::Period(2));
    let o = orbit(&base, 100, 2e-2, 11);
    assert_eq!(
        detect_period(&o, 8, 1e-4).unwrap(),
        Periodicity::NotPeriodic { up_to: 8 }
    );
}

#[test]
fn quasi_periodic_rotation_is_not_periodic() {
    let omega = (5f64.sqrt() - 1.0) / 2.0; // golden rotation number
    let o: Vec<[f64; 2]> = (0..300)
        .map(|k| {
            let a = std::f64::consts::TAU * omega * k as f64;
            [a.cos(), a.sin()]
        })
        .collect();
    assert_eq!(
        detect_period(&o, 32, 1e-3).unwrap(),
        Periodicity::NotPeriodic { up_to: 32 }
    );
    // A rational rotation 3/7 is period 7.
    let o: Vec<Vec<f64>> = (0..300)
        .map(|k| {
            let a = std::f64::consts::TAU * 3.0 / 7.0 * k as f64;
            vec![a.cos(), a.sin()]
        })
        .collect();
    assert_eq!(detect_period(&o, 32, 1e-9).unwrap(), Periodicity::Period(7));
    assert_eq!(Periodicity::Period(7).period(), Some(7));
}

#[test]
fn period_longer_than_bound_is_not_periodic() {
    let base: Vec<[f64; 2]> = (0..6).map(|i| [i as f64 * 0.1, 0.0]).collect();
    let o = orbit(&base, 60, 0.0, 1);
    assert_eq!(
        detect_period(&o, 5, 1e-9).unwrap(),
        Periodicity::NotPeriodic { up_to: 5 }
    );
    assert_eq!(detect_period(&o, 6, 1e-9).unwrap(), Periodicity::Period(6));
}

#[test]
fn a_leftover_transient_rejects_the_period() {
    let mut o = orbit(BASES[0], 50, 0.0, 1);
    o[0][0] += 0.1;
    assert!(detect_period(&o, 4, 1e-6).unwrap().period().is_none());
}

#[test]
fn scalar_version_and_residual() {
    let x: Vec<f64> = (0..40).map(|i| [0.2, 0.9][i % 2]).collect();
    assert_eq!(
        detect_period_scalar(&x, 4, 1e-12).unwrap(),
        Periodicity::Period(2)
    );
    let wrapped: Vec<[f64; 1]> = x.iter().map(|&v| [v]).collect();
    assert_eq!(recurrence_residual(&wrapped, 2).unwrap(), 0.0);
    // Lag 1: |0.9 - 0.2| / max(1, 0.7) = 0.7.
    assert!((recurrence_residual(&wrapped, 1).unwrap() - 0.7).abs() < 1e-15);
}

#[test]
fn bad_arguments_are_typed_errors() {
    let o = orbit(BASES[0], 10, 0.0, 1);
    assert!(matches!(
        detect_period(&o, 0, 1e-6),
        Err(AnalysisError::InvalidCount {
            name: "max_period",
            value: 0,
            ..
        })
    ));
    assert!(matches!(
        detect_period(&o, 2, f64::NAN),
        Err(AnalysisError::InvalidValue { name: "tol", .. })
    ));
    assert!(matches!(
        detect_period(&o, 2, -1.0),
        Err(AnalysisError::InvalidValue { name: "tol", value, .. }) if value == -1.0
    ));
    assert!(matches!(
        detect_period(&o, 6, 1e-6),
        Err(AnalysisError::TooFewSamples {
            got: 10,
            needed: 12,
            ..
        })
    ));
    let ragged = vec![vec![0.0, 1.0], vec![0.0], vec![0.0, 1.0], vec![0.0, 1.0]];
    assert_eq!(
        detect_period(&ragged, 1, 1e-6),
        Err(AnalysisError::DimensionMismatch {
            index: 1,
            expected: 2,
            found: 1
        })
    );
    let mut o = orbit(BASES[0], 10, 0.0, 1);
    o[4][1] = f64::INFINITY;
    let e = detect_period(&o, 2, 1e-6).unwrap_err();
    assert!(matches!(
        e,
        AnalysisError::NonFiniteSample {
            index: 4,
            component: 1,
            ..
        }
    ));
    assert!(e.to_string().contains("sample 4, component 1"), "{e}");
    let empty: [[f64; 2]; 0] = [];
    assert!(detect_period(&empty, 1, 1e-6).is_err());
}

#[test]
fn distinct_values_clusters() {
    let v = [0.5, 0.1, 0.1 + 1e-9, 0.5 - 1e-9, 0.9, 0.1 - 1e-9];
    assert_eq!(count_distinct(&v, 1e-6).unwrap(), 3);
    let means = distinct_values(&v, 1e-6).unwrap();
    assert!((means[0] - 0.1).abs() < 1e-12 && (means[2] - 0.9).abs() < 1e-12);
    assert_eq!(count_distinct(&v, 0.0).unwrap(), 6);
    assert_eq!(count_distinct(&[], 1e-6).unwrap(), 0);
    assert!(count_distinct(&[0.0, f64::NAN], 1e-6).is_err());
    assert!(count_distinct(&[0.0], f64::INFINITY).is_err());
}

proptest! {
    #![proptest_config(crate::rng::proptest_defaults())]

    #[test]
    fn constructed_period_is_found(
        p in 1usize..10,
        offsets in prop::collection::vec(0.0f64..0.5, 10),
        noise_seed in any::<u64>(),
    ) {
        // Base points at least 0.5 apart in x, so no shorter period exists.
        let base: Vec<[f64; 2]> = (0..p).map(|i| [i as f64 + offsets[i], offsets[9 - i]]).collect();
        let o = orbit(&base, 4 * p + 20, 1e-8, noise_seed);
        prop_assert_eq!(detect_period(&o, 12, 1e-6).unwrap(), Periodicity::Period(p));
    }

    #[test]
    fn distinct_count_ignores_order(mut v in prop::collection::vec(-10.0f64..10.0, 0..60), tol in 0.0f64..0.5) {
        let a = count_distinct(&v, tol).unwrap();
        v.reverse();
        prop_assert_eq!(count_distinct(&v, tol).unwrap(), a);
        prop_assert!(a <= v.len());
    }
}

#[test]
fn periodicity_displays_in_words() {
    assert_eq!(Periodicity::Period(3).to_string(), "period 3");
    assert_eq!(
        Periodicity::NotPeriodic { up_to: 16 }.to_string(),
        "not periodic up to 16"
    );
}
