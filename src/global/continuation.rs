//! Continuation of periodic orbits in any scalar parameter: pseudo-arclength through folds,
//! stability along the branch, bifurcations located, branch switching at a flip, and grazing
//! (a contact gained or lost) detected, located and passed.
//!
//! # The method
//!
//! A period-$n$ orbit is a zero of $F(z, p) = P^n_p(z) - z$, $z$ the non-algebraic components at
//! the section $\tau = 0$ (the rotor's $(x, y, x^\prime, y^\prime)$ for the paper's model) and
//! $p$ the parameter, the model being built at each $p$ by a closure. The branch is followed in
//! its arclength $s$ (pseudo-arclength): from a point $u_k = (z_k, p_k)$ with unit tangent
//! $t_k$ (the null vector of $[F_z\ F_p]$, oriented along the last one), the predictor
//! $u_k + \Delta s\thinspace t_k$ is corrected by Newton's method on
//!
//! $$F(u) = 0,\qquad t_k\cdot(u - u_k - \Delta s\thinspace t_k) = 0,$$
//!
//! which stays regular at a fold, where $p$ turns back. $F_z = DP^n - I$ is the Jacobian of the
//! variational equations through every event ([`StroboscopicMap`]); $F_p$ is a central
//! difference in $p$ (step $h = $ [`ContinuationConfig::param_step`] $\cdot(1 + |p|)$). The step
//! grows by 1.5 after an easy correction (at most 3 iterations) up to
//! [`ContinuationConfig::ds_max`] and halves after a failed one (a correction that does not
//! converge, or one larger than the step: Newton jumped to another branch); the branch ends if
//! it falls below [`ContinuationConfig::ds_min`].
//!
//! # Special points
//!
//! At every point the multipliers (eigenvalues of $DP^n$) are counted outside the unit circle
//! in three classes, real positive, real negative and complex, and the orbit's **event
//! structure** (the guards crossed over one orbit, compared up to a rotation) is recorded.
//! Between two points:
//!
//! * a change of the real positive count is a **fold**, of the real negative count a **flip**
//!   (period doubling), of the complex count a **Neimark–Sacker** bifurcation;
//! * a change of the event structure is a **grazing**: a contact (or a regime boundary inside
//!   a contact) appears or disappears, the margin of that event passing through zero. The
//!   multipliers do not announce it (they jump there, the map being only continuous), and the
//!   continuation goes on through it.
//!
//! Each is located by bisection along the secant between the two points (a corrected point on
//! the hyperplane through the midpoint, normal to the secant) until the bracket is narrower
//! than [`ContinuationConfig::locate`] in every component of $(z, p)$; the value reported is
//! the bracket's midpoint, with the multipliers at its near end. If the bisection stops short
//! (no corrected point or no orbit at a midpoint), the point is returned as detected but not
//! located: [`SpecialPoint::converged`] is `false`, with the reason and the bracket reached.
//!
//! **Branch switching** ([`switch_at_flip`]): at a flip of the period-$n$ orbit the period-$2n$
//! orbit branches off along the eigenvector $v$ of the multiplier $-1$. Its first point is
//! corrected on the hyperplane $v\cdot(z - z^{\ast}) = a$ (with $p$ free) for amplitudes $a$
//! from $10^{-3}$ up, until a point of minimal period $2n$ is found; its branch is then
//! continued as any other.

use nalgebra::{DMatrix, DVector, DefaultAllocator, OVector};
use thiserror::Error;

use crate::hybrid::{SimOptions, Variational, VariationalAlloc};
use crate::stability::{multipliers, Multiplier, StroboscopicMap, GRAZING_MARGIN};

