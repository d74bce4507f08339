//! A linear rotor at constant speed, in any coordinates and SI units: the system
//! ([`LinearSystem`]) and the [`SmoothRotor`] that puts it on the ring ([`LinearRotor`]).
//!
//! $$M q^{\prime\prime} + D q^\prime + K q = \operatorname{Re}\big(\hat F e^{i\Omega t}\big) + f_0,
//! \qquad D = C + \Omega G.$$

use nalgebra::{Complex, DMatrix, DMatrixView, DMatrixViewMut, DVector, Dyn, MatrixXx2, Vector2};

use super::matrices::{check_mass, check_matrix};
use super::{DofLayout, LinearFreeFlight, RotorError, RotorMatrices, SmoothRotor};
use crate::ode::JacobianMut;
use crate::ring::{ForceJacobian, Kinematics};

/// A second-order linear system at the spin speed $\Omega$ (rad/s), in any coordinates
/// (physical DOFs or reduced ones):
///
/// $$M q^{\prime\prime} + D q^\prime + K q = F(t),\qquad
/// F(t) = \operatorname{Re}\big(\hat F e^{i\Omega t}\big) + f_0,$$
///
/// with $D$ the *total* damping ($C + \Omega G$ for a rotor, [`LinearSystem::from_matrices`]),
/// $\hat F$ the complex amplitude of the forces synchronous with the spin (out of balance,
/// [`LinearSystem::with_unbalance`]) and $f_0$ a constant force (gravity,
/// [`LinearSystem::with_gravity`]). In SI units for a finite-element rotor: $q$ in m and rad,
/// forces in N (and N m), time in s.
///
/// A reduction builds its own with [`LinearSystem::from_parts`] from the projected matrices
/// and forces ($T^{\mathsf T} M T$, ..., $T^{\mathsf T}\hat F$).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LinearSystem {
    mass: DMatrix<f64>,
    damping: DMatrix<f64>,
    stiffness: DMatrix<f64>,
    speed: f64,
    harmonic_force: DVector<Complex<f64>>,
    constant_force: DVector<f64>,
}

fn check_finite(field: &'static str, value: f64) -> Result<f64, RotorError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(RotorError::Parameter { field, value })
    }
}

fn check_index(field: &'static str, index: usize, dofs: usize) -> Result<usize, RotorError> {
    if index < dofs {
        Ok(index)
    } else {
        Err(RotorError::DofOutOfRange { field, index, dofs })
    }
}

impl LinearSystem {
    /// The unforced system $M q^{\prime\prime} + D q^\prime + K q = 0$ at the speed
    /// `speed` (rad/s). Errors: a matrix not square or not of `M`'s size
    /// ([`RotorError::MatrixShape`], `D` named `"D"`), a non-finite entry
    /// ([`RotorError::MatrixEntry`]), an `M` that is not symmetric positive definite
    /// ([`RotorError::NotSymmetric`], [`RotorError::MassNotPositiveDefinite`]), a speed not
    /// finite and positive ([`RotorError::Speed`]), no coordinate at all
    /// ([`RotorError::DofCount`]). `D` and `K` may be non-symmetric (cross-coupled bearings).
    pub fn new(
        mass: DMatrix<f64>,
        damping: DMatrix<f64>,
        stiffness: DMatrix<f64>,
        speed: f64,
    ) -> Result<Self, RotorError> {
        let n = mass.nrows();
        if n == 0 {
            // Nothing to move (and nalgebra's solvers panic on empty systems).
            return Err(RotorError::DofCount {
                dofs: 0,
                per_node: 1,
            });
        }
        check_matrix("M", &mass, n)?;
        check_matrix("D", &damping, n)?;
        check_matrix("K", &stiffness, n)?;
        check_mass(&mass)?;
        if !(speed.is_finite() && speed > 0.0) {
            return Err(RotorError::Speed { value: speed });
        }
        Ok(Self {
            mass,
            damping,
            stiffness,
            speed,
            harmonic_force: DVector::zeros(n),
            constant_force: DVector::zeros(n),
        })
    }

    /// A rotor's matrices at the spin speed `speed`: $D = C + \Omega G$ (ROSS's convention,
    /// [`RotorMatrices`]). `C` and `K` are taken as exported (bearings at the export speed).
    /// Errors: as [`LinearSystem::new`].
    pub fn from_matrices(matrices: &RotorMatrices, speed: f64) -> Result<Self, RotorError> {
        if !(speed.is_finite() && speed > 0.0) {
            return Err(RotorError::Speed { value: speed });
        }
        let damping = matrices.damping() + matrices.gyroscopic() * speed;
        Self::new(
            matrices.mass().clone(),
            damping,
            matrices.stiffness().clone(),
            speed,
        )
    }

