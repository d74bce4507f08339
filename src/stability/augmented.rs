//! The variational equations as a model of their own: a [`RotorModel`] whose state is the
//! model's state $y$, a variation $M$ ($N\times k$) and the algebraic rows of $M$ at the start
//! of the current mode, $B$.
//!
//! Running it with [`simulate`] integrates $M^\prime = A M$ on the same steps as $y$ (the
//! variational components are algebraic for the driver: left out of the step-size control, so
//! the trajectory is bitwise that of a plain run), evaluates exact modes by their closed form
//! and its Jacobian, and applies the saltation matrix at every transition. Guards, modes and
//! event location are the model's own.

use std::cell::RefCell;

use nalgebra::{DVector, DefaultAllocator, Dim, Dyn, OMatrix, OVector, U1};

use super::error::StabilityError;
use super::saltation::{saltation, EventLinearization};
use crate::hybrid::{
    simulate, EventRecord, ExactSegment, Flow, GuardCrossing, HybridObserver, ModelError,
    OutputPlan, RotorModel, SimOptions, SimStats, StrobePoint, StrobeRange, Variational,
    VariationalAlloc, Workspace,
};
use crate::numeric::Direction;

/// The event structure of an orbit: its events' guard labels in order from the section; for
/// an orbit without events, the mode it stays in (`"in mode 1"` for the ring's free flight),
/// so that a free orbit and a permanent contact (a full annular rub) differ, and the speed
/// where one becomes the other is a grazing.
pub(crate) fn event_structure(events: &[LinearEvent], label: u8) -> Vec<&'static str> {
    const STAY: [&str; 17] = [
        "in mode 0",
        "in mode 1",
        "in mode 2",
        "in mode 3",
        "in mode 4",
        "in mode 5",
        "in mode 6",
        "in mode 7",
        "in mode 8",
        "in mode 9",
        "in mode 10",
        "in mode 11",
        "in mode 12",
        "in mode 13",
        "in mode 14",
        "in mode 15",
        "in a mode above 15",
    ];
    if events.is_empty() {
        vec![STAY[usize::from(label).min(16)]]
    } else {
        events.iter().map(|e| e.kind).collect()
    }
}

/// One event crossed by a linearised trajectory, with the crossing's margin.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct LinearEvent {
    /// Time of the event.
    pub t: f64,
    /// The guard's label ([`RotorModel::guard_label`]).
    #[cfg_attr(
        feature = "serde",
        serde(deserialize_with = "crate::serde_util::label")
    )]
    pub kind: crate::StaticStr,
    /// Whether the guard is a contact onset ([`RotorModel::is_contact_onset`]).
    pub contact_onset: bool,
    /// Mode label before.
    pub from: u8,
    /// Mode label after.
    pub to: u8,
    /// The crossing margin of its saltation matrix in $[0, 1]$
    /// ([`Saltation::margin`](super::Saltation::margin)): 0 at grazing.
    pub margin: f64,
    /// The guard's crossing rate $\nabla g\cdot f^- + g_t$.
    pub rate: f64,
    /// $\lVert S\rVert_\infty$ (largest absolute row sum) of the event's saltation matrix:
    /// where the saltation is unbounded at grazing it grows like $1/$`margin` as the margin
    /// goes to 0; where it stays bounded (a jump of the field proportional to the crossing
    /// rate) it does not.
    pub saltation_norm: f64,
}

/// A state and a variation.
pub(crate) type Unpacked<D> = (OVector<f64, D>, OMatrix<f64, D, Dyn>);

/// A segment's buffers for the model's state and its derivative.
pub(crate) struct Buffers<D: Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    y: OVector<f64, D>,
    dy: OVector<f64, D>,
}

/// The model with its variational equations (module docs).
pub(crate) struct Augmented<'a, M> {
    model: &'a M,
    /// The model's dimension.
    n: usize,
    /// Columns of the variation.
    k: usize,
    /// Events crossed, with their margins (a run is single-threaded; cleared per run).
    log: RefCell<Vec<LinearEvent>>,
}

