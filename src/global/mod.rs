//! Global dynamics: which attractors coexist, where their basins lie, how the dynamics change
//! over two parameters, and long sweeps that survive being killed and run on many processes.
//!
//! * [Attractors](#attractors): run a model until it settles, identify the attractor
//!   (period and a canonical periodic point, or "not periodic" with contact statistics), and
//!   match attractors reached from different starts ([`find_attractor`], [`Attractor`],
//!   [`MatchOptions`]).
//! * [Catalogues](#catalogues): the distinct attractors of a scan and the label of each point.
//! * The continuation of periodic orbits (pseudo-arclength, bifurcations, branch switching)
//!   is in [`crate::stability`] ([`crate::stability::continue_orbit`]).
//! * [Grid scans](#grid-scans): attractor scans over a grid ([`scan_grid`], [`Grid2`]): basins of attraction
//!   (a grid of initial states) and two-parameter maps (a grid of parameters). The paper's
//!   model has ready-made planes: [`crate::paper::BasinPlane`], [`crate::paper::ParamPlane`].
//! * [The runner](#the-runner): the engine under every scan: any computation over a list of points, in
//!   parallel, writing each outcome to a folder as it finishes, and skipping the points
//!   already there when restarted ([`run_points`], [`RunOptions`]), or only one [`Shard`] of
//!   them (a task of a job array, without MPI). Results are bitwise identical for any number
//!   of threads, across restarts, for any number of shards, and (feature `mpi`, module
//!   `distributed`) for any number of MPI ranks.
//! * [The store](#the-store): the folder (a manifest and records, one JSON object a line) and its rules for
//!   crashes ([`SweepStore`]); [records](#records) the format ([`Record`]: serde's JSON of the values).
//!
//! # Example: a resumable basin scan
//!
//! ```no_run
//! use jeffcott::analysis::StderrProgress;
//! use jeffcott::global::{scan_grid, AttractorOptions, Grid2, MatchOptions, RunOptions, SweepStore};
//! use jeffcott::paper::{BasinPlane, StartPlane};
//! use jeffcott::params::Preset;
//!
//! let plane = BasinPlane::new(Preset::Fig8a.params().with_eta(2.2), StartPlane::XVx);
//! let grid = Grid2::linspace((-1.0, 1.0, 200), (-1.5, 1.5, 200))?;
//! let config = AttractorOptions::default();
//! // The folder records the grid, every setting of `config` and the crate's version; the
//! // description (any `Serialize` value) adds what the scan cannot see: the model's parameters.
//! // Killed part-way? Run it again: the points in the folder are not run again (and a run
//! // with another grid, other settings or another description is refused).
//! let store = SweepStore::open_scan("out/basins-fig8a", "basins", &plane, &grid, &config)?;
//! let progress = StderrProgress::new("basins");
//! let scan = scan_grid(&grid, plane.setup(), &config, Some(&store), &RunOptions::default(), Some(&progress))?;
//! let catalogue = scan.catalogue(&MatchOptions::default());
//! for (k, e) in catalogue.entries.iter().enumerate() {
//!     println!("attractor {k}: {} ({} points)", e.attractor.describe(), e.count);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! # Attractors
//!
//! Which attractor a run settles on: its period, a canonical periodic point, and contact
//! statistics; and when two runs reached the same one.
//!
//! ## Identification
//!
//! [`find_attractor`] runs the model from its initial state at $t = 0$, discards
//! [`AttractorOptions::transient`] forcing periods, records [`AttractorOptions::record`]
//! stroboscopic points and tests them for a period ([`PeriodTest`](crate::analysis::PeriodTest)). If none is found (not
//! periodic, or not yet converged) the run
//! goes on from its last state for another `transient + record` periods, and again, until the
//! transients add up to [`AttractorOptions::max_transient`]: slowly attracting orbits (a
//! multiplier near the unit circle, close to a bifurcation) get the time they need, and
//! chaotic runs stop there. The forcing is periodic, so a run continued from its state at
//! $t = kP$ is restarted at $t = 0$ with the same forcing phase.
//!
//! * A **periodic** attractor of period $p$ is stored as its cycle: the last $p$ stroboscopic
//!   states, rotated to start at the **canonical point**, the one smallest in the
//!   lexicographic order of its components (compared with `f64::total_cmp`). Two runs that
//!   reach the same cycle from different initial states store it starting at the same point,
//!   up to the convergence of the runs.
//! * A **non-periodic** attractor (no period up to the test's bound: quasi-periodic, chaotic,
//!   or not converged within `max_transient`) is described by its statistics. A run whose
//!   last window passes the period test for some lag but is still converging (a stable orbit
//!   near a Neimark-Sacker or flip point, whose slowly shrinking transient nearly closes after
//!   a few periods) ends as [`Periodicity::NotConverged`](crate::analysis::Periodicity::NotConverged) with the residuals seen, never as a
//!   long cycle: see [period detection](crate::analysis#period-detection).
//!
//! Both carry [`OrbitStats`] over the recorded window: contacts per forcing period (onsets,
//! i.e. transitions out of the free-flight mode), the fraction of time in contact, the
//! occupancy of each mode (for the paper's model the regimes I-V), and the bounding box of the
//! recorded stroboscopic states.
//!
//! ## Matching
//!
//! [`Attractor::matches`] with a [`MatchOptions`]:
//!
//! * two periodic attractors match when their cycles, each first reduced to its shortest
//!   period **at the matching tolerance** (a cycle of period $2p$ whose halves agree to within
//!   `state` is compared as period $p$), have the same length and, for some cyclic shift,
//!   every component of every point agrees to within `state`;
//! * two non-periodic ones match when their contacts per period agree to within `contacts`
//!   and every side of their bounding boxes to within `extent`;
//! * a periodic attractor never matches a non-periodic one.
//!
//! `state` and `extent` are in units of the model's scale ([`RotorModel::state_scale`](crate::hybrid::RotorModel::state_scale), kept
//! in [`Attractor::scale`]): component $c$ agrees when $|a_c - b_c| \le$ `state` $\cdot
//! \max(s^a_c, s^b_c)$. The paper's model has scale 1 (its units: the gap); a model in SI
//! units gives its components' typical sizes, and the same tolerances mean the same there.
//! The period test runs in the same units ([`PeriodTest::detect_scaled`](crate::analysis::PeriodTest::detect_scaled)).
//!
//! # Catalogues
//!
//! The distinct attractors found over a scan, and which one each point reached.
//!
//! # Grid scans
//!
//! Attractor scans over a grid: basins of attraction (a grid of initial states) and
//! two-parameter maps (a grid of parameters).
//!
//! Both are the same computation: at each grid point a *setup* closure builds the model and
//! its initial state, [`find_attractor`] runs it, and the outcome is recorded
//! ([`run_points`]: parallel, resumable, deterministic). They differ in what the grid means
//! and how the outcomes are drawn:
//!
//! * **basins**: fixed parameters, the grid varies the initial state; the attractors are
//!   matched across points ([`GridScan::catalogue`]) and each point coloured by the one it
//!   reached;
//! * **parameter maps**: the grid varies two parameters, each run from the same initial state;
//!   each point coloured by its period ([`GridScan::periods`]) or its contacts per period
//!   ([`GridScan::contacts_per_period`]). Where attractors coexist, the map shows the one
//!   reached from that initial state.
//!
//! # The runner
//!
//! Running a computation over a list of points, in parallel, resumably.
//!
//! [`run_points`] calls `runner(&point)` once for each point not yet recorded in the sweep's
//! folder ([`SweepStore`]), on a pool of threads, writes each outcome to the folder as soon as
//! it is known, and returns every point's outcome (recorded earlier or computed now) in point
//! order.
//!
//! ## Guarantees
//!
//! * **Deterministic.** The points are independent: each outcome is `runner(&point)` and
//!   nothing else, so for a runner that is a deterministic function of its point, the
//!   outcomes are bitwise identical for any number of threads, any number of MPI ranks
//!   (module `distributed`, feature `mpi`), and across interruptions and
//!   restarts.
//! * **Every outcome passes through its record.** An outcome computed now is encoded and
//!   decoded back before it is written and returned, exactly as one read from the folder after
//!   a restart: a restarted run returns the same values as an uninterrupted one even if a
//!   [`Record`] encoding were lossy. An outcome that does not read back (a NaN written as
//!   `null`) is not written: the run stops with [`StoreError::RoundTrip`].
//! * **Failures are results.** A runner error is recorded (`"error"` in its line) and returned
//!   in its slot; it is not computed again on restart (delete its line to retry it). A panic
//!   inside the runner is a bug: it propagates, the records written so far stay.
//! * **Shards.** [`RunOptions::shard`] runs only the points of one [`Shard`] `i/n` (the points
//!   `i, i + n, i + 2n, …`) and writes them to the shard's own file in the folder: `n`
//!   independent processes (the tasks of a scheduler's job array) together run the whole
//!   sweep, without MPI and without file locking; a run without a shard then reads every
//!   point from the folder (and runs any a shard left undone). The outcomes are those of one
//!   run, bit for bit.
//! * **Partial runs.** [`RunOptions::max_new_points`] and [`RunOptions::time_budget`] stop
//!   starting new points (for a batch queue's time limit); the points not run are `None` and
//!   a later run with the same folder does them.
//!
//! # The store
//!
//! A sweep's output folder: a manifest saying which sweep it holds, and its records, one JSON
//! object a line, written as points finish.
//!
//! ## The folder
//!
//! * `manifest.json`: `{"format": 3, "crate_version": "0.2.0", "results_version": 1, "kind":
//!   "...", "points": N, "fingerprint": "<16 hex digits>", "settings": {...}, "description":
//!   {...}}`, written when the folder is created and checked whenever it is opened again:
//!   * `format` is the layout of the folder and its records ([`FORMAT_VERSION`]); a folder of
//!     another format is refused ([`StoreError::Format`]): format 2 (jeffcott 0.2.0, the
//!     hand-written JSON) wrote whole numbers as `17.0`, which this version does not read.
//!   * `crate_version` and `results_version` are written by the crate ([`CRATE_VERSION`],
//!     [`RESULTS_VERSION`]); a folder of another results version is refused
//!     ([`StoreError::ResultsVersion`]): its records were computed by a version whose results
//!     differ from this one's. A folder of another crate version with the same results
//!     version is resumed.
//!   * `fingerprint` is the 64-bit FNV-1a hash of the points' JSON, one a line (the grid).
//!   * `settings` are the computation's settings, recorded by the crate: for
//!     [`scan_grid`] its [`AttractorOptions`] as serde writes it, every field
//!     ([`SweepStore::open_scan`]); `null` for a folder opened with [`SweepStore::open`].
//!   * `kind` and `description` are the caller's: what the sweep computes, and what the crate
//!     cannot see, e.g. the model's parameters that the caller's `setup` closure uses (any
//!     `Serialize` value; `&()` for none).
//!
//!   A folder whose manifest differs from the sweep being run is refused
//!   ([`StoreError::Mismatch`], [`StoreError::SettingMismatch`] naming the setting, the
//!   folder's value and this run's): results of one sweep are never mixed into another, and a
//!   sweep is resumed only with the settings it was started with.
//! * `records-<w>.jsonl`, one file per writer `w` (the process, or the MPI rank), and
//!   `records-shard-<i>-of-<n>.jsonl`, one per shard of a sweep split into independent
//!   processes ([`Shard`], e.g. the tasks of a job array); each line one point:
//!   `{"index": i, "point": <the point>, "ok": <the result>}` or
//!   `{"index": i, "point": <the point>, "error": <the error>}`, each value as serde writes it
//!   ([`Record`], with the rules for numbers, NaN and infinities). `index` is the point's position
//!   in the sweep's list, so the order of the lines never matters. Reading the folder merges
//!   every records file: no file is written by two processes at once, so no file locking is
//!   needed, on a shared file system neither.
//!
//! Several processes may open the same new folder at once (the shards of a job array): the
//! manifest is written whole to a temporary file and linked to `manifest.json` only if there
//! is none yet (an atomic create-if-absent, also on NFS), then read back and checked: exactly
//! one manifest is created, and a process of another sweep is refused.
//!
//! ## Crashes and restarts
//!
//! A record is written with one `write` call as soon as its point finishes. A process killed
//! in the middle of a write leaves at most a partial last line without its line break: readers
//! ignore it, and the next writer of that file cuts it off before appending. On reading, a
//! point recorded twice (a rare race of two writers) keeps its first record, in the order of
//! the file names and the lines; the others are counted in [`Loaded::duplicates`]. A complete
//! line that is not a valid record is an error ([`StoreError::Corrupt`]), not silently redone.
//!
//! # Records
//!
//! [`Record`]: what a sweep writes to its folder and reads back: a point, a result, an error.
//!
//! A record is the value's JSON as [`serde_json`] writes it from the value's `Serialize`, and
//! is read back through its `Deserialize`: derive both for your point and result types
//! (`#[derive(serde::Serialize, serde::Deserialize)]`) and they are records.
//!
//! * **Numbers.** An `f64` is written in its shortest round-trip form (`0.1`, `1e-7`, `-0.0`)
//!   and read back with `serde_json`'s `float_roundtrip` parser: **bit for bit** the same value
//!   (subnormals, `-0.0` and the extremes included; a property test checks it).
//! * **NaN and infinities.** JSON has none: `serde_json` writes a non-finite `f64` as `null`,
//!   which does not read back as an `f64`. [`run_points`] reads every
//!   outcome back before writing it, so such an outcome is never written: the run stops with
//!   [`StoreError::RoundTrip`] naming the point. A result that
//!   may be undefined holds an `Option<f64>` (`null` is `None`) or an error instead.

mod attractor;
mod catalogue;
#[cfg(feature = "mpi")]
#[cfg_attr(docsrs, doc(cfg(feature = "mpi")))]
pub mod distributed;
mod failure;
mod record;
mod runner;
mod scan;
mod store;

pub use attractor::{find_attractor, Attractor, AttractorOptions, MatchOptions, OrbitStats};
pub use catalogue::{Catalogue, CatalogueEntry, PointLabel};
pub use failure::{PointFailure, SimFailureKind};
pub use record::Record;
pub use runner::{run_points, PointResults, RunOptions, Shard};
pub use scan::{attractor_at, scan_grid, Grid2, GridScan};
pub use store::{
    Loaded, Manifest, StoreError, SweepStore, CRATE_VERSION, FORMAT_VERSION, RESULTS_VERSION,
};
