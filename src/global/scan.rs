use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, OVector};

use super::attractor::{find_attractor, Attractor, AttractorOptions, MatchOptions};
use super::catalogue::Catalogue;
use super::failure::PointFailure;
use super::runner::{run_points, PointResults, RunOptions};
use super::store::{check_same, Manifest, StoreError, SweepStore, MANIFEST_FILE};
use crate::analysis::{linspace, AnalysisError, Progress};
use crate::hybrid::RotorModel;

/// A rectangular grid of points $(x_i, y_j)$. Point `k` is `(x[k % nx], y[k / nx])`: rows of
/// constant `y`, `x` fastest.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Grid2 {
    /// Values along the horizontal axis.
    pub x: Vec<f64>,
    /// Values along the vertical axis.
    pub y: Vec<f64>,
}

impl Grid2 {
    /// The grid of `x` by `y`.
    ///
    /// # Errors
    /// [`AnalysisError::InvalidCount`] for an empty axis, [`AnalysisError::InvalidValue`] for
    /// a non-finite value.
    pub fn new(x: Vec<f64>, y: Vec<f64>) -> Result<Self, AnalysisError> {
        for (name, axis) in [("x", &x), ("y", &y)] {
            if axis.is_empty() {
                return Err(AnalysisError::InvalidCount {
                    name,
                    value: 0,
                    expected: "at least one value per axis",
                });
            }
            if let Some(&v) = axis.iter().find(|v| !v.is_finite()) {
                return Err(AnalysisError::InvalidValue {
                    name,
                    value: v,
                    expected: "finite grid values",
                });
            }
        }
        Ok(Grid2 { x, y })
    }

    /// `nx` values evenly spaced over `[x0, x1]` by `ny` over `[y0, y1]` ([`linspace`]).
    ///
    /// # Errors
    /// As [`linspace`].
    pub fn linspace(
        (x0, x1, nx): (f64, f64, usize),
        (y0, y1, ny): (f64, f64, usize),
    ) -> Result<Self, AnalysisError> {
        Grid2::new(linspace(x0, x1, nx)?, linspace(y0, y1, ny)?)
    }

    /// Number of points.
    pub fn len(&self) -> usize {
        self.x.len() * self.y.len()
    }

    /// Whether the grid has no point (never, for a grid built by [`Grid2::new`]).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The point of index `k`.
    pub fn point(&self, k: usize) -> [f64; 2] {
        let nx = self.x.len();
        [self.x[k % nx], self.y[k / nx]]
    }

    /// Every point, in index order.
    pub fn points(&self) -> Vec<[f64; 2]> {
        (0..self.len()).map(|k| self.point(k)).collect()
    }
}

/// The outcome of [`scan_grid`]: the grid and one attractor (or failure) per point.
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GridScan {
    /// The grid.
    pub grid: Grid2,
    /// One slot per grid point, in index order.
    pub results: PointResults<Attractor, PointFailure>,
}

impl GridScan {
    /// The distinct attractors and each point's label ([`Catalogue::new`]).
    pub fn catalogue(&self, tol: &MatchOptions) -> Catalogue {
        Catalogue::new(&self.results.results, tol)
    }

    /// Each point's detected period: `Some(p)`, `Some(0)` for not periodic, `None` for a
    /// failed or missing point.
    pub fn periods(&self) -> Vec<Option<usize>> {
        self.results
            .results
            .iter()
            .map(|r| match r {
                Some(Ok(a)) => Some(a.period().unwrap_or(0)),
                _ => None,
            })
            .collect()
    }

    /// Each point's contacts per forcing period (NaN for a failed or missing point).
    pub fn contacts_per_period(&self) -> Vec<f64> {
        self.stat(|a| a.stats.contacts_per_period)
    }

    /// Each point's value of `f` (NaN for a failed or missing point).
    pub fn stat(&self, f: impl Fn(&Attractor) -> f64) -> Vec<f64> {
        self.results
            .results
            .iter()
            .map(|r| match r {
                Some(Ok(a)) => f(a),
                _ => f64::NAN,
            })
            .collect()
    }
}

impl Manifest {
    /// The manifest of a scan of `kind` over `grid` with `config`: the grid's points, and
    /// every field of `config` as the settings (its `Serialize`). `description` is the
    /// caller's: what the scan cannot see, e.g. the parameters its `setup` uses (any
    /// `Serialize` value, `&()` for none).
    ///
    /// # Errors
    /// [`StoreError::Encode`] if the description cannot be written as JSON.
    pub fn scan<D: serde::Serialize + ?Sized>(
        kind: &str,
        description: &D,
        grid: &Grid2,
        config: &AttractorOptions,
    ) -> Result<Self, StoreError> {
        Manifest::new(kind, description, &grid.points())?.with_settings(config)
    }
}

