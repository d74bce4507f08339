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
/// ([`LinearClosedForm`]). The rotor's state must be `[q (n), q' (n), x_s, y_s]`.
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
    condition: f64,
    residual: f64,
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
        Ok(LinearClosedForm {
            n,
            speed: self.system.speed(),
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
    /// Number of coordinates $n$.
    pub fn dofs(&self) -> usize {
        self.n
    }

    /// The eigenvalues $\lambda_k$ of $A$.
    pub fn eigenvalues(&self) -> &DVector<Complex<f64>> {
        &self.values
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
    /// ($2n\times 2n$; the forcing is additive, so it depends on $u$ only). $O(n^3)$.
    pub fn transition_matrix(&self, u: f64) -> DMatrix<f64> {
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
    /// (each of length $2n$).
    pub(crate) fn add_particular(&self, t: f64, x: &mut [f64], dx: &mut [f64]) {
        let (s, c) = (self.speed * t).sin_cos();
        let ph = Complex::new(c, s);
        let iw = Complex::new(0.0, self.speed);
        for i in 0..2 * self.n {
            let p = self.harmonic_state[i] * ph;
            x[i] += self.static_state[i] + p.re;
            dx[i] += (p * iw).re;
        }
    }

    /// Starts a segment at `t0` from the state `x0 = (q, q')` (length $2n$).
    pub fn segment(self: &Arc<Self>, t0: f64, x0: &[f64]) -> LinearSegment {
        let n2 = 2 * self.n;
        let mut xp = vec![0.0; n2];
        let mut dxp = vec![0.0; n2];
        self.add_particular(t0, &mut xp, &mut dxp);
        let z = DVector::from_fn(n2, |i, _| {
            Complex::new((x0[i] - xp[i]) / self.scale[i], 0.0)
        });
        let w = &self.inverse * z;
        let coef: Vec<[Complex<f64>; 2]> = (0..n2)
            .map(|k| [self.shape_x[k] * w[k], self.shape_y[k] * w[k]])
            .collect();
        let magnitude = coef
            .iter()
            .map(|c| (c[0].norm_sqr() + c[1].norm_sqr()).sqrt())
            .collect();
        let p = Vector2::new(
            self.harmonic_state[self.station[0]],
            self.harmonic_state[self.station[1]],
        );
        let rs = Vector2::new(
            self.static_state[self.station[0]],
            self.static_state[self.station[1]],
        ) - self.offset;
        LinearSegment {
            form: Arc::clone(self),
            t0,
            start: x0.to_vec(),
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

impl RotorMotion for LinearSegment {
    fn start(&self) -> f64 {
        self.t0
    }

    fn kinematics(&self, t: f64) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        let f = &*self.form;
        let [ix, iy] = f.station;
        let n = f.n;
        let (s, c) = (f.speed * t).sin_cos();
        let ph = Complex::new(c, s);
        let w = f.speed;
        let (px, py) = (f.harmonic_state[ix] * ph, f.harmonic_state[iy] * ph);
        let mut r = Vector2::new(
            f.static_state[ix] - f.offset.x + px.re,
            f.static_state[iy] - f.offset.y + py.re,
        );
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
        let (n, n2, [ix, iy]) = (f.n, 2 * f.n, f.station);
        motion.state(t, &mut y.as_mut_slice()[..n2], &mut dy.as_mut_slice()[..n2]);
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
        let (s, sd) = self.relax.at(&self.ring, t);
        y[n2] = s.x;
        y[n2 + 1] = s.y;
        dy[n2] = sd.x;
        dy[n2 + 1] = sd.y;
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
