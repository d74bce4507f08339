//! Sweeps split across MPI ranks (feature `mpi`, through the `mpi` crate, rsmpi).
//!
//! Every rank calls the same function with the same points; rank 0 reads the sweep's folder,
//! decides which points are still to run and sends the list to all; rank `r` of `n` runs the
//! points `r, r + n, r + 2n, …` of that list (the rule of [`super::Shard`]; on its own
//! threads, [`RunOptions::threads`]),
//! appending each outcome to its own file `records-<r>.jsonl` as it finishes; at the end the
//! record lines are gathered on rank 0, which returns every point's outcome. Other ranks get
//! `None`.
//!
//! # Guarantees
//!
//! * **Bitwise identical to one process.** Each outcome is the runner at its point and nothing
//!   else, passed through its record exactly as in [`super::run_points`]: the outcomes on rank
//!   0 are bitwise those of a single-process run, for any number of ranks and threads.
//! * **Restart.** Killed, and started again with the same folder (with any number of ranks),
//!   a sweep runs only the points not recorded. Rank 0 decides from what it sees in the
//!   folder: put the folder on a file system all ranks share (home or scratch on a cluster).
//!   Without one the result is still complete and identical (the records are gathered over
//!   MPI), but a restart runs again the points whose records rank 0 cannot see.
//! * **Errors are collective.** A failure on any rank (a folder that cannot be written,
//!   ranks called with different points) makes every rank return an error instead of
//!   waiting forever; the records written before it stay.
//!
//! The record lines of one run are gathered as bytes with 32-bit counts: at most 2 GiB per
//! run (about five million points of [`super::scan_grid`]); split larger sweeps with
//! [`RunOptions::max_new_points`].
//!
//! # Running
//!
//! `cargo build --release --features mpi --example basins`, then
//! `mpirun -np 4 target/release/examples/basins ...` (OpenMPI as root needs
//! `--allow-run-as-root`; more ranks than cores need `--oversubscribe`), or under Slurm
//! `srun -n 64 target/release/examples/basins ...`. See `docs/global.md`.

use std::path::Path;

use mpi::collective::SystemOperation;
use mpi::datatype::PartitionMut;
use mpi::traits::*;
use mpi::Count;
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, OVector};

use super::attractor::AttractorOptions;
use super::failure::PointFailure;
use super::record::Record;
use super::runner::{check_points, compute, Computed, PointResults, RunOptions, Shard};
use super::scan::{attractor_at, check_settings, Grid2, GridScan};
use super::store::{decode_line, fingerprint, Manifest, StoreError, SweepStore};
use crate::analysis::Progress;
use crate::hybrid::RotorModel;

/// Whether every rank succeeded; if not, which error this rank returns.
fn agree<C: Communicator, T>(
    comm: &C,
    local: Result<T, StoreError>,
    what: &str,
) -> Result<T, StoreError> {
    let mine: i32 = i32::from(local.is_err());
    let mut any: i32 = 0;
    comm.all_reduce_into(&mine, &mut any, SystemOperation::max());
    match local {
        Err(e) => Err(e),
        Ok(_) if any != 0 => Err(StoreError::Mpi(format!(
            "another rank failed {what}; see its message"
        ))),
        Ok(v) => Ok(v),
    }
}

/// [`SweepStore::open_manifest`] on every rank: rank 0 creates or checks the folder first,
/// then the others check it. Collective: call it on every rank. A scan's manifest is
/// [`Manifest::scan`] (the grid and its settings), another computation's [`Manifest::new`].
///
/// # Errors
/// As [`SweepStore::open_manifest`], on every rank if any rank failed.
pub fn open_store<C: Communicator>(
    comm: &C,
    dir: impl AsRef<Path>,
    manifest: Manifest,
) -> Result<SweepStore, StoreError> {
    let root = comm.rank() == 0;
    let first = if root {
        SweepStore::open_manifest(&dir, manifest.clone()).map(Some)
    } else {
        Ok(None)
    };
    let first = agree(comm, first, "to open the folder")?;
    let store = match first {
        Some(s) => Ok(s),
        None => SweepStore::open_manifest(&dir, manifest),
    };
    agree(comm, store, "to open the folder")
}

