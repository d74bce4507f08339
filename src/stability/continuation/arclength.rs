use std::cell::Cell;

use nalgebra::{DMatrix, DVector, DefaultAllocator, OVector};

use super::engine::{march, narrow, Flow, Growth, Mode, Probe, StepControl};
use super::{canonical, crossings, model, SpecialKind};
use crate::analysis::Progress;
use crate::hybrid::{SimOptions, Variational, VariationalAlloc};
use crate::stability::augmented::event_structure;
use crate::stability::newton::{self, Held, NewtonOptions, Rule, System};
use crate::stability::orbit::newton_error;
use crate::stability::{multipliers, Multiplier, StabilityError, StroboscopicMap, GRAZING_MARGIN};

mod probe;

/// Options of [`continue_orbit`] and [`switch_at_flip`]: `Default`, then the builder methods.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct ContinuationOptions {
    /// First arclength step (in the max norm of the scaled coordinates, module docs). Default
    /// 0.01.
    pub ds: f64,
    /// Smallest step: below it the branch ends ([`BranchEnd::Stalled`]). Default `1e-7`.
    pub ds_min: f64,
    /// Largest step. Default 0.02.
    pub ds_max: f64,
    /// Largest number of points on a branch. Default 5000.
    pub max_points: usize,
    /// Corrector convergence, absolute part: $|F_i| \le$ `atol`$\cdot s_i +$ `rtol`$\cdot
    /// |z_i|$. Default `1e-10` (above the map's noise, a few `1e-15`, and the parameter
    /// difference's rounding).
    pub atol: f64,
    /// Corrector convergence, relative part. Default 0.
    pub rtol: f64,
    /// Largest number of corrector iterations per point. Default 8.
    pub max_iterations: u32,
    /// Width of the bracket of a located special point, in the parameter's units (and in
    /// every component of $z$ relative to its scale). Default `1e-8`.
    pub bracket_width: f64,
    /// Relative step of the central difference $F_p$. Default `1e-6`.
    pub param_step: f64,
    /// The parameter's scale $s_p$ in the arclength (module docs); `None`: the magnitude of
    /// the parameter where the branch starts, or 1 where that is 0.
    pub param_scale: Option<f64>,
    /// Simulation options of every run. Default: [`SimOptions::default`].
    pub sim: SimOptions,
}

impl Default for ContinuationOptions {
    fn default() -> Self {
        ContinuationOptions {
            ds: 0.01,
            ds_min: 1e-7,
            ds_max: 0.02,
            max_points: 5000,
            atol: 1e-10,
            rtol: 0.0,
            max_iterations: 8,
            bracket_width: 1e-8,
            param_step: 1e-6,
            param_scale: None,
            sim: SimOptions::default(),
        }
    }
}

impl ContinuationOptions {
    /// With the first step [`ds`](Self::ds).
    pub fn with_ds(mut self, ds: f64) -> Self {
        self.ds = ds;
        self
    }
    /// With the smallest step [`ds_min`](Self::ds_min).
    pub fn with_ds_min(mut self, ds_min: f64) -> Self {
        self.ds_min = ds_min;
        self
    }
    /// With the largest step [`ds_max`](Self::ds_max).
    pub fn with_ds_max(mut self, ds_max: f64) -> Self {
        self.ds_max = ds_max;
        self
    }
    /// With at most `n` points per branch.
    pub fn with_max_points(mut self, n: usize) -> Self {
        self.max_points = n;
        self
    }
    /// With the corrector's absolute tolerance [`atol`](Self::atol).
    pub fn with_atol(mut self, atol: f64) -> Self {
        self.atol = atol;
        self
    }
    /// With the corrector's relative tolerance [`rtol`](Self::rtol).
    pub fn with_rtol(mut self, rtol: f64) -> Self {
        self.rtol = rtol;
        self
    }
    /// With at most `n` corrector iterations per point.
    pub fn with_max_iterations(mut self, n: u32) -> Self {
        self.max_iterations = n;
        self
    }
    /// With the located brackets' width [`bracket_width`](Self::bracket_width).
    pub fn with_bracket_width(mut self, width: f64) -> Self {
        self.bracket_width = width;
        self
    }
    /// With the relative step [`param_step`](Self::param_step) of $F_p$.
    pub fn with_param_step(mut self, step: f64) -> Self {
        self.param_step = step;
        self
    }
    /// With the parameter's scale [`param_scale`](Self::param_scale).
    pub fn with_param_scale(mut self, scale: f64) -> Self {
        self.param_scale = Some(scale);
        self
    }
    /// With the simulation options [`sim`](Self::sim).
    pub fn with_sim(mut self, sim: SimOptions) -> Self {
        self.sim = sim;
        self
    }
}

