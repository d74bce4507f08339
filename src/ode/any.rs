//! Run-time choice of the integration method.

use super::{Dop853, Dopri5, Etd4, Integrator, OdeError, OdeSystem, Options, Radau5, Rk4, Stats};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, DimName, OVector};

/// Run-time choice of integration method.
// serde always, not only with the feature: the sweeps of `global` record it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
pub enum Method {
    /// [`Dop853`].
    Dop853,
    /// [`Dopri5`].
    Dopri5,
    /// [`Rk4`] (needs [`Options::fixed_step`]).
    Rk4,
    /// [`Radau5`], implicit, for stiff problems (refuses [`Options::fixed_step`]).
    Radau5,
    /// [`Etd4`], exponential, for systems with a diagonal linear part
    /// ([`OdeSystem::linear_part`]; refuses [`Options::fixed_step`]). Not in
    /// [`Method::ALL`], which lists the methods for any system.
    Etd4,
}

impl Method {
    /// The methods for any system (every method but [`Method::Etd4`]).
    pub const ALL: [Method; 4] = [Method::Dop853, Method::Dopri5, Method::Rk4, Method::Radau5];

    /// Name for reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Dop853 => "DOP853",
            Method::Dopri5 => "DOPRI5",
            Method::Rk4 => "RK4",
            Method::Radau5 => "RADAU5",
            Method::Etd4 => "ETD4",
        }
    }

    /// Whether the method is implicit and L-stable (RADAU5): its steps are not limited by the
    /// fast components' stability, which an explicit method's error test guards.
    pub fn is_implicit(self) -> bool {
        matches!(self, Method::Radau5)
    }

    /// Interior samples per step at which the event detector reads the guards on this
    /// method's dense output, unless a run asks for others: 3 for ETD4, at the step's quarters,
    /// where its dense output reuses the $\varphi$-functions its step computed instead of
    /// evaluating its own; 4 for the others (at fifths).
    pub fn event_samples(self) -> usize {
        match self {
            Method::Etd4 => 3,
            Method::Dop853 | Method::Dopri5 | Method::Rk4 | Method::Radau5 => 4,
        }
    }

    /// Classical order of the propagating formula (8, 5, 4, 5, 4).
    pub fn order(self) -> u32 {
        match self {
            Method::Dop853 => 8,
            Method::Dopri5 => 5,
            Method::Rk4 => 4,
            Method::Radau5 => 5,
            Method::Etd4 => 4,
        }
    }
}

/// Enum dispatch over the integrators, so the method can be chosen at run
/// time without trait objects (the trait has generic methods).
#[derive(Debug, Clone)]
pub enum AnyIntegrator<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// DOP853.
    Dop853(Dop853<D>),
    /// DOPRI5.
    Dopri5(Dopri5<D>),
    /// RK4.
    Rk4(Rk4<D>),
    /// RADAU5 (boxed: its state is several times larger than the explicit methods').
    Radau5(Box<Radau5<D>>),
    /// ETD4 (boxed, as RADAU5).
    Etd4(Box<Etd4<D>>),
}

impl<D: DimName> AnyIntegrator<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Builds the integrator of `method` for a fixed dimension, validating
    /// `options`.
    pub fn new(method: Method, options: Options<D>) -> Result<Self, OdeError> {
        Self::with_dim(method, D::name(), options)
    }
}

impl<D: Dim> AnyIntegrator<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Builds the integrator of `method` for dimension `dim` (e.g. `Dyn(n)`),
    /// validating `options`.
    pub fn with_dim(method: Method, dim: D, options: Options<D>) -> Result<Self, OdeError> {
        Ok(match method {
            Method::Dop853 => AnyIntegrator::Dop853(Dop853::with_dim(dim, options)?),
            Method::Dopri5 => AnyIntegrator::Dopri5(Dopri5::with_dim(dim, options)?),
            Method::Rk4 => AnyIntegrator::Rk4(Rk4::with_dim(dim, options)?),
            Method::Radau5 => AnyIntegrator::Radau5(Box::new(Radau5::with_dim(dim, options)?)),
            Method::Etd4 => AnyIntegrator::Etd4(Box::new(Etd4::with_dim(dim, options)?)),
        })
    }

    /// The method of this integrator.
    pub fn method(&self) -> Method {
        match self {
            AnyIntegrator::Dop853(_) => Method::Dop853,
            AnyIntegrator::Dopri5(_) => Method::Dopri5,
            AnyIntegrator::Rk4(_) => Method::Rk4,
            AnyIntegrator::Radau5(_) => Method::Radau5,
            AnyIntegrator::Etd4(_) => Method::Etd4,
        }
    }
}

macro_rules! dispatch {
    ($self:expr, $i:ident => $e:expr) => {
        match $self {
            AnyIntegrator::Dop853($i) => $e,
            AnyIntegrator::Dopri5($i) => $e,
            AnyIntegrator::Rk4($i) => $e,
            AnyIntegrator::Radau5($i) => $e,
            AnyIntegrator::Etd4($i) => $e,
        }
    };
}

impl<D: Dim> Integrator<D> for AnyIntegrator<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn reset<S: OdeSystem<D>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &OVector<f64, D>,
        keep_step: bool,
    ) -> Result<(), OdeError> {
        dispatch!(self, i => i.reset(sys, t, y, keep_step))
    }
    fn step<S: OdeSystem<D>>(&mut self, sys: &S, t_bound: f64) -> Result<(), OdeError> {
        dispatch!(self, i => i.step(sys, t_bound))
    }
    fn t(&self) -> f64 {
        dispatch!(self, i => i.t())
    }
    fn y(&self) -> &OVector<f64, D> {
        dispatch!(self, i => i.y())
    }
    fn t_prev(&self) -> f64 {
        dispatch!(self, i => i.t_prev())
    }
    fn y_prev(&self) -> &OVector<f64, D> {
        dispatch!(self, i => i.y_prev())
    }
    fn dense<S: OdeSystem<D>>(&mut self, sys: &S, t: f64, out: &mut OVector<f64, D>) {
        dispatch!(self, i => i.dense(sys, t, out))
    }
    fn truncate<S: OdeSystem<D>>(&mut self, sys: &S, t_new: f64) -> Result<(), OdeError> {
        dispatch!(self, i => i.truncate(sys, t_new))
    }
    fn stats(&self) -> &Stats {
        dispatch!(self, i => i.stats())
    }
    fn stats_mut(&mut self) -> &mut Stats {
        dispatch!(self, i => i.stats_mut())
    }
    fn options(&self) -> &Options<D> {
        dispatch!(self, i => i.options())
    }
    fn h_next(&self) -> f64 {
        dispatch!(self, i => i.h_next())
    }
    fn name(&self) -> &'static str {
        dispatch!(self, i => i.name())
    }
    fn dim(&self) -> D {
        dispatch!(self, i => i.dim())
    }
    fn dy(&self) -> Option<&OVector<f64, D>> {
        dispatch!(self, i => i.dy())
    }
    fn dy_prev(&self) -> Option<&OVector<f64, D>> {
        dispatch!(self, i => i.dy_prev())
    }
}
