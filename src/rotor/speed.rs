//! A prescribed speed: the forcing frequency as a function of time, for run-up and run-down
//! through critical speeds (issue 21).
//!
//! Two kinds of profile share one API ([`SpeedProfile`]):
//!
//! * **Piecewise** ([`SpeedProfile::piecewise`], [`SpeedProfile::ramp`],
//!   [`SpeedProfile::constant`]): from $\eta_0$, a list of [`Segment`]s of constant rate (ramps
//!   to a speed, holds of a duration), then a hold at the last speed for ever. On a segment that
//!   starts at $t_i$ with the speed $\eta_i$ and the rate $R_i$,
//!
//!   $$\eta(t) = \eta_i + R_i (t - t_i), \qquad \Phi(t) = \Phi_i + \eta_i (t - t_i) + R_i (t - t_i)^2/2,$$
//!
//!   exact in closed form; the inverse ([`SpeedProfile::time_of_phase`]) is the root of the
//!   quadratic in the cancellation-free form $s = 2\phi / (\eta_i + \sqrt{\eta_i^2 + 2R_i\phi})$,
//!   $\phi = \Phi - \Phi_i$, $s = t - t_i$.
//! * **A user law** ([`SpeedProfile::from_fn`]): closures $\eta(t) \ge 0$ and $\eta^\prime(t)$
//!   on $[0, T]$, then a hold at $\eta(T)$. Its phase is integrated (see
//!   [`SpeedProfile::from_fn`] for its accuracy) and inverted with
//!   [`illinois`](crate::numeric::illinois).
//!
//! The forcing phase is $\varphi(t) = \varphi_0 + \Phi(t)$ with $\Phi(t) = \int_0^t \eta$.
//! The rate $\eta^\prime$ jumps where segments meet ([`SpeedProfile::breaks`]): the
//! out-of-balance force jumps there (by $\beta\thinspace\Delta R$), which an integrator crosses at a
//! lower order unless the run stops and restarts at each break.

use std::fmt;
use std::sync::Arc;

use super::speed_law::Law;
use super::RotorError;

/// One piece of a piecewise [`SpeedProfile`]: a constant rate for a while.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Segment {
    /// A ramp at the constant rate `rate` $= d\eta/dt$ to the speed `to` (`rate` > 0 up, < 0
    /// down).
    Ramp {
        /// The speed at the ramp's end.
        to: f64,
        /// The rate $d\eta/dt$.
        rate: f64,
    },
    /// The speed held for `duration`.
    Hold {
        /// How long, > 0.
        duration: f64,
    },
}

/// A segment placed in time: starts at `t0` with the speed `eta0` and the phase `phase0`.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Piece {
    t0: f64,
    eta0: f64,
    rate: f64,
    duration: f64,
    phase0: f64,
}

impl Piece {
    fn phase_at(&self, s: f64) -> f64 {
        self.phase0 + s * (self.eta0 + 0.5 * self.rate * s)
    }

    fn end_phase(&self) -> f64 {
        self.phase_at(self.duration)
    }

    /// The time since `t0` at which the phase reaches `phase` (within the piece).
    fn time_of(&self, phase: f64) -> f64 {
        let local = (phase - self.phase0).max(0.0);
        if local == 0.0 {
            return 0.0;
        }
        // The root of R s^2/2 + eta0 s - local = 0 that is the piece's, without cancellation.
        let disc = (self.eta0 * self.eta0 + 2.0 * self.rate * local).max(0.0);
        let s = 2.0 * local / (self.eta0 + disc.sqrt());
        s.min(self.duration)
    }
}

#[derive(Clone)]
enum Kind {
    Pieces(Arc<[Piece]>),
    Law(Arc<Law>),
}

/// A prescribed speed profile $\eta(t)$ for $t \ge 0$: piecewise of constant rate, or a user
/// law (see the module's docs for the formulas). Cheap to clone (the pieces or the law are
/// shared).
#[derive(Clone)]
pub struct SpeedProfile {
    kind: Kind,
    eta_from: f64,
    eta_to: f64,
    eta_max: f64,
    /// When the profile's last segment (or the law's interval) ends.
    end: f64,
}

