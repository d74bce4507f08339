//! Integration tests of the global dynamics (`jeffcott::global`): attractors, basins, resumable
//! sweeps and shards, continuation; one module per file: `cargo test --test global`,
//! or one module: `cargo test --test global global_scan::`. The MPI test is apart
//! (`tests/global_mpi.rs`, feature `mpi`, run under `mpirun`).

/// The built example programs (`continuation` runs its example).
#[path = "../support/examples.rs"]
mod support;

mod global_continuation;
mod global_records;
mod global_resume;
mod global_scan;