    /// A system with its forces: [`LinearSystem::new`] plus $\hat F$ (`harmonic_force`) and
    /// $f_0$ (`constant_force`). Errors: as [`LinearSystem::new`]; a force of another length
    /// ([`RotorError::VectorLength`]) or with a non-finite entry ([`RotorError::Parameter`]).
    pub fn from_parts(
        mass: DMatrix<f64>,
        damping: DMatrix<f64>,
        stiffness: DMatrix<f64>,
        speed: f64,
        harmonic_force: DVector<Complex<f64>>,
        constant_force: DVector<f64>,
    ) -> Result<Self, RotorError> {
        let mut system = Self::new(mass, damping, stiffness, speed)?;
        let n = system.dofs();
        for (vector, len) in [
            ("F_hat", harmonic_force.len()),
            ("f0", constant_force.len()),
        ] {
            if len != n {
                return Err(RotorError::VectorLength {
                    vector,
                    len,
                    expected: n,
                });
            }
        }
        for f in harmonic_force.iter() {
            check_finite("F_hat entry (real part)", f.re)?;
            check_finite("F_hat entry (imaginary part)", f.im)?;
        }
        for &f in constant_force.iter() {
            check_finite("f0 entry", f)?;
        }
        system.harmonic_force = harmonic_force;
        system.constant_force = constant_force;
        Ok(system)
    }

    /// Adds an out-of-balance mass at `node` of a physical `layout` (the system's coordinates
    /// are that layout's DOFs): magnitude `me` $= m e$ (kg m) at the angle `phase` (rad) at
    /// $t = 0$, so $F_x = m e\thinspace\Omega^2\cos(\Omega t + \varphi)$,
    /// $F_y = m e\thinspace\Omega^2\sin(\Omega t + \varphi)$ at the node's x and y DOFs
    /// (forward whirl): $\hat F_x = m e\thinspace\Omega^2 e^{i\varphi}$,
    /// $\hat F_y = -i\thinspace m e\thinspace\Omega^2 e^{i\varphi}$. This is ROSS's
    /// `unbalance_force_over_time`. Errors: the coordinates are not whole nodes of the layout
    /// ([`RotorError::DofCount`]), the node is out of range ([`RotorError::NodeOutOfRange`]),
    /// `me` or `phase` not finite ([`RotorError::Parameter`]).
    pub fn with_unbalance(
        mut self,
        layout: DofLayout,
        node: usize,
        me: f64,
        phase: f64,
    ) -> Result<Self, RotorError> {
        let x = self.x_dof(layout, node)?;
        check_finite("unbalance magnitude", me)?;
        check_finite("unbalance phase", phase)?;
        let fx = Complex::from_polar(me * self.speed * self.speed, phase);
        self.harmonic_force[x] += fx;
        self.harmonic_force[x + 1] += fx * Complex::new(0.0, -1.0);
        Ok(self)
    }

    /// Adds a harmonic force of complex amplitude `amplitude` (N) at coordinate `dof`:
    /// $\operatorname{Re}(a\thinspace e^{i\Omega t})$. Errors: `dof` out of range
    /// ([`RotorError::DofOutOfRange`]), a non-finite amplitude.
    pub fn with_harmonic_force(
        mut self,
        dof: usize,
        amplitude: Complex<f64>,
    ) -> Result<Self, RotorError> {
        check_index("force dof", dof, self.dofs())?;
        check_finite("force amplitude (real part)", amplitude.re)?;
        check_finite("force amplitude (imaginary part)", amplitude.im)?;
        self.harmonic_force[dof] += amplitude;
        Ok(self)
    }

    /// Adds a constant force `newtons` at coordinate `dof`. Errors: `dof` out of range
    /// ([`RotorError::DofOutOfRange`]), a non-finite force.
    pub fn with_constant_force(mut self, dof: usize, newtons: f64) -> Result<Self, RotorError> {
        check_index("force dof", dof, self.dofs())?;
        self.constant_force[dof] += check_finite("constant force", newtons)?;
        Ok(self)
    }

    /// Adds the weight of the rotor under the acceleration `acceleration` $= (g_x, g_y)$
    /// (m/s², e.g. `[0.0, -9.81]`) in a physical `layout`: $f_0 \mathrel{+}= M u$ with $u$ the
    /// rigid translation ($g_x$ at every node's x, $g_y$ at every y; exact for a consistent
    /// mass matrix). Errors: the coordinates are not whole nodes of the layout, a non-finite
    /// acceleration.
    pub fn with_gravity(
        mut self,
        layout: DofLayout,
        acceleration: [f64; 2],
    ) -> Result<Self, RotorError> {
        check_finite("gravity x", acceleration[0])?;
        check_finite("gravity y", acceleration[1])?;
        let per_node = layout.per_node();
        let n = self.dofs();
        if !n.is_multiple_of(per_node) {
            return Err(RotorError::DofCount { dofs: n, per_node });
        }
        let u = DVector::from_fn(n, |i, _| match i % per_node {
            0 => acceleration[0],
            1 => acceleration[1],
            _ => 0.0,
        });
        self.constant_force.gemv(1.0, &self.mass, &u, 1.0);
        Ok(self)
    }

    fn x_dof(&self, layout: DofLayout, node: usize) -> Result<usize, RotorError> {
        let (n, per_node) = (self.dofs(), layout.per_node());
        if !n.is_multiple_of(per_node) {
            return Err(RotorError::DofCount { dofs: n, per_node });
        }
        if node >= n / per_node {
            return Err(RotorError::NodeOutOfRange {
                node,
                nodes: n / per_node,
            });
        }
        Ok(per_node * node)
    }

