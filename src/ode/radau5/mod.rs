//! RADAU5, the three-stage Radau IIA method of order 5: the type [`Radau5`] (its docs give
//! the method), the tableau and transformation (`tableau`), the Newton iteration and error
//! estimate (`newton`).

mod newton;
mod tableau;
mod woodbury;

use self::newton::{error_estimate, iterate, Linear, Newton, Rate, StepInput, NIT};
use self::tableau::{C1, C2};
use super::core::{core_accessors, fit, zeros, Core};
use super::kernels::all_finite;
use super::{Integrator, OdeError, OdeSystem, Options, Stats};
use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, DimName, OVector};

/// Convergence rate below which the Jacobian is kept for the next step (RADAU5's `THET`).
const THETA_JAC: f64 = 1e-3;
/// Suggested step-size ratios $h_{\text{new}}/h$ within which $h$ is kept, to keep the LU
/// decompositions (RADAU5's `QUOT1`, `QUOT2`): Hairer's defaults, for small systems...
const KEEP_H_SMALL: (f64, f64) = (1.0, 1.2);
/// ...and the values his documentation suggests for large full systems, taken from
/// [`LARGE_SYSTEM`] states on.
const KEEP_H_LARGE: (f64, f64) = (0.99, 2.0);
/// From this dimension on the LU decompositions dominate a step's cost: a pair costs about
/// $\tfrac{10}{3}N^3$ flops, a step's Newton and error solves about $35N^2$.
const LARGE_SYSTEM: usize = 20;

