//! Tolerances and integrator options.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector, U1};

use super::OdeError;

/// A tolerance, either the same for every component or one value per
/// component (dimensionless for `rtol`, units of $y_i$ for `atol`).
///
/// For `atol` a component value of `f64::INFINITY` excludes that component
/// from error control (see [`Options::atol`]).
///
/// `Copy` for fixed dimensions; only `Clone` for [`Dyn`](nalgebra::Dyn)
/// (the per-component vector lives on the heap).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub enum Tolerance<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// The same value for every component.
    Scalar(f64),
    /// One value per component (length: the dimension of the system).
    PerComponent(OVector<f64, D>),
}

impl<D: Dim> Copy for Tolerance<D>
where
    DefaultAllocator: Allocator<D>,
    OVector<f64, D>: Copy,
{
}

impl<D: Dim> Tolerance<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// The tolerance of component `i`. Out-of-range indices return the
    /// largest component value for `PerComponent` (NaN if it is empty); never
    /// panics.
    #[inline]
    pub fn get(&self, i: usize) -> f64 {
        match self {
            Tolerance::Scalar(v) => *v,
            Tolerance::PerComponent(v) => match v.as_slice().get(i) {
                Some(x) => *x,
                None => v.iter().copied().fold(f64::NAN, f64::max),
            },
        }
    }

    /// The tolerance as a vector of dimension `dim` (a `PerComponent` vector
    /// of another length is returned as it is).
    pub fn to_vector(&self, dim: D) -> OVector<f64, D> {
        match self {
            Tolerance::Scalar(v) => OVector::from_element_generic(dim, U1, *v),
            Tolerance::PerComponent(v) => v.clone(),
        }
    }

    /// Number of components of a `PerComponent` tolerance (`None` for
    /// `Scalar`).
    pub fn components(&self) -> Option<usize> {
        match self {
            Tolerance::Scalar(_) => None,
            Tolerance::PerComponent(v) => Some(v.len()),
        }
    }

    /// Checks that every value is finite and non-negative (the rule for
    /// `rtol`); the error names `field`.
    pub fn validate(&self, field: &'static str) -> Result<(), OdeError> {
        self.check(field, false)
    }

    /// Checks every value: `>= 0`, finite, or `+inf` if `allow_infinite`.
    fn check(&self, field: &'static str, allow_infinite: bool) -> Result<(), OdeError> {
        let ok = |v: f64| v >= 0.0 && (v.is_finite() || allow_infinite);
        let bad = match self {
            Tolerance::Scalar(v) => (!ok(*v)).then_some(*v),
            Tolerance::PerComponent(v) => v.iter().copied().find(|x| !ok(*x)),
        };
        match bad {
            None => Ok(()),
            Some(value) => Err(OdeError::InvalidOption {
                field,
                value,
                hint: if allow_infinite {
                    "atol must be >= 0 (f64::INFINITY excludes a component from error control; typical 1e-12)"
                } else {
                    "tolerances must be finite and >= 0 (typical: rtol 1e-9, atol 1e-12)"
                },
            }),
        }
    }
}

impl<D: Dim> From<f64> for Tolerance<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn from(v: f64) -> Self {
        Tolerance::Scalar(v)
    }
}

