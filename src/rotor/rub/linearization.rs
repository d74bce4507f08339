//! A rubbing rotor's linearisation: [`Variational`] for [`RubbingRotor`], so that periodic
//! orbits, their Floquet multipliers and Lyapunov exponents go through slip reversals and the
//! roll-slip transitions.
//!
//! Free flight and the touch are the frictionless composition's ([`RingedRotor`]'s, analytic).
//! Slipping, the ring is a function of the rotor's position ($s = s^*_\sigma(r)$, algebraic
//! rows $\delta s = J\delta r$) and the trait's differences serve. Rolling, the ring's
//! direction $\theta$ is not a function of the rotor's state but of the roll's history (the
//! mode holds it): the state's ring slots carry it, $\theta$ the direction of $r - s$, so the
//! field, the guards and the resets are differenced with $\theta$ read from the slots, and the
//! slots' rows are $\delta s = \delta r - t\thinspace\gamma\delta\theta$ with $\delta\theta$ fixed
//! since the roll started (an imposed spin turns the contact at a rate no state changes; on a
//! non-ideal drive the rows are NaN: not built).

use nalgebra::{DefaultAllocator, Dyn, OMatrix, OVector, Vector2};

use super::{RubCache, RubMode, RubbingRotor};
use crate::hybrid::{
    field_differences, guard_differences, reset_differences, ModelError, RotorModel, Variational,
    VariationalAlloc, Workspace,
};
use crate::ode::JacobianMut;
use crate::ring::station::Station;
use crate::ring::RingMode;
use crate::rotor::SmoothRotor;

impl<R: SmoothRotor> RubbingRotor<R>
where
    DefaultAllocator: VariationalAlloc<R::Dim>,
{
    /// `mode` with, while rolling, the contact direction at `t` read from the ring's slots of
    /// `y` (the direction of $r - s$) instead of the roll's start.
    fn rolling_from_slots(&self, mode: RubMode, t: f64, y: &OVector<f64, R::Dim>) -> RubMode {
        let RubMode::Roll {
            shaft, branches, ..
        } = mode
        else {
            return mode;
        };
        let n = self.station(y).r - self.ring_position(y);
        let turned = self.radius / self.rub.ring().gap * (self.spin(t, y).angle - shaft);
        RubMode::Roll {
            angle: n.y.atan2(n.x) + turned,
            shaft,
            branches,
        }
    }

    /// The ring at the rotor's station (its affine map).
    fn station_map(&self) -> Station<'_> {
        let rotor = &self.inner.rotor;
        Station::sampled(self.rub.ring(), rotor.dim(), rotor.ring_slots(), |y| {
            rotor.station(y)
        })
    }

    /// The ring's rows of `m` set to NaN (no linearisation there).
    fn unknown_rows(&self, m: &mut OMatrix<f64, R::Dim, Dyn>) {
        for i in self.inner.rotor.ring_slots() {
            m.row_mut(i).fill(f64::NAN);
        }
    }
}

