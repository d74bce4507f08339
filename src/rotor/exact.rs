//! Exact free flight of a linear rotor at constant speed ([`LinearClosedForm`]).

use std::sync::Arc;

use nalgebra::allocator::Allocator;
use nalgebra::{Complex, DMatrix, DVector, DefaultAllocator, Dim, OVector, Vector2};

use super::{LinearSystem, RotorError};
use crate::hybrid::{ExactSegment, GuardCrossing};
use crate::numeric::eigen_decomposition;
use crate::ring::onset::{MotionBounds, OnsetScan, RotorMotion};
use crate::ring::{Relaxation, SnubberRing};

/// Default [`LinearFreeFlight::max_condition`]: $\kappa_1(V) \le 10^6$, so that the modal
/// coordinates carry at most about $10^6\varepsilon \approx 2\cdot 10^{-10}$ relative rounding.
pub const DEFAULT_MAX_CONDITION: f64 = 1e6;

/// Largest accepted backward error of the eigenpairs and of the rebuilt matrix (relative).
const MAX_RESIDUAL: f64 = 1e-10;

/// A linear rotor's free flight at constant speed, as a [`SmoothRotor`](super::SmoothRotor)
/// describes it ([`SmoothRotor::linear_free_flight`](super::SmoothRotor::linear_free_flight)):
/// $M q^{\prime\prime} + D q^\prime + K q = f_0 + \operatorname{Re}(\hat F e^{i\Omega t})$
/// ([`LinearClosedForm`]). The rotor's state must be `[q (n), q' (n), x_s, y_s]`, or, for a
/// [`ModalRotor`](super::ModalRotor), its modal coordinates and the ring's slots.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearFreeFlight {
    /// The system: $M$, $D = C + \Omega G$, $K$, the speed $\Omega$, $\hat F$ and $f_0$.
    pub system: LinearSystem,
    /// The coordinates $(i_x, i_y)$ of $q$ that the ring's station sees.
    pub station: [usize; 2],
    /// The ring centre's position $o$: the station is at $(q_{i_x}, q_{i_y}) - o$.
    pub offset: Vector2<f64>,
    /// Largest accepted condition number of the eigenvector matrix
    /// ([`DEFAULT_MAX_CONDITION`]).
    pub max_condition: f64,
    /// The closed form in the state's own modal coordinates, when the rotor already has it
    /// ([`LinearFreeFlight::modal`]).
    modal: Option<Result<LinearClosedForm, RotorError>>,
}