/// Integrator options. Start from [`Default`] (or [`Options::with_tol`],
/// [`Options::fixed`]) and change fields with the `with_` builders, e.g.
///
/// ```
/// use jeffcott::ode::Options;
/// use nalgebra::U2;
///
/// let opts = Options::<U2>::default().with_rtol(1e-10).with_h_max(0.1);
/// assert_eq!(opts.rtol.get(0), 1e-10);
/// assert_eq!(opts.h_max, 0.1);
/// ```
///
/// The fields are public for reading; the struct is `#[non_exhaustive]`, so
/// it cannot be built by a struct literal outside the crate (a new field is
/// then not a breaking change).
///
/// Times and step sizes are in the time unit of the system. `Copy` for
/// fixed dimensions, `Clone` for [`Dyn`](nalgebra::Dyn).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
#[non_exhaustive]
pub struct Options<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Relative tolerance (dimensionless, finite, >= 0). Default `1e-9`.
    pub rtol: Tolerance<D>,
    /// Absolute tolerance (units of $y_i$, >= 0). Default `1e-12`.
    /// For every component `rtol + atol > 0` is required.
    ///
    /// **Components excluded from error control:** `f64::INFINITY` for a
    /// component (in a [`Tolerance::PerComponent`]) makes its error scale
    /// $s_i$ infinite, so it contributes nothing to the error norm, and the
    /// RMS norm averages over the remaining (controlled) components only.
    /// Meant for components the model sets itself (algebraic components
    /// placed by a projection or a reset map, e.g. the position of a
    /// massless ring): their values still come from the Runge–Kutta formula
    /// and the dense output, with whatever accuracy the steps chosen for the
    /// other components give them. A scalar `f64::INFINITY` excludes every
    /// component (steps then grow by `fac_max` up to `h_max`). NaN and
    /// negative values (including `-inf`) are rejected.
    pub atol: Tolerance<D>,
    /// Initial step size (> 0). `None` (default) = Hairer's automatic
    /// initial step selection.
    pub h_init: Option<f64>,
    /// Largest step size (> 0). Default `+inf`.
    pub h_max: f64,
    /// Step-size underflow threshold (>= 0): when the controller wants a
    /// step smaller than `h_min` (or smaller than $10\thinspace\varepsilon\thinspace|t|$) the
    /// integrator returns [`OdeError::StepSizeUnderflow`]. Default `0`.
    pub h_min: f64,
    /// Maximum number of step attempts (accepted + rejected) between two
    /// calls of [`Integrator::reset`](super::Integrator::reset) (so per call
    /// of [`solve()`](super::solve())). Default `1_000_000`.
    pub max_steps: u64,
    /// Safety factor of the step-size controller, in (0, 1]. Default `0.9`.
    pub safety: f64,
    /// Smallest step-size ratio $h_{\text{new}}/h$, in (0, 1]. Default `0.2`.
    pub fac_min: f64,
    /// Largest step-size ratio $h_{\text{new}}/h$, >= 1. Default `10`.
    pub fac_max: f64,
    /// PI-controller exponent $\beta$ on the previous error, in [0, 0.2].
    /// `None` (default) = the method's default: `0.04` (DOPRI5 and DOP853;
    /// Hairer's `dop853.f` uses 0 — set `Some(0.0)` to reproduce it).
    pub beta: Option<f64>,
    /// Fixed step size (> 0). Required by [`Rk4`](super::Rk4). For
    /// [`Dopri5`](super::Dopri5) and [`Dop853`](super::Dop853) `Some(h)`
    /// switches error control off and takes steps of exactly `h` (the last
    /// one before a bound is shortened to land on it); this is meant for
    /// convergence studies and reproducing fixed grids. In fixed-step mode
    /// `h_init`, `h_min`, `h_max` and the controller fields are not used.
    /// Default `None`.
    pub fixed_step: Option<f64>,
}

impl<D: Dim> Copy for Options<D>
where
    DefaultAllocator: Allocator<D>,
    OVector<f64, D>: Copy,
{
}

impl<D: Dim> Default for Options<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn default() -> Self {
        Options {
            rtol: Tolerance::Scalar(1e-9),
            atol: Tolerance::Scalar(1e-12),
            h_init: None,
            h_max: f64::INFINITY,
            h_min: 0.0,
            max_steps: 1_000_000,
            safety: 0.9,
            fac_min: 0.2,
            fac_max: 10.0,
            beta: None,
            fixed_step: None,
        }
    }
}

/// Builders: each returns the options with one field changed (the value is
/// checked by [`Options::validate`], as for every other construction).
impl<D: Dim> Options<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// With [`rtol`](Self::rtol) = `value`. A scalar `f64` or a [`Tolerance`].
    #[must_use]
    pub fn with_rtol(mut self, value: impl Into<Tolerance<D>>) -> Self {
        self.rtol = value.into();
        self
    }

    /// With [`atol`](Self::atol) = `value`. A scalar `f64` or a [`Tolerance`].
    #[must_use]
    pub fn with_atol(mut self, value: impl Into<Tolerance<D>>) -> Self {
        self.atol = value.into();
        self
    }

    /// With [`h_init`](Self::h_init) = `value`. A step `h` or `None` (automatic).
    #[must_use]
    pub fn with_h_init(mut self, value: impl Into<Option<f64>>) -> Self {
        self.h_init = value.into();
        self
    }

    /// With [`h_max`](Self::h_max) = `value`.
    #[must_use]
    pub fn with_h_max(mut self, value: f64) -> Self {
        self.h_max = value;
        self
    }

    /// With [`h_min`](Self::h_min) = `value`.
    #[must_use]
    pub fn with_h_min(mut self, value: f64) -> Self {
        self.h_min = value;
        self
    }

    /// With [`max_steps`](Self::max_steps) = `value`.
    #[must_use]
    pub fn with_max_steps(mut self, value: u64) -> Self {
        self.max_steps = value;
        self
    }

    /// With [`safety`](Self::safety) = `value`.
    #[must_use]
    pub fn with_safety(mut self, value: f64) -> Self {
        self.safety = value;
        self
    }

    /// With [`fac_min`](Self::fac_min) = `value`.
    #[must_use]
    pub fn with_fac_min(mut self, value: f64) -> Self {
        self.fac_min = value;
        self
    }

    /// With [`fac_max`](Self::fac_max) = `value`.
    #[must_use]
    pub fn with_fac_max(mut self, value: f64) -> Self {
        self.fac_max = value;
        self
    }

    /// With [`beta`](Self::beta) = `value`. A value or `None` (the method's default).
    #[must_use]
    pub fn with_beta(mut self, value: impl Into<Option<f64>>) -> Self {
        self.beta = value.into();
        self
    }

    /// With [`fixed_step`](Self::fixed_step) = `value`. A step `h` or `None` (adaptive).
    #[must_use]
    pub fn with_fixed_step(mut self, value: impl Into<Option<f64>>) -> Self {
        self.fixed_step = value.into();
        self
    }
}