impl<R: SmoothRotor> Variational for RubbingRotor<R>
where
    DefaultAllocator: VariationalAlloc<R::Dim>,
{
    fn rhs_jacobian(
        &self,
        mode: RubMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        jac: &mut OMatrix<f64, R::Dim, R::Dim>,
        cache: &RubCache,
        work: &mut Workspace<R::Dim>,
    ) {
        if let RubMode::Ring(m) = mode {
            return self.inner.rhs_jacobian(m, t, y, jac, &cache.ring, work);
        }
        let dim = y.shape_generic().0;
        let mut view = JacobianMut::from_slice_generic(jac.as_mut_slice(), dim, dim);
        if matches!(mode, RubMode::Slip { .. }) && self.jacobian(mode, t, y, &mut view, cache) {
            return;
        }
        let field = |y: &OVector<f64, R::Dim>, dy: &mut OVector<f64, R::Dim>| {
            self.rhs(self.rolling_from_slots(mode, t, y), t, y, dy, cache)
        };
        field_differences(field, y, self.difference_step(), jac, work);
    }

    fn guard_gradient(
        &self,
        mode: RubMode,
        i: usize,
        t: f64,
        y: &OVector<f64, R::Dim>,
        grad: &mut OVector<f64, R::Dim>,
        cache: &RubCache,
        work: &mut Workspace<R::Dim>,
    ) -> f64 {
        if let RubMode::Ring(m) = mode {
            return self
                .inner
                .guard_gradient(m, i, t, y, grad, &cache.ring, work);
        }
        let value = |t: f64, y: &OVector<f64, R::Dim>| {
            self.guard_value(self.rolling_from_slots(mode, t, y), i, t, y, cache)
        };
        let steps = (self.difference_step(), self.forcing_period());
        guard_differences(value, t, y, steps, grad, work)
    }

    fn transition_jacobian(
        &self,
        mode: RubMode,
        guard: usize,
        t: f64,
        y: &OVector<f64, R::Dim>,
        after: &OVector<f64, R::Dim>,
        next: RubMode,
        rx: &mut OMatrix<f64, R::Dim, R::Dim>,
        rt: &mut OVector<f64, R::Dim>,
    ) -> Result<(), ModelError> {
        match (mode, next) {
            (RubMode::Ring(m), RubMode::Ring(n)) => {
                return self
                    .inner
                    .transition_jacobian(m, guard, t, y, after, n, rx, rt)
            }
            // A roll starts with the ring where the frictionless contact puts it: that
            // reset's Jacobian. (Differences would be one-sided: off the gap circle there is
            // no contact to start.)
            (RubMode::Ring(m), RubMode::Roll { branches, .. }) => {
                let next = RingMode::Contact(branches);
                return self
                    .inner
                    .transition_jacobian(m, guard, t, y, after, next, rx, rt);
            }
            _ => {}
        }
        let label = self.mode_label(next);
        let apply = |t: f64, y: &OVector<f64, R::Dim>| {
            let mut out = y.clone_owned();
            let from = self.rolling_from_slots(mode, t, y);
            match self.transition(from, guard, t, &mut out) {
                Ok(m) if self.mode_label(m) == label => Some(out),
                _ => None,
            }
        };
        let steps = (self.difference_step(), self.forcing_period());
        reset_differences(apply, (t, y, after), &self.state_scale(), steps, rx, rt)
    }

    fn algebraic_variation(
        &self,
        mode: RubMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        start: &OMatrix<f64, R::Dim, Dyn>,
        m: &mut OMatrix<f64, R::Dim, Dyn>,
        cache: &RubCache,
    ) {
        match mode {
            RubMode::Ring(ring) => {
                self.inner
                    .algebraic_variation(ring, t, y, start, m, &cache.ring)
            }
            RubMode::Slip { sense, branches } => {
                let r = self.station(y).r;
                match self
                    .rub
                    .locate_slipping_on(&r, sense, branches, cache.hint.get())
                {
                    Ok(c) => {
                        let source = m.clone_owned();
                        self.station_map().slaved_rows(&c.jacobian, &source, m);
                    }
                    Err(_) => self.unknown_rows(m),
                }
            }
            RubMode::Roll { angle, shaft, .. } => {
                if self.inner.rotor.spin_speed_index().is_some() {
                    // The drive's phase turns the contact too: not written out.
                    return self.unknown_rows(m);
                }
                let gap = self.rub.ring().gap;
                let theta = angle - self.radius / gap * (self.spin(t, y).angle - shaft);
                let tangent = |a: f64| Vector2::new(-a.sin(), a.cos());
                self.station_map()
                    .rolling_rows(tangent(theta), tangent(angle), start, m);
            }
        }
    }

    fn segment_jacobian(
        &self,
        mode: RubMode,
        t0: f64,
        y0: &OVector<f64, R::Dim>,
        t: f64,
        jac: &mut OMatrix<f64, R::Dim, R::Dim>,
    ) {
        match mode {
            RubMode::Ring(m) => self.inner.segment_jacobian(m, t0, y0, t, jac),
            // Contact modes are integrated, never exact.
            _ => jac.fill(f64::NAN),
        }
    }

    fn section_state(
        &self,
        t: f64,
        template: &OVector<f64, R::Dim>,
        z: &[f64],
    ) -> OVector<f64, R::Dim> {
        self.inner.section_state(t, template, z)
    }

    /// The frictionless composition's in its modes; in contact, 1: the slip's sense and the
    /// roll's direction are the contact's history, not functions of the rotor's state, so a
    /// map whose section falls in a contact is not closed on it (a run started there takes
    /// the onset rule's mode, which need not be the one the flow was in).
    fn section_openness(&self, mode: RubMode, t: f64, y: &OVector<f64, R::Dim>) -> f64 {
        match mode {
            RubMode::Ring(m) => self.inner.section_openness(m, t, y),
            _ => 1.0,
        }
    }

    fn contact_depth(&self, mode: RubMode, t: f64, y: &OVector<f64, R::Dim>) -> Option<f64> {
        self.inner.contact_depth(Self::ring_mode(mode), t, y)
    }
}