/// Exact free flight of a linear rotor at constant speed.
///
/// Between contacts a finite-element rotor on the ring is linear, with constant coefficients
/// and harmonic forcing,
///
/// $$M q^{\prime\prime} + D q^\prime + K q = f_0 + \operatorname{Re}(\hat F e^{i\Omega t}),$$
///
/// ($D = C + \Omega G$), i.e. $x^\prime = A x + b_0 + \operatorname{Re}(\hat b e^{i\Omega t})$
/// for $x = (q, q^\prime)$ with $A = \begin{pmatrix}0 & I\\\\ -M^{-1}K & -M^{-1}D\end{pmatrix}$.
/// Its solution is known in closed form ([`LinearClosedForm`]):
///
/// $$x(t) = x_p(t) + \operatorname{Re}\Big(\textstyle\sum_k V_k\thinspace w_k
/// e^{\lambda_k (t - t_0)}\Big),\qquad x_p(t) = x_s + \operatorname{Re}(X e^{i\Omega t}),$$
///
/// with $K q_s = f_0$, $(K - \Omega^2 M + i\Omega D) Q = \hat F$, $x_s = (q_s, 0)$,
/// $X = (Q, i\Omega Q)$, the eigen-decomposition $A = V\Lambda V^{-1}$
/// ([`crate::numeric::eigen_decomposition`], once per model) and the modal coordinates
/// $w = V^{-1}(x_0 - x_p(t_0))$ of a segment started at $(t_0, x_0)$ ([`LinearSegment`]).
/// The ring's station sees $r = (q_{i_x}, q_{i_y}) - o$, $o$ the ring centre's offset: with
/// the station's rows of $V$ (two complex numbers a mode) precomputed, $r$, $r^\prime$,
/// $r^{\prime\prime}$ cost $O(2n)$ a time, the full state $O(n^2)$ (segment ends, outputs).
///
/// **Refused, never inaccurate.** A near-defective $A$ (two modes about to coalesce, e.g. an
/// over-damped mode near critical damping) has an ill-conditioned $V$, and the modal
/// coordinates amplify rounding by its condition number $\kappa_1(V)$ (in balanced
/// coordinates). [`LinearFreeFlight::prepare`] refuses the closed form with
/// [`RotorError::IllConditionedModes`] when $\kappa$ exceeds
/// [`LinearFreeFlight::max_condition`] (default [`DEFAULT_MAX_CONDITION`]: the modal
/// coordinates then carry less than about $10^{-9}$ relative rounding), and
/// [`RingedRotor`](super::RingedRotor) integrates the free flight instead.
///
/// **Bounds for the certified onset search** ([`crate::ring::onset`]): on $[t_a, t_b]$,
/// $|r^{(p)}(t)| \le \Omega^p |P| + [p = 0]\thinspace|r_s| + \sum_k |\lambda_k|^p |c_k|
/// e^{\operatorname{Re}\lambda_k (\tau_k - t_0)}$, $c_k$ the mode's station coefficients
/// ($\mathbb{C}^2$), $P$ the particular amplitude at the station, $r_s$ its static position,
/// $\tau_k = t_a$ for a decaying mode and $t_b$ for a growing one
/// ([`RotorMotion::bounds_on`]): the high modes' huge jerk bound fades as they decay, and an
/// unstable rotor gets bounds on finite windows (the search's chunks: one forcing period).
///
/// **In modal coordinates** ([`LinearClosedForm::is_modal`]: a
/// [`ModalRotor`](super::ModalRotor), whose state is $w$ itself) the same form is built from
/// the rotor's own decomposition: each coordinate is
/// $w_k(t) = e^{\lambda_k(t - t_0)}(w_k(t_0) - p_k(t_0)) + p_k(t)$, $p_k$ its particular
/// solution, the station the rotor's rows of $T$ applied to $w(t)$ in the rotor's own order
/// (the search and the rotor see the same station to the last bit), and the bounds above
/// unchanged. Segment ends cost $O(n)$ too.
///
/// Computed once per model by [`LinearFreeFlight::prepare`].
#[derive(Debug, Clone, PartialEq)]
pub struct LinearClosedForm {
    n: usize,
    speed: f64,
    values: DVector<Complex<f64>>,
    /// Balancing scales: the state is $x = \operatorname{diag}(d) z$.
    scale: DVector<f64>,
    vectors: DMatrix<Complex<f64>>,
    inverse: DMatrix<Complex<f64>>,
    /// The station's rows of $\operatorname{diag}(d) V$.
    shape_x: DVector<Complex<f64>>,
    shape_y: DVector<Complex<f64>>,
    /// $x_s$ and $X$ of the particular solution.
    static_state: DVector<f64>,
    harmonic_state: DVector<Complex<f64>>,
    station: [usize; 2],
    offset: Vector2<f64>,
    /// The particular solution at the station: $P$ and $r_s$ (the offset subtracted).
    station_harmonic: [Complex<f64>; 2],
    station_static: Vector2<f64>,
    /// In modal coordinates ([`LinearFreeFlight::modal`]): the modes' particular solutions.
    modal: Option<ModalParticular>,
    condition: f64,
    residual: f64,
}

/// The particular solution of each modal coordinate of a rotor whose state is modal:
/// $w_k^\prime = \lambda_k w_k + g_{c,k}\cos\Omega t + g_{s,k}\sin\Omega t + g_{0,k}$ has
/// $p_k(t) = \alpha_k e^{i\Omega t} + \beta_k e^{-i\Omega t} + \sigma_k$ with
/// $\alpha_k = \tfrac12(g_{c,k} - i g_{s,k})/(i\Omega - \lambda_k)$,
/// $\beta_k = \tfrac12(g_{c,k} + i g_{s,k})/(-i\Omega - \lambda_k)$,
/// $\sigma_k = -g_{0,k}/\lambda_k$.
#[derive(Debug, Clone, PartialEq)]
struct ModalParticular {
    alpha: Vec<Complex<f64>>,
    beta: Vec<Complex<f64>>,
    sigma: Vec<Complex<f64>>,
    /// The station's rows of $T$: positions x, y, velocities x, y.
    rows: [DVector<Complex<f64>>; 4],
}

impl ModalParticular {
    /// $p_k$ and $p_k^\prime$ at the phase $e^{i\Omega t}$ (`ph`), `iw` $= i\Omega$.
    fn at(&self, k: usize, ph: Complex<f64>, iw: Complex<f64>) -> (Complex<f64>, Complex<f64>) {
        let (a, b) = (self.alpha[k] * ph, self.beta[k] * ph.conj());
        (a + b + self.sigma[k], iw * (a - b))
    }
}

