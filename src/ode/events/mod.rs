//! Event functions, their detection on the dense output of the last step and root location:
//! the rules are written out in the [`ode`](super) module docs, "Events".

mod closures;
mod detect;
mod state;

pub use closures::{EventDerivative, EventFns, NoDerivative};
pub use detect::find_first_event;
pub use state::EventState;

use super::OdeError;
use crate::numeric::Direction;
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

/// Maximum number of interior samples per step
/// ([`EventOptions::samples_per_step`]).
pub const MAX_SAMPLES: usize = 64;

/// A set of event functions $g_i(t, y)$, $i <$ `len()` (any number: the
/// detector's bookkeeping grows with the largest set it has seen).
pub trait EventSet<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Number of events.
    fn len(&self) -> usize;
    /// Whether the set is empty.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// Allowed crossing direction of event `i`.
    fn direction(&self, i: usize) -> Direction;
    /// Whether event `i` stops the integration ([`solve`](super::solve())).
    fn terminal(&self, i: usize) -> bool {
        let _ = i;
        true
    }
    /// Value $g_i(t, y)$.
    fn value(&self, i: usize, t: f64, y: &OVector<f64, D>) -> f64;
    /// Optional time derivative of event `i` along the flow,
    /// $\dot g_i = \partial_t g_i + \nabla_y g_i \cdot \dot y$, given `y` and
    /// `dy` $= f(t, y)$; enables detection of grazing (two roots inside one
    /// sample interval without a sign change) and gives the direction of a
    /// guard that is zero at the start of a segment. Must return `None` for
    /// every argument when not available (the detector asks at the start of
    /// every scanned step).
    fn derivative(
        &self,
        i: usize,
        t: f64,
        y: &OVector<f64, D>,
        dy: &OVector<f64, D>,
    ) -> Option<f64> {
        let _ = (i, t, y, dy);
        None
    }
    /// Whether [`EventSet::derivative`] reads its `dy` argument. When `false`
    /// the detector does not evaluate $f$ at the samples (saving one
    /// right-hand side per sample) and passes zeros as `dy`: return `false`
    /// when the derivatives are computed from `y` alone (e.g. a mechanical
    /// system whose velocities are part of the state).
    fn derivative_needs_rhs(&self) -> bool {
        true
    }
    /// Whether the derivative of event `i` reads its `dy` argument (default:
    /// [`EventSet::derivative_needs_rhs`] for every event). A set whose
    /// events differ (one derivative needs $f$, the others only $y$) saves the
    /// rhs evaluations at the samples of steps where only the others are
    /// sampled.
    fn derivative_needs_rhs_of(&self, i: usize) -> bool {
        let _ = i;
        self.derivative_needs_rhs()
    }
    /// Every active event's value and, if `with_derivatives`, its derivative (as
    /// [`EventSet::derivative`] returns it) at one point: calls `out(i, value, derivative)`
    /// for each active `i` in increasing order. `dy` is $f(t, y)$ (the detector calls this at
    /// a step's ends, where it has $f$ for free) or zeros when no event's derivative reads it.
    /// The default calls [`EventSet::value`] and [`EventSet::derivative`]; a set whose events
    /// share work (a contact location) can evaluate them together, with the same numbers.
    fn values_and_derivatives(
        &self,
        t: f64,
        y: &OVector<f64, D>,
        dy: &OVector<f64, D>,
        with_derivatives: bool,
        out: &mut dyn FnMut(usize, f64, Option<f64>),
    ) {
        for i in 0..self.len() {
            if self.active(i) {
                let d = if with_derivatives {
                    self.derivative(i, t, y, dy)
                } else {
                    None
                };
                out(i, self.value(i, t, y), d);
            }
        }
    }
    /// Whether event `i` is currently active (lets a model switch events off
    /// without reallocating).
    fn active(&self, i: usize) -> bool {
        let _ = i;
        true
    }
}

/// The empty event set.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoEvents;

impl<D: Dim> EventSet<D> for NoEvents
where
    DefaultAllocator: Allocator<D>,
{
    fn len(&self) -> usize {
        0
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Either
    }
    fn value(&self, _i: usize, _t: f64, _y: &OVector<f64, D>) -> f64 {
        1.0
    }
}