/// Settings of [`continue_orbit`] and [`switch_at_flip`]. A plain struct with `Default`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContinuationConfig {
    /// First arclength step (in the max norm of $(z, p)$ units). Default 0.01.
    pub ds: f64,
    /// Smallest step: below it the branch ends ([`BranchEnd::Stalled`]). Default `1e-7`.
    pub ds_min: f64,
    /// Largest step. Default 0.02.
    pub ds_max: f64,
    /// Largest number of points on a branch. Default 5000.
    pub max_points: usize,
    /// Corrector convergence: $\lVert F\rVert_\infty$ at most this. Default `1e-10` (above the
    /// map's noise, a few `1e-15`, and the parameter difference's rounding).
    pub tolerance: f64,
    /// Largest number of corrector iterations per point. Default 8.
    pub max_iterations: u32,
    /// Width of the bracket of a located special point, in every component of $(z, p)$.
    /// Default `1e-8`.
    pub locate: f64,
    /// Relative step of the central difference $F_p$. Default `1e-6`.
    pub param_step: f64,
    /// Simulation options of every run. Default: [`SimOptions::default`].
    pub sim: SimOptions,
    /// The guard label of a contact onset, to count contacts per orbit. Default
    /// `"contact onset"` ([`crate::paper::guard::ONSET`]).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::serde_util::label")
    )]
    pub onset_label: crate::StaticStr,
}

impl Default for ContinuationConfig {
    fn default() -> Self {
        ContinuationConfig {
            ds: 0.01,
            ds_min: 1e-7,
            ds_max: 0.02,
            max_points: 5000,
            tolerance: 1e-10,
            max_iterations: 8,
            locate: 1e-8,
            param_step: 1e-6,
            sim: SimOptions::default(),
            onset_label: crate::paper::guard::ONSET,
        }
    }
}

/// Why a continuation could not start.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum ContinuationError {
    /// A setting is out of range.
    #[error("invalid {field} = {value}: {hint}")]
    InvalidOption {
        /// The setting.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What to use.
        hint: &'static str,
    },
    /// No orbit of this period near the guess at the start: the corrector did not converge.
    #[error("no period-{period} orbit near the guess at parameter {param}: {reason}; try a longer transient, another period or a better guess")]
    NoStart {
        /// The period.
        period: u64,
        /// The parameter.
        param: f64,
        /// Why.
        reason: String,
    },
    /// Branch switching found no orbit of the doubled period next to the flip.
    #[error("no period-{period} orbit branches off the flip at {param}: {reason}")]
    NoSwitch {
        /// The doubled period.
        period: u64,
        /// The flip's parameter.
        param: f64,
        /// Why.
        reason: String,
    },
}

/// What a special point is (see the [module docs](self)).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum SpecialKind {
    /// A real multiplier through $+1$: the branch turns back (saddle-node).
    Fold,
    /// A real multiplier through $-1$: period doubling.
    Flip,
    /// A complex pair through the unit circle.
    NeimarkSacker,
    /// The event structure changes: a contact (or a regime boundary in contact) appears or
    /// disappears.
    Grazing,
}

impl SpecialKind {
    /// `"fold"`, `"flip"`, `"neimark-sacker"` or `"grazing"`.
    pub fn name(self) -> &'static str {
        match self {
            SpecialKind::Fold => "fold",
            SpecialKind::Flip => "flip",
            SpecialKind::NeimarkSacker => "neimark-sacker",
            SpecialKind::Grazing => "grazing",
        }
    }
}

/// One point of a branch.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BranchPoint {
    /// The parameter.
    pub param: f64,
    /// The periodic point $z$ at the section.
    pub point: Vec<f64>,
    /// The full state at the section.
    pub state: Vec<f64>,
    /// The orbit's $n$ points at the sections $\tau = 0, T, \dots$: $z, P(z), \dots$ (full
    /// states), for drawing.
    pub cycle: Vec<Vec<f64>>,
    /// The multipliers, largest modulus first.
    pub multipliers: Vec<Multiplier>,
    /// Whether every multiplier is inside the unit circle.
    pub stable: bool,
    /// The smallest crossing margin of the orbit's events (1 without events:
    /// [`crate::stability::LinearEvent::margin`]).
    pub min_margin: f64,
    /// Whether an event is crossed at a margin below [`GRAZING_MARGIN`]: the map is not
    /// differentiable at the orbit, and its multipliers are those of one side of it
    /// ([`crate::stability::PeriodicOrbit::grazing`]).
    pub grazing: bool,
    /// Contact onsets per orbit.
    pub contacts: usize,
    /// The guards crossed over one orbit, in order from the section.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::serde_util::labels")
    )]
    pub structure: Vec<&'static str>,
    /// Arclength from the branch's first point.
    pub arclength: f64,
}

