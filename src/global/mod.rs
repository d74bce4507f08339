//! Global dynamics: which attractors coexist, where their basins lie, how the dynamics change
//! over two parameters, and long sweeps that survive being killed and run on many processes.
//!
//! * [`attractor`](mod@attractor): run a model until it settles, identify the attractor
//!   (period and a canonical periodic point, or "not periodic" with contact statistics), and
//!   match attractors reached from different starts ([`find_attractor`], [`Attractor`],
//!   [`MatchTolerance`]).
//! * [`catalogue`]: the distinct attractors of a scan and the label of each point.
//! * The continuation of periodic orbits (pseudo-arclength, bifurcations, branch switching)
//!   is in [`crate::stability`] ([`crate::stability::continue_orbit`]).
//! * [`scan`]: attractor scans over a grid ([`scan_grid`], [`Grid2`]): basins of attraction
//!   (a grid of initial states) and two-parameter maps (a grid of parameters). The paper's
//!   model has ready-made planes: [`crate::paper::BasinPlane`], [`crate::paper::ParamPlane`].
//! * [`runner`]: the engine under every scan: any computation over a list of points, in
//!   parallel, writing each outcome to a folder as it finishes, and skipping the points
//!   already there when restarted ([`run_points`], [`RunConfig`]), or only one [`Shard`] of
//!   them (a task of a job array, without MPI). Results are bitwise identical for any number
//!   of threads, across restarts, for any number of shards, and (feature `mpi`, module
//!   `distributed`) for any number of MPI ranks.
//! * [`store`]: the folder (a manifest and records, one JSON object a line) and its rules for
//!   crashes ([`SweepStore`]); [`record`] the format ([`Record`]: serde's JSON of the values).
//!
//! # Example: a resumable basin scan
//!
//! ```no_run
//! use jeffcott::analysis::StderrProgress;
//! use jeffcott::global::{scan_grid, AttractorConfig, Grid2, MatchTolerance, RunConfig, SweepStore};
//! use jeffcott::paper::{BasinPlane, StartPlane};
//! use jeffcott::params::Preset;
//!
//! let plane = BasinPlane::new(Preset::Fig8a.params().with_eta(2.2), StartPlane::XVx);
//! let grid = Grid2::linspace((-1.0, 1.0, 200), (-1.5, 1.5, 200))?;
//! let config = AttractorConfig::default();
//! // The folder records the grid, every setting of `config` and the crate's version; the
//! // description (any `Serialize` value) adds what the scan cannot see: the model's parameters.
//! // Killed part-way? Run it again: the points in the folder are not run again (and a run
//! // with another grid, other settings or another description is refused).
//! let store = SweepStore::open_scan("out/basins-fig8a", "basins", &plane, &grid, &config)?;
//! let progress = StderrProgress::new("basins");
//! let scan = scan_grid(&grid, plane.setup(), &config, Some(&store), &RunConfig::default(), Some(&progress))?;
//! let catalogue = scan.catalogue(&MatchTolerance::default());
//! for (k, e) in catalogue.entries.iter().enumerate() {
//!     println!("attractor {k}: {} ({} points)", e.attractor.describe(), e.count);
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod attractor;
pub mod catalogue;
#[cfg(feature = "mpi")]
#[cfg_attr(docsrs, doc(cfg(feature = "mpi")))]
pub mod distributed;
mod failure;
pub mod record;
pub mod runner;
pub mod scan;
pub mod store;

pub use attractor::{find_attractor, Attractor, AttractorConfig, MatchTolerance, OrbitStats};
pub use catalogue::{Catalogue, CatalogueEntry, PointLabel};
pub use failure::{PointFailure, SimFailureKind};
pub use record::Record;
pub use runner::{run_points, PointResults, RunConfig, Shard};
pub use scan::{attractor_at, scan_grid, Grid2, GridScan};
pub use store::{
    Loaded, Manifest, StoreError, SweepStore, CRATE_VERSION, FORMAT_VERSION, RESULTS_VERSION,
};
