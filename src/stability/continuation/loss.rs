use nalgebra::{DVector, DefaultAllocator, OVector};

use super::engine::{march, narrow, Flow, Growth, Mode, Probe, StepControl};
use super::{canonical, crossings, largest_real_positive, model, SpecialKind};
use crate::hybrid::{Variational, VariationalAlloc};
use crate::stability::error::StabilityError;
use crate::stability::floquet::{CrossingKind, Multiplier};
use crate::stability::map::StroboscopicMap;
use crate::stability::newton::NewtonOptions;
use crate::stability::orbit::{periodic_orbit, OrbitOptions, PeriodicOrbit};

/// Options of [`locate_loss`]: `Default`, then the builder methods.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct LossOptions {
    /// The continuation step (its sign is taken from the direction `from -> to`). Default
    /// 0.005.
    pub step: f64,
    /// Width of the final bracket, in the parameter's units. Default `1e-8`.
    pub bracket_width: f64,
    /// Largest number of continuation steps. Default 10 000.
    pub max_steps: usize,
    /// Largest Newton correction $\max_i |z_i^{\ast} - z_i^{\rm pred}|/s_i$ accepted in a step
    /// (from the predicted $z^{\rm pred}$), $s_i$ the model's
    /// [`state_scale`](crate::hybrid::RotorModel::state_scale) (a larger one halves the step:
    /// Newton may have jumped to another orbit). Default 0.05.
    pub max_correction: f64,
    /// Go on through grazing bifurcations after which the orbit is still stable (a contact or a
    /// regime boundary appears or disappears, the multipliers stay inside the unit circle),
    /// recording them in [`Continuation::grazings`], and stop at the first loss by a
    /// multiplier or at the end of the branch. Default `false`: stop at the first change of
    /// any kind.
    pub through_grazing: bool,
    /// Options of each periodic-orbit solve. Default: [`OrbitOptions::default`] with at most
    /// 10 Newton iterations and 6 step halvings (from a predicted point Newton converges in
    /// a few; beyond a fold it cannot, and failing fast keeps the bisection cheap).
    pub orbit: OrbitOptions,
}

impl Default for LossOptions {
    fn default() -> Self {
        Self {
            step: 0.005,
            bracket_width: 1e-8,
            max_steps: 10_000,
            max_correction: 0.05,
            through_grazing: false,
            orbit: OrbitOptions {
                newton: NewtonOptions::default()
                    .with_max_iterations(10)
                    .with_max_halvings(6),
                ..OrbitOptions::default()
            },
        }
    }
}

impl LossOptions {
    /// With the continuation step [`step`](Self::step).
    pub fn with_step(mut self, step: f64) -> Self {
        self.step = step;
        self
    }
    /// With the final bracket's width [`bracket_width`](Self::bracket_width).
    pub fn with_bracket_width(mut self, width: f64) -> Self {
        self.bracket_width = width;
        self
    }
    /// With at most `n` continuation steps.
    pub fn with_max_steps(mut self, n: usize) -> Self {
        self.max_steps = n;
        self
    }
    /// With the largest accepted correction [`max_correction`](Self::max_correction).
    pub fn with_max_correction(mut self, c: f64) -> Self {
        self.max_correction = c;
        self
    }
    /// Going on through grazings ([`through_grazing`](Self::through_grazing)).
    pub fn with_through_grazing(mut self, on: bool) -> Self {
        self.through_grazing = on;
        self
    }
    /// With the periodic-orbit options [`orbit`](Self::orbit).
    pub fn with_orbit(mut self, orbit: OrbitOptions) -> Self {
        self.orbit = orbit;
        self
    }
}

/// One converged point of the continuation.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ContinuationPoint {
    /// The parameter.
    pub parameter: f64,
    /// The multipliers there.
    pub multipliers: Vec<Multiplier>,
    /// Contact phases per orbit.
    pub contacts: usize,
    /// The smallest contact depth ([`crate::stability::OrbitMargins::min_depth`]).
    pub min_depth: Option<f64>,
    /// The closest free-flight approach ([`crate::stability::OrbitMargins::clearance`]).
    pub clearance: Option<f64>,
    /// Whether the orbit has a grazing event ([`PeriodicOrbit::grazing`]): its multipliers
    /// are then those of one side of a map that is not differentiable there.
    pub grazing: bool,
}