/// A special point of a branch, located when its bracket converged.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpecialPoint {
    /// What it is.
    pub kind: SpecialKind,
    /// The parameter (the final bracket's midpoint): where the point is only if
    /// [`converged`](Self::converged); otherwise somewhere in the bracket.
    pub param: f64,
    /// The final bracket's parameters (near end, far end).
    pub bracket: (f64, f64),
    /// Whether the bisection narrowed the bracket to [`ContinuationConfig::locate`] in every
    /// component of $(z, p)$. `false`: the point was detected between two points but not
    /// located (`unconverged` says why); read [`bracket`](Self::bracket), not `param`.
    pub converged: bool,
    /// Why the bisection stopped before the bracket converged (a corrector or orbit failure
    /// at a midpoint, or the iteration limit); `None` when it converged.
    pub unconverged: Option<String>,
    /// The periodic point at the near end.
    pub point: Vec<f64>,
    /// The full state at the near end.
    pub state: Vec<f64>,
    /// The multipliers at the near end.
    pub multipliers: Vec<Multiplier>,
    /// Whether the orbit at the near end has a grazing event ([`BranchPoint::grazing`]): at a
    /// grazing it usually has, and its multipliers are those of one side.
    pub grazing: bool,
    /// Contacts per orbit before and after.
    pub contacts: (usize, usize),
    /// Event structure before and after.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::serde_util::label_pair")
    )]
    pub structure: (Vec<&'static str>, Vec<&'static str>),
    /// For a flip: the eigenvector of the multiplier $-1$ (unit, on $z$).
    pub eigenvector: Option<Vec<f64>>,
    /// Index in [`Branch::points`] of the point before it.
    pub after_point: usize,
}

/// How a branch ended.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum BranchEnd {
    /// The parameter left the range asked for.
    Reached,
    /// [`ContinuationConfig::max_points`] points.
    MaxPoints,
    /// The step fell below [`ContinuationConfig::ds_min`]: the corrector cannot go on (a
    /// non-smooth point it cannot pass, or the end of the branch).
    Stalled {
        /// The last parameter reached.
        param: f64,
        /// The last corrector failure.
        reason: String,
    },
}

/// A continued branch of period-`period` orbits.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Branch {
    /// The period in forcing periods.
    pub period: u64,
    /// The points, in order of arclength.
    pub points: Vec<BranchPoint>,
    /// The special points, in order of arclength.
    pub specials: Vec<SpecialPoint>,
    /// How it ended.
    pub end: BranchEnd,
}

/// $F$ and its derivatives at one $(z, p)$.
struct Eval<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    f: DVector<f64>,
    jac: DMatrix<f64>,
    fp: DVector<f64>,
    state: OVector<f64, D>,
    structure: Vec<&'static str>,
    min_margin: f64,
}

/// The bordered Jacobian of the continuation at `e`: $\begin{pmatrix} DP^n - I & \partial_p P^n
/// \\ \text{row} \end{pmatrix}$, the last row being the constraint's normal (corrector) or the
/// previous tangent (tangent).
fn bordered<D: nalgebra::Dim>(e: &Eval<D>, row: &DVector<f64>) -> DMatrix<f64>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    let k = e.f.len();
    let mut a = DMatrix::<f64>::zeros(k + 1, k + 1);
    for i in 0..k {
        for j in 0..k {
            a[(i, j)] = e.jac[(i, j)] - if i == j { 1.0 } else { 0.0 };
        }
        a[(i, k)] = e.fp[i];
    }
    for j in 0..=k {
        a[(k, j)] = row[j];
    }
    a
}

