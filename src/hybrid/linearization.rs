//! What a model supplies for its linearisation: the [`Variational`] extension of
//! [`RotorModel`].
//!
//! Linearising a hybrid trajectory needs, besides what the driver uses, the Jacobian of each
//! mode's vector field, the gradients of the guards, the Jacobian of each transition's reset and,
//! in exact modes, the Jacobian of the closed form. Every method of [`Variational`] has a
//! default by **central finite differences** of the model's own [`RotorModel`] methods, so that
//! `impl Variational for MyModel {}` is enough to start; a model overrides what it knows
//! analytically, or what the differences cannot do (see each method's contract).
//!
//! A model's linearisation lives with the model: the paper's model overrides every method
//! (`paper::linearization`), [`crate::rotor::RingedRotor`] the ring's parts
//! (`rotor::linearization`), both through the ring's station map (`ring::station`). The
//! analyses of [`crate::stability`] use the trait only. [`Variational::rhs_jacobian`] needs no
//! analysis type: an integrator can call it too.
//!
//! # Algebraic components
//!
//! Components that the model sets itself rather than integrates ([`Variational::is_algebraic_variation`],
//! by default [`RotorModel::is_algebraic`]) are not propagated by the variational equations:
//! their rows of a variation are written by [`Variational::algebraic_variation`] from the other
//! rows and from their value when the mode started (right after the transition into it). A
//! massless ring in contact is $s^*(r)$: its rows are $J$ times the rotor's position rows; out of
//! contact it relaxes in closed form from where it was released, independently of the rotor: its
//! rows are those at the release, scaled by the relaxation's sensitivity. Their dynamics may be
//! stiff; their closed form is what keeps the linearisation cheap and exact.
//!
//! # Contracts the defaults rely on
//!
//! * [`RotorModel::rhs`] and [`RotorModel::guard_value`] can be evaluated in **every** mode,
//!   exact ones included (the saltation matrix needs the fields on both sides of an event and
//!   the guard's gradient), and are smooth in $(t, y)$ within a mode (on the mode's branch:
//!   the smooth extension);
//! * a transition keeps its outcome (the next mode) under perturbations of the state of the
//!   size of the difference step, at least on one side; otherwise override
//!   [`Variational::transition_jacobian`];
//! * [`RotorModel::project`] writes the algebraic components as functions of the others (for
//!   [`Variational::algebraic_variation`]'s default) and leaves alone those that depend on
//!   the mode's history (those are then carried unchanged from the mode's start: override if
//!   they evolve, as a relaxing ring does).

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, Dyn, OMatrix, OVector, U1};

use super::{ExactSegment, ModelError, RotorModel};
use crate::ode::JacobianMut;

/// The allocations the linearisation of a model of dimension `D` needs (vectors, square
/// matrices and `D x Dyn` variations); every nalgebra dimension has them. Write
/// `DefaultAllocator: VariationalAlloc<D>` in bounds.
pub trait VariationalAlloc<D: Dim>: Allocator<D> + Allocator<D, D> + Allocator<D, Dyn> {}

impl<D: Dim, A> VariationalAlloc<D> for A where A: Allocator<D> + Allocator<D, D> + Allocator<D, Dyn>
{}

/// Scratch vectors for the finite-difference defaults, sized once per run (no allocation in
/// the stepping loop, for `Dyn` too), with the model's [`RotorModel::state_scale`] that sets
/// their increments.
#[derive(Debug, Clone)]
pub struct Workspace<D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    y: OVector<f64, D>,
    plus: OVector<f64, D>,
    minus: OVector<f64, D>,
    scale: OVector<f64, D>,
}

impl<D: Dim> Workspace<D>
where
    DefaultAllocator: Allocator<D>,
{
    /// Scratch for the states of `model`, with its scale.
    pub fn new<M: RotorModel<Dim = D>>(model: &M) -> Self {
        let dim = model.dim();
        Self {
            y: OVector::zeros_generic(dim, U1),
            plus: OVector::zeros_generic(dim, U1),
            minus: OVector::zeros_generic(dim, U1),
            scale: model.state_scale(),
        }
    }
}

