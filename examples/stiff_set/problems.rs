//! The five stiff problems of Hairer and Wanner, *Solving Ordinary Differential Equations II*
//! (Sect. IV.10), as the IVP test set of Mazzia et al. (University of Bari, release 2.4) states
//! them: right-hand sides, analytic Jacobians, end times, initial values and the published
//! reference end values, with the test set's measure of accuracy (`scd`).
//!
//! Shared by the example `stiff_set` (its `main.rs`) and the tests
//! (`tests/suite/ode/ode_stiff_set.rs`, which include this file with `#[path = ...] mod`).
//!
//! Sources (Fortran files of the test set, as stored in public repositories):
//! * VDPOL: `volpatto/pside`, `problems/VdPol/vdpol.f` (revision `vdpol.F,v 1.2`), `solut`;
//! * HIRES: `volpatto/pside`, `problems/HIRES/hires.f`, `solut`;
//! * ROBER, OREGO, E5: `liuqx315/Multiscale-pattern`,
//!   `sundials_extensions/regression/{rober,orego,e5}.f` (the test set's files, revisions
//!   `rober.F,v 1.2`, `orego.F,v 1.4`, `e5.F,v 1.3`; the right-hand sides `feval`, Jacobians
//!   `jeval` and `solut` are the originals, only split versions were added there);
//! * the scd: the test set's `report.f`, subroutine `getscd`;
//! * the usual absolute tolerances of ROBER and E5: Hairer's drivers of the book,
//!   `cpmech/hwode`, `tests/rob_radau5.f` (`ATOL=1.0D-6*RTOL`) and `tests/e5_radau5.f`
//!   (`ATOL=1.7D-24`).
//!
//! The Jacobians are methods (`jacobian_into`) so that the stiff integrator's optional
//! `OdeSystem::jacobian` can call them.
#![allow(dead_code)] // the example and the tests each use a part

use std::time::Instant;

use jeffcott::ode::{
    AnyIntegrator, Integrator, JacobianMut, Method, OdeError, OdeSystem, Options, Stats,
};
use nalgebra::{DVector, Dyn};

/// One problem of the set.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Problem {
    /// Van der Pol, $\varepsilon = 10^{-6}$, in the test set's scaled time:
    /// $y_1' = y_2$, $y_2' = ((1 - y_1^2) y_2 - y_1)/\varepsilon$, $y(0) = (2, 0)$, $t \in [0, 2]$.
    Vdpol,
    /// Robertson's chemical reaction, $t \in [0, 10^{11}]$.
    Rober,
    /// The Oregonator (Belousov–Zhabotinskii reaction), $t \in [0, 360]$.
    Orego,
    /// HIRES (plant physiology, 8 equations), $t \in [0, 321.8122]$.
    Hires,
    /// E5 (chemical pyrolysis, stiff DETEST), $t \in [0, 10^{13}]$.
    E5,
}

/// Van der Pol's $\varepsilon$ (vdpol.f: the division by `1.0d-6`).
const VDPOL_EPS: f64 = 1.0e-6;

/// E5's rate constants (e5.f: `A`, `B`, `CM`, `C`).
const E5_A: f64 = 7.89e-10;
const E5_B: f64 = 1.1e7;
const E5_CM: f64 = 1.13e9;
const E5_C: f64 = 1.13e3;

/// The test set's threshold below which a reference component has no relative error
/// (report.f, `getscd`: `min_value = 1.0d-200`).
pub const SCD_MIN_VALUE: f64 = 1.0e-200;

/// The scd of an exact result (report.f: a zero error counts as `uround = 1.D-16`).
pub const SCD_EXACT: f64 = 16.0;

impl Problem {
    /// The five problems in the book's order.
    pub const ALL: [Problem; 5] = [
        Problem::Vdpol,
        Problem::Rober,
        Problem::Orego,
        Problem::Hires,
        Problem::E5,
    ];