impl fmt::Debug for SpeedProfile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut d = f.debug_struct("SpeedProfile");
        match &self.kind {
            Kind::Pieces(p) => d.field("segments", &p.len()),
            Kind::Law(_) => d.field("law", &"closure"),
        };
        d.field("eta_from", &self.eta_from)
            .field("eta_to", &self.eta_to)
            .field("end", &self.end)
            .finish()
    }
}

/// Equal pieces compare equal; two user laws only if they are the same (shared) law.
impl PartialEq for SpeedProfile {
    fn eq(&self, other: &Self) -> bool {
        match (&self.kind, &other.kind) {
            (Kind::Pieces(a), Kind::Pieces(b)) => a == b,
            (Kind::Law(a), Kind::Law(b)) => Arc::ptr_eq(a, b),
            _ => false,
        }
    }
}

fn bad<T>(field: &'static str, value: f64, reason: &'static str) -> Result<T, RotorError> {
    Err(RotorError::SpeedProfile {
        field,
        value,
        reason,
    })
}

impl SpeedProfile {
    /// A ramp from `eta_from` to `eta_to` at the rate `rate` $= d\eta/dt$, then a hold at
    /// `eta_to`. `eta_from == eta_to` is a constant speed (any rate).
    ///
    /// # Errors
    /// [`RotorError::SpeedProfile`] for a speed that is negative or not finite, both speeds zero, or a
    /// rate that is zero, not finite or of the wrong sign for the ramp.
    pub fn ramp(eta_from: f64, eta_to: f64, rate: f64) -> Result<Self, RotorError> {
        if eta_from == eta_to && eta_from.is_finite() {
            return Self::piecewise(eta_from, &[]);
        }
        Self::piecewise(eta_from, &[Segment::Ramp { to: eta_to, rate }])
    }

    /// A constant speed `eta`.
    ///
    /// # Errors
    /// [`RotorError::SpeedProfile`] unless `eta` is finite and > 0.
    pub fn constant(eta: f64) -> Result<Self, RotorError> {
        Self::ramp(eta, eta, 0.0)
    }

    /// From `eta_from`, the `segments` one after the other, then a hold at the last speed. Up,
    /// hold, down: `[Ramp { to: 3.0, rate: 0.01 }, Hold { duration: 100.0 }, Ramp { to: 0.3,
    /// rate: -0.01 }]`.
    ///
    /// # Errors
    /// [`RotorError::SpeedProfile`] for a speed that is negative or not finite, a profile that
    /// is at rest throughout, a ramp's rate that is zero, not finite or of the wrong sign for
    /// its ramp (a ramp to the speed it starts at is refused too), or a hold's duration that is
    /// not finite and > 0.
    pub fn piecewise(eta_from: f64, segments: &[Segment]) -> Result<Self, RotorError> {
        if !(eta_from.is_finite() && eta_from >= 0.0) {
            return bad("eta_from", eta_from, "a speed must be finite and >= 0");
        }
        let mut pieces = Vec::with_capacity(segments.len());
        let (mut t, mut eta, mut phase, mut eta_max) = (0.0, eta_from, 0.0, eta_from);
        for segment in segments {
            let (rate, duration) = match *segment {
                Segment::Ramp { to, rate } => ramp_of(eta, to, rate)?,
                Segment::Hold { duration } => {
                    if !(duration.is_finite() && duration > 0.0) {
                        return bad("duration", duration, "a hold must last a finite time > 0");
                    }
                    (0.0, duration)
                }
            };
            let piece = Piece {
                t0: t,
                eta0: eta,
                rate,
                duration,
                phase0: phase,
            };
            (t, phase) = (t + duration, piece.end_phase());
            eta = match *segment {
                Segment::Ramp { to, .. } => to,
                Segment::Hold { .. } => eta,
            };
            eta_max = eta_max.max(eta);
            pieces.push(piece);
        }
        if eta_max <= 0.0 {
            return bad("eta_to", eta, "the rotor must turn: one speed must be > 0");
        }
        Ok(Self {
            kind: Kind::Pieces(pieces.into()),
            eta_from,
            eta_to: eta,
            eta_max,
            end: t,
        })
    }

