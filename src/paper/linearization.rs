//! The paper's model's linearisation, everything analytic: [`Variational`] for
//! [`JeffcottModel`].
//!
//! The ring's slots (4, 5) are the algebraic components; guards, resets and algebraic rows go
//! through the ring's station map (`ring::station`), here the identity on
//! $r = (y_0, y_1)$, $v = (y_2, y_3)$. The field's Jacobian is analytic
//! ([`SnubberRing::force_jacobian`](crate::ring::SnubberRing::force_jacobian)), and so is the
//! free flight's transition matrix ([`FreeOscillator::transition_matrix`]).

use nalgebra::{Dyn, OMatrix, OVector, Vector2, U6};

use super::free_flight::FreeOscillator;
use super::{Cache, JeffcottModel, Mode};
use crate::hybrid::{ModelError, Variational, Workspace};
use crate::ring::station::Station;
use crate::ring::{RingMode, SnubberRing};

/// The paper's station: `r = (y0, y1)`, `v = (y2, y3)`, ring in slots 4, 5.
fn station(ring: &SnubberRing) -> Station<'_> {
    Station::new(
        ring,
        vec![(0, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0), (3, 3, 1.0)],
        [0.0; 4],
        [4, 5],
    )
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
        station(self.ring()).guard_gradient(&mode, i, t, y, grad)
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
        station(self.ring())
            .transition_jacobian(&mode, y, &next, s_plus, rx, rt)
            .map_err(|e| ModelError::Transition {
                t,
                reason: e.to_string(),
            })
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
        station(self.ring()).algebraic_variation(&mode, t, y, start, m);
    }

    fn section_state(&self, _t: f64, template: &OVector<f64, U6>, z: &[f64]) -> OVector<f64, U6> {
        station(self.ring()).section_state(template, z)
    }

    fn section_openness(&self, mode: Mode, _t: f64, y: &OVector<f64, U6>) -> f64 {
        station(self.ring()).openness(&mode, y)
    }

    fn contact_depth(&self, mode: Mode, _t: f64, y: &OVector<f64, U6>) -> Option<f64> {
        Some(station(self.ring()).depth(&mode, y))
    }
}