/// The linearisation of a [`RotorModel`] (module docs). Every method has a finite-difference
/// default; see the module docs for what the defaults assume.
pub trait Variational: RotorModel
where
    DefaultAllocator: VariationalAlloc<Self::Dim>,
{
    /// Relative step $h$ of the central differences of the defaults: component $j$ moves by
    /// $h\thinspace(s_j + |y_j|)$, $s_j$ its [`RotorModel::state_scale`], and time by
    /// $h P$, $P$ the [`RotorModel::forcing_period`] (not by a step that grows with $|t|$).
    /// Default $10^{-5}$: for a smooth field with derivatives of order 1 to 100 (in units
    /// of the scale) the truncation ($h^2$) and the rounding ($\varepsilon/h$) errors are then
    /// both about $10^{-10}$ relative.
    fn difference_step(&self) -> f64 {
        1e-5
    }

    /// Whether component `i` is algebraic for the linearisation (module docs). Default:
    /// [`RotorModel::is_algebraic`].
    fn is_algebraic_variation(&self, i: usize) -> bool {
        self.is_algebraic(i)
    }

    /// The Jacobian $\partial f/\partial y$ of the vector field of `mode` at $(t, y)$, written
    /// into `jac`. Only the rows of the non-algebraic components are used. Default: the
    /// model's [`RotorModel::jacobian`] if it has one, else central differences of
    /// [`RotorModel::rhs`].
    #[allow(clippy::too_many_arguments)]
    fn rhs_jacobian(
        &self,
        mode: Self::Mode,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        jac: &mut OMatrix<f64, Self::Dim, Self::Dim>,
        cache: &Self::Cache,
        work: &mut Workspace<Self::Dim>,
    ) {
        let dim = y.shape_generic().0;
        let mut view = JacobianMut::from_slice_generic(jac.as_mut_slice(), dim, dim);
        if self.jacobian(mode, t, y, &mut view, cache) {
            return;
        }
        let field = |y: &OVector<f64, Self::Dim>, dy: &mut OVector<f64, Self::Dim>| {
            self.rhs(mode, t, y, dy, cache)
        };
        field_differences(field, y, self.difference_step(), jac, work);
    }

    /// The right-hand side of the variational equations, $JV$: the Jacobian of the field of
    /// `mode` at $(t, y)$ ([`Variational::rhs_jacobian`]) times the variation `v`, written
    /// into `out` (`jac` is scratch). Only the rows of the non-algebraic components are used.
    /// Default: the Jacobian into `jac`, then the dense product; a model whose Jacobian has
    /// structure (a large rotor's) overrides it with a product that does not form $J$.
    #[allow(clippy::too_many_arguments)]
    fn rhs_jacobian_product(
        &self,
        mode: Self::Mode,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        v: &OMatrix<f64, Self::Dim, Dyn>,
        out: &mut OMatrix<f64, Self::Dim, Dyn>,
        jac: &mut OMatrix<f64, Self::Dim, Self::Dim>,
        (cache, work): (&Self::Cache, &mut Workspace<Self::Dim>),
    ) {
        self.rhs_jacobian(mode, t, y, jac, cache, work);
        out.gemm(1.0, jac, v, 0.0);
    }

    /// The gradient $\nabla_y g$ of guard `i` of `mode` at $(t, y)$, written into `grad`, and
    /// $\partial g/\partial t$, returned: the guard as a function of the **full** state, in
    /// which algebraic components stand for themselves (a guard that reads a relaxing ring
    /// depends on the ring's component, and its time derivative at fixed state excludes the
    /// ring's motion, which the field's ring component carries). Default: central differences
    /// of [`RotorModel::guard_value`], which then must depend on the algebraic components
    /// through the state (override otherwise: a difference cannot see a dependence through
    /// the mode).
    #[allow(clippy::too_many_arguments)]
    fn guard_gradient(
        &self,
        mode: Self::Mode,
        i: usize,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        grad: &mut OVector<f64, Self::Dim>,
        cache: &Self::Cache,
        work: &mut Workspace<Self::Dim>,
    ) -> f64 {
        let value = |t: f64, y: &OVector<f64, Self::Dim>| self.guard_value(mode, i, t, y, cache);
        let steps = (self.difference_step(), self.forcing_period());
        guard_differences(value, t, y, steps, grad, work)
    }

    /// The Jacobian of the reset of the transition after guard `guard` of `mode` fired at
    /// $(t, y)$ (projected in `mode`), whose outcome was the state `after` in mode `next`:
    /// $R_y$ into `rx` and $R_t$ into `rt`. Default: central differences of [`RotorModel::transition`] (one-sided
    /// where a perturbed transition gives another mode than `next`).
    ///
    /// # Errors
    /// [`ModelError::Transition`] when the perturbed transitions fail or change the outcome
    /// on both sides of a component (the transition is not differentiable there with this
    /// step: override this method).
    #[allow(clippy::too_many_arguments)]
    fn transition_jacobian(
        &self,
        mode: Self::Mode,
        guard: usize,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        after: &OVector<f64, Self::Dim>,
        next: Self::Mode,
        rx: &mut OMatrix<f64, Self::Dim, Self::Dim>,
        rt: &mut OVector<f64, Self::Dim>,
    ) -> Result<(), ModelError> {
        // The same outcome: the same mode label (a mode may carry continuous data, e.g. where
        // a ring was released, that moves with the state).
        let label = self.mode_label(next);
        let apply = |t: f64, y: &OVector<f64, Self::Dim>| {
            let mut out = y.clone_owned();
            match self.transition(mode, guard, t, &mut out) {
                Ok(m) if self.mode_label(m) == label => Some(out),
                _ => None,
            }
        };
        let steps = (self.difference_step(), self.forcing_period());
        let at = (t, y, after);
        reset_differences(apply, at, &self.state_scale(), steps, rx, rt)
    }

    /// The Jacobian $\partial y(t)/\partial y(t_0)$ of the closed form of an exact `mode`
    /// started at $(t_0, y_0)$, written into `jac`. Only the rows of the non-algebraic
    /// components are used. Default: central differences of segments started at perturbed
    /// states ([`RotorModel::start_segment`], [`ExactSegment::eval`]).
    fn segment_jacobian(
        &self,
        mode: Self::Mode,
        t0: f64,
        y0: &OVector<f64, Self::Dim>,
        t: f64,
        jac: &mut OMatrix<f64, Self::Dim, Self::Dim>,
    ) {
        let h = self.difference_step();
        let dim = y0.shape_generic().0;
        let mut start = y0.clone_owned();
        let mut plus = OVector::zeros_generic(dim, U1);
        let mut minus = OVector::zeros_generic(dim, U1);
        let mut dy = OVector::zeros_generic(dim, U1);
        let scale = self.state_scale();
        for j in 0..y0.len() {
            let step = h * (scale[j] + y0[j].abs());
            start[j] = y0[j] + step;
            self.start_segment(mode, t0, &start)
                .eval(t, &mut plus, &mut dy);
            start[j] = y0[j] - step;
            self.start_segment(mode, t0, &start)
                .eval(t, &mut minus, &mut dy);
            start[j] = y0[j];
            let inv = 0.5 / step;
            for i in 0..y0.len() {
                jac[(i, j)] = (plus[i] - minus[i]) * inv;
            }
        }
    }

    /// Writes the algebraic rows of the variation `m` at $(t, y)$ in `mode` from its other
    /// rows and from `start`, the variation right after the transition into `mode` (module
    /// docs). Default: nothing without algebraic components; otherwise central differences of
    /// [`RotorModel::project`]: rows $\partial\pi/\partial y_{\rm diff}\thinspace m_{\rm diff} +
    /// \partial\pi/\partial y_{\rm alg}\thinspace {\rm start}_{\rm alg}$, $\pi$ the projection.
    fn algebraic_variation(
        &self,
        mode: Self::Mode,
        t: f64,
        y: &OVector<f64, Self::Dim>,
        start: &OMatrix<f64, Self::Dim, Dyn>,
        m: &mut OMatrix<f64, Self::Dim, Dyn>,
        cache: &Self::Cache,
    ) {
        let n = y.len();
        let algebraic: Vec<usize> = (0..n).filter(|&i| self.is_algebraic_variation(i)).collect();
        if algebraic.is_empty() {
            return;
        }
        let h = self.difference_step();
        let mut yp = y.clone_owned();
        let mut ym = y.clone_owned();
        let mut rows = OMatrix::<f64, Dyn, Dyn>::zeros(algebraic.len(), m.ncols());
        let scale = self.state_scale();
        for j in 0..n {
            let step = h * (scale[j] + y[j].abs());
            yp.copy_from(y);
            ym.copy_from(y);
            yp[j] += step;
            ym[j] -= step;
            self.project(mode, t, &mut yp, cache);
            self.project(mode, t, &mut ym, cache);
            let source = if self.is_algebraic_variation(j) {
                start.row(j)
            } else {
                m.row(j)
            };
            for (a, &i) in algebraic.iter().enumerate() {
                let d = (yp[i] - ym[i]) * (0.5 / step);
                if d != 0.0 {
                    for c in 0..m.ncols() {
                        rows[(a, c)] += d * source[c];
                    }
                }
            }
        }
        for (a, &i) in algebraic.iter().enumerate() {
            m.row_mut(i).copy_from(&rows.row(a));
        }
    }

    /// The full state at a stroboscopic section from the values `z` of its non-algebraic
    /// components, in their order, and a `template` state there (the trajectory's own): the
    /// algebraic components are placed for the new values (the driver then projects them).
    /// Default: `template` with the non-algebraic components replaced by `z`.
    fn section_state(
        &self,
        t: f64,
        template: &OVector<f64, Self::Dim>,
        z: &[f64],
    ) -> OVector<f64, Self::Dim> {
        let _ = t;
        let mut y = template.clone_owned();
        let mut k = 0;
        for i in 0..y.len() {
            if !self.is_algebraic_variation(i) {
                y[i] = z[k];
                k += 1;
            }
        }
        y
    }

    /// How far the state at a section is from being a function of its non-algebraic
    /// components (0 when it is, e.g. a ring that has relaxed to its centre): the map on those
    /// components is closed only at 0. Default 0.
    fn section_openness(&self, mode: Self::Mode, t: f64, y: &OVector<f64, Self::Dim>) -> f64 {
        let _ = (mode, t, y);
        0.0
    }

    /// A smooth signed measure of contact for grazing margins: positive, the depth of a
    /// contact, in contact modes; negative, minus the clearance, out of contact. `None`
    /// (default) if the model has no such notion.
    fn contact_depth(&self, mode: Self::Mode, t: f64, y: &OVector<f64, Self::Dim>) -> Option<f64> {
        let _ = (mode, t, y);
        None
    }
}

