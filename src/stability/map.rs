use nalgebra::{DMatrix, DVector, DefaultAllocator, Dim, Dyn, OMatrix, OVector};

use super::augmented::{propagate, LinearEvent};
use super::error::StabilityError;
use crate::hybrid::{
    simulate, HybridObserver, OutputPlan, SimOptions, SimStats, StrobePoint, Variational,
    VariationalAlloc,
};

/// The stroboscopic map $P^n$ of a model ([the stroboscopic map](crate::stability#the-stroboscopic-map)).
///
/// ```
/// use jeffcott::hybrid::SimOptions;
/// use jeffcott::paper::{JeffcottModel, State};
/// use jeffcott::params::Preset;
/// use jeffcott::stability::StroboscopicMap;
///
/// // The Jacobian from the variational equations against central differences of the map
/// // itself (an independent method), at the point one period after rest.
/// let model = JeffcottModel::new(Preset::Fig8a.params().with_eta(2.0))?;
/// let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-14);
/// let map = StroboscopicMap::new(&model, 1, opts)?;
/// let y = map.advance(&State::zeros())?.y;
/// let lin = map.linearize(&y)?;
/// let (z, h) = (map.reduce(&y), 1e-6);
/// for j in 0..z.len() {
///     let mut dz = z.clone() * 0.0;
///     dz[j] = h;
///     let plus = map.reduce(&map.advance(&map.state(&y, &(&z + &dz)))?.y);
///     let minus = map.reduce(&map.advance(&map.state(&y, &(&z - &dz)))?.y);
///     let column = (plus - minus) / (2.0 * h);
///     assert!((column - lin.jacobian.column(j)).amax() < 1e-5, "column {j}");
/// }
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy)]
pub struct StroboscopicMap<'a, M> {
    model: &'a M,
    periods: u64,
    opts: SimOptions,
}

/// $P^n$ of a full state.
#[derive(Debug, Clone, PartialEq)]
pub struct Advanced<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The state $n$ periods later.
    pub y: OVector<f64, D>,
    /// Its mode label ([`RotorModel::mode_label`](crate::hybrid::RotorModel::mode_label)).
    pub label: u8,
    /// Work done.
    pub stats: SimStats,
}

/// $P^n$ and its Jacobian at a point.
#[derive(Debug, Clone, PartialEq)]
pub struct Linearization<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The full state $n$ periods later.
    pub y: OVector<f64, D>,
    /// Its mode label.
    pub label: u8,
    /// $P^n(z)$ on the non-algebraic components.
    pub value: DVector<f64>,
    /// $DP^n(z)\thinspace Q$ for the directions $Q$ asked for (the Jacobian itself for
    /// [`StroboscopicMap::linearize`]).
    pub jacobian: DMatrix<f64>,
    /// Every event crossed, with its crossing margin.
    pub events: Vec<LinearEvent>,
    /// How far the sections at the start and at the end are from closing the map on $z$
    /// ([`Variational::section_openness`]); 0 for a closed map.
    pub openness: [f64; 2],
    /// Work done.
    pub stats: SimStats,
}

impl<D: nalgebra::Dim> Linearization<D>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The smallest crossing margin over the events (1 without events): below
    /// [`GRAZING_MARGIN`](super::GRAZING_MARGIN) an event was grazing and the Jacobian is that
    /// of a map that is not smooth there.
    pub fn min_margin(&self) -> f64 {
        self.events.iter().map(|e| e.margin).fold(1.0, f64::min)
    }
}

struct LastStrobe<D: nalgebra::Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    point: Option<StrobePoint<D>>,
}

impl<D: nalgebra::Dim> HybridObserver<D> for LastStrobe<D>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    fn on_strobe(&mut self, point: &StrobePoint<D>) {
        self.point = Some(point.clone());
    }
}

