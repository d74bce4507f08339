//! Test models with known solutions shared by the integrator tests.
#![allow(dead_code)]

use jeffcott::ode::OdeSystem;
use nalgebra::{SVector, U4};

/// State of the planar two-body problem.
pub type V4 = SVector<f64, 4>;

/// Kepler two-body problem ($\mu = 1$, semi-major axis 1) started at the pericentre with
/// eccentricity `e`; exact solution by Kepler's equation.
pub struct Kepler {
    /// Eccentricity.
    pub e: f64,
}

impl OdeSystem<U4> for Kepler {
    fn rhs(&self, _t: f64, y: &V4, dy: &mut V4) {
        let r2 = y[0] * y[0] + y[1] * y[1];
        let r3 = r2 * r2.sqrt();
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = -y[0] / r3;
        dy[3] = -y[1] / r3;
    }
}

impl Kepler {
    /// Exact state at time `t` (Kepler's equation solved by Newton).
    pub fn exact(&self, t: f64) -> V4 {
        let e = self.e;
        let m = t.rem_euclid(2.0 * std::f64::consts::PI);
        let mut ea = m;
        for _ in 0..60 {
            let d = (ea - e * ea.sin() - m) / (1.0 - e * ea.cos());
            ea -= d;
            if d.abs() < 1e-16 {
                break;
            }
        }
        let b = (1.0 - e * e).sqrt();
        let edot = 1.0 / (1.0 - e * ea.cos());
        V4::new(
            ea.cos() - e,
            b * ea.sin(),
            -ea.sin() * edot,
            b * ea.cos() * edot,
        )
    }
}

/// Least-squares slope of log(y) against log(x).
pub fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let lx: Vec<f64> = x.iter().map(|v| v.ln()).collect();
    let ly: Vec<f64> = y.iter().map(|v| v.ln()).collect();
    let mx = lx.iter().sum::<f64>() / n;
    let my = ly.iter().sum::<f64>() / n;
    let sxy: f64 = lx.iter().zip(&ly).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = lx.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}