/// Central differences of a field `field` at `y` ([`Variational::rhs_jacobian`]'s default, and
/// a model's own where its field depends on the state through more than `rhs` sees): column
/// $j$ moves $y_j$ by $h\thinspace(s_j + |y_j|)$, $s$ the scale held by `work`.
pub(crate) fn field_differences<D: Dim>(
    mut field: impl FnMut(&OVector<f64, D>, &mut OVector<f64, D>),
    y: &OVector<f64, D>,
    h: f64,
    jac: &mut OMatrix<f64, D, D>,
    work: &mut Workspace<D>,
) where
    DefaultAllocator: VariationalAlloc<D>,
{
    work.y.copy_from(y);
    for j in 0..y.len() {
        let step = h * (work.scale[j] + y[j].abs());
        work.y[j] = y[j] + step;
        field(&work.y, &mut work.plus);
        work.y[j] = y[j] - step;
        field(&work.y, &mut work.minus);
        work.y[j] = y[j];
        let inv = 0.5 / step;
        for i in 0..y.len() {
            jac[(i, j)] = (work.plus[i] - work.minus[i]) * inv;
        }
    }
}

/// Central differences of a guard `value(t, y)` at $(t, y)$ ([`Variational::guard_gradient`]'s
/// default): the gradient into `grad` (steps as [`field_differences`]'), the time derivative
/// returned (step $hP$); `steps` = $(h, P)$.
pub(crate) fn guard_differences<D: Dim>(
    mut value: impl FnMut(f64, &OVector<f64, D>) -> f64,
    t: f64,
    y: &OVector<f64, D>,
    (h, period): (f64, f64),
    grad: &mut OVector<f64, D>,
    work: &mut Workspace<D>,
) -> f64
where
    DefaultAllocator: VariationalAlloc<D>,
{
    work.y.copy_from(y);
    for j in 0..y.len() {
        let step = h * (work.scale[j] + y[j].abs());
        work.y[j] = y[j] + step;
        let p = value(t, &work.y);
        work.y[j] = y[j] - step;
        let m = value(t, &work.y);
        work.y[j] = y[j];
        grad[j] = (p - m) * (0.5 / step);
    }
    let step = h * period;
    let p = value(t + step, y);
    let m = value(t - step, y);
    (p - m) * (0.5 / step)
}

