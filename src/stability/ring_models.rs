//! The linearisation of the models built on the snubber ring: the paper's
//! [`JeffcottModel`] (everything analytic) and any [`RingedRotor`] (the ring's parts analytic,
//! the rotor's own field by differences).
//!
//! Both keep the ring's position in two state slots, set by the ring's rules, not integrated:
//! they are the algebraic components of the linearisation.
//!
//! * **Guards**: the ring's gradients ([`SnubberRing::guard_gradient`]) through the station's
//!   linear map; the onset guard $|r - s|^2 - \gamma^2$ depends on the ring's slots
//!   ($-2q$) and has no explicit time dependence at a fixed state (the ring's motion is in the
//!   field's ring components).
//! * **Resets**: the rotor is never reset; the ring is placed where the ring's rules put it:
//!   at $s^*(r)$ on some branches (rows $J\thinspace\partial r/\partial y$), at its centre or
//!   snapped onto its preload (zero rows).
//! * **Algebraic rows**: in contact $J$ times the station's position rows; in free flight the
//!   rows at the release scaled per axis by the relaxation's sensitivity
//!   ([`Relaxation::sensitivity`]), in closed form: the relaxation is stiff.
//! * **The paper's model** also gives its field's Jacobian analytically
//!   ([`SnubberRing::force_jacobian`]) and its free flight's transition matrix
//!   ([`FreeOscillator::transition_matrix`]).

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, Dyn, Matrix2, OMatrix, OVector, Vector2, U6};

use super::variational::{Variational, VariationalAlloc, Workspace};
use crate::hybrid::ModelError;
use crate::paper::free_flight::FreeOscillator;
use crate::paper::{Cache, JeffcottModel, Mode};
use crate::ring::{
    Branches, Kinematics, Relaxation, RingCache, RingContact, RingGuard, RingMode, SnubberRing,
};
use crate::rotor::{RingedRotor, SmoothRotor};

/// The ring at a rotor's station: the station's affine map and the ring's slots.
struct Station<'a> {
    ring: &'a SnubberRing,
    /// Row `a` (`r.x, r.y, v.x, v.y`) of the station map has its coefficient of `y[j]` at
    /// `(a, j)`; stored as the nonzero entries.
    map: Vec<(usize, usize, f64)>,
    /// The map's constant: the station at the zero state (the station's rest position
    /// relative to the ring's centre; zero velocity, checked by `RingedRotor::new`).
    offset: [f64; 4],
    slots: [usize; 2],
}

impl<'a> Station<'a> {
    /// The paper's model: `r = (y0, y1)`, `v = (y2, y3)`, ring in slots 4, 5.
    fn paper(ring: &'a SnubberRing) -> Self {
        Self {
            ring,
            map: vec![(0, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0), (3, 3, 1.0)],
            offset: [0.0; 4],
            slots: [4, 5],
        }
    }

