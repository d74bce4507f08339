//! # jeffcott — a Jeffcott rotor with a preloaded snubber ring
//!
//! A reference implementation of the model of Pavlovskaja, Karpenko and Wiercigroch,
//! *Non-linear dynamic interactions of a Jeffcott rotor with preloaded snubber ring*,
//! J. Sound Vib. 276 (2004) 361–379: a two-degree-of-freedom rotor driven by its
//! out-of-balance, making intermittent frictionless contact with a massless ring held by
//! preloaded spring-damper units. The system is piecewise smooth; this crate simulates it
//! exactly where it can and to a stated tolerance where it must, and analyses it with
//! stroboscopic (Poincaré) maps, phase portraits and bifurcation diagrams.
//!
//! ## The model in one page
//!
//! Non-dimensional (gap $\gamma = 1$, time $\tau = \omega_n t$), rotor centre $r = (x, y)$,
//! ring centre $s = (x_s, y_s)$:
//!
//! $$x^{\prime\prime} + 2\nu_1 x^\prime + (x - e_x) + f_x = \beta\eta^2\cos(\varphi_0 + \eta\tau),\qquad
//!   y^{\prime\prime} + 2\nu_1 y^\prime + (y - e_y) + f_y = \beta\eta^2\sin(\varphi_0 + \eta\tau).$$
//!
//! **The ring** ([`ring`]). Each axis has two preloaded units of stiffness $K$ and damping
//! $2\nu_2$; a unit only pushes, so beyond the preload $D$ one lifts off:
//!
//! $$f_i = \begin{cases} 2K s_i + 4\nu_2 s_i^\prime & |s_i| < D_i\\\\
//!   \operatorname{sign}(s_i)\thinspace K(|s_i| + D_i) + 2\nu_2 s_i^\prime & |s_i| \ge D_i.\end{cases}$$
//!
//! **Five regimes.** I: no contact, $|r - s| < 1$. In contact ($|r - s| = 1$) the massless
//! ring sits where its elastic energy $E(s)$ is least under that constraint (a Lagrange
//! problem, $\nabla E = 2\mu (r - s)$, $\mu > 0$); regimes II–V say which axes are beyond their
//! preload (II none, III x, IV y, V both). With zero preload only I and V exist.
//!
//! **Switching.** Contact starts when $|r - s|$ reaches 1; it ends when the normal contact
//! force $n\cdot f$ turns negative (or $|r|$ falls to 1). Out of contact the rotor is a damped
//! linear oscillator and the ring relaxes exponentially with time constant $2\nu_2/K$: both
//! are solved **in closed form** ([`paper::FreeFlight`]), and contact onset is found on the
//! closed form by a **certified** search that cannot step over a contact
//! ([`ring::onset`]). Contact phases are integrated (DOP853 by default, [`ode`]); regime
//! boundaries inside contact are events, so no step straddles a kink.
//!
//! ## Layers
//!
//! | module | role |
//! |---|---|
//! | [`params`] | non-dimensional and SI parameters, validation, the paper's presets |
//! | [`ring`] | the snubber ring as a reusable contact element: force, energy, minimum-energy location and its Jacobian, regimes, relaxation |
//! | [`ode`] | generic explicit Runge–Kutta integrators (DOP853, DOPRI5, RK4) with dense output and event location |
//! | [`hybrid`] | the [`hybrid::RotorModel`] trait of piecewise-smooth rotor models (state size fixed, e.g. `U6`, or known at run time, `Dyn`), the driver through modes and events, and a model's linearisation, [`hybrid::Variational`] (finite-difference defaults) |
//! | [`paper`] | the paper's model implementing [`hybrid::RotorModel`] and, analytically, [`hybrid::Variational`], and sweeps over its parameters |
//! | [`analysis`] | for any [`hybrid::RotorModel`]: period detection, stroboscopic orbits, phase portraits and Poincaré sections, deterministic parallel sweeps, bifurcation diagrams and a bifurcation locator |
//! | [`global`] | global dynamics: attractors identified and matched, basins of attraction and two-parameter maps, long sweeps that write as they go and resume after a kill, on threads or MPI ranks (feature `mpi`) |
//! | [`rotor`] | your rotor on the ring: a smooth rotor model of any size ([`rotor::SmoothRotor`]) composed with the ring's contact element into a [`hybrid::RotorModel`] and a [`hybrid::Variational`] with the ring's parts analytic ([`rotor::RingedRotor`]) |
//! | [`stability`] | linearisation through events, for any [`hybrid::Variational`] model: saltation matrices, the stroboscopic map's Jacobian, periodic orbits and their multipliers, Lyapunov exponents, continuation of periodic orbits (pseudo-arclength, folds, flips, grazing, branch switching) and bifurcations located |
//!
//! Layers, bottom to top: [`ode`] and [`ring`]; [`hybrid`] and [`rotor`]; the analyses
//! ([`analysis`], [`stability`], [`global`]), which name no concrete model; [`paper`] on top;
//! [`params`] is used by all. No module uses a higher one (`tests/suite/layers.rs`): a model's
//! linearisation lives with the model, the shared ring parts of it with the ring.
//!
//! The most used items are re-exported here: [`JeffcottModel`], [`State`], and [`nalgebra`]
//! itself (the version this crate is built with, so that a user need not match it). The items
//! of the common tasks (simulate, sweep, stability, basins) come together with
//! `use jeffcott::prelude::*;` ([`prelude`]).
//!
//! ## Guides
//!
//! Long-form guides ship with the crate, in its `docs/` folder (Markdown, formulas in TeX):
//!
//! * [model.md][guide-model]: the model as implemented, every erratum of the paper and every
//!   choice;
//! * [hybrid.md][guide-hybrid]: your own rotor model: the contract of [`hybrid::RotorModel`],
//!   run-time sizes, algebraic components, the analyses;
//! * [ring.md][guide-ring]: the snubber ring's element, its minimum-energy location and its solver;
//! * [integrators.md][guide-integrators]: the Runge–Kutta integrators, dense output and event
//!   location;
//! * [stability.md][guide-stability]: saltation matrices, multipliers, Lyapunov exponents;
//! * [global.md][guide-global]: continuation, coexisting attractors, basins, two-parameter
//!   maps, long resumable sweeps, MPI on a cluster;
//! * [reproduction.md][guide-reproduction]: the paper's figures and numbers against the crate's;
//! * [accuracy.md][guide-accuracy]: work-precision data against independent references;
//! * [reliability.md][guide-reliability]: every outcome of a run and when it is the honest one,
//!   fuzzing counts, known open defects;
//! * [performance.md][guide-performance]: what runs cost and how to keep a debug build fast.
//!
//! [guide-model]: https://docs.rs/crate/jeffcott/latest/source/docs/model.md
//! [guide-hybrid]: https://docs.rs/crate/jeffcott/latest/source/docs/hybrid.md
//! [guide-ring]: https://docs.rs/crate/jeffcott/latest/source/docs/ring.md
//! [guide-integrators]: https://docs.rs/crate/jeffcott/latest/source/docs/integrators.md
//! [guide-stability]: https://docs.rs/crate/jeffcott/latest/source/docs/stability.md
//! [guide-global]: https://docs.rs/crate/jeffcott/latest/source/docs/global.md
//! [guide-reproduction]: https://docs.rs/crate/jeffcott/latest/source/docs/reproduction.md
//! [guide-accuracy]: https://docs.rs/crate/jeffcott/latest/source/docs/accuracy.md
//! [guide-reliability]: https://docs.rs/crate/jeffcott/latest/source/docs/reliability.md
//! [guide-performance]: https://docs.rs/crate/jeffcott/latest/source/docs/performance.md
//!
//! ## Features
//!
//! Both are off by default.
//!
//! * **`serde`**: `Serialize` and `Deserialize` (with [`serde`](https://docs.rs/serde)'s
//!   derive) for the types a user saves: the parameter sets ([`params::Params`],
//!   [`params::DimensionalParams`], ...), every options and configuration struct
//!   ([`hybrid::SimOptions`], [`hybrid::OutputPlan`], [`analysis::BifurcationOptions`],
//!   [`analysis::PeriodTest`], [`stability::OrbitOptions`], [`global::AttractorOptions`], ...),
//!   the results ([`hybrid::Trajectory`], [`analysis::Bifurcation`], [`analysis::Periodicity`],
//!   [`stability::PeriodicOrbit`], [`stability::Continuation`], [`stability::LyapunovSpectrum`],
//!   [`global::Attractor`], [`stability::Branch`] and its points, ...) and the errors results
//!   carry. Guard and event names (`&'static str`) read back are interned: each distinct name
//!   is allocated once for the life of the process. JSON has no infinity: options holding
//!   `f64::INFINITY` (the default `ode::Options::h_max`) need a format that has one. It turns
//!   on nalgebra's `serde-serialize`, so the vectors inside serialize too. Pure Rust, no
//!   system library. Working state (integrators, caches, event state) is not serialisable.
//!   `serde` and `serde_json` themselves are dependencies with or without the feature: the
//!   resumable sweeps of [`global`] write their records with them, so the types a sweep
//!   records or describes its settings with ([`global::Attractor`], [`global::PointFailure`],
//!   [`global::AttractorOptions`] with [`hybrid::SimOptions`] and [`analysis::PeriodTest`],
//!   [`params::Params`], [`paper::BasinPlane`], [`paper::ParamPlane`], ...) derive both always.
//! * **`mpi`**: the module `global::distributed`: the resumable sweeps of [`global`]
//!   (`open_store`, `run_points`, `scan_grid`) split across MPI ranks, with results bitwise
//!   equal to one process (the examples `basins` and `param_map` use it under `mpirun`). It
//!   builds the [`mpi`](https://docs.rs/mpi) crate (rsmpi), which needs an MPI library and
//!   libclang at build time (Debian: `libopenmpi-dev`, `openmpi-bin`, `libclang-dev`) and
//!   `mpirun` to run. Not built on docs.rs: `cargo doc --features mpi` documents it locally.
//!
//! ## Example
//!
//! Stroboscopic states of the paper's Fig. 8b scene from rest, after 300 forcing periods:
//!
//! ```
//! use jeffcott::hybrid::SimOptions;
//! use jeffcott::params::Preset;
//! use jeffcott::{JeffcottModel, State};
//!
//! let model = JeffcottModel::new(Preset::Fig8b.params().with_eta(2.0))?;
//! let (orbit, stats) = model.strobe_range(&State::zeros(), 300, 305, &SimOptions::default())?;
//! for p in &orbit.strobe {
//!     println!("k = {}, tau = {:.4}: x = {:.6}, regime {}", p.k, p.t, p.y[0], p.label);
//! }
//! // Period 1 at eta = 2: consecutive stroboscopic points coincide.
//! let (a, b) = (orbit.strobe[0].y, orbit.strobe[5].y);
//! assert!((a - b).norm() < 1e-8);
//! assert!(stats.transitions > 0); // the rotor hits the ring
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
#![forbid(unsafe_code)]
#![deny(missing_docs)]
// docs.rs (`--cfg docsrs`, nightly rustdoc) marks the items of a feature with a badge.
#![cfg_attr(docsrs, feature(doc_cfg))]