/// RADAU5: the three-stage Radau IIA collocation method of order 5 (L-stable, stiffly
/// accurate), after Hairer and Wanner's `radau5.f` (*Solving ODEs II*, §IV.8).
///
/// # The method
///
/// A step of size $h$ from $(t, y)$ solves the stage system for $Z_i = Y_i - y$,
/// $$Z_i = h\sum_{j=1}^3 a_{ij}\thinspace f(t + c_j h, y + Z_j),\qquad i = 1, 2, 3,$$
/// with the Radau IIA tableau
/// $$\begin{array}{c|ccc}
/// \frac{4-\sqrt6}{10} & \frac{88-7\sqrt6}{360} & \frac{296-169\sqrt6}{1800} & \frac{-2+3\sqrt6}{225}\\\\
/// \frac{4+\sqrt6}{10} & \frac{296+169\sqrt6}{1800} & \frac{88+7\sqrt6}{360} & \frac{-2-3\sqrt6}{225}\\\\
/// 1 & \frac{16-\sqrt6}{36} & \frac{16+\sqrt6}{36} & \frac19
/// \end{array}$$
/// and takes $y_{\text{new}} = y + Z_3$ (stiffly accurate: the last stage is the new point).
///
/// **Simplified Newton, transformed.** With $J \approx \partial f/\partial y$ at the start of
/// the step and $W = (T^{-1}\otimes I) Z$, where $T^{-1}A^{-1}T = \Lambda =
/// \mathrm{diag}\big(\gamma, \begin{pmatrix}\alpha & -\beta\\\\ \beta & \alpha\end{pmatrix}\big)$,
/// each iteration solves one real system with $(\gamma/h) I - J$ and one complex system with
/// $((\alpha + i\beta)/h) I - J$ ($3N$ real unknowns for the price of $N$ real plus $N$
/// complex ones). The contraction rate $\theta_k = \Vert\Delta W_k\Vert / \Vert\Delta W_{k-1}\Vert$
/// is monitored: the iteration stops when $\frac{\theta}{1-\theta}\Vert\Delta W_k\Vert \le
/// \kappa$ ($\kappa = \max(10\varepsilon/\mathrm{rtol}^\prime, \min(0.03, \sqrt{\mathrm{rtol}^\prime}))$),
/// and the step is rejected with a smaller $h$ when $\theta \ge 0.99$, when the error
/// predicted after the remaining iterations exceeds $\kappa$, or after 7 iterations. Newton
/// failure is always a rejection (counted in [`Stats::rejected`](super::Stats)), never an
/// accepted step; when $h$ underflows it is [`OdeError::StepSizeUnderflow`].
///
/// **Reuse.** $J$ is computed at the start of a step only when the last step converged
/// slowly ($\theta > 10^{-3}$) or after a reset; after a rejection it is recomputed unless it
/// is already fresh at this point. The two LU decompositions are redone only when $h$
/// changes; after a fast-converging step, a suggested ratio $h_{\text{new}}/h$ in $[1, 1.2]$
/// is not taken, to keep them, and from $N = 20$ states on one in $[0.99, 2]$ (the values
/// Hairer's documentation of RADAU5 gives for large full systems: there the decompositions,
/// $\tfrac{10}{3}N^3$ flops a pair, cost more than the extra steps; on the 64-mode flexible shaft
/// with contacts, 258 states, a third of the decompositions and 25 % more steps).
///
/// **Second-order systems.** When the system declares $q^\prime = v$ for its first $2p$
/// components ([`OdeSystem::second_order`]), both Newton matrices are condensed to the
/// $N - p$ unknowns $(v, z)$ (Hairer and Wanner's option `M1` = `M2`), the positions
/// recovered as $x_q = (b_q + x_v)/c$: for a mechanical system the decompositions cost an
/// eighth. Measured (release, shared 2-core machine): S1 (a 204-DOF finite-element rotor on
/// the ring, 274 states) 10.0 s CPU before, 2.9 s after, 2.7 s with the analytic Jacobian of
/// `rotor::LinearRotor`; the 64-mode flexible shaft (258 states, 40 periods at
/// rtol $10^{-8}$) 17.6 s before, 5.7 s after, with the same error against DOP853 at
/// $10^{-12}$.
///
/// **Diagonal springs, low-rank coupling.** When a second-order system also declares the
/// diagonal springs and dampers of its Jacobian ([`OdeSystem::diagonal_springs`]: modes
/// coupled only by a force through a station), each Jacobian is split once into that
/// diagonal and a coupling of rank $r \le 8$ (cross approximation, exact for a coupling of
/// rank $r$; the dense LU when the rest is not of low rank), and the condensed matrices,
/// diagonal plus rank $r$, are solved by the Sherman-Morrison-Woodbury formula: $O(Nr)$ a
/// solve and $O(Nr^2)$ a decomposition, and the step size is then kept only for ratios in
/// $[1, 1.2]$. Measured on the 64-mode shaft with contacts (40 periods at rtol $10^{-8}$, wall
/// time on a loaded machine, docs/integrators.md): atol $10^{-12}$ 8.3 s to 1.35 s (DOP853
/// 7.5 s), atol $10^{-8}$ 1.7 s to 0.24 s (DOP853 7.3 s). The split needs the system's own
/// Jacobian: the noise of a finite-difference one is not of low rank.
///
/// **Error estimate.** $e = (\tfrac{\gamma}{h} I - J)^{-1}\big(f(t, y) + \tfrac1h(d_1Z_1 + d_2Z_2 + d_3Z_3)\big)$
/// with $d = (-(13 + 7\sqrt6)/3, (-13 + 7\sqrt6)/3, -1/3)$, a third-order estimate filtered by
/// the resolvent so that it stays bounded for stiff components; on the first step after a
/// reset and after a rejection, if $\Vert e\Vert > 1$, it is refined once with
/// $f(t, y + e)$ in place of $f(t, y)$. The norm is the crate's RMS norm with the scale
/// $s_i = \mathrm{atol}_i + \mathrm{rtol}^\prime_i|y_i|$ at the start of the step, where RADAU5's
/// tolerance transformation $\mathrm{rtol}^\prime = 0.1\thinspace\mathrm{rtol}^{2/3}$ maps the
/// requested relative tolerance of the order-5 solution to the order-3 estimate. The absolute
/// tolerance is held as given: Hairer's code also scales it, by $\mathrm{rtol}^\prime/\mathrm{rtol}$,
/// which is consistent only where atol/rtol is the size of the solution (at rtol $10^{-13}$ and
/// atol $10^{-4}$ it made an absolute tolerance of 0.2, and errors of $1.7\cdot10^{-3}$).
///
/// **Step size.** $h_{\text{new}} = h/q$ with $q = \Vert e\Vert^{1/4}/\mathrm{fac}$ kept
/// between the reciprocals of [`Options::fac_max`] and [`Options::fac_min`], where
/// $\mathrm{fac} = \min(\mathrm{safety}, \mathrm{safety}\thinspace(1 + 2\cdot7)/(k + 2\cdot 7))$
/// for $k$ Newton iterations; a rejected first step after a reset divides $h$ by 10 instead
/// (Hairer's rule for a guessed initial step) unless the step size was kept across the reset
/// (`keep_step`: a step size that worked before a discontinuity, whose error estimate is then
/// trusted as any other); on acceptance the predictive controller of Gustafsson may lower
/// it:
/// $h_{\text{new}} \le h\thinspace\mathrm{safety}\thinspace\frac{h}{h_{\text{acc}}}
/// \big(\mathrm{err}_{\text{acc}}/\mathrm{err}^2\big)^{1/4}$ (acc: the previous accepted
/// step and its error). [`Options::beta`] is not used.
///
/// **Dense output** is the collocation polynomial raised to order 4: the cubic $u$ with
/// $u(t_{\text{prev}}) = y_{\text{prev}}$, $u(t_{\text{prev}} + c_i h) = y_{\text{prev}} + Z_i$,
/// in Newton's form about the step's left end, $u = y_{\text{prev}} + \theta\big(d_1 + (\theta -
/// c_1)(d_2 + (\theta - c_2) d_3)\big)$, $\theta = (t - t_{\text{prev}})/h$, with the divided
/// differences $d_k$ of the $Z_i$ (about the left end, where events restart, so that no value
/// there cancels against the far end of a long step), plus $r(\theta)\thinspace\gamma e$ with
/// $r(\theta) = \theta(1 - \theta)^2(1 - \tfrac52\theta)$ and $e$ the step's error estimate. The
/// cubic alone is of order 3 inside the step (local error $O(h^4)$, as the error estimate, so
/// held to $0.1\thinspace\mathrm{rtol}^{2/3}$, not rtol); $\gamma e$ is its slope mismatch at
/// the start, $hf(t_{\text{prev}}, y_{\text{prev}}) - u^\prime(0)$, filtered by the resolvent,
/// and the sum is the quartic through both ends with the start's slope and the collocation
/// slopes: local error $O(h^5)$ (`eval_poly` derives it). It is exact at both ends
/// ($y_{\text{prev}}$ and $y_{\text{new}}$ are returned as stored), costs no evaluation of $f$
/// (the estimate is there already), and its cubic gives the Newton starting values of the
/// next step by extrapolation. On the first step after a reset one more term, $q(\theta)d_5$
/// with $q = \theta(1 - \theta/c_1)^3$ on $[0, c_1]$ (zero at the nodes and beyond $c_1$),
/// makes its slope at the start exactly $f(t_{\text{prev}}, y_{\text{prev}})$: events restart
/// there, and a guard on zero with a rate of 0 (a contact loss) must not cross zero on the
/// polynomial by its stage error (`eval_poly`).
///
/// Every vector, the Jacobian and both LU factorisations are allocated by the constructor
/// ($N^2$ reals and $N^2$ complex numbers): `reset`, `step`, `dense` and `truncate` never
/// allocate, also for [`Dyn`](nalgebra::Dyn). With [`Options::fixed_step`] (for convergence
/// studies) there is no error control and a Newton failure is [`OdeError::NewtonFailure`];
/// the Newton tolerance still comes from `rtol` and `atol`.
///
/// ```
/// use jeffcott::ode::{Integrator, Options, Radau5};
/// use nalgebra::SVector;
///
/// // Robertson's chemical kinetics, stiff up to t = 1e5; the finite-difference Jacobian.
/// let rober = |_t: f64, y: &SVector<f64, 3>, dy: &mut SVector<f64, 3>| {
///     dy[0] = -0.04 * y[0] + 1e4 * y[1] * y[2];
///     dy[2] = 3e7 * y[1] * y[1];
///     dy[1] = -dy[0] - dy[2];
/// };
/// let mut integ = Radau5::new(Options::with_tol(1e-8, 1e-12))?;
/// integ.reset(&rober, 0.0, &SVector::<f64, 3>::new(1.0, 0.0, 0.0), false)?;
/// while integ.t() < 40.0 {
///     integ.step(&rober, 40.0)?;
/// }
/// // Hairer and Wanner's reference solution at t = 40.
/// let y = integ.y();
/// assert!((y[0] - 0.7158270687193e0).abs() < 1e-6);
/// assert!((y[1] - 0.9185534764557e-5).abs() < 1e-10);
/// // A few hundred steps, where an explicit method needs ~1e5 on this interval.
/// assert!(integ.stats().steps < 500);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone)]
pub struct Radau5<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    core: Core<D>,
    /// RADAU5's transformed relative tolerance, and the absolute one as given (see the type docs).
    rtol: OVector<f64, D>,
    atol: OVector<f64, D>,
    /// Newton stopping tolerance $\kappa$.
    fnewt: f64,
    scal: OVector<f64, D>,
    /// Stage increments $Z_i$ (scratch during the Newton iteration).
    z: [OVector<f64, D>; 3],
    /// Transformed increments $W = T^{-1} Z$.
    w: [OVector<f64, D>; 3],
    /// Dense-output coefficients $d_1, \dots, d_5$ of the last accepted step (see `eval_poly`).
    cont: [OVector<f64, D>; 5],
    /// Right end of the last accepted (untruncated) step.
    t_end: f64,
    yt: OVector<f64, D>,
    ft: OVector<f64, D>,
    lin: Linear,
    /// A Jacobian exists and may be used.
    jac_ok: bool,
    /// The Jacobian was computed at the current point.
    jac_fresh: bool,
    /// The step size the LU decompositions are for (0 = none).
    lu_h: f64,
    rate: Rate,
    /// No step accepted since the last reset.
    first: bool,
    /// Gustafsson's memory: last accepted step and its error (`h_acc` 0 = none).
    h_acc: f64,
    err_acc: f64,
    /// The step size was kept across the last reset (not guessed).
    h_kept: bool,
    /// Ratios $h_{\text{new}}/h$ within which $h$ and the LU decompositions are kept.
    keep_h: (f64, f64),
}