/// A corrected point.
struct Solved<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    u: DVector<f64>,
    eval: Eval<D>,
    iterations: u32,
}

/// Multipliers outside the unit circle: (real positive, real negative, complex).
type Counts = (usize, usize, usize);

fn counts(m: &[Multiplier]) -> Counts {
    let mut c = (0, 0, 0);
    for x in m.iter().filter(|x| x.modulus() > 1.0) {
        if x.is_real(1e-7) {
            if x.re > 0.0 {
                c.0 += 1;
            } else {
                c.1 += 1;
            }
        } else {
            c.2 += 1;
        }
    }
    c
}

/// The structure up to a rotation: its least rotation in lexical order.
fn canonical(s: &[&'static str]) -> Vec<&'static str> {
    (0..s.len().max(1))
        .map(|r| {
            let mut v = s.to_vec();
            v.rotate_left(r.min(s.len()));
            v
        })
        .min()
        .unwrap_or_default()
}

struct Solver<'a, B> {
    build: &'a B,
    period: u64,
    config: &'a ContinuationConfig,
}

impl<B, M, E> Solver<'_, B>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    fn model(&self, p: f64) -> Result<M, String> {
        (self.build)(p).map_err(|e| format!("no model at {p}: {e}"))
    }

    /// $F$, $DP^n$, $F_p$ at `u = (z, p)`, the algebraic components placed from `template`.
    fn eval(
        &self,
        u: &DVector<f64>,
        template: &OVector<f64, M::Dim>,
    ) -> Result<Eval<M::Dim>, String> {
        let k = u.len() - 1;
        let p = u[k];
        let z = u.rows(0, k).into_owned();
        let model = self.model(p)?;
        let map = StroboscopicMap::new(&model, self.period, self.config.sim)
            .map_err(|e| e.to_string())?;
        let state = map.state(template, &z);
        let lin = map.linearize(&state).map_err(|e| e.to_string())?;
        let h = self.config.param_step * (1.0 + p.abs());
        let mut ends = Vec::with_capacity(2);
        for q in [p + h, p - h] {
            let m = self.model(q)?;
            let mq = StroboscopicMap::new(&m, self.period, self.config.sim)
                .map_err(|e| e.to_string())?;
            let y = mq.state(template, &z);
            ends.push(mq.reduce(&mq.advance(&y).map_err(|e| e.to_string())?.y));
        }
        let fp = (&ends[0] - &ends[1]) / (2.0 * h);
        let min_margin = lin.min_margin();
        Ok(Eval {
            f: &lin.value - &z,
            jac: lin.jacobian,
            fp,
            state,
            structure: lin.events.iter().map(|e| e.kind).collect(),
            min_margin,
        })
    }

    /// Newton on $F(u) = 0$, $n\cdot(u - c) = 0$ from `start`.
    fn correct(
        &self,
        start: &DVector<f64>,
        normal: &DVector<f64>,
        c: &DVector<f64>,
        template: &OVector<f64, M::Dim>,
    ) -> Result<Solved<M::Dim>, String> {
        let k = start.len() - 1;
        let mut u = start.clone();
        let mut reason = String::from("no iteration");
        for it in 0..=self.config.max_iterations {
            let e = self.eval(&u, template)?;
            let res = e.f.amax();
            if !res.is_finite() {
                return Err("non-finite residual".into());
            }
            let constraint = normal.dot(&(&u - c));
            if res <= self.config.tolerance && constraint.abs() <= 1e3 * self.config.tolerance {
                return Ok(Solved {
                    u,
                    eval: e,
                    iterations: it,
                });
            }
            if it == self.config.max_iterations {
                reason = format!("residual {res:e} after {it} iterations");
                break;
            }
            let a = bordered(&e, normal);
            let mut r = DVector::<f64>::zeros(k + 1);
            for i in 0..k {
                r[i] = -e.f[i];
            }
            r[k] = -constraint;
            let Some(du) = a.lu().solve(&r) else {
                return Err("singular corrector matrix".into());
            };
            u += du;
        }
        Err(reason)
    }

    /// The unit tangent at a solved point, oriented along `prev`.
    fn tangent(&self, e: &Eval<M::Dim>, prev: &DVector<f64>) -> DVector<f64> {
        let k = e.f.len();
        let a = bordered(e, prev);
        let mut rhs = DVector::<f64>::zeros(k + 1);
        rhs[k] = 1.0;
        match a.lu().solve(&rhs) {
            Some(t) if t.norm() > 0.0 && t.iter().all(|v| v.is_finite()) => {
                let t = t.normalize();
                if t.dot(prev) < 0.0 {
                    -t
                } else {
                    t
                }
            }
            _ => prev.clone(),
        }
    }

    /// The branch point of a solved point.
    fn point(&self, s: &Solved<M::Dim>, arclength: f64) -> Result<BranchPoint, String> {
        let k = s.u.len() - 1;
        let p = s.u[k];
        let m = multipliers(&s.eval.jac).map_err(|e| e.to_string())?;
        let model = self.model(p)?;
        let one = StroboscopicMap::new(&model, 1, self.config.sim).map_err(|e| e.to_string())?;
        let mut cycle = vec![s.eval.state.iter().copied().collect::<Vec<f64>>()];
        let mut y = s.eval.state.clone();
        for _ in 1..self.period {
            y = one.advance(&y).map_err(|e| e.to_string())?.y;
            cycle.push(y.iter().copied().collect());
        }
        let onset = self.config.onset_label;
        Ok(BranchPoint {
            param: p,
            point: s.u.rows(0, k).iter().copied().collect(),
            state: s.eval.state.iter().copied().collect(),
            cycle,
            stable: m.iter().all(|x| x.modulus() < 1.0),
            min_margin: s.eval.min_margin,
            grazing: s.eval.min_margin < GRAZING_MARGIN,
            contacts: s.eval.structure.iter().filter(|&&l| l == onset).count(),
            structure: s.eval.structure.clone(),
            multipliers: m,
            arclength,
        })
    }
}

