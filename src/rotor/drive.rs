//! The paper's Jeffcott rotor on a **non-ideal drive** (issue 21): the speed is a state, driven
//! by a motor's torque characteristic through the rotor's polar inertia and loaded by the
//! out-of-balance's reaction torque. A [`SmoothRotor`] that [`RingedRotor`] puts on the paper's
//! ring (the contact rules are the ring's, as for [`ProfiledJeffcott`]).
//!
//! **The equations.** The rotor of total translating mass $M$ (the out-of-balance mass $m$
//! included) at $X = (X, Y)$ carries $m$ at $X + \rho(\cos\varphi, \sin\varphi)$; its polar
//! inertia about the shaft, $m$ included, is $J_p$; the motor's torque is $T(\dot\varphi)$.
//! With the kinetic energy
//! $\tfrac12 M|\dot X|^2 + \tfrac12 J_p\dot\varphi^2 + m\rho\dot\varphi\thinspace\dot X\cdot t_\varphi$,
//! $t_\varphi = (-\sin\varphi, \cos\varphi)$ (Lagrange's equations; the
//! $\tfrac12 m\rho^2\dot\varphi^2$ is in $J_p$), the rotor's equations are the paper's with
//! $\Omega = \dot\varphi$, and the spin's is
//! $J_p\ddot\varphi = T(\dot\varphi) + m\rho(\ddot X\sin\varphi - \ddot Y\cos\varphi)$: the
//! second term is the out-of-balance's reaction torque. In MODEL.md's units (lengths over the
//! gap $\gamma$, $\tau = \omega_n t$, energies and torques over $k_r\gamma^2$), with
//! $\eta = \dot\varphi/\omega_n$, the inertia $j = J_p/(M\gamma^2)$ and the torque
//! $t(\eta) = T/(k_r\gamma^2)$, the state is $(x, y, x^\prime, y^\prime, x_s, y_s, \eta, \varphi)$ and
//!
//! $$x^{\prime\prime} + 2\nu_1 x^\prime + (x - e_x) + f_x = \beta(\eta^2\cos\varphi + \eta^\prime\sin\varphi),$$
//! $$y^{\prime\prime} + 2\nu_1 y^\prime + (y - e_y) + f_y = \beta(\eta^2\sin\varphi - \eta^\prime\cos\varphi),$$
//! $$j\thinspace\eta^\prime = t(\eta) + \beta(x^{\prime\prime}\sin\varphi - y^{\prime\prime}\cos\varphi), \qquad \varphi^\prime = \eta,$$
//!
//! $f$ the ring's force, $\beta = m\rho/(M\gamma)$ as in the paper. The accelerations are
//! coupled; with $a = (a_x, a_y)$ the rotor's acceleration without the $\eta^\prime$ terms
//! (everything else on the right, $f$ included) they solve in closed form:
//! $(j - \beta^2)\thinspace\eta^\prime = t(\eta) + \beta(a_x\sin\varphi - a_y\cos\varphi)$, then
//! $x^{\prime\prime} = a_x + \beta\eta^\prime\sin\varphi$, $y^{\prime\prime} = a_y - \beta\eta^\prime\cos\varphi$.
//! $j > \beta^2$ holds for any physical rotor ($J_p \ge m\rho^2$ and $M > m$) and is required.
//!
//! **Energy.** The energy
//! $E = \tfrac12|r^\prime|^2 + \tfrac12 j\eta^2 + \beta\eta\thinspace r^\prime\cdot t_\varphi +
//! \tfrac12|r - e|^2 + E_\text{ring}(s)$ (the out-of-balance's kinetic energy is the cross
//! term) changes by the motor's work $\int t(\eta)\eta\thinspace d\tau$ minus the rotor's damping
//! $\int 2\nu_1|r^\prime|^2$ and the ring's losses (`tests/suite/simulation/drive_energy.rs`
//! checks it).
//!
//! The strobes are at the shaft's turns, where the phase state reaches $\varphi_0 + 2\pi k$
//! ([`RotorModel::strobe_phase`](crate::hybrid::RotorModel::strobe_phase)), so that a
//! revolution's analysis ([`crate::analysis::per_revolution`]) sees the shaft's revolutions.

use std::f64::consts::TAU;
use std::fmt;
use std::sync::Arc;

use nalgebra::{SVector, Vector2, U8};

use super::{paper_ring, RingedRotor, RotorError, SmoothRotor};
use crate::params::{ParamError, Params};
use crate::ring::Kinematics;

