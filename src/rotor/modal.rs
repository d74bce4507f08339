//! A linear rotor in the modal coordinates of its state matrix ([`ModalRotor`]): $O(n)$ a
//! right-hand side, its linear part diagonal for the exponential integrator.

use nalgebra::{Complex, DMatrix, DVector, Dyn, Vector2};

use super::exact::{ModalData, DEFAULT_MAX_CONDITION};
use super::{LinearRotor, RotorError, SmoothRotor};
use crate::numeric::eigen_decomposition;
use crate::ode::{BlockForcing, DiagonalLinearPart, JacobianMut, OdeError};
use crate::ring::{ForceJacobian, Kinematics};

/// Largest accepted backward error of the eigenpairs and of the rebuilt matrix (relative), as
/// for the closed form.
const MAX_RESIDUAL: f64 = 1e-10;

/// A [`LinearRotor`] in the modal coordinates of its state matrix: with
/// $A = T\Lambda T^{-1}$ ($T = \operatorname{diag}(d)V$, the balanced eigen-decomposition,
/// [`crate::numeric::eigen_decomposition`]) and $x = (q, q^\prime) = T w$, every complex modal
/// coordinate obeys
///
/// $$w_k^\prime = \lambda_k w_k + g_k(t) + b_{x,k} F_x + b_{y,k} F_y,$$
///
/// $g = T^{-1}(0, M^{-1}F(t))$ the forcing, $b = T^{-1}(0, M^{-1}e_{i_x})$, … the ring force's
/// inputs. The state is $[\operatorname{Re}w_0, \operatorname{Im}w_0, \dots,
/// \operatorname{Re}w_{2n-1}, \operatorname{Im}w_{2n-1}, s_x, s_y]$ ($4n + 2$ components: each
/// of the $2n$ eigenvalues keeps its own complex coordinate, so that no pairing of conjugates
/// is needed); the station is the row combination $r = \operatorname{Re}\sum_k T_{i_x k}w_k - o$
/// (and $T_{n + i_x, k}$ for its velocity). The right-hand side, the station and the force
/// cost $O(n)$; the linear part $\Lambda$ is diagonal and carries the forcing $g$
/// ([`SmoothRotor::linear_part`]), so the exponential integrator [`Etd4`](crate::ode::Etd4)
/// propagates both exactly and takes steps set by the contact, at $O(n)$ a step.
///
/// Free flight is exact: [`SmoothRotor::linear_free_flight`] gives the closed form in these
/// coordinates from the rotor's own decomposition, $w_k(t) = e^{\lambda_k(t - t_0)}(w_k(t_0) -
/// p_k(t_0)) + p_k(t)$ with $p_k$ the particular solution of $g_k$
/// ([`LinearClosedForm`](super::LinearClosedForm), $O(n)$ a station evaluation), and contact
/// onsets are found by the certified search of [`crate::ring::onset`] (no touch missed,
/// however shallow), as for [`LinearRotor`]; the integrator runs only the contact phases.
/// Outputs: [`ModalRotor::station_displacement`] ($O(n)$), [`ModalRotor::physical_state`]
/// ($O(n^2)$).
///
/// Refused, as the closed form: $\kappa_1(V) > 10^6$ ([`RotorError::IllConditionedModes`]) or
/// a backward error above $10^{-10}$ ([`RotorError::EigenResidual`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ModalRotor {
    /// The physical rotor, when built from one ([`ModalRotor::new`]).
    linear: Option<LinearRotor>,
    speed: f64,
    offset: [f64; 2],
    /// The ring's gap once composed ([`ModalRotor::ringed`]); before, 1 mm.
    gap: f64,
    values: DVector<Complex<f64>>,
    /// $T = \operatorname{diag}(d) V$ and $T^{-1}$.
    shapes: DMatrix<Complex<f64>>,
    inverse: DMatrix<Complex<f64>>,
    /// The station's rows of $T$: positions x, y, velocities x, y.
    rows: [DVector<Complex<f64>>; 4],
    /// $T^{-1}(0, M^{-1}\cdot)$ of the forcing's cosine, sine and constant parts, and of unit
    /// forces at the station along x and y.
    inputs: [DVector<Complex<f64>>; 5],
    has_constant: bool,
    linear_part: DiagonalLinearPart,
    scale: DVector<f64>,
    /// The system, its decomposition's $\kappa_1(V)$ and backward error, for the closed form
    /// ([`SmoothRotor::linear_free_flight`]).
    system: super::LinearSystem,
    condition: f64,
    residual: f64,
}