/// One point of a branch.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BranchPoint {
    /// The parameter.
    pub parameter: f64,
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
    /// Contact onsets per orbit
    /// ([`RotorModel::is_contact_onset`](crate::hybrid::RotorModel::is_contact_onset)).
    pub contacts: usize,
    /// The guards crossed over one orbit, in order from the section; for an orbit without
    /// events, the mode it stays in (`"in mode 1"`: free flight; `"in mode 2"` to `"in mode
    /// 5"`: a permanent contact in that regime).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::serde_util::labels")
    )]
    pub structure: Vec<&'static str>,
    /// Arclength from the branch's first point, in the scaled coordinates (module docs).
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
    pub parameter: f64,
    /// The final bracket's parameters (near end, far end).
    pub bracket: (f64, f64),
    /// Whether the bisection narrowed the bracket to [`ContinuationOptions::bracket_width`].
    /// `false`: the point was detected between two points but not located (`unconverged`
    /// says why); read [`bracket`](Self::bracket), not `parameter`.
    pub converged: bool,
    /// Why the bisection stopped before the bracket converged (the corrector's or the
    /// orbit's error at a midpoint, or [`StabilityError::Budget`]); `None` when it converged.
    pub unconverged: Option<StabilityError>,
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
    /// [`ContinuationOptions::max_points`] points.
    MaxPoints,
    /// The step fell below [`ContinuationOptions::ds_min`]: the corrector cannot go on (a
    /// non-smooth point it cannot pass, or the end of the branch).
    Stalled {
        /// The last parameter reached.
        parameter: f64,
        /// The last corrector failure.
        reason: StabilityError,
    },
    /// The caller's observer asked to stop
    /// ([`continue_orbit_with_progress`]): the branch is what was computed by then.
    Stopped {
        /// The last parameter reached.
        parameter: f64,
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

/// $F$ and its derivatives at one scaled point $w$.
struct Eval<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// $F_i/s_i$.
    f: DVector<f64>,
    /// $DP^n$ on $z$, unscaled (for the multipliers and the flip's eigenvector).
    jac: DMatrix<f64>,
    /// $[F_w\ F_p]$ in the scaled coordinates: $k \times (k + 1)$.
    top: DMatrix<f64>,
    state: OVector<f64, D>,
    structure: Vec<&'static str>,
    contacts: usize,
    min_margin: f64,
}

/// The bordered Jacobian of the continuation of `top` $= [F_w\ F_p]$ (an [`Eval`]'s): `top`
/// over `row`, the constraint's normal (corrector) or the previous tangent (tangent).
fn bordered(top: &DMatrix<f64>, row: &DVector<f64>) -> DMatrix<f64> {
    let k = top.nrows();
    let mut a = top.clone().insert_row(k, 0.0);
    for j in 0..=k {
        a[(k, j)] = row[j];
    }
    a
}

/// The corrector's stopping rule: full steps (the constraint may need the residual to grow),
/// the constraint row converged at 1e3 `atol`.
fn corrector_rule<'a>(newton: &'a NewtonOptions, ones: &'a DVector<f64>) -> Rule<'a> {
    Rule {
        opts: newton,
        scale: ones,
        constraint: Some(1e3),
        line_search: false,
    }
}

/// A corrected point.
struct Solved<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    w: DVector<f64>,
    eval: Eval<D>,
    iterations: u32,
    /// Full evaluations made (the variational equations and $F_p$'s runs), the zero's
    /// included: Newton's one a step, a held matrix's one at the zero and one a refresh.
    full_evaluations: u32,
}

/// The branch's model builder, period, options and scales.
struct Solver<'a, B> {
    build: &'a B,
    period: u64,
    opts: &'a ContinuationOptions,
    /// $s_i$ of $z$'s components.
    scale: DVector<f64>,
    /// $s_p$.
    param_scale: f64,
    /// Told of each point, asked before each step and each bisection whether to stop.
    progress: &'a dyn Progress,
    /// Whether it said so: once it has, every later question is answered yes without it.
    stopped: Cell<bool>,
}

