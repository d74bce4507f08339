//! Python bindings of `jeffcott` (the extension module `jeffcott._jeffcott`): the paper's
//! model and finite-element rotors on the snubber ring, numpy arrays in and out. The loops
//! stay compiled: Python hands over arrays and parameters once, never a callback per step.
//! Long runs release the GIL; Ctrl-C stops them: a run through the driver's observer
//! (`HybridObserver::should_stop`, `runs`), the Lyapunov exponents and the continuation
//! through the crate's `Progress` observer (`interrupt`).

mod arrays;
mod basins;
mod bearings;
mod continuation;
mod errors;
mod fe;
mod fe_modes;
mod fe_rub_map;
mod fe_run;
mod fe_run_up;
mod fe_transient;
mod interrupt;
mod lyapunov;
mod motor;
mod options;
mod orders;
mod paper;
mod params;
mod poincare;
mod revolutions;
mod run_up;
mod runs;
mod stability;

use pyo3::prelude::*;

/// The compiled part of the `jeffcott` package (its functions are re-exported there).
#[pymodule]
mod _jeffcott {
    use pyo3::prelude::*;

    #[pymodule_export]
    use crate::basins::{basins, BasinAttractor, Basins};
    #[pymodule_export]
    use crate::continuation::{continue_orbit, ContinuedBranch, SpecialPointPy};
    #[pymodule_export]
    use crate::errors::SimulationError;
    #[pymodule_export]
    use crate::fe_modes::{fewest_modes, response_error};
    #[pymodule_export]
    use crate::fe_rub_map::{fe_rub_map, FeRubMap, RubSpecialPoint};
    #[pymodule_export]
    use crate::fe_run::{ContactEpisodes, FeRun};
    #[pymodule_export]
    use crate::fe_run_up::fe_run_up;
    #[pymodule_export]
    use crate::fe_transient::fe_transient;
    #[pymodule_export]
    use crate::lyapunov::{lyapunov_exponents, Lyapunov};
    #[pymodule_export]
    use crate::motor::Motor;
    #[pymodule_export]
    use crate::orders::{
        amplitude_spectrum, full_spectrum, order_track, OrderTrack, WhirlSpectrum,
    };
    #[pymodule_export]
    use crate::paper::{
        bifurcation, regime, ring_position, simulate, simulate_dense, DenseRun, Diagram, StrobeRun,
    };
    #[pymodule_export]
    use crate::params::{presets, PyParams};
    #[pymodule_export]
    use crate::poincare::{poincare, Section};
    #[pymodule_export]
    use crate::revolutions::Revolutions;
    #[pymodule_export]
    use crate::run_up::{run_up, RunUp};
    #[pymodule_export]
    use crate::stability::{periodic_orbit, Orbit};

    #[pymodule_init]
    fn init(m: &Bound<'_, PyModule>) -> PyResult<()> {
        // numpy's C API, loaded now: loaded at a run's first array it runs Python code, and a
        // Ctrl-C pending then (pressed during the run) made the loader panic.
        numpy::PyArray1::<f64>::zeros(m.py(), 0, false);
        m.add("__version__", env!("CARGO_PKG_VERSION"))
    }
}
