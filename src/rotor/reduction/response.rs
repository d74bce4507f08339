//! What a reduction costs in accuracy: its error on the steady harmonic (unbalance) response
//! at the boundary DOFs, at one speed, over a sweep, and the fewest modes that meet a tolerance.

use nalgebra::{Complex, DMatrix, DVector};

use super::{check_length, CraigBampton, ModeSelection};
use crate::rotor::{LinearSystem, RotorError, RotorMatrices};

/// The reduction's error on a steady harmonic response at the boundary DOFs
/// ([`CraigBampton::response_error`]).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct ResponseError {
    /// The speed $\Omega$ (rad/s) of the response.
    pub speed: f64,
    /// $\Vert X_b^{\mathrm{red}} - X_b \Vert_2 / \Vert X_b \Vert_2$ over the boundary DOFs
    /// (0 if both responses vanish).
    pub relative: f64,
    /// $\Vert X_b \Vert_2$, the full model's boundary amplitude (the unit of the DOFs, m).
    pub amplitude: f64,
}

impl CraigBampton {
    /// The reduced system: $T^{\mathsf T} M T$, $T^{\mathsf T} D\thinspace T$,
    /// $T^{\mathsf T} K T$ at the same speed, with the forces $T^{\mathsf T} \hat F$ and
    /// $T^{\mathsf T} f_0$; its coordinates are the reduced ones (the boundary DOFs first: put
    /// the ring at coordinates 0 and 1 of [`LinearRotor`](crate::rotor::LinearRotor) when the
    /// ring's node is the boundary). Error: a system of another size
    /// ([`RotorError::MatrixShape`]).
    pub fn reduce(&self, system: &LinearSystem) -> Result<LinearSystem, RotorError> {
        LinearSystem::from_parts(
            self.project(system.mass())?,
            self.project(system.damping())?,
            self.project(system.stiffness())?,
            system.speed(),
            self.project_force(system.harmonic_force())?,
            self.project_force(system.constant_force())?,
        )
    }

    /// The reduction's relative error on the steady harmonic response at the boundary DOFs:
    /// [`LinearSystem::steady_response`] of the full system against that of the reduced one
    /// ([`CraigBampton::reduce`]), $X$ solving
    /// $(K - \Omega^2 M + \mathrm i\thinspace\Omega D)\thinspace X = \hat F$ (for an
    /// unbalance, [`LinearSystem::with_unbalance`]).
    ///
    /// Errors: a system of another size ([`RotorError::MatrixShape`]), a singular full or
    /// reduced dynamic stiffness, e.g. an undamped rotor at a resonance
    /// ([`RotorError::Singular`]).
    pub fn response_error(&self, system: &LinearSystem) -> Result<ResponseError, RotorError> {
        let reduced = self.reduce(system)?;
        let full = system.steady_response()?;
        Ok(self.compare(system.speed(), &full, &steady(&reduced)?))
    }

    /// The worst [`CraigBampton::response_error`] over `speeds` (rad/s, each positive), with
    /// $D = C + \Omega G$ at each and the rotor's `M`, `C`, `G`, `K` held as given (a code
    /// exports the bearings at one speed) under the harmonic force $\hat F$ `force`. The
    /// relative error does not depend on the force's scale, so an unbalance's $\hat F$ at any
    /// one speed serves all. Errors: those of [`CraigBampton::response_error`], a force of
    /// another length ([`RotorError::VectorLength`]), a speed that is not finite and positive
    /// or an empty list ([`RotorError::Speed`], NaN for the empty list).
    pub fn response_error_sweep(
        &self,
        rotor: &RotorMatrices,
        force: &DVector<Complex<f64>>,
        speeds: &[f64],
    ) -> Result<ResponseError, RotorError> {
        Sweep::new(self, rotor, force, speeds)?.worst(self, self.reduced_dofs())
    }

    /// The same reduction with only its lowest `modes` fixed-interface modes (the leading
    /// columns of the basis). Error: more modes than it has ([`RotorError::ModeCount`]).
    pub fn truncated(&self, modes: usize) -> Result<Self, RotorError> {
        if modes > self.modes() {
            return Err(RotorError::ModeCount {
                requested: modes,
                available: self.modes(),
            });
        }
        let columns = self.boundary.len() + modes;
        Ok(Self {
            boundary: self.boundary.clone(),
            basis: self.basis.columns(0, columns).into_owned(),
            frequencies: self.frequencies[..modes].to_vec(),
        })
    }