impl ModalRotor {
    /// The modal form of `rotor` (one eigen-decomposition of its $2n \times 2n$ state matrix,
    /// $O(n^3)$). Errors: a singular $M$, a failed decomposition ([`RotorError::Eigen`]),
    /// ill-conditioned modes or a large backward error (as [`super::LinearFreeFlight::prepare`]).
    pub fn new(rotor: &LinearRotor) -> Result<Self, RotorError> {
        let n = rotor.system().dofs();
        let rows = rotor.station_dofs().map(|i| {
            let mut row = DVector::zeros(n);
            row[i] = 1.0;
            row
        });
        let mut modal = Self::from_station_rows(rotor.system(), &rows, rotor.ring_offset())?;
        modal.linear = Some(rotor.clone());
        modal.scale = modal.modal_scale();
        Ok(modal)
    }

    /// The modal form of `system` with the ring's station at the row combinations
    /// $r = (c_x^{\mathsf T}q, c_y^{\mathsf T}q) - o$ (`rows` $= [c_x, c_y]$, $n$ entries each;
    /// e.g. a modal shaft's mode shapes at the ring) and the ring's centre at `offset` $= o$.
    /// The ring's force enters as $M^{-1}(c_x F_x + c_y F_y)$. Errors: as
    /// [`ModalRotor::new`]; rows of another length ([`RotorError::VectorLength`]) or not
    /// finite, an offset not finite ([`RotorError::Parameter`]).
    pub fn from_station_rows(
        system: &super::LinearSystem,
        rows: &[DVector<f64>; 2],
        offset: [f64; 2],
    ) -> Result<Self, RotorError> {
        let n = system.dofs();
        for row in rows {
            if row.len() != n {
                return Err(RotorError::VectorLength {
                    vector: "station row",
                    len: row.len(),
                    expected: n,
                });
            }
            if let Some(&value) = row.iter().find(|v| !v.is_finite()) {
                return Err(RotorError::Parameter {
                    field: "station row entry",
                    value,
                });
            }
        }
        if let Some(&value) = offset.iter().find(|v| !v.is_finite()) {
            return Err(RotorError::Parameter {
                field: "ring offset",
                value,
            });
        }
        let e = eigen_decomposition(&system.state_matrix()?).map_err(RotorError::Eigen)?;
        if e.condition.is_nan() || e.condition > DEFAULT_MAX_CONDITION {
            return Err(RotorError::IllConditionedModes {
                condition: e.condition,
                limit: DEFAULT_MAX_CONDITION,
            });
        }
        if !(e.residual <= MAX_RESIDUAL && e.reconstruction <= MAX_RESIDUAL) {
            return Err(RotorError::EigenResidual {
                residual: e.residual,
                reconstruction: e.reconstruction,
            });
        }
        let d = &e.scale;
        let shapes = DMatrix::from_fn(2 * n, 2 * n, |i, k| e.vectors[(i, k)] * d[i]);
        let inverse = DMatrix::from_fn(2 * n, 2 * n, |k, i| e.inverse[(k, i)] / d[i]);
        let row_of = |c: &DVector<f64>, half: usize| {
            DVector::from_fn(2 * n, |k, _| {
                (0..n)
                    .map(|i| shapes[(half + i, k)] * c[i])
                    .sum::<Complex<f64>>()
            })
        };
        let station_rows = [
            row_of(&rows[0], 0),
            row_of(&rows[1], 0),
            row_of(&rows[0], n),
            row_of(&rows[1], n),
        ];
        let mut forces = DMatrix::zeros(n, 5);
        forces
            .column_mut(0)
            .copy_from(&system.harmonic_force().map(|f| f.re));
        forces
            .column_mut(1)
            .copy_from(&system.harmonic_force().map(|f| -f.im));
        forces.column_mut(2).copy_from(system.constant_force());
        forces.column_mut(3).copy_from(&rows[0]);
        forces.column_mut(4).copy_from(&rows[1]);
        let accel = system.solve_mass(&forces)?;
        let inputs = std::array::from_fn(|j| {
            DVector::from_fn(2 * n, |k, _| {
                (0..n)
                    .map(|i| inverse[(k, n + i)] * accel[(i, j)])
                    .sum::<Complex<f64>>()
            })
        });
        let blocks: Vec<(usize, Complex<f64>)> = e
            .values
            .iter()
            .enumerate()
            .map(|(k, &l)| (2 * k, l))
            .collect();
        let has_constant = system.constant_force().iter().any(|&f| f != 0.0);
        let linear_part = DiagonalLinearPart::new(4 * n + 2, &[], &blocks)
            .map_err(|_| RotorError::Parameter {
                field: "state matrix eigenvalue",
                value: f64::NAN,
            })
            .and_then(|lp| modal_forcing(lp, system.speed(), &inputs, has_constant))?;
        let mut modal = Self {
            linear: None,
            speed: system.speed(),
            offset,
            gap: 1e-3,
            values: e.values,
            shapes,
            inverse,
            rows: station_rows,
            inputs,
            has_constant,
            linear_part,
            scale: DVector::zeros(4 * n + 2),
            system: system.clone(),
            condition: e.condition,
            residual: e.residual.max(e.reconstruction),
        };
        modal.scale = modal.modal_scale();
        Ok(modal)
    }

