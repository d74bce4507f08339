//! Integration options from Python keywords.

use jeffcott::hybrid::SimOptions;
use jeffcott::ode::Method;
use pyo3::PyResult;

use crate::errors::value_error;

/// The integration method of a name (case-insensitive): dop853, dopri5, radau5, etd4 (which
/// only a model with a diagonal linear part takes: a finite-element rotor in modal form).
pub fn method(name: &str) -> PyResult<Method> {
    match name.to_ascii_lowercase().as_str() {
        "dop853" => Ok(Method::Dop853),
        "dopri5" => Ok(Method::Dopri5),
        "radau5" => Ok(Method::Radau5),
        "etd4" => Ok(Method::Etd4),
        other => Err(value_error(format!(
            "method '{other}' is not one of dop853, dopri5, radau5, etd4"
        ))),
    }
}

/// [`SimOptions`] with the given tolerances and method; `None` keeps the crate's default.
pub fn sim_options(
    rtol: Option<f64>,
    atol: Option<f64>,
    name: Option<&str>,
) -> PyResult<SimOptions> {
    let mut o = SimOptions::default();
    if let Some(r) = rtol {
        o = o.with_rtol(positive("rtol", r)?);
    }
    if let Some(a) = atol {
        o = o.with_atol(positive("atol", a)?);
    }
    if let Some(m) = name {
        o = o.with_method(method(m)?);
    }
    Ok(o)
}

/// `value` if finite and > 0, else a `ValueError` naming it.
pub fn positive(name: &str, value: f64) -> PyResult<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(value_error(format!(
            "{name} = {value} must be finite and > 0"
        )))
    }
}

/// Coulomb friction at the ring from the keywords ``friction`` (the coefficient, finite and
/// not negative) and ``shaft_radius`` (required when it is positive; `units` names its unit
/// in the error): `None` for a frictionless run, else `(mu, radius)`.
pub fn coulomb(mu: f64, radius: Option<f64>, units: &str) -> PyResult<Option<(f64, f64)>> {
    if !(mu.is_finite() && mu >= 0.0) {
        return Err(value_error(format!(
            "friction must be finite and >= 0, got {mu}"
        )));
    }
    match (mu, radius) {
        (0.0, _) => Ok(None),
        (mu, Some(radius)) => Ok(Some((mu, radius))),
        (_, None) => Err(value_error(format!(
            "friction needs shaft_radius: the shaft's radius at the ring, {units}"
        ))),
    }
}
