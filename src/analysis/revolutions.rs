//! Per-revolution outputs of a run at a varying speed: in each revolution of the
//! out-of-balance, the largest radius at the ring, whether and how long the rotor touched it,
//! and the time in each regime (the analysis module's docs, "Per-revolution outputs").

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector, Vector2};

use super::AnalysisError;
use crate::hybrid::{EventRecord, Trajectory};
use crate::numeric::{hermite_slope_weights, hermite_weights, illinois, RootOptions};
use crate::ring::Kinematics;

/// One revolution of [`per_revolution`].
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Revolution {
    /// When the revolution starts (its first strobe).
    pub t_start: f64,
    /// When it ends (the next revolution's first strobe).
    pub t_end: f64,
    /// Its mean angular speed, $2\pi/(t_\text{end} - t_\text{start})$.
    pub speed: f64,
    /// The largest radius from the ring's centre in the revolution: at its strobes and events
    /// and, between each two of them, the largest on the cubic Hermite interpolant of the
    /// station's position and velocity there ([`per_revolution`]).
    pub max_radius: f64,
    /// The time spent in contact (regimes II to V, and the friction's modes).
    pub contact_time: f64,
    /// The fraction of the revolution's time in each mode label 1 to 8: the regimes I (free) to
    /// V, then, with friction at the ring ([`RubbingRotor`](crate::rotor::RubbingRotor)),
    /// slipping forward, slipping backward and rolling; sums to 1.
    pub occupancy: [f64; 8],
}

impl Revolution {
    /// Whether the rotor touched the ring in this revolution (some time in contact).
    pub fn touched(&self) -> bool {
        self.contact_time > 0.0
    }
}

/// The revolutions of `traj`, whose strobes are `per_revolution` a revolution from strobe 0
/// (as a profiled rotor's, `ProfiledJeffcott::with_strobes_per_revolution`) and whose events
/// were recorded; `station` gives the rotor's position and velocity at the ring's station
/// relative to the ring's centre from a state: a rotor's own
/// [`SmoothRotor::station`](crate::rotor::SmoothRotor::station), e.g.
/// `|y| model.rotor().station(y)` for a [`RingedRotor`](crate::rotor::RingedRotor) `model`,
/// whatever its coordinates (physical, reduced, modal). The regime is the strobes' and events'
/// mode label (the ring's regime number, 1 to 5); a revolution is cut at the strobes
/// $k = jS$, and an incomplete last one is left out.
///
/// The largest radius is located, not sampled: the strobes, the dense samples
/// ([`OutputPlan::dense`](crate::hybrid::OutputPlan::dense), if the run recorded any) and the
/// events' states (before and after) are knots, and between two knots $t_0 < t_1$ the station's
/// path is the cubic Hermite interpolant of its positions and velocities there
/// ([`crate::numeric::hermite_weights`]), whose largest radius is found where
/// $\tfrac{d}{dt}|p|^2 = 2\thinspace p \cdot p^\prime$ falls through zero
/// ([`crate::numeric::illinois`], after 16 samples of the interval). Its error is that of the
/// interpolant, at most $h^4 \max|r^{(4)}|/384$ with $h = t_1 - t_0$. In free flight, for a
/// whirl at the rotation speed and $S$ strobes a revolution, that is about $(2\pi/S)^4/384$ of
/// the radius ($4 \times 10^{-6}$ at $S = 32$, where the strobes alone miss the peak by up to
/// $1 - \cos(\pi/S) = 4.8 \times 10^{-3}$). In contact the station moves at the contact's
/// own, faster, frequency, and the knots must resolve it: on Fig. 8a's rotor ramped through
/// its resonance on the ring, 32 strobes a revolution alone leave the located peak
/// $2.5 \times 10^{-3}$ of the radius off (the strobes' own peak $3 \times 10^{-2}$); with
/// dense samples 256 a revolution as knots too, within $3 \times 10^{-7}$ (the truth's own
/// resolution; the test
/// `analysis::revolutions::the_peak_is_located_between_the_strobes`).
///
/// # Errors
/// `InvalidCount` for `per_revolution` = 0; [`AnalysisError::InvalidValue`] (`"label"`) for a
/// mode label outside 1..=5.
pub fn per_revolution<D: Dim>(
    traj: &Trajectory<D>,
    per_revolution: usize,
    station: impl Fn(&OVector<f64, D>) -> Kinematics,
) -> Result<Vec<Revolution>, AnalysisError>
where
    DefaultAllocator: Allocator<D>,
{
    if per_revolution == 0 {
        return Err(AnalysisError::InvalidCount {
            name: "per_revolution",
            value: 0,
            expected: "at least 1 strobe a revolution",
        });
    }
    let knot = |t: f64, y: &OVector<f64, D>| Knot { t, at: station(y) };
    let starts: Vec<_> = traj.strobe.iter().step_by(per_revolution).collect();
    let mut out = Vec::with_capacity(starts.len().saturating_sub(1));
    for pair in starts.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        // The knots in time order: strobes and samples in [a, b], events in [a, b) (an event
        // after a strobe or sample at its time; the sort is stable).
        let strobes = in_span(&traj.strobe, |p| p.t, (a.t, b.t), true);
        let samples = in_span(&traj.samples, |p| p.t, (a.t, b.t), true);
        let events = in_span(&traj.events, |e| e.t, (a.t, b.t), false);
        let mut knots: Vec<(f64, Node<'_, D>)> = strobes
            .iter()
            .map(|p| (p.t, Node::Point(&p.y)))
            .chain(samples.iter().map(|p| (p.t, Node::Point(&p.y))))
            .chain(events.iter().map(|e| (e.t, Node::Event(e))))
            .collect();
        knots.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut time_in = [0.0; 8];
        let (mut label, mut since) = (a.label, a.t);
        let mut peak = Peak::default();
        for (t, node) in knots {
            match node {
                Node::Point(y) => peak.through(knot(t, y)),
                Node::Event(e) => {
                    peak.through(knot(t, &e.before));
                    peak.restart(knot(t, &e.after));
                    *slot(&mut time_in, label)? += t - since;
                    (label, since) = (e.to, t);
                }
            }
        }
        *slot(&mut time_in, label)? += b.t - since;
        let span = b.t - a.t;
        out.push(Revolution {
            t_start: a.t,
            t_end: b.t,
            speed: std::f64::consts::TAU / span,
            max_radius: peak.radius,
            contact_time: time_in[1..].iter().sum(),
            occupancy: time_in.map(|t| t / span),
        });
    }
    Ok(out)
}