impl<'a, B, M, E> Solver<'a, B>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    /// The solver of period `period` from the model at `p0`.
    fn new(
        build: &'a B,
        period: u64,
        opts: &'a ContinuationOptions,
        p0: f64,
    ) -> Result<(Self, M), StabilityError> {
        let model = model(build, p0)?;
        let map = StroboscopicMap::new(&model, period, opts.sim)?;
        let scale = map.reduce(&model.error_scale().unwrap_or_else(|| model.state_scale()));
        let param_scale = opts
            .param_scale
            .unwrap_or(if p0 == 0.0 { 1.0 } else { p0.abs() });
        let solver = Solver {
            build,
            period,
            opts,
            scale,
            param_scale,
            progress: &(),
            stopped: Cell::new(false),
        };
        Ok((solver, model))
    }

    /// Whether to stop: the observer's answer, kept once it is yes.
    fn stop_asked(&self) -> bool {
        if !self.stopped.get() && self.progress.should_stop() {
            self.stopped.set(true);
        }
        self.stopped.get()
    }

    /// The scaled coordinates of $(z, p)$.
    fn scaled(&self, z: &DVector<f64>, p: f64) -> DVector<f64> {
        let k = z.len();
        DVector::from_iterator(
            k + 1,
            z.iter()
                .zip(self.scale.iter())
                .map(|(zi, si)| zi / si)
                .chain([p / self.param_scale]),
        )
    }

    /// $(z, p)$ of scaled coordinates.
    fn unscaled(&self, w: &DVector<f64>) -> (DVector<f64>, f64) {
        let k = w.len() - 1;
        let z = w.rows(0, k).component_mul(&self.scale);
        (z, w[k] * self.param_scale)
    }

    /// $F$, $DP^n$, $F_p$ at the scaled point `w`, the algebraic components placed from
    /// `template`.
    fn eval(
        &self,
        w: &DVector<f64>,
        template: &OVector<f64, M::Dim>,
    ) -> Result<Eval<M::Dim>, StabilityError> {
        let (z, p) = self.unscaled(w);
        let k = z.len();
        let at_p = model(self.build, p)?;
        let map = StroboscopicMap::new(&at_p, self.period, self.opts.sim)?;
        let state = map.state(template, &z);
        let lin = map.linearize(&state)?;
        let h = self.opts.param_step * (1.0 + p.abs());
        let mut ends = Vec::with_capacity(2);
        for q in [p + h, p - h] {
            let m = model(self.build, q)?;
            let mq = StroboscopicMap::new(&m, self.period, self.opts.sim)?;
            let y = mq.state(template, &z);
            ends.push(mq.reduce(&mq.advance(&y)?.y));
        }
        let fp = (&ends[0] - &ends[1]) / (2.0 * h);
        let s = &self.scale;
        let top = DMatrix::from_fn(k, k + 1, |i, j| {
            if j == k {
                fp[i] * self.param_scale / s[i]
            } else {
                let d = lin.jacobian[(i, j)] - if i == j { 1.0 } else { 0.0 };
                d * s[j] / s[i]
            }
        });
        Ok(Eval {
            f: (&lin.value - &z).component_div(s),
            top,
            state,
            structure: event_structure(&lin.events, lin.label),
            contacts: lin.events.iter().filter(|e| e.contact_onset).count(),
            min_margin: lin.min_margin(),
            jac: lin.jacobian,
        })
    }

    /// The corrector's Newton options (at most `steps` steps) and the scale of its residual
    /// of `len` components: $F_i / s_i$ has scale 1, and its relative part is
    /// rtol $|z_i| / s_i$.
    fn corrector(&self, steps: u32, len: usize) -> (NewtonOptions, DVector<f64>) {
        let newton = NewtonOptions::default()
            .with_atol(self.opts.atol)
            .with_rtol(self.opts.rtol)
            .with_max_iterations(steps + 1);
        (newton, DVector::from_element(len, 1.0))
    }

    /// $F$ alone at the scaled point `w` (one run of the map, no variational equations).
    fn residual(
        &self,
        w: &DVector<f64>,
        template: &OVector<f64, M::Dim>,
    ) -> Result<DVector<f64>, StabilityError> {
        let (z, p) = self.unscaled(w);
        let at_p = model(self.build, p)?;
        let map = StroboscopicMap::new(&at_p, self.period, self.opts.sim)?;
        let end = map.advance(&map.state(template, &z))?;
        Ok((map.reduce(&end.y) - &z).component_div(&self.scale))
    }

    /// The one Newton (full steps) on $F(w) = 0$, $n\cdot(w - c) = 0$ from `start`; with
    /// `held` (the $[F_w\ F_p]$ of a point near `start`, e.g. the branch's previous point) the
    /// simplified Newton on it, each step one run of the map instead of one with the
    /// variational equations and $F_p$'s two, the full evaluation made once at the zero
    /// (and where a step does not contract).
    fn correct(
        &self,
        (start, held): (&DVector<f64>, Option<&DMatrix<f64>>),
        normal: &DVector<f64>,
        c: &DVector<f64>,
        template: &OVector<f64, M::Dim>,
    ) -> Result<Solved<M::Dim>, StabilityError> {
        let (newton, ones) = self.corrector(self.opts.max_iterations, start.len());
        let rule = corrector_rule(&newton, &ones);
        let eval = |w: &DVector<f64>| {
            self.eval(w, template).map(|e| {
                let residual = e.f.clone().push(normal.dot(&(w - c)));
                System {
                    residual,
                    matrix: bordered(&e.top, normal),
                    extra: e,
                }
            })
        };
        let held = held.map(|top| Held {
            matrix: bordered(top, normal),
            residual: |w: &DVector<f64>| {
                let f = self.residual(w, template)?;
                Ok(f.push(normal.dot(&(w - c))))
            },
        });
        let zero = newton::solve_held(start, eval, held, &rule).map_err(newton_error)?;
        Ok(Solved {
            w: zero.u,
            eval: zero.system.extra,
            iterations: zero.iterations - 1,
            full_evaluations: zero.full_evaluations,
        })
    }

    /// The unit tangent at a solved point, oriented along `prev`.
    fn tangent(&self, e: &Eval<M::Dim>, prev: &DVector<f64>) -> DVector<f64> {
        let k = e.f.len();
        let a = bordered(&e.top, prev);
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
    fn point(&self, s: &Solved<M::Dim>, arclength: f64) -> Result<BranchPoint, StabilityError> {
        let (z, p) = self.unscaled(&s.w);
        let m = multipliers(&s.eval.jac)?;
        let at_p = model(self.build, p)?;
        let one = StroboscopicMap::new(&at_p, 1, self.opts.sim)?;
        let mut cycle = vec![s.eval.state.iter().copied().collect::<Vec<f64>>()];
        let mut y = s.eval.state.clone();
        for _ in 1..self.period {
            y = one.advance(&y)?.y;
            cycle.push(y.iter().copied().collect());
        }
        Ok(BranchPoint {
            parameter: p,
            point: z.iter().copied().collect(),
            state: s.eval.state.iter().copied().collect(),
            cycle,
            stable: m.iter().all(|x| x.modulus() < 1.0),
            min_margin: s.eval.min_margin,
            grazing: s.eval.min_margin < GRAZING_MARGIN,
            contacts: s.eval.contacts,
            structure: s.eval.structure.clone(),
            multipliers: m,
            arclength,
        })
    }

    /// The error of a correction that landed at the scaled point `w`, `correction` away from
    /// where it was aimed, more than `max_correction`: it left the branch (or the bracket).
    fn left_branch(
        &self,
        w: &DVector<f64>,
        correction: f64,
        max_correction: f64,
    ) -> StabilityError {
        StabilityError::LeftBranch {
            parameter: w[w.len() - 1] * self.param_scale,
            correction,
            max_correction,
            minimal_period: self.period,
            expected_period: self.period,
        }
    }

    /// The end of a branch that stalled at the scaled point `w` for `reason`.
    fn stalled(&self, w: &DVector<f64>, reason: StabilityError) -> BranchEnd {
        BranchEnd::Stalled {
            parameter: w[w.len() - 1] * self.param_scale,
            reason,
        }
    }

    /// The bracket's width: in the parameter's units, and in $z$ relative to its scale.
    fn width(&self, a: &DVector<f64>, b: &DVector<f64>) -> f64 {
        let k = a.len() - 1;
        let state = (a.rows(0, k) - b.rows(0, k)).amax();
        state.max((a[k] - b[k]).abs() * self.param_scale)
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

fn check(opts: &ContinuationOptions) -> Result<(), StabilityError> {
    let positive = |field, v: f64, hint| {
        if v.is_finite() && v > 0.0 {
            Ok(())
        } else {
            Err(StabilityError::InvalidOption {
                field,
                value: v,
                hint,
            })
        }
    };
    positive("ds", opts.ds, "a finite step > 0, e.g. 0.01")?;
    positive("ds_min", opts.ds_min, "a finite step > 0, e.g. 1e-7")?;
    positive("ds_max", opts.ds_max, "a finite step > 0, e.g. 0.02")?;
    positive("atol", opts.atol, "above the map's noise, e.g. 1e-10")?;
    positive(
        "bracket_width",
        opts.bracket_width,
        "a bracket width > 0, e.g. 1e-8",
    )?;
    positive(
        "param_step",
        opts.param_step,
        "a relative step > 0, e.g. 1e-6",
    )?;
    if let Some(s) = opts.param_scale {
        positive(
            "param_scale",
            s,
            "a finite scale > 0, e.g. the parameter's size",
        )?;
    }
    if !(opts.rtol.is_finite() && opts.rtol >= 0.0) {
        return Err(StabilityError::InvalidOption {
            field: "rtol",
            value: opts.rtol,
            hint: "a finite relative tolerance >= 0, e.g. 0",
        });
    }
    if opts.ds_min > opts.ds_max || opts.ds > opts.ds_max {
        return Err(StabilityError::InvalidOption {
            field: "ds_max",
            value: opts.ds_max,
            hint: "ds_min <= ds <= ds_max",
        });
    }
    Ok(())
}

/// One predictor-corrector step from `cur` along `t` by `ds`: the corrected point, or why not
/// (a correction larger than the step is another branch).
fn step<B, M, E>(
    solver: &Solver<'_, B>,
    cur: &Solved<M::Dim>,
    t: &DVector<f64>,
    ds: f64,
) -> Result<Solved<M::Dim>, StabilityError>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let pred = &cur.w + t * ds;
    let s = solver.correct((&pred, Some(&cur.eval.top)), t, &pred, &cur.eval.state)?;
    let jump = (&s.w - &pred).amax();
    let largest = ds.max(10.0 * solver.opts.atol);
    if jump > largest {
        return Err(solver.left_branch(&s.w, jump, largest));
    }
    Ok(s)
}

/// The special points between the consecutive points `a` (branch point `pa`, index `last`)
/// and `b` (`pb`), located, nearest `pa` first.
fn specials_between<B, M, E>(
    solver: &Solver<'_, B>,
    (a, pa): (&Solved<M::Dim>, &BranchPoint),
    (b, pb): (&Solved<M::Dim>, &BranchPoint),
    last: usize,
) -> Vec<SpecialPoint>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let mut found = Vec::new();
    for kind in crossings(&pa.multipliers, &pb.multipliers) {
        let reference = pa.multipliers.clone();
        let same = move |bp: &BranchPoint| !crossings(&reference, &bp.multipliers).contains(&kind);
        found.push(locate(solver, kind, (a, pa), (b, pb), &same, last));
    }
    if canonical(&pa.structure) != canonical(&pb.structure) {
        let reference = canonical(&pa.structure);
        let same = move |bp: &BranchPoint| canonical(&bp.structure) == reference;
        let kind = SpecialKind::Grazing;
        found.push(locate(solver, kind, (a, pa), (b, pb), &same, last));
    }
    found.sort_by(|x, y| {
        ((x.parameter - pa.parameter).abs()).total_cmp(&(y.parameter - pa.parameter).abs())
    });
    found
}