    /// The test set's name, upper case (`"HIRES"`).
    pub fn name(self) -> &'static str {
        match self {
            Problem::Vdpol => "VDPOL",
            Problem::Rober => "ROBER",
            Problem::Orego => "OREGO",
            Problem::Hires => "HIRES",
            Problem::E5 => "E5",
        }
    }

    /// The problem of a name, in any case.
    pub fn from_name(name: &str) -> Option<Problem> {
        Problem::ALL
            .into_iter()
            .find(|p| p.name().eq_ignore_ascii_case(name))
    }

    /// Number of equations.
    pub fn dim(self) -> usize {
        match self {
            Problem::Vdpol => 2,
            Problem::Rober | Problem::Orego => 3,
            Problem::Hires => 8,
            Problem::E5 => 4,
        }
    }

    /// End of the integration interval (the test set's `prob`: `t(1)`); it starts at 0.
    pub fn t_end(self) -> f64 {
        match self {
            Problem::Vdpol => 2.0,
            Problem::Rober => 1.0e11,
            Problem::Orego => 360.0,
            Problem::Hires => 321.8122,
            Problem::E5 => 1.0e13,
        }
    }

    /// Initial values (the test set's `init`).
    pub fn y0(self) -> DVector<f64> {
        DVector::from_column_slice(match self {
            Problem::Vdpol => &[2.0, 0.0],
            Problem::Rober => &[1.0, 0.0, 0.0],
            Problem::Orego => &[1.0, 2.0, 3.0],
            Problem::Hires => &[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0057],
            Problem::E5 => &[1.76e-3, 0.0, 0.0, 0.0],
        })
    }

    /// The published reference solution at [`Problem::t_end`] (the test set's `solut`,
    /// computed by its authors with RADAU/RADAU5 at `rtol = 1.1d-18` in extended precision;
    /// files in the module header). Never computed with this crate. The digits are the
    /// published ones, even where f64 cannot hold them all.
    #[allow(clippy::excessive_precision)]
    pub fn reference(self) -> &'static [f64] {
        match self {
            // vdpol.f, solut.
            Problem::Vdpol => &[0.1706167732170483e1, -0.8928097010247975e0],
            // rober.f, solut.
            Problem::Rober => &[
                0.2083340149701255e-7,
                0.8333360770334713e-13,
                0.9999999791665050e0,
            ],
            // orego.f, solut.
            Problem::Orego => &[
                0.1000814870318523e1,
                0.1228178521549917e4,
                0.1320554942846706e3,
            ],
            // hires.f, solut.
            Problem::Hires => &[
                0.7371312573325668e-3,
                0.1442485726316185e-3,
                0.5888729740967575e-4,
                0.1175651343283149e-2,
                0.2386356198831331e-2,
                0.6238968252742796e-2,
                0.2849998395185769e-2,
                0.2850001604814231e-2,
            ],
            // e5.f, solut. Doubtful at the 1e-3 level: $y_2 - y_3 - y_4$ is a linear invariant
            // ($f_3 = f_2 - f_4$), 0 at the start, and $y_4 = 0$ here, yet $y_2$ and $y_3$ differ
            // by 1.45e-3 relative. A method that keeps linear invariants (every Runge-Kutta
            // method) cannot have both within 7e-4 of these values: its relative scd on E5 is
            // at most about 3.1.
            Problem::E5 => &[
                0.1152903278711829e-290,
                0.8867655517642120e-22,
                0.8854814626268838e-22,
                0.0,
            ],
        }
    }

    /// The usual absolute tolerance for a relative tolerance `rtol`: `rtol` itself, except
    /// ROBER ($10^{-6}\thinspace\mathrm{rtol}$) and E5 ($1.7 \cdot 10^{-24}$), as in Hairer's drivers
    /// (which give HIRES $10^{-4}\thinspace\mathrm{rtol}$ and OREGO $10^{-6}\thinspace\mathrm{rtol}$;
    /// issue 19 asks for atol = rtol there).
    pub fn usual_atol(self, rtol: f64) -> f64 {
        match self {
            Problem::Rober => 1.0e-6 * rtol,
            Problem::E5 => 1.7e-24,
            _ => rtol,
        }
    }

    /// Writes $f(t, y)$ into `dy` (the test set's `feval`).
    pub fn rhs_into(self, y: &[f64], dy: &mut [f64]) {
        match self {
            Problem::Vdpol => {
                dy[0] = y[1];
                dy[1] = ((1.0 - y[0] * y[0]) * y[1] - y[0]) / VDPOL_EPS;
            }
            Problem::Rober => {
                dy[0] = -0.04 * y[0] + 1.0e4 * y[1] * y[2];
                dy[1] = 0.04 * y[0] - 1.0e4 * y[1] * y[2] - 3.0e7 * y[1] * y[1];
                dy[2] = 3.0e7 * y[1] * y[1];
            }
            Problem::Orego => {
                dy[0] = 77.27 * (y[1] + y[0] * (1.0 - 8.375e-6 * y[0] - y[1]));
                dy[1] = (y[2] - (1.0 + y[0]) * y[1]) / 77.27;
                dy[2] = 0.161 * (y[0] - y[2]);
            }
            Problem::Hires => hires_rhs(y, dy),
            Problem::E5 => {
                let prod1 = E5_A * y[0];
                let prod2 = E5_B * y[0] * y[2];
                let prod3 = E5_CM * y[1] * y[2];
                let prod4 = E5_C * y[3];
                dy[0] = -prod1 - prod2;
                dy[1] = prod1 - prod3;
                dy[3] = prod2 - prod4;
                dy[2] = dy[1] - dy[3];
            }
        }
    }

    /// Writes the Jacobian $\partial f / \partial y$ at $(t, y)$ into `jac` (the test set's
    /// `jeval`; the problems are autonomous). `jac` must be `dim x dim`.
    pub fn jacobian_into(&self, _t: f64, y: &DVector<f64>, jac: &mut JacobianMut<'_, Dyn>) {
        jac.fill(0.0);
        match self {
            Problem::Vdpol => {
                jac[(0, 1)] = 1.0;
                jac[(1, 0)] = (-2.0 * y[0] * y[1] - 1.0) / VDPOL_EPS;
                jac[(1, 1)] = (1.0 - y[0] * y[0]) / VDPOL_EPS;
            }
            Problem::Rober => {
                jac[(0, 0)] = -0.04;
                jac[(0, 1)] = 1.0e4 * y[2];
                jac[(0, 2)] = 1.0e4 * y[1];
                jac[(1, 0)] = 0.04;
                jac[(1, 1)] = -1.0e4 * y[2] - 6.0e7 * y[1];
                jac[(1, 2)] = -1.0e4 * y[1];
                jac[(2, 1)] = 6.0e7 * y[1];
            }
            Problem::Orego => {
                jac[(0, 0)] = 77.27 * (1.0 - 2.0 * 8.375e-6 * y[0] - y[1]);
                jac[(0, 1)] = 77.27 * (1.0 - y[0]);
                jac[(1, 0)] = -y[1] / 77.27;
                jac[(1, 1)] = -(1.0 + y[0]) / 77.27;
                jac[(1, 2)] = 1.0 / 77.27;
                jac[(2, 0)] = 0.161;
                jac[(2, 2)] = -0.161;
            }
            Problem::Hires => hires_jacobian(y, jac),
            Problem::E5 => {
                jac[(0, 0)] = -E5_A - E5_B * y[2];
                jac[(0, 2)] = -E5_B * y[0];
                jac[(1, 0)] = E5_A;
                jac[(1, 1)] = -E5_CM * y[2];
                jac[(1, 2)] = -E5_CM * y[1];
                jac[(2, 0)] = E5_A - E5_B * y[2];
                jac[(2, 1)] = -E5_CM * y[2];
                jac[(2, 2)] = -E5_B * y[0] - E5_CM * y[1];
                jac[(2, 3)] = E5_C;
                jac[(3, 0)] = E5_B * y[2];
                jac[(3, 2)] = E5_B * y[0];
                jac[(3, 3)] = -E5_C;
            }
        }
    }
}