/// Where the orbit loses stability.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct StabilityLoss<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The parameter value located (module docs).
    pub parameter: f64,
    /// The final bracket: the orbit is stable with its structure at `.0`, not at `.1`.
    pub bracket: (f64, f64),
    /// How: a fold, flip or Neimark–Sacker bifurcation, or a grazing.
    pub kind: SpecialKind,
    /// The orbit at the stable end of the bracket (its multipliers are those at the loss, to
    /// the bracket's width times their slope).
    pub orbit: PeriodicOrbit<D>,
    /// The multipliers at the other end of the bracket (`None` if no orbit was found there).
    pub beyond: Option<Vec<Multiplier>>,
    /// Whether the orbit at the other end has a grazing event ([`PeriodicOrbit::grazing`]):
    /// its multipliers are then those of one side of a non-smooth map, and a crossing they
    /// show may be a jump at the grazing. `false` if no orbit was found there.
    pub beyond_grazing: bool,
    /// The event structure at the other end of the bracket (what a grazing changed), `None`
    /// if no orbit was found there.
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::serde_util::option_labels")
    )]
    pub beyond_structure: Option<Vec<&'static str>>,
}

/// Why a continuation ended before `to` without a located loss of stability (module docs):
/// the error, where it happened and the last orbit found.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct BranchFailure<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The parameter at which no orbit was found (the far end of the final bracket), or
    /// where the budget ran out.
    pub parameter: f64,
    /// What went wrong there.
    pub error: StabilityError,
    /// The parameter of the last orbit found.
    pub last_parameter: f64,
    /// The last orbit found.
    pub last_orbit: PeriodicOrbit<D>,
}

/// The continuation's outcome. At most one of `loss` and `failure` is set; neither when the
/// orbit was followed, stable, up to `to`.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct Continuation<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The first loss of stability met, `None` if there is none up to `to` or up to a
    /// failure.
    pub loss: Option<StabilityLoss<D>>,
    /// Why the continuation stopped before `to` without a located loss (module docs), `None`
    /// if it did not.
    pub failure: Option<BranchFailure<D>>,
    /// The converged points of the continuation, in order (bisection points excluded).
    pub path: Vec<ContinuationPoint>,
    /// The grazing bifurcations passed with [`LossOptions::through_grazing`], in order.
    pub grazings: Vec<StabilityLoss<D>>,
}

fn point<D: nalgebra::Dim>(p: f64, o: &PeriodicOrbit<D>) -> ContinuationPoint
where
    DefaultAllocator: VariationalAlloc<D>,
{
    ContinuationPoint {
        parameter: p,
        multipliers: o.multipliers.clone(),
        contacts: o.margins.contacts,
        min_depth: o.margins.min_depth,
        clearance: o.margins.clearance,
        grazing: o.grazing,
    }
}

/// A parameter and the orbit there.
type Solved<D> = (f64, PeriodicOrbit<D>);

/// The orbits of the branch: the model builder, the period, the options, the scale of $z$.
struct Stepper<'a, F> {
    build: &'a F,
    period: u64,
    opts: &'a LossOptions,
    scale: DVector<f64>,
    /// The minimal period of the orbit followed.
    minimal: u64,
}

impl<F, M, E> Stepper<'_, F>
where
    M: Variational,
    F: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    /// The orbit at `p` from a template state and a guess of its point; another orbit (one
    /// of another minimal period, or far from the prediction) is not this branch.
    fn solve(
        &self,
        p: f64,
        template: &OVector<f64, M::Dim>,
        z: &DVector<f64>,
    ) -> Result<PeriodicOrbit<M::Dim>, StabilityError> {
        let model = model(self.build, p)?;
        let guess = model.section_state(0.0, template, z.as_slice());
        let o = periodic_orbit(&model, &guess, self.period, &self.opts.orbit)?;
        let correction = (&o.point - z).component_div(&self.scale).amax();
        if o.minimal_period != self.minimal || correction > self.opts.max_correction {
            return Err(StabilityError::LeftBranch {
                parameter: p,
                correction,
                max_correction: self.opts.max_correction,
                minimal_period: o.minimal_period,
                expected_period: self.minimal,
            });
        }
        Ok(o)
    }
}

