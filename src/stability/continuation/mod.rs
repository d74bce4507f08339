//! Following periodic orbits along a parameter: one continuation core, one Newton, one locator
//! of special points.
//!
//! The parameter enters through a closure that builds the model at each value (any parameter,
//! any model). A period-$n$ orbit is a zero of $F(z, p) = P^n_p(z) - z$, $z$ the
//! non-algebraic components at the section.
//!
//! * [`continue_orbit`] follows the branch in its **pseudo-arclength** (through folds), with
//!   its stability, and locates every special point on the way; [`switch_at_flip`] starts the
//!   period-$2n$ branch at a flip. The method is in [`arclength`](mod@arclength).
//! * [`locate_loss`] is its **natural-parameter** case, for the question "where does this
//!   stable orbit stop being stable?": steps in the parameter itself (the constraint row of
//!   the corrector is $e_p$), each orbit found by [`periodic_orbit`](super::periodic_orbit),
//!   until the first loss of stability, which it brackets and reports with the orbit there, or
//!   a [`BranchFailure`] with its error. The method is in [`loss`](mod@loss).
//!
//! Both use the one Newton ([`super::newton`]) with its relative-plus-absolute
//! stopping rule on the model's [`state_scale`](crate::hybrid::RotorModel::state_scale), and
//! the one locator: a special point is bracketed between two orbits and the bracket bisected
//! (by the crate's one bisection, [`crate::numeric::bisect`]) until it is narrower than the options' `bracket_width` (a width, in the
//! parameter's units; the residual tolerances are `atol`/`rtol`).
//!
//! **The special points, one definition.** The multipliers outside the unit circle are
//! counted in three classes: a change of the count of real positive ones is a
//! [**fold**](SpecialKind::Fold) (a real multiplier through $+1$), of real negative ones a
//! [**flip**](SpecialKind::Flip) (through $-1$), of complex ones a
//! [**Neimark–Sacker**](SpecialKind::NeimarkSacker) bifurcation. A change of the orbit's
//! **event structure** (the guards crossed over one orbit, compared up to a rotation) is a
//! [**grazing**](SpecialKind::Grazing): the margin of a contact onset (or of a regime boundary
//! in contact) going to zero, a contact gained or lost; the multipliers do not announce it.
//! The contacts per orbit are the events on guards the model calls contact onsets
//! ([`RotorModel::is_contact_onset`](crate::hybrid::RotorModel::is_contact_onset)).

pub mod arclength;
pub mod loss;

pub use arclength::{
    continue_orbit, switch_at_flip, Branch, BranchEnd, BranchPoint, ContinuationOptions,
    SpecialPoint,
};
pub use loss::{
    locate_loss, BranchFailure, Continuation, ContinuationPoint, LossOptions, StabilityLoss,
};

use super::floquet::{CrossingKind, Multiplier};
use super::StabilityError;

/// What a special point is (module docs).
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
    /// disappears, the margin of its event going to zero.
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

impl From<CrossingKind> for SpecialKind {
    fn from(k: CrossingKind) -> Self {
        match k {
            CrossingKind::Flip => SpecialKind::Flip,
            CrossingKind::Fold => SpecialKind::Fold,
            CrossingKind::NeimarkSacker => SpecialKind::NeimarkSacker,
        }
    }
}

/// A multiplier is real when its imaginary part is below this times its modulus.
const REAL: f64 = 1e-7;

/// The multipliers outside the unit circle by class: real positive (fold), real negative
/// (flip), complex (Neimark–Sacker).
pub(crate) fn counts(m: &[Multiplier]) -> [usize; 3] {
    let mut c = [0; 3];
    for x in m.iter().filter(|x| x.modulus() > 1.0) {
        let class = match (x.is_real(REAL), x.re > 0.0) {
            (true, true) => 0,
            (true, false) => 1,
            (false, _) => 2,
        };
        c[class] += 1;
    }
    c
}

/// The kinds of multiplier crossing between two sets of multipliers (module docs), in the
/// order fold, flip, Neimark–Sacker.
pub(crate) fn crossings(a: &[Multiplier], b: &[Multiplier]) -> Vec<SpecialKind> {
    let (ca, cb) = (counts(a), counts(b));
    [
        SpecialKind::Fold,
        SpecialKind::Flip,
        SpecialKind::NeimarkSacker,
    ]
    .into_iter()
    .zip(ca.iter().zip(cb.iter()))
    .filter(|(_, (x, y))| x != y)
    .map(|(k, _)| k)
    .collect()
}

/// The largest real positive multiplier (0 if none): how close a branch is to a fold.
pub(crate) fn largest_real_positive(m: &[Multiplier]) -> f64 {
    m.iter()
        .filter(|m| m.is_real(REAL) && m.re > 0.0)
        .map(|m| m.re)
        .fold(0.0, f64::max)
}

/// The event structure up to a rotation: its least rotation in lexical order.
pub(crate) fn canonical(structure: &[&'static str]) -> Vec<&'static str> {
    (0..structure.len().max(1))
        .map(|r| {
            let mut v = structure.to_vec();
            v.rotate_left(r.min(structure.len()));
            v
        })
        .min()
        .unwrap_or_default()
}

/// The model at `p`, or why the builder could not make it.
fn model<B, M, E>(build: &B, p: f64) -> Result<M, StabilityError>
where
    B: Fn(f64) -> Result<M, E>,
    E: std::fmt::Display,
{
    build(p).map_err(|e| StabilityError::Model {
        parameter: p,
        reason: e.to_string(),
    })
}
