//! A prescribed speed: the forcing frequency as a function of time, for run-up and run-down
//! through critical speeds (issue 21).
//!
//! The profile is a ramp at constant acceleration $R$ from $\eta_0$ to $\eta_1$, then a hold at
//! $\eta_1$ (a run-up for $R > 0$, a run-down for $R < 0$, a constant speed for
//! $\eta_0 = \eta_1$). With the ramp's duration $T = (\eta_1 - \eta_0)/R$,
//!
//! $$\eta(t) = \eta_0 + R t \ (0 \le t \le T), \qquad \eta(t) = \eta_1 \ (t > T),$$
//!
//! and the forcing phase is its integral, exact in closed form:
//! $\varphi(t) = \varphi_0 + \Phi(t)$ with $\Phi(t) = \eta_0 t + R t^2/2$ on the ramp and
//! $\Phi(T) + \eta_1 (t - T)$ on the hold. Its inverse ([`SpeedProfile::time_of_phase`]) is the
//! root of the quadratic in the cancellation-free form
//! $t = 2\Phi / (\eta_0 + \sqrt{\eta_0^2 + 2R\Phi})$.

use super::RotorError;

/// A prescribed speed profile $\eta(t)$: a ramp at constant rate, then a hold (see the module's
/// docs for the formulas).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SpeedProfile {
    eta_from: f64,
    eta_to: f64,
    rate: f64,
    /// The ramp's duration $T$ (0 for a constant speed).
    ramp_time: f64,
}

impl SpeedProfile {
    /// A ramp from `eta_from` to `eta_to` at the rate `rate` $= d\eta/dt$, then a hold at
    /// `eta_to`. `eta_from == eta_to` is a constant speed (any rate).
    ///
    /// # Errors
    /// [`RotorError::SpeedProfile`] for a speed that is negative or not finite, both speeds zero, or a
    /// rate that is zero, not finite or of the wrong sign for the ramp.
    pub fn ramp(eta_from: f64, eta_to: f64, rate: f64) -> Result<Self, RotorError> {
        let bad = |field: &'static str, value: f64, reason: &'static str| {
            Err(RotorError::SpeedProfile {
                field,
                value,
                reason,
            })
        };
        for (field, v) in [("eta_from", eta_from), ("eta_to", eta_to)] {
            if !(v.is_finite() && v >= 0.0) {
                return bad(field, v, "a speed must be finite and >= 0");
            }
        }
        if eta_from.max(eta_to) <= 0.0 {
            return bad(
                "eta_to",
                eta_to,
                "the rotor must turn: one speed must be > 0",
            );
        }
        if eta_from == eta_to {
            return Ok(Self::constant_unchecked(eta_from));
        }
        if !(rate.is_finite() && rate != 0.0) {
            return bad("rate", rate, "a ramp's rate must be finite and not 0");
        }
        let ramp_time = (eta_to - eta_from) / rate;
        if ramp_time <= 0.0 || !ramp_time.is_finite() {
            return bad(
                "rate",
                rate,
                "the rate's sign must take eta_from to eta_to (> 0 up, < 0 down)",
            );
        }
        Ok(Self {
            eta_from,
            eta_to,
            rate,
            ramp_time,
        })
    }

    /// A constant speed `eta`.
    ///
    /// # Errors
    /// [`RotorError::SpeedProfile`] unless `eta` is finite and > 0.
    pub fn constant(eta: f64) -> Result<Self, RotorError> {
        Self::ramp(eta, eta, 0.0)
    }

    fn constant_unchecked(eta: f64) -> Self {
        Self {
            eta_from: eta,
            eta_to: eta,
            rate: 0.0,
            ramp_time: 0.0,
        }
    }

    /// The speed at the start, $\eta_0$.
    pub fn eta_from(&self) -> f64 {
        self.eta_from
    }

    /// The speed at the end of the ramp and of the hold, $\eta_1$.
    pub fn eta_to(&self) -> f64 {
        self.eta_to
    }

    /// The ramp's rate $R$ (0 for a constant speed).
    pub fn rate(&self) -> f64 {
        self.rate
    }