/// Secant prediction of the point at `p` from the last two.
fn predict<D: nalgebra::Dim>(
    last: &Solved<D>,
    before: &Option<(f64, DVector<f64>)>,
    p: f64,
) -> DVector<f64>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    match before {
        Some((pb, zb)) if *pb != last.0 => {
            let w = (p - last.0) / (last.0 - pb);
            &last.1.point + (&last.1.point - zb) * w
        }
        _ => last.1.point.clone(),
    }
}

fn check(from: f64, to: f64, opts: &LossOptions) -> Result<(), StabilityError> {
    let bad = |field, value, hint| Err(StabilityError::InvalidOption { field, value, hint });
    if !(opts.step.is_finite() && opts.step != 0.0) {
        return bad(
            "step",
            opts.step,
            "a finite nonzero continuation step, e.g. 0.005",
        );
    }
    if !(opts.bracket_width.is_finite() && opts.bracket_width > 0.0) {
        return bad(
            "bracket_width",
            opts.bracket_width,
            "a finite bracket width > 0, e.g. 1e-8",
        );
    }
    if !(from.is_finite() && to.is_finite()) {
        return bad("to", to, "finite parameter bounds");
    }
    Ok(())
}

/// The stable orbit at `from` and the stepper of its branch.
fn start<'a, M, F, E>(
    build: &'a F,
    from: f64,
    guess: &OVector<f64, M::Dim>,
    period: u64,
    opts: &'a LossOptions,
) -> Result<(Stepper<'a, F>, PeriodicOrbit<M::Dim>), StabilityError>
where
    M: Variational,
    F: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let model = model(build, from)?;
    let first = periodic_orbit(&model, guess, period, &opts.orbit)?;
    if first.spectral_radius() >= 1.0 {
        return Err(StabilityError::Unstable {
            parameter: from,
            spectral_radius: first.spectral_radius(),
        });
    }
    let scale = StroboscopicMap::new(&model, period, opts.orbit.sim)?.reduce(&model.state_scale());
    let stepper = Stepper {
        build,
        period,
        opts,
        scale,
        minimal: first.minimal_period,
    };
    Ok((stepper, first))
}

/// Continues the period-`period` orbit through the full state `guess` at parameter `from`
/// towards `to` and locates its first loss of stability (module docs): the continuation core
/// in its natural-parameter mode. `build(p)` makes the model at `p`.
///
/// # Errors
/// [`StabilityError::InvalidOption`] for bad options, [`StabilityError::Model`] for a model
/// that cannot be built at `from`, [`StabilityError::Unstable`] if the orbit at `from` is not
/// stable, or the error of the first orbit solve. A failure after the first orbit (including
/// [`StabilityError::Budget`] when `max_steps` run out) is returned with the path, in
/// [`Continuation::failure`].
pub fn locate_loss<M, F, E>(
    build: F,
    from: f64,
    to: f64,
    guess: &OVector<f64, M::Dim>,
    period: u64,
    opts: &LossOptions,
) -> Result<Continuation<M::Dim>, StabilityError>
where
    M: Variational,
    F: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    check(from, to, opts)?;
    let (stepper, first) = start(&build, from, guess, period, opts)?;
    let mut mode = Natural {
        structure: canonical(&first.margins.structure),
        c: Continuation {
            loss: None,
            failure: None,
            path: vec![point(from, &first)],
            grazings: Vec::new(),
        },
        stepper,
        to,
        dir: (to - from).signum(),
        before: None,
        steps: 0,
    };
    // A failed step is halved while it is above the bracket width (the half at least the next
    // float above half the width); then the failure itself is bisected.
    let control = StepControl {
        first: opts.step.abs(),
        min: (0.5 * opts.bracket_width).next_up(),
        max: opts.step.abs(),
        growth: Growth::Reset,
    };
    let end = march(&mut mode, (from, first), &control);
    let mut c = mode.c;
    match end {
        Some(End::Loss(loss)) => c.loss = Some(loss),
        Some(End::Failure(f)) => c.failure = Some(f),
        None => {}
    }
    Ok(c)
}

