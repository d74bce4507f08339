//! Following a periodic orbit along a parameter and locating where it loses stability.
//!
//! The parameter enters through a closure that builds the model at each value (any parameter,
//! any model). From the orbit found at `from`, natural-parameter continuation steps towards
//! `to`, each orbit found by Newton ([`periodic_orbit`]) from a secant prediction of the last
//! two, until one of these happens between two steps:
//!
//! * a multiplier leaves the unit circle (the spectral radius passes 1): **flip** (real,
//!   through $-1$), **fold** (real, through $+1$) or **Neimark–Sacker** (a complex pair);
//! * the orbit's **event structure** changes (a contact appears or disappears: a grazing
//!   bifurcation, which the multipliers do not announce; compared up to a rotation, so that
//!   an event moving across the section does not count);
//! * Newton fails and keeps failing as the step is halved down to the tolerance: the branch
//!   ends, a fold if a real multiplier approaches $+1$ there (above 0.95 at the last orbit),
//!   otherwise a non-smooth end (reported as grazing: a contact or a regime boundary met
//!   tangentially, where the map is not differentiable).
//!
//! The bracket is then bisected (Newton at each midpoint, warm-started from the stable end)
//! until it is narrower than [`ContinuationOptions::tolerance`]; for a multiplier crossing the
//! value reported is the linear interpolation of the spectral radius to 1 inside the final
//! bracket, for the others its midpoint.

use nalgebra::{DVector, DefaultAllocator, OVector};

use super::error::StabilityError;
use super::floquet::{CrossingKind, Multiplier};
use super::newton::NewtonOptions;
use super::orbit::{periodic_orbit, OrbitOptions, PeriodicOrbit};
use super::variational::{Variational, VariationalAlloc};

/// Options of [`locate_loss`]. A plain struct with `Default`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinuationOptions {
    /// The continuation step (its sign is taken from the direction `from -> to`). Default
    /// 0.005.
    pub step: f64,
    /// Width of the final bracket. Default `1e-8`.
    pub tolerance: f64,
    /// Largest number of continuation steps. Default 10 000.
    pub max_steps: usize,
    /// Largest Newton correction $\lVert z^{\ast} - z_{\rm predicted}\rVert_\infty$ accepted in a
    /// step (a larger one halves the step: Newton may have jumped to another orbit). Default
    /// 0.05.
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

impl Default for ContinuationOptions {
    fn default() -> Self {
        Self {
            step: 0.005,
            tolerance: 1e-8,
            max_steps: 10_000,
            max_correction: 0.05,
            through_grazing: false,
            orbit: OrbitOptions {
                newton: NewtonOptions {
                    max_iterations: 10,
                    max_halvings: 6,
                    ..NewtonOptions::default()
                },
                ..OrbitOptions::default()
            },
        }
    }
}

/// How an orbit loses stability.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[non_exhaustive]
pub enum LossKind {
    /// A multiplier crossing the unit circle.
    Multiplier(CrossingKind),
    /// The event structure changes: a contact appears or disappears.
    Grazing,
}

impl LossKind {
    /// `"flip"`, `"fold"`, `"neimark-sacker"` or `"grazing"`.
    pub fn name(self) -> &'static str {
        match self {
            LossKind::Multiplier(k) => k.name(),
            LossKind::Grazing => "grazing",
        }
    }
}

/// One converged point of the continuation.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuationPoint {
    /// The parameter.
    pub parameter: f64,
    /// The multipliers there.
    pub multipliers: Vec<Multiplier>,
    /// Contact phases per orbit.
    pub contacts: usize,
    /// The smallest contact depth ([`super::OrbitMargins::min_depth`]).
    pub min_depth: Option<f64>,
    /// The closest free-flight approach ([`super::OrbitMargins::clearance`]).
    pub clearance: Option<f64>,
}

/// Where the orbit loses stability.
#[derive(Debug, Clone, PartialEq)]
pub struct StabilityLoss<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The parameter value located (module docs).
    pub parameter: f64,
    /// The final bracket: the orbit is stable with its structure at `.0`, not at `.1`.
    pub bracket: (f64, f64),
    /// How.
    pub kind: LossKind,
    /// The orbit at the stable end of the bracket (its multipliers are those at the loss, to
    /// the bracket's width times their slope).
    pub orbit: PeriodicOrbit<D>,
    /// The multipliers at the other end of the bracket (`None` if no orbit was found there).
    pub beyond: Option<Vec<Multiplier>>,
    /// The event structure at the other end of the bracket (what a grazing changed), `None`
    /// if no orbit was found there.
    pub beyond_structure: Option<Vec<&'static str>>,
}

/// The continuation's outcome.
#[derive(Debug, Clone, PartialEq)]
pub struct Continuation<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The first loss of stability met, `None` if the orbit stays stable up to `to`.
    pub loss: Option<StabilityLoss<D>>,
    /// The converged points of the continuation, in order (bisection points excluded).
    pub path: Vec<ContinuationPoint>,
    /// The grazing bifurcations passed with [`ContinuationOptions::through_grazing`], in order.
    pub grazings: Vec<StabilityLoss<D>>,
}