/// The index of the speed $\eta$ in [`DrivenJeffcott`]'s state.
pub const ETA: usize = 6;
/// The index of the phase $\varphi$ in [`DrivenJeffcott`]'s state.
pub const PHASE: usize = 7;

type Characteristic = Arc<dyn Fn(f64) -> f64 + Send + Sync>;

/// A motor's torque characteristic $t(\eta)$ in the paper's units (torque over
/// $k_r\gamma^2$).
#[derive(Clone)]
pub enum MotorTorque {
    /// A linear (DC) motor $t = t_0(1 - \eta/\eta_0)$: stall torque $t_0$, no-load speed
    /// $\eta_0$.
    Linear {
        /// The stall torque $t_0$.
        stall: f64,
        /// The no-load speed $\eta_0 > 0$.
        no_load: f64,
    },
    /// A user's characteristic (finite for every speed the run reaches).
    User(Characteristic),
}

impl fmt::Debug for MotorTorque {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Self::Linear { stall, no_load } => f
                .debug_struct("Linear")
                .field("stall", stall)
                .field("no_load", no_load)
                .finish(),
            Self::User(_) => f.write_str("User(closure)"),
        }
    }
}

impl MotorTorque {
    /// A linear DC motor $t_0(1 - \eta/\eta_0)$.
    ///
    /// # Errors
    /// [`ParamError::NotFinite`] for `stall` or `no_load` not finite,
    /// [`ParamError::NotPositive`] for `no_load` <= 0.
    pub fn linear(stall: f64, no_load: f64) -> Result<Self, ParamError> {
        for (field, value) in [("stall", stall), ("no_load", no_load)] {
            if !value.is_finite() {
                return Err(ParamError::NotFinite { field, value });
            }
        }
        if no_load <= 0.0 {
            return Err(ParamError::NotPositive {
                field: "no_load",
                value: no_load,
            });
        }
        Ok(Self::Linear { stall, no_load })
    }

    /// A user's characteristic $t(\eta)$.
    pub fn user(torque: impl Fn(f64) -> f64 + Send + Sync + 'static) -> Self {
        Self::User(Arc::new(torque))
    }

    /// The torque at the speed `eta`.
    pub fn torque(&self, eta: f64) -> f64 {
        match self {
            Self::Linear { stall, no_load } => stall * (1.0 - eta / no_load),
            Self::User(t) => t(eta),
        }
    }

    /// The torque's slope $t^\prime(\eta)$ at the speed `eta`: $-t_0/\eta_0$ for a linear
    /// motor; for a user's characteristic (which gives no derivative) the central difference
    /// $(t(\eta + h) - t(\eta - h))/2h$ with $h = \varepsilon^{1/3}\max(|\eta|, 1)$, whose
    /// truncation and rounding errors balance at about $\varepsilon^{2/3} \approx 4\cdot 10^{-11}$
    /// of the torque's scale for a smooth characteristic (in the units of `eta`, rad/s or the
    /// paper's, a step of at least $6\cdot 10^{-6}$).
    pub fn slope(&self, eta: f64) -> f64 {
        match self {
            Self::Linear { stall, no_load } => -stall / no_load,
            Self::User(t) => {
                let h = f64::EPSILON.cbrt() * eta.abs().max(1.0);
                let (up, down) = (eta + h, eta - h);
                (t(up) - t(down)) / (up - down)
            }
        }
    }
}

/// The spin's acceleration of a rotor driven by the torque `torque` through the polar inertia
/// `inertia` $J$, shared by every driven rotor ([`DrivenJeffcott`],
/// [`super::DrivenLinearRotor`]). With the out-of-balance's kinetic energy
/// $\dot\varphi\thinspace\dot q\cdot b(\varphi)$ in the Lagrangian (for a mass $m$ at $\rho$
/// from a node: $b = m\rho(-\sin\varphi, \cos\varphi)$ at its x and y), the equations are
/// $M\ddot q = F - \ddot\varphi\thinspace b + \dot\varphi^2 m\rho(\cos\varphi, \sin\varphi)$ and
/// $J\ddot\varphi = T - b\cdot\ddot q$. With $a$ the acceleration without the
/// $\ddot\varphi$ term (`b_dot_a` $= b\cdot a$, `b_minv_b` $= b\cdot M^{-1}b$) they solve in
/// closed form: $(J - b\cdot M^{-1}b)\thinspace\ddot\varphi = T - b\cdot a$, then
/// $\ddot q = a - \ddot\varphi\thinspace M^{-1}b$.
pub(super) fn spin_acceleration(torque: f64, inertia: f64, b_dot_a: f64, b_minv_b: f64) -> f64 {
    (torque - b_dot_a) / (inertia - b_minv_b)
}