/// The unit eigenvector of `jac` for its eigenvalue closest to $-1$ (the right singular
/// vector of $J + I$ with the smallest singular value).
fn flip_vector(jac: &DMatrix<f64>) -> Option<Vec<f64>> {
    let k = jac.nrows();
    let a = jac + DMatrix::<f64>::identity(k, k);
    let svd = a.svd(false, true);
    let v_t = svd.v_t?;
    let (i, _) = svd
        .singular_values
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))?;
    let v: Vec<f64> = v_t.row(i).iter().copied().collect();
    Some(v)
}

fn check(config: &ContinuationConfig) -> Result<(), ContinuationError> {
    let positive = |field, v: f64, hint| {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(ContinuationError::InvalidOption {
                field,
                value: v,
                hint,
            })
        }
    };
    positive("ds", config.ds, "a finite step > 0, e.g. 0.01")?;
    positive("ds_min", config.ds_min, "a finite step > 0, e.g. 1e-7")?;
    positive("ds_max", config.ds_max, "a finite step > 0, e.g. 0.02")?;
    positive(
        "tolerance",
        config.tolerance,
        "above the map's noise, e.g. 1e-10",
    )?;
    positive("locate", config.locate, "a bracket width > 0, e.g. 1e-8")?;
    positive(
        "param_step",
        config.param_step,
        "a relative step > 0, e.g. 1e-6",
    )?;
    if config.ds_min > config.ds_max || config.ds > config.ds_max {
        return Err(ContinuationError::InvalidOption {
            field: "ds_max",
            value: config.ds_max,
            hint: "ds_min <= ds <= ds_max",
        });
    }
    Ok(())
}