/// The event structure up to a rotation: the rotation that is least in lexical order.
fn canonical(structure: &[&'static str]) -> Vec<&'static str> {
    (0..structure.len().max(1))
        .map(|r| {
            let mut v = structure.to_vec();
            v.rotate_left(r.min(structure.len()));
            v
        })
        .min()
        .unwrap_or_default()
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
    }
}

/// Continues the period-`period` orbit through the full state `guess` at parameter `from`
/// towards `to` and locates its first loss of stability (module docs). `build(p)` makes the
/// model at `p`.
///
/// # Errors
/// [`StabilityError::InvalidOption`] for bad options or a model that cannot be built,
/// [`StabilityError::Unstable`] if the orbit at `from` is not stable, or the error of the
/// first orbit solve.
pub fn locate_loss<M, F, E>(
    build: F,
    from: f64,
    to: f64,
    guess: &OVector<f64, M::Dim>,
    period: u64,
    opts: &ContinuationOptions,
) -> Result<Continuation<M::Dim>, StabilityError>
where
    M: Variational,
    F: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    if !(opts.step.is_finite() && opts.step != 0.0) {
        return Err(StabilityError::InvalidOption {
            field: "step",
            value: opts.step,
            hint: "a finite nonzero continuation step, e.g. 0.005",
        });
    }
    if !(opts.tolerance.is_finite() && opts.tolerance > 0.0) {
        return Err(StabilityError::InvalidOption {
            field: "tolerance",
            value: opts.tolerance,
            hint: "a finite bracket width > 0, e.g. 1e-8",
        });
    }
    if !(from.is_finite() && to.is_finite()) {
        return Err(StabilityError::InvalidOption {
            field: "to",
            value: to,
            hint: "finite parameter bounds",
        });
    }
    // The orbit at p from a template state and a guess of its point.
    let solve = |p: f64,
                 template: &OVector<f64, M::Dim>,
                 z: &DVector<f64>|
     -> Result<PeriodicOrbit<M::Dim>, StabilityError> {
        let model = build(p).map_err(|e| StabilityError::Model {
            parameter: p,
            reason: e.to_string(),
        })?;
        let guess = model.section_state(0.0, template, z.as_slice());
        periodic_orbit(&model, &guess, period, &opts.orbit)
    };
    let first = {
        let model = build(from).map_err(|e| StabilityError::Model {
            parameter: from,
            reason: e.to_string(),
        })?;
        periodic_orbit(&model, guess, period, &opts.orbit)?
    };
    if first.spectral_radius() >= 1.0 {
        return Err(StabilityError::Unstable {
            parameter: from,
            spectral_radius: first.spectral_radius(),
        });
    }
    let mut structure = canonical(&first.margins.structure);
    let mut grazings = Vec::new();
    let minimal = first.minimal_period;
    let dir = (to - from).signum();
    let mut step = opts.step.abs() * dir;
    let mut path = vec![point(from, &first)];
    let mut last: (f64, PeriodicOrbit<M::Dim>) = (from, first);
    let mut before: Option<(f64, DVector<f64>)> = None;
    // In the bisection: an orbit of another minimal period, or far from the stable end, is
    // not this branch.
    let solve_on_branch = |p: f64, template: &OVector<f64, M::Dim>, z: &DVector<f64>| {
        solve(p, template, z).and_then(|o| {
            if o.minimal_period != minimal || (&o.point - z).amax() > opts.max_correction {
                Err(StabilityError::InvalidOption {
                    field: "max_correction",
                    value: (&o.point - z).amax(),
                    hint: "Newton left the branch",
                })
            } else {
                Ok(o)
            }
        })
    };
    // Secant prediction of the point at p from the last two.
    let predict =
        |last: &(f64, PeriodicOrbit<M::Dim>), before: &Option<(f64, DVector<f64>)>, p: f64| {
            match before {
                Some((pb, zb)) if *pb != last.0 => {
                    let w = (p - last.0) / (last.0 - pb);
                    &last.1.point + (&last.1.point - zb) * w
                }
                _ => last.1.point.clone(),
            }
        };
    for _ in 0..opts.max_steps {
        if (last.0 - to) * dir >= 0.0 {
            return Ok(Continuation {
                loss: None,
                path,
                grazings,
            });
        }
        let p = if (last.0 + step - to) * dir > 0.0 {
            to
        } else {
            last.0 + step
        };
        let z = predict(&last, &before, p);
        // Another orbit (a jump, or one of a shorter period) is a failed step.
        let solved = solve(p, &last.1.state, &z).and_then(|o| {
            if o.minimal_period != minimal || (&o.point - &z).amax() > opts.max_correction {
                Err(StabilityError::InvalidOption {
                    field: "max_correction",
                    value: (&o.point - &z).amax(),
                    hint: "Newton left the branch",
                })
            } else {
                Ok(o)
            }
        });
        match solved {
            Ok(o) if !is_lost(&o, &structure) => {
                path.push(point(p, &o));
                before = Some((last.0, last.1.point.clone()));
                last = (p, o);
                step = opts.step.abs() * dir;
            }
            Ok(o) => {
                let (loss, beyond) = bisect(
                    &solve_on_branch,
                    last,
                    (p, Some(o)),
                    &structure,
                    opts.tolerance,
                );
                match beyond {
                    Some(next)
                        if opts.through_grazing
                            && loss.kind == LossKind::Grazing
                            && next.1.spectral_radius() < 1.0 =>
                    {
                        structure = canonical(&next.1.margins.structure);
                        path.push(point(next.0, &next.1));
                        grazings.push(loss);
                        before = None;
                        last = next;
                        step = opts.step.abs() * dir;
                    }
                    _ => {
                        return Ok(Continuation {
                            loss: Some(loss),
                            path,
                            grazings,
                        })
                    }
                }
            }
            Err(_) if step.abs() > opts.tolerance => step *= 0.5,
            Err(_) => {
                let (loss, _) = bisect(
                    &solve_on_branch,
                    last,
                    (p, None),
                    &structure,
                    opts.tolerance,
                );
                return Ok(Continuation {
                    loss: Some(loss),
                    path,
                    grazings,
                });
            }
        }
    }
    Err(StabilityError::InvalidOption {
        field: "max_steps",
        value: opts.max_steps as f64,
        hint: "the continuation did not reach `to`: allow more steps or a larger step",
    })
}