impl<'a, M> StroboscopicMap<'a, M>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    /// $P^n$ of `model` with `periods` $= n \ge 1$, runs with `opts`.
    ///
    /// # Errors
    /// [`StabilityError::InvalidOption`] for `periods = 0`.
    pub fn new(model: &'a M, periods: u64, opts: SimOptions) -> Result<Self, StabilityError> {
        if periods == 0 {
            return Err(StabilityError::InvalidOption {
                field: "periods",
                value: 0.0,
                hint: "the map advances at least one forcing period",
            });
        }
        Ok(Self {
            model,
            periods,
            opts,
        })
    }

    /// The model.
    pub fn model(&self) -> &'a M {
        self.model
    }

    /// $n$.
    pub fn periods(&self) -> u64 {
        self.periods
    }

    /// The simulation options.
    pub fn options(&self) -> &SimOptions {
        &self.opts
    }

    /// Indices of the non-algebraic components (those $z$ holds), in order.
    pub fn components(&self) -> Vec<usize> {
        (0..self.model.dim().value())
            .filter(|&i| !self.model.is_algebraic_variation(i))
            .collect()
    }

    /// $z$: the non-algebraic components of a full state.
    pub fn reduce(&self, y: &OVector<f64, M::Dim>) -> DVector<f64> {
        let idx = self.components();
        reduce_with(&idx, y.as_slice())
    }

    /// The full state at the section for `z`, from a `template` state there
    /// ([`Variational::section_state`]).
    pub fn state(&self, template: &OVector<f64, M::Dim>, z: &DVector<f64>) -> OVector<f64, M::Dim> {
        self.model.section_state(0.0, template, z.as_slice())
    }

    /// $P^n$ of the full state `y` (at $\tau = 0$), without linearisation.
    ///
    /// # Errors
    /// [`StabilityError::Simulation`] when the run fails.
    pub fn advance(&self, y: &OVector<f64, M::Dim>) -> Result<Advanced<M::Dim>, StabilityError> {
        let period = self.model.forcing_period();
        let plan = OutputPlan::strobe(period, self.periods, self.periods);
        let mut obs = LastStrobe { point: None };
        let stats = simulate(self.model, 0.0, y, &plan, &self.opts, &mut obs).map_err(|e| {
            StabilityError::Simulation {
                kind: e.kind,
                t: e.t,
            }
        })?;
        let point = obs.point.ok_or(StabilityError::NoStroboscopicPoint {
            periods: self.periods,
        })?;
        Ok(Advanced {
            y: point.y,
            label: point.label,
            stats,
        })
    }

    /// $P^n$ and its Jacobian $DP^n$ on $z$ at the full state `y` (at $\tau = 0$).
    ///
    /// # Errors
    /// [`StabilityError::Simulation`] when the run fails (a model error names an event the
    /// linearisation could not cross).
    pub fn linearize(
        &self,
        y: &OVector<f64, M::Dim>,
    ) -> Result<Linearization<M::Dim>, StabilityError> {
        let k = self.components().len();
        self.linearize_along(y, &DMatrix::identity(k, k))
    }

    /// $P^n$ and $DP^n\thinspace Q$ for the directions `q` (columns, in $z$'s coordinates) at
    /// the full state `y`: a Jacobian-vector product for one column.
    ///
    /// # Errors
    /// As [`StroboscopicMap::linearize`]; [`StabilityError::InvalidOption`] when `q` does not
    /// have one row per component of $z$.
    pub fn linearize_along(
        &self,
        y: &OVector<f64, M::Dim>,
        q: &DMatrix<f64>,
    ) -> Result<Linearization<M::Dim>, StabilityError> {
        let idx = self.components();
        if q.nrows() != idx.len() || q.ncols() == 0 {
            return Err(StabilityError::InvalidOption {
                field: "q",
                value: q.nrows() as f64,
                hint: "one row per non-algebraic component and at least one column",
            });
        }
        let d = self.model.dim();
        let mut m0 = OMatrix::<f64, M::Dim, Dyn>::zeros_generic(d, Dyn(q.ncols()));
        for (a, &i) in idx.iter().enumerate() {
            for c in 0..q.ncols() {
                m0[(i, c)] = q[(a, c)];
            }
        }
        let start_mode = self.model.initial_mode(0.0, y).ok();
        let start_open = start_mode.map_or(0.0, |m| self.model.section_openness(m, 0.0, y));
        let out = propagate(self.model, y, &m0, self.periods, &self.opts)?;
        let jacobian = rows_of(&idx, out.m.as_slice(), out.m.nrows(), q.ncols());
        let end_mode = self.model.initial_mode(0.0, &out.y).ok();
        let end_open = end_mode.map_or(0.0, |m| self.model.section_openness(m, 0.0, &out.y));
        Ok(Linearization {
            value: reduce_with(&idx, out.y.as_slice()),
            y: out.y,
            label: out.label,
            jacobian,
            events: out.events,
            openness: [start_open, end_open],
            stats: out.stats,
        })
    }
}

/// The entries `idx` of a state.
fn reduce_with(idx: &[usize], y: &[f64]) -> DVector<f64> {
    DVector::from_iterator(idx.len(), idx.iter().map(|&i| y[i]))
}

/// Rows `idx` of a column-major `rows x cols` matrix.
fn rows_of(idx: &[usize], data: &[f64], rows: usize, cols: usize) -> DMatrix<f64> {
    DMatrix::from_fn(idx.len(), cols, |a, c| data[c * rows + idx[a]])
}
