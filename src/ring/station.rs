//! The ring at a rotor's station: the linearisation pieces every model built on the ring
//! shares (the paper's model, `paper::linearization`; any [`crate::rotor::RingedRotor`],
//! `rotor::linearization`).
//!
//! A model keeps the ring's position in two state slots, set by the ring's rules, not
//! integrated: they are the algebraic components of its linearisation. The rotor meets the ring
//! at a station whose displacement and velocity are an affine map of the state.
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

use std::fmt;

use nalgebra::allocator::Allocator;
use nalgebra::{DefaultAllocator, Dim, Dyn, Matrix2, OMatrix, OVector, Vector2};

use super::{
    Branches, Kinematics, Relaxation, RingCache, RingContact, RingGuard, RingMode, SnubberRing,
};

/// A transition put the ring where no contact branch puts it: the reset's Jacobian is unknown.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Unplaced {
    s: Vector2<f64>,
}

impl fmt::Display for Unplaced {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "cannot tell where the ring was placed at s = ({}, {}): no contact branch puts \
             it there",
            self.s.x, self.s.y
        )
    }
}

/// The ring at a rotor's station: the station's affine map and the ring's slots.
pub(crate) struct Station<'a> {
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
    /// A station given by its map's nonzero entries `(a, j, c)` (row `a` of `r.x, r.y, v.x,
    /// v.y` has coefficient `c` of `y[j]`), its constant and the ring's slots.
    pub(crate) fn new(
        ring: &'a SnubberRing,
        map: Vec<(usize, usize, f64)>,
        offset: [f64; 4],
        slots: [usize; 2],
    ) -> Self {
        Self {
            ring,
            map,
            offset,
            slots,
        }
    }

    /// A station from its (affine) map `station`, applied to the zero state of dimension `dim`
    /// and to unit vectors.
    pub(crate) fn sampled<D: Dim>(
        ring: &'a SnubberRing,
        dim: D,
        slots: [usize; 2],
        station: impl Fn(&OVector<f64, D>) -> Kinematics,
    ) -> Self
    where
        DefaultAllocator: Allocator<D>,
    {
        let mut e = OVector::<f64, D>::zeros_generic(dim, nalgebra::U1);
        let k0 = station(&e);
        let offset = [k0.r.x, k0.r.y, k0.v.x, k0.v.y];
        let mut map = Vec::new();
        for j in 0..dim.value() {
            e[j] = 1.0;
            let k = station(&e);
            e[j] = 0.0;
            for (a, c) in [k.r.x, k.r.y, k.v.x, k.v.y].into_iter().enumerate() {
                let c = c - offset[a];
                if c != 0.0 {
                    map.push((a, j, c));
                }
            }
        }
        Self::new(ring, map, offset, slots)
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

    pub(crate) fn ring_position<D: Dim>(&self, y: &OVector<f64, D>) -> Vector2<f64>
    where
        DefaultAllocator: Allocator<D>,
    {
        Vector2::new(y[self.slots[0]], y[self.slots[1]])
    }

    fn is_slot(&self, i: usize) -> bool {
        self.slots.contains(&i)
    }

    /// The full-state gradient of guard `i` of `mode` (the onset guard if `mode` has no such
    /// guard); 0, its time derivative at a fixed state (NaN where the ring has no gradient).
    pub(crate) fn guard_gradient<D: Dim>(
        &self,
        mode: &RingMode,
        i: usize,
        t: f64,
        y: &OVector<f64, D>,
        grad: &mut OVector<f64, D>,
    ) -> f64
    where
        DefaultAllocator: Allocator<D>,
    {
        let guard = self.ring.guard(mode, i).unwrap_or(RingGuard::Onset);
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
    /// The ring's rows of `out`: $J$ times the station's position rows of `source`.
    pub(crate) fn slaved_rows<D: Dim>(
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

    /// The ring's rows of `m` while the shaft rolls on it: $s = r - \gamma n(\theta)$, the contact
    /// direction's variation $\delta\theta$ fixed since the roll started (an imposed spin turns
    /// it at a rate no state changes), read from `start` (the variation then) as
    /// $\gamma\delta\theta = t_0\cdot(\delta r_0 - \delta s_0)$: $\delta s = \delta r -
    /// t\thinspace\gamma\delta\theta$, `tangent` $t$ now and `tangent_start` $t_0$.
    pub(crate) fn rolling_rows<D: Dim>(
        &self,
        tangent: Vector2<f64>,
        tangent_start: Vector2<f64>,
        start: &OMatrix<f64, D, Dyn>,
        m: &mut OMatrix<f64, D, Dyn>,
    ) where
        DefaultAllocator: Allocator<D, Dyn>,
    {
        let position = |source: &OMatrix<f64, D, Dyn>, col: usize| {
            let mut dr = Vector2::new(0.0, 0.0);
            for &(a, j, c) in &self.map {
                if a < 2 {
                    dr[a] += c * source[(j, col)];
                }
            }
            dr
        };
        for col in 0..m.ncols() {
            let ds0 = Vector2::new(start[(self.slots[0], col)], start[(self.slots[1], col)]);
            let turn = tangent_start.dot(&(position(start, col) - ds0));
            let ds = position(m, col) - tangent * turn;
            m[(self.slots[0], col)] = ds.x;
            m[(self.slots[1], col)] = ds.y;
        }
    }

    /// The reset's Jacobian: identity on the rotor; the ring's slots differentiate where the
    /// transition placed the ring (`s_plus`), found among the branches it can have used.
    pub(crate) fn transition_jacobian<D: Dim>(
        &self,
        mode: &RingMode,
        y: &OVector<f64, D>,
        next: &RingMode,
        s_plus: Vector2<f64>,
        rx: &mut OMatrix<f64, D, D>,
        rt: &mut OVector<f64, D>,
    ) -> Result<(), Unplaced>
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
        let contact = placed.ok_or(Unplaced { s: s_plus })?;
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
    pub(crate) fn algebraic_variation<D: Dim>(
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
    pub(crate) fn section_state<D: Dim>(
        &self,
        template: &OVector<f64, D>,
        z: &[f64],
    ) -> OVector<f64, D>
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
        if r.norm() > self.ring.gap
            && let Ok(c) = self.ring.locate(&r)
        {
            y[self.slots[0]] = c.s.x;
            y[self.slots[1]] = c.s.y;
        }
        y
    }

    pub(crate) fn openness<D: Dim>(&self, mode: &RingMode, y: &OVector<f64, D>) -> f64
    where
        DefaultAllocator: Allocator<D>,
    {
        match mode {
            RingMode::Free { .. } => self.ring_position(y).norm(),
            RingMode::Contact(_) => 0.0,
        }
    }

    pub(crate) fn depth<D: Dim>(&self, mode: &RingMode, y: &OVector<f64, D>) -> f64
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