    /// The reduction of `rotor` with the boundary DOFs `boundary` and the fewest
    /// fixed-interface modes whose [`CraigBampton::response_error_sweep`] over `speeds` is at
    /// most `tolerance` (relative), with that worst error. The error is not monotone in the
    /// number of modes (a Galerkin projection of an indefinite, non-symmetric problem), so every
    /// count is tried from 0 up; the full responses are solved once and the reduced matrices
    /// projected once (those of fewer modes are leading blocks).
    ///
    /// Errors: those of [`CraigBampton::from_rotor`] and of the sweep; no count meets the
    /// tolerance, not even all modes, whose error is rounding only
    /// ([`RotorError::ModeTolerance`]).
    pub fn fewest_modes(
        rotor: &RotorMatrices,
        boundary: &[usize],
        force: &DVector<Complex<f64>>,
        speeds: &[f64],
        tolerance: f64,
    ) -> Result<(Self, ResponseError), RotorError> {
        let all = Self::from_rotor(rotor, boundary, ModeSelection::Below(f64::INFINITY))?;
        let sweep = Sweep::new(&all, rotor, force, speeds)?;
        let mut best = f64::INFINITY;
        for modes in 0..=all.modes() {
            let worst = sweep.worst(&all, boundary.len() + modes)?;
            if worst.relative <= tolerance {
                return Ok((all.truncated(modes)?, worst));
            }
            best = best.min(worst.relative);
        }
        Err(RotorError::ModeTolerance { tolerance, best })
    }

    /// The error of the reduced response `red` (reduced coordinates) against the full `full`
    /// at the boundary DOFs.
    fn compare(
        &self,
        speed: f64,
        full: &DVector<Complex<f64>>,
        red: &DVector<Complex<f64>>,
    ) -> ResponseError {
        let (mut diff, mut amp) = (0.0, 0.0);
        for (j, &b) in self.boundary.iter().enumerate() {
            diff += (red[j] - full[b]).norm_sqr();
            amp += full[b].norm_sqr();
        }
        let relative = if diff == 0.0 {
            0.0
        } else {
            (diff / amp).sqrt()
        };
        ResponseError {
            speed,
            relative,
            amplitude: amp.sqrt(),
        }
    }
}

/// A speed sweep: the full model's responses, solved once, and the rotor's matrices and force
/// projected once with a reduction's whole basis (a reduction keeping fewer of its modes has
/// the leading blocks).
struct Sweep<'a> {
    speeds: &'a [f64],
    full: Vec<DVector<Complex<f64>>>,
    /// $T^{\mathsf T} A\thinspace T$ for $M$, $C$, $G$, $K$.
    reduced: [DMatrix<f64>; 4],
    force: DVector<Complex<f64>>,
}

impl<'a> Sweep<'a> {
    fn new(
        cb: &CraigBampton,
        rotor: &RotorMatrices,
        force: &DVector<Complex<f64>>,
        speeds: &'a [f64],
    ) -> Result<Self, RotorError> {
        check_length("F_hat", force.len(), cb.full_dofs())?;
        if speeds.is_empty() {
            return Err(RotorError::Speed { value: f64::NAN });
        }
        let (m, c, g, k) = (
            rotor.mass(),
            rotor.damping(),
            rotor.gyroscopic(),
            rotor.stiffness(),
        );
        let full = speeds
            .iter()
            .map(|&w| {
                let d = c + g * w;
                let system = LinearSystem::from_parts(
                    m.clone(),
                    d,
                    k.clone(),
                    w,
                    force.clone(),
                    zero(k.nrows()),
                )?;
                system.steady_response()
            })
            .collect::<Result<_, _>>()?;
        Ok(Self {
            speeds,
            full,
            reduced: [
                cb.project(m)?,
                cb.project(c)?,
                cb.project(g)?,
                cb.project(k)?,
            ],
            force: cb.project_force(force)?,
        })
    }

    /// The worst error over the speeds of `cb` truncated to its first `size` reduced
    /// coordinates.
    fn worst(&self, cb: &CraigBampton, size: usize) -> Result<ResponseError, RotorError> {
        let [m, c, g, k] = &self
            .reduced
            .each_ref()
            .map(|a| a.view((0, 0), (size, size)).into_owned());
        let force = self.force.rows(0, size).into_owned();
        let mut worst: Option<ResponseError> = None;
        for (&speed, full) in self.speeds.iter().zip(&self.full) {
            let d = c + g * speed;
            let system = LinearSystem::from_parts(
                m.clone(),
                d,
                k.clone(),
                speed,
                force.clone(),
                zero(size),
            )?;
            let red = steady(&system)?;
            let e = cb.compare(speed, full, &red);
            // total_cmp: a NaN error (an overflowing response) counts as the worst.
            if worst.is_none_or(|w| e.relative.total_cmp(&w.relative).is_gt()) {
                worst = Some(e);
            }
        }
        worst.ok_or(RotorError::Speed { value: f64::NAN })
    }
}

fn zero(n: usize) -> DVector<f64> {
    DVector::zeros(n)
}

/// [`LinearSystem::steady_response`], also for a system without coordinates (no boundary
/// DOF and no mode kept), on which nalgebra's LU panics.
fn steady(system: &LinearSystem) -> Result<DVector<Complex<f64>>, RotorError> {
    if system.dofs() == 0 {
        return Ok(DVector::zeros(0));
    }
    system.steady_response()
}