/// Follows the branch from the solved point `first` (tangent initialised along `dir` in $p$),
/// while the parameter stays in `range`.
fn follow<B, M, E>(
    solver: &Solver<'_, B>,
    first: Solved<M::Dim>,
    dir: f64,
    range: (f64, f64),
) -> Branch
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let config = solver.config;
    let k = first.u.len() - 1;
    let mut prev_t = DVector::<f64>::zeros(k + 1);
    prev_t[k] = dir;
    let mut t = solver.tangent(&first.eval, &prev_t);
    let mut points = Vec::new();
    let mut specials = Vec::new();
    let mut cur = first;
    let mut arclength = 0.0;
    match solver.point(&cur, 0.0) {
        Ok(p) => points.push(p),
        Err(reason) => {
            return Branch {
                period: solver.period,
                points,
                specials,
                end: BranchEnd::Stalled {
                    param: cur.u[k],
                    reason,
                },
            }
        }
    }
    let mut ds = config.ds;
    let end = loop {
        if points.len() >= config.max_points {
            break BranchEnd::MaxPoints;
        }
        let pred = &cur.u + &t * ds;
        let solved = solver
            .correct(&pred, &t, &pred, &cur.eval.state)
            .and_then(|s| {
                let jump = (&s.u - &pred).amax();
                if jump > ds.max(10.0 * config.tolerance) {
                    Err(format!(
                        "the correction ({jump:e}) exceeds the step: another branch"
                    ))
                } else {
                    Ok(s)
                }
            });
        let next = match solved {
            Ok(s) => s,
            Err(reason) => {
                ds *= 0.5;
                if ds < config.ds_min {
                    break BranchEnd::Stalled {
                        param: cur.u[k],
                        reason,
                    };
                }
                continue;
            }
        };
        arclength += (&next.u - &cur.u).norm();
        let point = match solver.point(&next, arclength) {
            Ok(p) => p,
            Err(reason) => {
                break BranchEnd::Stalled {
                    param: next.u[k],
                    reason,
                }
            }
        };
        let last = points.len() - 1;
        let before: &BranchPoint = &points[last];
        let (ca, cb) = (counts(&before.multipliers), counts(&point.multipliers));
        let mut found = Vec::new();
        for (kind, a, b) in [
            (SpecialKind::Fold, ca.0, cb.0),
            (SpecialKind::Flip, ca.1, cb.1),
            (SpecialKind::NeimarkSacker, ca.2, cb.2),
        ] {
            if a != b {
                let sel = move |m: &[Multiplier]| {
                    let c = counts(m);
                    match kind {
                        SpecialKind::Fold => c.0,
                        SpecialKind::Flip => c.1,
                        _ => c.2,
                    }
                };
                let same = move |bp: &BranchPoint| sel(&bp.multipliers) == a;
                found.push(locate(
                    solver, kind, &cur, &next, before, &point, &same, last,
                ));
            }
        }
        if canonical(&before.structure) != canonical(&point.structure) {
            let reference = canonical(&before.structure);
            let same = move |bp: &BranchPoint| canonical(&bp.structure) == reference;
            found.push(locate(
                solver,
                SpecialKind::Grazing,
                &cur,
                &next,
                before,
                &point,
                &same,
                last,
            ));
        }
        found.sort_by(|a, b| {
            ((a.param - before.param).abs()).total_cmp(&(b.param - before.param).abs())
        });
        specials.extend(found);
        let p_next = next.u[k];
        t = solver.tangent(&next.eval, &t);
        if next.iterations <= 3 {
            ds = (ds * 1.5).min(config.ds_max);
        }
        points.push(point);
        cur = next;
        if p_next < range.0 || p_next > range.1 {
            break BranchEnd::Reached;
        }
    };
    Branch {
        period: solver.period,
        points,
        specials,
        end,
    }
}