/// The natural-parameter mode of the continuation core: each step solves the orbit at a fixed
/// parameter ([`Stepper::solve`]), the first loss of stability ends it (a grazing after which
/// the orbit is still stable does not, with [`LossOptions::through_grazing`]).
struct Natural<'a, F, D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    stepper: Stepper<'a, F>,
    /// The end of the range and the direction towards it ($\pm 1$).
    to: f64,
    dir: f64,
    /// The event structure of the orbit followed.
    structure: Vec<&'static str>,
    /// The point before the current one, for the secant prediction.
    before: Option<(f64, DVector<f64>)>,
    /// Steps tried.
    steps: usize,
    /// The outcome so far.
    c: Continuation<D>,
}

impl<F, M, E> Mode for Natural<'_, F, M::Dim>
where
    M: Variational,
    F: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    type Point = Solved<M::Dim>;
    /// The far end of a bracket: no orbit, or one that is lost.
    type Failure = Far<M::Dim>;
    /// `None`: `to` reached.
    type End = Option<End<M::Dim>>;

    fn stop(&mut self, cur: &Solved<M::Dim>) -> Option<Self::End> {
        if self.steps >= self.stepper.opts.max_steps {
            return Some(Some(End::Failure(out_of_steps(self.stepper.opts, cur))));
        }
        ((cur.0 - self.to) * self.dir >= 0.0).then_some(None)
    }

    fn step(&mut self, cur: &Solved<M::Dim>, ds: f64) -> Result<Solved<M::Dim>, Far<M::Dim>> {
        self.steps += 1;
        let p = next_parameter(cur.0, ds * self.dir, self.to, self.dir);
        let z = predict(cur, &self.before, p);
        match self.stepper.solve(p, &cur.1.state, &z) {
            Ok(o) => Ok((p, o)),
            Err(e) => Err((p, Err(e))),
        }
    }

    fn easy(&self, _: &Solved<M::Dim>) -> bool {
        true
    }

    fn accept(&mut self, cur: Self::Point, next: Self::Point) -> Flow<Self::Point, Self::End> {
        if is_lost(&next.1, &self.structure) {
            return self.stall(cur, (next.0, Ok(next.1)));
        }
        self.c.path.push(point(next.0, &next.1));
        self.before = Some((cur.0, cur.1.point));
        Flow::Go(next)
    }

    /// Locates what happened between the stable `last` and `far`: a loss or a failure that
    /// ends the continuation, or a grazing it goes on through.
    fn stall(&mut self, last: Self::Point, far: Far<M::Dim>) -> Flow<Self::Point, Self::End> {
        let (stepper, width) = (&self.stepper, self.stepper.opts.bracket_width);
        let solve = |p, t: &_, z: &_| stepper.solve(p, t, z);
        match bisect_with(&solve, last, far, &self.structure, width) {
            (End::Loss(loss), Some(next))
                if self.stepper.opts.through_grazing
                    && loss.kind == SpecialKind::Grazing
                    && next.1.spectral_radius() < 1.0 =>
            {
                self.structure = canonical(&next.1.margins.structure);
                self.c.path.push(point(next.0, &next.1));
                self.c.grazings.push(loss);
                self.before = None;
                Flow::Go(next)
            }
            (end, _) => Flow::Stop(Some(end)),
        }
    }
}

/// `last + step`, or `to` if that is beyond it (in the direction `dir`).
fn next_parameter(last: f64, step: f64, to: f64, dir: f64) -> f64 {
    if (last + step - to) * dir > 0.0 {
        to
    } else {
        last + step
    }
}

/// The failure when `max_steps` run out at `last`.
fn out_of_steps<D: nalgebra::Dim>(opts: &LossOptions, last: &Solved<D>) -> BranchFailure<D>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    let error = StabilityError::Budget {
        field: "max_steps",
        limit: opts.max_steps as f64,
        parameter: last.0,
    };
    BranchFailure {
        parameter: last.0,
        error,
        last_parameter: last.0,
        last_orbit: last.1.clone(),
    }
}

/// How a bracket ends: a located loss or a failure.
enum End<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    Loss(StabilityLoss<D>),
    Failure(BranchFailure<D>),
}

/// A branch that ends with a real multiplier above this is a fold (its multiplier reaches +1
/// at the end; within the bracket of `1e-8` it is above 0.99 for a square-root fold whose
/// multiplier moves like $1 - c\sqrt{\eta^{\ast} - \eta}$ with $c$ up to $10^2$).
const FOLD_MULTIPLIER: f64 = 0.95;

