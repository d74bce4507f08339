use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use rayon::prelude::*;

use super::record::Record;
use super::store::{
    decode_line, encode_line, fingerprint, RecordWriter, StoreError, SweepStore, MANIFEST_FILE,
};
use crate::analysis::{on_pool, Progress};

/// One part `index` of `count` of a sweep, run by its own process (e.g. the task
/// `$SLURM_ARRAY_TASK_ID` of a job array of `count` tasks): the points at positions `index`,
/// `index + count`, `index + 2 count`, … of the list, the rule that splits a sweep's points
/// across MPI ranks (module `distributed`). Written `index/count` (`"2/8"`, [`str::parse`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Shard {
    index: usize,
    count: usize,
}

impl Shard {
    /// The shard `index` of `count` (numbered from 0).
    ///
    /// # Errors
    /// [`StoreError::InvalidShard`] naming the field: `count` 0, or `index ≥ count`.
    pub fn new(index: usize, count: usize) -> Result<Self, StoreError> {
        let field = if count == 0 {
            "count"
        } else if index >= count {
            "index"
        } else {
            return Ok(Shard { index, count });
        };
        Err(StoreError::InvalidShard {
            field,
            index,
            count,
        })
    }

    /// The shard's index, in `0..count`.
    pub fn index(&self) -> usize {
        self.index
    }

    /// The number of shards.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Whether the point at position `position` of a list is this shard's.
    pub fn owns(&self, position: usize) -> bool {
        position % self.count == self.index
    }

    /// This shard's items of `list`: those at positions `index`, `index + count`, ….
    pub fn take<T>(self, list: &[T]) -> impl Iterator<Item = &T> {
        list.iter().skip(self.index).step_by(self.count)
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl std::str::FromStr for Shard {
    type Err = StoreError;

    /// Parses `index/count`, e.g. `"2/8"`.
    fn from_str(text: &str) -> Result<Self, StoreError> {
        let syntax = || StoreError::ShardSyntax {
            text: text.to_string(),
        };
        let (i, n) = text.trim().split_once('/').ok_or_else(syntax)?;
        let i: usize = i.trim().parse().map_err(|_| syntax())?;
        let n: usize = n.trim().parse().map_err(|_| syntax())?;
        Shard::new(i, n)
    }
}

/// Written as its text `index/count`, read back through [`str::parse`] (so a shard read from a
/// file is validated like one given on a command line).
#[cfg(feature = "serde")]
impl serde::Serialize for Shard {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.collect_str(self)
    }
}

#[cfg(feature = "serde")]
impl<'de> serde::Deserialize<'de> for Shard {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        let text = <String as serde::Deserialize>::deserialize(deserializer)?;
        text.parse().map_err(serde::de::Error::custom)
    }
}

/// Settings of [`run_points`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct RunOptions {
    /// Worker threads: `None` (default) uses rayon's global pool (all cores, or
    /// `RAYON_NUM_THREADS`), `Some(n)` a dedicated pool of `n ≥ 1`. Results do not depend on it.
    pub threads: Option<usize>,
    /// Start at most this many points in this run (default: no limit).
    pub max_new_points: Option<usize>,
    /// Start no new point after this much wall time (default: no limit); points already
    /// started finish.
    pub time_budget: Option<Duration>,
    /// Run only this shard's points, written to its own file in the folder (default: all
    /// points). See [`Shard`].
    pub shard: Option<Shard>,
}

impl RunOptions {
    /// The same settings with a dedicated pool of `threads` worker threads.
    pub fn with_threads(self, threads: usize) -> Self {
        RunOptions {
            threads: Some(threads),
            ..self
        }
    }

    /// The same settings starting at most `n` new points.
    pub fn with_max_new_points(self, n: usize) -> Self {
        RunOptions {
            max_new_points: Some(n),
            ..self
        }
    }

    /// The same settings running only the points of `shard`.
    pub fn with_shard(self, shard: Shard) -> Self {
        RunOptions {
            shard: Some(shard),
            ..self
        }
    }

    /// The same settings starting no new point after `budget`.
    pub fn with_time_budget(self, budget: Duration) -> Self {
        RunOptions {
            time_budget: Some(budget),
            ..self
        }
    }
}

/// The outcomes of a [`run_points`], in point order.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct PointResults<T, E> {
    /// One slot per point: its outcome, or `None` if it has not been run (a partial run).
    pub results: Vec<Option<Result<T, E>>>,
    /// Points whose outcome was read from the folder (done by an earlier run).
    pub reused: usize,
    /// Points computed by this run.
    pub computed: usize,
    /// Points found recorded more than once in the folder (the first record is used).
    pub duplicates: usize,
    /// Worker threads per process (does not affect the results).
    pub threads: usize,
}

