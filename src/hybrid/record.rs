//! What a run records: stroboscopic states, dense samples, the event log.

use nalgebra::SVector;

/// Which outputs a run produces (all times absolute).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OutputPlan {
    /// End time of the run.
    pub t_end: f64,
    /// Stroboscopic outputs at $t_k = k P$ ($P$ the forcing period) for
    /// `k` in `strobe_first..=strobe_last`; `None` for none.
    pub strobe: Option<(u64, u64)>,
    /// Dense samples every `dt` from `t_start` on (phase portraits); `None` for none.
    pub dense: Option<(f64, f64)>,
    /// Whether events are passed to the observer.
    pub events: bool,
}

impl OutputPlan {
    /// Stroboscopic outputs `k = first..=last`, nothing else; the run ends at the last.
    pub fn strobe(period: f64, first: u64, last: u64) -> Self {
        Self {
            t_end: period * last as f64,
            strobe: Some((first, last)),
            dense: None,
            events: false,
        }
    }
}

/// A dense sample: time, state, its derivative and the mode label.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample<const N: usize> {
    /// Time.
    pub t: f64,
    /// State.
    pub y: SVector<f64, N>,
    /// Time derivative of the state (for the ring: its velocity, with its jumps).
    pub dy: SVector<f64, N>,
    /// Mode label ([`super::RotorModel::mode_label`]).
    pub label: u8,
}

/// One entry of the event log.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EventRecord<const N: usize> {
    /// Time of the event.
    pub t: f64,
    /// Guard name ([`super::RotorModel::guard_label`]).
    pub kind: &'static str,
    /// State just before the transition.
    pub before: SVector<f64, N>,
    /// State just after the transition (equal unless the transition resets it).
    pub after: SVector<f64, N>,
    /// Mode label before.
    pub from: u8,
    /// Mode label after.
    pub to: u8,
}

/// Receives a run's outputs. Every method defaults to doing nothing.
pub trait HybridObserver<const N: usize> {
    /// Stroboscopic output `k` at time `t` (the state's left limit if an event is exactly there).
    fn on_strobe(&mut self, k: u64, t: f64, y: &SVector<f64, N>, label: u8) {
        let _ = (k, t, y, label);
    }
    /// A dense sample.
    fn on_sample(&mut self, sample: &Sample<N>) {
        let _ = sample;
    }
    /// An event.
    fn on_event(&mut self, event: &EventRecord<N>) {
        let _ = event;
    }
}

impl<const N: usize> HybridObserver<N> for () {}

/// Records everything in memory.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Trajectory<const N: usize> {
    /// Stroboscopic outputs `(k, t, y, label)`.
    pub strobe: Vec<(u64, f64, SVector<f64, N>, u8)>,
    /// Dense samples.
    pub samples: Vec<Sample<N>>,
    /// Event log.
    pub events: Vec<EventRecord<N>>,
}

impl<const N: usize> HybridObserver<N> for Trajectory<N> {
    fn on_strobe(&mut self, k: u64, t: f64, y: &SVector<f64, N>, label: u8) {
        self.strobe.push((k, t, *y, label));
    }
    fn on_sample(&mut self, sample: &Sample<N>) {
        self.samples.push(*sample);
    }
    fn on_event(&mut self, event: &EventRecord<N>) {
        self.events.push(*event);
    }
}