/// Central differences of a reset `apply(t, y)` (`None` where the perturbed transition has
/// another outcome) at `at` = $(t, y, $ the nominal outcome$)$
/// ([`Variational::transition_jacobian`]'s default): one-sided where one side changes the
/// outcome; `steps` = $(h, P)$ and `scale` as [`guard_differences`]'.
///
/// # Errors
/// [`ModelError::Transition`] where both sides of a component change the outcome.
pub(crate) fn reset_differences<D: Dim>(
    apply: impl Fn(f64, &OVector<f64, D>) -> Option<OVector<f64, D>>,
    (t, y, nominal): (f64, &OVector<f64, D>, &OVector<f64, D>),
    scale: &OVector<f64, D>,
    (h, period): (f64, f64),
    rx: &mut OMatrix<f64, D, D>,
    rt: &mut OVector<f64, D>,
) -> Result<(), ModelError>
where
    DefaultAllocator: VariationalAlloc<D>,
{
    let difference = |plus: Option<OVector<f64, D>>,
                      minus: Option<OVector<f64, D>>,
                      step: f64,
                      what: &str|
     -> Result<OVector<f64, D>, ModelError> {
        match (plus, minus) {
            (Some(p), Some(m)) => Ok((p - m) * (0.5 / step)),
            (Some(p), None) => Ok((p - nominal) * (1.0 / step)),
            (None, Some(m)) => Ok((nominal - m) * (1.0 / step)),
            (None, None) => Err(ModelError::Transition {
                t,
                reason: format!(
                    "the transition's outcome changes under a perturbation of {what} by \
                     {step:e} on both sides: it is not differentiable by differences there \
                     (override Variational::transition_jacobian)"
                ),
            }),
        }
    };
    let mut yp = y.clone_owned();
    for j in 0..y.len() {
        let step = h * (scale[j] + y[j].abs());
        yp[j] = y[j] + step;
        let plus = apply(t, &yp);
        yp[j] = y[j] - step;
        let minus = apply(t, &yp);
        yp[j] = y[j];
        let col = difference(plus, minus, step, "a state component")?;
        rx.set_column(j, &col);
    }
    let step = h * period;
    let col = difference(apply(t + step, y), apply(t - step, y), step, "the time")?;
    rt.copy_from(&col);
    Ok(())
}
