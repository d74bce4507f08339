use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

use super::{section_crossings_hermite, AnalysisError, Crossing};
use crate::hybrid::{
    simulate, DenseSampling, EventRecord, OutputPlan, RotorModel, Sample, SimError, SimErrorKind,
    SimOptions, SimStats, Trajectory,
};
use crate::numeric::Direction;

/// Dense samples of a run and its event log: a phase portrait that knows where it jumps.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct PhasePortrait<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// Samples every `dt` in `[t_start, t_end]`, with the state's derivative (for the paper's
    /// model `dy[4]`, `dy[5]` are the ring's velocity).
    pub samples: Vec<Sample<D>>,
    /// Every transition in `[0, t_end]` (mode changes; derivatives may jump there).
    pub events: Vec<EventRecord<D>>,
    /// Work done by the run.
    pub stats: SimStats,
}

impl<D: Dim> PhasePortrait<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// The samples split into smooth pieces at the event times: no piece contains an event
    /// strictly between two of its samples, so a curve drawn through a piece never bridges a
    /// velocity jump. Empty pieces are dropped.
    pub fn pieces(&self) -> Vec<&[Sample<D>]> {
        let mut out = Vec::new();
        let mut start = 0;
        let mut ev = self.events.iter().map(|e| e.t).peekable();
        for i in 1..self.samples.len() {
            let (a, b) = (self.samples[i - 1].t, self.samples[i].t);
            let mut split = false;
            while let Some(&te) = ev.peek() {
                if te <= a {
                    ev.next();
                } else {
                    if te < b {
                        split = true;
                    }
                    break;
                }
            }
            if split {
                out.push(&self.samples[start..i]);
                start = i;
            }
        }
        if start < self.samples.len() {
            out.push(&self.samples[start..]);
        }
        out
    }

    /// A curve per smooth piece, mapping each sample with `f` (e.g. `|s| (s.y[4], s.dy[4])`
    /// for the ring's $(x_s, x_s^\prime)$ in the paper's model).
    pub fn curves<F: Fn(&Sample<D>) -> (f64, f64)>(&self, f: F) -> Vec<Vec<(f64, f64)>> {
        self.pieces()
            .into_iter()
            .map(|p| p.iter().map(&f).collect())
            .collect()
    }

    /// All samples as one curve with a `(NaN, NaN)` point between smooth pieces (what line
    /// plotters that break at NaN expect).
    pub fn broken_curve<F: Fn(&Sample<D>) -> (f64, f64)>(&self, f: F) -> Vec<(f64, f64)> {
        let mut out = Vec::with_capacity(self.samples.len() + self.events.len());
        for (i, piece) in self.curves(f).into_iter().enumerate() {
            if i > 0 {
                out.push((f64::NAN, f64::NAN));
            }
            out.extend(piece);
        }
        out
    }

    /// Crossings of the section $h(t, y) = 0$ in `direction` (a Poincaré section of the
    /// run), located by [`section_crossings_hermite`] on each smooth piece, so that no
    /// interpolant spans a jump. `Crossing::interval` indexes [`PhasePortrait::samples`].
    /// A crossing that falls between the last sample before an event and the first one after
    /// it is not reported: sample densely enough.
    ///
    /// # Errors
    /// As [`section_crossings_hermite`] (e.g. `h` returning NaN).
    pub fn crossings<H>(
        &self,
        section: H,
        direction: Direction,
    ) -> Result<Vec<Crossing>, AnalysisError>
    where
        H: Fn(f64, &[f64]) -> f64,
    {
        let mut out = Vec::new();
        let mut offset = 0;
        for piece in self.pieces() {
            let times: Vec<f64> = piece.iter().map(|s| s.t).collect();
            let states: Vec<&[f64]> = piece.iter().map(|s| s.y.as_slice()).collect();
            let derivs: Vec<&[f64]> = piece.iter().map(|s| s.dy.as_slice()).collect();
            let found = section_crossings_hermite(&times, &states, &derivs, &section, direction)?;
            out.extend(found.into_iter().map(|mut c| {
                c.interval += offset;
                c
            }));
            offset += piece.len();
        }
        Ok(out)
    }
}

/// Runs `model` from `y0` at $t = 0$ to `t_end`, sampling every `dt` from `t_start` on, and
/// logging events.
///
/// # Errors
/// The driver's [`SimError`], also for an invalid `dt`, `t_start` or `t_end`
/// ([`SimErrorKind::InvalidOption`]; `t_end < t_start` is one).
pub fn phase_portrait<M: RotorModel>(
    model: &M,
    y0: &OVector<f64, M::Dim>,
    t_start: f64,
    t_end: f64,
    dt: f64,
    opts: &SimOptions,
) -> Result<PhasePortrait<M::Dim>, SimError<M::Dim>>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    let bad = |field: &'static str, value: f64, hint: &'static str| SimError {
        kind: SimErrorKind::InvalidOption { field, value, hint },
        t: 0.0,
        y: y0.clone(),
        stats: Box::default(),
    };
    if !(dt.is_finite() && dt > 0.0) {
        return Err(bad("dt", dt, "a finite sampling step > 0"));
    }
    if !(t_start.is_finite() && t_start >= 0.0) {
        return Err(bad("t_start", t_start, "a finite start time >= 0"));
    }
    if !(t_end.is_finite() && t_end >= t_start) {
        return Err(bad("t_end", t_end, "a finite end time >= t_start"));
    }
    let plan = OutputPlan {
        t_end,
        strobe: None,
        dense: Some(DenseSampling { t_start, dt }),
        events: true,
    };
    let mut traj = Trajectory::default();
    let stats = simulate(model, 0.0, y0, &plan, opts, &mut traj)?;
    Ok(PhasePortrait {
        samples: traj.samples,
        events: traj.events,
        stats,
    })
}
