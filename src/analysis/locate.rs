use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, OVector};

use super::bifurcation::orbit_at;
use super::{AnalysisError, OrbitError, PeriodTest, Periodicity};
use crate::hybrid::{ModelError, RotorModel, SimOptions};
use crate::numeric::{bisect, Side};

/// Settings of [`locate_period_change`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct LocatorOptions {
    /// Forcing periods discarded at each evaluation. Default 2000 (longer than a diagram's,
    /// because transients decay slowly near a bifurcation).
    pub transient: u64,
    /// Forcing periods recorded for the period test. Default 200.
    pub record: u64,
    /// Stop when the bracket is narrower than this. Default `5e-4` (3 decimals).
    pub resolution: f64,
    /// Integration options. Default [`SimOptions::default`].
    pub opts: SimOptions,
    /// The period test. Default [`PeriodTest::default`].
    pub period_test: PeriodTest,
}

/// Builders: each returns the options with one field changed.
impl LocatorOptions {
    /// With [`transient`](Self::transient) = `value`.
    #[must_use]
    pub fn with_transient(mut self, value: u64) -> Self {
        self.transient = value;
        self
    }

    /// With [`record`](Self::record) = `value`.
    #[must_use]
    pub fn with_record(mut self, value: u64) -> Self {
        self.record = value;
        self
    }

    /// With [`resolution`](Self::resolution) = `value`.
    #[must_use]
    pub fn with_resolution(mut self, value: f64) -> Self {
        self.resolution = value;
        self
    }

    /// With [`opts`](Self::opts) = `value`.
    #[must_use]
    pub fn with_opts(mut self, value: SimOptions) -> Self {
        self.opts = value;
        self
    }

    /// With [`period_test`](Self::period_test) = `value`.
    #[must_use]
    pub fn with_period_test(mut self, value: PeriodTest) -> Self {
        self.period_test = value;
        self
    }
}

impl Default for LocatorOptions {
    fn default() -> Self {
        LocatorOptions {
            transient: 2000,
            record: 200,
            resolution: 5e-4,
            opts: SimOptions::default(),
            period_test: PeriodTest::default(),
        }
    }
}

/// Two parameter values with different detected periods.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PeriodChange {
    /// The value on the reference side.
    pub from: f64,
    /// The other value (above or below `from`).
    pub to: f64,
    /// Periodicity at `from`.
    pub at_from: Periodicity,
    /// Periodicity at `to` (not [agreeing](Periodicity::agrees_with) with `at_from`).
    pub at_to: Periodicity,
}

impl PeriodChange {
    /// The midpoint of the bracket, the estimated bifurcation value.
    pub fn value(&self) -> f64 {
        0.5 * (self.from + self.to)
    }
}

/// The bracket found by [`locate_period_change`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LocatedChange {
    /// The final bracket: `at_from` is the periodicity at the initial `from`, and
    /// `|to − from| ≤ resolution`.
    pub bracket: PeriodChange,
    /// Simulations run.
    pub evaluations: usize,
}

impl LocatedChange {
    /// The midpoint of the bracket, the located bifurcation value.
    pub fn value(&self) -> f64 {
        self.bracket.value()
    }
}

/// Locates by bisection ([`numeric::bisect`](crate::numeric::bisect)) where the detected period changes between `from` and `to`, for the
/// model family `build` started by `start` (see [`bifurcation`](super::bifurcation()) for the
/// two closures; `start` always receives `None` here).
///
/// Each evaluation runs the model at one value from its reset state (every evaluation
/// independent), discards `config.transient` periods and tests the next `config.record`. The
/// periodicity at `from` is the reference: the bracket is halved, keeping the half whose
/// `from` end has the reference periodicity and whose `to` end does not, until it is narrower
/// than `config.resolution`. `to` may lie below or above `from`, so the search can find where a
/// periodicity ends when coming from either side. If several changes lie between the ends, one
/// of them is found (not necessarily the nearest).
///
/// # Errors
/// [`OrbitError::NoChange`] if `from` and `to` have the same periodicity
/// ([`Periodicity::agrees_with`]); the builder's,
/// the start rule's, the driver's or the period test's error at any evaluation;
/// [`OrbitError::Analysis`] for equal or non-finite ends or a bad resolution.
pub fn locate_period_change<M, E, B, S>(
    from: f64,
    to: f64,
    build: B,
    start: S,
    config: &LocatorOptions,
) -> Result<LocatedChange, OrbitError<M::Dim, E>>
where
    M: RotorModel,
    B: Fn(f64) -> Result<M, E>,
    S: Fn(&M, Option<&OVector<f64, M::Dim>>) -> Result<OVector<f64, M::Dim>, ModelError>,
    DefaultAllocator: Allocator<M::Dim>,
{
    check_ends(from, to, config)?;
    let mut evaluations = 0;
    let mut classify = |v: f64| -> Result<Periodicity, OrbitError<M::Dim, E>> {
        evaluations += 1;
        orbit_at(
            &build,
            &start,
            v,
            None,
            config.transient,
            config.record,
            &config.opts,
            &config.period_test,
        )
        .map(|m| m.periodicity)
    };
    let at_from = classify(from)?;
    let mut at_to = classify(to)?;
    if at_from.agrees_with(&at_to) {
        return Err(OrbitError::NoChange(Box::new(PeriodChange {
            from,
            to,
            at_from,
            at_to,
        })));
    }
    let found = bisect(
        from,
        to,
        config.resolution,
        usize::MAX,
        |m| -> Result<Side, OrbitError<M::Dim, E>> {
            let pm = classify(m)?;
            Ok(if pm.agrees_with(&at_from) {
                Side::Near
            } else {
                at_to = pm;
                Side::Far
            })
        },
    )?;
    let (a, b) = (found.near, found.far);
    Ok(LocatedChange {
        bracket: PeriodChange {
            from: a,
            to: b,
            at_from,
            at_to,
        },
        evaluations,
    })
}

/// The ends of [`locate_period_change`] finite and distinct, its resolution finite and > 0.
fn check_ends(from: f64, to: f64, config: &LocatorOptions) -> Result<(), AnalysisError> {
    if !(from.is_finite() && to.is_finite() && from != to) {
        return Err(AnalysisError::InvalidValue {
            name: "to",
            value: to,
            expected: "finite and different from a finite `from`",
        });
    }
    if !(config.resolution.is_finite() && config.resolution > 0.0) {
        return Err(AnalysisError::InvalidValue {
            name: "resolution",
            value: config.resolution,
            expected: "a finite number > 0",
        });
    }
    Ok(())
}