impl<D: Dim> Options<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Options with the given scalar tolerances and defaults otherwise.
    pub fn with_tol(rtol: f64, atol: f64) -> Self {
        Options::default().with_rtol(rtol).with_atol(atol)
    }

    /// Options for fixed steps of size `h` (see [`Options::fixed_step`]).
    pub fn fixed(h: f64) -> Self {
        Options::default().with_fixed_step(h)
    }

    /// Number of components whose `atol` is finite, i.e. that are
    /// error-controlled, out of `n`.
    pub(crate) fn controlled_components(&self, n: usize) -> usize {
        (0..n).filter(|&i| self.atol.get(i).is_finite()).count()
    }

    /// Checks that per-component tolerances have `dim` components.
    pub(crate) fn check_dim(&self, dim: usize) -> Result<(), OdeError> {
        for (field, tol) in [("rtol", &self.rtol), ("atol", &self.atol)] {
            if let Some(found) = tol.components()
                && found != dim
            {
                return Err(OdeError::DimensionMismatch {
                    field,
                    expected: dim,
                    found,
                });
            }
        }
        Ok(())
    }

    /// Checks every field; the error names the first offending field.
    /// (The length of per-component tolerances is checked by the
    /// integrators' constructors, which know the dimension.)
    pub fn validate(&self) -> Result<(), OdeError> {
        self.validate_tolerances()?;
        self.validate_step_sizes()?;
        self.validate_controller()
    }

    /// `rtol`, `atol` valid, and not both zero for any component.
    fn validate_tolerances(&self) -> Result<(), OdeError> {
        self.rtol.validate("rtol")?;
        self.atol.check("atol", true)?;
        let n = self
            .rtol
            .components()
            .unwrap_or(1)
            .max(self.atol.components().unwrap_or(1));
        for i in 0..n {
            if self.rtol.get(i) + self.atol.get(i) <= 0.0 {
                return Err(OdeError::InvalidOption {
                    field: "atol",
                    value: self.atol.get(i),
                    hint: "rtol and atol are both zero for a component; make atol > 0",
                });
            }
        }
        Ok(())
    }

    /// `h_init`, `h_max`, `h_min` and `max_steps`.
    fn validate_step_sizes(&self) -> Result<(), OdeError> {
        if let Some(h) = self.h_init
            && !(h.is_finite() && h > 0.0)
        {
            return bad(
                "h_init",
                h,
                "use a finite h_init > 0, or None for automatic",
            );
        }
        if self.h_max.is_nan() || self.h_max <= 0.0 {
            return bad(
                "h_max",
                self.h_max,
                "h_max must be > 0 (f64::INFINITY = no limit)",
            );
        }
        if !(self.h_min.is_finite() && self.h_min >= 0.0 && self.h_min <= self.h_max) {
            return bad(
                "h_min",
                self.h_min,
                "h_min must be finite, >= 0 and <= h_max",
            );
        }
        if let Some(h) = self.h_init
            && h < self.h_min
        {
            return bad("h_init", h, "h_init must be >= h_min");
        }
        if self.max_steps == 0 {
            return bad("max_steps", 0.0, "max_steps must be >= 1");
        }
        Ok(())
    }

    /// The step-size controller (`safety`, `fac_min`, `fac_max`, `beta`), then `fixed_step`.
    fn validate_controller(&self) -> Result<(), OdeError> {
        if !(self.safety > 0.0 && self.safety <= 1.0) {
            return bad(
                "safety",
                self.safety,
                "safety must be in (0, 1]; typical 0.9",
            );
        }
        if !(self.fac_min > 0.0 && self.fac_min <= 1.0) {
            return bad(
                "fac_min",
                self.fac_min,
                "fac_min must be in (0, 1]; typical 0.2",
            );
        }
        if !(self.fac_max >= 1.0 && self.fac_max.is_finite()) {
            return bad(
                "fac_max",
                self.fac_max,
                "fac_max must be finite and >= 1; typical 10",
            );
        }
        if let Some(b) = self.beta
            && !(0.0..=0.2).contains(&b)
        {
            return bad("beta", b, "beta must be in [0, 0.2]; typical 0.04");
        }
        if let Some(h) = self.fixed_step
            && !(h.is_finite() && h > 0.0)
        {
            return bad("fixed_step", h, "fixed_step must be finite and > 0");
        }
        Ok(())
    }
}

/// An [`OdeError::InvalidOption`] naming the field, its value and the rule.
fn bad(field: &'static str, value: f64, hint: &'static str) -> Result<(), OdeError> {
    Err(OdeError::InvalidOption { field, value, hint })
}
