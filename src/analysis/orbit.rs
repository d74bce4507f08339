use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, OVector};

use super::{AnalysisError, PeriodTest, Periodicity};
use crate::hybrid::{
    simulate, OutputPlan, RotorModel, SimError, SimErrorKind, SimOptions, SimStats, StrobePoint,
    Trajectory,
};

/// A stroboscopic orbit after a transient.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct StrobeOrbit<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// The recorded points, `k = transient + 1 ..= transient + record`.
    pub points: Vec<StrobePoint<D>>,
    /// The state at the end of the run (`k = transient + record`), to continue from.
    pub last: OVector<f64, D>,
    /// Work done by the run.
    pub stats: SimStats,
    /// The model's [`RotorModel::state_scale`]: the units in which [`StrobeOrbit::period`]
    /// tests the points.
    pub scale: OVector<f64, D>,
}

impl<D: Dim> StrobeOrbit<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// The recorded states.
    pub fn states(&self) -> Vec<OVector<f64, D>> {
        self.points.iter().map(|p| p.y.clone()).collect()
    }

    /// The points as `(component i, component j)` pairs, e.g. `(0, 2)` for the paper's
    /// $(x, x^\prime)$. Components out of range give NaN.
    pub fn pairs(&self, i: usize, j: usize) -> Vec<(f64, f64)> {
        let get = |y: &OVector<f64, D>, c: usize| y.get(c).copied().unwrap_or(f64::NAN);
        self.points
            .iter()
            .map(|p| (get(&p.y, i), get(&p.y, j)))
            .collect()
    }

    /// The period of the recorded states under `test`, in units of the model's scale
    /// ([`StrobeOrbit::scale`], [`PeriodTest::detect_scaled`]).
    ///
    /// # Errors
    /// As [`PeriodTest::detect_scaled`].
    pub fn period(&self, test: &PeriodTest) -> Result<Periodicity, AnalysisError> {
        let slices: Vec<&[f64]> = self.points.iter().map(|p| p.y.as_slice()).collect();
        test.detect_slices_scaled(&slices, self.scale.as_slice())
    }

    /// The orbit with its period under `test`.
    ///
    /// # Errors
    /// As [`PeriodTest::detect`].
    pub fn classify(self, test: &PeriodTest) -> Result<PoincareMap<D>, AnalysisError> {
        let periodicity = self.period(test)?;
        Ok(PoincareMap {
            orbit: self,
            periodicity,
        })
    }
}

/// A stroboscopic orbit and its detected period.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(
    feature = "serde",
    serde(bound(
        serialize = "nalgebra::OVector<f64, D>: serde::Serialize",
        deserialize = "nalgebra::OVector<f64, D>: serde::Deserialize<'de>"
    ))
)]
pub struct PoincareMap<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    /// The recorded orbit.
    pub orbit: StrobeOrbit<D>,
    /// Its detected period.
    pub periodicity: Periodicity,
}

/// Runs `model` from `y0` at $t = 0$ for `transient + record` forcing periods and keeps the
/// stroboscopic points of the last `record` periods (see the [module docs](super)).
///
/// # Errors
/// The driver's [`SimError`]; `record = 0` and a `transient + record` that overflows `u64`
/// are invalid options ([`SimErrorKind::InvalidOption`]), not an empty orbit.
pub fn strobe_orbit<M: RotorModel>(
    model: &M,
    y0: &OVector<f64, M::Dim>,
    transient: u64,
    record: u64,
    opts: &SimOptions,
) -> Result<StrobeOrbit<M::Dim>, SimError<M::Dim>>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    let invalid = |field, value, hint| SimError {
        kind: SimErrorKind::InvalidOption { field, value, hint },
        t: 0.0,
        y: y0.clone(),
        stats: Box::default(),
    };
    if record == 0 {
        return Err(invalid("record", 0.0, "record at least one forcing period"));
    }
    let Some(last_k) = transient.checked_add(record) else {
        return Err(invalid(
            "record",
            record as f64,
            "transient + record must fit in a u64",
        ));
    };
    let plan = OutputPlan::strobe(model.forcing_period(), transient + 1, last_k);
    let mut traj = Trajectory::default();
    let stats = simulate(model, 0.0, y0, &plan, opts, &mut traj)?;
    let last = traj
        .strobe
        .last()
        .map_or_else(|| y0.clone(), |s| s.y.clone());
    Ok(StrobeOrbit {
        points: traj.strobe,
        last,
        stats,
        scale: model.state_scale(),
    })
}