    /// Each modal coordinate's scale. Built from a [`LinearRotor`]: the largest amplitude
    /// that moves no physical component by more than its scale ([`SmoothRotor::state_scale`]
    /// of the rotor), $\min_i s_i / |T_{ik}|$. From station rows: the amplitude that moves the
    /// station by the gap, $\gamma/\max(|c_{x,k}|, |c_{y,k}|)$ (the modes are coupled only
    /// through the station, so this is the error the contact sees), at most $10^3$ times the
    /// smallest. The ring's slots: the gap.
    fn modal_scale(&self) -> DVector<f64> {
        let n2 = self.values.len();
        let mut scale = DVector::from_element(2 * n2 + 2, self.gap);
        let physical = self.linear.as_ref().and_then(|l| l.state_scale());
        let seen = |k: usize| self.rows[0][k].norm().max(self.rows[1][k].norm());
        let largest = (0..n2).map(seen).fold(0.0, f64::max);
        for k in 0..n2 {
            let s = match &physical {
                Some(p) => (0..n2)
                    .map(|i| p[i] / self.shapes[(i, k)].norm())
                    .fold(f64::INFINITY, f64::min),
                None => self.gap / seen(k).max(1e-3 * largest),
            };
            let s = if s.is_finite() && s > 0.0 {
                s
            } else {
                self.gap
            };
            scale[2 * k] = s;
            scale[2 * k + 1] = s;
        }
        if let Some(p) = &physical {
            scale[2 * n2] = p[n2];
            scale[2 * n2 + 1] = p[n2 + 1];
        }
        scale
    }

    /// Composes the rotor with `ring`, the scales raised to the ring's gap as
    /// [`LinearRotor::ringed`] does. Errors: as [`super::RingedRotor::new`].
    pub fn ringed(
        mut self,
        ring: crate::ring::SnubberRing,
    ) -> Result<super::RingedRotor<Self>, RotorError> {
        self.gap = ring.gap;
        self.linear = self.linear.map(|l| l.with_gap_scale(ring.gap));
        self.scale = self.modal_scale();
        super::RingedRotor::new(self, ring)
    }