    /// A user law: the speed `eta`$(t) \ge 0$ and its derivative `eta_rate`$(t)$ on
    /// $[0, T]$, $T$ = `end`, then a hold at $\eta(T)$ (rate 0).
    ///
    /// **The phase is integrated**: $\Phi$ is tabulated at the ends of $n = \lceil 8T\rceil$
    /// equal panels of width $h = T/n \le 1/8$ by 5-point Gauss-Legendre quadrature, and
    /// $\Phi(t)$ is the table's value at the panel's start plus the same quadrature over the
    /// rest of the panel. For a speed with ten continuous derivatives the error of one panel is
    /// at most $3.95\times10^{-13}\thinspace h^{11}\max|\eta^{(10)}|$ (the Gauss-Legendre remainder
    /// $h^{11}(5!)^4/(11\thinspace(10!)^3)$), so $|\Phi - \int_0^t\eta| \le 3.95\times10^{-13}\thinspace t\thinspace h^{10}
    /// \max|\eta^{(10)}|$ plus rounding (measured: $7\times10^{-15}$ of the phase for
    /// $\eta = 1.5 + \sin(0.3t)$ over 400 time units, `rotor::speed_law`'s tests). A speed with
    /// kinks (a rate that jumps) loses this order on the panel of the kink: use
    /// [`SpeedProfile::piecewise`] for it. The inverse is found by
    /// [`illinois`](crate::numeric::illinois) to a few ulp of the time.
    ///
    /// `eta_rate` must be the derivative of `eta` (it enters the out-of-balance force's
    /// tangential part); it is not checked.
    ///
    /// # Errors
    /// [`RotorError::SpeedProfile`] for `end` not finite and > 0 (`"end"`), a speed at a
    /// quadrature node that is negative or not finite (`"eta"`, its value), or a speed that is
    /// zero at every node.
    pub fn from_fn(
        end: f64,
        eta: impl Fn(f64) -> f64 + Send + Sync + 'static,
        eta_rate: impl Fn(f64) -> f64 + Send + Sync + 'static,
    ) -> Result<Self, RotorError> {
        let law = Law::new(end, Box::new(eta), Box::new(eta_rate))?;
        Ok(Self {
            eta_from: law.eta(0.0),
            eta_to: law.eta(end),
            eta_max: law.eta_max(),
            end,
            kind: Kind::Law(Arc::new(law)),
        })
    }

    /// The speed at the start, $\eta_0$.
    pub fn eta_from(&self) -> f64 {
        self.eta_from
    }

    /// The speed at the end (held for ever after), $\eta_1$.
    pub fn eta_to(&self) -> f64 {
        self.eta_to
    }

    /// The rate at the start: the first segment's rate (a ramp's $R$; 0 for a constant speed),
    /// a user law's $\eta^\prime(0)$.
    pub fn rate(&self) -> f64 {
        match &self.kind {
            Kind::Pieces(p) => p.first().map_or(0.0, |p| p.rate),
            Kind::Law(law) => law.eta_rate(0.0),
        }
    }

    /// When the profile stops varying $T$: the end of its last segment (a ramp's duration, 0
    /// for a constant speed) or of a user law's interval. The name is kept from the ramp-only
    /// profile.
    pub fn ramp_time(&self) -> f64 {
        self.end
    }

    /// The times where segments meet, in order (the rate may jump there), the last one
    /// [`SpeedProfile::ramp_time`]; empty for a constant speed and a user law (whose rate is the
    /// user's).
    pub fn breaks(&self) -> Vec<f64> {
        match &self.kind {
            Kind::Pieces(p) => p.iter().map(|p| p.t0 + p.duration).collect(),
            Kind::Law(_) => Vec::new(),
        }
    }

