//! The paper's Jeffcott rotor at a prescribed, time-varying speed ([`SpeedProfile`]): a
//! [`SmoothRotor`] that [`RingedRotor`] puts on the paper's ring.
//!
//! **The out-of-balance force at varying speed.** The out-of-balance mass $m$ sits at
//! $\rho(\cos\varphi, \sin\varphi)$ from the rotor's centre, $\varphi^\prime = \Omega$. Its
//! acceleration relative to the centre is
//! $\rho(-\Omega^2\cos\varphi - \Omega^\prime\sin\varphi,\ -\Omega^2\sin\varphi + \Omega^\prime\cos\varphi)$,
//! and the force it puts on the rotor is minus $m$ times that:
//! $m\rho(\Omega^2\cos\varphi + \Omega^\prime\sin\varphi,\ \Omega^2\sin\varphi - \Omega^\prime\cos\varphi)$.
//! The $\Omega^\prime$ terms are the tangential (Euler) force of the accelerating mass. In the
//! paper's units ($\tau = \omega_n t$, lengths over the gap) this is
//!
//! $$x^{\prime\prime} + 2\nu_1 x^\prime + (x - e_x) + f_x = \beta(\eta^2\cos\varphi + \eta^\prime\sin\varphi),$$
//! $$y^{\prime\prime} + 2\nu_1 y^\prime + (y - e_y) + f_y = \beta(\eta^2\sin\varphi - \eta^\prime\cos\varphi),$$
//!
//! with $\eta(\tau)$ and $\varphi = \varphi_0 + \int_0^\tau\eta$ from the profile (exact) and $f$
//! the ring's force. At constant speed this is MODEL.md's equation. The speed's rate jumps
//! where a ramp ends (the forcing then jumps by $\beta R$): a run that goes on past the ramp
//! should stop there and restart, or accept the integrator's lower order across the jump.
//!
//! **Free flight is integrated** (no closed form at varying speed), so contact onsets are found
//! by the event detector on the dense output, with [`RingedRotor`]'s onset guarantee: every
//! touch of the integrated trajectory's dense output is found, and whether the exact orbit
//! touches is decided to that trajectory's own error. Measured on an undamped circular orbit
//! whose largest radius is $1 + d$ (`tests/suite/simulation/run_up.rs`): at `rtol` $10^{-12}$
//! touches of depth $d = 10^{-9}$ down to $10^{-13}$ are found, and a miss by $10^{-9}$ is not
//! taken for a touch.

use std::f64::consts::TAU;

use nalgebra::{SVector, Vector2, U6};

use super::{RingedRotor, RotorError, SmoothRotor, SpeedProfile};
use crate::params::{ParamError, Params};
use crate::ring::{Kinematics, RingAxis, SnubberRing};

/// The paper's Jeffcott rotor driven by a [`SpeedProfile`]. State
/// `[x, y, x', y', x_s, y_s]` (the ring's centre last), as the paper's model.
/// Cloned, not copied: the profile may share a user law.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfiledJeffcott {
    params: Params,
    profile: SpeedProfile,
    strobes_per_revolution: u32,
}

impl ProfiledJeffcott {
    /// The gap of the ring that [`ProfiledJeffcott::off_ring`] puts out of reach, in gaps.
    pub const OUT_OF_REACH: f64 = 1e6;

    /// The rotor of `params` at the speed `profile` (the parameters' `eta` is not used: the
    /// profile gives the speed). One stroboscopic output per revolution.
    ///
    /// # Errors
    /// [`ParamError`] for invalid parameters (checked with `eta` set to the profile's largest
    /// speed).
    pub fn new(params: Params, profile: SpeedProfile) -> Result<Self, ParamError> {
        let params = Params {
            eta: profile.eta_max(),
            ..params
        }
        .validated()?;
        Ok(Self {
            params,
            profile,
            strobes_per_revolution: 1,
        })
    }

    /// With `count` stroboscopic outputs per revolution of the out-of-balance: output `k` is
    /// at the phase $\varphi = \varphi_0 + 2\pi k/S$, $S$ = `count`.
    ///
    /// # Errors
    /// [`RotorError::SpeedProfile`] for `count` = 0.
    pub fn with_strobes_per_revolution(mut self, count: u32) -> Result<Self, RotorError> {
        self.strobes_per_revolution = strobes_per_revolution(count)?;
        Ok(self)
    }

    /// The parameters (with `eta` the profile's largest speed).
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The speed profile.
    pub fn profile(&self) -> &SpeedProfile {
        &self.profile
    }

    /// The forcing phase $\varphi(\tau) = \varphi_0 + \int_0^\tau\eta$.
    pub fn phase(&self, tau: f64) -> f64 {
        self.params.phi0 + self.profile.phase(tau)
    }