    /// Number of coordinates $n$.
    pub fn dofs(&self) -> usize {
        self.mass.nrows()
    }
    /// Mass matrix $M$.
    pub fn mass(&self) -> &DMatrix<f64> {
        &self.mass
    }
    /// Total damping $D$ ($C + \Omega G$ for a rotor).
    pub fn damping(&self) -> &DMatrix<f64> {
        &self.damping
    }
    /// Stiffness matrix $K$.
    pub fn stiffness(&self) -> &DMatrix<f64> {
        &self.stiffness
    }
    /// Spin speed $\Omega$, rad/s (the frequency of $\hat F$).
    pub fn speed(&self) -> f64 {
        self.speed
    }
    /// Complex amplitude $\hat F$ of the synchronous force.
    pub fn harmonic_force(&self) -> &DVector<Complex<f64>> {
        &self.harmonic_force
    }
    /// Constant force $f_0$.
    pub fn constant_force(&self) -> &DVector<f64> {
        &self.constant_force
    }

    /// The synchronous steady response's complex amplitude $X$, $q(t) = \operatorname{Re}(X
    /// e^{i\Omega t})$: $(K - \Omega^2 M + i\Omega D) X = \hat F$ (complex LU). The constant
    /// force's part is [`LinearSystem::static_deflection`] (not a harmonic: it is added to
    /// $\operatorname{Re}(X e^{i\Omega t})$, not to $X$). One step of iterative refinement
    /// follows the solve. Error: a singular dynamic stiffness
    /// (an undamped resonance at $\Omega$, [`RotorError::Singular`]).
    pub fn steady_response(&self) -> Result<DVector<Complex<f64>>, RotorError> {
        let (w, n) = (self.speed, self.dofs());
        let a = DMatrix::from_fn(n, n, |i, j| {
            Complex::new(
                self.stiffness[(i, j)] - w * w * self.mass[(i, j)],
                w * self.damping[(i, j)],
            )
        });
        let singular = RotorError::Singular {
            matrix: "K - W^2 M + i W D",
            hint: "an undamped resonance at the spin speed",
        };
        let finite =
            |x: &DVector<Complex<f64>>| x.iter().all(|v| v.re.is_finite() && v.im.is_finite());
        let lu = a.clone().lu();
        let mut x = lu
            .solve(&self.harmonic_force)
            .filter(finite)
            .ok_or(singular)?;
        // One step of iterative refinement: the LU's rounding grows with the condition of
        // the dynamic stiffness (Rayleigh damping's stiff high modes).
        let residual = &self.harmonic_force - &a * &x;
        if let Some(dx) = lu.solve(&residual).filter(finite) {
            x += dx;
        }
        Ok(x)
    }
    /// Each coordinate's frequency: the rate at which an error in its velocity turns into
    /// displacement, $\omega_i = \sqrt{M_{ii}/P_{ii}}$ with $P = M K_s^{-1} M$ and $K_s$ the
    /// symmetric part of $K$. A velocity error $\delta v\thinspace e_i$ starts free oscillations in the
    /// mass-normalised modes $\phi_k$ ($K_s\phi_k = \omega_k^2 M\phi_k$) of amplitudes
    /// $c_k = \phi_k^{\mathsf T}Me_i\thinspace\delta v/\omega_k$, whose mass-weighted sum of
    /// squares is $\sum_k c_k^2 = P_{ii}\thinspace\delta v^2$, against the
    /// error's own $M_{ii}\thinspace\delta v^2$. For a modal coordinate ($M = I$, $K$
    /// diagonal) it is the mode's natural frequency; a physical coordinate, which takes part in
    /// the low modes, gets a frequency near the lowest. $\Omega$ (the speed) for every
    /// coordinate when $K_s$ is singular or the ratio is not finite and positive for one of
    /// them (a free rotor's rigid-body modes). One LU of $K_s$.
    pub fn coordinate_frequencies(&self) -> DVector<f64> {
        let n = self.dofs();
        let fallback = DVector::from_element(n, self.speed);
        let ks = (&self.stiffness + self.stiffness.transpose()) * 0.5;
        let Some(x) = ks.lu().solve(&self.mass) else {
            return fallback;
        };
        let w = DVector::from_fn(n, |i, _| {
            let mkm = self.mass.row(i).dot(&x.column(i).transpose());
            (self.mass[(i, i)] / mkm).sqrt()
        });
        if w.iter().all(|v| v.is_finite() && *v > 0.0) {
            w
        } else {
            fallback
        }
    }

    /// $M^{-1} B$ for the columns of `b` (one LU of $M$). Error: a singular $M$
    /// ([`RotorError::Singular`]).
    pub fn solve_mass(&self, b: &DMatrix<f64>) -> Result<DMatrix<f64>, RotorError> {
        self.mass
            .clone()
            .lu()
            .solve(b)
            .filter(|x| x.iter().all(|v| v.is_finite()))
            .ok_or(RotorError::Singular {
                matrix: "M",
                hint:
                    "every coordinate needs inertia (a massless coordinate must be condensed out)",
            })
    }

    /// The first-order state matrix of $x = (q, q^\prime)$,
    /// $A = \begin{pmatrix}0 & I\\\\ -M^{-1}K & -M^{-1}D\end{pmatrix}$ ($2n\times 2n$).
    /// Error: a singular $M$ ([`RotorError::Singular`]).
    pub fn state_matrix(&self) -> Result<DMatrix<f64>, RotorError> {
        let n = self.dofs();
        let mut kd = DMatrix::zeros(n, 2 * n);
        kd.columns_mut(0, n).copy_from(&self.stiffness);
        kd.columns_mut(n, n).copy_from(&self.damping);
        let accel = self.solve_mass(&kd)?;
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        a.view_mut((0, n), (n, n)).fill_diagonal(1.0);
        a.view_mut((n, 0), (n, 2 * n)).copy_from(&(-accel));
        Ok(a)
    }

