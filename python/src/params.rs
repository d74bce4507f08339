//! The paper's non-dimensional parameters as a Python class, and the named presets.

use std::str::FromStr;

use jeffcott::params::{Params, Preset};
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::errors::value_error;

/// The struct `PyParams` as written (the Python class `Params`: each field an attribute, a
/// getter and setter with the field's doc), and what goes field by field: the names in order
/// ([`FIELDS`]), the conversions from and to the crate's [`Params`] (exhaustive
/// destructuring: a field the crate adds and the struct lacks is a compile error), the values
/// in order and the field of a name.
macro_rules! py_params {
    (
        $(#[doc = $class_doc:literal])*
        pub struct PyParams {
            $($(#[doc = $doc:literal])* pub $field:ident: f64,)+
        }
    ) => {
        $(#[doc = $class_doc])*
        #[pyclass(
            name = "Params",
            module = "jeffcott",
            get_all,
            set_all,
            eq,
            from_py_object
        )]
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct PyParams {
            $($(#[doc = $doc])* pub $field: f64,)+
        }

        /// The field names, in the order of the crate's struct.
        const FIELDS: &[&str] = &[$(stringify!($field)),+];

        impl From<Params> for PyParams {
            fn from(p: Params) -> Self {
                let Params { $($field),+ } = p;
                Self { $($field),+ }
            }
        }

        impl From<PyParams> for Params {
            fn from(p: PyParams) -> Self {
                let PyParams { $($field),+ } = p;
                Self { $($field),+ }
            }
        }

        impl PyParams {
            /// The values, in the order of [`FIELDS`].
            fn values(&self) -> [f64; FIELDS.len()] {
                [$(self.$field),+]
            }

            /// The field of a name, if there is one.
            fn field_mut(&mut self, name: &str) -> Option<&mut f64> {
                match name {
                    $(stringify!($field) => Some(&mut self.$field),)+
                    _ => None,
                }
            }
        }
    };
}

// The class as a struct; the macro adds what goes field by field.
py_params! {
/// The paper's non-dimensional parameters (time in units of $1/\omega_n$, lengths in units of
/// the radial gap $\gamma$). Every field of the crate's `jeffcott::params::Params`, with the
/// same names and defaults (the paper's Fig. 8a set at eta = 2).
///
/// ``Params(**fields)`` builds and validates (``ValueError`` with the crate's message);
/// ``Params.preset("fig8b")`` gives a named figure's set; ``to_dict``/``from_dict`` round trip.
pub struct PyParams {
    /// Frequency ratio eta = Omega / omega_n (> 0), dimensionless.
    pub eta: f64,
    /// Rotor damping ratio nu1 = c_r / (2 sqrt(k_r M)) (>= 0), dimensionless.
    pub nu1: f64,
    /// Ring damping ratio nu2 = c_s / (2 sqrt(k_r M)) per spring-damper unit (>= 0).
    pub nu2: f64,
    /// Ring unit stiffness ratio along x, K_x = k_sx / k_r (> 0).
    pub kx: f64,
    /// Ring unit stiffness ratio along y, K_y = k_sy / k_r (> 0).
    pub ky: f64,
    /// Out-of-balance beta = (m/M)(rho/gamma) (>= 0); the forcing amplitude is beta eta^2.
    pub beta: f64,
    /// Preload along x over the gap, D_x = Delta_x / gamma (>= 0).
    pub dx: f64,
    /// Preload along y over the gap, D_y = Delta_y / gamma (>= 0).
    pub dy: f64,
    /// Eccentricity of the rotor's rest position along x, in gaps.
    pub ex: f64,
    /// Eccentricity of the rotor's rest position along y, in gaps.
    pub ey: f64,
    /// Initial phase of the out-of-balance, rad.
    pub phi0: f64,
}
}

impl PyParams {
    /// The crate's parameters, validated (`ValueError` naming the bad field).
    pub fn checked(&self) -> PyResult<Params> {
        Params::from(*self).validated().map_err(value_error)
    }

    fn set(&mut self, name: &str, v: f64) -> PyResult<()> {
        let slot = self.field_mut(name).ok_or_else(|| {
            value_error(format!(
                "unknown parameter '{name}' (the fields are {})",
                FIELDS.join(", ")
            ))
        })?;
        *slot = v;
        Ok(())
    }
}

#[pymethods]
impl PyParams {
    /// Parameters from keywords (the others at their defaults), validated.
    #[new]
    #[pyo3(signature = (**fields))]
    fn new(fields: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let mut p = PyParams::from(Params::default());
        if let Some(d) = fields {
            for (k, v) in d.iter() {
                p.set(&k.extract::<String>()?, v.extract::<f64>()?)?;
            }
        }
        p.checked()?;
        Ok(p)
    }

    /// The parameters of a named figure of the paper (``presets()`` lists the names).
    #[staticmethod]
    fn preset(name: &str) -> PyResult<Self> {
        let preset = Preset::from_str(name).map_err(value_error)?;
        Ok(preset.params().into())
    }

    /// A dict of every field (float values), the inverse of ``from_dict``.
    #[allow(clippy::wrong_self_convention)] // a pyo3 method takes `&self`
    fn to_dict<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = PyDict::new(py);
        for (k, v) in FIELDS.iter().zip(self.values()) {
            d.set_item(k, v)?;
        }
        Ok(d)
    }

    /// Parameters from a dict of fields (missing ones at their defaults), validated.
    #[staticmethod]
    fn from_dict(d: &Bound<'_, PyDict>) -> PyResult<Self> {
        Self::new(Some(d))
    }

    /// Raises ``ValueError`` (the crate's message) unless the parameters are valid.
    fn validate(&self) -> PyResult<()> {
        self.checked().map(|_| ())
    }

    /// The same parameters with the ring stiffness ratio K on both axes.
    fn with_stiffness(&self, k: f64) -> Self {
        Self {
            kx: k,
            ky: k,
            ..*self
        }
    }

    /// The same parameters with the preload D on both axes (in gaps).
    fn with_preload(&self, d: f64) -> Self {
        Self {
            dx: d,
            dy: d,
            ..*self
        }
    }

    /// The forcing period 2 pi / eta (non-dimensional time).
    #[getter]
    pub fn forcing_period(&self) -> f64 {
        2.0 * std::f64::consts::PI / self.eta
    }

    fn __repr__(&self) -> String {
        let body: Vec<String> = FIELDS
            .iter()
            .zip(self.values())
            .map(|(k, v)| format!("{k}={v:?}"))
            .collect();
        format!("Params({})", body.join(", "))
    }
}

/// The names of the presets, in figure order (``Params.preset(name)``).
#[pyfunction]
pub fn presets() -> Vec<&'static str> {
    Preset::NAMES.to_vec()
}