/// Follows the branch from the solved point `first` (tangent initialised along `dir` in $p$),
/// while the parameter stays in `range`: the continuation core in its arclength mode.
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
    let opts = solver.opts;
    let k = first.w.len() - 1;
    let mut prev_t = DVector::<f64>::zeros(k + 1);
    prev_t[k] = dir;
    let mut branch = Branch {
        period: solver.period,
        points: Vec::new(),
        specials: Vec::new(),
        end: BranchEnd::Reached,
    };
    let start = match solver.point(&first, 0.0) {
        Ok(p) => {
            let start = p.parameter;
            branch.points.push(p);
            solver
                .progress
                .update(share_done(1, opts.max_points, 0.0), PROGRESS_UNITS);
            start
        }
        Err(reason) => {
            branch.end = solver.stalled(&first.w, reason);
            return branch;
        }
    };
    let target = if dir > 0.0 { range.1 } else { range.0 };
    let mut mode = Arclength {
        t: solver.tangent(&first.eval, &prev_t),
        solver,
        branch,
        arclength: 0.0,
        range,
        headway: (start, target, 0.0),
    };
    let control = StepControl {
        first: opts.ds,
        min: opts.ds_min,
        max: opts.ds_max,
        growth: Growth::Grow(1.5),
    };
    mode.branch.end = march(&mut mode, first, &control);
    mode.branch
}

