//! Finite-element rotors (ROSS exports) on the ring.

mod fe_exact;
mod fe_matrices;