impl<D: DimName> Radau5<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Creates the integrator for a fixed dimension (`U3`, `Const<3>`), validating `options`.
    /// Call [`Integrator::reset`] before stepping.
    pub fn new(options: Options<D>) -> Result<Self, OdeError> {
        Self::with_dim(D::name(), options)
    }
}

impl<D: Dim> Radau5<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Creates the integrator for dimension `dim` (e.g. `Dyn(n)`), validating `options`.
    /// Allocates everything it will use, including the $N\times N$ Jacobian and the two
    /// factorisations.
    pub fn with_dim(dim: D, options: Options<D>) -> Result<Self, OdeError> {
        let core = Core::new(dim, options, 4.0, 0.0, 5.0)?;
        let n = dim.value();
        let z = zeros(dim);
        let (mut rtol, mut atol) = (z.clone(), z.clone());
        let mut rmin = f64::INFINITY;
        for i in 0..n {
            let (r, a) = (core.opts.rtol.get(i), core.opts.atol.get(i));
            let r2 = 0.1 * r.powf(2.0 / 3.0);
            rtol[i] = r2;
            atol[i] = a;
            if r2 > 0.0 {
                rmin = rmin.min(r2);
            }
        }
        let fnewt = if rmin.is_finite() {
            (10.0 * f64::EPSILON / rmin).max(0.03f64.min(rmin.sqrt()))
        } else {
            0.03
        };
        Ok(Radau5 {
            core,
            rtol,
            atol,
            fnewt,
            scal: z.clone(),
            z: std::array::from_fn(|_| z.clone()),
            w: std::array::from_fn(|_| z.clone()),
            cont: std::array::from_fn(|_| z.clone()),
            t_end: 0.0,
            yt: z.clone(),
            ft: z,
            lin: Linear::new(n),
            jac_ok: false,
            jac_fresh: false,
            lu_h: 0.0,
            rate: Rate {
                theta: THETA_JAC,
                faccon: 1.0,
            },
            first: true,
            h_acc: 0.0,
            err_acc: 1e-2,
            h_kept: false,
            keep_h: if n >= LARGE_SYSTEM {
                KEEP_H_LARGE
            } else {
                KEEP_H_SMALL
            },
        })
    }

    /// Evaluates the collocation polynomial of the last step at `t`.
    fn eval_dense(&self, t: f64, out: &mut [f64]) {
        let c = &self.core;
        let ends = [(c.t_prev, &c.y_prev), (self.t_end, &c.y_end)];
        eval_poly(&self.cont, c.h_dense, ends, t, true, out);
    }

    /// Newton starting values for a step of size `h` from the current point: zero after a
    /// reset, else the last collocation polynomial extrapolated to $t + c_i h$.
    fn starting_values(&mut self, h: f64) {
        let n = self.core.dim.value();
        if self.first {
            for v in self.z.iter_mut().chain(self.w.iter_mut()) {
                v.fill(0.0);
            }
            return;
        }
        let c = &self.core;
        for (s_i, ci) in [C1, C2, 1.0].into_iter().enumerate() {
            // Beyond the last step: the polynomial itself (its right end never matches).
            let ends = [(c.t_prev, &c.y_prev), (f64::NAN, &c.y_end)];
            let zi = self.z[s_i].as_mut_slice();
            eval_poly(&self.cont, c.h_dense, ends, c.t + ci * h, false, zi);
            for i in 0..n {
                zi[i] -= c.y[i];
            }
        }
        let [z0, z1, z2] = &self.z;
        let [w0, w1, w2] = &mut self.w;
        let ti = tableau::TI;
        for i in 0..n {
            w0[i] = ti[0][0] * z0[i] + ti[0][1] * z1[i] + ti[0][2] * z2[i];
            w1[i] = ti[1][0] * z0[i] + ti[1][1] * z1[i] + ti[1][2] * z2[i];
            w2[i] = ti[2][0] * z0[i] + ti[2][1] * z1[i] + ti[2][2] * z2[i];
        }
    }

    /// The dense-output coefficients of the step of size `h` just accepted (the core still at
    /// its start, `ft` holding the step's error estimate $e$): the divided differences
    /// $d_1, d_2, d_3$ of the stage increments over the nodes $0, c_1, c_2, 1$ (in units of
    /// the step), the order-raising term's $d_4 = \gamma e$ (the resolvent-filtered slope
    /// mismatch $(I - hJ/\gamma)^{-1}(hf(t, y) - u^\prime(0))$), and on a restart's step the
    /// tangency term's $d_5 = hf(t, y) - u^\prime(0) - d_4$ (see `eval_poly`).
    fn update_dense(&mut self, h: f64, restart: bool) {
        let n = self.core.dim.value();
        let f0 = &self.core.f;
        let g = self.lin.gamma;
        let [z1, z2, z3] = &self.z;
        let [d1, d2, d3, d4, d5] = &mut self.cont;
        for i in 0..n {
            let a = z1[i] / C1;
            let b = (z2[i] - z1[i]) / (C2 - C1);
            let c = (z3[i] - z2[i]) / (1.0 - C2);
            let ab = (b - a) / C2;
            let bc = (c - b) / (1.0 - C1);
            d1[i] = a;
            d2[i] = ab;
            d3[i] = bc - ab;
            d4[i] = g * self.ft[i];
            // The cubic's slope at the start, in units of the step: d1 - c1 d2 + c1 c2 d3.
            d5[i] = if restart {
                h * f0[i] - (a - C1 * ab + C1 * C2 * (bc - ab)) - d4[i]
            } else {
                0.0
            };
        }
    }

    /// The error scale $s_i = \mathrm{atol}_i + \mathrm{rtol}^\prime_i |y_i|$ at the current point.
    fn update_scale(&mut self) {
        let c = &self.core;
        for i in 0..self.scal.len() {
            self.scal[i] = self.atol[i] + self.rtol[i] * c.y[i].abs();
        }
    }

    /// Makes the Jacobian and the LU decompositions ready for a step of size `h`; `false`
    /// if a Newton matrix is singular.
    fn prepare_linear<S: OdeSystem<D>>(&mut self, sys: &S, h: f64) -> bool {
        if !self.jac_ok {
            let c = &mut self.core;
            self.lin.jacobian(
                sys,
                c.t,
                &c.y,
                &c.f,
                &mut self.yt,
                &mut self.ft,
                &mut c.stats,
            );
            self.jac_ok = true;
            self.jac_fresh = true;
            self.lu_h = 0.0;
        }
        if self.lu_h != h {
            self.lu_h = h;
            if !self.lin.decompose(h, &mut self.core.stats) {
                self.lu_h = 0.0;
                return false;
            }
        }
        true
    }
}