/// The arclength mode of the continuation core: each step is corrected in $(z, p)$ on the
/// hyperplane normal to the tangent, every special point met is located and passed.
struct Arclength<'s, 'a, B> {
    solver: &'s Solver<'a, B>,
    /// The unit tangent at the current point.
    t: DVector<f64>,
    /// The branch so far.
    branch: Branch,
    /// Arclength of the current point.
    arclength: f64,
    /// The parameter's range.
    range: (f64, f64),
    /// The start's parameter, the range's end it heads for and the largest share of the way
    /// between them reached so far (the progress reported).
    headway: (f64, f64, f64),
}

/// The units of the continuation's progress: `update(done, PROGRESS_UNITS)`.
const PROGRESS_UNITS: usize = 1000;

/// The share of the branch done, in [`PROGRESS_UNITS`]: the larger of the points' share of
/// `max_points` and the share of the way to the range's end reached (`reach`), since the
/// branch ends when either is full. (The points alone mislead: a branch that reaches its end
/// in 300 of 5000 points showed 6 % there, and an hour left.)
fn share_done(points: usize, max_points: usize, reach: f64) -> usize {
    let share = (points as f64 / max_points as f64)
        .max(reach)
        .clamp(0.0, 1.0);
    (share * PROGRESS_UNITS as f64).floor() as usize
}

impl<B, M, E> Mode for Arclength<'_, '_, B>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    type Point = Solved<M::Dim>;
    type Failure = StabilityError;
    type End = BranchEnd;

    fn stop(&mut self, cur: &Solved<M::Dim>) -> Option<BranchEnd> {
        if self.branch.points.len() >= self.solver.opts.max_points {
            return Some(BranchEnd::MaxPoints);
        }
        let k = cur.w.len() - 1;
        let parameter = cur.w[k] * self.solver.param_scale;
        self.solver
            .stop_asked()
            .then_some(BranchEnd::Stopped { parameter })
    }

    fn step(&mut self, cur: &Solved<M::Dim>, ds: f64) -> Result<Solved<M::Dim>, StabilityError> {
        step(self.solver, cur, &self.t, ds)
    }

    fn easy(&self, next: &Solved<M::Dim>) -> bool {
        // Easy: at most Newton's three steps, or a held matrix's six (each one run) with at
        // most one refresh (no more full evaluations than Newton's easy correction).
        next.iterations <= 3 || (next.full_evaluations <= 2 && next.iterations <= 6)
    }

    fn accept(&mut self, cur: Self::Point, next: Self::Point) -> Flow<Self::Point, BranchEnd> {
        self.arclength += (&next.w - &cur.w).norm();
        let point = match self.solver.point(&next, self.arclength) {
            Ok(p) => p,
            Err(reason) => return Flow::Stop(self.solver.stalled(&next.w, reason)),
        };
        let points = &self.branch.points;
        let last = points.len() - 1;
        let found = specials_between(self.solver, (&cur, &points[last]), (&next, &point), last);
        self.branch.specials.extend(found);
        let p_next = point.parameter;
        self.t = self.solver.tangent(&next.eval, &self.t);
        self.branch.points.push(point);
        let (start, target, reach) = self.headway;
        let reach = reach.max((p_next - start) / (target - start));
        self.headway.2 = reach;
        let done = share_done(self.branch.points.len(), self.solver.opts.max_points, reach);
        self.solver.progress.update(done, PROGRESS_UNITS);
        if p_next < self.range.0 || p_next > self.range.1 {
            return Flow::Stop(BranchEnd::Reached);
        }
        Flow::Go(next)
    }

    /// Before the branch ends, a leap: where a contact starts (a grazing, above all the start
    /// of a permanent contact, a full annular rub) the map is not twice differentiable and
    /// Newton, its Jacobian taken on one side, can fail at every step across it. The leap
    /// steps the parameter alone (by [`LEAPS`] of the largest step, in the branch's
    /// direction), runs [`SETTLE`] periods there from the last orbit, and corrects the
    /// parameter held fixed from where that run ends: past a grazing into a stable contact
    /// the run lands near the orbit. The special point between is located as any other.
    fn stall(&mut self, cur: Self::Point, reason: StabilityError) -> Flow<Self::Point, BranchEnd> {
        for fraction in LEAPS {
            if let Ok(next) = leap(self.solver, &cur, &self.t, fraction) {
                return self.accept(cur, next);
            }
        }
        Flow::Stop(self.solver.stalled(&cur.w, reason))
    }
}

