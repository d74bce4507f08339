//! A grid scan split across two MPI ranks (`mpirun -np 2` on this machine) equals the
//! single-process scan bit for bit, also when the MPI run is interrupted and resumed, and a
//! single process then reads the ranks' folder back unchanged.
//!
//! Run with `cargo test --features mpi --test global_mpi`; needs OpenMPI's `mpirun` (Debian:
//! `openmpi-bin`). The test re-runs its own binary under `mpirun`, selecting the `mpi_worker`
//! test, which does nothing unless `JEFFCOTT_MPI_WORKER_DIR` is set.
#![cfg(feature = "mpi")]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

use jeffcott::global::{
    distributed, scan_grid, AttractorOptions, Grid2, GridScan, Manifest, RunOptions, SweepStore,
};
use jeffcott::paper::{BasinPlane, StartPlane};
use jeffcott::params::Preset;
use mpi::traits::Communicator;

const DIR_VAR: &str = "JEFFCOTT_MPI_WORKER_DIR";
const PHASE_VAR: &str = "JEFFCOTT_MPI_WORKER_PHASE";

fn grid() -> Grid2 {
    Grid2::linspace((-1.0, 1.0, 6), (-1.5, 1.5, 5)).unwrap()
}

fn plane() -> BasinPlane {
    BasinPlane::new(Preset::Fig8b.params().with_eta(2.2), StartPlane::XVx)
}

fn config() -> AttractorOptions {
    AttractorOptions::default()
        .with_transient(300)
        .with_record(32)
        .with_max_transient(600)
}

/// The sweep's description: the plane (its parameters).
fn description() -> BasinPlane {
    plane()
}

/// Every outcome as its record text (equal text is equal bits).
fn texts(scan: &GridScan) -> Vec<String> {
    scan.results
        .results
        .iter()
        .map(|r| match r {
            Some(Ok(a)) => serde_json::to_string(a).unwrap(),
            Some(Err(e)) => serde_json::to_string(e).unwrap(),
            None => "missing".into(),
        })
        .collect()
}

/// The rank side: runs the scan on every rank; rank 0 writes the outcomes to `result.txt`.
#[test]
fn mpi_worker() {
    let Ok(dir) = std::env::var(DIR_VAR) else {
        return; // not under mpirun: nothing to do
    };
    let phase = std::env::var(PHASE_VAR).unwrap_or_default();
    let universe = mpi::initialize().expect("MPI initialised once");
    let world = universe.world();
    let grid = grid();
    let manifest = Manifest::scan("basins", &description(), &grid, &config()).unwrap();
    let store = distributed::open_store(&world, &dir, manifest).unwrap();
    let mut run = RunOptions::default().with_threads(1);
    if phase == "partial" {
        run = run.with_max_new_points(4); // per rank
    }
    let scan = distributed::scan_grid(
        &world,
        &grid,
        plane().setup(),
        &config(),
        Some(&store),
        &run,
        None,
    )
    .unwrap();
    match scan {
        Some(scan) => {
            assert_eq!(world.rank(), 0);
            let mut text = format!(
                "computed {} reused {} missing {}\n",
                scan.results.computed,
                scan.results.reused,
                scan.results.missing()
            );
            for t in texts(&scan) {
                text.push_str(&t);
                text.push('\n');
            }
            fs::write(Path::new(&dir).join(format!("result-{phase}.txt")), text).unwrap();
        }
        None => assert_ne!(world.rank(), 0),
    }
}

fn mpirun(dir: &Path, phase: &str) -> String {
    let exe = std::env::current_exe().unwrap();
    let out = Command::new("mpirun")
        // OpenMPI refuses root without the first, and two ranks on fewer cores without the second.
        .args(["-np", "2", "--allow-run-as-root", "--oversubscribe"])
        .arg(&exe)
        .args([
            "--exact",
            "mpi_worker",
            "--nocapture",
            "--test-threads",
            "1",
        ])
        .env(DIR_VAR, dir)
        .env(PHASE_VAR, phase)
        // Shared-memory transport between the two local ranks, no network.
        .env("OMPI_MCA_btl", "self,vader")
        .output()
        .expect("run mpirun (Debian: apt-get install openmpi-bin libopenmpi-dev)");
    assert!(
        out.status.success(),
        "mpirun failed: {}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    fs::read_to_string(dir.join(format!("result-{phase}.txt"))).unwrap()
}

#[test]
fn two_ranks_equal_one_process_bitwise_across_a_restart() {
    let exe = std::env::current_exe().unwrap();
    let target = exe.parent().and_then(|d| d.parent()).unwrap().to_path_buf();
    let dir: PathBuf = target.join("global_mpi_test");
    let _ = fs::remove_dir_all(&dir);
    let grid = grid();
    let n = grid.len();

    let single = scan_grid(
        &grid,
        plane().setup(),
        &config(),
        None,
        &RunOptions::default().with_threads(1),
        None,
    )
    .unwrap();
    let expected = texts(&single);

    // Interrupted: each rank starts at most 4 points.
    let partial = mpirun(&dir, "partial");
    let mut lines = partial.lines();
    assert_eq!(
        lines.next().unwrap(),
        format!("computed 8 reused 0 missing {}", n - 8)
    );
    let done: Vec<&str> = lines.collect();
    let matching = done
        .iter()
        .zip(&expected)
        .filter(|(a, b)| **a == b.as_str())
        .count();
    assert_eq!(matching, 8, "the 8 points done equal the single process's");
    for rank in 0..2 {
        let path = dir.join(format!("records-{rank}.jsonl"));
        assert_eq!(
            fs::read_to_string(&path).unwrap().lines().count(),
            4,
            "{path:?}"
        );
    }

    // Resumed: the other points, split across the two ranks.
    let full = mpirun(&dir, "full");
    let mut lines = full.lines();
    assert_eq!(
        lines.next().unwrap(),
        format!("computed {} reused 8 missing 0", n - 8)
    );
    let got: Vec<&str> = lines.collect();
    assert_eq!(got.len(), n);
    for (i, (a, b)) in got.iter().zip(&expected).enumerate() {
        assert_eq!(*a, b.as_str(), "point {i}");
    }

    // One process reads the ranks' records back: nothing to run, the same outcomes.
    let store = SweepStore::open_scan(&dir, "basins", &description(), &grid, &config()).unwrap();
    let back = scan_grid(
        &grid,
        plane().setup(),
        &config(),
        Some(&store),
        &RunOptions::default(),
        None,
    )
    .unwrap();
    assert_eq!((back.results.computed, back.results.reused), (0, n));
    assert_eq!(texts(&back), expected);
    assert_eq!(back.results.results, single.results.results);
    fs::remove_dir_all(&dir).unwrap();
}