/// Scratch of the augmented right-hand side, sized once per run.
pub(crate) struct Scratch<D: Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    y: OVector<f64, D>,
    dy: OVector<f64, D>,
    jac: OMatrix<f64, D, D>,
    m: OMatrix<f64, D, Dyn>,
    b: OMatrix<f64, D, Dyn>,
    dm: OMatrix<f64, D, Dyn>,
    work: Workspace<D>,
}

/// The augmented model's cache: the model's own and the scratch.
pub(crate) struct AugmentedCache<M: RotorModel>
where
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    inner: M::Cache,
    scratch: RefCell<Scratch<M::Dim>>,
}

impl<'a, M> Augmented<'a, M>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    pub(crate) fn new(model: &'a M, k: usize) -> Self {
        Self {
            model,
            n: model.dim().value(),
            k,
            log: RefCell::new(Vec::new()),
        }
    }

    /// The augmented state from `y`, a variation `m` (its algebraic rows as they are at the
    /// start: they become the start rows `B`).
    pub(crate) fn pack(
        &self,
        y: &OVector<f64, M::Dim>,
        m: &OMatrix<f64, M::Dim, Dyn>,
    ) -> DVector<f64> {
        let (n, k) = (self.n, self.k);
        let mut out = DVector::zeros(n + 2 * n * k);
        out.rows_mut(0, n).copy_from_slice(y.as_slice());
        out.rows_mut(n, n * k).copy_from_slice(m.as_slice());
        out.rows_mut(n + n * k, n * k).copy_from_slice(m.as_slice());
        out
    }

    /// `y` and `M` of an augmented state.
    pub(crate) fn unpack(&self, aug: &DVector<f64>) -> Unpacked<M::Dim> {
        let d = self.model.dim();
        let mut y = OVector::zeros_generic(d, U1);
        let mut m = OMatrix::zeros_generic(d, Dyn(self.k));
        self.read(aug, &mut y, &mut m, None);
        (y, m)
    }

    fn read(
        &self,
        aug: &DVector<f64>,
        y: &mut OVector<f64, M::Dim>,
        m: &mut OMatrix<f64, M::Dim, Dyn>,
        b: Option<&mut OMatrix<f64, M::Dim, Dyn>>,
    ) {
        let (n, k) = (self.n, self.k);
        y.copy_from_slice(&aug.as_slice()[..n]);
        m.copy_from_slice(&aug.as_slice()[n..n + n * k]);
        if let Some(b) = b {
            b.copy_from_slice(&aug.as_slice()[n + n * k..]);
        }
    }

    pub(crate) fn take_log(&self) -> Vec<LinearEvent> {
        std::mem::take(&mut *self.log.borrow_mut())
    }

    fn scratch(&self) -> Scratch<M::Dim> {
        let d = self.model.dim();
        let kd = Dyn(self.k);
        Scratch {
            y: OVector::zeros_generic(d, U1),
            dy: OVector::zeros_generic(d, U1),
            jac: OMatrix::zeros_generic(d, d),
            m: OMatrix::zeros_generic(d, kd),
            b: OMatrix::zeros_generic(d, kd),
            dm: OMatrix::zeros_generic(d, kd),
            work: Workspace::new(self.model),
        }
    }
}

