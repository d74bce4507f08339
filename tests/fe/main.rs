//! Finite-element rotors (ROSS exports) on the ring.

mod fe_matrices;
mod fe_reduction;
mod fe_reduction_table;