    /// The physical rotor, when built from one ([`ModalRotor::new`]).
    pub fn linear(&self) -> Option<&LinearRotor> {
        self.linear.as_ref()
    }

    /// The eigenvalues $\lambda_k$ of the state matrix.
    pub fn eigenvalues(&self) -> &DVector<Complex<f64>> {
        &self.values
    }

    /// Number of physical coordinates $n$ (the state has $4n + 2$ components).
    pub fn dofs(&self) -> usize {
        self.values.len() / 2
    }

    /// The state at rest ($q = q^\prime = 0$, $s = 0$): zero.
    pub fn rest_state(&self) -> DVector<f64> {
        DVector::zeros(2 * self.values.len() + 2)
    }

    /// The modal state of a physical state `[q, q', s_x, s_y]` ($2n + 2$ components;
    /// $w = T^{-1}x$, $O(n^2)$). `None` for another length.
    pub fn modal_state(&self, physical: &DVector<f64>) -> Option<DVector<f64>> {
        let n2 = self.values.len();
        if physical.len() != n2 + 2 {
            return None;
        }
        let mut y = DVector::zeros(2 * n2 + 2);
        for k in 0..n2 {
            let w: Complex<f64> = (0..n2).map(|i| self.inverse[(k, i)] * physical[i]).sum();
            y[2 * k] = w.re;
            y[2 * k + 1] = w.im;
        }
        y[2 * n2] = physical[n2];
        y[2 * n2 + 1] = physical[n2 + 1];
        Some(y)
    }

    /// The physical state `[q, q', s_x, s_y]` of a modal state `y` ($x =
    /// \operatorname{Re}\thinspace T w$, $O(n^2)$). `None` for another length.
    pub fn physical_state(&self, y: &DVector<f64>) -> Option<DVector<f64>> {
        let n2 = self.values.len();
        if y.len() != 2 * n2 + 2 {
            return None;
        }
        let mut x = DVector::zeros(n2 + 2);
        for i in 0..n2 {
            x[i] = (0..n2)
                .map(|k| (self.shapes[(i, k)] * Complex::new(y[2 * k], y[2 * k + 1])).re)
                .sum();
        }
        x[n2] = y[2 * n2];
        x[n2 + 1] = y[2 * n2 + 1];
        Some(x)
    }

    /// $\operatorname{Re}\sum_k c_k w_k$ for the four station rows (positions x, y,
    /// velocities x, y) in one pass.
    fn station_rows(&self, y: &DVector<f64>) -> [f64; 4] {
        let n2 = self.values.len();
        let w = y.as_slice()[..2 * n2].chunks_exact(2);
        let [a, b, c, d] = self.rows.each_ref().map(|r| &r.as_slice()[..n2]);
        let mut sum = [0.0; 4];
        for (k, w) in w.enumerate() {
            let (re, im) = (w[0], w[1]);
            sum[0] += a[k].re * re - a[k].im * im;
            sum[1] += b[k].re * re - b[k].im * im;
            sum[2] += c[k].re * re - c[k].im * im;
            sum[3] += d[k].re * re - d[k].im * im;
        }
        sum
    }