impl<T, E> PointResults<T, E> {
    /// Whether every point has an outcome.
    pub fn is_complete(&self) -> bool {
        self.results.iter().all(Option::is_some)
    }

    /// Number of points not run yet.
    pub fn missing(&self) -> usize {
        self.results.iter().filter(|r| r.is_none()).count()
    }

    /// The failed points, as `(index, error)`, in point order.
    pub fn failures(&self) -> impl Iterator<Item = (usize, &E)> {
        self.results
            .iter()
            .enumerate()
            .filter_map(|(i, r)| match r {
                Some(Err(e)) => Some((i, e)),
                _ => None,
            })
    }

    /// The successful points, as `(index, output)`, in point order.
    pub fn successes(&self) -> impl Iterator<Item = (usize, &T)> {
        self.results
            .iter()
            .enumerate()
            .filter_map(|(i, r)| match r {
                Some(Ok(t)) => Some((i, t)),
                _ => None,
            })
    }
}

/// Runs `runner` on every point of `points` not yet recorded in `store`, and returns all
/// outcomes in point order (see the [module docs](super) for the guarantees). Without a
/// store nothing is written and every point is run. With [`RunOptions::shard`], only the
/// shard's points are run (written to the shard's file); the other points are those the
/// folder holds, `None` if it holds none.
///
/// `progress` is called after each point computed now, with `(done, total)` counting the
/// points of this run only (not those reused from the folder).
///
/// # Errors
/// [`StoreError`] for a folder that cannot be read or written, holds corrupt records, was
/// opened for other points ([`StoreError::Mismatch`]), or a bad configuration (0 threads). Runner errors are not errors of `run_points`: they are
/// outcomes. If writing fails part-way, no new point is started and the error is returned
/// (the points written stay in the folder).
///
/// # Example
///
/// ```
/// use jeffcott::global::{run_points, RunOptions, SweepStore};
///
/// let dir = std::env::temp_dir().join(format!("jeffcott-doc-run-points-{}", std::process::id()));
/// # let _ = std::fs::remove_dir_all(&dir);
/// let points: Vec<f64> = (0..20).map(|i| i as f64).collect();
/// let store = SweepStore::open(&dir, "squares", &(), &points)?;
/// let square = |x: &f64| if *x < 15.0 { Ok(x * x) } else { Err(format!("{x} too large")) };
/// // A first run stops after 8 points; the second does the other 12.
/// let config = RunOptions::default().with_threads(2);
/// let first = run_points(&points, Some(&store), &config.with_max_new_points(8), square, None)?;
/// assert_eq!((first.computed, first.missing()), (8, 12));
/// let second = run_points(&points, Some(&store), &config, square, None)?;
/// assert_eq!((second.reused, second.computed), (8, 12));
/// assert_eq!(second.results[3], Some(Ok(9.0)));
/// assert_eq!(second.failures().count(), 5);
/// # std::fs::remove_dir_all(&dir)?;
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn run_points<P, T, E, F>(
    points: &[P],
    store: Option<&SweepStore>,
    config: &RunOptions,
    runner: F,
    progress: Option<&dyn Progress>,
) -> Result<PointResults<T, E>, StoreError>
where
    P: Record + Sync,
    T: Record + Send,
    E: Record + Send,
    F: Fn(&P) -> Result<T, E> + Sync,
{
    check_points(points, store)?;
    let (mut results, duplicates) = match store {
        Some(s) => {
            let loaded = s.load::<T, E>()?;
            (loaded.results, loaded.duplicates)
        }
        None => ((0..points.len()).map(|_| None).collect(), 0),
    };
    let reused = results.iter().filter(|r| r.is_some()).count();
    let todo: Vec<usize> = (0..points.len())
        .filter(|&i| results[i].is_none() && config.shard.is_none_or(|s| s.owns(i)))
        .collect();
    let writer = match (store, config.shard) {
        (Some(s), Some(shard)) => Some(s.shard_writer(shard)?),
        (Some(s), None) => Some(s.writer(0)?),
        (None, _) => None,
    };
    let (records, threads) = compute(points, &todo, writer, config, &runner, progress)?;
    let computed = records.len();
    for r in records {
        results[r.index] = Some(r.outcome);
    }
    Ok(PointResults {
        results,
        reused,
        computed,
        duplicates,
        threads,
    })
}