/// The paper's Jeffcott rotor whose speed is driven by a [`MotorTorque`] (see the module's
/// docs for the equations). State `[x, y, x', y', x_s, y_s, eta, phi]`
/// (indices [`ETA`], [`PHASE`]).
#[derive(Debug, Clone)]
pub struct DrivenJeffcott {
    params: Params,
    motor: MotorTorque,
    inertia: f64,
    eta_ref: f64,
}

impl DrivenJeffcott {
    /// The rotor of `params` (whose `eta` is the reference speed: the forcing period
    /// $2\pi/\eta$ and the velocities' scale; the speed itself is the state's) with the
    /// non-dimensional polar inertia `inertia` $= j = J_p/(M\gamma^2)$, driven by `motor`.
    ///
    /// # Errors
    /// [`ParamError`] for invalid parameters, `inertia` not finite
    /// ([`ParamError::NotFinite`]) or not above $\beta^2$ ([`ParamError::NotPositive`] of
    /// the field `"inertia - beta^2"`: $J_p M > (m\rho)^2$ for any physical rotor).
    pub fn new(params: Params, inertia: f64, motor: MotorTorque) -> Result<Self, ParamError> {
        let params = params.validated()?;
        if !inertia.is_finite() {
            return Err(ParamError::NotFinite {
                field: "inertia",
                value: inertia,
            });
        }
        let margin = inertia - params.beta * params.beta;
        if margin <= 0.0 {
            return Err(ParamError::NotPositive {
                field: "inertia - beta^2",
                value: margin,
            });
        }
        Ok(Self {
            eta_ref: params.eta,
            params,
            motor,
            inertia,
        })
    }

    /// The parameters.
    pub fn params(&self) -> &Params {
        &self.params
    }

    /// The motor.
    pub fn motor(&self) -> &MotorTorque {
        &self.motor
    }

    /// The polar inertia $j$.
    pub fn inertia(&self) -> f64 {
        self.inertia
    }

    /// The state at rest at `r` with the speed `eta` and the phase $\varphi_0$ of the
    /// parameters (the ring's slots zero: [`RingedRotor`] places the ring).
    pub fn state_at(&self, r: [f64; 2], v: [f64; 2], eta: f64) -> SVector<f64, 8> {
        SVector::<f64, 8>::from([r[0], r[1], v[0], v[1], 0.0, 0.0, eta, self.params.phi0])
    }

    /// On the paper's ring (gap 1, $K$, $D$, $\nu_2$ from the parameters).
    ///
    /// # Errors
    /// [`RotorError`] if the ring or the composition refuses.
    pub fn on_ring(&self) -> Result<RingedRotor<Self>, RotorError> {
        RingedRotor::new(self.clone(), paper_ring(&self.params, 1.0)?)
    }

    /// Without contact: the ring's gap is [`super::ProfiledJeffcott::OUT_OF_REACH`].
    ///
    /// # Errors
    /// [`RotorError`] if the ring or the composition refuses.
    pub fn off_ring(&self) -> Result<RingedRotor<Self>, RotorError> {
        let gap = super::ProfiledJeffcott::OUT_OF_REACH;
        RingedRotor::new(self.clone(), paper_ring(&self.params, gap)?)
    }

    /// The out-of-balance's reaction torque $\beta(x^{\prime\prime}\sin\varphi -
    /// y^{\prime\prime}\cos\varphi)$ at the state `y` whose derivative is `dy`.
    pub fn reaction_torque(&self, y: &SVector<f64, 8>, dy: &SVector<f64, 8>) -> f64 {
        let (sin, cos) = y[PHASE].sin_cos();
        self.params.beta * (dy[2] * sin - dy[3] * cos)
    }

    /// The energy $E$ of the module's docs without the ring's part (the rotor's kinetic,
    /// the spin's and the out-of-balance's, and the rotor's elastic energy).
    pub fn energy(&self, y: &SVector<f64, 8>) -> f64 {
        let p = &self.params;
        let (sin, cos) = y[PHASE].sin_cos();
        let (vx, vy, eta) = (y[2], y[3], y[ETA]);
        let (ux, uy) = (y[0] - p.ex, y[1] - p.ey);
        0.5 * (vx * vx + vy * vy + self.inertia * eta * eta + ux * ux + uy * uy)
            + p.beta * eta * (vy * cos - vx * sin)
    }