    /// The ramp's duration $T$ (0 for a constant speed).
    pub fn ramp_time(&self) -> f64 {
        self.ramp_time
    }

    /// The largest speed, $\max(\eta_0, \eta_1) > 0$.
    pub fn eta_max(&self) -> f64 {
        self.eta_from.max(self.eta_to)
    }

    /// The speed $\eta(t)$ (for $t < 0$: $\eta_0$).
    pub fn eta(&self, t: f64) -> f64 {
        if t <= 0.0 {
            self.eta_from
        } else if t < self.ramp_time {
            self.eta_from + self.rate * t
        } else {
            self.eta_to
        }
    }

    /// The acceleration $\eta^\prime(t)$: $R$ on the ramp $0 < t < T$, 0 elsewhere.
    pub fn eta_rate(&self, t: f64) -> f64 {
        if t > 0.0 && t < self.ramp_time {
            self.rate
        } else {
            0.0
        }
    }

    /// The phase advanced since $t = 0$, $\Phi(t) = \int_0^t \eta$ (the constant speed
    /// $\eta_0$ before 0).
    pub fn phase(&self, t: f64) -> f64 {
        if t <= 0.0 {
            return self.eta_from * t;
        }
        let on_ramp = t.min(self.ramp_time);
        let ramp = on_ramp * (self.eta_from + 0.5 * self.rate * on_ramp);
        ramp + self.eta_to * (t - on_ramp)
    }

    /// The time at which the phase advanced reaches `phase` ($\Phi^{-1}$, closed form), or
    /// `None` if it never does (a run-down to rest holds its phase after the ramp, and a
    /// phase $< 0$ is before the start).
    pub fn time_of_phase(&self, phase: f64) -> Option<f64> {
        if phase.is_nan() || phase < 0.0 {
            return None;
        }
        let ramp_phase = self.phase(self.ramp_time);
        if phase <= ramp_phase {
            if phase == 0.0 {
                return Some(0.0);
            }
            // The root of R t^2/2 + eta0 t - phase = 0 that is the ramp's, without cancellation.
            let disc = (self.eta_from * self.eta_from + 2.0 * self.rate * phase).max(0.0);
            let t = 2.0 * phase / (self.eta_from + disc.sqrt());
            return Some(t.min(self.ramp_time));
        }
        if self.eta_to > 0.0 {
            Some(self.ramp_time + (phase - ramp_phase) / self.eta_to)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_phase_inverse_is_the_phase_s_inverse() {
        for (a, b, r) in [
            (0.3, 3.0, 0.01),
            (3.0, 0.3, -0.05),
            (0.0, 2.0, 1.0),
            (2.0, 0.0, -0.5),
        ] {
            let p = SpeedProfile::ramp(a, b, r).unwrap();
            let end = p.phase(p.ramp_time());
            // The phase's closed form at the ramp's end: the mean speed times the duration.
            assert!((end - 0.5 * (a + b) * p.ramp_time()).abs() <= 1e-13 * end);
            for i in 0..=100 {
                let phase = end * 1.2 * f64::from(i) / 100.0;
                match p.time_of_phase(phase) {
                    Some(t) => assert!((p.phase(t) - phase).abs() <= 1e-13 * end, "{phase}"),
                    None => assert!(b == 0.0 && phase > end, "{phase}"),
                }
            }
        }
    }

    #[test]
    fn a_ramp_the_rate_cannot_make_is_refused() {
        for (a, b, r) in [
            (0.3, 3.0, -0.01),
            (0.3, 3.0, 0.0),
            (0.0, 0.0, 1.0),
            (-1.0, 1.0, 1.0),
        ] {
            assert!(matches!(
                SpeedProfile::ramp(a, b, r),
                Err(RotorError::SpeedProfile { .. })
            ));
        }
        assert!(SpeedProfile::ramp(0.3, 3.0, f64::NAN).is_err());
        assert!(SpeedProfile::constant(0.0).is_err());
        let c = SpeedProfile::constant(2.0).unwrap();
        assert_eq!(
            (c.eta(5.0), c.eta_rate(5.0), c.phase(5.0)),
            (2.0, 0.0, 10.0)
        );
    }
}
