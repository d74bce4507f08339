//! Event sets given as closures.

use super::{Direction, EventSet};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};
use std::marker::PhantomData;

/// An [`EventSet`] built from closures: one [`Direction`] per event and a
/// function `|i, t, y| -> f64` giving $g_i(t, y)$; optionally the derivative
/// along the flow `|i, t, y, dy| -> f64` (grazing detection, direction of a
/// guard that starts on zero) and per-event terminal flags (default: every
/// event is terminal).
///
/// # Example
///
/// A ball bouncing on a floor (event 0, falling through $x = 0$) and passing
/// the height $0.3$ on the way up (event 1, not terminal), with the
/// derivative of both from the state:
///
/// ```
/// use jeffcott::ode::{solve, Dop853, EventFns, Options, Recorder, Stopped};
/// use jeffcott::numeric::Direction;
/// use nalgebra::SVector;
/// type V2 = SVector<f64, 2>;
///
/// let ball = |_t: f64, y: &V2, dy: &mut V2| {
///     dy[0] = y[1];
///     dy[1] = -1.0;
/// };
/// let events = EventFns::new([Direction::Falling, Direction::Rising], |i, _t, y: &V2| {
///     if i == 0 { y[0] } else { y[0] - 0.3 }
/// })
/// .with_derivative(|_i, _t, y: &V2, _dy: &V2| y[1])
/// .derivative_from_state()
/// .terminal([true, false]);
///
/// let mut integ = Dop853::new(Options::with_tol(1e-12, 1e-12))?;
/// let mut rec = Recorder::default();
/// // Thrown up from the floor with speed 1: above 0.3 at t = 1 - sqrt(0.4).
/// let rep = solve(&mut integ, &ball, 0.0, &V2::new(0.0, 1.0), 5.0, &events, &mut rec)?;
/// assert_eq!(rep.stopped, Stopped::Event(0, rep.t));
/// assert!((rep.t - 2.0).abs() < 1e-12);
/// assert!((rec.events[0].t - (1.0 - 0.4f64.sqrt())).abs() < 1e-12);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct EventFns<D, G, H = NoDerivative> {
    directions: Vec<Direction>,
    terminal: Vec<bool>,
    value: G,
    derivative: H,
    needs_rhs: bool,
    _dim: PhantomData<fn() -> D>,
}

/// The derivative of an [`EventFns`] set: [`NoDerivative`], or a closure
/// `|i, t, y, dy| -> f64` returning $\dot g_i$.
pub trait EventDerivative<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// $\dot g_i(t, y)$ given $\dot y$ = `dy`, or `None` if not available.
    fn eval(&self, i: usize, t: f64, y: &OVector<f64, D>, dy: &OVector<f64, D>) -> Option<f64>;
}

/// No derivative (the default of [`EventFns`]).
#[derive(Debug, Clone, Copy, Default)]
pub struct NoDerivative;

impl<D: Dim> EventDerivative<D> for NoDerivative
where
    DefaultAllocator: Allocator<D>,
{
    fn eval(&self, _: usize, _: f64, _: &OVector<f64, D>, _: &OVector<f64, D>) -> Option<f64> {
        None
    }
}

impl<D: Dim, F> EventDerivative<D> for F
where
    DefaultAllocator: Allocator<D>,
    F: Fn(usize, f64, &OVector<f64, D>, &OVector<f64, D>) -> f64,
{
    #[inline]
    fn eval(&self, i: usize, t: f64, y: &OVector<f64, D>, dy: &OVector<f64, D>) -> Option<f64> {
        Some(self(i, t, y, dy))
    }
}

impl<D: Dim, G> EventFns<D, G, NoDerivative>
where
    DefaultAllocator: Allocator<D>,
    G: Fn(usize, f64, &OVector<f64, D>) -> f64,
{
    /// Events `i < directions.len()` with $g_i(t, y)$ = `value(i, t, y)`,
    /// all terminal, without derivative.
    pub fn new(directions: impl Into<Vec<Direction>>, value: G) -> Self {
        EventFns {
            directions: directions.into(),
            terminal: Vec::new(),
            value,
            derivative: NoDerivative,
            needs_rhs: true,
            _dim: PhantomData,
        }
    }
}

impl<D: Dim, G, H> EventFns<D, G, H>
where
    DefaultAllocator: Allocator<D>,
{
    /// Adds the derivative $\dot g_i$ = `derivative(i, t, y, dy)` along the
    /// flow ($\dot y$ = `dy`).
    pub fn with_derivative<H2>(self, derivative: H2) -> EventFns<D, G, H2>
    where
        H2: Fn(usize, f64, &OVector<f64, D>, &OVector<f64, D>) -> f64,
    {
        EventFns {
            directions: self.directions,
            terminal: self.terminal,
            value: self.value,
            derivative,
            needs_rhs: self.needs_rhs,
            _dim: PhantomData,
        }
    }

    /// Declares that the derivative does not read `dy`
    /// ([`EventSet::derivative_needs_rhs`] is `false`): saves a right-hand
    /// side per sample.
    pub fn derivative_from_state(mut self) -> Self {
        self.needs_rhs = false;
        self
    }

    /// Per-event terminal flags (events beyond the list are terminal).
    pub fn terminal(mut self, terminal: impl Into<Vec<bool>>) -> Self {
        self.terminal = terminal.into();
        self
    }

    /// Makes every event non-terminal.
    pub fn non_terminal(mut self) -> Self {
        self.terminal = vec![false; self.directions.len()];
        self
    }
}

impl<D: Dim, G, H> EventSet<D> for EventFns<D, G, H>
where
    DefaultAllocator: Allocator<D>,
    G: Fn(usize, f64, &OVector<f64, D>) -> f64,
    H: EventDerivative<D>,
{
    fn len(&self) -> usize {
        self.directions.len()
    }
    fn direction(&self, i: usize) -> Direction {
        self.directions.get(i).copied().unwrap_or(Direction::Either)
    }
    fn terminal(&self, i: usize) -> bool {
        self.terminal.get(i).copied().unwrap_or(true)
    }
    fn value(&self, i: usize, t: f64, y: &OVector<f64, D>) -> f64 {
        (self.value)(i, t, y)
    }
    fn derivative(
        &self,
        i: usize,
        t: f64,
        y: &OVector<f64, D>,
        dy: &OVector<f64, D>,
    ) -> Option<f64> {
        self.derivative.eval(i, t, y, dy)
    }
    fn derivative_needs_rhs(&self) -> bool {
        self.needs_rhs
    }
}
