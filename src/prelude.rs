//! The items of the common tasks, for `use jeffcott::prelude::*;`.
//!
//! | task | items |
//! |---|---|
//! | the paper's model and its parameters | [`JeffcottModel`], [`State`], [`Params`], [`Preset`] |
//! | simulate any model | [`simulate`], [`SimOptions`], [`OutputPlan`], [`Trajectory`], [`RotorModel`], [`Variational`] |
//! | stroboscopic orbits, periods | [`strobe_orbit`], [`PeriodTest`], [`Periodicity`] |
//! | sweeps and bifurcation diagrams | [`ParamSweep`], [`SweepParameter`], [`bifurcation`], [`start_from`], [`linspace`], [`BifurcationOptions`], [`StderrProgress`] |
//! | stability | [`periodic_orbit`], [`OrbitOptions`], [`PeriodicOrbit`], [`StroboscopicMap`], [`lyapunov_exponents`], [`LyapunovOptions`], [`continue_orbit`], [`ContinuationOptions`], [`locate_loss`], [`LossOptions`] |
//! | attractors and basins | [`find_attractor`], [`AttractorOptions`], [`MatchOptions`], [`scan_grid`], [`Grid2`], [`RunOptions`], [`SweepStore`], [`BasinPlane`], [`ParamPlane`], [`StartPlane`] |
//!
//! Each item keeps its one home (its module); the prelude only re-exports it.
//!
//! # Example
//!
//! The paper's Fig. 8a scene at $\eta = 2$: a simulation, the periodic orbit it settles on
//! with its multipliers, a two-value bifurcation diagram and a small basin scan, with nothing
//! imported but the prelude.
//!
//! ```
//! use jeffcott::prelude::*;
//!
//! // Simulate: stroboscopic states from rest, after 300 forcing periods.
//! let model = JeffcottModel::new(Preset::Fig8a.params().with_eta(2.0))?;
//! let (run, _) = model.strobe_range(&State::zeros(), 300, 300, &SimOptions::default())?;
//! let start = run.strobe[0].y;
//!
//! // Stability: Newton on the period-1 stroboscopic map from there, and its multipliers.
//! let orbit = periodic_orbit(&model, &start, 1, &OrbitOptions::default())?;
//! assert_eq!(orbit.multipliers.len(), 4);
//! assert!(orbit.spectral_radius() < 1.0); // reached by simulation: an attractor, stable
//!
//! // Sweep: period 1 at eta = 2, period 2 at eta = 3 (the paper's Fig. 8a).
//! let family = ParamSweep::new(Preset::Fig8a.params(), SweepParameter::Eta);
//! let config = BifurcationOptions::default().with_transient(300).with_record(8);
//! let diagram = family.bifurcation(&[2.0, 3.0], &config, None)?;
//! let period = |k: usize| diagram.columns[k].as_ref().ok()?.periodicity.period();
//! assert_eq!((period(0), period(1)), (Some(1), Some(2)));
//!
//! // Basins: a 2 x 2 grid of starts, each run until it settles, the attractors matched.
//! let plane = BasinPlane::new(Preset::Fig8a.params().with_eta(2.0), StartPlane::XVx);
//! let grid = Grid2::linspace((-0.5, 0.5, 2), (-0.5, 0.5, 2))?;
//! let attractor = AttractorOptions::default().with_transient(300);
//! let scan = scan_grid(&grid, plane.setup(), &attractor, None, &RunOptions::default(), None)?;
//! let catalogue = scan.catalogue(&MatchOptions::default());
//! assert!(!catalogue.entries.is_empty());
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#[doc(no_inline)]
pub use crate::analysis::{
    bifurcation, linspace, start_from, strobe_orbit, BifurcationOptions, PeriodTest, Periodicity,
    StderrProgress,
};
#[doc(no_inline)]
pub use crate::global::{
    find_attractor, scan_grid, AttractorOptions, Grid2, MatchOptions, RunOptions, SweepStore,
};
#[doc(no_inline)]
pub use crate::hybrid::{simulate, OutputPlan, RotorModel, SimOptions, Trajectory, Variational};
#[doc(no_inline)]
pub use crate::paper::{
    BasinPlane, JeffcottModel, ParamPlane, ParamSweep, StartPlane, State, SweepParameter,
};
#[doc(no_inline)]
pub use crate::params::{Params, Preset};
#[doc(no_inline)]
pub use crate::stability::{
    continue_orbit, locate_loss, lyapunov_exponents, periodic_orbit, ContinuationOptions,
    LossOptions, LyapunovOptions, OrbitOptions, PeriodicOrbit, StroboscopicMap,
};
