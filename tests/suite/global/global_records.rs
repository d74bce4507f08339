//! The sweeps' record format (serde's JSON of the values, `global::Record`): every `f64`
//! written to a sweep's folder reads back bit for bit, whether the run computed it or a
//! restart read it from the folder; a value that would not read back (NaN, an infinity) is
//! never written.

use std::fs;
use std::path::PathBuf;

use jeffcott::global::{run_points, RunOptions, StoreError, SweepStore};
use proptest::prelude::*;

fn temp_dir(name: &str) -> PathBuf {
    let exe = std::env::current_exe().unwrap();
    let target = exe.parent().and_then(|d| d.parent()).unwrap().to_path_buf();
    let dir = target.join("global_records_test").join(name);
    let _ = fs::remove_dir_all(&dir);
    dir
}

/// Finite `f64`s: uniform over the bit patterns (so subnormals, both zeros and both ends of
/// the range come often), and the edge values themselves.
fn finite() -> impl Strategy<Value = f64> {
    let edges = [
        0x0000_0000_0000_0000, // 0.0
        0x8000_0000_0000_0000, // -0.0
        0x0000_0000_0000_0001, // smallest subnormal, 5e-324
        0x800F_FFFF_FFFF_FFFF, // -(largest subnormal)
        0x0010_0000_0000_0000, // f64::MIN_POSITIVE
        0x7FEF_FFFF_FFFF_FFFF, // f64::MAX
        0xFFEF_FFFF_FFFF_FFFF, // f64::MIN
        0x3FEF_FFFF_FFFF_FFFF, // 1 - 2^-53
        0x3FB9_9999_9999_999A, // 0.1
        0x4340_0000_0000_0001, // 2^53 + 2: integral, beyond the exact integers of an f64
    ];
    prop_oneof![
        any::<u64>()
            .prop_map(f64::from_bits)
            .prop_filter("finite", |v| v.is_finite()),
        prop::sample::select(edges.map(f64::from_bits).to_vec()),
    ]
}

type Outcome = Option<Result<[f64; 2], f64>>;

/// The bits of every number of the outcomes, and which slot each came from.
fn bits(results: &[Outcome]) -> Vec<(usize, char, u64)> {
    let mut out = Vec::new();
    for (i, r) in results.iter().enumerate() {
        match r {
            Some(Ok([a, b])) => {
                out.push((i, 'o', a.to_bits()));
                out.push((i, 'o', b.to_bits()));
            }
            Some(Err(e)) => out.push((i, 'e', e.to_bits())),
            None => out.push((i, '-', 0)),
        }
    }
    out
}

proptest! {
    #![proptest_config(crate::rng::proptest_cases(64))]

    /// Points, results and errors of random f64s pass through the folder bit for bit: as
    /// computed (each outcome is read back from its record before it is returned), as read by
    /// a restart, and as loaded from the folder.
    #[test]
    fn every_f64_survives_its_record_bit_for_bit(values in prop::collection::vec(finite(), 1..24)) {
        let dir = temp_dir("f64");
        // Odd bit patterns fail, so errors carry numbers too.
        let runner = |x: &f64| {
            if x.to_bits() % 2 == 1 { Err(-x) } else { Ok([*x, -x]) }
        };
        let expected: Vec<Outcome> = values.iter().map(|x| Some(runner(x))).collect();
        let one = RunOptions::default().with_threads(1);
        let store = SweepStore::open(&dir, "records", &(), &values).unwrap();
        let first = run_points(&values, Some(&store), &one, runner, None).unwrap();
        prop_assert_eq!(first.computed, values.len());
        prop_assert_eq!(bits(&first.results), bits(&expected));
        // A restart reads every point from the folder (the points' fingerprint matches).
        let store = SweepStore::open(&dir, "records", &(), &values).unwrap();
        let second = run_points(&values, Some(&store), &one, runner, None).unwrap();
        prop_assert_eq!((second.reused, second.computed), (values.len(), 0));
        prop_assert_eq!(bits(&second.results), bits(&expected));
        let loaded = store.load::<[f64; 2], f64>().unwrap();
        prop_assert_eq!(bits(&loaded.results), bits(&expected));
        fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn an_outcome_that_does_not_read_back_is_not_written() {
    // JSON has no NaN or infinity: serde_json writes them as null, not an f64.
    for (name, bad) in [("nan", f64::NAN), ("inf", f64::INFINITY)] {
        let dir = temp_dir(name);
        let points = [1.0, 2.0, 3.0];
        let store = SweepStore::open(&dir, "records", &(), &points).unwrap();
        let runner = |x: &f64| Ok::<f64, String>(if *x == 2.0 { bad } else { *x });
        let one = RunOptions::default().with_threads(1);
        let err = run_points(&points, Some(&store), &one, runner, None).unwrap_err();
        assert!(
            matches!(err, StoreError::RoundTrip { index: 1, .. }),
            "{err:?}"
        );
        assert!(err.to_string().contains("NaN or infinity"), "{err}");
        // The point before it is recorded, it is not (a restart would not read a bad line).
        let loaded = store.load::<f64, String>().unwrap();
        assert_eq!(loaded.results, vec![Some(Ok(1.0)), None, None]);
        fs::remove_dir_all(&dir).unwrap();
    }
}

#[test]
fn an_outcome_written_as_null_reads_back() {
    // `"ok": null` (an `Option` that is `None`) is an outcome, not a missing key.
    let dir = temp_dir("null");
    let points = [-1.0, 2.0];
    let store = SweepStore::open(&dir, "records", &(), &points).unwrap();
    let runner = |x: &f64| Ok::<Option<f64>, String>((*x > 0.0).then_some(*x));
    let one = RunOptions::default().with_threads(1);
    let first = run_points(&points, Some(&store), &one, runner, None).unwrap();
    assert_eq!(first.results, vec![Some(Ok(None)), Some(Ok(Some(2.0)))]);
    let again = run_points(&points, Some(&store), &one, runner, None).unwrap();
    assert_eq!((again.reused, again.results), (2, first.results));
    fs::remove_dir_all(&dir).unwrap();
}