    /// A smooth rotor's station, from its (affine) station map applied to the zero state and
    /// to unit vectors.
    fn of<R: SmoothRotor>(rotor: &R, ring: &'a SnubberRing) -> Self
    where
        DefaultAllocator: Allocator<R::Dim>,
    {
        let dim = rotor.dim();
        let mut e = OVector::<f64, R::Dim>::zeros_generic(dim, nalgebra::U1);
        let k0 = rotor.station(&e);
        let offset = [k0.r.x, k0.r.y, k0.v.x, k0.v.y];
        let mut map = Vec::new();
        for j in 0..dim.value() {
            e[j] = 1.0;
            let k = rotor.station(&e);
            e[j] = 0.0;
            for (a, c) in [k.r.x, k.r.y, k.v.x, k.v.y].into_iter().enumerate() {
                let c = c - offset[a];
                if c != 0.0 {
                    map.push((a, j, c));
                }
            }
        }
        Self {
            ring,
            map,
            offset,
            slots: rotor.ring_slots(),
        }
    }

    fn kinematics<D: Dim>(&self, y: &OVector<f64, D>) -> Kinematics
    where
        DefaultAllocator: Allocator<D>,
    {
        let mut k = self.offset;
        for &(a, j, c) in &self.map {
            k[a] += c * y[j];
        }
        Kinematics::new([k[0], k[1]], [k[2], k[3]])
    }

    fn ring_position<D: Dim>(&self, y: &OVector<f64, D>) -> Vector2<f64>
    where
        DefaultAllocator: Allocator<D>,
    {
        Vector2::new(y[self.slots[0]], y[self.slots[1]])
    }

    fn is_slot(&self, i: usize) -> bool {
        self.slots.contains(&i)
    }

    /// The full-state gradient of a ring guard.
    fn guard_gradient<D: Dim>(
        &self,
        mode: &RingMode,
        guard: RingGuard,
        t: f64,
        y: &OVector<f64, D>,
        grad: &mut OVector<f64, D>,
    ) -> f64
    where
        DefaultAllocator: Allocator<D>,
    {
        grad.fill(0.0);
        let k = self.kinematics(y);
        let Some(g) = self
            .ring
            .guard_gradient(mode, guard, t, &k, &RingCache::default())
        else {
            grad.fill(f64::NAN);
            return f64::NAN;
        };
        let rv = [g.r.x, g.r.y, g.v.x, g.v.y];
        for &(a, j, c) in &self.map {
            grad[j] += c * rv[a];
        }
        // In free flight the guard reads the relaxing ring, which is the state's ring: its
        // dependence is on the slots, and at a fixed state the guard has no explicit time
        // dependence (the ring's motion is the field's ring component).
        grad[self.slots[0]] += g.s.x;
        grad[self.slots[1]] += g.s.y;
        0.0
    }

    /// Rows `J (dr/dy) m` of the ring slots: the variation of a ring at `c`.
    fn slaved_rows<D: Dim>(
        &self,
        jac: &Matrix2<f64>,
        source: &OMatrix<f64, D, Dyn>,
        out: &mut OMatrix<f64, D, Dyn>,
    ) where
        DefaultAllocator: Allocator<D, Dyn>,
    {
        for col in 0..source.ncols() {
            let mut dr = [0.0; 2];
            for &(a, j, c) in &self.map {
                if a < 2 {
                    dr[a] += c * source[(j, col)];
                }
            }
            let ds = mat_vec(jac, dr);
            out[(self.slots[0], col)] = ds[0];
            out[(self.slots[1], col)] = ds[1];
        }
    }

    #[allow(clippy::too_many_arguments)]
    /// The reset's Jacobian: identity on the rotor; the ring's slots differentiate where the
    /// transition placed the ring (`s_plus`), found among the branches it can have used.
    fn transition_jacobian<D: Dim>(
        &self,
        mode: &RingMode,
        t: f64,
        y: &OVector<f64, D>,
        next: &RingMode,
        s_plus: Vector2<f64>,
        rx: &mut OMatrix<f64, D, D>,
        rt: &mut OVector<f64, D>,
    ) -> Result<(), ModelError>
    where
        DefaultAllocator: Allocator<D> + Allocator<D, D>,
    {
        rx.fill_with_identity();
        rt.fill(0.0);
        let [i, j] = self.slots;
        rx.row_mut(i).fill(0.0);
        rx.row_mut(j).fill(0.0);
        if s_plus == Vector2::zeros() {
            return Ok(()); // placed at its centre: a constant
        }
        let k = self.kinematics(y);
        let ring = self.ring;
        let mut candidates: Vec<Branches> = Vec::with_capacity(4);
        for m in [mode, next] {
            if let RingMode::Contact(b) = m {
                candidates.push(*b);
            }
        }
        if let Ok(c) = ring.locate(&k.r) {
            candidates.push(c.branches);
        }
        candidates.push(Branches::of(ring, &Vector2::zeros()));
        let tol = 1e-9 * ring.gap;
        let placed: Option<RingContact> = candidates.iter().find_map(|b| {
            ring.locate_on(&k.r, *b, f64::NAN)
                .ok()
                .filter(|c| (c.s - s_plus).abs().max() <= tol)
        });
        let contact = placed.ok_or_else(|| ModelError::Transition {
            t,
            reason: format!(
                "cannot tell where the ring was placed at s = ({}, {}): no contact branch puts \
                 it there",
                s_plus.x, s_plus.y
            ),
        })?;
        for (axis, slot) in [i, j].into_iter().enumerate() {
            // An axis snapped onto its preload is a constant.
            let d = if axis == 0 {
                ring.x.preload
            } else {
                ring.y.preload
            };
            if d > 0.0 && s_plus[axis].abs() == d && contact.s[axis] != s_plus[axis] {
                continue;
            }
            for &(a, col, c) in &self.map {
                if a < 2 {
                    rx[(slot, col)] += contact.jacobian[(axis, a)] * c;
                }
            }
        }
        Ok(())
    }

    /// The algebraic (ring) rows of `m` in `mode` at `(t, y)`.
    fn algebraic_variation<D: Dim>(
        &self,
        mode: &RingMode,
        t: f64,
        y: &OVector<f64, D>,
        start: &OMatrix<f64, D, Dyn>,
        m: &mut OMatrix<f64, D, Dyn>,
    ) where
        DefaultAllocator: Allocator<D> + Allocator<D, Dyn>,
    {
        match mode {
            RingMode::Contact(b) => {
                let k = self.kinematics(y);
                match self.ring.locate_on(&k.r, *b, f64::NAN) {
                    Ok(c) => {
                        let source = m.clone_owned();
                        self.slaved_rows(&c.jacobian, &source, m);
                    }
                    Err(_) => {
                        m.row_mut(self.slots[0]).fill(f64::NAN);
                        m.row_mut(self.slots[1]).fill(f64::NAN);
                    }
                }
            }
            RingMode::Free { relax, .. } => {
                let rho = relaxation_factor(relax, self.ring, t);
                for (axis, slot) in self.slots.into_iter().enumerate() {
                    for c in 0..m.ncols() {
                        m[(slot, c)] = rho[axis] * start[(slot, c)];
                    }
                }
            }
        }
    }

    /// The section state: rotor components from `z`, the ring placed (in contact) or kept.
    fn section_state<D: Dim>(&self, template: &OVector<f64, D>, z: &[f64]) -> OVector<f64, D>
    where
        DefaultAllocator: Allocator<D>,
    {
        let mut y = template.clone_owned();
        let mut k = 0;
        for i in 0..y.len() {
            if !self.is_slot(i) {
                y[i] = z[k];
                k += 1;
            }
        }
        let r = self.kinematics(&y).r;
        if r.norm() > self.ring.gap {
            if let Ok(c) = self.ring.locate(&r) {
                y[self.slots[0]] = c.s.x;
                y[self.slots[1]] = c.s.y;
            }
        }
        y
    }

    fn openness<D: Dim>(&self, mode: &RingMode, y: &OVector<f64, D>) -> f64
    where
        DefaultAllocator: Allocator<D>,
    {
        match mode {
            RingMode::Free { .. } => self.ring_position(y).norm(),
            RingMode::Contact(_) => 0.0,
        }
    }

    fn depth<D: Dim>(&self, mode: &RingMode, y: &OVector<f64, D>) -> f64
    where
        DefaultAllocator: Allocator<D>,
    {
        let r = self.kinematics(y).r;
        match mode {
            RingMode::Contact(_) => r.norm() - self.ring.gap,
            RingMode::Free { .. } => (r - self.ring_position(y)).norm() - self.ring.gap,
        }
    }
}

/// `j * v` (kept out of the generic functions, whose allocator bounds would shadow `Const<2>`'s).
fn mat_vec(j: &Matrix2<f64>, v: [f64; 2]) -> [f64; 2] {
    [
        j[(0, 0)] * v[0] + j[(0, 1)] * v[1],
        j[(1, 0)] * v[0] + j[(1, 1)] * v[1],
    ]
}

/// The relaxation's sensitivity at `t` (1 at its start).
fn relaxation_factor(relax: &Relaxation, ring: &SnubberRing, t: f64) -> Vector2<f64> {
    relax.sensitivity(ring, t)
}

impl Variational for JeffcottModel {
    fn is_algebraic_variation(&self, i: usize) -> bool {
        i >= 4
    }