/// A branch that ends with a real multiplier above this is a fold (its multiplier reaches +1
/// at the end; within the bracket of `1e-8` it is above 0.99 for a square-root fold whose
/// multiplier moves like $1 - c\sqrt{\eta^{\ast} - \eta}$ with $c$ up to $10^2$).
const FOLD_MULTIPLIER: f64 = 0.95;

/// Bisects `[a, b]` (stable with the reference structure at `a`, not at `b`) to `tol`.
#[allow(clippy::type_complexity)]
fn bisect<D, S>(
    solve: &S,
    mut a: (f64, PeriodicOrbit<D>),
    mut b: (f64, Option<PeriodicOrbit<D>>),
    structure: &[&'static str],
    tol: f64,
) -> (StabilityLoss<D>, Option<(f64, PeriodicOrbit<D>)>)
where
    D: nalgebra::Dim,
    DefaultAllocator: VariationalAlloc<D>,
    S: Fn(f64, &OVector<f64, D>, &DVector<f64>) -> Result<PeriodicOrbit<D>, StabilityError>,
{
    let lost = |o: &PeriodicOrbit<D>| is_lost(o, structure);
    while (b.0 - a.0).abs() > tol {
        let mid = 0.5 * (a.0 + b.0);
        if mid == a.0 || mid == b.0 {
            break;
        }
        match solve(mid, &a.1.state, &a.1.point) {
            Ok(o) if !lost(&o) => a = (mid, o),
            Ok(o) => b = (mid, Some(o)),
            Err(_) => b = (mid, None),
        }
    }
    let grazing =
        b.1.as_ref()
            .is_some_and(|o| canonical(&o.margins.structure) != structure);
    let (kind, parameter) = match &b.1 {
        _ if grazing => (LossKind::Grazing, 0.5 * (a.0 + b.0)),
        Some(o) => {
            let critical = o
                .multipliers
                .first()
                .copied()
                .unwrap_or(Multiplier { re: 1.0, im: 0.0 });
            let (ra, rb) = (a.1.spectral_radius(), o.spectral_radius());
            let p = if rb > ra {
                a.0 + (1.0 - ra) / (rb - ra) * (b.0 - a.0)
            } else {
                0.5 * (a.0 + b.0)
            };
            (LossKind::Multiplier(CrossingKind::of(&critical, 1e-6)), p)
        }
        // The branch ends. With a real multiplier near +1 it is a fold; otherwise it ends at a
        // non-smooth point (a grazing or a regime boundary met tangentially) where the map is
        // not differentiable and Newton cannot follow it.
        None => {
            let near_one =
                a.1.multipliers
                    .iter()
                    .any(|m| m.is_real(1e-6) && m.re > FOLD_MULTIPLIER);
            let kind = if near_one {
                LossKind::Multiplier(CrossingKind::Fold)
            } else {
                LossKind::Grazing
            };
            (kind, 0.5 * (a.0 + b.0))
        }
    };
    let loss = StabilityLoss {
        parameter,
        bracket: (a.0, b.0),
        kind,
        beyond_structure: b.1.as_ref().map(|o| o.margins.structure.clone()),
        beyond: b.1.as_ref().map(|o| o.multipliers.clone()),
        orbit: a.1,
    };
    (loss, b.1.map(|o| (b.0, o)))
}

/// Whether an orbit is unstable or has another event structure than `structure`.
fn is_lost<D: nalgebra::Dim>(o: &PeriodicOrbit<D>, structure: &[&'static str]) -> bool
where
    DefaultAllocator: VariationalAlloc<D>,
{
    o.spectral_radius() >= 1.0 || canonical(&o.margins.structure) != structure
}
