//! A linear (finite-element) rotor on a **non-ideal drive**: [`DrivenLinearRotor`], the speed
//! a state driven by a motor's torque characteristic ([`MotorTorque`], in N m against rad/s)
//! through the polar inertia $J$ (kg m²), loaded by the out-of-balance's reaction torque, as
//! [`super::DrivenJeffcott`] for the paper's rotor (issue 21).
//!
//! **The equations.** The out-of-balance is the [`LinearSystem`]'s synchronous force per unit
//! squared speed, $\hat U = \hat F/\Omega_r^2$ ($\Omega_r$ the system's speed, the reference);
//! its kinetic energy's cross term is $\dot\varphi\thinspace\dot q\cdot b(\varphi)$ with
//! $b(\varphi) = -\operatorname{Im}(\hat U e^{i\varphi})$ (for $m e$ at a node:
//! $m e(-\sin, \cos)$ of $\varphi_0 + \varphi$ at its x and y). Lagrange's equations
//! ([`spin_acceleration`](super::drive) writes them out) give, with $\Omega = \dot\varphi$,
//!
//! $$M q^{\prime\prime} + (C + \Omega G)\thinspace q^\prime + K q = \operatorname{Re}\big(\hat U(\Omega^2 - i\Omega^\prime)e^{i\varphi}\big) + f_0 + E_s f,$$
//! $$J\Omega^\prime = T(\Omega) - b(\varphi)\cdot q^{\prime\prime}, \qquad \varphi^\prime = \Omega,$$
//!
//! $f$ the ring's force at the station, $C = D - \Omega_r G$ as in
//! [`super::ProfiledLinearRotor`] (whose out-of-balance term this shares). The coupled
//! accelerations are solved in closed form (the same function as the paper's rotor's). The
//! gyroscopic moments' reaction on the spin is of second order in the tilts and left out, as in
//! the linear model: $G$ is skew, $q^{\prime\mathsf T}G q^\prime = 0$, so it does no work. No
//! $K_{st}$ (the imports have none, and the spin equation would need its reaction).
//!
//! **Energy.** $E = \tfrac12 q^{\prime\mathsf T}Mq^\prime + \tfrac12 J\Omega^2 +
//! \Omega\thinspace q^\prime\cdot b + \tfrac12 q^{\mathsf T}K_s q - f_0\cdot q + E_\text{ring}$
//! ($K_s$ the symmetric part of $K$) changes by the motor's work $\int T\Omega$ minus
//! $\int q^{\prime\mathsf T}C q^\prime$, the circulatory $\int q^{\prime\mathsf T}K_a q$ ($K_a$
//! the skew part: cross-coupled bearings) and the ring's losses (`tests/fe/fe_drive.rs`
//! checks it).
//!
//! Free flight is integrated, with [`super::RingedRotor`]'s onset guarantee (see
//! [`super::ProfiledLinearRotor`]). The strobes are at equal times $2\pi k/\Omega_r$.

use std::f64::consts::TAU;

use nalgebra::{DMatrix, DVector, DVectorViewMut, Dyn, Matrix2, Vector2};

use super::drive::spin_acceleration;
use super::matrices::check_matrix;
use super::{LinearRotor, MotorTorque, ProfiledLinearRotor, RingedRotor, RotorError, SmoothRotor};
use crate::ring::{Kinematics, SnubberRing};

/// A [`LinearRotor`] whose speed is driven by a [`MotorTorque`] (the module's docs give the
/// equations). State $[q\ (n), q^\prime\ (n), s_x, s_y, \Omega, \varphi]$
/// ([`DrivenLinearRotor::speed_index`], [`DrivenLinearRotor::phase_index`]).
#[derive(Debug, Clone)]
pub struct DrivenLinearRotor {
    rotor: LinearRotor,
    motor: MotorTorque,
    inertia: f64,
    /// $-M^{-1}G$.
    gyroscopic: DMatrix<f64>,
    /// $b(\varphi) = $ `b[0]` $\cos\varphi$ + `b[1]` $\sin\varphi$.
    b: [DVector<f64>; 2],
    /// $M^{-1}b(\varphi)$, the same way.
    minv_b: [DVector<f64>; 2],
    /// $b\cdot M^{-1}b = (\cos, \sin)\thinspace Q\thinspace(\cos, \sin)^{\mathsf T}$.
    q: Matrix2<f64>,
    /// $b\cdot M^{-1}E_s f = (\cos, \sin)\thinspace P f$.
    p: Matrix2<f64>,
}

