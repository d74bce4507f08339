use std::ops::Range;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

use super::{
    strobe_orbit, sweep, AnalysisError, OrbitError, PeriodChange, PeriodTest, Periodicity,
    PoincareMap, Progress, StrobeOrbit, SweepOptions,
};
use crate::hybrid::{ModelError, RotorModel, SimOptions};

/// Settings of a [`bifurcation`] sweep.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub struct BifurcationOptions {
    /// Forcing periods discarded at each value. Default 300 (the paper's).
    pub transient: u64,
    /// Forcing periods recorded at each value (at least 1). Default 150 (the paper's).
    pub record: u64,
    /// Reset mode or carry-over chunks, and threads. Default reset, global pool.
    pub sweep: SweepOptions,
    /// Integration options. Default: [`SimOptions::default`].
    pub opts: SimOptions,
    /// Period test of each column. Default [`PeriodTest::default`].
    pub period_test: PeriodTest,
}

/// Builders: each returns the options with one field changed.
impl BifurcationOptions {
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

    /// With [`sweep`](Self::sweep) = `value`.
    #[must_use]
    pub fn with_sweep(mut self, value: SweepOptions) -> Self {
        self.sweep = value;
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

impl Default for BifurcationOptions {
    fn default() -> Self {
        BifurcationOptions {
            transient: 300,
            record: 150,
            sweep: SweepOptions::reset(),
            opts: SimOptions::default(),
            period_test: PeriodTest::default(),
        }
    }
}

/// One column of a bifurcation diagram: the orbit recorded at one parameter value.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct Column<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// The parameter value.
    pub value: f64,
    /// Whether this value started from the reset state (chunk start, reset mode, or after a
    /// failure) rather than from the previous value's final state.
    pub from_reset: bool,
    /// The recorded stroboscopic orbit.
    pub orbit: StrobeOrbit<D>,
    /// Its detected period.
    pub periodicity: Periodicity,
}

/// A bifurcation diagram: one column (or the error that prevented it) per parameter value.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize, E: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>, E: serde::Deserialize<'de>"
    ))
)]
pub struct Bifurcation<D: Dim, E>
where
    DefaultAllocator: Allocator<D>,
{
    /// The parameter values, in order.
    pub values: Vec<f64>,
    /// One entry per value: the column, or why it failed.
    pub columns: Vec<Result<Column<D>, OrbitError<D, E>>>,
    /// The chains of carried state (one per value in reset mode).
    pub chains: Vec<Range<usize>>,
    /// Worker threads used (does not affect the results).
    pub threads: usize,
}

/// A failed value of a [`Bifurcation`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Failure<'a, D: Dim, E>
where
    DefaultAllocator: Allocator<D>,
{
    /// The parameter value.
    pub value: f64,
    /// Why it failed.
    pub error: &'a OrbitError<D, E>,
}

impl<D: Dim, E> Bifurcation<D, E>
where
    DefaultAllocator: Allocator<D>,
{
    /// `(value, component c)` for every recorded point of every successful column (e.g.
    /// `c = 0` for the paper's $x_r$): the points of the diagram.
    pub fn points(&self, c: usize) -> Vec<(f64, f64)> {
        let mut out = Vec::new();
        for col in self.columns.iter().flatten() {
            out.extend(
                col.orbit
                    .points
                    .iter()
                    .map(|p| (col.value, p.y.get(c).copied().unwrap_or(f64::NAN))),
            );
        }
        out
    }

    /// The failed values, in order.
    pub fn failures(&self) -> Vec<Failure<'_, D, E>> {
        self.values
            .iter()
            .zip(&self.columns)
            .filter_map(|(v, c)| c.as_ref().err().map(|error| Failure { value: *v, error }))
            .collect()
    }

    /// Where the detected periodicity differs from the previous successful value's
    /// ([`Periodicity::agrees_with`]: two not-converged columns with the same lags are no
    /// change, a not-converged column between periodic ones is two changes): a coarse map of
    /// the bifurcations (`from` the previous value, `to` the value), to refine with
    /// [`locate_period_change`](super::locate_period_change).
    pub fn period_changes(&self) -> Vec<PeriodChange> {
        let mut out = Vec::new();
        let mut prev: Option<(f64, Periodicity)> = None;
        for col in self.columns.iter().flatten() {
            if let Some((v, p)) = prev
                && !p.agrees_with(&col.periodicity)
            {
                out.push(PeriodChange {
                    from: v,
                    to: col.value,
                    at_from: p,
                    at_to: col.periodicity,
                });
            }
            prev = Some((col.value, col.periodicity));
        }
        out
    }
}

