//! Finite-element rotors (ROSS exports) on the ring.

mod fe_bearing_table;
mod fe_contact_force;
mod fe_contact_scale;
mod fe_drive;
mod fe_drive_jacobian;
pub(crate) mod fe_eccentric;
mod fe_energy;
mod fe_error_weights;
mod fe_exact;
mod fe_jacobian;
mod fe_linear;
mod fe_matrices;
mod fe_modal;
mod fe_modal_exact;
mod fe_reduction;
mod fe_reduction_s1;
mod fe_reduction_table;
mod fe_rub_map;
mod fe_run_up;
mod fe_s1;
mod fe_stability_margin;
mod fe_steady;