    /// The static deflection $K^{-1} f_0$ under the constant force (zero without one, whatever
    /// $K$). Error: $f_0 \ne 0$ and $K$ singular ([`RotorError::Singular`]: a rotor with free
    /// rigid-body modes, e.g. ROSS's axial and torsional DOFs: take
    /// [`RotorMatrices::lateral`]).
    pub fn static_deflection(&self) -> Result<DVector<f64>, RotorError> {
        if self.constant_force.iter().all(|&f| f == 0.0) {
            return Ok(DVector::zeros(self.dofs()));
        }
        self.stiffness
            .clone()
            .lu()
            .solve(&self.constant_force)
            .filter(|x| x.iter().all(|v| v.is_finite()))
            .ok_or(RotorError::Singular {
                matrix: "K",
                hint:
                    "a rigid-body mode under a constant force (drop the axial and torsional DOFs)",
            })
    }
}

/// A [`LinearSystem`] as a [`SmoothRotor`] with the ring at two of its coordinates (the ring
/// node's physical x and y), in SI units. State $y = [q\ (n),\ q^\prime\ (n),\ s_x,\ s_y]$,
/// $2n + 2$ components; the ring's position $s$ in m from its rest centre.
///
/// The right-hand side is one dense product with the precomputed
/// $[-M^{-1}K \mid -M^{-1}D]$ (an $n \times 2n$ matrix) plus the forcing
/// $M^{-1}\hat F$ and $M^{-1} f_0$; a ring force adds two columns of $M^{-1}$. Nothing is
/// allocated per evaluation.
///
/// The station is the ring node's displacement relative to the ring's centre:
/// $r = (q_{i_x}, q_{i_y}) - o$, with $o$ the ring centre's offset from the undeflected node (m).
///
/// # The ring in SI units, and the non-dimensional ring
///
/// [`SnubberRing::from_units`](crate::ring::SnubberRing::from_units) builds the ring from its
/// physical parameters: unit stiffness $k_s$ (N/m), unit damping $c_s$ (N s/m), preloads
/// $\Delta_x, \Delta_y$ (m), radial gap $\gamma$ (m). The element's fields are then
/// $K = k_s$, $D = \Delta$, $\nu_2 = c_s/2$, gap $= \gamma$, and its force is in N: per axis
/// $f = 2k_s s + 2c_s s^\prime$ inside the preload, $\operatorname{sign}(s)\thinspace k_s(|s| +
/// \Delta) + c_s s^\prime$ beyond it. The element is scale-free (its tolerances are relative to
/// the gap), so it runs in metres as it is.
///
/// The paper's non-dimensional ring is the same ring in the units of its 2-DOF rotor of mass
/// $m$ and stiffness $k_r$, $\omega_n = \sqrt{k_r/m}$: lengths in $\gamma$, forces in
/// $k_r\gamma$, time in $1/\omega_n$. There $K = k_s/k_r$, $D = \Delta/\gamma$,
/// $\nu_2 = c_s/(2\sqrt{k_r m})$, gap 1. For any rotor the rule is the same: pick a length
/// unit $L$ (the gap), a force unit $F$ and a time unit $T$; then $K = k_s L/F$,
/// $D = \Delta/L$, $\nu_2 = c_s L/(2FT)$, gap $= \gamma/L$, and the rotor's equations are
/// written in the same units. This type uses $L = 1$ m, $F = 1$ N, $T = 1$ s.
///
/// # Example
///
/// A Jeffcott rotor (10 kg on 1e6 N/m, 2 % damping) at 1.2 times its critical speed with a
/// ring 0.1 mm out: its steady response is the closed form, and on the ring it makes contact.
///
/// ```
/// use jeffcott::hybrid::{simulate, OutputPlan, SimOptions};
/// use jeffcott::nalgebra::{Complex, DMatrix};
/// use jeffcott::ring::SnubberRing;
/// use jeffcott::rotor::{LinearRotor, LinearSystem};
///
/// let (m, k) = (10.0f64, 1e6f64);
/// let c = 2.0 * 0.02 * (k * m).sqrt();
/// let w = 1.2 * (k / m).sqrt();
/// let me = 5e-4; // kg m, phase 0: F = me w^2 (cos wt, sin wt)
/// let eye = DMatrix::<f64>::identity(2, 2);
/// let system = LinearSystem::new(&eye * m, &eye * c, &eye * k, w)?
///     .with_harmonic_force(0, Complex::new(me * w * w, 0.0))?
///     .with_harmonic_force(1, Complex::new(0.0, -me * w * w))?;
/// let x = system.steady_response()?;
/// let closed = me * w * w / Complex::new(k - w * w * m, c * w);
/// assert!((x[0] - closed).norm() < 1e-12 * closed.norm());
/// assert!(x[0].norm() > 1.5e-4); // beyond the ring's gap of 1e-4 m
///
/// let ring = SnubberRing::from_units(5e6, 50.0, [0.0, 0.0], 1e-4)?;
/// let model = LinearRotor::new(system, [0, 1], [0.0, 0.0])?.ringed(ring)?;
/// let y0 = model.rotor().rest_state();
/// let plan = OutputPlan { t_end: 0.2, strobe: None, dense: None, events: false };
/// let stats = simulate(&model, 0.0, &y0, &plan, &SimOptions::default(), &mut ())?;
/// assert!(stats.transitions > 0); // the rotor meets the ring
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct LinearRotor {
    system: LinearSystem,
    station: [usize; 2],
    offset: [f64; 2],
    /// $[-M^{-1}K \mid -M^{-1}D]$, $n \times 2n$.
    pub(super) accel: DMatrix<f64>,
    /// $\operatorname{Re}(M^{-1}\hat F)$ and $-\operatorname{Im}(M^{-1}\hat F)$: the forcing
    /// is `cos` times the first plus `sin` times the second.
    pub(super) forcing_cos: DVector<f64>,
    pub(super) forcing_sin: DVector<f64>,
    /// $M^{-1} f_0$.
    pub(super) forcing_constant: DVector<f64>,
    pub(super) has_constant: bool,
    /// The columns of $M^{-1}$ at the station's coordinates.
    pub(super) station_compliance: MatrixXx2<f64>,
    scale: DVector<f64>,
    /// Each coordinate's frequency $\omega_i$ ([`LinearSystem::coordinate_frequencies`],
    /// $\Omega$ where it has none), weighing its velocity's error
    /// ([`SmoothRotor::error_scale`]); `None` with [`LinearRotor::with_frequency_weights`]
    /// `(false)`.
    frequencies: Option<DVector<f64>>,
    /// Row sums of $|M^{-1}K|$, of $|M^{-1}D|$ and of the station's columns of $|M^{-1}|$
    /// ([`SmoothRotor::max_rate`]).
    row_sums: [DVector<f64>; 3],
    /// Whether [`SmoothRotor::linear_free_flight`] gives the closed form.
    exact_free_flight: bool,
}