    fn rhs_jacobian(
        &self,
        mode: Mode,
        _t: f64,
        y: &OVector<f64, U6>,
        jac: &mut OMatrix<f64, U6, U6>,
        _cache: &Cache,
        _work: &mut Workspace<U6>,
    ) {
        let nu1 = self.params().nu1;
        jac.fill(0.0);
        for i in 0..2 {
            jac[(i, i + 2)] = 1.0;
            jac[(i + 2, i)] = -1.0;
            jac[(i + 2, i + 2)] = -2.0 * nu1;
        }
        if let RingMode::Contact(b) = mode {
            let r = Vector2::new(y[0], y[1]);
            let v = Vector2::new(y[2], y[3]);
            match self.ring().locate_on(&r, b, f64::NAN) {
                Ok(c) => {
                    let f = self.ring().force_jacobian(&c, &v);
                    for i in 0..2 {
                        for j in 0..2 {
                            jac[(i + 2, j)] -= f.position[(i, j)];
                            jac[(i + 2, j + 2)] -= f.velocity[(i, j)];
                        }
                    }
                }
                Err(_) => jac.fill(f64::NAN),
            }
        }
    }

    fn guard_gradient(
        &self,
        mode: Mode,
        i: usize,
        t: f64,
        y: &OVector<f64, U6>,
        grad: &mut OVector<f64, U6>,
        _cache: &Cache,
        _work: &mut Workspace<U6>,
    ) -> f64 {
        let guard = self.ring().guard(&mode, i).unwrap_or(RingGuard::Onset);
        Station::paper(self.ring()).guard_gradient(&mode, guard, t, y, grad)
    }

