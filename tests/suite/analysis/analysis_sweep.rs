//! The parameter sweep: determinism across thread counts, order, failures, progress.

use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Duration;

use jeffcott::analysis::{
    chunk_ranges, sweep, AnalysisError, Progress, StderrProgress, SweepOptions,
};

/// A chaotic "simulation": 2000 logistic-map steps from the carried state (or 0.3 after a
/// reset). Any change in the carried state or the order of operations changes the bits.
fn logistic(r: &f64, state: Option<f64>) -> Result<(Vec<f64>, f64), String> {
    let mut x = state.unwrap_or(0.3);
    let mut out = Vec::new();
    for k in 0..2000 {
        x = r * x * (1.0 - x);
        if k >= 1990 {
            out.push(x);
        }
    }
    Ok((out, x))
}

fn params() -> Vec<f64> {
    (0..97).map(|i| 2.8 + 1.2 * i as f64 / 96.0).collect()
}

fn bits(r: &[Result<Vec<f64>, String>]) -> Vec<Vec<u64>> {
    r.iter()
        .map(|v| v.as_ref().unwrap().iter().map(|x| x.to_bits()).collect())
        .collect()
}

#[test]
fn carry_over_is_bitwise_identical_for_one_and_two_threads() {
    let p = params();
    for chunks in [1, 3, 8, 200] {
        let one = sweep(
            &p,
            &SweepOptions::carry_over(chunks).with_threads(1),
            logistic,
            None,
        )
        .unwrap();
        let two = sweep(
            &p,
            &SweepOptions::carry_over(chunks).with_threads(2),
            logistic,
            None,
        )
        .unwrap();
        let global = sweep(&p, &SweepOptions::carry_over(chunks), logistic, None).unwrap();
        assert_eq!(one.threads, 1);
        assert_eq!(two.threads, 2);
        assert_eq!(bits(&one.results), bits(&two.results), "chunks = {chunks}");
        assert_eq!(
            bits(&one.results),
            bits(&global.results),
            "chunks = {chunks}"
        );
        assert_eq!(one.chains, chunk_ranges(p.len(), chunks).unwrap());
    }
}

#[test]
fn reset_is_bitwise_identical_for_one_and_two_threads() {
    let p = params();
    let one = sweep(&p, &SweepOptions::reset().with_threads(1), logistic, None).unwrap();
    let two = sweep(&p, &SweepOptions::reset().with_threads(2), logistic, None).unwrap();
    assert_eq!(bits(&one.results), bits(&two.results));
    // Each value on its own equals a direct call from the reset state.
    for (r, res) in p.iter().zip(&one.results) {
        assert_eq!(res.as_ref().unwrap(), &logistic(r, None).unwrap().0);
    }
}

#[test]
fn carry_over_hands_the_state_on_within_each_chunk() {
    // The state counts how many values the chain has run; the output is that count.
    let p: Vec<usize> = (0..10).collect();
    let runner = |_: &usize, s: Option<usize>| -> Result<(usize, usize), ()> {
        let n = s.map_or(1, |n| n + 1);
        Ok((n, n))
    };
    let out = sweep(
        &p,
        &SweepOptions::carry_over(3).with_threads(2),
        runner,
        None,
    )
    .unwrap();
    let got: Vec<usize> = out.results.into_iter().map(Result::unwrap).collect();
    // Chunks 0..4, 4..7, 7..10.
    assert_eq!(got, vec![1, 2, 3, 4, 1, 2, 3, 1, 2, 3]);
    let out = sweep(&p, &SweepOptions::reset(), runner, None).unwrap();
    assert!(out.results.iter().all(|r| *r == Ok(1)));
}

#[test]
fn results_come_back_in_parameter_order() {
    // Early values take longest, so they finish last.
    let p: Vec<u64> = (0..16).collect();
    let runner = |i: &u64, _: Option<()>| -> Result<(u64, ()), ()> {
        std::thread::sleep(Duration::from_millis(2 * (16 - i)));
        Ok((i * 10, ()))
    };
    for config in [SweepOptions::reset(), SweepOptions::carry_over(4)] {
        let out = sweep(&p, &config.with_threads(2), runner, None).unwrap();
        let got: Vec<u64> = out.results.into_iter().map(Result::unwrap).collect();
        assert_eq!(got, (0..16).map(|i| i * 10).collect::<Vec<_>>());
    }
}

