//! The paper's model: the Jeffcott rotor with a preloaded snubber ring, as a
//! [`RotorModel`](crate::hybrid::RotorModel), and the analyses of [`crate::analysis`] over its
//! parameters ([`ParamSweep`]) and on the grids of [`crate::global`] ([`BasinPlane`],
//! [`ParamPlane`]).
//!
//! # The rotor's free flight in closed form
//!
//! The rotor's free flight in closed form.
//!
//! Out of contact each axis is a damped linear oscillator under the rotating out-of-balance.
//! In complex notation $z = x + iy$:
//!
//! $$z^{\prime\prime} + 2\nu_1 z^\prime + z = e + B e^{i\theta(\tau)},\qquad \theta = \varphi_0 + \eta\tau,\quad
//! B = \beta\eta^2.$$
//!
//! The particular solution is the circular orbit $z_p = e + Z e^{i\theta}$ with
//! $Z = B/(1 - \eta^2 + 2i\nu_1\eta)$; the rest $w = z - z_p$ solves the homogeneous equation,
//!
//! $$w(\tau_0 + u) = e^{-\nu_1 u}\big(w_0\thinspace c(u) + (w_0^\prime + \nu_1 w_0)\thinspace S(u)\big),$$
//!
//! with $c = \cos\omega_d u$, $S = \sin(\omega_d u)/\omega_d$, $\omega_d^2 = 1 - \nu_1^2$
//! ($\cosh$/$\sinh$ when over-damped, $c = 1$, $S = u$ when critical).
//!
//! The energy $|w|^2 + |w^\prime|^2$ of the homogeneous part never grows
//! ($\tfrac{d}{d\tau}(|w|^2+|w^\prime|^2) = -4\nu_1|w^\prime|^2$), which gives the bounds that the contact
//! search needs (see [`FreeFlight::bounds`]).
mod free_flight;
mod linearization;
mod model;
mod planes;
pub mod rub;
mod sweep;

pub use free_flight::{FreeFlight, FreeOscillator, RotorState};
pub use model::{guard, Cache, FreeSegment, JeffcottModel, Mode, RunFailure, State};
pub use planes::{BasinPlane, ParamPlane, StartPlane};
pub use sweep::{poincare_map, ParamSweep, RotorStart, SweepParameter};