impl OdeSystem<Dyn> for Problem {
    fn rhs(&self, _t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        self.rhs_into(y.as_slice(), dy.as_mut_slice());
    }
    fn jacobian(&self, t: f64, y: &DVector<f64>, jac: &mut JacobianMut<'_, Dyn>) -> bool {
        self.jacobian_into(t, y, jac);
        true
    }
}

/// HIRES's right-hand side (hires.f, `feval`, the rate constants written out).
fn hires_rhs(y: &[f64], dy: &mut [f64]) {
    dy[0] = -1.71 * y[0] + 0.43 * y[1] + 8.32 * y[2] + 0.0007;
    dy[1] = 1.71 * y[0] - 8.75 * y[1];
    dy[2] = -10.03 * y[2] + 0.43 * y[3] + 0.035 * y[4];
    dy[3] = 8.32 * y[1] + 1.71 * y[2] - 1.12 * y[3];
    dy[4] = -1.745 * y[4] + 0.43 * y[5] + 0.43 * y[6];
    dy[5] = -280.0 * y[5] * y[7] + 0.69 * y[3] + 1.71 * y[4] - 0.43 * y[5] + 0.69 * y[6];
    dy[6] = 280.0 * y[5] * y[7] - 1.81 * y[6];
    dy[7] = -dy[6];
}

