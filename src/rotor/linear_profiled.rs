//! A linear (finite-element) rotor at a prescribed, time-varying speed ([`SpeedProfile`]):
//! [`ProfiledLinearRotor`], the run-up of a [`LinearRotor`] (issue 21).
//!
//! **The equations.** With the speed $\Omega(t)$ of the profile (rad/s in SI units, the
//! profile's $\eta$), its phase $\Phi(t) = \int_0^t\Omega$ and the rate $\Omega^\prime$,
//!
//! $$M q^{\prime\prime} + (C + \Omega G)\thinspace q^\prime + (K + \Omega^\prime K_{st})\thinspace q
//! = \operatorname{Re}\big(\hat U(\Omega^2 - i\Omega^\prime)\thinspace e^{i\Phi}\big) + f_0,$$
//!
//! $\hat U = \hat F/\Omega_r^2$ the out-of-balance per unit squared speed, from the
//! [`LinearSystem`]'s synchronous force $\hat F$ at its speed $\Omega_r$ (the *reference*
//! speed). An out-of-balance $m e$ at the node's x and y ($\hat U_x = m e\thinspace e^{i\varphi_0}$,
//! $\hat U_y = -i\thinspace m e\thinspace e^{i\varphi_0}$, [`LinearSystem::with_unbalance`]) then
//! pushes with $m e(\Omega^2\cos\varphi + \Omega^\prime\sin\varphi,\ \Omega^2\sin\varphi -
//! \Omega^\prime\cos\varphi)$, $\varphi = \varphi_0 + \Phi$: the radial force and the tangential
//! (Euler) force of the accelerating mass, as in [`super::ProfiledJeffcott`]. *Every*
//! synchronous force of the system is taken for an out-of-balance (scaled by $\Omega^2$).
//! $C = D - \Omega_r G$ from the system's total damping $D$ and the gyroscopic matrix $G$
//! given here. The bearings' coefficients stay the system's, those of the export speed,
//! unless a [`BearingTable`] gives them against the speed
//! ([`ProfiledLinearRotor::with_bearing_table`]): then $K$ and $C$ above are $K(\Omega)$ and
//! $C(\Omega)$.
//!
//! $K_{st}$ is the stiffness that multiplies the spin's acceleration in ROSS's transient
//! (`Ksdt`, from the disks' polar inertia: $I_p\Omega^\prime$ couples the tilts). The crate's
//! imports ([`super::RotorMatrices`]: ROSS's `.mat`) carry no $K_{st}$ (ROSS's
//! `save_mat` does not export it), so it is zero unless given
//! ([`ProfiledLinearRotor::with_acceleration_stiffness`]).
//!
//! At a constant profile at $\Omega_r$ the field is [`LinearRotor`]'s, bit for bit (the
//! corrections are skipped where they are zero; `tests/suite/fe/fe_run_up.rs` checks it).
//!
//! **Free flight is integrated** (no closed form at varying speed), so contact onsets are found
//! by the event detector on the dense output, with [`super::RingedRotor`]'s onset guarantee,
//! the same as for [`super::ProfiledJeffcott`]: every touch of the integrated trajectory's
//! dense output is found, and whether the exact orbit touches is decided to that
//! trajectory's own error. Measured on an undamped circular orbit whose largest distance from
//! the ring's centre is $1 + d$ gaps (`tests/suite/fe/fe_run_up.rs`): at `rtol` $10^{-12}$ touches
//! of depth $d = 10^{-9}$ down to $10^{-12}$ are found ($10^{-13}$ is not: the paper's model
//! finds it), and a miss by $10^{-9}$ is not taken for a touch.

use std::f64::consts::TAU;

use nalgebra::{DMatrix, DVector, Dyn, Vector2};

use super::bearing_table::SpeedCorrection;
use super::matrices::check_matrix;
use super::{BearingTable, LinearRotor, RingedRotor, RotorError, SmoothRotor, SpeedProfile};
use crate::ode::JacobianMut;
use crate::ring::{ForceJacobian, Kinematics, SnubberRing};

/// A [`LinearRotor`] whose speed follows a [`SpeedProfile`] (the module's docs give the
/// equations). State $[q, q^\prime, s_x, s_y]$, as the [`LinearRotor`]'s.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfiledLinearRotor {
    rotor: LinearRotor,
    profile: SpeedProfile,
    /// $G$ as given.
    gyroscopic_given: DMatrix<f64>,
    /// $-M^{-1}G$.
    gyroscopic: DMatrix<f64>,
    /// Speed-dependent stiffness and damping, if given.
    bearings: Option<SpeedCorrection>,
    /// $-M^{-1}K_{st}$, if given.
    acceleration_stiffness: Option<DMatrix<f64>>,
    /// Largest row sums of $|M^{-1}G|$ and $|M^{-1}K_{st}|$ ([`SmoothRotor::max_rate`]).
    row_bounds: [f64; 2],
    strobes_per_revolution: u32,
}

fn largest_row_sum(m: &DMatrix<f64>) -> f64 {
    m.row_iter()
        .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
        .fold(0.0, f64::max)
}