impl LinearRotor {
    /// The rotor `system` with the ring at its coordinates `station` $= [i_x, i_y]$ (the ring
    /// node's physical x and y: [`RotorMatrices::x_dof`] and the next one for a physical
    /// layout), the ring's rest centre at `ring_offset` (m) from the undeflected node.
    /// Precomputes $M^{-1}K$, $M^{-1}D$, the forcing and the station's columns of $M^{-1}$
    /// (one LU of $M$) and the state's scale ([`SmoothRotor::state_scale`]).
    ///
    /// Errors: a station coordinate out of range ([`RotorError::DofOutOfRange`]) or given twice
    /// ([`RotorError::StationCoincident`]), a non-finite offset ([`RotorError::Parameter`]),
    /// a singular $M$ ([`RotorError::Singular`]).
    pub fn new(
        system: LinearSystem,
        station: [usize; 2],
        ring_offset: [f64; 2],
    ) -> Result<Self, RotorError> {
        let n = system.dofs();
        check_index("station x", station[0], n)?;
        check_index("station y", station[1], n)?;
        if station[0] == station[1] {
            return Err(RotorError::StationCoincident { index: station[0] });
        }
        check_finite("ring offset x", ring_offset[0])?;
        check_finite("ring offset y", ring_offset[1])?;
        let mut rhs = DMatrix::zeros(n, 2 * n + 5);
        rhs.columns_mut(0, n).copy_from(&system.stiffness);
        rhs.columns_mut(n, n).copy_from(&system.damping);
        rhs.column_mut(2 * n)
            .copy_from(&system.harmonic_force.map(|f| f.re));
        rhs.column_mut(2 * n + 1)
            .copy_from(&system.harmonic_force.map(|f| -f.im));
        rhs.column_mut(2 * n + 2).copy_from(&system.constant_force);
        rhs[(station[0], 2 * n + 3)] = 1.0;
        rhs[(station[1], 2 * n + 4)] = 1.0;
        let x = system.solve_mass(&rhs)?;
        let accel = -x.columns(0, 2 * n);
        let station_compliance =
            MatrixXx2::from_columns(&[x.column(2 * n + 3), x.column(2 * n + 4)]);
        let abs_sums = |m: nalgebra::DMatrixView<f64>| {
            DVector::from_fn(n, |i, _| m.row(i).iter().map(|v| v.abs()).sum())
        };
        let row_sums = [
            abs_sums(accel.columns(0, n)),
            abs_sums(accel.columns(n, n)),
            abs_sums(station_compliance.columns(0, 2)),
        ];
        let mut rotor = Self {
            accel,
            forcing_cos: x.column(2 * n).into_owned(),
            forcing_sin: x.column(2 * n + 1).into_owned(),
            forcing_constant: x.column(2 * n + 2).into_owned(),
            has_constant: system.constant_force.iter().any(|&f| f != 0.0),
            station_compliance,
            scale: DVector::zeros(2 * n + 2),
            frequencies: Some(system.coordinate_frequencies()),
            row_sums,
            system,
            station,
            offset: ring_offset,
            exact_free_flight: true,
        };
        rotor.scale = rotor.natural_scale();
        Ok(rotor)
    }