    /// The out-of-balance force at $\tau$ (see the module's docs).
    pub fn forcing(&self, tau: f64) -> [f64; 2] {
        let (eta, rate) = (self.profile.eta(tau), self.profile.eta_rate(tau));
        let (sin, cos) = self.phase(tau).sin_cos();
        let (radial, tangential) = (self.params.beta * eta * eta, self.params.beta * rate);
        [
            radial * cos + tangential * sin,
            radial * sin - tangential * cos,
        ]
    }

    /// On the paper's ring (gap 1, $K$, $D$, $\nu_2$ from the parameters).
    ///
    /// # Errors
    /// [`RotorError`] if the ring or the composition refuses.
    /// (A clone of the rotor: its profile is shared, not copied.)
    pub fn on_ring(&self) -> Result<RingedRotor<Self>, RotorError> {
        self.with_gap(1.0)
    }

    /// Without contact: the ring's gap is [`ProfiledJeffcott::OUT_OF_REACH`], so a rotor within that radius
    /// never touches it (the run's `transitions` count says so).
    ///
    /// # Errors
    /// [`RotorError`] if the ring or the composition refuses.
    pub fn off_ring(&self) -> Result<RingedRotor<Self>, RotorError> {
        self.with_gap(Self::OUT_OF_REACH)
    }

    fn with_gap(&self, gap: f64) -> Result<RingedRotor<Self>, RotorError> {
        RingedRotor::new(self.clone(), paper_ring(&self.params, gap)?)
    }
}

/// `count` stroboscopic outputs per revolution, checked: at least one.
pub(super) fn strobes_per_revolution(count: u32) -> Result<u32, RotorError> {
    if count == 0 {
        return Err(RotorError::SpeedProfile {
            field: "strobes_per_revolution",
            value: 0.0,
            reason: "at least one output per revolution",
        });
    }
    Ok(count)
}

/// The paper's ring of `p` ($K$, $D$, $\nu_2$) with the gap `gap` (1, or out of reach): the
/// ring of [`ProfiledJeffcott`] and [`super::DrivenJeffcott`].
pub(super) fn paper_ring(p: &Params, gap: f64) -> Result<SnubberRing, RotorError> {
    Ok(SnubberRing::new(
        RingAxis::new(p.kx, p.dx),
        RingAxis::new(p.ky, p.dy),
        p.nu2,
        gap,
    )?)
}

impl SmoothRotor for ProfiledJeffcott {
    type Dim = U6;

    fn dim(&self) -> U6 {
        U6
    }

    fn rhs(&self, t: f64, y: &SVector<f64, 6>, dy: &mut SVector<f64, 6>) {
        let p = &self.params;
        let [fx, fy] = self.forcing(t);
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = fx - 2.0 * p.nu1 * y[2] - (y[0] - p.ex);
        dy[3] = fy - 2.0 * p.nu1 * y[3] - (y[1] - p.ey);
    }

    fn station(&self, y: &SVector<f64, 6>) -> Kinematics {
        Kinematics::new([y[0], y[1]], [y[2], y[3]])
    }

    fn add_station_force(&self, _y: &SVector<f64, 6>, f: &Vector2<f64>, dy: &mut SVector<f64, 6>) {
        dy[2] += f.x;
        dy[3] += f.y;
    }

    fn ring_slots(&self) -> [usize; 2] {
        [4, 5]
    }

    /// The profile's speed, phase and rate.
    fn spin(&self, t: f64, _y: &SVector<f64, 6>) -> Option<super::Spin> {
        Some(super::Spin {
            speed: self.profile.eta(t),
            angle: self.phase(t),
            accel: self.profile.eta_rate(t),
        })
    }

    /// The period at the profile's largest speed (the shortest).
    fn forcing_period(&self) -> f64 {
        TAU / self.profile.eta_max()
    }

    /// The time the phase reaches $\varphi_0 + 2\pi k/S$ (closed form,
    /// [`SpeedProfile::time_of_phase`]); infinite if it never does.
    fn strobe_time(&self, k: u64) -> f64 {
        let phase = TAU * k as f64 / f64::from(self.strobes_per_revolution);
        self.profile.time_of_phase(phase).unwrap_or(f64::INFINITY)
    }

    /// Positions 1 (the gap), velocities the largest speed, as the paper's model (the ring out
    /// of reach has a huge gap that must not scale the errors).
    fn state_scale(&self) -> Option<SVector<f64, 6>> {
        let v = self.profile.eta_max();
        Some(SVector::<f64, 6>::from([1.0, 1.0, v, v, 1.0, 1.0]))
    }
}