/// The start rule "reset runs start from `y0`, carried states are used as they are" (see the
/// [module docs](super)).
#[allow(clippy::type_complexity)] // the closure's signature, spelled out for the reader
pub fn start_from<D: Dim, M>(
    y0: OVector<f64, D>,
) -> impl Fn(&M, Option<&OVector<f64, D>>) -> Result<OVector<f64, D>, ModelError> + Sync + Clone
where
    DefaultAllocator: Allocator<D>,
    OVector<f64, D>: Sync,
{
    move |_: &M, carried: Option<&OVector<f64, D>>| Ok(carried.unwrap_or(&y0).clone())
}

/// Builds the model at `value`, picks its start state, records and classifies the orbit.
#[allow(clippy::too_many_arguments)]
pub(super) fn orbit_at<M, E, B, S>(
    build: &B,
    start: &S,
    value: f64,
    carried: Option<&OVector<f64, M::Dim>>,
    transient: u64,
    record: u64,
    opts: &SimOptions,
    test: &PeriodTest,
) -> Result<PoincareMap<M::Dim>, OrbitError<M::Dim, E>>
where
    M: RotorModel,
    B: Fn(f64) -> Result<M, E>,
    S: Fn(&M, Option<&OVector<f64, M::Dim>>) -> Result<OVector<f64, M::Dim>, ModelError>,
    DefaultAllocator: Allocator<M::Dim>,
{
    let model = build(value).map_err(OrbitError::Build)?;
    let y0 = start(&model, carried)?;
    let orbit = strobe_orbit(&model, &y0, transient, record, opts)?;
    Ok(orbit.classify(test)?)
}

/// A bifurcation diagram: for each of `values`, build the model (`build`), start it (`start`,
/// see the [module docs](super)), discard `config.transient` periods, record `config.record`
/// stroboscopic points and detect their period.
///
/// Runs on [`sweep()`]: in reset mode every value starts from the reset state; in carry-over
/// mode the final state at one value starts the next, within contiguous chunks that each
/// start from the reset state and run in parallel. The chunking depends only on the number of
/// values and `chunks`, never on the thread count, so **the results are bitwise identical for
/// any number of threads** (with `chunks = 1` the whole sweep is one serial chain). A failure
/// at one value (a model that cannot be built, a failed run) is recorded in its column and the
/// sweep goes on; in carry-over mode the next value starts from the reset state. `progress` is
/// called once per value.
///
/// # Errors
/// Only for a bad sweep configuration ([`AnalysisError`] from [`sweep()`]).
///
/// # Example
///
/// A user's model family: here the paper's model built from its parameters, swept over the
/// ring stiffness, every value from rest.
///
/// ```
/// use jeffcott::analysis::{bifurcation, start_from, BifurcationOptions};
/// use jeffcott::params::Preset;
/// use jeffcott::{JeffcottModel, State};
///
/// let base = Preset::Fig8a.params().with_eta(3.0);
/// let build = |k: f64| JeffcottModel::new(base.with_stiffness(k));
/// let config = BifurcationOptions::default().with_transient(50).with_record(8);
/// let diagram = bifurcation(&[20.0, 30.0], build, start_from(State::zeros()), &config, None)?;
/// assert_eq!(diagram.points(0).len(), 16);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn bifurcation<M, E, B, S>(
    values: &[f64],
    build: B,
    start: S,
    config: &BifurcationOptions,
    progress: Option<&dyn Progress>,
) -> Result<Bifurcation<M::Dim, E>, AnalysisError>
where
    M: RotorModel,
    E: Send,
    B: Fn(f64) -> Result<M, E> + Sync,
    S: Fn(&M, Option<&OVector<f64, M::Dim>>) -> Result<OVector<f64, M::Dim>, ModelError> + Sync,
    DefaultAllocator: Allocator<M::Dim>,
    OVector<f64, M::Dim>: Send,
{
    type Carried<M> = OVector<f64, <M as RotorModel>::Dim>;
    type Outcome<M, E> =
        Result<(Column<<M as RotorModel>::Dim>, Carried<M>), OrbitError<<M as RotorModel>::Dim, E>>;
    let runner = |v: &f64, carried: Option<Carried<M>>| -> Outcome<M, E> {
        let PoincareMap { orbit, periodicity } = orbit_at(
            &build,
            &start,
            *v,
            carried.as_ref(),
            config.transient,
            config.record,
            &config.opts,
            &config.period_test,
        )?;
        let last = orbit.last.clone();
        let column = Column {
            value: *v,
            from_reset: carried.is_none(),
            orbit,
            periodicity,
        };
        Ok((column, last))
    };
    let out = sweep(values, &config.sweep, runner, progress)?;
    Ok(Bifurcation {
        values: values.to_vec(),
        columns: out.results,
        chains: out.chains,
        threads: out.threads,
    })
}
