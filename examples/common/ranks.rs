//! Where a sweep runs: in this process, or, built with `--features mpi` and started by
//! `mpirun` or `srun`, split across the MPI ranks (`jeffcott::global::distributed`). Rank 0
//! gets the results and writes the figures; the other ranks only compute.

use std::path::Path;

use jeffcott::analysis::Progress;
use jeffcott::global::{
    AttractorOptions, Grid2, GridScan, Manifest, PointFailure, RunOptions, StoreError, SweepStore,
};
use jeffcott::hybrid::RotorModel;
use jeffcott::nalgebra::allocator::Allocator;
use jeffcott::nalgebra::{DefaultAllocator, OVector};

/// This process's place among the ranks (one rank without the `mpi` feature).
pub struct Ranks {
    #[cfg(feature = "mpi")]
    universe: mpi::environment::Universe,
    /// This process's rank.
    pub rank: usize,
    /// Number of ranks.
    pub size: usize,
}

impl Ranks {
    /// Starts MPI with the `mpi` feature (a lone process is a world of one rank); one rank
    /// otherwise.
    pub fn init() -> Ranks {
        #[cfg(feature = "mpi")]
        {
            use mpi::traits::Communicator;
            let universe = mpi::initialize().unwrap_or_else(|| {
                eprintln!("error: MPI was already initialised");
                std::process::exit(1)
            });
            let world = universe.world();
            let (rank, size) = (world.rank() as usize, world.size() as usize);
            Ranks {
                universe,
                rank,
                size,
            }
        }
        #[cfg(not(feature = "mpi"))]
        Ranks { rank: 0, size: 1 }
    }

    /// Whether this is rank 0 (which prints, draws and gets the results).
    pub fn is_root(&self) -> bool {
        self.rank == 0
    }

    /// Opens the sweep's folder (rank 0 first) for the sweep of `manifest`
    /// ([`Manifest::scan`] for a scan).
    pub fn open_store(&self, dir: &Path, manifest: Manifest) -> Result<SweepStore, StoreError> {
        #[cfg(feature = "mpi")]
        {
            jeffcott::global::distributed::open_store(&self.universe.world(), dir, manifest)
        }
        #[cfg(not(feature = "mpi"))]
        SweepStore::open_manifest(dir, manifest)
    }

    /// The grid scan, on this process or across the ranks; `Some` on rank 0.
    pub fn scan_grid<M, S>(
        &self,
        grid: &Grid2,
        setup: S,
        config: &AttractorOptions,
        store: Option<&SweepStore>,
        run: &RunOptions,
        progress: Option<&dyn Progress>,
    ) -> Result<Option<GridScan>, StoreError>
    where
        M: RotorModel,
        S: Fn(&[f64; 2]) -> Result<(M, OVector<f64, M::Dim>), PointFailure> + Sync,
        DefaultAllocator: Allocator<M::Dim>,
    {
        #[cfg(feature = "mpi")]
        {
            jeffcott::global::distributed::scan_grid(
                &self.universe.world(),
                grid,
                setup,
                config,
                store,
                run,
                progress,
            )
        }
        #[cfg(not(feature = "mpi"))]
        jeffcott::global::scan_grid(grid, setup, config, store, run, progress).map(Some)
    }
}
