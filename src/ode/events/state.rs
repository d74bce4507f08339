//! What the event detector keeps between calls.

use super::{Direction, EventHit};
use crate::ode::core::zeros;
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

/// Per-event bookkeeping of one scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Slot {
    pub active: bool,
    pub has_der: bool,
    /// Whether sign changes count (see the re-arming rule).
    pub armed: bool,
    /// Reference value: $g$ at the left end of the current sample interval.
    pub g_ref: f64,
    /// $\dot g$ at the same point (0 if unknown).
    pub d_ref: f64,
    /// $g$ at the segment origin.
    pub g_origin: f64,
    /// How the guard may leave zero at the origin (start-of-segment rule).
    pub leave: Leave,
    /// Its derivative reads `dy` ([`EventSet::derivative_needs_rhs_of`](super::EventSet::derivative_needs_rhs_of)).
    pub needs_rhs: bool,
    /// NaN at the right end of the current sample interval.
    pub nan: bool,
    /// $g$ and $\dot g$ (0 if unknown) at the right end of the current sample interval.
    pub end: (f64, f64),
}

/// Whether a guard may have left zero at the segment origin.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Leave {
    /// Not on zero (or not at the origin, or the event that just fired).
    No,
    /// On zero and moving towards this sign (from the derivative).
    Towards(f64),
    /// Unknown without a derivative: the probe decides when it matters.
    Probe,
}

impl Default for Slot {
    fn default() -> Self {
        Slot {
            active: false,
            has_der: false,
            armed: false,
            g_ref: 0.0,
            d_ref: 0.0,
            g_origin: f64::NAN,
            leave: Leave::No,
            needs_rhs: false,
            nan: false,
            end: (f64::NAN, 0.0),
        }
    }
}

/// Bookkeeping of the detector between calls: the segment origin (for the
/// re-arming rule, see [`ode`, Events](crate::ode#events)), where to resume after a hit
/// inside the current step, per-event data sized from the event set, scratch
/// vectors, and the last hit.
///
/// The scratch has the integrator's dimension: allocated by
/// [`EventState::with_dim`], or on the first call of
/// [`find_first_event`](super::find_first_event) (for fixed dimensions
/// [`EventState::new`] already has it, on the stack). The per-event data grows
/// when a set larger than any seen before arrives. In steady state nothing is
/// allocated.
#[derive(Debug, Clone)]
pub struct EventState<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Time of the segment origin; `None` = the left end of the next scanned
    /// step.
    pub(super) origin: Option<f64>,
    /// `(t_prev, t_hit)` of the last hit: scanning of a step with the same
    /// `t_prev` resumes at `t_hit`.
    pub(super) resume: Option<(f64, f64)>,
    /// Index and direction of the last hit (cleared by `reset`).
    pub(super) last_hit: Option<(usize, Direction)>,
    pub(super) slots: Vec<Slot>,
    pub(super) scratch: Scratch<D>,
    pub(super) hit: EventHit<D>,
}

/// Scratch vectors of one scan.
#[derive(Debug, Clone)]
pub(super) struct Scratch<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    pub y_a: OVector<f64, D>,
    pub f_a: OVector<f64, D>,
    pub y_b: OVector<f64, D>,
    pub f_b: OVector<f64, D>,
    /// The dense output at the probe point.
    pub y_p: OVector<f64, D>,
    pub tmp: OVector<f64, D>,
    pub f_c: OVector<f64, D>,
    /// Always zero: the `dy` passed to derivatives that do not need it.
    pub zero: OVector<f64, D>,
}

impl<D: Dim> Scratch<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn new(dim: D) -> Self {
        let z = zeros(dim);
        Scratch {
            y_a: z.clone(),
            f_a: z.clone(),
            y_b: z.clone(),
            f_b: z.clone(),
            y_p: z.clone(),
            tmp: z.clone(),
            f_c: z.clone(),
            zero: z,
        }
    }
}

impl<D: Dim> Default for EventState<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn default() -> Self {
        Self::new()
    }
}

impl<D: Dim> EventState<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Fresh state: the left end of the next scanned step is a segment
    /// origin. For `Dyn` the scratch is allocated on first use (use
    /// [`EventState::with_dim`] to allocate it now).
    pub fn new() -> Self {
        // Fixed dimensions know their size; Dyn starts empty.
        Self::with_dim(D::from_usize(D::try_to_usize().unwrap_or(0)))
    }

    /// Fresh state with scratch for dimension `dim` (e.g. `Dyn(n)`) and room
    /// for a few events, allocated now.
    pub fn with_dim(dim: D) -> Self {
        EventState {
            origin: None,
            resume: None,
            last_hit: None,
            slots: Vec::with_capacity(4),
            scratch: Scratch::new(dim),
            hit: EventHit {
                index: 0,
                t: f64::NAN,
                y: zeros(dim),
                direction: Direction::Either,
            },
        }
    }

    /// Call after [`Integrator::reset`](crate::ode::Integrator::reset): the
    /// next scanned step starts a new segment (its left end is the origin)
    /// and nothing is resumed. Keeps the scratch (no allocation).
    pub fn reset(&mut self) {
        self.origin = None;
        self.resume = None;
        self.last_hit = None;
    }

    /// The current segment origin, if fixed.
    pub fn origin(&self) -> Option<f64> {
        self.origin
    }

    /// The last hit returned (its `t` is NaN before the first one).
    pub fn hit(&self) -> &EventHit<D> {
        &self.hit
    }

    /// Makes the scratch fit dimension `dim` and `events` events; allocates
    /// only when they do not fit yet.
    pub(super) fn prepare(&mut self, dim: D, events: usize) {
        if self.scratch.y_a.len() != dim.value() {
            self.scratch = Scratch::new(dim);
            self.hit.y = zeros(dim);
        }
        if self.slots.len() < events {
            self.slots.resize(events, Slot::default());
        }
    }
}
