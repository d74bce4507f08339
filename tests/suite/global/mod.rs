//! Integration tests of the global dynamics (`jeffcott::global`): attractors, basins, resumable
//! sweeps and shards, continuation; one module per file: `cargo test --test suite global::`,
//! or one module: `cargo test --test suite global::global_scan::`. The MPI test is apart
//! (`tests/global_mpi.rs`, feature `mpi`, run under `mpirun`).

mod global_continuation;
mod global_records;
mod global_resume;
mod global_scan;