/// The leaps tried at a stall, in fractions of the largest step (smallest first: the least
/// of the branch skipped).
const LEAPS: [f64; 3] = [0.25, 0.5, 1.0];

/// Periods run before a leap's correction.
const SETTLE: u64 = 200;

/// The leap of [`Arclength::stall`] from `cur` with tangent `t`: the parameter stepped by
/// `fraction` of the largest step, the orbit found there by [`settled`].
fn leap<B, M, E>(
    solver: &Solver<'_, B>,
    cur: &Solved<M::Dim>,
    t: &DVector<f64>,
    fraction: f64,
) -> Result<Solved<M::Dim>, StabilityError>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let k = cur.w.len() - 1;
    let p = cur.w[k] + t[k].signum() * fraction * solver.opts.ds_max;
    settled(solver, p, &cur.eval.state)
}

/// The orbit at the scaled parameter `p` found the robust way, where Newton from a prediction
/// fails at a non-smooth point: [`SETTLE`] periods run there from the full state `from`, then
/// the correction with the parameter held fixed from where the run ended.
fn settled<B, M, E>(
    solver: &Solver<'_, B>,
    p: f64,
    from: &OVector<f64, M::Dim>,
) -> Result<Solved<M::Dim>, StabilityError>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let at = model(solver.build, p * solver.param_scale)?;
    let map = StroboscopicMap::new(&at, solver.period, solver.opts.sim)?;
    let mut y = from.clone();
    for _ in 0..SETTLE.div_ceil(solver.period) {
        y = map.advance(&y)?.y;
    }
    let k = solver.scale.len();
    let mut start = DVector::zeros(k + 1);
    start
        .rows_mut(0, k)
        .copy_from(&map.reduce(&y).component_div(&solver.scale));
    start[k] = p;
    let mut along_p = DVector::zeros(k + 1);
    along_p[k] = 1.0;
    solver.correct((&start, None), &along_p, &start, &y)
}

/// One end of a locator's bracket: the corrected point, its branch point and its $DP^n$.
struct End<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    w: DVector<f64>,
    point: BranchPoint,
    jac: DMatrix<f64>,
    /// Its $[F_w\ F_p]$, or for a [`Solver::structure_probe`]'s the one it held.
    top: DMatrix<f64>,
    state: OVector<f64, D>,
    /// Whether `point` has its multipliers and `jac` its Jacobian (not a structure probe's).
    complete: bool,
}

impl<D: nalgebra::Dim> End<D>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The end at a solved point.
    fn of(s: &Solved<D>, point: &BranchPoint) -> Self {
        End {
            w: s.w.clone(),
            point: point.clone(),
            jac: s.eval.jac.clone(),
            top: s.eval.top.clone(),
            state: s.eval.state.clone(),
            complete: true,
        }
    }
}

/// Locates the special point `kind` between the solved points `a` and `b` (branch points
/// `pa`, `pb`) by the one locator; `same` says whether a point is still like `pa`.
fn locate<B, M, E>(
    solver: &Solver<'_, B>,
    kind: SpecialKind,
    (a, pa): (&Solved<M::Dim>, &BranchPoint),
    (b, pb): (&Solved<M::Dim>, &BranchPoint),
    same: &dyn Fn(&BranchPoint) -> bool,
    after_point: usize,
) -> SpecialPoint
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let end = End::of;
    let width = solver.opts.bracket_width;
    // The bisection on the secant's fraction; each probe bisects the ends in (z, p) and stops
    // the search (`Err`) once they are within the width (`None`) or the corrector fails.
    let ends = (end(a, pa), end(b, pb));
    let (near, far, out) = narrow(ends, (0.0, 1.0), (0.0, 200), |_, near, far| {
        if solver.width(&near.w, &far.w) <= width {
            return Err(None);
        }
        if solver.stop_asked() {
            return Err(Some(StabilityError::Stopped {
                done: after_point as u64 + 1,
                total: solver.opts.max_points as u64,
                partial: None,
            }));
        }
        let mid = (&near.w + &far.w) * 0.5;
        let normal = &far.w - &near.w;
        let k = mid.len() - 1;
        // A correction farther from the midpoint than the ends (the hyperplane met the branch
        // again, beyond them) is not a probe of this bracket. Where it is not, or Newton fails
        // (where a contact starts), the probe is the orbit a run settles to at the midpoint's
        // parameter (from either end's state). A grazing's bisection reads the probe's event
        // structure alone, and first tries the cheap probe (the simplified Newton held at an
        // end, no Jacobian); the others need the multipliers and take Newton itself (held, at
        // a fold where a contact starts, an isotropic rotor's rub branch turning where it
        // meets the free orbit, their probes never narrowed the bracket).
        let reach = 0.5 * (&far.w - &near.w).norm();
        let within = |w: &DVector<f64>| {
            let off = (w - &mid).norm();
            (off <= reach)
                .then_some(())
                .ok_or_else(|| solver.left_branch(w, off, reach))
        };
        let inside = |s: Solved<M::Dim>| within(&s.w).map(|()| s);
        if kind == SpecialKind::Grazing {
            let probe = solver.structure_probe(&mid, &normal, &near.top, &near.state);
            if let Ok(e) = probe.and_then(|e| within(&e.w).map(|()| e)) {
                return Ok(if same(&e.point) {
                    Probe::Near(e)
                } else {
                    Probe::Far(e)
                });
            }
        }
        match solver
            .correct((&mid, None), &normal, &mid, &near.state)
            .and_then(inside)
            .or_else(|e| settled(solver, mid[k], &near.state).map_err(|_| e))
            .or_else(|e| settled(solver, mid[k], &far.state).map_err(|_| e))
            .and_then(|s| solver.point(&s, 0.0).map(|p| end(&s, &p)))
        {
            Ok(e) if same(&e.point) => Ok(Probe::Near(e)),
            Ok(e) => Ok(Probe::Far(e)),
            Err(error) => Err(Some(error)),
        }
    });
    let k = near.w.len() - 1;
    let (pn, pf) = (
        near.w[k] * solver.param_scale,
        far.w[k] * solver.param_scale,
    );
    let unconverged = (solver.width(&near.w, &far.w) > width).then(|| {
        out.err().flatten().unwrap_or(StabilityError::Budget {
            field: "bisections",
            limit: 200.0,
            parameter: 0.5 * (pn + pf),
        })
    });
    let normal = &far.w - &near.w;
    let near = solver.completed(near, &normal);
    special(kind, (pn, &near), (pf, &far), unconverged, after_point)
}