/// $p(t) = y_{\text{prev}} + \theta\big(d_1 + (\theta - c_1)(d_2 + (\theta - c_2)d_3)\big) +
/// r(\theta)d_4 + q(\theta)d_5$, $\theta = (t - t_{\text{prev}})/h$ (Newton's form about the
/// left end, where events restart: no cancellation against the values at the far end of a
/// long step), except that the ends return their stored states exactly. `ends` = the step's
/// two ends `(t, y)`. With `corrected` false (the Newton starting values, extrapolated
/// beyond the step) only the cubic $u$, RADAU5's collocation polynomial through $y$ and the
/// three stages.
///
/// **Order 4 inside the step** ($d_4$). The cubic $u$ has $u(0) = y_{\text{prev}}$ and the
/// collocation slopes $u^\prime(c_i) = hf(Y_i)$ ($c_3 = 1$); its local error inside the step
/// is $O(h^4)$, the order of the error estimate, so it is held to the transformed tolerance
/// $0.1\thinspace\mathrm{rtol}^{2/3}$, not to rtol (issue 31: samples $170\thinspace$rtol off
/// at rtol $10^{-10}$). Adding the start's slope gives the quartic $p$ with $p(0) =
/// y_{\text{prev}}$, $p(1) = y_{\text{new}}$, $p^\prime(0) = hf(t_{\text{prev}},
/// y_{\text{prev}})$ and $p^\prime(c_i) = u^\prime(c_i)$: the ends are of order 5 and the slopes
/// are $h$ times $f$ at stages of error $O(h^4)$, so $p$'s local error is $O(h^5)$. Then
/// $p = u + (hf - u^\prime(0))\thinspace r(\theta)$ with
/// $$r(\theta) = \theta(1 - \theta)^2\big(1 - \tfrac52\theta\big),$$
/// the quartic with $r(0) = r(1) = 0$, $r^\prime(0) = 1$, $r^\prime(c_1) = r^\prime(c_2) =
/// r^\prime(1) = 0$ ($|r| \le 0.068$, largest at $c_1$). The slope mismatch $hf - u^\prime(0)$ is
/// the error estimate's right-hand side $hf + \sum_i \delta_i Z_i$ (with the estimate's
/// coefficients $\delta_i$, the type docs' $d$: both are the one combination of $hf$, with
/// weight 1, and the $Z_i$ that vanishes on cubics), so $d_4 = \gamma e$, $e$ the step's error
/// estimate, is that mismatch filtered by the resolvent, $(I - hJ/\gamma)^{-1}(hf -
/// u^\prime(0))$: equal to it up to $O(h^5)$, the order of $p$'s own error, on smooth
/// components, damped on stiff ones (where the mismatch measures $y_{\text{prev}}$'s distance
/// from the slow manifold times $h\lambda$, not the cubic's error). The term moves the output
/// by at most $0.068\gamma|e_i| \approx 0.25|e_i|$, a quarter of the error the step was
/// accepted with: it can sharpen the cubic, never take it far. Measured on a forced oscillator
/// (`tests/suite/ode/ode_radau_dense.rs`, rtol = atol $10^{-6}$ to $10^{-10}$): samples 2.8
/// to 73 rtol off with the cubic alone, 0.16 to 0.66 with $p$, in the same steps.
///
/// **Tangent at a restart** ($d_5$). On every step but the first after a reset $d_5 = 0$. On
/// that step $d_5 = hf - u^\prime(0) - d_4$, the part of the mismatch the filter removed, and
/// $q(\theta) = \theta(1 - \theta/c_1)^3$ on $[0, c_1]$, 0 beyond ($q(0) = 0$, $q^\prime(0) = 1$,
/// and $q$ meets 0 at $c_1$ with two derivatives): the slope at the start is exactly $f$, and
/// everything past $c_1$ is as without it. The dense output leaves a restart tangent to the
/// flow, as the explicit methods' does. There a guard can sit on zero with a rate of 0 (a
/// contact loss); on the collocation polynomial alone it could rise through zero and back by
/// the stage error (a $10^{-10}$ spurious onset on the 8-mode shaft at rtol $10^{-6}$, then
/// chattering), and the event screens, which take the start's slope from $f$, would disagree
/// with the curve they search. Why local: a term spread over the whole step (the quartic
/// $\theta(\theta - c_1)(\theta - c_2)(\theta - 1)$, tried first, which keeps the stage values
/// rather than their slopes and so gains no order) is as large as 0.18 of its coefficient in
/// $[c_2, 1]$; with the raw mismatch, which is large on stiff components after a jump, it made
/// a $3.8\cdot10^{-6}$ excursion beyond the ring that the screens missed (fuzz seed 777, case
/// 21024). $q$ is at most $0.0163|d_5|$, and only in the first $15\thinspace\%$ of the step.
fn eval_poly<D: Dim>(
    cont: &[OVector<f64, D>; 5],
    h: f64,
    ends: [(f64, &OVector<f64, D>); 2],
    t: f64,
    corrected: bool,
    out: &mut [f64],
) where
    DefaultAllocator: Allocator<D>,
{
    let [(t0, y0), (t1, y1)] = ends;
    if t == t0 || t == t1 {
        out.copy_from_slice(if t == t0 { y0 } else { y1 }.as_slice());
        return;
    }
    let th = (t - t0) / h;
    let [d1, d2, d3, d4, d5] = cont;
    let y0 = y0.as_slice();
    // The order-raising term's weight r(θ) = θ(1 - θ)²(1 - 5θ/2), and the tangency term's
    // q(θ) = θ(1 - θ/c1)³ on [0, c1], 0 beyond.
    let (r, q) = if corrected {
        let r = order_weight(th);
        let q = if th > 0.0 && th < C1 {
            th * (1.0 - th / C1).powi(3)
        } else {
            0.0
        };
        (r, q)
    } else {
        (0.0, 0.0)
    };
    for i in 0..out.len() {
        let cubic = th * (d1[i] + (th - C1) * (d2[i] + (th - C2) * d3[i]));
        out[i] = y0[i] + cubic + r * d4[i] + q * d5[i];
    }
}