impl LinearRotor {
    /// This rotor on a non-ideal drive: the motor `motor` ($T(\Omega)$, N m) through the polar
    /// inertia `inertia` $J$ (kg m², the out-of-balance's included), with the gyroscopic
    /// matrix `gyroscopic` $G$ in the system's coordinates. The system's speed is the
    /// reference $\Omega_r$ (the strobes' period, the state's scale).
    ///
    /// # Errors
    /// As [`LinearRotor::with_speed_profile`] for $G$; [`RotorError::Inertia`] unless $J$ is
    /// finite and above $\max_\varphi b\cdot M^{-1}b$ (which holds for any physical rotor).
    pub fn with_drive(
        self,
        gyroscopic: &DMatrix<f64>,
        inertia: f64,
        motor: MotorTorque,
    ) -> Result<DrivenLinearRotor, RotorError> {
        let system = self.system();
        check_matrix("G", gyroscopic, system.dofs())?;
        let gyroscopic = -system.solve_mass(gyroscopic)?;
        let w2 = system.speed() * system.speed();
        let f = system.harmonic_force();
        let b = [f.map(|z| -z.im / w2), f.map(|z| -z.re / w2)];
        let minv_b = [&self.forcing_sin / w2, &self.forcing_cos / -w2];
        let dot = |u: &DVector<f64>, v: &DVector<f64>| u.dot(v);
        let q = Matrix2::from_fn(|i, j| dot(&b[i], &minv_b[j]));
        let c = &self.station_compliance;
        let p = Matrix2::from_fn(|i, j| b[i].dot(&c.column(j)));
        let sym = 0.5 * (q + q.transpose());
        let largest = sym.symmetric_eigenvalues().max();
        if !(inertia.is_finite() && inertia > largest) {
            return Err(RotorError::Inertia {
                inertia,
                required: largest,
            });
        }
        Ok(DrivenLinearRotor {
            rotor: self,
            motor,
            inertia,
            gyroscopic,
            b,
            minv_b,
            q,
            p,
        })
    }
}

impl DrivenLinearRotor {
    /// The index of the speed $\Omega$ in the state, $2n + 2$.
    pub fn speed_index(&self) -> usize {
        2 * self.rotor.system().dofs() + 2
    }

    /// The index of the phase $\varphi$ in the state, $2n + 3$.
    pub fn phase_index(&self) -> usize {
        self.speed_index() + 1
    }

    /// The rotor at the reference speed.
    pub fn rotor(&self) -> &LinearRotor {
        &self.rotor
    }

    /// The motor.
    pub fn motor(&self) -> &MotorTorque {
        &self.motor
    }

    /// The polar inertia $J$.
    pub fn inertia(&self) -> f64 {
        self.inertia
    }

    /// At rest ($q = q^\prime = 0$, the ring at its centre) with the speed `speed` and the
    /// phase 0.
    pub fn rest_state(&self, speed: f64) -> DVector<f64> {
        let mut y = DVector::zeros(self.phase_index() + 1);
        y[self.speed_index()] = speed;
        y
    }

    /// $b(\varphi)\cdot v$ and the out-of-balance's coupling $b(\varphi)$'s weights.
    fn b_dot(&self, (cos, sin): (f64, f64), v: &nalgebra::DVectorView<'_, f64>) -> f64 {
        cos * self.b[0].dot(v) + sin * self.b[1].dot(v)
    }

    /// $b(\varphi)\cdot M^{-1}b(\varphi)$.
    fn b_minv_b(&self, (cos, sin): (f64, f64)) -> f64 {
        let u = Vector2::new(cos, sin);
        u.dot(&(self.q * u))
    }

    /// Subtracts $\Omega^\prime M^{-1}b$ from the acceleration `accel`.
    fn add_coupling(&self, (cos, sin): (f64, f64), rate: f64, accel: &mut DVectorViewMut<'_, f64>) {
        accel.axpy(-rate * cos, &self.minv_b[0], 1.0);
        accel.axpy(-rate * sin, &self.minv_b[1], 1.0);
    }