impl LinearRotor {
    /// This rotor at the speed `profile` (rad/s), with the gyroscopic matrix `gyroscopic`
    /// $G$ in the system's coordinates ([`super::RotorMatrices::gyroscopic`], or its
    /// projection for a reduced system). The system's speed is the reference $\Omega_r$
    /// (see [`ProfiledLinearRotor`]); it also sets the state's scale, so take the system at a
    /// speed the run reaches (e.g. the profile's largest).
    ///
    /// # Errors
    /// [`RotorError::MatrixShape`] (named `"G"`) or [`RotorError::MatrixEntry`] for a
    /// gyroscopic matrix of another size or with a non-finite entry, [`RotorError::Singular`]
    /// for a singular $M$.
    pub fn with_speed_profile(
        self,
        gyroscopic: &DMatrix<f64>,
        profile: SpeedProfile,
    ) -> Result<ProfiledLinearRotor, RotorError> {
        check_matrix("G", gyroscopic, self.system().dofs())?;
        let gyroscopic_given = gyroscopic.clone();
        let gyroscopic = -self.system().solve_mass(gyroscopic)?;
        Ok(ProfiledLinearRotor {
            row_bounds: [largest_row_sum(&gyroscopic), 0.0],
            rotor: self,
            profile,
            gyroscopic_given,
            gyroscopic,
            bearings: None,
            acceleration_stiffness: None,
            strobes_per_revolution: 1,
        })
    }
}

impl ProfiledLinearRotor {
    /// With the stiffness $K_{st}$ that multiplies the spin's acceleration (ROSS's `Ksdt`; the
    /// crate's imports have none).
    ///
    /// # Errors
    /// As [`LinearRotor::with_speed_profile`] for the matrix (named `"K_st"`).
    pub fn with_acceleration_stiffness(
        mut self,
        stiffness: &DMatrix<f64>,
    ) -> Result<Self, RotorError> {
        check_matrix("K_st", stiffness, self.rotor.system().dofs())?;
        let k = -self.rotor.system().solve_mass(stiffness)?;
        self.row_bounds[1] = largest_row_sum(&k);
        self.acceleration_stiffness = Some(k);
        Ok(self)
    }

    /// With stiffness and damping that follow the speed ([`BearingTable`]: fluid-film bearings,
    /// seals): the field is that of $K(\Omega)$ and $C(\Omega) + \Omega G$ in place of the
    /// system's $K$ and $D$, with the table's rule between and beyond its grid speeds. The
    /// state's scale stays the system's at its speed.
    ///
    /// # Errors
    /// [`RotorError::BearingTable`] for a table of another size than the system.
    pub fn with_bearing_table(mut self, table: &BearingTable) -> Result<Self, RotorError> {
        let correction = SpeedCorrection::new(table, self.rotor.system(), &self.gyroscopic_given)?;
        self.bearings = Some(correction);
        Ok(self)
    }

    /// With `count` stroboscopic outputs per revolution: output `k` where the phase has
    /// advanced by $2\pi k/S$, $S$ = `count`.
    ///
    /// # Errors
    /// [`RotorError::SpeedProfile`] for `count` = 0.
    pub fn with_strobes_per_revolution(mut self, count: u32) -> Result<Self, RotorError> {
        self.strobes_per_revolution = super::run_up::strobes_per_revolution(count)?;
        Ok(self)
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

    /// The rotor at the reference speed.
    pub fn rotor(&self) -> &LinearRotor {
        &self.rotor
    }

    /// The speed profile.
    pub fn profile(&self) -> &SpeedProfile {
        &self.profile
    }

    /// The out-of-balance's acceleration term $M^{-1}\operatorname{Re}(\hat U(\Omega^2 -
    /// i\Omega^\prime)e^{i\Phi})$ added to `accel` at the speed `speed`, the rate `rate` and the
    /// phase `phase` (shared with [`super::DrivenLinearRotor`], whose speed is a state).
    pub(super) fn add_unbalance(
        rotor: &LinearRotor,
        (speed, rate, phase): (f64, f64, f64),
        accel: &mut nalgebra::DVectorViewMut<'_, f64>,
    ) {
        let w_ref = rotor.system().speed();
        let (sin, cos) = phase.sin_cos();
        // (w / w_ref)^2 is exactly 1 at the reference speed: LinearRotor's field bit for bit.
        let radial = (speed * speed) / (w_ref * w_ref);
        accel.axpy(radial * cos, &rotor.forcing_cos, 1.0);
        accel.axpy(radial * sin, &rotor.forcing_sin, 1.0);
        if rate != 0.0 {
            let tangential = rate / (w_ref * w_ref);
            accel.axpy(tangential * sin, &rotor.forcing_cos, 1.0);
            accel.axpy(-tangential * cos, &rotor.forcing_sin, 1.0);
        }
    }
}

impl SmoothRotor for ProfiledLinearRotor {
    type Dim = Dyn;

    fn dim(&self) -> Dyn {
        self.rotor.dim()
    }