/// What a rotor in modal coordinates already has ([`LinearClosedForm::modal`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ModalData<'a> {
    /// $\Omega$.
    pub speed: f64,
    /// $\lambda_k$.
    pub values: &'a DVector<Complex<f64>>,
    /// $T$ and $T^{-1}$.
    pub shapes: &'a DMatrix<Complex<f64>>,
    pub inverse: &'a DMatrix<Complex<f64>>,
    /// The station's rows of $T$: positions x, y, velocities x, y.
    pub rows: &'a [DVector<Complex<f64>>; 4],
    /// $g_c$, $g_s$, $g_0$: the forcing's cosine, sine and constant parts in modal coordinates.
    pub forcing: [&'a DVector<Complex<f64>>; 3],
    /// The ring centre's offset $o$.
    pub offset: Vector2<f64>,
    /// $\kappa_1(V)$ and the backward error of the decomposition.
    pub condition: f64,
    pub residual: f64,
}

impl LinearFreeFlight {
    /// The free flight of `system` with the ring's station at its coordinates `station` and
    /// the ring centre at `offset`, with [`DEFAULT_MAX_CONDITION`].
    pub fn new(system: LinearSystem, station: [usize; 2], offset: Vector2<f64>) -> Self {
        Self {
            system,
            station,
            offset,
            max_condition: DEFAULT_MAX_CONDITION,
            modal: None,
        }
    }

    /// The free flight of a rotor whose state is the modal coordinates of `system`'s state
    /// matrix ([`ModalRotor`](super::ModalRotor): `[Re w_0, Im w_0, …, Re w_{2n-1},
    /// Im w_{2n-1}, x_s, y_s]`), with its closed form already built from the rotor's own
    /// decomposition (or the reason it has none). [`LinearFreeFlight::prepare`] returns it;
    /// `station` and `max_condition` are not used.
    pub(crate) fn modal(
        system: LinearSystem,
        offset: Vector2<f64>,
        form: Result<LinearClosedForm, RotorError>,
    ) -> Self {
        Self {
            system,
            station: [0, 0],
            offset,
            max_condition: DEFAULT_MAX_CONDITION,
            modal: Some(form),
        }
    }

    /// Number of the state's components before the ring's slots: $2n$ for `[q, q']`, $4n$
    /// in modal coordinates (a complex coordinate a mode).
    pub fn state_len(&self) -> usize {
        match self.modal {
            Some(_) => 4 * self.dofs(),
            None => 2 * self.dofs(),
        }
    }

    /// The real state matrix in the state's own coordinates: $A$ for `[q, q']`, the
    /// $2\times 2$ blocks $\begin{pmatrix}\operatorname{Re}\lambda_k & -\operatorname{Im}
    /// \lambda_k\\\\ \operatorname{Im}\lambda_k & \operatorname{Re}\lambda_k\end{pmatrix}$ in modal
    /// coordinates.
    ///
    /// # Errors
    /// [`RotorError::Singular`] for a singular $M$.
    pub(crate) fn state_coordinates_matrix(&self) -> Result<DMatrix<f64>, RotorError> {
        match &self.modal {
            Some(Ok(form)) => Ok(form.modal_block_matrix(|l| l)),
            _ => self.system.state_matrix(),
        }
    }

    /// Number of coordinates $n$ (the state has $2n + 2$ components with the ring).
    pub fn dofs(&self) -> usize {
        self.system.dofs()
    }

    /// The closed form: eigen-decomposition of $A$, particular solution, station shapes.
    ///
    /// # Errors
    /// [`RotorError::LinearStation`] for a station out of range or an offset not finite;
    /// [`RotorError::Singular`] for a singular $M$ ([`LinearSystem::state_matrix`]), or,
    /// naming it, a singular $K - \Omega^2 M + i\Omega D$ (forcing at an undamped resonance)
    /// or $K$ under a static force (no particular solution);
    /// [`RotorError::Eigen`] if the decomposition fails; [`RotorError::IllConditionedModes`]
    /// (near-defective $A$) or [`RotorError::EigenResidual`]: the closed form is refused.
    pub fn prepare(&self) -> Result<LinearClosedForm, RotorError> {
        if let Some(form) = &self.modal {
            return form.clone();
        }
        let n = self.dofs();
        let fits = self.station.iter().all(|&i| i < n) && self.offset.iter().all(|v| v.is_finite());
        if !fits {
            return Err(RotorError::LinearStation {
                station: self.station,
                dofs: n,
            });
        }
        let a = self.system.state_matrix()?;
        let e = eigen_decomposition(&a).map_err(RotorError::Eigen)?;
        if e.condition.is_nan() || e.condition > self.max_condition {
            return Err(RotorError::IllConditionedModes {
                condition: e.condition,
                limit: self.max_condition,
            });
        }
        let too_large = |v: f64| v.is_nan() || v > MAX_RESIDUAL;
        if too_large(e.residual) || too_large(e.reconstruction) {
            return Err(RotorError::EigenResidual {
                residual: e.residual,
                reconstruction: e.reconstruction,
            });
        }
        let (static_state, harmonic_state) = self.particular()?;
        let shape = |i: usize| e.vectors.row(i).transpose() * Complex::new(e.scale[i], 0.0);
        let [ix, iy] = self.station;
        Ok(LinearClosedForm {
            n,
            speed: self.system.speed(),
            station_harmonic: [harmonic_state[ix], harmonic_state[iy]],
            station_static: Vector2::new(static_state[ix], static_state[iy]) - self.offset,
            modal: None,
            shape_x: shape(self.station[0]),
            shape_y: shape(self.station[1]),
            values: e.values,
            scale: e.scale,
            vectors: e.vectors,
            inverse: e.inverse,
            static_state,
            harmonic_state,
            station: self.station,
            offset: self.offset,
            condition: e.condition,
            residual: e.residual.max(e.reconstruction),
        })
    }