/// The special point of the final bracket `near` (at the parameter `pn`) to `far` (at `pf`).
fn special<D: nalgebra::Dim>(
    kind: SpecialKind,
    (pn, near): (f64, &End<D>),
    (pf, far): (f64, &End<D>),
    unconverged: Option<StabilityError>,
    after_point: usize,
) -> SpecialPoint
where
    DefaultAllocator: VariationalAlloc<D>,
{
    let n = &near.point;
    SpecialPoint {
        kind,
        parameter: 0.5 * (pn + pf),
        bracket: (pn, pf),
        converged: unconverged.is_none(),
        unconverged,
        point: n.point.clone(),
        state: n.state.clone(),
        multipliers: n.multipliers.clone(),
        grazing: n.grazing,
        contacts: (n.contacts, far.point.contacts),
        structure: (n.structure.clone(), far.point.structure.clone()),
        eigenvector: (kind == SpecialKind::Flip)
            .then(|| flip_vector(&near.jac))
            .flatten(),
        after_point,
    }
}

/// Continues the period-`period` orbit through the full state `guess` (at the section, e.g. a
/// point of a simulated orbit) at parameter `from`, towards `to` (see the
/// [module docs](crate::stability); the arguments in the order of [`locate_loss`](super::locate_loss)). `build(p)` makes the model at `p`. The branch ends when its
/// parameter leaves the interval between `from` and `to`; after a fold it may come back
/// through it.
///
/// # Errors
/// [`StabilityError::InvalidOption`] for bad options; [`StabilityError::NoStart`] when no
/// orbit is found near the guess at `from`. A branch that cannot go on is not an error: it
/// ends with [`BranchEnd::Stalled`].
///
/// # Example
///
/// The period-1 orbit of Fig. 8a from η = 2 up to its flip:
///
/// ```no_run
/// use jeffcott::stability::{continue_orbit, ContinuationOptions, SpecialKind};
/// use jeffcott::params::Preset;
/// use jeffcott::JeffcottModel;
///
/// let base = Preset::Fig8a.params();
/// let build = |eta: f64| JeffcottModel::new(base.with_eta(eta));
/// let guess = JeffcottModel::new(base.with_eta(2.0))?
///     .state_at([0.5781, -0.0233], [0.0944, -0.3099])?;
/// let branch = continue_orbit(build, 2.0, 2.3, &guess, 1, &ContinuationOptions::default())?;
/// let flip = branch.specials.iter().find(|s| s.kind == SpecialKind::Flip).unwrap();
/// assert!((flip.parameter - 2.2348433).abs() < 1e-6);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn continue_orbit<M, B, E>(
    build: B,
    from: f64,
    to: f64,
    guess: &OVector<f64, M::Dim>,
    period: u64,
    opts: &ContinuationOptions,
) -> Result<Branch, StabilityError>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    continue_orbit_with_progress(build, from, to, guess, period, opts, &())
}

