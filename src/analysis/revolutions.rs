//! Per-revolution outputs of a run at a varying speed: in each revolution of the
//! out-of-balance, the largest radius at the ring, whether and how long the rotor touched it,
//! and the time in each regime (the analysis module's docs, "Per-revolution outputs").

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

use super::AnalysisError;
use crate::hybrid::Trajectory;

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
    /// The largest radius from the ring's centre at the revolution's strobes and events.
    pub max_radius: f64,
    /// The time spent in contact (regimes II to V).
    pub contact_time: f64,
    /// The fraction of the revolution's time in each regime, I (free) to V; sums to 1.
    pub occupancy: [f64; 5],
}

impl Revolution {
    /// Whether the rotor touched the ring in this revolution (some time in contact).
    pub fn touched(&self) -> bool {
        self.contact_time > 0.0
    }
}

/// The revolutions of `traj`, whose strobes are `per_revolution` a revolution from strobe 0
/// (as a profiled rotor's, `ProfiledJeffcott::with_strobes_per_revolution`) and whose events
/// were recorded; `station` gives the rotor's position $(x, y)$ relative to the ring's centre
/// from a state. The regime is the strobes' and events' mode label (the ring's regime
/// number, 1 to 5); a revolution is cut at the strobes $k = jS$, and an incomplete last one is
/// left out. The largest radius is taken at the strobes and at the events' states, so a touch
/// between two strobes counts with the radius it had at its onset.
///
/// # Errors
/// `InvalidCount` for `per_revolution` = 0; [`AnalysisError::InvalidValue`] (`"label"`) for a
/// mode label outside 1..=5.
pub fn per_revolution<D: Dim>(
    traj: &Trajectory<D>,
    per_revolution: usize,
    station: impl Fn(&OVector<f64, D>) -> [f64; 2],
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
    let radius = |y: &OVector<f64, D>| {
        let [x, y] = station(y);
        x.hypot(y)
    };
    let starts: Vec<_> = traj.strobe.iter().step_by(per_revolution).collect();
    let mut events = traj.events.iter().peekable();
    let mut out = Vec::with_capacity(starts.len().saturating_sub(1));
    for pair in starts.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let mut time_in = [0.0; 5];
        let (mut label, mut since) = (a.label, a.t);
        let mut max_radius = traj
            .strobe
            .iter()
            .skip_while(|s| s.t < a.t)
            .take_while(|s| s.t < b.t)
            .map(|s| radius(&s.y))
            .fold(0.0f64, f64::max);
        while let Some(e) = events.next_if(|e| e.t < b.t) {
            if e.t < a.t {
                continue;
            }
            *slot(&mut time_in, label)? += e.t - since;
            max_radius = max_radius.max(radius(&e.before)).max(radius(&e.after));
            (label, since) = (e.to, e.t);
        }
        *slot(&mut time_in, label)? += b.t - since;
        let span = b.t - a.t;
        out.push(Revolution {
            t_start: a.t,
            t_end: b.t,
            speed: std::f64::consts::TAU / span,
            max_radius,
            contact_time: time_in[1..].iter().sum(),
            occupancy: time_in.map(|t| t / span),
        });
    }
    Ok(out)
}

fn slot(time_in: &mut [f64; 5], label: u8) -> Result<&mut f64, AnalysisError> {
    match label {
        1..=5 => Ok(&mut time_in[usize::from(label - 1)]),
        _ => Err(AnalysisError::InvalidValue {
            name: "label",
            value: f64::from(label),
            expected: "a ring regime number 1..=5",
        }),
    }
}