    /// $x_s = (q_s, 0)$ and $X = (Q, i\Omega Q)$, from the system's static deflection and
    /// steady response ([`LinearSystem::static_deflection`], [`LinearSystem::steady_response`]).
    fn particular(&self) -> Result<(DVector<f64>, DVector<Complex<f64>>), RotorError> {
        let (n, w) = (self.dofs(), self.system.speed());
        let mut xs = DVector::zeros(2 * n);
        xs.rows_mut(0, n)
            .copy_from(&self.system.static_deflection()?);
        let q = self.system.steady_response()?;
        let mut xh = DVector::from_element(2 * n, Complex::new(0.0, 0.0));
        for i in 0..n {
            xh[i] = q[i];
            xh[n + i] = q[i] * Complex::new(0.0, w);
        }
        Ok((xs, xh))
    }
}

impl LinearClosedForm {
    /// The closed form of a rotor whose state is its modal coordinates, from the modal data it
    /// already has: each coordinate's particular solution ([`ModalParticular`]) and the station
    /// rows of $T$; no second decomposition.
    ///
    /// # Errors
    /// [`RotorError::Singular`] when a particular solution does not exist (a mode forced at
    /// its eigenvalue: an undamped resonance $\lambda_k = \pm i\Omega$, or $\lambda_k = 0$
    /// under a static force).
    pub(crate) fn modal(data: ModalData<'_>) -> Result<Self, RotorError> {
        let n2 = data.values.len();
        let iw = Complex::new(0.0, data.speed);
        let [gc, gs, g0] = data.forcing;
        let i = Complex::new(0.0, 1.0);
        let part = |g: Complex<f64>, den: Complex<f64>, name: &'static str| {
            if g == Complex::new(0.0, 0.0) {
                return Ok(g);
            }
            let p = g / den;
            if p.re.is_finite() && p.im.is_finite() {
                Ok(p)
            } else {
                Err(RotorError::Singular {
                    matrix: name,
                    hint: "a mode is forced at its eigenvalue: no particular solution",
                })
            }
        };
        let (mut alpha, mut beta, mut sigma) = (vec![], vec![], vec![]);
        for (k, &l) in data.values.iter().enumerate() {
            let harmonic = "K - W^2 M + i W D";
            alpha.push(part(0.5 * (gc[k] - i * gs[k]), iw - l, harmonic)?);
            beta.push(part(0.5 * (gc[k] + i * gs[k]), -iw - l, harmonic)?);
            sigma.push(part(-g0[k], l, "K")?);
        }
        let sum = |row: &DVector<Complex<f64>>, c: &[Complex<f64>]| -> Complex<f64> {
            row.iter().zip(c).map(|(a, b)| a * b).sum()
        };
        let [rx, ry, ..] = data.rows;
        // Re(A e^{i W t}) + Re(B e^{-i W t}) = Re((A + conj B) e^{i W t}).
        let harmonic = |row| sum(row, &alpha) + sum(row, &beta).conj();
        let station_static = Vector2::new(sum(rx, &sigma).re, sum(ry, &sigma).re) - data.offset;
        Ok(Self {
            n: n2 / 2,
            speed: data.speed,
            values: data.values.clone(),
            scale: DVector::from_element(n2, 1.0),
            vectors: data.shapes.clone(),
            inverse: data.inverse.clone(),
            shape_x: rx.clone(),
            shape_y: ry.clone(),
            static_state: DVector::zeros(0),
            harmonic_state: DVector::zeros(0),
            station: [0, 0],
            offset: data.offset,
            station_harmonic: [harmonic(rx), harmonic(ry)],
            station_static,
            modal: Some(ModalParticular {
                alpha,
                beta,
                sigma,
                rows: data.rows.clone(),
            }),
            condition: data.condition,
            residual: data.residual,
        })
    }

    /// The real $4n\times 4n$ block-diagonal matrix of $f(\lambda_k)$ acting on
    /// $(\operatorname{Re}w_k, \operatorname{Im}w_k)$.
    pub(crate) fn modal_block_matrix(
        &self,
        f: impl Fn(Complex<f64>) -> Complex<f64>,
    ) -> DMatrix<f64> {
        let n2 = self.values.len();
        let mut m = DMatrix::zeros(2 * n2, 2 * n2);
        for (k, &l) in self.values.iter().enumerate() {
            let e = f(l);
            m[(2 * k, 2 * k)] = e.re;
            m[(2 * k, 2 * k + 1)] = -e.im;
            m[(2 * k + 1, 2 * k)] = e.im;
            m[(2 * k + 1, 2 * k + 1)] = e.re;
        }
        m
    }

    /// Number of the state's components the closed form propagates (before the ring's
    /// slots): $2n$ for `[q, q']`, $4n$ in modal coordinates.
    pub fn state_len(&self) -> usize {
        match self.modal {
            Some(_) => 4 * self.n,
            None => 2 * self.n,
        }
    }

    /// Whether the state is the modal coordinates ([`ModalRotor`](super::ModalRotor)).
    pub fn is_modal(&self) -> bool {
        self.modal.is_some()
    }

    /// Number of coordinates $n$.
    pub fn dofs(&self) -> usize {
        self.n
    }

    /// The eigenvalues $\lambda_k$ of $A$.
    pub fn eigenvalues(&self) -> &DVector<Complex<f64>> {
        &self.values
    }

    /// The least damping ratio of the rotor's modes without contact,
    /// $\zeta_{\min} = \min_k -\operatorname{Re}\lambda_k / |\lambda_k|$ over the eigenvalues
    /// with $|\lambda_k| > 10^{-12} \max_j |\lambda_j|$ (a rigid-body mode, $\lambda = 0$, has
    /// none). Negative when a mode grows: the rotor is linearly unstable (e.g. cross-coupled
    /// bearings past the threshold), its free response grows without bound and contact is not
    /// what limits it. `f64::INFINITY` when every eigenvalue is zero.
    ///
    /// ```
    /// use jeffcott::nalgebra::{DMatrix, Vector2};
    /// use jeffcott::rotor::{LinearFreeFlight, LinearSystem};
    /// // One node, x and y: k = 1, cross-coupling q = 0.05 past its threshold c sqrt(k) = 0.02.
    /// let (m, c) = (DMatrix::identity(2, 2), DMatrix::identity(2, 2) * 0.02);
    /// let k = DMatrix::from_row_slice(2, 2, &[1.0, 0.05, -0.05, 1.0]);
    /// let system = LinearSystem::new(m, c, k, 1.0)?;
    /// let form = LinearFreeFlight::new(system, [0, 1], Vector2::zeros()).prepare()?;
    /// assert!(form.least_damping_ratio() < 0.0);
    /// # Ok::<(), jeffcott::rotor::RotorError>(())
    /// ```
    pub fn least_damping_ratio(&self) -> f64 {
        let largest = self.values.iter().map(|l| l.norm()).fold(0.0, f64::max);
        self.values
            .iter()
            .filter(|l| l.norm() > 1e-12 * largest)
            .map(|l| -l.re / l.norm())
            .fold(f64::INFINITY, f64::min)
    }

    /// The rounding level of the eigenvalues' real parts,
    /// $\delta = \kappa_1(V)\thinspace r \max_j|\lambda_j|$ ([`LinearClosedForm::condition`],
    /// [`LinearClosedForm::residual`] $r$): the first-order bound on how far a computed
    /// eigenvalue may lie from the exact one of $A$. An undamped rotor's eigenvalues are on the
    /// imaginary axis to within it, on either side.
    pub fn growth_threshold(&self) -> f64 {
        let largest = self.values.iter().map(|l| l.norm()).fold(0.0, f64::max);
        self.condition * self.residual.max(f64::EPSILON) * largest
    }

    /// Whether a mode grows without contact beyond rounding: some
    /// $\operatorname{Re}\lambda_k > \delta$ ([`LinearClosedForm::growth_threshold`]). An
    /// undamped rotor (every $\operatorname{Re}\lambda_k$ zero up to rounding, its
    /// [`LinearClosedForm::least_damping_ratio`] maybe $-10^{-17}$) is not unstable.
    ///
    /// ```
    /// use jeffcott::nalgebra::{DMatrix, Vector2};
    /// use jeffcott::rotor::{LinearFreeFlight, LinearSystem};
    /// let form = |c: f64, q: f64| {
    ///     let k = DMatrix::from_row_slice(2, 2, &[1.0, q, -q, 1.0]);
    ///     let system = LinearSystem::new(DMatrix::identity(2, 2), DMatrix::identity(2, 2) * c, k, 2.0)?;
    ///     LinearFreeFlight::new(system, [0, 1], Vector2::zeros()).prepare()
    /// };
    /// assert!(!form(0.0, 0.0)?.is_linearly_unstable()); // undamped: neutral
    /// assert!(!form(0.02, 0.01)?.is_linearly_unstable()); // below the threshold c sqrt(k)
    /// assert!(form(0.02, 0.05)?.is_linearly_unstable()); // above it
    /// # Ok::<(), jeffcott::rotor::RotorError>(())
    /// ```
    pub fn is_linearly_unstable(&self) -> bool {
        let threshold = self.growth_threshold();
        self.values.iter().any(|l| l.re > threshold)
    }

    /// $\kappa_1(V)$ in balanced coordinates.
    pub fn condition(&self) -> f64 {
        self.condition
    }

    /// The decomposition's relative backward error (largest of the eigenpairs' residual and
    /// the reconstruction's).
    pub fn residual(&self) -> f64 {
        self.residual
    }

    /// The state-transition matrix $\partial x(t_0 + u)/\partial x(t_0) =
    /// \operatorname{diag}(d) V e^{\Lambda u} V^{-1} \operatorname{diag}(d)^{-1}$
    /// ($2n\times 2n$; the forcing is additive, so it depends on $u$ only). $O(n^3)$. In
    /// modal coordinates the blocks of $e^{\lambda_k u}$ ($4n\times 4n$).
    pub fn transition_matrix(&self, u: f64) -> DMatrix<f64> {
        if self.modal.is_some() {
            return self.modal_block_matrix(|l| (l * u).exp());
        }
        let n2 = 2 * self.n;
        let mut left = self.vectors.clone();
        for (k, mut col) in left.column_iter_mut().enumerate() {
            col *= (self.values[k] * u).exp();
        }
        let phi = left * &self.inverse;
        DMatrix::from_fn(n2, n2, |i, j| {
            phi[(i, j)].re * self.scale[i] / self.scale[j]
        })
    }

    /// The particular solution's state and its derivative at `t`, added to `x`, `dx`
    /// (each of length [`LinearClosedForm::state_len`]).
    pub(crate) fn add_particular(&self, t: f64, x: &mut [f64], dx: &mut [f64]) {
        let (s, c) = (self.speed * t).sin_cos();
        let ph = Complex::new(c, s);
        let iw = Complex::new(0.0, self.speed);
        if let Some(m) = &self.modal {
            for k in 0..2 * self.n {
                let (p, dp) = m.at(k, ph, iw);
                x[2 * k] += p.re;
                x[2 * k + 1] += p.im;
                dx[2 * k] += dp.re;
                dx[2 * k + 1] += dp.im;
            }
            return;
        }
        for i in 0..2 * self.n {
            let p = self.harmonic_state[i] * ph;
            x[i] += self.static_state[i] + p.re;
            dx[i] += (p * iw).re;
        }
    }

    /// Starts a segment at `t0` from the state `x0 = (q, q')` (length $2n$).
    pub fn segment(self: &Arc<Self>, t0: f64, x0: &[f64]) -> LinearSegment {
        let n2 = 2 * self.n;
        let len = self.state_len();
        let mut xp = vec![0.0; len];
        let mut dxp = vec![0.0; len];
        self.add_particular(t0, &mut xp, &mut dxp);
        let w = if self.modal.is_some() {
            // The state is the modal coordinates: w = w(t0) - p(t0).
            DVector::from_fn(n2, |k, _| {
                Complex::new(x0[2 * k] - xp[2 * k], x0[2 * k + 1] - xp[2 * k + 1])
            })
        } else {
            let z = DVector::from_fn(n2, |i, _| {
                Complex::new((x0[i] - xp[i]) / self.scale[i], 0.0)
            });
            &self.inverse * z
        };
        let coef: Vec<[Complex<f64>; 2]> = (0..n2)
            .map(|k| [self.shape_x[k] * w[k], self.shape_y[k] * w[k]])
            .collect();
        let magnitude = coef
            .iter()
            .map(|c| (c[0].norm_sqr() + c[1].norm_sqr()).sqrt())
            .collect();
        let p = self.station_harmonic;
        let rs = self.station_static;
        LinearSegment {
            form: Arc::clone(self),
            t0,
            start: x0[..len].to_vec(),
            w,
            coef,
            magnitude,
            particular_amplitude: (p[0].norm_sqr() + p[1].norm_sqr()).sqrt(),
            static_station: rs.norm(),
        }
    }
}