    /// The largest speed, > 0 (for a user law: the largest at the quadrature's nodes and the
    /// panels' ends).
    pub fn eta_max(&self) -> f64 {
        self.eta_max
    }

    /// The piece of the profile that holds `t` (the later one where two meet); `None` on the
    /// final hold.
    fn piece_at(pieces: &[Piece], t: f64) -> Option<&Piece> {
        let i = pieces.partition_point(|p| p.t0 <= t);
        pieces[..i].last().filter(|p| t < p.t0 + p.duration)
    }

    /// The speed $\eta(t)$ (for $t < 0$: $\eta_0$).
    pub fn eta(&self, t: f64) -> f64 {
        if t <= 0.0 {
            return self.eta_from;
        }
        match &self.kind {
            Kind::Pieces(p) => {
                Self::piece_at(p, t).map_or(self.eta_to, |p| p.eta0 + p.rate * (t - p.t0))
            }
            Kind::Law(law) => law.eta(t.min(self.end)),
        }
    }

    /// The acceleration $\eta^\prime(t)$: the segment's rate for $0 < t < T$ (the later
    /// segment's where two meet), 0 elsewhere.
    pub fn eta_rate(&self, t: f64) -> f64 {
        if t <= 0.0 || t >= self.end {
            return 0.0;
        }
        match &self.kind {
            Kind::Pieces(p) => Self::piece_at(p, t).map_or(0.0, |p| p.rate),
            Kind::Law(law) => law.eta_rate(t),
        }
    }

    /// The phase advanced since $t = 0$, $\Phi(t) = \int_0^t \eta$ (the constant speed
    /// $\eta_0$ before 0).
    pub fn phase(&self, t: f64) -> f64 {
        if t <= 0.0 {
            return self.eta_from * t;
        }
        let (end_phase, inside) = match &self.kind {
            Kind::Pieces(p) => (
                p.last().map_or(0.0, Piece::end_phase),
                Self::piece_at(p, t).map(|p| p.phase_at(t - p.t0)),
            ),
            Kind::Law(law) => (law.phase(self.end), (t < self.end).then(|| law.phase(t))),
        };
        inside.unwrap_or(end_phase + self.eta_to * (t - self.end))
    }

    /// The first time at which the phase advanced reaches `phase` ($\Phi^{-1}$), or `None` if
    /// it never does (a run-down to rest holds its phase after the end, and a phase $< 0$ is
    /// before the start).
    pub fn time_of_phase(&self, phase: f64) -> Option<f64> {
        if phase.is_nan() || phase < 0.0 {
            return None;
        }
        if phase == 0.0 {
            return Some(0.0);
        }
        let end_phase = self.phase(self.end);
        if phase <= end_phase {
            return Some(match &self.kind {
                Kind::Pieces(p) => {
                    let piece = &p[p
                        .partition_point(|p| p.end_phase() < phase)
                        .min(p.len() - 1)];
                    (piece.t0 + piece.time_of(phase)).min(self.end)
                }
                Kind::Law(law) => law.time_of_phase(phase),
            });
        }
        (self.eta_to > 0.0).then(|| self.end + (phase - end_phase) / self.eta_to)
    }
}

/// A ramp's `(rate, duration)` from `from` to `to`, checked.
fn ramp_of(from: f64, to: f64, rate: f64) -> Result<(f64, f64), RotorError> {
    if !(to.is_finite() && to >= 0.0) {
        return bad("eta_to", to, "a speed must be finite and >= 0");
    }
    if !(rate.is_finite() && rate != 0.0) {
        return bad("rate", rate, "a ramp's rate must be finite and not 0");
    }
    let duration = (to - from) / rate;
    if duration <= 0.0 || !duration.is_finite() {
        return bad(
            "rate",
            rate,
            "the rate's sign must take the ramp to its speed (> 0 up, < 0 down)",
        );
    }
    Ok((rate, duration))
}

#[cfg(test)]
mod tests;