    fn transition_jacobian(
        &self,
        mode: Mode,
        guard: usize,
        t: f64,
        y: &OVector<f64, U6>,
        after: &OVector<f64, U6>,
        next: Mode,
        rx: &mut OMatrix<f64, U6, U6>,
        rt: &mut OVector<f64, U6>,
    ) -> Result<(), ModelError> {
        let _ = guard;
        let s_plus = Vector2::new(after[4], after[5]);
        Station::paper(self.ring()).transition_jacobian(&mode, t, y, &next, s_plus, rx, rt)
    }

    fn segment_jacobian(
        &self,
        _mode: Mode,
        t0: f64,
        _y0: &OVector<f64, U6>,
        t: f64,
        jac: &mut OMatrix<f64, U6, U6>,
    ) {
        let phi = FreeOscillator::new(self.params()).transition_matrix(t - t0);
        jac.fill(0.0);
        jac.fixed_view_mut::<4, 4>(0, 0).copy_from(&phi);
    }

    fn algebraic_variation(
        &self,
        mode: Mode,
        t: f64,
        y: &OVector<f64, U6>,
        start: &OMatrix<f64, U6, Dyn>,
        m: &mut OMatrix<f64, U6, Dyn>,
        _cache: &Cache,
    ) {
        Station::paper(self.ring()).algebraic_variation(&mode, t, y, start, m);
    }

    fn section_state(&self, _t: f64, template: &OVector<f64, U6>, z: &[f64]) -> OVector<f64, U6> {
        Station::paper(self.ring()).section_state(template, z)
    }

    fn section_openness(&self, mode: Mode, _t: f64, y: &OVector<f64, U6>) -> f64 {
        Station::paper(self.ring()).openness(&mode, y)
    }

    fn contact_depth(&self, mode: Mode, _t: f64, y: &OVector<f64, U6>) -> Option<f64> {
        Some(Station::paper(self.ring()).depth(&mode, y))
    }
}

impl<R: SmoothRotor> Variational for RingedRotor<R>
where
    DefaultAllocator: VariationalAlloc<R::Dim>,
{
    fn guard_gradient(
        &self,
        mode: RingMode,
        i: usize,
        t: f64,
        y: &OVector<f64, R::Dim>,
        grad: &mut OVector<f64, R::Dim>,
        _cache: &RingCache,
        _work: &mut Workspace<R::Dim>,
    ) -> f64 {
        let guard = self.ring().guard(&mode, i).unwrap_or(RingGuard::Onset);
        Station::of(self.rotor(), self.ring()).guard_gradient(&mode, guard, t, y, grad)
    }

    fn transition_jacobian(
        &self,
        mode: RingMode,
        guard: usize,
        t: f64,
        y: &OVector<f64, R::Dim>,
        after: &OVector<f64, R::Dim>,
        next: RingMode,
        rx: &mut OMatrix<f64, R::Dim, R::Dim>,
        rt: &mut OVector<f64, R::Dim>,
    ) -> Result<(), ModelError> {
        let _ = guard;
        let station = Station::of(self.rotor(), self.ring());
        let s_plus = station.ring_position(after);
        station.transition_jacobian(&mode, t, y, &next, s_plus, rx, rt)
    }

    fn algebraic_variation(
        &self,
        mode: RingMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        start: &OMatrix<f64, R::Dim, Dyn>,
        m: &mut OMatrix<f64, R::Dim, Dyn>,
        _cache: &RingCache,
    ) {
        Station::of(self.rotor(), self.ring()).algebraic_variation(&mode, t, y, start, m);
    }

    fn section_state(
        &self,
        _t: f64,
        template: &OVector<f64, R::Dim>,
        z: &[f64],
    ) -> OVector<f64, R::Dim> {
        Station::of(self.rotor(), self.ring()).section_state(template, z)
    }

    fn section_openness(&self, mode: RingMode, _t: f64, y: &OVector<f64, R::Dim>) -> f64 {
        Station::of(self.rotor(), self.ring()).openness(&mode, y)
    }

    fn contact_depth(&self, mode: RingMode, _t: f64, y: &OVector<f64, R::Dim>) -> Option<f64> {
        Some(Station::of(self.rotor(), self.ring()).depth(&mode, y))
    }
}