/// Checks that `store` (if any) was opened for `points`: their number and their fingerprint
/// (a folder opened over one grid never receives another grid's results).
pub(crate) fn check_points<P: Record>(
    points: &[P],
    store: Option<&SweepStore>,
) -> Result<(), StoreError> {
    let Some(s) = store else { return Ok(()) };
    let m = s.manifest();
    let mismatch = |field, expected: String, found: String| StoreError::Mismatch {
        path: s.dir().join(MANIFEST_FILE),
        field,
        expected,
        found,
    };
    if m.points != points.len() {
        return Err(mismatch(
            "points",
            points.len().to_string(),
            m.points.to_string(),
        ));
    }
    let given = fingerprint(points)?;
    if m.fingerprint != given {
        return Err(mismatch(
            "fingerprint (the points)",
            format!("{given:016x}"),
            format!("{:016x}", m.fingerprint),
        ));
    }
    Ok(())
}

/// A point computed by this process: its record line and its outcome as read back from it.
pub(crate) struct Computed<T, E> {
    /// The point's index.
    pub(crate) index: usize,
    /// Its record line (without the line break).
    pub(crate) line: String,
    /// Its outcome, read back from `line`.
    pub(crate) outcome: Result<T, E>,
}

/// The record of point `index` and its outcome read back from it.
///
/// # Errors
/// [`StoreError::Encode`] if it cannot be written, [`StoreError::RoundTrip`] if it does not
/// read back.
fn record<P: Record, T: Record, E: Record>(
    index: usize,
    point: &P,
    outcome: &Result<T, E>,
) -> Result<Computed<T, E>, StoreError> {
    let line = encode_line(index, point, outcome)?;
    let round_trip = |message| StoreError::RoundTrip { index, message };
    let (i, outcome) = decode_line::<T, E>(&line).map_err(round_trip)?;
    if i != index {
        return Err(round_trip(format!("index {i} read back")));
    }
    Ok(Computed {
        index,
        line,
        outcome,
    })
}

/// Runs the points `todo` (indices into `points`) in parallel, appending each record line to
/// `writer` as it finishes (after reading it back: a record that does not read back is not
/// written, and stops the run); returns the points run, in `todo` order, and the number of
/// threads.
pub(crate) fn compute<P, T, E, F>(
    points: &[P],
    todo: &[usize],
    writer: Option<RecordWriter>,
    config: &RunOptions,
    runner: &F,
    progress: Option<&dyn Progress>,
) -> Result<(Vec<Computed<T, E>>, usize), StoreError>
where
    P: Record + Sync,
    T: Record + Send,
    E: Record + Send,
    F: Fn(&P) -> Result<T, E> + Sync,
{
    let total = config
        .max_new_points
        .map_or(todo.len(), |m| m.min(todo.len()));
    let deadline = config.time_budget.map(|d| Instant::now() + d);
    let started = AtomicUsize::new(0);
    let done = AtomicUsize::new(0);
    let stop = AtomicBool::new(false);
    let writer = writer.map(Mutex::new);
    let failure: Mutex<Option<StoreError>> = Mutex::new(None);
    let run_one = |&i: &usize| -> Option<Computed<T, E>> {
        if stop.load(Ordering::Acquire) {
            return None;
        }
        if started.fetch_add(1, Ordering::AcqRel) >= total {
            return None;
        }
        if deadline.is_some_and(|d| Instant::now() >= d) {
            stop.store(true, Ordering::Release);
            return None;
        }
        let written = record(i, &points[i], &runner(&points[i])).and_then(|r| match &writer {
            Some(w) => {
                let mut w = w.lock().unwrap_or_else(|p| p.into_inner());
                w.append(&r.line).map(|()| r)
            }
            None => Ok(r),
        });
        let r = match written {
            Ok(r) => r,
            Err(e) => {
                stop.store(true, Ordering::Release);
                failure
                    .lock()
                    .unwrap_or_else(|p| p.into_inner())
                    .get_or_insert(e);
                return None;
            }
        };
        let d = done.fetch_add(1, Ordering::AcqRel) + 1;
        if let Some(p) = progress {
            p.update(d, total);
        }
        Some(r)
    };
    let (records, threads) = on_pool(config.threads, || {
        todo.par_iter()
            .map(run_one)
            .collect::<Vec<Option<Computed<T, E>>>>()
    })?;
    if let Some(e) = failure.into_inner().unwrap_or_else(|p| p.into_inner()) {
        return Err(e);
    }
    Ok((records.into_iter().flatten().collect(), threads))
}