impl SweepStore {
    /// Opens the folder `dir` for a scan ([`scan_grid`]) of `kind` over `grid` with
    /// `config`, described by `description` ([`Manifest::scan`]): the folder records the
    /// grid and every setting of `config`, and a resume with another grid or another setting
    /// is refused.
    ///
    /// # Errors
    /// As [`Manifest::scan`] and [`SweepStore::open_manifest`].
    pub fn open_scan<D: serde::Serialize + ?Sized>(
        dir: impl AsRef<std::path::Path>,
        kind: &str,
        description: &D,
        grid: &Grid2,
        config: &AttractorOptions,
    ) -> Result<Self, StoreError> {
        SweepStore::open_manifest(dir, Manifest::scan(kind, description, grid, config)?)
    }
}

/// Checks that `store` (if any) records the scan's `config` ([`SweepStore::open_scan`]).
pub(crate) fn check_settings(
    store: Option<&SweepStore>,
    config: &AttractorOptions,
) -> Result<(), StoreError> {
    let Some(s) = store else { return Ok(()) };
    let path = s.dir().join(MANIFEST_FILE);
    if s.manifest().settings.is_null() {
        return Err(StoreError::SettingsNotRecorded {
            path,
            needed: "AttractorOptions",
        });
    }
    let given = serde_json::to_value(config).map_err(|e| StoreError::Encode {
        what: "the settings".into(),
        message: e.to_string(),
    })?;
    check_same(&path, "settings", &given, &s.manifest().settings)
}

/// Builds the model and initial state at `point` with `setup` and identifies the attractor.
pub fn attractor_at<P, M, S>(
    setup: &S,
    point: &P,
    config: &AttractorOptions,
) -> Result<Attractor, PointFailure>
where
    M: RotorModel,
    S: Fn(&P) -> Result<(M, OVector<f64, M::Dim>), PointFailure>,
    DefaultAllocator: Allocator<M::Dim>,
{
    let (model, y0) = setup(point)?;
    Ok(find_attractor(&model, &y0, config)?)
}

/// Runs [`find_attractor`] at every point of `grid`, the model and initial state built by
/// `setup` (see the [module docs](super)), in parallel, writing each outcome to `store` as it
/// finishes and skipping the points it already holds ([`run_points`]).
///
/// A folder must be opened for this scan with [`SweepStore::open_scan`]: it records the grid
/// and every setting of `config`, and a scan with another grid or another setting is refused
/// before any point runs, so that a resumed scan never mixes results of two settings.
///
/// # Errors
/// As [`run_points`]: only for the folder or the configuration; a point's failure is its
/// outcome. [`StoreError::SettingMismatch`] (naming the setting) if `config` is not the
/// folder's, [`StoreError::Mismatch`] if `grid` is not, [`StoreError::SettingsNotRecorded`]
/// for a folder opened with [`SweepStore::open`].
///
/// # Example
///
/// The basins of the paper's Fig. 8a model at $\eta = 2.2$ on a coarse grid of $(x_0,
/// x_0^\prime)$, without a folder:
///
/// ```
/// use jeffcott::global::{scan_grid, AttractorOptions, Grid2, MatchOptions, RunOptions};
/// use jeffcott::paper::{BasinPlane, StartPlane};
/// use jeffcott::params::Preset;
///
/// let plane = BasinPlane::new(Preset::Fig8a.params().with_eta(2.2), StartPlane::XVx);
/// let grid = Grid2::linspace((0.2, 0.8, 3), (-0.5, 0.5, 2))?;
/// let config = AttractorOptions::default().with_transient(400).with_max_transient(400);
/// let scan = scan_grid(&grid, plane.setup(), &config, None, &RunOptions::default(), None)?;
/// let catalogue = scan.catalogue(&MatchOptions::default());
/// assert!(catalogue.entries.iter().all(|e| e.attractor.period().is_some()));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn scan_grid<M, S>(
    grid: &Grid2,
    setup: S,
    config: &AttractorOptions,
    store: Option<&SweepStore>,
    run: &RunOptions,
    progress: Option<&dyn Progress>,
) -> Result<GridScan, StoreError>
where
    M: RotorModel,
    S: Fn(&[f64; 2]) -> Result<(M, OVector<f64, M::Dim>), PointFailure> + Sync,
    DefaultAllocator: Allocator<M::Dim>,
{
    check_settings(store, config)?;
    let points = grid.points();
    let results = run_points(
        &points,
        store,
        run,
        |p| attractor_at(&setup, p, config),
        progress,
    )?;
    Ok(GridScan {
        grid: grid.clone(),
        results,
    })
}