/// The order-raising term's weight $r(\theta) = \theta(1 - \theta)^2(1 - \tfrac52\theta)$
/// (see `eval_poly`).
fn order_weight(th: f64) -> f64 {
    th * (1.0 - th) * (1.0 - th) * (1.0 - 2.5 * th)
}

/// An accepted step, as [`Radau5::accept`] books it.
struct StepEnd {
    /// The step taken.
    h_try: f64,
    /// The step that was asked for (`h_try` is shorter when clipped to a bound).
    h: f64,
    /// Its right end.
    t_new: f64,
    /// The suggested ratio $h_{\text{new}}/h$.
    ratio: f64,
    /// Its scaled error.
    err: f64,
    /// A rejection came before it: the next step may not grow.
    no_growth: bool,
    /// Clipped to the bound: the next step is at least `h`.
    clipped: bool,
}

/// What one attempt gave.
enum Attempt {
    /// Accepted with this step-size ratio suggestion $h_{\text{new}}/h$ and error.
    Accepted { ratio: f64, err: f64 },
    /// Rejected; retry with `h * factor`.
    Rejected { factor: f64, non_finite: bool },
}

impl<D: Dim> Radau5<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// One attempt of a step of size `h` (the new point is left in `core.y_new`).
    fn attempt<S: OdeSystem<D>>(&mut self, sys: &S, h: f64, reject_before: bool) -> Attempt {
        if !self.prepare_linear(sys, h) {
            return Attempt::Rejected {
                factor: 0.5,
                non_finite: false,
            };
        }
        self.update_scale();
        self.starting_values(h);
        let iters = match self.newton(sys, h) {
            Newton::Converged { iterations } => iterations,
            Newton::Failed { factor, non_finite } => {
                return Attempt::Rejected { factor, non_finite }
            }
        };
        if self.core.opts.fixed_step.is_some() {
            // No error control; the estimate (unrefined) only for the dense output's d4.
            self.estimate(sys, h, false);
            self.take_stages();
            return Attempt::Accepted {
                ratio: 1.0,
                err: 0.0,
            };
        }
        let err = self.estimate(sys, h, self.first || reject_before);
        if !err.is_finite() {
            return Attempt::Rejected {
                factor: self.core.opts.fac_min,
                non_finite: true,
            };
        }
        self.control(h, err, iters)
    }

    /// The simplified Newton iteration of a step of size `h` from the starting values in `z`.
    fn newton<S: OdeSystem<D>>(&mut self, sys: &S, h: f64) -> Newton {
        let Core {
            opts,
            n_ctrl,
            stats,
            t,
            y,
            ..
        } = &mut self.core;
        let inp = StepInput {
            t: *t,
            h,
            y,
            scal: &self.scal,
            n_ctrl: *n_ctrl,
            fnewt: self.fnewt,
            patient: opts.fixed_step.is_some(),
        };
        iterate(
            sys,
            &inp,
            &mut self.lin,
            &mut self.z,
            &mut self.w,
            &mut self.yt,
            &mut self.rate,
            stats,
        )
    }

    /// The scaled error of the converged step of size `h` ([`error_estimate`], refined once
    /// if `refine` and it is at least 1); the estimate's vector $e$ is left in `ft` for the
    /// dense output.
    fn estimate<S: OdeSystem<D>>(&mut self, sys: &S, h: f64, refine: bool) -> f64 {
        let Core {
            opts,
            n_ctrl,
            stats,
            t,
            y,
            f,
            f_new,
            ..
        } = &mut self.core;
        let inp = StepInput {
            t: *t,
            h,
            y,
            scal: &self.scal,
            n_ctrl: *n_ctrl,
            fnewt: self.fnewt,
            patient: opts.fixed_step.is_some(),
        };
        // f_new is scratch here; the new point's f is computed after acceptance.
        error_estimate(
            sys,
            &inp,
            f,
            &self.lin,
            &self.z,
            refine,
            &mut self.ft,
            f_new,
            &mut self.yt,
            stats,
        )
    }

    /// Accepts or rejects a step of size `h` with scaled error `err` after `iters` Newton
    /// iterations, with the step-size ratio or factor that follows (RADAU5's `FAC`, `QUOT`,
    /// and Gustafsson's predictive controller after an accepted step).
    fn control(&mut self, h: f64, err: f64, iters: usize) -> Attempt {
        let opts = &self.core.opts;
        let (safety, fac_min, fac_max) = (opts.safety, opts.fac_min, opts.fac_max);
        let fac = safety.min(safety * (1 + 2 * NIT) as f64 / (iters + 2 * NIT) as f64);
        let quot = (err.powf(0.25) / fac).clamp(1.0 / fac_max, 1.0 / fac_min);
        if err >= 1.0 {
            return Attempt::Rejected {
                factor: if self.first && !self.h_kept {
                    0.1
                } else {
                    1.0 / quot
                },
                non_finite: false,
            };
        }
        // Gustafsson's predictive controller (needs a previous accepted step).
        let mut quot = quot;
        if self.h_acc > 0.0 {
            let gus = (self.h_acc / h) * (err * err / self.err_acc).powf(0.25) / safety;
            quot = quot.max(gus.clamp(1.0 / fac_max, 1.0 / fac_min));
        }
        self.take_stages();
        Attempt::Accepted {
            ratio: 1.0 / quot,
            err,
        }
    }

    /// The new point $y + Z_3$ into `core.y_new`.
    fn take_stages(&mut self) {
        let Core { y, y_new, .. } = &mut self.core;
        for i in 0..y.len() {
            y_new[i] = y[i] + self.z[2][i];
        }
    }

    /// Retries until a step is accepted (see [`Integrator::step`]).
    fn step_loop<S: OdeSystem<D>>(&mut self, sys: &S, t_bound: f64) -> Result<(), OdeError> {
        let fixed = self.core.opts.fixed_step;
        let mut h = fixed.unwrap_or(self.core.h.min(self.core.opts.h_max));
        let mut reject_before = false;
        let mut non_finite = false;
        loop {
            let c = &mut self.core;
            if c.attempts >= c.opts.max_steps {
                return Err(OdeError::TooManySteps {
                    t: c.t,
                    h,
                    max_steps: c.opts.max_steps,
                });
            }
            let h_floor = c.opts.h_min.max(10.0 * f64::EPSILON * c.t.abs());
            if fixed.is_none() && (h < h_floor || h.is_nan()) {
                return Err(if non_finite {
                    OdeError::NonFiniteRhs { t: c.t, h }
                } else {
                    OdeError::StepSizeUnderflow {
                        t: c.t,
                        h,
                        h_min: h_floor,
                    }
                });
            }
            // Land exactly on the bound when it is within 1% beyond one step.
            let (h_try, t_new, clipped) = if c.t + 1.01 * h >= t_bound {
                (t_bound - c.t, t_bound, true)
            } else {
                (h, c.t + h, false)
            };
            c.attempts += 1;
            let mut outcome = self.attempt(sys, h_try, reject_before);
            if let Attempt::Accepted { .. } = outcome {
                let c = &mut self.core;
                sys.rhs(t_new, &c.y_new, &mut c.f_new);
                c.stats.rhs_evals += 1;
                if !all_finite(c.f_new.as_slice()) {
                    outcome = Attempt::Rejected {
                        factor: c.opts.fac_min,
                        non_finite: true,
                    };
                }
            }
            match outcome {
                Attempt::Accepted { ratio, err } => {
                    let ratio = if fixed.is_some() { 1.0 } else { ratio };
                    self.accept(StepEnd {
                        h_try,
                        h,
                        t_new,
                        ratio,
                        err,
                        no_growth: reject_before,
                        clipped,
                    });
                    return Ok(());
                }
                Attempt::Rejected {
                    factor,
                    non_finite: nf,
                } => {
                    let t = self.core.t;
                    if fixed.is_some() {
                        return Err(if nf {
                            OdeError::NonFiniteRhs { t, h: h_try }
                        } else {
                            OdeError::NewtonFailure { t, h: h_try }
                        });
                    }
                    self.reject();
                    (reject_before, non_finite) = (true, nf);
                    h = h_try * factor;
                }
            }
        }
    }

    /// The last step taken again from its left end to `t_new` (see [`Integrator::truncate`]);
    /// `false`, with the last step's polynomial and ends untouched, if that step fails.
    fn step_again<S: OdeSystem<D>>(&mut self, sys: &S, t_new: f64) -> bool {
        let c = &mut self.core;
        let h_keep = c.h;
        c.t = c.t_prev;
        c.y.copy_from(&c.y_prev);
        c.f.copy_from(&c.f_prev);
        let h = t_new - c.t;
        let (ratio, err) = match self.attempt(sys, h, false) {
            Attempt::Accepted { ratio, err } => (ratio, err),
            Attempt::Rejected { .. } => return false,
        };
        let c = &mut self.core;
        sys.rhs(t_new, &c.y_new, &mut c.f_new);
        c.stats.rhs_evals += 1;
        if !all_finite(c.f_new.as_slice()) {
            return false;
        }
        self.accept(StepEnd {
            h_try: h,
            h,
            t_new,
            ratio,
            err,
            no_growth: false,
            clipped: false,
        });
        self.core.h = h_keep;
        true
    }

    /// Bookkeeping of a rejected attempt: a Jacobian not computed at this point is redone.
    fn reject(&mut self) {
        self.core.stats.rejected += 1;
        if !self.jac_fresh {
            self.jac_ok = false;
        }
    }

    /// Moves to the accepted point `(t_new, core.y_new)` and sets the next step size.
    fn accept(&mut self, end: StepEnd) {
        let StepEnd {
            h_try,
            h,
            t_new,
            ratio,
            err,
            no_growth,
            clipped,
        } = end;
        self.h_acc = h_try;
        self.err_acc = err.max(1e-2);
        let keep_jac = self.rate.theta <= THETA_JAC;
        // Woodbury factors cost O(N): keep h only as for a small system.
        let keep_h = if self.lin.structured {
            KEEP_H_SMALL
        } else {
            self.keep_h
        };
        let mut h_next = if no_growth {
            h_try * ratio.min(1.0)
        } else if keep_jac && (keep_h.0..=keep_h.1).contains(&ratio) {
            h_try
        } else {
            h_try * ratio
        };
        if clipped {
            h_next = h_next.max(h);
        }
        if let Some(hf) = self.core.opts.fixed_step {
            h_next = hf;
        }
        self.jac_ok = keep_jac;
        self.jac_fresh = false;
        let restart = self.first;
        self.first = false;
        self.t_end = t_new;
        self.update_dense(h_try, restart);
        let h_next = h_next.min(self.core.opts.h_max);
        self.core.advance(t_new, h_try, h_next);
    }
}

