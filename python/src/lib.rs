//! Python bindings of `jeffcott` (the extension module `jeffcott._jeffcott`): the paper's
//! model and finite-element rotors on the snubber ring, numpy arrays in and out. The loops
//! stay compiled: Python hands over arrays and parameters once, never a callback per step.
//! Long runs release the GIL and run in chunks, checking for Ctrl-C between them; the
//! Lyapunov exponents and the continuation, single library calls, check for it through the
//! crate's `Progress` observer (`interrupt`).

mod arrays;
mod basins;
mod chunks;
mod continuation;
mod errors;
mod fe;
mod interrupt;
mod lyapunov;
mod options;
mod paper;
mod params;
mod poincare;
mod run_up;
mod stability;

use pyo3::prelude::*;

/// The compiled part of the `jeffcott` package (its functions are re-exported there).
#[pymodule]
fn _jeffcott(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // numpy's C API, loaded now: loaded at a run's first array it runs Python code, and a
    // Ctrl-C pending then (pressed during the run) made the loader panic.
    numpy::PyArray1::<f64>::zeros(m.py(), 0, false);
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add(
        "SimulationError",
        m.py().get_type::<errors::SimulationError>(),
    )?;
    m.add_class::<params::PyParams>()?;
    m.add_class::<paper::StrobeRun>()?;
    m.add_class::<paper::DenseRun>()?;
    m.add_class::<paper::Diagram>()?;
    m.add_class::<fe::FeTransient>()?;
    m.add_class::<stability::Orbit>()?;
    m.add_class::<poincare::Section>()?;
    m.add_class::<lyapunov::Lyapunov>()?;
    m.add_class::<continuation::ContinuedBranch>()?;
    m.add_class::<continuation::SpecialPointPy>()?;
    m.add_class::<basins::Basins>()?;
    m.add_class::<basins::BasinAttractor>()?;
    m.add_class::<run_up::RunUp>()?;
    m.add_function(wrap_pyfunction!(params::presets, m)?)?;
    m.add_function(wrap_pyfunction!(paper::simulate, m)?)?;
    m.add_function(wrap_pyfunction!(paper::simulate_dense, m)?)?;
    m.add_function(wrap_pyfunction!(paper::bifurcation, m)?)?;
    m.add_function(wrap_pyfunction!(paper::ring_position, m)?)?;
    m.add_function(wrap_pyfunction!(paper::regime, m)?)?;
    m.add_function(wrap_pyfunction!(fe::fe_transient, m)?)?;
    m.add_function(wrap_pyfunction!(stability::periodic_orbit, m)?)?;
    m.add_function(wrap_pyfunction!(poincare::poincare, m)?)?;
    m.add_function(wrap_pyfunction!(lyapunov::lyapunov_exponents, m)?)?;
    m.add_function(wrap_pyfunction!(continuation::continue_orbit, m)?)?;
    m.add_function(wrap_pyfunction!(basins::basins, m)?)?;
    m.add_function(wrap_pyfunction!(run_up::run_up, m)?)?;
    Ok(())
}
