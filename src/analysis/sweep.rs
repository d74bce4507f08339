use std::io::{IsTerminal, Write};
use std::ops::Range;
use std::sync::atomic::{AtomicBool, AtomicU64, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use super::AnalysisError;

/// How successive parameter values are linked. See the [module docs](super).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum SweepMode {
    /// Every value starts from the reset state; values run in parallel.
    Reset,
    /// The final state of each value seeds the next, within `chunks` contiguous chunks that each
    /// start from the reset state and run in parallel.
    CarryOver {
        /// Number of contiguous chunks (at least 1). If larger than the number of values, each
        /// value is its own chunk.
        chunks: usize,
    },
}

/// Settings of a [`sweep`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct SweepOptions {
    /// How successive values are linked. Default: [`SweepMode::Reset`].
    pub mode: SweepMode,
    /// Number of worker threads. `None` (default) uses rayon's global pool (all cores, or
    /// `RAYON_NUM_THREADS`); `Some(n)` builds a dedicated pool of `n ≥ 1` threads for this sweep.
    /// The results do not depend on it.
    pub threads: Option<usize>,
}

/// Builders: each returns the options with one field changed.
impl SweepOptions {
    /// With [`mode`](Self::mode) = `value`.
    #[must_use]
    pub fn with_mode(mut self, value: SweepMode) -> Self {
        self.mode = value;
        self
    }
}

impl Default for SweepOptions {
    fn default() -> Self {
        SweepOptions {
            mode: SweepMode::Reset,
            threads: None,
        }
    }
}

impl SweepOptions {
    /// Independent values ([`SweepMode::Reset`]) on the global pool.
    pub fn reset() -> Self {
        SweepOptions::default()
    }

    /// Carried-over state ([`SweepMode::CarryOver`]) in `chunks` chunks, on the global pool.
    pub fn carry_over(chunks: usize) -> Self {
        SweepOptions {
            mode: SweepMode::CarryOver { chunks },
            threads: None,
        }
    }

    /// The same settings with a dedicated pool of `threads` worker threads.
    pub fn with_threads(self, threads: usize) -> Self {
        SweepOptions {
            threads: Some(threads),
            ..self
        }
    }
}

/// The results of a [`sweep`], in parameter order.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct SweepResult<T, E> {
    /// One entry per parameter value, in the order of the parameter list.
    pub results: Vec<Result<T, E>>,
    /// The index ranges of the chains that were run: one per value in reset mode, the
    /// [`chunk_ranges`] in carry-over mode. A chain restarts after a failure (not listed here).
    pub chains: Vec<Range<usize>>,
    /// Number of worker threads the sweep ran on (does not affect the results).
    pub threads: usize,
}

impl<T, E> SweepResult<T, E> {
    /// Number of values whose runner failed.
    pub fn failure_count(&self) -> usize {
        self.results.iter().filter(|r| r.is_err()).count()
    }

    /// The failed values, as `(index, error)` pairs in parameter order.
    pub fn failures(&self) -> impl Iterator<Item = (usize, &E)> {
        self.results
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.as_ref().err().map(|e| (i, e)))
    }

    /// The successful values, as `(index, output)` pairs in parameter order.
    pub fn successes(&self) -> impl Iterator<Item = (usize, &T)> {
        self.results
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.as_ref().ok().map(|t| (i, t)))
    }
}

/// Observer of a long computation's progress, and its stop button. Object-safe; `()` does
/// nothing and never stops.
///
/// A sweep calls it concurrently from the worker threads, hence `Sync`. The long single
/// computations
/// ([`lyapunov_exponents_with_progress`](crate::stability::lyapunov_exponents_with_progress),
/// [`continue_orbit_with_progress`](crate::stability::continue_orbit_with_progress)) call it
/// from their own thread after each unit of work, and ask [`should_stop`](Self::should_stop)
/// between units: a caller's Ctrl-C or time limit ends them there, with what they computed.
pub trait Progress: Sync {
    /// Called once after each unit of work (a sweep's value, successfully or not), with the
    /// number of units finished so far and the total. In a sweep each `done` in `1..=total` is
    /// reported once, in no guaranteed order.
    fn update(&self, done: usize, total: usize);

    /// Whether the computation should stop now. Asked between units of work by the long
    /// single computations (not by the sweeps); default `false`, never.
    fn should_stop(&self) -> bool {
        false
    }
}

impl Progress for () {
    fn update(&self, _done: usize, _total: usize) {}
}

/// Any `Fn(done, total)` closure is an observer.
impl<F: Fn(usize, usize) + Sync> Progress for F {
    fn update(&self, done: usize, total: usize) {
        self(done, total)
    }
}