    /// Subtracts the ring force's part $B(F_r R + F_v V)$ from `jac` (see
    /// [`SmoothRotor::jacobian`]): column by column, the force's derivative along the column's
    /// modal component, then its image through the inputs $b_x$, $b_y$.
    fn add_contact_jacobian(&self, f: &ForceJacobian, jac: &mut JacobianMut<'_, Dyn>) {
        let [.., bx, by] = &self.inputs;
        let [rx, ry, vx, vy] = &self.rows;
        // Re(c w) = Re c Re w - Im c Im w: its derivative along Re w (j = 0) or Im w (j = 1).
        let along = |c: Complex<f64>, j: usize| if j == 0 { c.re } else { -c.im };
        for m in 0..self.values.len() {
            for j in 0..2 {
                let col = 2 * m + j;
                let r = Vector2::new(along(rx[m], j), along(ry[m], j));
                let v = Vector2::new(along(vx[m], j), along(vy[m], j));
                let force = f.position * r + f.velocity * v;
                for k in 0..self.values.len() {
                    let g = bx[k] * force.x + by[k] * force.y;
                    jac[(2 * k, col)] -= g.re;
                    jac[(2 * k + 1, col)] -= g.im;
                }
            }
        }
    }

    /// The ring node's displacement $(q_{i_x}, q_{i_y})$ in a modal state `y` (m, from its
    /// undeflected position), $O(n)$. NaN for a state of another length.
    pub fn station_displacement(&self, y: &DVector<f64>) -> [f64; 2] {
        if y.len() != 2 * self.values.len() + 2 {
            return [f64::NAN; 2];
        }
        let [x, y, ..] = self.station_rows(y);
        [x, y]
    }
}

/// `lp` with the modal forcing declared ([`DiagonalLinearPart::with_forcing`]): coordinate
/// $w_k$'s $g_k(t) = g_{c,k}\cos\Omega t + g_{s,k}\sin\Omega t + g_{0,k}$, as
/// [`SmoothRotor::rhs`] adds it (`inputs[0..3]`; the constant only when there is one, as
/// there).
fn modal_forcing(
    lp: DiagonalLinearPart,
    speed: f64,
    inputs: &[DVector<Complex<f64>>; 5],
    has_constant: bool,
) -> Result<DiagonalLinearPart, RotorError> {
    let [gc, gs, g0, ..] = inputs;
    let blocks: Vec<(usize, BlockForcing)> = (0..gc.len())
        .map(|k| {
            let constant = if has_constant {
                g0[k]
            } else {
                Complex::new(0.0, 0.0)
            };
            let block = BlockForcing {
                cos: gc[k],
                sin: gs[k],
                constant,
            };
            (2 * k, block)
        })
        .collect();
    lp.with_forcing(speed, &blocks)
        .map_err(|e| RotorError::Parameter {
            field: "modal forcing",
            value: match e {
                OdeError::InvalidForcing { value, .. } => value,
                _ => f64::NAN,
            },
        })
}

impl SmoothRotor for ModalRotor {
    type Dim = Dyn;

    fn dim(&self) -> Dyn {
        Dyn(2 * self.values.len() + 2)
    }

    /// $w_k^\prime = \lambda_k w_k + g_k(t)$: $O(n)$, no allocation.
    fn rhs(&self, t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        let (sin, cos) = (self.speed * t).sin_cos();
        let [gc, gs, g0, ..] = &self.inputs;
        for k in 0..self.values.len() {
            let w = Complex::new(y[2 * k], y[2 * k + 1]);
            let mut d = self.values[k] * w + gc[k] * cos + gs[k] * sin;
            if self.has_constant {
                d += g0[k];
            }
            dy[2 * k] = d.re;
            dy[2 * k + 1] = d.im;
        }
    }

    fn station(&self, y: &DVector<f64>) -> Kinematics {
        let o = self.offset;
        let [x, y, vx, vy] = self.station_rows(y);
        Kinematics::new([x - o[0], y - o[1]], [vx, vy])
    }

    fn add_station_force(&self, _y: &DVector<f64>, force: &Vector2<f64>, dy: &mut DVector<f64>) {
        let [.., bx, by] = &self.inputs;
        for k in 0..self.values.len() {
            let d = bx[k] * force.x + by[k] * force.y;
            dy[2 * k] += d.re;
            dy[2 * k + 1] += d.im;
        }
    }