/// The part of `items` (in time order) from `a` to `b`: $a \le t < b$, or $a \le t \le b$
/// with `end_in`.
fn in_span<T>(items: &[T], time: impl Fn(&T) -> f64, (a, b): (f64, f64), end_in: bool) -> &[T] {
    let first = items.partition_point(|x| time(x) < a);
    let last = items.partition_point(|x| time(x) < b || (end_in && time(x) == b));
    &items[first..last.max(first)]
}

/// A recorded state of a revolution: a strobe or a dense sample, or an event (its states
/// before and after).
enum Node<'a, D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    Point(&'a OVector<f64, D>),
    Event(&'a EventRecord<D>),
}

/// The station at a time: a knot of the interpolated path.
#[derive(Clone, Copy)]
struct Knot {
    t: f64,
    at: Kinematics,
}

/// The largest radius along a path of knots, each two joined by their Hermite interpolant.
#[derive(Default)]
struct Peak {
    last: Option<Knot>,
    radius: f64,
}

impl Peak {
    /// The path goes on to `k`.
    fn through(&mut self, k: Knot) {
        if let Some(a) = self.last {
            self.radius = self.radius.max(segment_peak(&a, &k));
        }
        self.restart(k);
    }

    /// The path starts again at `k` (after an event: the next piece starts from its state).
    fn restart(&mut self, k: Knot) {
        self.radius = self.radius.max(k.at.r.norm());
        self.last = Some(k);
    }
}

/// The largest radius inside `(a, b)` on the cubic Hermite interpolant of the two knots'
/// positions and velocities (0 if it has no interior maximum).
fn segment_peak(a: &Knot, b: &Knot) -> f64 {
    const SAMPLES: usize = 16;
    let h = b.t - a.t;
    if h <= 0.0 || h.is_nan() {
        return 0.0;
    }
    let combine = |w: [f64; 4]| -> Vector2<f64> {
        w[0] * a.at.r + (w[1] * h) * a.at.v + w[2] * b.at.r + (w[3] * h) * b.at.v
    };
    let position = |s: f64| combine(hermite_weights(s));
    // Half the derivative of |p|^2 in s: positive while the radius grows.
    let growth = |s: f64| position(s).dot(&combine(hermite_slope_weights(s)));
    let opts = RootOptions::default().with_tol(1e-12);
    let mut radius = 0.0f64;
    let mut prev = (0.0, growth(0.0));
    for i in 1..=SAMPLES {
        let s = i as f64 / SAMPLES as f64;
        let next = (s, growth(s));
        if prev.1 > 0.0 && next.1 <= 0.0 {
            let at = illinois(prev, next, &opts, growth).map_or(s, |r| r.hi);
            radius = radius.max(position(at).norm());
        }
        prev = next;
    }
    radius
}

fn slot(time_in: &mut [f64; 8], label: u8) -> Result<&mut f64, AnalysisError> {
    match label {
        1..=8 => Ok(&mut time_in[usize::from(label - 1)]),
        _ => Err(AnalysisError::InvalidValue {
            name: "label",
            value: f64::from(label),
            expected: "a mode label 1..=8 (the ring's regimes, the friction's modes)",
        }),
    }
}