/// The far end of a bracket: a parameter and the orbit there, or why there is none.
type Far<D> = (f64, Result<PeriodicOrbit<D>, StabilityError>);

/// Bisects `[a, b]` (stable with the reference structure at `a`, not at `b`) to the width
/// `tol` by the one locator, each orbit found by `solve`.
fn bisect_with<D, S>(
    solve: &S,
    a: Solved<D>,
    b: Far<D>,
    structure: &[&'static str],
    tol: f64,
) -> (End<D>, Option<Solved<D>>)
where
    D: nalgebra::Dim,
    DefaultAllocator: VariationalAlloc<D>,
    S: Fn(f64, &OVector<f64, D>, &DVector<f64>) -> Result<PeriodicOrbit<D>, StabilityError>,
{
    let start_real = largest_real_positive(&a.1.multipliers);
    let ends = (a.0, b.0);
    // Each probe solves at the midpoint, warm-started from the near end; a failure there is
    // like the far end (the bracket then holds the branch's end).
    let (a, b, out) = narrow((a, b), ends, (tol, usize::MAX), |mid, a, _| {
        Ok::<_, std::convert::Infallible>(match solve(mid, &a.1.state, &a.1.point) {
            Ok(o) if !is_lost(&o, structure) => Probe::Near((mid, o)),
            other => Probe::Far((mid, other)),
        })
    });
    let Ok(_) = out;
    match b.1 {
        Ok(o) => {
            let l = crossing(a, b.0, &o, structure);
            (End::Loss(l), Some((b.0, o)))
        }
        Err(error) => (branch_end(a, b.0, error, start_real), None),
    }
}

/// The loss between the stable `a` and the orbit `o` at `pb`, lost by a multiplier crossing or
/// a change of structure.
fn crossing<D: nalgebra::Dim>(
    a: Solved<D>,
    pb: f64,
    o: &PeriodicOrbit<D>,
    structure: &[&'static str],
) -> StabilityLoss<D>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    let (kind, parameter) = if canonical(&o.margins.structure) != structure {
        (SpecialKind::Grazing, 0.5 * (a.0 + pb))
    } else {
        let critical = o
            .multipliers
            .first()
            .copied()
            .unwrap_or(Multiplier { re: 1.0, im: 0.0 });
        let kind = crossings(&a.1.multipliers, &o.multipliers)
            .first()
            .copied()
            .unwrap_or_else(|| CrossingKind::of(&critical, super::REAL).into());
        let (ra, rb) = (a.1.spectral_radius(), o.spectral_radius());
        let p = if rb > ra {
            a.0 + (1.0 - ra) / (rb - ra) * (pb - a.0)
        } else {
            0.5 * (a.0 + pb)
        };
        (kind, p)
    };
    StabilityLoss {
        parameter,
        bracket: (a.0, pb),
        kind,
        beyond_structure: Some(o.margins.structure.clone()),
        beyond: Some(o.multipliers.clone()),
        beyond_grazing: o.grazing,
        orbit: a.1,
    }
}

/// The branch ends between `a` and `pb`, where no orbit was found (`error`): a fold or a
/// grazing only on evidence, and only when Newton itself is what failed (module docs).
fn branch_end<D: nalgebra::Dim>(
    a: Solved<D>,
    pb: f64,
    error: StabilityError,
    start_real: f64,
) -> End<D>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    let newton = matches!(
        error,
        StabilityError::NotConverged { .. }
            | StabilityError::Singular { .. }
            | StabilityError::LeftBranch { .. }
    );
    let real = largest_real_positive(&a.1.multipliers);
    let kind = if newton && real > FOLD_MULTIPLIER && real >= start_real {
        SpecialKind::Fold
    } else if newton && a.1.grazing {
        SpecialKind::Grazing
    } else {
        return End::Failure(BranchFailure {
            parameter: pb,
            error,
            last_parameter: a.0,
            last_orbit: a.1,
        });
    };
    End::Loss(StabilityLoss {
        parameter: 0.5 * (a.0 + pb),
        bracket: (a.0, pb),
        kind,
        beyond_structure: None,
        beyond: None,
        beyond_grazing: false,
        orbit: a.1,
    })
}