    fn ring_slots(&self) -> [usize; 2] {
        let n2 = self.values.len();
        [2 * n2, 2 * n2 + 1]
    }

    /// Exact: the blocks $\begin{pmatrix}\operatorname{Re}\lambda_k &
    /// -\operatorname{Im}\lambda_k\\\\ \operatorname{Im}\lambda_k &
    /// \operatorname{Re}\lambda_k\end{pmatrix}$ and, in contact, $-B(F_r R + F_v V)$ with $B$ the
    /// inputs $b_x$, $b_y$ and $R$, $V$ the station's rows of $T$ (the derivatives of
    /// $\operatorname{Re}\sum_k c_k w_k$ along $\operatorname{Re}w_k$ and
    /// $\operatorname{Im}w_k$: $\operatorname{Re}c_k$ and $-\operatorname{Im}c_k$). $O(n^2)$, no
    /// allocation. Finite differences cannot stand in: a growing mode's coordinates far above
    /// $1/\varepsilon$ times a decayed one's (an unstable rotor late in a run) lose every
    /// column, the large coordinates' increments below their last bit and the small ones'
    /// changes of $f$ below the rounding of the contact force's terms.
    fn jacobian(
        &self,
        _t: f64,
        _y: &DVector<f64>,
        contact: Option<&ForceJacobian>,
        jac: &mut JacobianMut<'_, Dyn>,
    ) -> bool {
        let n2 = self.values.len();
        if jac.nrows() != 2 * n2 + 2 || jac.ncols() != 2 * n2 + 2 {
            return false;
        }
        jac.fill(0.0);
        for (k, l) in self.values.iter().enumerate() {
            jac[(2 * k, 2 * k)] = l.re;
            jac[(2 * k, 2 * k + 1)] = -l.im;
            jac[(2 * k + 1, 2 * k)] = l.im;
            jac[(2 * k + 1, 2 * k + 1)] = l.re;
        }
        if let Some(f) = contact {
            self.add_contact_jacobian(f, jac);
        }
        true
    }

    /// The constant speed, and the angle $\Omega t$.
    fn spin(&self, t: f64, _y: &DVector<f64>) -> Option<super::Spin> {
        Some(super::Spin {
            speed: self.speed,
            angle: self.speed * t,
            accel: 0.0,
        })
    }

    fn forcing_period(&self) -> f64 {
        std::f64::consts::TAU / self.speed
    }

    /// The physical scales carried to the modes (see [`ModalRotor::ringed`]).
    fn state_scale(&self) -> Option<DVector<f64>> {
        Some(self.scale.clone())
    }

    /// $\Lambda$: a complex block per eigenvalue, with the forcing $g_k(t)$ of the field
    /// declared on it (exact in [`Etd4`](crate::ode::Etd4)), nothing at the ring's slots:
    /// the ring's force and motion are the rest, left to the steps.
    fn linear_part(&self) -> Option<&DiagonalLinearPart> {
        Some(&self.linear_part)
    }

    /// The closed form in the rotor's own modal coordinates, from the data it already has
    /// ([`LinearClosedForm`](super::LinearClosedForm): each coordinate
    /// $w_k(t) = e^{\lambda_k(t - t_0)}(w_k(t_0) - p_k(t_0)) + p_k(t)$, the station $O(n)$ a
    /// time), so that free flight is exact and onsets are found by the certified search.
    fn linear_free_flight(&self) -> Option<super::LinearFreeFlight> {
        let [gc, gs, g0, ..] = &self.inputs;
        let offset = Vector2::from(self.offset);
        let form = super::LinearClosedForm::modal(ModalData {
            speed: self.speed,
            values: &self.values,
            shapes: &self.shapes,
            inverse: &self.inverse,
            rows: &self.rows,
            forcing: [gc, gs, g0],
            offset,
            condition: self.condition,
            residual: self.residual,
        });
        Some(super::LinearFreeFlight::modal(
            self.system.clone(),
            offset,
            form,
        ))
    }
}