    /// The state's scale before the gap is known ([`SmoothRotor::state_scale`]).
    fn natural_scale(&self) -> DVector<f64> {
        let n = self.system.dofs();
        let w = self.system.speed;
        let amplitude = match (
            self.system.steady_response(),
            self.system.static_deflection(),
        ) {
            (Ok(x), Ok(q0)) => DVector::from_fn(n, |i, _| x[i].norm() + q0[i].abs()),
            _ => DVector::zeros(n),
        };
        let largest = amplitude.amax();
        let floor = if largest > 0.0 && largest.is_finite() {
            1e-3 * largest
        } else {
            1e-3
        };
        DVector::from_fn(2 * n + 2, |i, _| {
            let q = if i < 2 * n {
                amplitude[i % n].max(floor)
            } else {
                floor
            };
            if (n..2 * n).contains(&i) {
                q * w
            } else {
                q
            }
        })
    }

    /// The rotor with the state's scale in the contact's units: the ring's gap `gap` (m) is
    /// the length the contact resolves, so an error at the tolerance should move the station
    /// by about the tolerance times the gap, whatever the free response.
    ///
    /// 1. Where the station's scale (its steady unbalance response plus static deflection,
    ///    [`SmoothRotor::state_scale`]) exceeds the gap, every component's scale is divided
    ///    by the same factor, so that the station's is the gap: each coordinate keeps its
    ///    share of the free response's shape (rotations and distant nodes in proportion),
    ///    at the station's accuracy. Near a critical speed, or on a soft mount under gravity,
    ///    the free response is many gaps (thousands to $10^{12}$) and that scale would let
    ///    the absolute tolerance pass contacts by.
    /// 2. The station's scale and the ring's slots are raised to at least the gap (and
    ///    $\Omega$ `gap` for the station's velocities): a run that sees the ring should not
    ///    measure the station's error against a smaller steady amplitude either.
    ///
    /// [`RingedRotor`] runs take the scale as it is; call this with the ring's gap before
    /// composing (the helper [`LinearRotor::ringed`] does). Idempotent.
    ///
    /// [`RingedRotor`]: super::RingedRotor
    #[must_use]
    pub fn with_gap_scale(mut self, gap: f64) -> Self {
        let n = self.system.dofs();
        let w = self.system.speed;
        if gap.is_finite() && gap > 0.0 {
            let station = self.scale[self.station[0]].max(self.scale[self.station[1]]);
            if station > gap {
                self.scale *= gap / station;
            }
            for i in self.station {
                self.scale[i] = self.scale[i].max(gap);
                self.scale[n + i] = self.scale[n + i].max(gap * w);
            }
            for i in [2 * n, 2 * n + 1] {
                self.scale[i] = self.scale[i].max(gap);
            }
        }
        self
    }

    /// The rotor with each velocity's error weighed by its coordinate's frequency (`true`,
    /// the default: [`SmoothRotor::error_scale`]) or by the state's scale as every component's
    /// (`false`: [`SmoothRotor::state_scale`], the runs before the weights).
    #[must_use]
    pub fn with_frequency_weights(mut self, on: bool) -> Self {
        self.frequencies = on.then(|| self.system.coordinate_frequencies());
        self
    }

    /// Composes the rotor with `ring` ([`super::RingedRotor::new`]), the scale of the station
    /// raised to the ring's gap ([`LinearRotor::with_gap_scale`]). Errors: as
    /// [`super::RingedRotor::new`].
    pub fn ringed(
        self,
        ring: crate::ring::SnubberRing,
    ) -> Result<super::RingedRotor<Self>, RotorError> {
        let gap = ring.gap;
        super::RingedRotor::new(self.with_gap_scale(gap), ring)
    }

    /// The rotor with its free flight in closed form (`true`, the default:
    /// [`SmoothRotor::linear_free_flight`], exact between contacts with the certified onset
    /// search, at the cost of one eigen-decomposition of the $2n\times 2n$ state matrix when
    /// composed with the ring) or integrated (`false`).
    #[must_use]
    pub fn with_exact_free_flight(mut self, exact: bool) -> Self {
        self.exact_free_flight = exact;
        self
    }

    /// The system.
    pub fn system(&self) -> &LinearSystem {
        &self.system
    }
    /// The station's coordinates $[i_x, i_y]$.
    pub fn station_dofs(&self) -> [usize; 2] {
        self.station
    }
    /// The ring centre's offset from the undeflected station, m.
    pub fn ring_offset(&self) -> [f64; 2] {
        self.offset
    }

    /// The ring node's displacement $(q_{i_x}, q_{i_y})$ in a state `y` (m, from its
    /// undeflected position; not relative to the ring). Returns NaN for a state of another
    /// length.
    pub fn station_displacement(&self, y: &DVector<f64>) -> [f64; 2] {
        match (y.get(self.station[0]), y.get(self.station[1])) {
            (Some(&x), Some(&yy)) if y.len() == 2 * self.system.dofs() + 2 => [x, yy],
            _ => [f64::NAN; 2],
        }
    }

    /// $[-M^{-1}K \mid -M^{-1}D]$ ($n \times 2n$): the acceleration's dependence on
    /// $[q, q^\prime]$.
    pub fn acceleration_matrix(&self) -> &DMatrix<f64> {
        &self.accel
    }

    /// The station's two columns of $M^{-1}$: the acceleration per unit force at the station
    /// along x and y.
    pub fn station_compliance(&self) -> &MatrixXx2<f64> {
        &self.station_compliance
    }