/// [`continue_orbit`] with an observer: `progress` is told `(done, 1000)` after each point
/// of the branch, `done` the thousandths of the branch done (the larger of the points' share
/// of `max_points` and the share of the way from `from` to `to` reached), and asked
/// ([`Progress::should_stop`]) before each step and each bisection step of a special point's
/// location whether to stop. Once it says yes (it is not asked again), the branch ends with
/// [`BranchEnd::Stopped`] at the next point; a special point whose location it cut short is
/// unconverged, with [`StabilityError::Stopped`]. The start's Newton is not cut short. Until the stop the results are those of
/// [`continue_orbit`], bit for bit.
///
/// # Errors
/// Those of [`continue_orbit`].
#[allow(clippy::too_many_arguments)] // continue_orbit's arguments and the observer
pub fn continue_orbit_with_progress<M, B, E>(
    build: B,
    from: f64,
    to: f64,
    guess: &OVector<f64, M::Dim>,
    period: u64,
    opts: &ContinuationOptions,
    progress: &dyn Progress,
) -> Result<Branch, StabilityError>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    check(opts)?;
    if !(from.is_finite() && to.is_finite() && from != to) || period == 0 {
        return Err(StabilityError::InvalidOption {
            field: "to",
            value: to,
            hint: "finite, distinct ends and a period of at least 1",
        });
    }
    let no_start = |e: StabilityError| StabilityError::NoStart {
        period,
        parameter: from,
        source: Box::new(e),
    };
    let (mut solver, model) = Solver::new(&build, period, opts, from).map_err(no_start)?;
    solver.progress = progress;
    let map = StroboscopicMap::new(&model, period, opts.sim).map_err(no_start)?;
    let w = solver.scaled(&map.reduce(guess), from);
    let k = w.len() - 1;
    // The start at fixed p: the constraint row is e_p.
    let mut normal = DVector::<f64>::zeros(k + 1);
    normal[k] = 1.0;
    let first = solver
        .correct((&w, None), &normal, &w, guess)
        .map_err(no_start)?;
    let dir = (to - from).signum();
    Ok(follow(&solver, first, dir, (from.min(to), from.max(to))))
}

/// Switches at the flip `flip` of a period-`period` branch onto the period-`2 period` branch
/// and continues it from there towards `to` (see the [module docs](crate::stability)).
///
/// # Errors
/// [`StabilityError::InvalidOption`] if `flip` is not a flip with an eigenvector;
/// [`StabilityError::NoSwitch`] if no orbit of the doubled period is found next to it, or if
/// the flip was detected but not located (`converged` false; the source is its `unconverged`).
pub fn switch_at_flip<M, B, E>(
    build: B,
    flip: &SpecialPoint,
    to: f64,
    period: u64,
    opts: &ContinuationOptions,
) -> Result<Branch, StabilityError>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    check(opts)?;
    let Some(v) = flip
        .eigenvector
        .as_ref()
        .filter(|_| flip.kind == SpecialKind::Flip)
    else {
        return Err(StabilityError::InvalidOption {
            field: "flip",
            value: flip.parameter,
            hint: "a special point of kind Flip, with its eigenvector",
        });
    };
    let doubled = 2 * period;
    let no_switch = |e: StabilityError| StabilityError::NoSwitch {
        period: doubled,
        parameter: flip.parameter,
        source: Box::new(e),
    };
    // A flip detected but not located: its point and eigenvector are the bracket's near end,
    // possibly far from the flip, where the doubled branch need not start.
    if !flip.converged {
        return Err(no_switch(flip.unconverged.clone().unwrap_or(
            StabilityError::InvalidOption {
                field: "flip.converged",
                value: flip.parameter,
                hint: "a flip whose bracket converged",
            },
        )));
    }
    let (solver, model) = Solver::new(&build, doubled, opts, flip.parameter).map_err(no_switch)?;
    let (single, _) = Solver::new(&build, period, opts, flip.parameter).map_err(no_switch)?;
    let template = OVector::<f64, M::Dim>::from_iterator_generic(
        model.dim(),
        nalgebra::U1,
        flip.state.iter().copied(),
    );
    let base = solver.scaled(&DVector::from_column_slice(&flip.point), flip.parameter);
    let k = flip.point.len();
    // The eigenvector in the scaled coordinates, unit, with no component in p.
    let mut normal = DVector::<f64>::zeros(k + 1);
    for i in 0..k {
        normal[i] = v[i] / solver.scale[i];
    }
    let normal = normal.normalize();
    let s = doubled_start(&solver, &single, (&base, &normal), &template).map_err(no_switch)?;
    let dir = (to - flip.parameter).signum();
    let lo = flip.parameter.min(to) - opts.ds_max * solver.param_scale;
    let hi = flip.parameter.max(to) + opts.ds_max * solver.param_scale;
    Ok(follow(&solver, s, dir, (lo, hi)))
}

/// The first point of the doubled branch: corrected on the hyperplane through
/// `base + a normal`, normal to `normal`, for growing amplitudes $a$, the first that is not
/// the period-$n$ orbit of `single` again; or the last error.
fn doubled_start<B, M, E>(
    solver: &Solver<'_, B>,
    single: &Solver<'_, B>,
    (base, normal): (&DVector<f64>, &DVector<f64>),
    template: &OVector<f64, M::Dim>,
) -> Result<Solved<M::Dim>, StabilityError>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let period = single.period;
    let mut last = None;
    for amplitude in [1e-3, 3e-3, 1e-2, 3e-2, 0.1] {
        let start = base + normal * amplitude;
        match solver.correct((&start, None), normal, &start, template) {
            Ok(s) => {
                // Not the period-n orbit again: P^n(z) differs from z.
                let e = single.eval(&s.w, &s.eval.state)?;
                if e.f.amax() > 1e3 * solver.opts.atol + 1e-8 {
                    return Ok(s);
                }
                last = Some(StabilityError::SamePeriod { period, amplitude });
            }
            Err(e) => last = Some(e),
        }
    }
    Err(last.unwrap_or(StabilityError::SamePeriod {
        period,
        amplitude: 0.0,
    }))
}