    /// [`LinearRotor`]'s field with $-(\Omega - \Omega_r)M^{-1}G q^\prime$,
    /// $-\Omega^\prime M^{-1}K_{st}q$, the bearing table's correction (if given) and the
    /// out-of-balance at $\Omega(t)$, $\Phi(t)$: no allocation.
    fn rhs(&self, t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        let r = &self.rotor;
        let n = r.system().dofs();
        dy.rows_mut(0, n).copy_from(&y.rows(n, n));
        let mut accel = dy.rows_mut(n, n);
        accel.gemv(1.0, &r.accel, &y.rows(0, 2 * n), 0.0);
        let (speed, rate) = (self.profile.eta(t), self.profile.eta_rate(t));
        let excess = speed - r.system().speed();
        if excess != 0.0 {
            accel.gemv(excess, &self.gyroscopic, &y.rows(n, n), 1.0);
        }
        if let (Some(k), true) = (&self.acceleration_stiffness, rate != 0.0) {
            accel.gemv(rate, k, &y.rows(0, n), 1.0);
        }
        if let Some(bearings) = &self.bearings {
            bearings.add_acceleration(speed, y, &mut accel);
        }
        Self::add_unbalance(r, (speed, rate, self.profile.phase(t)), &mut accel);
        if r.has_constant {
            accel += &r.forcing_constant;
        }
    }

    fn station(&self, y: &DVector<f64>) -> Kinematics {
        self.rotor.station(y)
    }

    fn add_station_force(&self, y: &DVector<f64>, force: &Vector2<f64>, dy: &mut DVector<f64>) {
        self.rotor.add_station_force(y, force, dy);
    }

    fn ring_slots(&self) -> [usize; 2] {
        self.rotor.ring_slots()
    }

    /// The period at the profile's largest speed (the shortest).
    /// The profile's speed and phase.
    fn spin(&self, t: f64, _y: &DVector<f64>) -> Option<super::Spin> {
        Some(super::Spin {
            speed: self.profile.eta(t),
            angle: self.profile.phase(t),
            accel: self.profile.eta_rate(t),
        })
    }

    fn forcing_period(&self) -> f64 {
        TAU / self.profile.eta_max()
    }

    /// Where the phase has advanced by $2\pi k/S$ ([`SpeedProfile::time_of_phase`]); infinite
    /// if it never does.
    fn strobe_time(&self, k: u64) -> f64 {
        let phase = TAU * k as f64 / f64::from(self.strobes_per_revolution);
        self.profile.time_of_phase(phase).unwrap_or(f64::INFINITY)
    }

    /// [`LinearRotor`]'s (at the reference speed).
    fn state_scale(&self) -> Option<DVector<f64>> {
        self.rotor.state_scale()
    }

    /// [`LinearRotor`]'s (at the reference speed).
    fn error_scale(&self) -> Option<DVector<f64>> {
        self.rotor.error_scale()
    }

    /// [`LinearRotor`]'s bound plus $|\Omega - \Omega_r|$ times the largest row sum of
    /// $|M^{-1}G|$ and $\sqrt{|\Omega^\prime|}$ times the root of $|M^{-1}K_{st}|$'s (the
    /// added damping and stiffness: $\sqrt{a + c} \le \sqrt a + \sqrt c$), plus the bearing
    /// table's bound (the same rule).
    fn max_rate(&self, t: f64, y: &DVector<f64>, stiffness: f64, damping: f64) -> Option<f64> {
        let base = self.rotor.max_rate(t, y, stiffness, damping)?;
        let excess = (self.profile.eta(t) - self.rotor.system().speed()).abs();
        let rate = self.profile.eta_rate(t).abs();
        let bearings = self
            .bearings
            .as_ref()
            .map_or(0.0, SpeedCorrection::rate_bound);
        Some(base + excess * self.row_bounds[0] + (rate * self.row_bounds[1]).sqrt() + bearings)
    }

    fn second_order(&self) -> Option<usize> {
        self.rotor.second_order()
    }

    /// [`LinearRotor`]'s Jacobian with $-(\Omega - \Omega_r)M^{-1}G$ added to the velocity
    /// columns, $-\Omega^\prime M^{-1}K_{st}$ to the position columns and the bearing table's
    /// correction to both.
    fn jacobian(
        &self,
        t: f64,
        y: &DVector<f64>,
        contact: Option<&ForceJacobian>,
        jac: &mut JacobianMut<'_, Dyn>,
    ) -> bool {
        if !self.rotor.jacobian(t, y, contact, jac) {
            return false;
        }
        let n = self.rotor.system().dofs();
        let excess = self.profile.eta(t) - self.rotor.system().speed();
        let rate = self.profile.eta_rate(t);
        for i in 0..n {
            for j in 0..n {
                jac[(n + i, n + j)] += excess * self.gyroscopic[(i, j)];
                if let Some(k) = &self.acceleration_stiffness {
                    jac[(n + i, j)] += rate * k[(i, j)];
                }
            }
        }
        if let Some(bearings) = &self.bearings {
            bearings.add_jacobian(self.profile.eta(t), n, jac);
        }
        true
    }
}