    /// Writes the Jacobian of [`SmoothRotor::rhs`] into `jac` ($(2n + 2) \times (2n + 2)$,
    /// every entry written): $\begin{pmatrix} 0 & I \\\\ -M^{-1}K & -M^{-1}D \end{pmatrix}$
    /// and zero rows and columns for the ring's slots (set by the composition). Constant: the
    /// rotor is linear. The ring's contribution in contact is not included. Returns `false`
    /// (writing nothing) for a matrix of another size.
    pub fn write_jacobian(&self, jac: &mut crate::ode::JacobianMut<'_, Dyn>) -> bool {
        let n = self.system.dofs();
        if jac.nrows() != 2 * n + 2 || jac.ncols() != 2 * n + 2 {
            return false;
        }
        jac.fill(0.0);
        jac.view_mut((0, n), (n, n)).fill_diagonal(1.0);
        jac.view_mut((n, 0), (n, 2 * n)).copy_from(&self.accel);
        true
    }

    /// The state at $t = 0$ of the rotor's steady orbit without the ring: the static
    /// deflection plus the synchronous response, $q = q_s + \operatorname{Re} X$,
    /// $q^\prime = \operatorname{Re}(i\Omega X) = -\Omega\operatorname{Im} X$
    /// ([`LinearSystem::steady_response`], [`LinearSystem::static_deflection`]), the ring at its
    /// rest centre. Off the ring this is the periodic orbit itself: the start of a continuation
    /// in speed from below the first contact
    /// ([`rub_map`](crate::stability::rub_map)).
    ///
    /// # Errors
    /// Those of the two solves ([`RotorError::Singular`]).
    pub fn steady_state(&self) -> Result<DVector<f64>, RotorError> {
        let n = self.system.dofs();
        let x = self.system.steady_response()?;
        let q0 = self.system.static_deflection()?;
        let w = self.system.speed;
        let mut y = DVector::zeros(2 * n + 2);
        for i in 0..n {
            y[i] = q0[i] + x[i].re;
            y[n + i] = -w * x[i].im;
        }
        Ok(y)
    }

    /// The state at rest: $q = q^\prime = 0$ and the ring at its rest centre ($s = 0$), as
    /// ROSS's Newmark starts. If the offset puts the undeflected node beyond the gap, place the
    /// ring with [`super::RingedRotor::make_consistent`].
    pub fn rest_state(&self) -> DVector<f64> {
        DVector::zeros(2 * self.system.dofs() + 2)
    }
}

impl SmoothRotor for LinearRotor {
    type Dim = Dyn;

    fn dim(&self) -> Dyn {
        Dyn(2 * self.system.dofs() + 2)
    }

    /// $q^{\prime\prime} = -M^{-1}K q - M^{-1}D q^\prime + M^{-1}F(t)$: one matrix-vector
    /// product and three vector updates, no allocation.
    fn rhs(&self, t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        let n = self.system.dofs();
        dy.rows_mut(0, n).copy_from(&y.rows(n, n));
        let mut accel = dy.rows_mut(n, n);
        accel.gemv(1.0, &self.accel, &y.rows(0, 2 * n), 0.0);
        let (sin, cos) = (self.system.speed * t).sin_cos();
        accel.axpy(cos, &self.forcing_cos, 1.0);
        accel.axpy(sin, &self.forcing_sin, 1.0);
        if self.has_constant {
            accel += &self.forcing_constant;
        }
    }

    fn station(&self, y: &DVector<f64>) -> Kinematics {
        let n = self.system.dofs();
        let [i, j] = self.station;
        Kinematics::new(
            [y[i] - self.offset[0], y[j] - self.offset[1]],
            [y[n + i], y[n + j]],
        )
    }

    fn add_station_force(&self, _y: &DVector<f64>, force: &Vector2<f64>, dy: &mut DVector<f64>) {
        let n = self.system.dofs();
        dy.rows_mut(n, n)
            .gemv(1.0, &self.station_compliance, force, 1.0);
    }

    fn ring_slots(&self) -> [usize; 2] {
        let n = self.system.dofs();
        [2 * n, 2 * n + 1]
    }

    /// [`LinearRotor::write_jacobian`], and in contact $-M^{-1}E_s\thinspace(F_r, F_v)$ in the
    /// station's position and velocity columns ($M^{-1}E_s$: the station's two columns of
    /// $M^{-1}$, [`LinearRotor::station_compliance`]; $F_r$, $F_v$ the ring force's Jacobians).
    fn jacobian(
        &self,
        _t: f64,
        _y: &DVector<f64>,
        contact: Option<&ForceJacobian>,
        jac: &mut JacobianMut<'_, Dyn>,
    ) -> bool {
        if !self.write_jacobian(jac) {
            return false;
        }
        let Some(f) = contact else {
            return true;
        };
        let n = self.system.dofs();
        for (a, &dof) in self.station.iter().enumerate() {
            for (col, d) in [(dof, &f.position), (n + dof, &f.velocity)] {
                for k in 0..n {
                    let b = self.station_compliance.row(k);
                    jac[(n + k, col)] -= b[0] * d[(0, a)] + b[1] * d[(1, a)];
                }
            }
        }
        true
    }

