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
//! the skew part: cross-coupled bearings) and the ring's losses (`tests/suite/fe/fe_drive.rs`
//! checks it).
//!
//! Free flight is integrated, with [`super::RingedRotor`]'s onset guarantee (see
//! [`super::ProfiledLinearRotor`]). The strobes are at the shaft's turns, where the phase state
//! reaches $2\pi k$ ([`RotorModel::strobe_phase`](crate::hybrid::RotorModel::strobe_phase)).

use std::f64::consts::TAU;

use nalgebra::{DMatrix, DVector, DVectorViewMut, Dyn, Matrix2, Vector2};

use super::bearing_table::SpeedCorrection;
use super::drive::spin_acceleration;
use super::matrices::check_matrix;
use super::{
    BearingTable, LinearRotor, MotorTorque, ProfiledLinearRotor, RingedRotor, RotorError,
    SmoothRotor,
};
use crate::ode::JacobianMut;
use crate::ring::{ForceJacobian, Kinematics, SnubberRing};

/// A [`LinearRotor`] whose speed is driven by a [`MotorTorque`] (the module's docs give the
/// equations). State $[q\ (n), q^\prime\ (n), s_x, s_y, \Omega, \varphi]$
/// ([`DrivenLinearRotor::speed_index`], [`DrivenLinearRotor::phase_index`]).
#[derive(Debug, Clone)]
pub struct DrivenLinearRotor {
    rotor: LinearRotor,
    motor: MotorTorque,
    inertia: f64,
    /// $G$ as given.
    gyroscopic_given: DMatrix<f64>,
    /// $-M^{-1}G$.
    gyroscopic: DMatrix<f64>,
    /// Speed-dependent stiffness and damping, if given.
    bearings: Option<SpeedCorrection>,
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
    /// reference $\Omega_r$ (the forcing period, the state's scale).
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
        let gyroscopic_given = gyroscopic.clone();
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
            gyroscopic_given,
            gyroscopic,
            bearings: None,
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

    /// With stiffness and damping that follow the speed, as
    /// [`ProfiledLinearRotor::with_bearing_table`]: at the state's speed $\Omega$ the field is
    /// that of $K(\Omega)$ and $C(\Omega) + \Omega G$.
    ///
    /// # Errors
    /// [`RotorError::BearingTable`] for a table of another size than the system.
    pub fn with_bearing_table(mut self, table: &BearingTable) -> Result<Self, RotorError> {
        let correction = SpeedCorrection::new(table, self.rotor.system(), &self.gyroscopic_given)?;
        self.bearings = Some(correction);
        Ok(self)
    }

    /// The rotor at the reference speed.
    pub fn rotor(&self) -> &LinearRotor {
        &self.rotor
    }