/// HIRES's Jacobian (hires.f, `jeval`).
fn hires_jacobian(y: &DVector<f64>, jac: &mut JacobianMut<'_, Dyn>) {
    let entries = [
        (0, 0, -1.71),
        (0, 1, 0.43),
        (0, 2, 8.32),
        (1, 0, 1.71),
        (1, 1, -8.75),
        (2, 2, -10.03),
        (2, 3, 0.43),
        (2, 4, 0.035),
        (3, 1, 8.32),
        (3, 2, 1.71),
        (3, 3, -1.12),
        (4, 4, -1.745),
        (4, 5, 0.43),
        (4, 6, 0.43),
        (5, 3, 0.69),
        (5, 4, 1.71),
        (5, 5, -280.0 * y[7] - 0.43),
        (5, 6, 0.69),
        (5, 7, -280.0 * y[5]),
        (6, 5, 280.0 * y[7]),
        (6, 6, -1.81),
        (6, 7, 280.0 * y[5]),
        (7, 5, -280.0 * y[7]),
        (7, 6, 1.81),
        (7, 7, -280.0 * y[5]),
    ];
    for (i, j, v) in entries {
        jac[(i, j)] = v;
    }
}

/// The test set's scd (significant correct digits, report.f `getscd`, relative error):
/// $\mathrm{scd} = -\log_{10} \max_i |y_i - r_i| / |r_i|$ over the components with
/// $|r_i| \ge 10^{-200}$ (the others, E5's $y_1 \approx 10^{-290}$ and $y_4 = 0$, have no
/// relative error); an exact result counts as [`SCD_EXACT`]. A non-finite `y` gives `-inf`.
pub fn scd(y: &[f64], reference: &[f64]) -> f64 {
    let mut worst = 0.0_f64;
    for (&yi, &ri) in y.iter().zip(reference) {
        if !yi.is_finite() {
            return f64::NEG_INFINITY;
        }
        if ri.abs() >= SCD_MIN_VALUE {
            worst = worst.max(((yi - ri) / ri).abs());
        }
    }
    if worst == 0.0 {
        SCD_EXACT
    } else {
        -worst.log10()
    }
}

/// The test set's mixed-error scd (report.f `getscd`, `mescd`):
/// $-\log_{10} \max_i |y_i - r_i| / (\mathrm{atol}/\mathrm{rtol} + |r_i|)$ over every
/// component, the measure that the tolerances control.
pub fn mescd(y: &[f64], reference: &[f64], rtol: f64, atol: f64) -> f64 {
    let mut worst = 0.0_f64;
    for (&yi, &ri) in y.iter().zip(reference) {
        if !yi.is_finite() {
            return f64::NEG_INFINITY;
        }
        worst = worst.max(((yi - ri) / (atol / rtol + ri.abs())).abs());
    }
    if worst == 0.0 {
        SCD_EXACT
    } else {
        -worst.log10()
    }
}

/// The outcome of one integration of a problem over its whole interval.
#[derive(Debug, Clone)]
pub struct Run {
    /// The problem.
    pub problem: Problem,
    /// The state at [`Problem::t_end`].
    pub y: DVector<f64>,
    /// The integrator's work counters.
    pub stats: Stats,
    /// Wall-clock time of the integration (construction excluded), seconds.
    pub seconds: f64,
}

impl Run {
    /// The test set's scd of this run ([`scd`]).
    pub fn scd(&self) -> f64 {
        scd(self.y.as_slice(), self.problem.reference())
    }
}

/// Integrates `problem` over $[0, t_{\text{end}}]$ with `method` at the scalar tolerances,
/// stepping to the end (no output points), at most `max_steps` step attempts.
pub fn run(
    problem: Problem,
    method: Method,
    rtol: f64,
    atol: f64,
    max_steps: u64,
) -> Result<Run, OdeError> {
    let opts = Options::with_tol(rtol, atol).with_max_steps(max_steps);
    let mut integ = AnyIntegrator::with_dim(method, Dyn(problem.dim()), opts)?;
    let t_end = problem.t_end();
    let start = Instant::now();
    integ.reset(&problem, 0.0, &problem.y0(), false)?;
    while integ.t() < t_end {
        integ.step(&problem, t_end)?;
    }
    Ok(Run {
        problem,
        y: integ.y().clone(),
        stats: *integ.stats(),
        seconds: start.elapsed().as_secs_f64(),
    })
}