/// One free-flight segment of a [`LinearClosedForm`]: the motion from $(t_0, x_0)$ on, at the
/// station ([`RotorMotion`], $O(2n)$ a time) and in full ([`LinearSegment::state`],
/// $O(n^2)$).
#[derive(Debug, Clone, PartialEq)]
pub struct LinearSegment {
    form: Arc<LinearClosedForm>,
    t0: f64,
    start: Vec<f64>,
    /// Modal coordinates $w = V^{-1} z_0$.
    w: DVector<Complex<f64>>,
    /// Each mode's station coefficients $c_k$ (x and y).
    coef: Vec<[Complex<f64>; 2]>,
    /// $|c_k|$.
    magnitude: Vec<f64>,
    /// $|P|$: the particular solution's amplitude at the station.
    particular_amplitude: f64,
    /// $|r_s|$: the static station position.
    static_station: f64,
}

impl LinearSegment {
    /// The closed form.
    pub fn form(&self) -> &LinearClosedForm {
        &self.form
    }

    /// The state $x = (q, q^\prime)$ and its derivative at `t` ($t \ge t_0$; the start state
    /// itself at $t_0$), written into `x` and `dx` (length $2n$).
    pub fn state(&self, t: f64, x: &mut [f64], dx: &mut [f64]) {
        let f = &*self.form;
        let n2 = 2 * f.n;
        if let Some(m) = &f.modal {
            let (ph, iw) = self.phase(t);
            for k in 0..n2 {
                let [w, dw, _] = self.modal_coordinate(m, k, t, ph, iw);
                x[2 * k] = w.re;
                x[2 * k + 1] = w.im;
                dx[2 * k] = dw.re;
                dx[2 * k + 1] = dw.im;
            }
            return;
        }
        x[..n2].fill(0.0);
        dx[..n2].fill(0.0);
        f.add_particular(t, x, dx);
        let u = t - self.t0;
        for k in 0..n2 {
            let e = (f.values[k] * u).exp() * self.w[k];
            if e.re == 0.0 && e.im == 0.0 {
                continue;
            }
            let de = e * f.values[k];
            for i in 0..n2 {
                let v = f.vectors[(i, k)];
                x[i] += f.scale[i] * (v * e).re;
                dx[i] += f.scale[i] * (v * de).re;
            }
        }
        if t == self.t0 {
            // The particular and homogeneous parts cancel to rounding at the start, whose
            // state is known exactly.
            x[..n2].copy_from_slice(&self.start);
        }
    }
}