/// A progress line on standard error: `label: 37/150 (24.7 %), 3.2 s elapsed, ~10 s left`.
///
/// Prints at most once per `interval` (default 0.5 s), plus always when the last value
/// finishes. On a terminal the line rewrites itself (`\r`); otherwise each update is a new
/// line. Safe to call from many threads: the throttle is a lock-free atomic.
#[derive(Debug)]
pub struct StderrProgress {
    label: String,
    start: Instant,
    interval: Duration,
    /// Milliseconds since `start` of the last print, plus 1 (0 = never printed).
    last_print_ms: AtomicU64,
    finished: AtomicBool,
    terminal: bool,
}

impl StderrProgress {
    /// A progress line with the given label, printing at most every 0.5 s.
    pub fn new(label: impl Into<String>) -> Self {
        StderrProgress {
            label: label.into(),
            start: Instant::now(),
            interval: Duration::from_millis(500),
            last_print_ms: AtomicU64::new(0),
            finished: AtomicBool::new(false),
            terminal: std::io::stderr().is_terminal(),
        }
    }

    /// The same line, printing at most once per `interval`.
    pub fn with_interval(self, interval: Duration) -> Self {
        StderrProgress { interval, ..self }
    }

    fn line(&self, done: usize, total: usize, elapsed: f64) -> String {
        let pct = if total == 0 {
            100.0
        } else {
            100.0 * done as f64 / total as f64
        };
        let mut s = format!(
            "{}: {done}/{total} ({pct:.1} %), {elapsed:.1} s elapsed",
            self.label
        );
        if done > 0 && done < total && elapsed >= 1.0 {
            let left = elapsed * (total - done) as f64 / done as f64;
            s.push_str(&format!(", ~{left:.0} s left"));
        }
        s
    }
}

impl Progress for StderrProgress {
    fn update(&self, done: usize, total: usize) {
        let elapsed = self.start.elapsed();
        let last = done >= total;
        if last {
            if self.finished.swap(true, Ordering::AcqRel) {
                return;
            }
        } else {
            let now = u64::try_from(elapsed.as_millis())
                .unwrap_or(u64::MAX - 1)
                .saturating_add(1);
            let prev = self.last_print_ms.load(Ordering::Acquire);
            let gap = u64::try_from(self.interval.as_millis()).unwrap_or(u64::MAX);
            if prev != 0 && now.saturating_sub(prev) < gap {
                return;
            }
            // Only the thread that wins the exchange prints.
            if self
                .last_print_ms
                .compare_exchange(prev, now, Ordering::AcqRel, Ordering::Acquire)
                .is_err()
            {
                return;
            }
            if self.finished.load(Ordering::Acquire) {
                return;
            }
        }
        let text = self.line(done, total, elapsed.as_secs_f64());
        let out = if self.terminal {
            if last {
                format!("\r{text}\x1b[K\n")
            } else {
                format!("\r{text}\x1b[K")
            }
        } else {
            format!("{text}\n")
        };
        // Progress output is best effort: a closed stderr must not fail the sweep.
        let mut err = std::io::stderr().lock();
        let _ = err.write_all(out.as_bytes());
        let _ = err.flush();
    }
}

/// Splits `0..len` into `chunks` contiguous ranges whose lengths differ by at most one (the
/// longer ones first). If `chunks > len`, returns `len` ranges of one value; if `len` is 0,
/// returns no range. Depends only on `len` and `chunks`, never on the thread count.
///
/// # Errors
///
/// [`AnalysisError::InvalidCount`] if `chunks` is 0.
///
/// ```
/// use jeffcott::analysis::chunk_ranges;
/// assert_eq!(chunk_ranges(7, 3).unwrap(), vec![0..3, 3..5, 5..7]);
/// ```
pub fn chunk_ranges(len: usize, chunks: usize) -> Result<Vec<Range<usize>>, AnalysisError> {
    if chunks == 0 {
        return Err(AnalysisError::InvalidCount {
            name: "chunks",
            value: 0,
            expected: "at least 1",
        });
    }
    let n = chunks.min(len);
    if n == 0 {
        return Ok(Vec::new());
    }
    let base = len / n;
    let extra = len % n;
    let mut ranges = Vec::with_capacity(n);
    let mut start = 0;
    for k in 0..n {
        let size = base + usize::from(k < extra);
        ranges.push(start..start + size);
        start += size;
    }
    Ok(ranges)
}

