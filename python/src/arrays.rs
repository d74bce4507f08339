//! Results as numpy arrays: a 1-D array of values, a 2-D array of rows, Floquet multipliers
//! as complex numbers.

use jeffcott::stability::Multiplier;
use numpy::ndarray::{Array1, Array2};
use numpy::{Complex64, Element, IntoPyArray, PyArray1, PyArray2};
use pyo3::prelude::*;

use crate::errors::value_error;

/// The values as a 1-D numpy array.
pub fn array<T: Element>(py: Python<'_>, values: impl IntoIterator<Item = T>) -> Py<PyArray1<T>> {
    Array1::from_iter(values).into_pyarray(py).unbind()
}

/// The rows, each `width` long (6 for a state, 4 for a periodic point), as an (N, width)
/// numpy array; rows that do not fill N × width exactly are a `ValueError`.
pub fn table<T, R>(
    py: Python<'_>,
    rows: impl ExactSizeIterator<Item = R>,
    width: usize,
) -> PyResult<Py<PyArray2<T>>>
where
    T: Element,
    R: IntoIterator<Item = T>,
{
    let n = rows.len();
    let flat: Vec<T> = rows.flatten().collect();
    let table = Array2::from_shape_vec((n, width), flat).map_err(value_error)?;
    Ok(table.into_pyarray(py).unbind())
}

/// Floquet multipliers as numpy's complex numbers.
pub fn complex(m: &[Multiplier]) -> impl Iterator<Item = Complex64> + '_ {
    m.iter().map(|m| Complex64::new(m.re, m.im))
}