/// Bisects between the solved points `a` and `b` (branch points `pa`, `pb`) until the bracket
/// is narrower than the tolerance; `same` says whether a point is still like `pa`.
#[allow(clippy::too_many_arguments)]
fn locate<B, M, E>(
    solver: &Solver<'_, B>,
    kind: SpecialKind,
    a: &Solved<M::Dim>,
    b: &Solved<M::Dim>,
    pa: &BranchPoint,
    pb: &BranchPoint,
    same: &dyn Fn(&BranchPoint) -> bool,
    after_point: usize,
) -> SpecialPoint
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let k = a.u.len() - 1;
    let mut ua = a.u.clone();
    let mut ub = b.u.clone();
    let mut near = pa.clone();
    let mut near_jac = a.eval.jac.clone();
    let mut far = pb.clone();
    let mut template = a.eval.state.clone();
    let mut failed = None;
    for _ in 0..200 {
        if (&ub - &ua).amax() <= solver.config.locate {
            break;
        }
        let mid = (&ua + &ub) * 0.5;
        let normal = &ub - &ua;
        let s = match solver.correct(&mid, &normal, &mid, &template) {
            Ok(s) => s,
            Err(reason) => {
                failed = Some(format!("no corrected point at {}: {reason}", mid[k]));
                break;
            }
        };
        let p = match solver.point(&s, 0.0) {
            Ok(p) => p,
            Err(reason) => {
                failed = Some(format!("no orbit at {}: {reason}", s.u[k]));
                break;
            }
        };
        if same(&p) {
            ua = s.u.clone();
            near = p;
            near_jac = s.eval.jac.clone();
            template = s.eval.state.clone();
        } else {
            ub = s.u.clone();
            far = p;
        }
    }
    let unconverged = ((&ub - &ua).amax() > solver.config.locate)
        .then(|| failed.unwrap_or_else(|| String::from("200 bisections")));
    SpecialPoint {
        kind,
        param: 0.5 * (ua[k] + ub[k]),
        bracket: (ua[k], ub[k]),
        converged: unconverged.is_none(),
        unconverged,
        point: near.point.clone(),
        state: near.state.clone(),
        multipliers: near.multipliers.clone(),
        grazing: near.grazing,
        contacts: (near.contacts, far.contacts),
        structure: (near.structure.clone(), far.structure.clone()),
        eigenvector: (kind == SpecialKind::Flip)
            .then(|| flip_vector(&near_jac))
            .flatten(),
        after_point,
    }
}

/// Continues the period-`period` orbit through the full state `guess` (at the section, e.g. a
/// point of a simulated orbit) at parameter `from`, towards `to` (see the
/// [module docs](self)). `build(p)` makes the model at `p`. The branch ends when its
/// parameter leaves the interval between `from` and `to`; after a fold it may come back
/// through it.
///
/// # Errors
/// [`ContinuationError::InvalidOption`] for bad settings; [`ContinuationError::NoStart`] when
/// no orbit is found near the guess at `from`. A branch that cannot go on is not an error: it
/// ends with [`BranchEnd::Stalled`].
///
/// # Example
///
/// The period-1 orbit of Fig. 8a from η = 2 up to its flip:
///
/// ```no_run
/// use jeffcott::global::{continue_orbit, ContinuationConfig, SpecialKind};
/// use jeffcott::params::Preset;
/// use jeffcott::JeffcottModel;
///
/// let base = Preset::Fig8a.params();
/// let build = |eta: f64| JeffcottModel::new(base.with_eta(eta));
/// let guess = JeffcottModel::new(base.with_eta(2.0))?
///     .state_at([0.5781, -0.0233], [0.0944, -0.3099])?;
/// let branch = continue_orbit(build, 2.0, &guess, 1, 2.3, &ContinuationConfig::default())?;
/// let flip = branch.specials.iter().find(|s| s.kind == SpecialKind::Flip).unwrap();
/// assert!((flip.param - 2.2348433).abs() < 1e-6);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn continue_orbit<M, B, E>(
    build: B,
    from: f64,
    guess: &OVector<f64, M::Dim>,
    period: u64,
    to: f64,
    config: &ContinuationConfig,
) -> Result<Branch, ContinuationError>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    check(config)?;
    if !(from.is_finite() && to.is_finite() && from != to) || period == 0 {
        return Err(ContinuationError::InvalidOption {
            field: "to",
            value: to,
            hint: "finite, distinct ends and a period of at least 1",
        });
    }
    let solver = Solver {
        build: &build,
        period,
        config,
    };
    let no_start = |reason: String| ContinuationError::NoStart {
        period,
        param: from,
        reason,
    };
    let model = solver.model(from).map_err(no_start)?;
    let map =
        StroboscopicMap::new(&model, period, config.sim).map_err(|e| no_start(e.to_string()))?;
    let mut u = map.reduce(guess).push(from);
    let k = u.len() - 1;
    // The start at fixed p: the constraint row is e_p.
    let mut normal = DVector::<f64>::zeros(k + 1);
    normal[k] = 1.0;
    u[k] = from;
    let first = solver.correct(&u, &normal, &u, guess).map_err(no_start)?;
    let dir = (to - from).signum();
    Ok(follow(&solver, first, dir, (from.min(to), from.max(to))))
}