impl<'a, M> RotorModel for Augmented<'a, M>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    type Dim = Dyn;
    type Mode = M::Mode;
    type Segment = AugmentedSegment<'a, M>;
    type Cache = AugmentedCache<M>;

    fn dim(&self) -> Dyn {
        Dyn(self.n + 2 * self.n * self.k)
    }

    /// The model's scale on its state (so that the state is integrated as in a plain run); 1
    /// on the variations, which are algebraic for the driver.
    fn state_scale(&self) -> DVector<f64> {
        let inner = self.model.state_scale();
        DVector::from_fn(self.n + 2 * self.n * self.k, |i, _| {
            inner.get(i).copied().unwrap_or(1.0)
        })
    }

    fn new_cache(&self) -> AugmentedCache<M> {
        AugmentedCache {
            inner: self.model.new_cache(),
            scratch: RefCell::new(self.scratch()),
        }
    }

    fn is_algebraic(&self, i: usize) -> bool {
        i >= self.n || self.model.is_algebraic(i)
    }

    fn initial_mode(&self, t: f64, y: &DVector<f64>) -> Result<M::Mode, ModelError> {
        let (inner, _) = self.unpack(y);
        self.model.initial_mode(t, &inner)
    }

    fn flow(&self, mode: M::Mode) -> Flow {
        self.model.flow(mode)
    }

    fn rhs(
        &self,
        mode: M::Mode,
        t: f64,
        y: &DVector<f64>,
        dy: &mut DVector<f64>,
        cache: &AugmentedCache<M>,
    ) {
        let (n, k) = (self.n, self.k);
        let mut s = cache.scratch.borrow_mut();
        let Scratch {
            y: yi,
            dy: dyi,
            jac,
            m,
            b,
            dm,
            work,
        } = &mut *s;
        self.read(y, yi, m, Some(b));
        self.model.rhs(mode, t, yi, dyi, &cache.inner);
        dy.rows_mut(0, n).copy_from_slice(dyi.as_slice());
        if self.model.flow(mode) == Flow::Exact {
            dy.rows_mut(n, 2 * n * k).fill(0.0);
            return;
        }
        self.model
            .algebraic_variation(mode, t, yi, b, m, &cache.inner);
        self.model
            .rhs_jacobian_product(mode, t, yi, m, dm, jac, (&cache.inner, work));
        for i in 0..n {
            if self.model.is_algebraic_variation(i) {
                dm.row_mut(i).fill(0.0);
            }
        }
        dy.rows_mut(n, n * k).copy_from_slice(dm.as_slice());
        dy.rows_mut(n + n * k, n * k).fill(0.0);
    }

    fn guard_count(&self, mode: M::Mode) -> usize {
        self.model.guard_count(mode)
    }

    fn guard_direction(&self, mode: M::Mode, i: usize) -> Direction {
        self.model.guard_direction(mode, i)
    }

    fn guard_value(
        &self,
        mode: M::Mode,
        i: usize,
        t: f64,
        y: &DVector<f64>,
        cache: &AugmentedCache<M>,
    ) -> f64 {
        let mut s = cache.scratch.borrow_mut();
        s.y.copy_from_slice(&y.as_slice()[..self.n]);
        self.model.guard_value(mode, i, t, &s.y, &cache.inner)
    }

    fn guard_derivative(
        &self,
        mode: M::Mode,
        i: usize,
        t: f64,
        y: &DVector<f64>,
        dy: &DVector<f64>,
        cache: &AugmentedCache<M>,
    ) -> Option<f64> {
        let mut s = cache.scratch.borrow_mut();
        let Scratch { y: yi, dy: dyi, .. } = &mut *s;
        yi.copy_from_slice(&y.as_slice()[..self.n]);
        dyi.copy_from_slice(&dy.as_slice()[..self.n]);
        self.model
            .guard_derivative(mode, i, t, yi, dyi, &cache.inner)
    }

    fn guard_derivative_needs_rhs(&self) -> bool {
        self.model.guard_derivative_needs_rhs()
    }

    fn guard_label(&self, mode: M::Mode, i: usize) -> &'static str {
        self.model.guard_label(mode, i)
    }

    fn guard_error(
        &self,
        mode: M::Mode,
        i: usize,
        t: f64,
        y: &DVector<f64>,
        cache: &AugmentedCache<M>,
    ) -> ModelError {
        let mut s = cache.scratch.borrow_mut();
        s.y.copy_from_slice(&y.as_slice()[..self.n]);
        self.model.guard_error(mode, i, t, &s.y, &cache.inner)
    }

    fn transition(
        &self,
        mode: M::Mode,
        guard: usize,
        t: f64,
        y: &mut DVector<f64>,
    ) -> Result<M::Mode, ModelError> {
        let model = self.model;
        let d = model.dim();
        let (y_minus, m_minus) = self.unpack(y);
        let cache = model.new_cache();
        let mut work = Workspace::new(model);
        let mut f_minus = OVector::zeros_generic(d, U1);
        model.rhs(mode, t, &y_minus, &mut f_minus, &cache);
        let mut grad = OVector::zeros_generic(d, U1);
        let gt = model.guard_gradient(mode, guard, t, &y_minus, &mut grad, &cache, &mut work);
        let mut y_plus = y_minus.clone();
        let next = model.transition(mode, guard, t, &mut y_plus)?;
        let mut f_plus = OVector::zeros_generic(d, U1);
        model.rhs(next, t, &y_plus, &mut f_plus, &model.new_cache());
        let mut rx = OMatrix::zeros_generic(d, d);
        let mut rt = OVector::zeros_generic(d, U1);
        model.transition_jacobian(mode, guard, t, &y_minus, &y_plus, next, &mut rx, &mut rt)?;
        let scale = model.state_scale();
        let event = EventLinearization {
            field_before: &f_minus,
            field_after: &f_plus,
            guard_gradient: &grad,
            guard_time_derivative: gt,
            reset_jacobian: Some(&rx),
            reset_time_derivative: Some(&rt),
            state_scale: scale.iter().any(|&s| s != 1.0).then_some(&scale),
        };
        let s = saltation(&event, 0.0).map_err(|e| ModelError::Transition {
            t,
            reason: format!(
                "the variational equations cannot cross the `{}` event: {e}",
                model.guard_label(mode, guard)
            ),
        })?;
        let m_plus = &s.matrix * &m_minus;
        self.log.borrow_mut().push(LinearEvent {
            t,
            kind: model.guard_label(mode, guard),
            contact_onset: model.is_contact_onset(mode, guard),
            from: model.mode_label(mode),
            to: model.mode_label(next),
            margin: s.margin(),
            rate: s.denominator,
            saltation_norm: s
                .matrix
                .row_iter()
                .map(|r| r.iter().map(|v| v.abs()).sum::<f64>())
                .fold(0.0, f64::max),
        });
        *y = self.pack(&y_plus, &m_plus);
        Ok(next)
    }

    fn start_segment(&self, mode: M::Mode, t: f64, y: &DVector<f64>) -> AugmentedSegment<'a, M> {
        let (y0, m0) = self.unpack(y);
        let b0 = {
            let mut b = m0.clone();
            b.copy_from_slice(&y.as_slice()[self.n + self.n * self.k..]);
            b
        };
        let d = self.model.dim();
        AugmentedSegment {
            model: self.model,
            inner: self.model.start_segment(mode, t, &y0),
            cache: self.model.new_cache(),
            mode,
            t0: t,
            n: self.n,
            y0,
            m0,
            b0,
            buffers: RefCell::new(Buffers {
                y: OVector::zeros_generic(d, U1),
                dy: OVector::zeros_generic(d, U1),
            }),
        }
    }

    fn project(&self, mode: M::Mode, t: f64, y: &mut DVector<f64>, cache: &AugmentedCache<M>) {
        let (n, k) = (self.n, self.k);
        let mut s = cache.scratch.borrow_mut();
        let Scratch { y: yi, m, b, .. } = &mut *s;
        self.read(y, yi, m, Some(b));
        self.model.project(mode, t, yi, &cache.inner);
        self.model
            .algebraic_variation(mode, t, yi, b, m, &cache.inner);
        y.rows_mut(0, n).copy_from_slice(yi.as_slice());
        y.rows_mut(n, n * k).copy_from_slice(m.as_slice());
    }

    fn mode_label(&self, mode: M::Mode) -> u8 {
        self.model.mode_label(mode)
    }

    fn forcing_period(&self) -> f64 {
        self.model.forcing_period()
    }

    fn strobe_time(&self, k: u64) -> f64 {
        self.model.strobe_time(k)
    }
}