    /// [`SmoothRotor::jacobian`]'s $J$ times $V$ without forming $J$: the position rows are
    /// $V$'s velocity rows, the velocity rows $-M^{-1}(K, D)$ times $V$'s position and
    /// velocity rows, and in contact the rank-two
    /// $-M^{-1}E_s\thinspace(F_r V_r + F_v V_v)$ ($V_r$, $V_v$: $V$'s rows of the station's positions and velocities); about half the dense
    /// product's work and no $J$ written.
    fn jacobian_product(
        &self,
        _t: f64,
        _y: &DVector<f64>,
        contact: Option<&ForceJacobian>,
        v: &[f64],
        out: &mut [f64],
    ) -> bool {
        let n = self.system.dofs();
        let rows = 2 * n + 2;
        if v.len() != out.len() || !v.len().is_multiple_of(rows) {
            return false;
        }
        let k = v.len() / rows;
        let v = DMatrixView::from_slice(v, rows, k);
        let mut out = DMatrixViewMut::from_slice(out, rows, k);
        out.rows_mut(0, n).copy_from(&v.rows(n, n));
        out.rows_mut(n, n)
            .gemm(1.0, &self.accel, &v.rows(0, 2 * n), 0.0);
        let Some(f) = contact else {
            return true;
        };
        let [i, j] = self.station;
        for c in 0..k {
            // w = F_r v_r + F_v v_v for this column; its velocity rows less M^{-1}E_s w.
            let vr = Vector2::new(v[(i, c)], v[(j, c)]);
            let vv = Vector2::new(v[(n + i, c)], v[(n + j, c)]);
            let w = f.position * vr + f.velocity * vv;
            out.column_mut(c)
                .rows_mut(n, n)
                .gemv(-1.0, &self.station_compliance, &w, 1.0);
        }
        true
    }

    /// $n$: the state is $[q, q^\prime, s]$ and the first $n$ rows of [`SmoothRotor::rhs`]
    /// copy $q^\prime$.
    fn second_order(&self) -> Option<usize> {
        Some(self.system.dofs())
    }

    /// The constant speed, and the angle $\Omega t$.
    fn spin(&self, t: f64, _y: &DVector<f64>) -> Option<super::Spin> {
        let speed = self.system.speed;
        Some(super::Spin {
            speed,
            angle: speed * t,
            accel: 0.0,
        })
    }

    fn forcing_period(&self) -> f64 {
        std::f64::consts::TAU / self.system.speed
    }

    /// The system's matrices, forces, speed and station ([`LinearFreeFlight`]), unless
    /// [`LinearRotor::with_exact_free_flight`] turned it off.
    fn linear_free_flight(&self) -> Option<LinearFreeFlight> {
        let s = &self.system;
        self.exact_free_flight.then(|| {
            LinearFreeFlight::new(
                s.clone(),
                self.station,
                Vector2::new(self.offset[0], self.offset[1]),
            )
        })
    }

    /// Each coordinate's steady amplitude $|X_i| + |q_{0,i}|$ (the synchronous response plus
    /// the static deflection), at least $10^{-3}$ of the largest (a coordinate at a node of
    /// the response); $\Omega$ times that for the velocities; the station's raised to the
    /// ring's gap by [`LinearRotor::ringed`] ([`LinearRotor::with_gap_scale`]). Without
    /// forcing, or at an undamped resonance, 1 mm (and 1 mm times $\Omega$). The absolute
    /// tolerance of a run is `atol` times this: `atol = rtol` asks for each coordinate's
    /// error relative to its amplitude, as S1's reference did.
    fn state_scale(&self) -> Option<DVector<f64>> {
        Some(self.scale.clone())
    }

    /// The state's scale with the velocity of coordinate $i$ weighed by
    /// $\max(\Omega, \omega_i)$ instead of $\Omega$: its displacement's scale times
    /// $\max(\Omega, \omega_i)$, $\omega_i$ the coordinate's frequency
    /// ([`LinearSystem::coordinate_frequencies`]; units: the displacement's per second).
    /// Positions and the ring's slots keep the state's scale. See
    /// [`SmoothRotor::error_scale`] for why.
    fn error_scale(&self) -> Option<DVector<f64>> {
        let n = self.system.dofs();
        let w = self.system.speed;
        let mut scale = self.scale.clone();
        for (i, wi) in self.frequencies.as_ref()?.iter().enumerate() {
            scale[n + i] *= wi.max(w) / w;
        }
        Some(scale)
    }

    /// A bound of the state matrix's spectral radius with a spring `stiffness` $k$ and a
    /// damper `damping` $c$ at the station: $\sqrt{a} + b$, where $a$ is the largest row sum
    /// of $|M^{-1}K|$ plus $k$ times the row sum of the station's two columns of $|M^{-1}|$,
    /// and $b$ the same of $|M^{-1}D|$ and $c$: the infinity norm of the state matrix scaled by
    /// $\operatorname{diag}(I, \sqrt{a} I)$ (for a unit mass, $\sqrt{k_0 + k} + c_0 + c$).
    /// Pessimistic where coordinates of different units mix (metres and radians).
    fn max_rate(&self, _t: f64, _y: &DVector<f64>, stiffness: f64, damping: f64) -> Option<f64> {
        let [k, d, s] = &self.row_sums;
        let (mut a, mut b) = (0.0f64, 0.0f64);
        for i in 0..k.len() {
            a = a.max(k[i] + stiffness * s[i]);
            b = b.max(d[i] + damping * s[i]);
        }
        Some(a.sqrt() + b)
    }
}