impl LinearSegment {
    /// $e^{i\Omega t}$ and $i\Omega$.
    fn phase(&self, t: f64) -> (Complex<f64>, Complex<f64>) {
        let (s, c) = (self.form.speed * t).sin_cos();
        (Complex::new(c, s), Complex::new(0.0, self.form.speed))
    }

    /// The modal coordinate $w_k$ and its first two derivatives at `t`, $w_k =
    /// e^{\lambda_k(t - t_0)}(w_k(t_0) - p_k(t_0)) + p_k(t)$ (the start state itself at $t_0$).
    fn modal_coordinate(
        &self,
        m: &ModalParticular,
        k: usize,
        t: f64,
        ph: Complex<f64>,
        iw: Complex<f64>,
    ) -> [Complex<f64>; 3] {
        let lam = self.form.values[k];
        let e = (lam * (t - self.t0)).exp() * self.w[k];
        let (a, b) = (m.alpha[k] * ph, m.beta[k] * ph.conj());
        let w = if t == self.t0 {
            Complex::new(self.start[2 * k], self.start[2 * k + 1])
        } else {
            e + a + b + m.sigma[k]
        };
        [w, lam * e + iw * (a - b), lam * lam * e + iw * iw * (a + b)]
    }

    /// The station's kinematics in modal coordinates: the rows of $T$ applied to $w(t)$ in
    /// the order and arithmetic of [`ModalRotor`](super::ModalRotor)'s station, so that the
    /// onset search and the rotor see the same station to the last bit.
    fn modal_kinematics(
        &self,
        m: &ModalParticular,
        t: f64,
    ) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        let (ph, iw) = self.phase(t);
        let dot = |c: Complex<f64>, w: Complex<f64>| c.re * w.re - c.im * w.im;
        let [rx, ry, vx, vy] = &m.rows;
        let (mut r, mut v, mut a) = ([0.0; 2], [0.0; 2], [0.0; 2]);
        for k in 0..2 * self.form.n {
            let [w, dw, _] = self.modal_coordinate(m, k, t, ph, iw);
            r[0] += dot(rx[k], w);
            r[1] += dot(ry[k], w);
            v[0] += dot(vx[k], w);
            v[1] += dot(vy[k], w);
            a[0] += dot(vx[k], dw);
            a[1] += dot(vy[k], dw);
        }
        let o = self.form.offset;
        (
            Vector2::new(r[0] - o.x, r[1] - o.y),
            Vector2::from(v),
            Vector2::from(a),
        )
    }
}