    /// The out-of-balance's reaction torque $-b(\varphi)\cdot q^{\prime\prime}$ at the state `y`
    /// whose derivative is `dy`.
    pub fn reaction_torque(&self, y: &DVector<f64>, dy: &DVector<f64>) -> f64 {
        let n = self.rotor.system().dofs();
        let (sin, cos) = y[self.phase_index()].sin_cos();
        -self.b_dot((cos, sin), &dy.rows(n, n))
    }

    /// Composes the rotor with `ring` ([`RingedRotor::new`]), the station's scale raised to the
    /// ring's gap ([`LinearRotor::with_gap_scale`]).
    ///
    /// # Errors
    /// As [`RingedRotor::new`].
    pub fn ringed(mut self, ring: SnubberRing) -> Result<RingedRotor<Self>, RotorError> {
        self.rotor = self.rotor.with_gap_scale(ring.gap);
        RingedRotor::new(self, ring)
    }

    /// The state's scale with the speed's ($\Omega_r$) and the phase's (1) appended.
    fn extended(&self, inner: DVector<f64>) -> DVector<f64> {
        let n = inner.len();
        let mut scale = inner.resize_vertically(n + 2, 1.0);
        scale[n] = self.rotor.system().speed();
        scale
    }
}

impl SmoothRotor for DrivenLinearRotor {
    type Dim = Dyn;

    fn dim(&self) -> Dyn {
        Dyn(self.phase_index() + 1)
    }

    /// [`LinearRotor`]'s field at the state's speed and phase, with the spin's equation
    /// solved with it: no allocation.
    fn rhs(&self, _t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        let r = &self.rotor;
        let n = r.system().dofs();
        let (speed, phase) = (y[self.speed_index()], y[self.phase_index()]);
        let (sin, cos) = phase.sin_cos();
        dy.rows_mut(0, n).copy_from(&y.rows(n, n));
        let mut accel = dy.rows_mut(n, n);
        accel.gemv(1.0, &r.accel, &y.rows(0, 2 * n), 0.0);
        accel.gemv(
            speed - r.system().speed(),
            &self.gyroscopic,
            &y.rows(n, n),
            1.0,
        );
        ProfiledLinearRotor::add_unbalance(r, (speed, 0.0, phase), &mut accel);
        if r.has_constant {
            accel += &r.forcing_constant;
        }
        let b_dot_a = self.b_dot((cos, sin), &accel.rows(0, n));
        let torque = self.motor.torque(speed);
        let rate = spin_acceleration(torque, self.inertia, b_dot_a, self.b_minv_b((cos, sin)));
        self.add_coupling((cos, sin), rate, &mut accel);
        dy[self.speed_index()] = rate;
        dy[self.phase_index()] = speed;
    }

    fn station(&self, y: &DVector<f64>) -> Kinematics {
        self.rotor.station(y)
    }

    /// The force's acceleration $M^{-1}E_s f$ and its share of the spin's: no allocation
    /// (its coupling $b\cdot M^{-1}E_s f$ is precomputed as a 2×2 matrix).
    fn add_station_force(&self, y: &DVector<f64>, force: &Vector2<f64>, dy: &mut DVector<f64>) {
        let n = self.rotor.system().dofs();
        let (sin, cos) = y[self.phase_index()].sin_cos();
        let b_dot_a = Vector2::new(cos, sin).dot(&(self.p * force));
        let rate = spin_acceleration(0.0, self.inertia, b_dot_a, self.b_minv_b((cos, sin)));
        self.rotor.add_station_force(y, force, dy);
        self.add_coupling((cos, sin), rate, &mut dy.rows_mut(n, n));
        dy[self.speed_index()] += rate;
    }

    fn ring_slots(&self) -> [usize; 2] {
        self.rotor.ring_slots()
    }

    /// $2\pi/\Omega_r$.
    fn forcing_period(&self) -> f64 {
        TAU / self.rotor.system().speed()
    }

    /// [`LinearRotor`]'s, the speed's $\Omega_r$ and the phase's 1 appended.
    fn state_scale(&self) -> Option<DVector<f64>> {
        Some(self.extended(self.rotor.state_scale()?))
    }

    /// [`LinearRotor`]'s, the speed's $\Omega_r$ and the phase's 1 appended.
    fn error_scale(&self) -> Option<DVector<f64>> {
        Some(self.extended(self.rotor.error_scale()?))
    }

    fn second_order(&self) -> Option<usize> {
        self.rotor.second_order()
    }
}