/// Broadcasts a vector of `u64` from rank 0.
fn broadcast_u64s<C: Communicator>(comm: &C, data: &mut Vec<u64>) {
    let root = comm.process_at_rank(0);
    let mut len = data.len() as u64;
    root.broadcast_into(&mut len);
    data.resize(len as usize, 0);
    root.broadcast_into(&mut data[..]);
}

/// [`super::run_points`] split across the ranks of `comm` (see the [module docs](self)).
/// Collective: call it on every rank with the same points, store folder and runner.
/// Returns the outcomes on rank 0, `None` on the others.
///
/// # Errors
/// As [`super::run_points`], on every rank if any rank failed; [`StoreError::Mpi`] if the
/// ranks were given different points, a [`RunOptions::shard`] (the ranks split the whole
/// sweep), or the records exceed 2 GiB.
pub fn run_points<C, P, T, E, F>(
    comm: &C,
    points: &[P],
    store: Option<&SweepStore>,
    config: &RunOptions,
    runner: F,
    progress: Option<&dyn Progress>,
) -> Result<Option<PointResults<T, E>>, StoreError>
where
    C: Communicator,
    P: Record + Sync,
    T: Record + Send,
    E: Record + Send,
    F: Fn(&P) -> Result<T, E> + Sync,
{
    let rank = comm.rank() as usize;
    let size = comm.size() as usize;
    if let Some(shard) = config.shard {
        return Err(StoreError::Mpi(format!(
            "shard {shard} given to an MPI run: the ranks split the whole sweep; run one shard per process without MPI, or the whole sweep with MPI"
        )));
    }
    check_same_points(comm, points, store)?;
    let (mut results, duplicates, todo) = what_is_left::<C, T, E>(comm, points.len(), store)?;
    // The shard rule: rank r of n takes positions r, r + n, … of the list.
    let mine: Vec<usize> = Shard::new(rank, size)?
        .take(&todo)
        .map(|&i| i as usize)
        .collect();
    let reused = points.len() - todo.len();

    // Each rank runs its share and writes its own file.
    let local = store
        .map(|s| s.writer(rank))
        .transpose()
        .and_then(|w| compute(points, &mine, w, config, &runner, progress));
    let (records, threads) = agree(comm, local, "while running its points")?;

    let Some(text) = gather_records(comm, &records)? else {
        return Ok(None);
    };
    let computed = fill_from_records(&text, &mut results)?;
    Ok(Some(PointResults {
        results,
        reused,
        computed,
        duplicates,
        threads,
    }))
}

/// Checks (collectively) that every rank was given the points of rank 0 and that they fit
/// the store.
fn check_same_points<C: Communicator, P: Record>(
    comm: &C,
    points: &[P],
    store: Option<&SweepStore>,
) -> Result<(), StoreError> {
    let rank = comm.rank();
    let fingerprint = agree(comm, fingerprint(points), "to write its points")?;
    let mut check = vec![points.len() as u64, fingerprint];
    broadcast_u64s(comm, &mut check);
    let same = if check == [points.len() as u64, fingerprint] {
        check_points(points, store)
    } else {
        Err(StoreError::Mpi(format!(
            "rank {rank} was given other points than rank 0 ({} points, fingerprint {fingerprint:016x}; rank 0: {} points, {:016x})",
            points.len(), check[0], check.get(1).copied().unwrap_or(0)
        )))
    };
    agree(comm, same, "the check of the points")
}

/// The outcomes recorded in the folder and the duplicates found there (as rank 0 reads them;
/// none on the other ranks), and the indices still to run (broadcast from rank 0).
type Left<T, E> = (Vec<Option<Result<T, E>>>, usize, Vec<u64>);

/// Rank 0 reads the folder and says what is left to do (collective).
fn what_is_left<C, T, E>(
    comm: &C,
    n: usize,
    store: Option<&SweepStore>,
) -> Result<Left<T, E>, StoreError>
where
    C: Communicator,
    T: Record,
    E: Record,
{
    let root = comm.rank() == 0;
    let loaded = match (root, store) {
        (true, Some(s)) => s.load::<T, E>().map(Some),
        _ => Ok(None),
    };
    let loaded = agree(comm, loaded, "to read the folder")?;
    let (results, duplicates) = match loaded {
        Some(l) => (l.results, l.duplicates),
        None => ((0..n).map(|_| None).collect(), 0),
    };
    let mut todo: Vec<u64> = if root {
        (0..n)
            .filter(|&i| results[i].is_none())
            .map(|i| i as u64)
            .collect()
    } else {
        Vec::new()
    };
    broadcast_u64s(comm, &mut todo);
    Ok((results, duplicates, todo))
}