/// Switches at the flip `flip` of a period-`period` branch onto the period-`2 period` branch
/// and continues it towards `to` (see the [module docs](self)).
///
/// # Errors
/// [`ContinuationError::InvalidOption`] if `flip` is not a flip with an eigenvector;
/// [`ContinuationError::NoSwitch`] if no orbit of the doubled period is found next to it.
pub fn switch_at_flip<M, B, E>(
    build: B,
    flip: &SpecialPoint,
    period: u64,
    to: f64,
    config: &ContinuationConfig,
) -> Result<Branch, ContinuationError>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    check(config)?;
    let Some(v) = flip
        .eigenvector
        .as_ref()
        .filter(|_| flip.kind == SpecialKind::Flip)
    else {
        return Err(ContinuationError::InvalidOption {
            field: "flip",
            value: flip.param,
            hint: "a special point of kind Flip, with its eigenvector",
        });
    };
    let doubled = 2 * period;
    let solver = Solver {
        build: &build,
        period: doubled,
        config,
    };
    let no_switch = |reason: String| ContinuationError::NoSwitch {
        period: doubled,
        param: flip.param,
        reason,
    };
    let model = solver.model(flip.param).map_err(no_switch)?;
    let template = OVector::<f64, M::Dim>::from_iterator_generic(
        model.dim(),
        nalgebra::U1,
        flip.state.iter().copied(),
    );
    let k = flip.point.len();
    let mut normal = DVector::<f64>::zeros(k + 1);
    for i in 0..k {
        normal[i] = v[i];
    }
    let base = DVector::from_iterator(k + 1, flip.point.iter().copied().chain([flip.param]));
    let single = Solver {
        build: &build,
        period,
        config,
    };
    let mut last = String::from("no amplitude tried");
    for amp in [1e-3, 3e-3, 1e-2, 3e-2, 0.1] {
        let start = &base + &normal * amp;
        match solver.correct(&start, &normal, &start, &template) {
            Ok(s) => {
                // Not the period-n orbit again: P^n(z) differs from z.
                let e = single.eval(&s.u, &s.eval.state).map_err(no_switch)?;
                if e.f.amax() > 1e3 * config.tolerance + 1e-8 {
                    let dir = (to - flip.param).signum();
                    let lo = flip.param.min(to) - config.ds_max;
                    let hi = flip.param.max(to) + config.ds_max;
                    return Ok(follow(&solver, s, dir, (lo, hi)));
                }
                last = format!("amplitude {amp}: the corrector found the period-{period} orbit");
            }
            Err(reason) => last = format!("amplitude {amp}: {reason}"),
        }
    }
    Err(no_switch(last))
}