impl RotorMotion for LinearSegment {
    fn start(&self) -> f64 {
        self.t0
    }

    fn kinematics(&self, t: f64) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        let f = &*self.form;
        if let Some(m) = &f.modal {
            return self.modal_kinematics(m, t);
        }
        let [ix, iy] = f.station;
        let n = f.n;
        let (s, c) = (f.speed * t).sin_cos();
        let ph = Complex::new(c, s);
        let w = f.speed;
        let (px, py) = (f.station_harmonic[0] * ph, f.station_harmonic[1] * ph);
        let mut r = Vector2::new(f.station_static.x + px.re, f.station_static.y + py.re);
        let mut v = Vector2::new(-w * px.im, -w * py.im);
        let mut a = Vector2::new(-w * w * px.re, -w * w * py.re);
        let u = t - self.t0;
        for (k, c) in self.coef.iter().enumerate() {
            let lam = f.values[k];
            let e = (lam * u).exp();
            if e.re == 0.0 && e.im == 0.0 {
                continue;
            }
            let (ex, ey) = (c[0] * e, c[1] * e);
            let (dx, dy) = (ex * lam, ey * lam);
            r.x += ex.re;
            r.y += ey.re;
            v.x += dx.re;
            v.y += dy.re;
            a.x += (dx * lam).re;
            a.y += (dy * lam).re;
        }
        if t == self.t0 {
            r = Vector2::new(self.start[ix], self.start[iy]) - f.offset;
            v = Vector2::new(self.start[n + ix], self.start[n + iy]);
        }
        (r, v, a)
    }

    fn bounds(&self) -> MotionBounds {
        self.bounds_on(self.t0, f64::INFINITY)
    }

    fn bounds_on(&self, from: f64, to: f64) -> MotionBounds {
        let f = &*self.form;
        let w = f.speed.abs();
        let p = self.particular_amplitude;
        let mut b = [self.static_station + p, w * p, w * w * p, w * w * w * p];
        for (k, &m) in self.magnitude.iter().enumerate() {
            let lam = f.values[k];
            let tau = if lam.re <= 0.0 { from } else { to } - self.t0;
            if m == 0.0 {
                continue;
            }
            let e = m * (lam.re * tau.max(0.0)).exp();
            if e == 0.0 {
                continue;
            }
            let l = lam.norm();
            b[0] += e;
            b[1] += e * l;
            b[2] += e * l * l;
            b[3] += e * l * l * l;
        }
        // Sums of 2n + 1 positive terms, each of a few roundings.
        let margin = 1.0 + 8.0 * (2 * f.n + 8) as f64 * f64::EPSILON;
        MotionBounds {
            position: b[0] * margin,
            velocity: b[1] * margin,
            acceleration: b[2] * margin,
            jerk: b[3] * margin,
        }
    }
}