/// An exact mode of the augmented model: the model's closed form, and the variation
/// transported by its Jacobian.
pub(crate) struct AugmentedSegment<'a, M: RotorModel>
where
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    model: &'a M,
    inner: M::Segment,
    cache: M::Cache,
    mode: M::Mode,
    t0: f64,
    n: usize,
    y0: OVector<f64, M::Dim>,
    m0: OMatrix<f64, M::Dim, Dyn>,
    b0: OMatrix<f64, M::Dim, Dyn>,
    buffers: RefCell<Buffers<M::Dim>>,
}

impl<M> ExactSegment<Dyn> for AugmentedSegment<'_, M>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    fn eval(&self, t: f64, y: &mut DVector<f64>, dy: &mut DVector<f64>) {
        let n = self.n;
        let mut buf = self.buffers.borrow_mut();
        let Buffers { y: yi, dy: dyi } = &mut *buf;
        self.inner.eval(t, yi, dyi);
        let d = self.model.dim();
        let mut jac = OMatrix::zeros_generic(d, d);
        self.model
            .segment_jacobian(self.mode, self.t0, &self.y0, t, &mut jac);
        let mut m = &jac * &self.m0;
        self.model
            .algebraic_variation(self.mode, t, yi, &self.b0, &mut m, &self.cache);
        let nk = m.len();
        y.rows_mut(0, n).copy_from_slice(yi.as_slice());
        y.rows_mut(n, nk).copy_from_slice(m.as_slice());
        y.rows_mut(n + nk, nk).copy_from_slice(self.b0.as_slice());
        dy.rows_mut(0, n).copy_from_slice(dyi.as_slice());
        dy.rows_mut(n, 2 * nk).fill(0.0);
    }

    fn next_guard(&mut self, t_from: f64, t_to: f64) -> Option<GuardCrossing> {
        self.inner.next_guard(t_from, t_to)
    }

    fn evaluations(&self) -> u64 {
        self.inner.evaluations()
    }
}