impl<D: Dim> Integrator<D> for Radau5<D>
where
    DefaultAllocator: Allocator<D>,
{
    fn reset<S: OdeSystem<D>>(
        &mut self,
        sys: &S,
        t: f64,
        y: &OVector<f64, D>,
        keep_step: bool,
    ) -> Result<(), OdeError> {
        self.h_kept = keep_step && self.core.h > 0.0;
        self.core.reset(sys, t, y, keep_step)?;
        // A reset marks a discontinuity: a new Jacobian (the old one may filter the error
        // estimate with stiffness the new field lacks), zero starting values (the last
        // polynomial does not extrapolate across a jump), no error history for Gustafsson's
        // controller.
        self.first = true;
        self.jac_ok = false;
        self.jac_fresh = false;
        self.lu_h = 0.0;
        self.h_acc = 0.0;
        self.rate = Rate {
            theta: THETA_JAC,
            faccon: 1.0,
        };
        Ok(())
    }

    fn step<S: OdeSystem<D>>(&mut self, sys: &S, t_bound: f64) -> Result<(), OdeError> {
        if self.core.check_bound(t_bound)? {
            return Ok(());
        }
        self.step_loop(sys, t_bound)
    }

    fn dense<S: OdeSystem<D>>(&mut self, _sys: &S, t: f64, out: &mut OVector<f64, D>) {
        if !self.core.has_step {
            self.core.copy_state(out);
            return;
        }
        fit(out, self.core.dim);
        self.eval_dense(t, out.as_mut_slice());
    }

    /// Truncates by taking the step again, from $t_{\text{prev}}$ to exactly `t_new`: the
    /// dense output is of order 4 inside a step (of order 3 before issue 31, its error then
    /// that of the transformed tolerance $0.1\thinspace\mathrm{rtol}^{2/3}$), while a step's end
    /// has the method's order 5. A hybrid run truncates at every event, so the placed state must have the
    /// step's accuracy (100 jumps placed on the polynomial: 7.0e-7 off at rtol 1e-10;
    /// stepped again: 2.8e-10). Costs one Newton solve and two LU decompositions. Should that
    /// step fail (Newton diverges at the shorter step, non-finite values), the point is
    /// placed on the polynomial, as the explicit methods place it on their dense output.
    /// The step-size suggestion is kept; `dense` is then the new step's polynomial.
    fn truncate<S: OdeSystem<D>>(&mut self, sys: &S, t_new: f64) -> Result<(), OdeError> {
        self.core.check_truncate(t_new)?;
        if t_new == self.core.t {
            return Ok(());
        }
        if self.step_again(sys, t_new) {
            return Ok(());
        }
        let c = &mut self.core;
        let ends = [(c.t_prev, &c.y_prev), (self.t_end, &c.y_end)];
        eval_poly(
            &self.cont,
            c.h_dense,
            ends,
            t_new,
            true,
            c.y_new.as_mut_slice(),
        );
        c.apply_truncate(sys, t_new)
    }

    core_accessors!();

    fn name(&self) -> &'static str {
        "RADAU5"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// $r(0) = r(1) = 0$, $r^\prime(0) = 1$, $r^\prime(c_1) = r^\prime(c_2) = r^\prime(1) = 0$
    /// (by central differences), and $|r| \le 0.068$ on the step.
    #[test]
    fn order_weight_has_the_start_slope_alone() {
        let d = |t: f64| (order_weight(t + 1e-6) - order_weight(t - 1e-6)) / 2e-6;
        assert_eq!(order_weight(0.0), 0.0);
        assert_eq!(order_weight(1.0), 0.0);
        assert!((d(0.0) - 1.0).abs() < 1e-9);
        for c in [C1, C2, 1.0] {
            assert!(d(c).abs() < 1e-9, "r'({c}) = {}", d(c));
        }
        let max = (0..=1000)
            .map(|k| order_weight(k as f64 / 1000.0).abs())
            .fold(0.0, f64::max);
        assert!(max < 0.068 && max > 0.067, "{max}");
    }
}
