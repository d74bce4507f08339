//! What a run records: stroboscopic states, dense samples, the event log.

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

/// Stroboscopic outputs at $t_k = k P$ ($P$ the forcing period; in general the model's
/// [`super::RotorModel::strobe_time`]) for `k` in `first..=last`.
///
/// `first > last` is an invalid option of [`super::simulate`] (not an empty output).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct StrobeRange {
    /// First index `k` (inclusive).
    pub first: u64,
    /// Last index `k` (inclusive, at least `first`).
    pub last: u64,
}

/// Dense samples at $t_\text{start} + i\thinspace\Delta t$, $i = 0, 1, \dots$, up to the end of
/// the run (phase portraits).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DenseSampling {
    /// Time of the first sample (samples before the run's start are skipped).
    pub t_start: f64,
    /// Interval $\Delta t$ between samples (finite, > 0).
    pub dt: f64,
}

/// Which outputs a run produces (all times absolute).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct OutputPlan {
    /// End time of the run.
    pub t_end: f64,
    /// Stroboscopic outputs; `None` for none.
    pub strobe: Option<StrobeRange>,
    /// Dense samples; `None` for none.
    pub dense: Option<DenseSampling>,
    /// Whether events are passed to the observer.
    pub events: bool,
}

impl OutputPlan {
    /// Stroboscopic outputs `k = first..=last`, nothing else; the run ends at the last.
    /// (`first > last` is rejected by [`super::simulate`].)
    pub fn strobe(period: f64, first: u64, last: u64) -> Self {
        Self {
            t_end: period * last as f64,
            strobe: Some(StrobeRange { first, last }),
            dense: None,
            events: false,
        }
    }

    /// Every stroboscopic output from `k = 0` up to `t_end`, with the event log: the plan of
    /// a run whose strobes are not equally spaced in time (a speed profile's revolutions,
    /// [`super::RotorModel::strobe_time`]).
    ///
    /// ```
    /// use jeffcott::hybrid::OutputPlan;
    /// let plan = OutputPlan::every_strobe(100.0);
    /// assert_eq!(plan.strobe.map(|s| s.first), Some(0));
    /// assert!(plan.events && plan.dense.is_none());
    /// ```
    pub fn every_strobe(t_end: f64) -> Self {
        Self {
            t_end,
            strobe: Some(StrobeRange {
                first: 0,
                last: u64::MAX - 1,
            }),
            dense: None,
            events: true,
        }
    }
}

/// A stroboscopic output: index `k`, time $t_k = kP$, state, mode label.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct StrobePoint<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Forcing periods since $t = 0$.
    pub k: u64,
    /// Time $t_k = kP$ (the model's [`super::RotorModel::strobe_time`]).
    pub t: f64,
    /// State at $t_k$ (its left limit if an event falls exactly there).
    pub y: OVector<f64, D>,
    /// Mode label at $t_k$ ([`super::RotorModel::mode_label`]; for the paper's model the
    /// regime, 1..=5 for I..V).
    pub label: u8,
}

/// A dense sample: time, state, its derivative and the mode label.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct Sample<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Time.
    pub t: f64,
    /// State.
    pub y: OVector<f64, D>,
    /// Time derivative of the state (for the ring: its velocity, with its jumps).
    pub dy: OVector<f64, D>,
    /// Mode label ([`super::RotorModel::mode_label`]).
    pub label: u8,
}

/// One entry of the event log.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct EventRecord<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Time of the event.
    pub t: f64,
    /// Guard name ([`super::RotorModel::guard_label`]).
    ///
    /// Read back with the `serde` feature, a name is interned: each distinct name is allocated
    /// once and kept for the life of the process (so the record stays `'static`-labelled).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::serde_util::label")
    )]
    pub kind: crate::StaticStr,
    /// State just before the transition.
    pub before: OVector<f64, D>,
    /// State just after the transition (equal unless the transition resets it).
    pub after: OVector<f64, D>,
    /// Mode label before.
    pub from: u8,
    /// Mode label after.
    pub to: u8,
}

/// Receives a run's outputs. Every method defaults to doing nothing.
///
/// The driver reuses the values it passes (no allocation per output): clone what you keep.
pub trait HybridObserver<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// A stroboscopic output.
    fn on_strobe(&mut self, point: &StrobePoint<D>) {
        let _ = point;
    }
    /// A dense sample.
    fn on_sample(&mut self, sample: &Sample<D>) {
        let _ = sample;
    }
    /// An event.
    fn on_event(&mut self, event: &EventRecord<D>) {
        let _ = event;
    }
    /// Whether the run should stop now: asked after every step (and every output of a mode
    /// in closed form). `true` ends the run with [`SimErrorKind::Stopped`](super::SimErrorKind::Stopped)
    /// at the last good point, with what was recorded kept here: how a caller stops a long
    /// run on a user's request (Ctrl-C) without cutting it into pieces. Default: never.
    fn should_stop(&mut self) -> bool {
        false
    }
}

impl<D: Dim> HybridObserver<D> for () where DefaultAllocator: Allocator<D> {}

/// Records everything in memory.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct Trajectory<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Stroboscopic outputs, in time order.
    pub strobe: Vec<StrobePoint<D>>,
    /// Dense samples, in time order.
    pub samples: Vec<Sample<D>>,
    /// Event log, in time order.
    pub events: Vec<EventRecord<D>>,
}

impl<D: Dim> Default for Trajectory<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn default() -> Self {
        Self {
            strobe: Vec::new(),
            samples: Vec::new(),
            events: Vec::new(),
        }
    }
}

impl<D: Dim> HybridObserver<D> for Trajectory<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn on_strobe(&mut self, point: &StrobePoint<D>) {
        self.strobe.push(point.clone());
    }
    fn on_sample(&mut self, sample: &Sample<D>) {
        self.samples.push(sample.clone());
    }
    fn on_event(&mut self, event: &EventRecord<D>) {
        self.events.push(event.clone());
    }
}

// Fixed sizes keep `Copy`.
impl<D: Dim> Copy for StrobePoint<D>
where
    DefaultAllocator: Allocator<D>,
    OVector<f64, D>: Copy,
{
}

impl<D: Dim> Copy for Sample<D>
where
    DefaultAllocator: Allocator<D>,
    OVector<f64, D>: Copy,
{
}

impl<D: Dim> Copy for EventRecord<D>
where
    DefaultAllocator: Allocator<D>,
    OVector<f64, D>: Copy,
{
}