/// Whether an orbit is unstable or has another event structure than `structure`.
fn is_lost<D: nalgebra::Dim>(o: &PeriodicOrbit<D>, structure: &[&'static str]) -> bool
where
    DefaultAllocator: VariationalAlloc<D>,
{
    o.spectral_radius() >= 1.0 || canonical(&o.margins.structure) != structure
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stability::orbit::OrbitMargins;
    use nalgebra::{DMatrix, U1};

    /// A synthetic stable orbit with largest multiplier `m` (real) and an event at `margin`.
    fn orbit(m: f64, margin: f64) -> PeriodicOrbit<U1> {
        PeriodicOrbit {
            period: 1,
            state: OVector::<f64, U1>::new(0.0),
            point: DVector::from_element(1, 0.0),
            residual: 0.0,
            iterations: 1,
            monodromy: DMatrix::from_element(1, 1, m),
            multipliers: vec![Multiplier { re: m, im: 0.0 }],
            events: Vec::new(),
            margins: OrbitMargins {
                contacts: 1,
                min_depth: None,
                clearance: None,
                min_event_margin: margin,
                structure: vec!["e"],
            },
            grazing: margin < crate::stability::GRAZING_MARGIN,
            openness: 0.0,
            minimal_period: 1,
        }
    }

    /// Bisects [0, 1] with orbits `good(p)` below 0.5 and `bad(p)` from 0.5 on.
    fn run(
        good: impl Fn(f64) -> PeriodicOrbit<U1>,
        bad: impl Fn(f64) -> StabilityError,
    ) -> End<U1> {
        let solve = |p: f64, _: &OVector<f64, U1>, _: &DVector<f64>| {
            if p < 0.5 {
                Ok(good(p))
            } else {
                Err(bad(p))
            }
        };
        let (end, _) = bisect_with(&solve, (0.0, good(0.0)), (1.0, Err(bad(1.0))), &["e"], 1e-8);
        end
    }

    fn newton(_: f64) -> StabilityError {
        StabilityError::NotConverged {
            last: DVector::zeros(1),
            residual: 1.0,
            iterations: 10,
            reason: "test",
        }
    }

    fn model(p: f64) -> StabilityError {
        StabilityError::Model {
            parameter: p,
            reason: "test".into(),
        }
    }

    #[test]
    fn a_branch_end_is_a_fold_or_a_grazing_only_on_evidence() {
        // A square-root fold at 0.5: the multiplier rises to 1 there.
        let fold = |p: f64| orbit(1.0 - (0.5 - p).max(0.0).sqrt(), 0.5);
        match run(fold, newton) {
            End::Loss(l) => {
                assert_eq!(l.kind, SpecialKind::Fold);
                assert!((l.parameter - 0.5).abs() < 1e-8);
            }
            End::Failure(f) => panic!("{:?}", f.error),
        }
        // An event's margin going to 0 at 0.5.
        let graze = |p: f64| orbit(0.6, (0.5 - p).max(0.0).sqrt());
        match run(graze, newton) {
            End::Loss(l) => assert_eq!(l.kind, SpecialKind::Grazing),
            End::Failure(f) => panic!("{:?}", f.error),
        }
        // Neither: Newton's failure is reported.
        match run(|_| orbit(0.6, 0.5), newton) {
            End::Loss(l) => panic!("a failure located as {:?}", l.kind),
            End::Failure(f) => {
                assert!(matches!(f.error, StabilityError::NotConverged { .. }));
                assert!(f.parameter >= 0.5 && f.last_parameter < 0.5);
                assert!(f.parameter - f.last_parameter <= 1e-8);
            }
        }
        // With the same evidence, a model that cannot be built is a failure, not a fold.
        match run(fold, model) {
            End::Loss(l) => panic!("a failure located as {:?}", l.kind),
            End::Failure(f) => assert!(matches!(f.error, StabilityError::Model { .. })),
        }
        // A multiplier near 1 that moves away from 1 is no fold.
        match run(|p| orbit(0.99 - 0.01 * p, 0.5), newton) {
            End::Loss(l) => panic!("a failure located as {:?}", l.kind),
            End::Failure(_) => {}
        }
    }
}