pub mod analysis;
pub mod global;
pub mod hybrid;
pub mod numeric;
pub mod ode;
pub mod paper;
pub mod params;
pub mod prelude;
pub mod ring;
pub mod rotor;
// Always compiled: the records of `global` read `analysis::LagResiduals` through it; the label
// readers serve the derives of the `serde` feature.
#[cfg_attr(not(feature = "serde"), allow(dead_code))]
mod serde_util;

/// `&'static str`, spelt so that serde's derive does not borrow it from the input: a field of
/// this type is read back through an interned copy (`serde_util::label`), so the types holding
/// one implement `Deserialize<'de>` for every `'de` (not only `'static`).
type StaticStr = &'static str;
pub mod stability;

/// The linear algebra crate of the public API (states are `nalgebra` vectors).
pub use nalgebra;
pub use paper::{JeffcottModel, State};

/// The README's Rust snippets, compiled and run as doctests (`cargo test --doc`).
#[doc = include_str!("../README.md")]
#[cfg(doctest)]
pub struct ReadmeDoctests;

/// docs/fe-rotors.md's Rust snippets, compiled as doctests (`cargo test --doc`).
#[doc = include_str!("../docs/fe-rotors.md")]
#[cfg(doctest)]
pub struct FeRotorsDoctests;
