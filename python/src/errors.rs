//! The crate's errors as Python exceptions: bad input is a `ValueError`, a failed run a
//! `SimulationError` (a `RuntimeError`) carrying what was computed before the failure.

use jeffcott::hybrid::{SimError, SimErrorKind};
use jeffcott::nalgebra::allocator::Allocator;
use jeffcott::nalgebra::{DefaultAllocator, Dim};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    jeffcott,
    SimulationError,
    PyRuntimeError,
    "A run failed (integrator, chattering, a model error along the way). The message is the \
     crate's; `partial` holds what was computed before the failure, of the same type as the \
     successful result."
);

/// A bad parameter or input: `ValueError` with the crate's message.
pub fn value_error(e: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A failed run: `SimulationError(message)` with the attribute `partial`.
pub fn simulation_error(py: Python<'_>, message: String, partial: Py<PyAny>) -> PyErr {
    let err = SimulationError::new_err(message);
    // The attribute is best effort: the message is what matters if it cannot be set.
    let _ = err.value(py).setattr("partial", partial);
    err
}

/// A failed run: `ValueError` for an invalid option, else `SimulationError` with `partial`.
pub fn run_error<D: Dim>(py: Python<'_>, e: SimError<D>, partial: Py<PyAny>) -> PyErr
where
    DefaultAllocator: Allocator<D>,
{
    match e.kind {
        SimErrorKind::InvalidOption { .. } | SimErrorKind::DimensionMismatch { .. } => {
            value_error(&e)
        }
        _ => simulation_error(py, e.to_string(), partial),
    }
}
