//! A Jeffcott rotor with cross-coupled stiffness `q` and a cubic bearing term `k3`, written as
//! a [`SmoothRotor`] and put on the crate's snubber ring with [`RingedRotor`]. With
//! $u = r - e$ the displacement from the rest position,
//!
//! $$u'' + 2\nu_1 u' + u + q\,(u_y, -u_x) + k_3 |u|^2 u + f_{ring} = \beta\eta^2
//!   (\cos, \sin)(\varphi_0 + \eta\tau).$$

use jeffcott::nalgebra::{SVector, Vector2, U6};
use jeffcott::params::Params;
use jeffcott::ring::{Kinematics, RingAxis, SnubberRing};
use jeffcott::rotor::{RingedRotor, RotorError, SmoothRotor};

/// The rotor without the ring; state `[x, y, x', y', x_s, y_s]`.
#[derive(Debug, Clone, PartialEq)]
pub struct CrossCoupledRotor {
    /// The paper's parameters (damping, forcing, eccentricity, phase).
    pub params: Params,
    /// Cross-coupled stiffness.
    pub q: f64,
    /// Cubic bearing stiffness.
    pub k3: f64,
}

impl SmoothRotor for CrossCoupledRotor {
    type Dim = U6;
    fn dim(&self) -> U6 {
        U6
    }
    fn rhs(&self, t: f64, y: &SVector<f64, 6>, dy: &mut SVector<f64, 6>) {
        let p = &self.params;
        let (ux, uy) = (y[0] - p.ex, y[1] - p.ey);
        let (sin, cos) = (p.phi0 + p.eta * t).sin_cos();
        let (b, cubic) = (p.forcing_amplitude(), self.k3 * (ux * ux + uy * uy));
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = b * cos - 2.0 * p.nu1 * y[2] - ux - self.q * uy - cubic * ux;
        dy[3] = b * sin - 2.0 * p.nu1 * y[3] - uy + self.q * ux - cubic * uy;
    }
    fn station(&self, y: &SVector<f64, 6>) -> Kinematics {
        Kinematics::new([y[0], y[1]], [y[2], y[3]])
    }
    fn add_station_force(&self, _y: &SVector<f64, 6>, f: &Vector2<f64>, dy: &mut SVector<f64, 6>) {
        dy[2] += f.x; // unit mass
        dy[3] += f.y;
    }
    fn ring_slots(&self) -> [usize; 2] {
        [4, 5]
    }
    fn forcing_period(&self) -> f64 {
        self.params.forcing_period()
    }
    fn max_rate(&self, _t: f64, y: &SVector<f64, 6>, k: f64, c: f64) -> Option<f64> {
        // Unit mass: stiffness 1 + k3 (|u|^2 I + 2 u u^T) (eigenvalues up to 3 |k3| |u|^2),
        // the cross coupling q (a skew part, rate |q|), damping 2 nu1.
        let u2 = (y[0] - self.params.ex).powi(2) + (y[1] - self.params.ey).powi(2);
        let stiffness = 1.0 + 3.0 * self.k3.abs() * u2 + k;
        // The forcing's frequency eta must be resolved too.
        Some((stiffness.sqrt() + self.q.abs() + 2.0 * self.params.nu1 + c).max(self.params.eta))
    }
}

/// The rotor on the ring of `params` (stiffness, preload, damping; gap 1).
pub fn on_ring(
    params: Params,
    q: f64,
    k3: f64,
) -> Result<RingedRotor<CrossCoupledRotor>, RotorError> {
    let ring = SnubberRing::new(
        RingAxis::new(params.kx, params.dx),
        RingAxis::new(params.ky, params.dy),
        params.nu2,
        1.0,
    )?;
    RingedRotor::new(CrossCoupledRotor { params, q, k3 }, ring)
}