#[test]
fn a_failure_is_recorded_and_the_rest_completes() {
    let p: Vec<usize> = (0..12).collect();
    let seen = Mutex::new(Vec::new());
    let runner = |i: &usize, s: Option<usize>| -> Result<(usize, usize), String> {
        seen.lock().unwrap().push((*i, s));
        if *i == 5 {
            return Err(format!("diverged at value {i}"));
        }
        let n = s.map_or(1, |n| n + 1);
        Ok((n, n))
    };
    // Chunks 0..6 and 6..12: the failure is the last value of the first chunk.
    let out = sweep(
        &p,
        &SweepOptions::carry_over(2).with_threads(2),
        runner,
        None,
    )
    .unwrap();
    assert_eq!(out.failure_count(), 1);
    let failures: Vec<(usize, &String)> = out.failures().collect();
    assert_eq!(failures, vec![(5, &"diverged at value 5".to_string())]);
    let ok: Vec<(usize, usize)> = out.successes().map(|(i, n)| (i, *n)).collect();
    assert_eq!(
        ok,
        vec![
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 4),
            (4, 5),
            (6, 1),
            (7, 2),
            (8, 3),
            (9, 4),
            (10, 5),
            (11, 6)
        ]
    );
    // One chain: the failure is mid-chain, and the next value restarts from the reset state.
    seen.lock().unwrap().clear();
    let out = sweep(
        &p,
        &SweepOptions::carry_over(1).with_threads(2),
        runner,
        None,
    )
    .unwrap();
    let got: Vec<Result<usize, String>> = out.results;
    assert_eq!(got[4], Ok(5));
    assert!(got[5].is_err());
    assert_eq!(
        got[6],
        Ok(1),
        "the value after a failure restarts from the reset state"
    );
    assert_eq!(got[11], Ok(6));
    let seen = seen.lock().unwrap().clone();
    assert!(seen.contains(&(5, Some(5))));
    assert!(seen.contains(&(6, None)));
    // Reset mode: the same single failure.
    let out = sweep(&p, &SweepOptions::reset().with_threads(2), runner, None).unwrap();
    assert_eq!(out.failures().map(|(i, _)| i).collect::<Vec<_>>(), vec![5]);
    assert_eq!(out.successes().count(), 11);
}

#[derive(Default)]
struct Counter {
    calls: AtomicUsize,
    seen: Mutex<Vec<usize>>,
}

impl Progress for Counter {
    fn update(&self, done: usize, total: usize) {
        assert_eq!(total, 40);
        self.calls.fetch_add(1, Ordering::Relaxed);
        self.seen.lock().unwrap().push(done);
    }
}

#[test]
fn progress_is_called_once_per_value() {
    let p = params()[..40].to_vec();
    for config in [SweepOptions::reset(), SweepOptions::carry_over(5)] {
        let counter = Counter::default();
        sweep(&p, &config.with_threads(2), logistic, Some(&counter)).unwrap();
        assert_eq!(counter.calls.load(Ordering::Relaxed), 40);
        let mut seen = counter.seen.into_inner().unwrap();
        seen.sort_unstable();
        assert_eq!(seen, (1..=40).collect::<Vec<_>>());
    }
    // A closure observer.
    let calls = AtomicUsize::new(0);
    let count = |_: usize, _: usize| {
        calls.fetch_add(1, Ordering::Relaxed);
    };
    sweep(
        &p,
        &SweepOptions::carry_over(3).with_threads(2),
        logistic,
        Some(&count),
    )
    .unwrap();
    assert_eq!(calls.load(Ordering::Relaxed), 40);
    // The no-op observer and the stderr line from two threads.
    sweep(
        &p,
        &SweepOptions::reset().with_threads(2),
        logistic,
        Some(&()),
    )
    .unwrap();
    let bar = StderrProgress::new("test sweep").with_interval(Duration::from_millis(1));
    sweep(
        &p,
        &SweepOptions::reset().with_threads(2),
        logistic,
        Some(&bar),
    )
    .unwrap();
}

#[test]
fn bad_configuration_is_a_typed_error() {
    let p = params();
    assert!(matches!(
        sweep(&p, &SweepOptions::carry_over(0), logistic, None),
        Err(AnalysisError::InvalidCount {
            name: "chunks",
            value: 0,
            ..
        })
    ));
    assert!(matches!(
        sweep(&p, &SweepOptions::reset().with_threads(0), logistic, None),
        Err(AnalysisError::InvalidCount {
            name: "threads",
            value: 0,
            ..
        })
    ));
    let empty: [f64; 0] = [];
    let out = sweep(&empty, &SweepOptions::carry_over(4), logistic, None).unwrap();
    assert!(out.results.is_empty() && out.chains.is_empty());
}

#[test]
fn chunk_ranges_cover_the_list() {
    for len in 0..30 {
        for chunks in 1..12 {
            let r = chunk_ranges(len, chunks).unwrap();
            assert_eq!(r.len(), chunks.min(len));
            let mut next = 0;
            for range in &r {
                assert_eq!(range.start, next);
                assert!(!range.is_empty());
                next = range.end;
            }
            assert_eq!(next, len);
            let sizes: Vec<usize> = r.iter().map(|x| x.len()).collect();
            if let (Some(max), Some(min)) = (sizes.iter().max(), sizes.iter().min()) {
                assert!(max - min <= 1);
            }
        }
    }
    assert!(chunk_ranges(5, 0).is_err());
}