    /// The ring node's displacement $(q_{i_x}, q_{i_y})$ in a state `y` of this rotor (m, from
    /// its undeflected position; not relative to the ring), as
    /// [`LinearRotor::station_displacement`]. NaN for a state of another length.
    pub fn station_displacement(&self, y: &DVector<f64>) -> [f64; 2] {
        if y.len() != self.phase_index() + 1 {
            return [f64::NAN; 2];
        }
        self.rotor.station_dofs().map(|i| y[i])
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

    /// Writes into `accel` the acceleration $a$ without the spin's coupling $-\Omega^\prime
    /// M^{-1}b$ and without the ring:
    /// $a = [-M^{-1}K \mid -M^{-1}D]\thinspace(q, q^\prime) - (\Omega - \Omega_r)M^{-1}G q^\prime + \Omega^2\operatorname{Re}(M^{-1}\hat U e^{i\varphi}) + M^{-1}f_0$,
    /// plus the bearing table's correction at $\Omega$ (if given).
    fn uncoupled_acceleration(&self, y: &DVector<f64>, accel: &mut DVectorViewMut<'_, f64>) {
        let r = &self.rotor;
        let n = r.system().dofs();
        let (speed, phase) = (y[self.speed_index()], y[self.phase_index()]);
        accel.gemv(1.0, &r.accel, &y.rows(0, 2 * n), 0.0);
        accel.gemv(
            speed - r.system().speed(),
            &self.gyroscopic,
            &y.rows(n, n),
            1.0,
        );
        if let Some(bearings) = &self.bearings {
            bearings.add_acceleration(speed, y, accel);
        }
        ProfiledLinearRotor::add_unbalance(r, (speed, 0.0, phase), accel);
        if r.has_constant {
            *accel += &r.forcing_constant;
        }
    }

    /// Writes into the columns of `jac`'s acceleration rows the uncoupled acceleration's
    /// derivatives by the speed, $\partial a/\partial\Omega = -M^{-1}G q^\prime +
    /// 2\Omega\operatorname{Re}(M^{-1}\hat U e^{i\varphi})$, and by the phase,
    /// $\partial a/\partial\varphi = \Omega^2\operatorname{Re}(iM^{-1}\hat U e^{i\varphi})$.
    fn speed_and_phase_columns(&self, y: &DVector<f64>, jac: &mut JacobianMut<'_, Dyn>) {
        let r = &self.rotor;
        let n = r.system().dofs();
        let (speed, phase) = (y[self.speed_index()], y[self.phase_index()]);
        let (sin, cos) = phase.sin_cos();
        let w2 = r.system().speed() * r.system().speed();
        let mut column = jac.column_mut(self.speed_index());
        let mut d_speed = column.rows_mut(n, n);
        d_speed.gemv(1.0, &self.gyroscopic, &y.rows(n, n), 0.0);
        d_speed.axpy(2.0 * speed * cos / w2, &r.forcing_cos, 1.0);
        d_speed.axpy(2.0 * speed * sin / w2, &r.forcing_sin, 1.0);
        if let Some(bearings) = &self.bearings {
            bearings.add_speed_derivative(speed, y, &mut d_speed);
        }
        let radial = speed * speed / w2;
        let mut column = jac.column_mut(self.phase_index());
        let mut d_phase = column.rows_mut(n, n);
        d_phase.axpy(radial * cos, &r.forcing_sin, 0.0);
        d_phase.axpy(-radial * sin, &r.forcing_cos, 1.0);
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
        let n = self.rotor.system().dofs();
        let (speed, phase) = (y[self.speed_index()], y[self.phase_index()]);
        let (sin, cos) = phase.sin_cos();
        dy.rows_mut(0, n).copy_from(&y.rows(n, n));
        let mut accel = dy.rows_mut(n, n);
        self.uncoupled_acceleration(y, &mut accel);
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

    /// The state's speed $\Omega$ and phase $\varphi$ (its acceleration is the field's).
    fn spin(&self, _t: f64, y: &DVector<f64>) -> Option<super::Spin> {
        Some(super::Spin {
            speed: y[self.speed_index()],
            angle: y[self.phase_index()],
            accel: f64::NAN,
        })
    }

    fn spin_speed_index(&self) -> Option<usize> {
        Some(self.speed_index())
    }

    /// A torque $T_c$ (N m) adds to the motor's: $\Omega^\prime$ gains
    /// $T_c/(J - b\cdot M^{-1}b)$ and the accelerations its coupling $-M^{-1}b$. No allocation.
    fn add_shaft_torque(&self, y: &DVector<f64>, torque: f64, dy: &mut DVector<f64>) {
        let n = self.rotor.system().dofs();
        let (sin, cos) = y[self.phase_index()].sin_cos();
        let rate = spin_acceleration(torque, self.inertia, 0.0, self.b_minv_b((cos, sin)));
        self.add_coupling((cos, sin), rate, &mut dy.rows_mut(n, n));
        dy[self.speed_index()] += rate;
    }

    /// $2\pi/\Omega_r$.
    fn forcing_period(&self) -> f64 {
        TAU / self.rotor.system().speed()
    }

    /// The shaft's turns: $\varphi = 2\pi k$ (from the phase 0 of
    /// [`DrivenLinearRotor::rest_state`]).
    fn strobe_phase(&self, k: u64) -> Option<(usize, f64)> {
        Some((self.phase_index(), TAU * k as f64))
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

    /// Analytic, every entry. With $a$ the acceleration without the spin's coupling (the
    /// ring's force $g = -F$ included: $a = a_0 + M^{-1}E_s g$), $u = (\cos\varphi,
    /// \sin\varphi)$, $b\cdot M^{-1}b = u^{\mathsf T}Qu$, $\Delta = J - b\cdot M^{-1}b$ and
    /// $\dot\Omega = (T - b\cdot a)/\Delta$ (`rhs`),
    /// the field's rows are $q^{\prime\prime} = a - \dot\Omega\thinspace M^{-1}b$,
    /// $\dot\Omega$ and $\dot\varphi = \Omega$. For a state component $y_j$, with $a_j =
    /// \partial a/\partial y_j$ ([`LinearRotor`]'s blocks $-M^{-1}K$, $-M^{-1}D$ and its
    /// contact part $-M^{-1}E_s(F_r, F_v)$, plus $-(\Omega - \Omega_r)M^{-1}G$ in the velocity
    /// columns and the bearing table's correction at $\Omega$, if given),
    ///
    /// $$\frac{\partial\dot\Omega}{\partial y_j} = \frac{T_j - b\cdot a_j + \delta_{j\varphi}\big(\dot\Omega\thinspace\partial_\varphi(b\cdot M^{-1}b) - \partial_\varphi b\cdot a\big)}{\Delta}, \qquad \frac{\partial q^{\prime\prime}}{\partial y_j} = a_j - \frac{\partial\dot\Omega}{\partial y_j}M^{-1}b - \delta_{j\varphi}\dot\Omega\thinspace\partial_\varphi M^{-1}b,$$
    ///
    /// where $T_\Omega = T^\prime(\Omega)$ ([`MotorTorque::slope`]: exact for a linear motor,
    /// a central difference of $T$ alone for a user's closure) and $T_j = 0$ otherwise,
    /// $a_\Omega = -M^{-1}Gq^\prime + 2\Omega\operatorname{Re}(M^{-1}\hat U e^{i\varphi})$
    /// (plus the table's slope between its grid speeds applied to $(q, q^\prime)$),
    /// $a_\varphi = \Omega^2\operatorname{Re}(iM^{-1}\hat U e^{i\varphi})$,
    /// $\partial_\varphi b = b(\varphi + \pi/2)$ (the same for $M^{-1}b$) and
    /// $\partial_\varphi(b\cdot M^{-1}b) = u^{\prime\mathsf T}(Q + Q^{\mathsf T})u$,
    /// $u^\prime = (-\sin\varphi, \cos\varphi)$. The quotient is
    /// the shared `spin_acceleration` again, with $T_j$ (plus the phase's terms) for the
    /// torque and $a_j$ for the acceleration: no second copy of the spin's equation. No
    /// allocation ($a$ is built in the phase column before that column is written).
    fn jacobian(
        &self,
        t: f64,
        y: &DVector<f64>,
        contact: Option<&ForceJacobian>,
        jac: &mut JacobianMut<'_, Dyn>,
    ) -> bool {
        let r = &self.rotor;
        let n = r.system().dofs();
        let (iw, ip) = (self.speed_index(), self.phase_index());
        if jac.nrows() != ip + 1 || jac.ncols() != ip + 1 {
            return false;
        }
        jac.fill(0.0);
        // LinearRotor's Jacobian (it reads nothing of y) is the top-left block.
        if !r.jacobian(t, y, contact, &mut jac.view_mut((0, 0), (iw, iw))) {
            return false;
        }
        let excess = y[iw] - r.system().speed();
        for j in 0..n {
            let mut column = jac.column_mut(n + j);
            column
                .rows_mut(n, n)
                .axpy(excess, &self.gyroscopic.column(j), 1.0);
        }
        if let Some(bearings) = &self.bearings {
            bearings.add_jacobian(y[iw], n, jac);
        }
        let (sin, cos) = y[ip].sin_cos();
        let u = Vector2::new(cos, sin);
        let (b_dot_a, db_dot_a) = {
            let mut column = jac.column_mut(ip);
            let mut a = column.rows_mut(n, n);
            self.uncoupled_acceleration(y, &mut a);
            if let Some(f) = contact {
                a.gemv(-1.0, &r.station_compliance, &f.force, 1.0);
            }
            let a = a.rows(0, n);
            (self.b_dot((cos, sin), &a), self.b_dot((-sin, cos), &a))
        };
        let b_minv_b = self.b_minv_b((cos, sin));
        let rate = spin_acceleration(self.motor.torque(y[iw]), self.inertia, b_dot_a, b_minv_b);
        let du = Vector2::new(-sin, cos);
        let phase_torque = rate * du.dot(&((self.q + self.q.transpose()) * u)) - db_dot_a;
        self.speed_and_phase_columns(y, jac);
        for j in 0..=ip {
            let torque = match j {
                _ if j == iw => self.motor.slope(y[iw]),
                _ if j == ip => phase_torque,
                _ => 0.0,
            };
            let mut column = jac.column_mut(j);
            let mut accel = column.rows_mut(n, n);
            let b_dot_aj = self.b_dot((cos, sin), &accel.rows(0, n));
            let d_rate = spin_acceleration(torque, self.inertia, b_dot_aj, b_minv_b);
            self.add_coupling((cos, sin), d_rate, &mut accel);
            if j == ip {
                self.add_coupling((-sin, cos), rate, &mut accel);
            }
            jac[(iw, j)] = d_rate;
        }
        jac[(ip, iw)] = 1.0;
        true
    }
}