/// The free-flight segment of a [`RingedRotor`](super::RingedRotor) whose rotor has a linear
/// closed form: the rotor's [`LinearSegment`], the ring's exact relaxation and the certified
/// onset search ([`OnsetScan`], as the paper's model runs it). State `[q, q', x_s, y_s]`.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearFreeSegment {
    pub(super) motion: Option<LinearSegment>,
    pub(super) relax: Relaxation,
    pub(super) ring: SnubberRing,
    pub(super) scan: OnsetScan,
}

impl<D: Dim> ExactSegment<D> for LinearFreeSegment
where
    DefaultAllocator: Allocator<D>,
{
    fn eval(&self, t: f64, y: &mut OVector<f64, D>, dy: &mut OVector<f64, D>) {
        let Some(motion) = &self.motion else {
            // Never started without a closed form (the free flight is then integrated).
            y.fill(f64::NAN);
            dy.fill(f64::NAN);
            return;
        };
        let f = &*motion.form;
        let (n, n2, [ix, iy]) = (f.n, f.state_len(), f.station);
        motion.state(t, &mut y.as_mut_slice()[..n2], &mut dy.as_mut_slice()[..n2]);
        let (s, sd) = self.relax.at(&self.ring, t);
        y[n2] = s.x;
        y[n2 + 1] = s.y;
        dy[n2] = sd.x;
        dy[n2 + 1] = sd.y;
        if f.modal.is_some() {
            // The rotor's station is computed from the modal state exactly as the search did.
            return;
        }
        // The station's coordinates as the onset search saw them (the station shapes' sums,
        // which differ from the full state's by rounding): a contact found there starts there.
        let (r, v, a) = motion.kinematics(t);
        y[ix] = r.x + f.offset.x;
        y[iy] = r.y + f.offset.y;
        y[n + ix] = v.x;
        y[n + iy] = v.y;
        dy[ix] = v.x;
        dy[iy] = v.y;
        dy[n + ix] = a.x;
        dy[n + iy] = a.y;
    }

    fn next_guard(&mut self, t_from: f64, t_to: f64) -> Option<GuardCrossing> {
        let motion = self.motion.as_ref()?;
        self.scan
            .next_onset(motion, &self.relax, &self.ring, t_from, t_to)
            .map(|t| GuardCrossing { guard: 0, t })
    }

    fn evaluations(&self) -> u64 {
        self.scan.evaluations()
    }
}