/// Runs `runner` over `params` and returns the results in parameter order.
///
/// See the [module docs](super) for the runner's contract, the two modes, the determinism
/// guarantee and what happens on failure.
///
/// # Errors
///
/// Only for a bad configuration, before any value runs:
/// [`AnalysisError::InvalidCount`] if `chunks` or `threads` is 0, and
/// [`AnalysisError::ThreadPool`] if the dedicated pool cannot be built.
/// Runner errors are not errors of `sweep`: they are recorded in [`SweepResult::results`].
///
/// # Example
///
/// ```
/// use jeffcott::analysis::{sweep, SweepOptions};
/// // A "simulation" whose state is a running sum, carried from value to value.
/// let params = [1.0, 2.0, 3.0, 4.0];
/// let runner = |p: &f64, state: Option<f64>| -> Result<(f64, f64), String> {
///     let s = state.unwrap_or(0.0) + p;
///     Ok((s, s))
/// };
/// let out = sweep(&params, &SweepOptions::carry_over(2).with_threads(2), runner, None).unwrap();
/// let values: Vec<f64> = out.results.into_iter().map(Result::unwrap).collect();
/// assert_eq!(values, vec![1.0, 3.0, 3.0, 7.0]); // chunks [1, 2] and [3, 4]
/// ```
pub fn sweep<P, T, S, E, F>(
    params: &[P],
    config: &SweepOptions,
    runner: F,
    progress: Option<&dyn Progress>,
) -> Result<SweepResult<T, E>, AnalysisError>
where
    P: Sync,
    T: Send,
    S: Send,
    E: Send,
    F: Fn(&P, Option<S>) -> Result<(T, S), E> + Sync,
{
    let chains = match config.mode {
        SweepMode::Reset => (0..params.len()).map(|i| i..i + 1).collect(),
        SweepMode::CarryOver { chunks } => chunk_ranges(params.len(), chunks)?,
    };
    let total = params.len();
    let done = AtomicUsize::new(0);
    let run_chain = |range: &Range<usize>| -> Vec<Result<T, E>> {
        let mut state: Option<S> = None;
        let mut out = Vec::with_capacity(range.len());
        for p in &params[range.clone()] {
            match runner(p, state.take()) {
                Ok((t, s)) => {
                    out.push(Ok(t));
                    state = Some(s);
                }
                Err(e) => out.push(Err(e)),
            }
            let d = done.fetch_add(1, Ordering::AcqRel) + 1;
            if let Some(pr) = progress {
                pr.update(d, total);
            }
        }
        out
    };
    let run_all = || -> Vec<Result<T, E>> {
        let per_chain: Vec<Vec<Result<T, E>>> = chains.par_iter().map(run_chain).collect();
        per_chain.into_iter().flatten().collect()
    };
    let (results, threads) = on_pool(config.threads, run_all)?;
    Ok(SweepResult {
        results,
        chains,
        threads,
    })
}

/// Runs `f` on a dedicated pool of `threads` worker threads (`Some(n)`), or on rayon's global
/// pool (`None`), and returns its result with the number of threads it ran on: the crate's one
/// pool builder (the sweeps of [`analysis`](crate::analysis) and [`global`](crate::global)).
///
/// # Errors
/// [`AnalysisError::InvalidCount`] for `Some(0)`, [`AnalysisError::ThreadPool`] if the pool
/// cannot be built.
pub(crate) fn on_pool<R: Send>(
    threads: Option<usize>,
    f: impl FnOnce() -> R + Send,
) -> Result<(R, usize), AnalysisError> {
    match threads {
        None => Ok((f(), rayon::current_num_threads())),
        Some(0) => Err(AnalysisError::InvalidCount {
            name: "threads",
            value: 0,
            expected: "at least 1 (or None for the global pool)",
        }),
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n)
                .build()
                .map_err(|e| AnalysisError::ThreadPool {
                    threads: n,
                    message: e.to_string(),
                })?;
            Ok((pool.install(f), n))
        }
    }
}

/// `n` evenly spaced values from `lo` to `hi` inclusive, a parameter list for [`sweep`]: value
/// `i` is `lo + (hi − lo) · i / (n − 1)` (exactly `lo` and `hi` at the ends; `[lo]` if
/// `n = 1`).
///
/// # Errors
/// [`AnalysisError::InvalidValue`] for non-finite ends or a reversed range (`hi < lo`);
/// [`AnalysisError::InvalidCount`] for `n = 0`.
///
/// ```
/// use jeffcott::analysis::linspace;
/// assert_eq!(linspace(2.0, 3.0, 3).unwrap(), vec![2.0, 2.5, 3.0]);
/// assert!(linspace(3.0, 2.0, 3).is_err());
/// ```
pub fn linspace(lo: f64, hi: f64, n: usize) -> Result<Vec<f64>, AnalysisError> {
    if !lo.is_finite() {
        return Err(AnalysisError::InvalidValue {
            name: "lo",
            value: lo,
            expected: "a finite number",
        });
    }
    if !(hi.is_finite() && hi >= lo) {
        return Err(AnalysisError::InvalidValue {
            name: "hi",
            value: hi,
            expected: "a finite number >= lo",
        });
    }
    if n == 0 {
        return Err(AnalysisError::InvalidCount {
            name: "n",
            value: 0,
            expected: "at least 1",
        });
    }
    if n == 1 {
        return Ok(vec![lo]);
    }
    let last = (n - 1) as f64;
    Ok((0..n)
        .map(|i| {
            if i == n - 1 {
                hi
            } else {
                lo + (hi - lo) * (i as f64 / last)
            }
        })
        .collect())
}
