//! The paper's model on the grids of [`crate::global`]: planes of initial states for basins of
//! attraction ([`BasinPlane`]) and planes of two parameters for maps ([`ParamPlane`]).

use super::{JeffcottModel, RotorStart, State, SweepParameter};
use crate::global::PointFailure;
use crate::params::Params;

/// Which two coordinates of the start a basin grid varies (horizontal, vertical); the other
/// coordinates are those of [`BasinPlane::rest`] (by default zero).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize,
)]
#[non_exhaustive]
pub enum StartPlane {
    /// $x_0$ against $x_0^\prime$ (the default).
    #[default]
    XVx,
    /// $x_0$ against $y_0$.
    XY,
    /// The forcing phase $\varphi_0$ against $x_0$ (the phase is a parameter of the model:
    /// each point builds its own).
    PhaseX,
}

impl StartPlane {
    /// Names of the horizontal and vertical coordinates, for labels and CSV columns:
    /// `("x0", "vx0")`, `("x0", "y0")`, `("phi0", "x0")`.
    pub fn names(self) -> (&'static str, &'static str) {
        match self {
            StartPlane::XVx => ("x0", "vx0"),
            StartPlane::XY => ("x0", "y0"),
            StartPlane::PhaseX => ("phi0", "x0"),
        }
    }
}

/// A plane of initial states of the paper's model at fixed parameters: the grid of a basin
/// of attraction ([`crate::global::scan_grid`]).
///
/// Serialized (serde), it is the description of a basin sweep's folder: its parameters are
/// recorded, and a resume with others is refused ([`crate::global::SweepStore::open_scan`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BasinPlane {
    /// The parameters (for [`StartPlane::PhaseX`], `phi0` is replaced at each point).
    pub params: Params,
    /// The coordinates varied.
    pub plane: StartPlane,
    /// The coordinates not varied. Default at rest at the origin.
    pub rest: RotorStart,
}

impl BasinPlane {
    /// The plane `plane` at `params`, the other coordinates zero.
    pub fn new(params: Params, plane: StartPlane) -> Self {
        BasinPlane {
            params,
            plane,
            rest: RotorStart::at_rest(),
        }
    }

    /// The parameters and rotor start at grid point `[h, v]`.
    pub fn start(&self, [h, v]: [f64; 2]) -> (Params, RotorStart) {
        let mut p = self.params;
        let mut s = self.rest;
        match self.plane {
            StartPlane::XVx => {
                s.position[0] = h;
                s.velocity[0] = v;
            }
            StartPlane::XY => s.position = [h, v],
            StartPlane::PhaseX => {
                p.phi0 = h;
                s.position[0] = v;
            }
        }
        (p, s)
    }

    /// The setup closure of [`crate::global::scan_grid`]: the model and its consistent initial
    /// state (ring placed by [`JeffcottModel::state_at`]) at a grid point.
    pub fn setup(
        &self,
    ) -> impl Fn(&[f64; 2]) -> Result<(JeffcottModel, State), PointFailure> + Sync + Send + Clone + use<>
    {
        let this = *self;
        move |point: &[f64; 2]| {
            let (params, start) = this.start(*point);
            let model = JeffcottModel::new(params).map_err(PointFailure::build)?;
            let y0 = start.state(&model)?;
            Ok((model, y0))
        }
    }
}

/// A plane of two parameters of the paper's model, every run from the same start: the grid
/// of a two-parameter map ([`crate::global::scan_grid`]).
///
/// Serialized (serde), it is the description of a map's folder
/// ([`crate::global::SweepStore::open_scan`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ParamPlane {
    /// The other parameters.
    pub base: Params,
    /// The horizontal parameter.
    pub x: SweepParameter,
    /// The vertical parameter.
    pub y: SweepParameter,
    /// Where every run starts (the ring placed consistently). Default at rest at the origin,
    /// the paper's zero initial conditions.
    pub start: RotorStart,
}

impl ParamPlane {
    /// `x` against `y` about `base`, runs from rest.
    pub fn new(base: Params, x: SweepParameter, y: SweepParameter) -> Self {
        ParamPlane {
            base,
            x,
            y,
            start: RotorStart::at_rest(),
        }
    }

    /// The parameters at grid point `[h, v]`.
    pub fn params(&self, [h, v]: [f64; 2]) -> Params {
        self.y.apply(&self.x.apply(&self.base, h), v)
    }

    /// The setup closure of [`crate::global::scan_grid`].
    pub fn setup(
        &self,
    ) -> impl Fn(&[f64; 2]) -> Result<(JeffcottModel, State), PointFailure> + Sync + Send + Clone + use<>
    {
        let this = *self;
        move |point: &[f64; 2]| {
            let model = JeffcottModel::new(this.params(*point)).map_err(PointFailure::build)?;
            let y0 = this.start.state(&model)?;
            Ok((model, y0))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Preset;

    #[test]
    fn planes_place_the_grid_point() {
        let p = Preset::Fig8b.params().with_eta(2.2);
        let b = BasinPlane::new(p, StartPlane::PhaseX);
        let (q, s) = b.start([1.5, 0.3]);
        assert_eq!(
            (q.phi0, s.position, s.velocity),
            (1.5, [0.3, 0.0], [0.0, 0.0])
        );
        let m = ParamPlane::new(p, SweepParameter::Eta, SweepParameter::Preload);
        let q = m.params([3.0, 0.05]);
        assert_eq!((q.eta, q.dx, q.dy, q.ex), (3.0, 0.05, 0.05, p.ex));
        let text = serde_json::to_string(&p).unwrap();
        assert_eq!(serde_json::from_str::<Params>(&text).unwrap(), p);
        // A start beyond the ring is placed in contact; invalid parameters are a build failure.
        let (model, y0) = BasinPlane::new(p, StartPlane::XY).setup()(&[1.05, 0.0]).unwrap();
        assert!(model.params().eta == 2.2 && y0[4] > 0.0);
        let bad =
            ParamPlane::new(p, SweepParameter::Eta, SweepParameter::Nu1).setup()(&[-1.0, 0.1]);
        assert!(matches!(bad, Err(PointFailure::Build { .. })));
    }
}