/// A located event. [`find_first_event`] returns a reference to the hit held
/// by the [`EventState`] (no allocation); clone it to keep it (`Copy` for
/// fixed dimensions).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct EventHit<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Index of the event in its set.
    pub index: usize,
    /// Event time (post-crossing end of the final bracket).
    pub t: f64,
    /// Dense-output state at `t`.
    pub y: OVector<f64, D>,
    /// Direction of the crossing: `Rising` or `Falling`.
    pub direction: Direction,
}

impl<D: Dim> Copy for EventHit<D>
where
    DefaultAllocator: Allocator<D>,
    OVector<f64, D>: Copy,
{
}

/// Options of the event detector. Every entry point that takes them
/// ([`find_first_event`], [`solve_with`](super::solve_with)) validates them
/// first ([`EventOptions::validate`]).
///
/// Start from [`Default`] and change fields with the `with_` builders, e.g.
/// `EventOptions::default().with_samples_per_step(8)`. The
/// fields are public for reading; the struct is `#[non_exhaustive]`, so it
/// cannot be built by a struct literal outside the crate.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct EventOptions {
    /// Interior dense-output samples per step, in `1..=`[`MAX_SAMPLES`]
    /// (others are an [`OdeError::InvalidOption`]). Default `4`.
    pub samples_per_step: usize,
    /// Time tolerance of the root finder (units of $t$); the effective
    /// tolerance is $\max(\text{root\\_tol}, 4\varepsilon|t|)$, i.e. about 4
    /// ulp for the default `0`.
    pub root_tol: f64,
    /// Values with $|g| \le$ `value_tol` at the segment origin count as zero
    /// (the event takes the sign of its motion, see the module docs).
    /// Default `0`.
    pub value_tol: f64,
    /// Re-arm window after the segment origin (units of $t$), see the module
    /// docs; the effective window is $\max(\text{rearm\\_time}, 2\thinspace\text{tol})$.
    /// Default `0`.
    pub rearm_time: f64,
    /// Maximum iterations of each root/extremum search (>= 1). Default `200`.
    pub max_iter: usize,
}

impl Default for EventOptions {
    fn default() -> Self {
        EventOptions {
            samples_per_step: 4,
            root_tol: 0.0,
            value_tol: 0.0,
            rearm_time: 0.0,
            max_iter: 200,
        }
    }
}

/// Builders: each returns the options with one field changed (the value is
/// checked by [`EventOptions::validate`]).
impl EventOptions {
    /// With [`samples_per_step`](Self::samples_per_step) = `value`.
    #[must_use]
    pub fn with_samples_per_step(mut self, value: usize) -> Self {
        self.samples_per_step = value;
        self
    }

    /// With [`root_tol`](Self::root_tol) = `value`.
    #[must_use]
    pub fn with_root_tol(mut self, value: f64) -> Self {
        self.root_tol = value;
        self
    }

    /// With [`value_tol`](Self::value_tol) = `value`.
    #[must_use]
    pub fn with_value_tol(mut self, value: f64) -> Self {
        self.value_tol = value;
        self
    }

    /// With [`rearm_time`](Self::rearm_time) = `value`.
    #[must_use]
    pub fn with_rearm_time(mut self, value: f64) -> Self {
        self.rearm_time = value;
        self
    }

    /// With [`max_iter`](Self::max_iter) = `value`.
    #[must_use]
    pub fn with_max_iter(mut self, value: usize) -> Self {
        self.max_iter = value;
        self
    }
}

impl EventOptions {
    /// Checks the fields; the error names the offending field.
    pub fn validate(&self) -> Result<(), OdeError> {
        let check = |field: &'static str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(OdeError::InvalidOption {
                    field,
                    value: v,
                    hint: "event tolerances must be finite and >= 0 (0 = automatic)",
                })
            }
        };
        check("root_tol", self.root_tol)?;
        check("value_tol", self.value_tol)?;
        check("rearm_time", self.rearm_time)?;
        if self.samples_per_step == 0 || self.samples_per_step > MAX_SAMPLES {
            return Err(OdeError::InvalidOption {
                field: "samples_per_step",
                value: self.samples_per_step as f64,
                hint: "samples_per_step must be in 1..=MAX_SAMPLES (64); typical 4",
            });
        }
        if self.max_iter == 0 {
            return Err(OdeError::InvalidOption {
                field: "max_iter",
                value: 0.0,
                hint: "max_iter must be >= 1; typical 200",
            });
        }
        Ok(())
    }
}