/// What a linearised run recorded.
struct Recorder {
    strobe: Option<StrobePoint<Dyn>>,
    events: Vec<(f64, &'static str, u8, u8)>,
}

impl HybridObserver<Dyn> for Recorder {
    fn on_strobe(&mut self, point: &StrobePoint<Dyn>) {
        self.strobe = Some(point.clone());
    }
    fn on_event(&mut self, e: &EventRecord<Dyn>) {
        self.events.push((e.t, e.kind, e.from, e.to));
    }
}

/// The end of a linearised run.
pub(crate) struct Propagated<D: Dim>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    /// The state at the end.
    pub y: OVector<f64, D>,
    /// The variation at the end.
    pub m: OMatrix<f64, D, Dyn>,
    /// The mode label at the end.
    pub label: u8,
    /// Events crossed, with their margins.
    pub events: Vec<LinearEvent>,
    /// Work done.
    pub stats: SimStats,
}

/// [`simulate`] for a model of dynamic dimension (kept apart from the callers' bounds on the
/// inner model's dimension, which would otherwise shadow the allocator of `Dyn`).
fn run_dyn<A: RotorModel<Dim = Dyn>, O: HybridObserver<Dyn>>(
    model: &A,
    y0: &DVector<f64>,
    plan: &OutputPlan,
    opts: &SimOptions,
    obs: &mut O,
) -> Result<SimStats, StabilityError> {
    simulate(model, 0.0, y0, plan, opts, obs).map_err(|e| StabilityError::Simulation {
        kind: e.kind,
        t: e.t,
    })
}

/// Runs `model` with its variational equations from $(0, y_0)$, variation `m0` ($N\times k$,
/// zero algebraic rows: the algebraic components at the start are held fixed, then placed),
/// for `periods` forcing periods.
pub(crate) fn propagate<M>(
    model: &M,
    y0: &OVector<f64, M::Dim>,
    m0: &OMatrix<f64, M::Dim, Dyn>,
    periods: u64,
    opts: &SimOptions,
) -> Result<Propagated<M::Dim>, StabilityError>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let aug = Augmented::new(model, m0.ncols());
    let start = aug.pack(y0, m0);
    let period = model.forcing_period();
    let plan = OutputPlan {
        t_end: period * periods as f64,
        strobe: Some(StrobeRange {
            first: periods,
            last: periods,
        }),
        dense: None,
        events: true,
    };
    let mut rec = Recorder {
        strobe: None,
        events: Vec::new(),
    };
    let stats = run_dyn(&aug, &start, &plan, opts, &mut rec)?;
    let log = aug.take_log();
    let point = rec
        .strobe
        .ok_or(StabilityError::NoStroboscopicPoint { periods })?;
    let (y, m) = aug.unpack(&point.y);
    debug_assert_eq!(log.len(), rec.events.len());
    Ok(Propagated {
        y,
        m,
        label: point.label,
        events: log,
        stats,
    })
}