    /// Adds to the accelerations `(a_x, a_y)` already in `dy` the $\eta^\prime$ terms, with
    /// the motor's torque `torque` (0 for a force's share), and writes $\eta^\prime$'s share.
    /// The out-of-balance's coupling is $b = \beta t_\varphi$ with unit mass:
    /// $b\cdot M^{-1}b = \beta^2$ ([`spin_acceleration`]).
    fn couple(&self, phase: f64, torque: f64, dy: &mut SVector<f64, 8>) -> f64 {
        let beta = self.params.beta;
        let (sin, cos) = phase.sin_cos();
        let b_dot_a = beta * (dy[3] * cos - dy[2] * sin);
        let rate = spin_acceleration(torque, self.inertia, b_dot_a, beta * beta);
        dy[2] += beta * rate * sin;
        dy[3] -= beta * rate * cos;
        rate
    }
}

impl SmoothRotor for DrivenJeffcott {
    type Dim = U8;

    fn dim(&self) -> U8 {
        U8
    }

    fn rhs(&self, _t: f64, y: &SVector<f64, 8>, dy: &mut SVector<f64, 8>) {
        let p = &self.params;
        let (eta, phase) = (y[ETA], y[PHASE]);
        let (sin, cos) = phase.sin_cos();
        let radial = p.beta * eta * eta;
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = radial * cos - 2.0 * p.nu1 * y[2] - (y[0] - p.ex);
        dy[3] = radial * sin - 2.0 * p.nu1 * y[3] - (y[1] - p.ey);
        dy[ETA] = self.couple(phase, self.motor.torque(eta), dy);
        dy[PHASE] = eta;
    }

    fn station(&self, y: &SVector<f64, 8>) -> Kinematics {
        Kinematics::new([y[0], y[1]], [y[2], y[3]])
    }

    /// The force enters the coupled accelerations linearly: its share of $\eta^\prime$ and
    /// of the $\eta^\prime$ terms is added with it.
    fn add_station_force(&self, y: &SVector<f64, 8>, f: &Vector2<f64>, dy: &mut SVector<f64, 8>) {
        let mut share = SVector::<f64, 8>::zeros();
        share[2] = f.x;
        share[3] = f.y;
        let rate = self.couple(y[PHASE], 0.0, &mut share);
        dy[2] += share[2];
        dy[3] += share[3];
        dy[ETA] += rate;
    }

    fn ring_slots(&self) -> [usize; 2] {
        [4, 5]
    }

    /// The state's speed $\eta$ and phase $\varphi$ (its acceleration is the field's).
    fn spin(&self, _t: f64, y: &SVector<f64, 8>) -> Option<super::Spin> {
        Some(super::Spin {
            speed: y[ETA],
            angle: y[PHASE],
            accel: f64::NAN,
        })
    }

    fn spin_speed_index(&self) -> Option<usize> {
        Some(ETA)
    }

    /// A torque $t_c$ (in $k_r\gamma^2$) adds to the motor's: $\eta^\prime$ gains
    /// $t_c/(j - \beta^2)$ and the accelerations its coupling, as for a force's share.
    fn add_shaft_torque(&self, y: &SVector<f64, 8>, torque: f64, dy: &mut SVector<f64, 8>) {
        let mut share = SVector::<f64, 8>::zeros();
        let rate = self.couple(y[PHASE], torque, &mut share);
        dy[2] += share[2];
        dy[3] += share[3];
        dy[ETA] += rate;
    }

    /// $2\pi/\eta_\text{ref}$ (the parameters' `eta`).
    fn forcing_period(&self) -> f64 {
        TAU / self.eta_ref
    }

    /// The shaft's turns: $\varphi = \varphi_0 + 2\pi k$ ($\varphi_0$ of the parameters).
    fn strobe_phase(&self, k: u64) -> Option<(usize, f64)> {
        Some((PHASE, self.params.phi0 + TAU * k as f64))
    }

    /// Positions 1 (the gap), velocities and the speed $\eta_\text{ref}$, the phase 1.
    fn state_scale(&self) -> Option<SVector<f64, 8>> {
        let v = self.eta_ref;
        Some(SVector::<f64, 8>::from([1.0, 1.0, v, v, 1.0, 1.0, v, 1.0]))
    }
}
