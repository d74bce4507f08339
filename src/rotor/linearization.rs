//! A ringed rotor's linearisation: [`Variational`] for [`RingedRotor`], the ring's parts
//! analytic, the rotor's own field by differences (the trait's default).
//!
//! The ring's slots ([`SmoothRotor::ring_slots`]) are the algebraic components; guards, resets
//! and algebraic rows go through the ring's station map (`ring::station`), sampled from
//! [`SmoothRotor::station`] (affine, checked by [`RingedRotor::new`]).

use nalgebra::{DefaultAllocator, Dyn, OMatrix, OVector};

use super::{RingedRotor, SmoothRotor};
use crate::hybrid::{ModelError, Variational, VariationalAlloc, Workspace};
use crate::ring::station::Station;
use crate::ring::{RingCache, RingMode};

/// The ring at the rotor's station.
fn station<R: SmoothRotor>(model: &RingedRotor<R>) -> Station<'_>
where
    DefaultAllocator: VariationalAlloc<R::Dim>,
{
    let rotor = model.rotor();
    Station::sampled(model.ring(), rotor.dim(), rotor.ring_slots(), |y| {
        rotor.station(y)
    })
}

impl<R: SmoothRotor> Variational for RingedRotor<R>
where
    DefaultAllocator: VariationalAlloc<R::Dim>,
{
    /// The rotor's [`SmoothRotor::jacobian_product`] where it has one (the ring force's
    /// Jacobian on the mode's branches in contact, the ring slots' rows zero), else the dense
    /// product of [`RotorModel::jacobian`](crate::hybrid::RotorModel::jacobian).
    fn rhs_jacobian_product(
        &self,
        mode: RingMode,
        t: f64,
        y: &OVector<f64, R::Dim>,
        v: &OMatrix<f64, R::Dim, Dyn>,
        out: &mut OMatrix<f64, R::Dim, Dyn>,
        jac: &mut OMatrix<f64, R::Dim, R::Dim>,
        (cache, work): (&RingCache, &mut Workspace<R::Dim>),
    ) {
        if let Some(force) = self.force_jacobian(mode, y, cache) {
            let rotor = self.rotor();
            if rotor.jacobian_product(t, y, force.as_ref(), v.as_slice(), out.as_mut_slice()) {
                for i in rotor.ring_slots() {
                    out.row_mut(i).fill(0.0);
                }
                return;
            }
        }
        self.rhs_jacobian(mode, t, y, jac, cache, work);
        out.gemm(1.0, jac, v, 0.0);
    }

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
        station(self).guard_gradient(&mode, i, t, y, grad)
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
        let station = station(self);
        let s_plus = station.ring_position(after);
        station
            .transition_jacobian(&mode, y, &next, s_plus, rx, rt)
            .map_err(|e| ModelError::Transition {
                t,
                reason: e.to_string(),
            })
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
        station(self).algebraic_variation(&mode, t, y, start, m);
    }

    /// The closed form's transition matrix ([`LinearClosedForm::transition_matrix`](super::LinearClosedForm::transition_matrix)) in the
    /// rotor's rows and columns; the ring's columns are zero (the rotor's free flight does not
    /// depend on the ring), its rows unused (algebraic). Asked for only in exact modes, which
    /// exist only with an accepted closed form ([`RingedRotor::closed_form`]).
    fn segment_jacobian(
        &self,
        _mode: RingMode,
        t0: f64,
        _y0: &OVector<f64, R::Dim>,
        t: f64,
        jac: &mut OMatrix<f64, R::Dim, R::Dim>,
    ) {
        let Some(Ok(form)) = self.closed_form() else {
            jac.fill(f64::NAN);
            return;
        };
        let phi = form.transition_matrix(t - t0);
        jac.fill(0.0);
        let n2 = phi.nrows();
        for j in 0..n2 {
            for i in 0..n2 {
                jac[(i, j)] = phi[(i, j)];
            }
        }
    }

    fn section_state(
        &self,
        _t: f64,
        template: &OVector<f64, R::Dim>,
        z: &[f64],
    ) -> OVector<f64, R::Dim> {
        station(self).section_state(template, z)
    }

    fn section_openness(&self, mode: RingMode, _t: f64, y: &OVector<f64, R::Dim>) -> f64 {
        station(self).openness(&mode, y)
    }

    fn contact_depth(&self, mode: RingMode, _t: f64, y: &OVector<f64, R::Dim>) -> Option<f64> {
        Some(station(self).depth(&mode, y))
    }
}