/// Gathers the record lines of every rank on rank 0 (collective): their text there, `None`
/// on the other ranks.
fn gather_records<C: Communicator, T, E>(
    comm: &C,
    records: &[Computed<T, E>],
) -> Result<Option<String>, StoreError> {
    let mut bytes = Vec::new();
    for r in records {
        bytes.extend_from_slice(r.line.as_bytes());
        bytes.push(b'\n');
    }
    // One gather carries at most `Count::MAX` bytes in all: check on every rank first.
    let mine_len = bytes.len() as u64;
    let mut total: u64 = 0;
    comm.all_reduce_into(&mine_len, &mut total, SystemOperation::sum());
    let count = Count::try_from(bytes.len())
        .ok()
        .filter(|_| total <= Count::MAX as u64);
    let Some(count) = count else {
        return Err(StoreError::Mpi(format!(
            "{total} bytes of records in one run: more than one gather can carry (2 GiB); the records are in the folder: split the run with RunOptions::max_new_points"
        )));
    };
    let root_process = comm.process_at_rank(0);
    if comm.rank() != 0 {
        root_process.gather_into(&count);
        root_process.gather_varcount_into(&bytes[..]);
        return Ok(None);
    }
    let mut counts: Vec<Count> = vec![0; comm.size() as usize];
    root_process.gather_into_root(&count, &mut counts[..]);
    let mut displs: Vec<Count> = Vec::with_capacity(counts.len());
    let mut acc: Count = 0;
    for &c in &counts {
        displs.push(acc);
        acc += c; // the sum is at most `total <= Count::MAX`
    }
    let mut all = vec![0u8; total as usize];
    {
        let mut partition = PartitionMut::new(&mut all[..], &counts[..], &displs[..]);
        root_process.gather_varcount_into_root(&bytes[..], &mut partition);
    }
    String::from_utf8(all)
        .map(Some)
        .map_err(|_| StoreError::Mpi("the gathered records are not UTF-8 text".into()))
}

/// Puts each gathered record line's outcome in its empty slot of `results`; returns how many.
fn fill_from_records<T: Record, E: Record>(
    text: &str,
    results: &mut [Option<Result<T, E>>],
) -> Result<usize, StoreError> {
    let mut computed = 0;
    for (k, line) in text.lines().enumerate() {
        let (i, outcome) = decode_line::<T, E>(line).map_err(|message| StoreError::Corrupt {
            path: "<records gathered from the ranks>".into(),
            line: k + 1,
            message,
        })?;
        match results.get_mut(i) {
            Some(slot @ None) => {
                *slot = Some(outcome);
                computed += 1;
            }
            _ => {
                return Err(StoreError::Mpi(format!(
                    "point {i} was returned twice or is not a point of the sweep"
                )))
            }
        }
    }
    Ok(computed)
}

/// [`super::scan_grid`] split across the ranks of `comm`. Collective; the scan is returned on
/// rank 0, `None` on the others. The folder is opened with [`Manifest::scan`].
///
/// # Errors
/// As [`run_points`] and [`super::scan_grid`] (a folder of other settings is refused on every
/// rank).
pub fn scan_grid<C, M, S>(
    comm: &C,
    grid: &Grid2,
    setup: S,
    config: &AttractorOptions,
    store: Option<&SweepStore>,
    run: &RunOptions,
    progress: Option<&dyn Progress>,
) -> Result<Option<GridScan>, StoreError>
where
    C: Communicator,
    M: RotorModel,
    S: Fn(&[f64; 2]) -> Result<(M, OVector<f64, M::Dim>), PointFailure> + Sync,
    DefaultAllocator: Allocator<M::Dim>,
{
    agree(
        comm,
        check_settings(store, config),
        "the check of the settings",
    )?;
    let points = grid.points();
    let results = run_points(
        comm,
        &points,
        store,
        run,
        |p| attractor_at(&setup, p, config),
        progress,
    )?;
    Ok(results.map(|results| GridScan {
        grid: grid.clone(),
        results,
    }))
}
