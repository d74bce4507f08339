//! The analyses of [`crate::analysis`] over the paper's parameters: which parameter a sweep
//! varies, where each run starts, and convenience wrappers taking [`Params`].

use crate::analysis::{
    self, AnalysisError, Bifurcation, BifurcationOptions, LocatedChange, LocatorOptions,
    OrbitError, PeriodTest, PoincareMap, Progress,
};
use nalgebra::U6;

use crate::hybrid::{ModelError, SimOptions};
use crate::params::{ParamError, Params};

use super::{JeffcottModel, State};

/// A parameter of [`Params`] that a sweep varies.
// serde always, not only with the feature: the sweeps of `global` record it.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Default, serde::Serialize, serde::Deserialize,
)]
#[non_exhaustive]
pub enum SweepParameter {
    /// Frequency ratio $\eta$ (the default).
    #[default]
    Eta,
    /// Both preloads $D_x = D_y$.
    Preload,
    /// Preload $D_x$ only.
    PreloadX,
    /// Both ring stiffness ratios $K_x = K_y$.
    Stiffness,
    /// Rotor damping $\nu_1$.
    Nu1,
    /// Ring damping $\nu_2$.
    Nu2,
    /// Out-of-balance $\beta$.
    Beta,
    /// Eccentricity $e_x$.
    Ex,
    /// Eccentricity $e_y$.
    Ey,
    /// Initial phase $\varphi_0$.
    Phi0,
}

impl SweepParameter {
    /// `base` with this parameter set to `value` (not validated).
    pub fn apply(self, base: &Params, value: f64) -> Params {
        let mut p = *base;
        match self {
            SweepParameter::Eta => p.eta = value,
            SweepParameter::Preload => {
                p.dx = value;
                p.dy = value;
            }
            SweepParameter::PreloadX => p.dx = value,
            SweepParameter::Stiffness => {
                p.kx = value;
                p.ky = value;
            }
            SweepParameter::Nu1 => p.nu1 = value,
            SweepParameter::Nu2 => p.nu2 = value,
            SweepParameter::Beta => p.beta = value,
            SweepParameter::Ex => p.ex = value,
            SweepParameter::Ey => p.ey = value,
            SweepParameter::Phi0 => p.phi0 = value,
        }
        p
    }

    /// Its symbol, for labels: `"eta"`, `"D"`, `"Dx"`, `"K"`, `"nu1"`, ...
    pub fn symbol(self) -> &'static str {
        match self {
            SweepParameter::Eta => "eta",
            SweepParameter::Preload => "D",
            SweepParameter::PreloadX => "Dx",
            SweepParameter::Stiffness => "K",
            SweepParameter::Nu1 => "nu1",
            SweepParameter::Nu2 => "nu2",
            SweepParameter::Beta => "beta",
            SweepParameter::Ex => "ex",
            SweepParameter::Ey => "ey",
            SweepParameter::Phi0 => "phi0",
        }
    }

    /// Whether changing this parameter moves the ring's contact location, so that a carried
    /// state must have its ring re-placed ([`JeffcottModel::state_at`]).
    pub fn moves_ring(self) -> bool {
        matches!(
            self,
            SweepParameter::Preload | SweepParameter::PreloadX | SweepParameter::Stiffness
        )
    }
}

/// A rotor state the ring is placed for ([`JeffcottModel::state_at`]): position $(x, y)$ and
/// velocity $(x^\prime, y^\prime)$. The default is at rest at the origin (the paper's zero
/// initial conditions).
// serde always, not only with the feature: the sweeps of `global` record it.
#[derive(Debug, Clone, Copy, PartialEq, Default, serde::Serialize, serde::Deserialize)]
pub struct RotorStart {
    /// Position $(x, y)$.
    pub position: [f64; 2],
    /// Velocity $(x^\prime, y^\prime)$.
    pub velocity: [f64; 2],
}

impl RotorStart {
    /// At rest at the origin.
    pub fn at_rest() -> Self {
        Self::default()
    }

    /// The full state for `model`, the ring placed consistently.
    ///
    /// # Errors
    /// As [`JeffcottModel::state_at`].
    pub fn state(&self, model: &JeffcottModel) -> Result<State, ModelError> {
        model.state_at(self.position, self.velocity)
    }
}

/// A one-parameter family of the paper's model: `base` with `parameter` set to each swept
/// value, runs from the reset state starting at `start`.
///
/// It supplies the two closures of the generic analyses ([`ParamSweep::model`],
/// [`ParamSweep::start_state`]) and wraps them ([`ParamSweep::bifurcation`],
/// [`ParamSweep::locate_period_change`]).
///
/// ```
/// use jeffcott::analysis::BifurcationOptions;
/// use jeffcott::paper::{ParamSweep, SweepParameter};
/// use jeffcott::params::Preset;
///
/// let family = ParamSweep::new(Preset::Fig8a.params(), SweepParameter::Eta);
/// let config = BifurcationOptions::default().with_transient(300).with_record(8);
/// let diagram = family.bifurcation(&[2.0, 3.0], &config, None)?;
/// let periods: Vec<_> = diagram.columns.iter().map(|c| c.as_ref().unwrap().periodicity.period()).collect();
/// assert_eq!(periods, [Some(1), Some(2)]);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ParamSweep {
    /// The other parameters.
    pub base: Params,
    /// The parameter varied.
    pub parameter: SweepParameter,
    /// Where runs from the reset state start (the ring placed consistently). Default at rest
    /// at the origin.
    pub start: RotorStart,
}

impl ParamSweep {
    /// `parameter` varied about `base`, runs from rest at the origin.
    pub fn new(base: Params, parameter: SweepParameter) -> Self {
        Self {
            base,
            parameter,
            start: RotorStart::at_rest(),
        }
    }

    /// The same family with runs from the reset state starting at `start`.
    pub fn with_start(self, start: RotorStart) -> Self {
        Self { start, ..self }
    }

    /// The model at `value`.
    ///
    /// # Errors
    /// [`ParamError`] for invalid parameters.
    pub fn model(&self, value: f64) -> Result<JeffcottModel, ParamError> {
        JeffcottModel::new(self.parameter.apply(&self.base, value))
    }

    /// The start state of a run of `model`: [`ParamSweep::start`] for a run from the reset
    /// state (`carried = None`); a carried state as it is, or with its ring re-placed for the
    /// rotor's position and velocity if the parameter moves the ring
    /// ([`SweepParameter::moves_ring`]).
    ///
    /// # Errors
    /// As [`JeffcottModel::state_at`].
    pub fn start_state(
        &self,
        model: &JeffcottModel,
        carried: Option<&State>,
    ) -> Result<State, ModelError> {
        match carried {
            Some(y) if self.parameter.moves_ring() => model.state_at([y[0], y[1]], [y[2], y[3]]),
            Some(y) => Ok(*y),
            None => self.start.state(model),
        }
    }

    /// A bifurcation diagram over `values` ([`analysis::bifurcation()`]).
    ///
    /// # Errors
    /// Only for a bad sweep configuration; failures at single values are in the columns.
    pub fn bifurcation(
        &self,
        values: &[f64],
        config: &BifurcationOptions,
        progress: Option<&dyn Progress>,
    ) -> Result<Bifurcation<U6, ParamError>, AnalysisError> {
        analysis::bifurcation(
            values,
            |v| self.model(v),
            |m: &JeffcottModel, c: Option<&State>| self.start_state(m, c),
            config,
            progress,
        )
    }

    /// Where the detected period changes between `from` and `to`
    /// ([`analysis::locate_period_change`]).
    ///
    /// # Errors
    /// As [`analysis::locate_period_change`].
    pub fn locate_period_change(
        &self,
        from: f64,
        to: f64,
        config: &LocatorOptions,
    ) -> Result<LocatedChange, OrbitError<U6, ParamError>> {
        analysis::locate_period_change(
            from,
            to,
            |v| self.model(v),
            |m: &JeffcottModel, c: Option<&State>| self.start_state(m, c),
            config,
        )
    }
}

/// The Poincaré map of the paper's model at `params`: from `start` (ring placed
/// consistently), discard `transient` periods, record `record`, detect the period.
///
/// # Errors
/// [`OrbitError`] for invalid parameters or state, a failed run, or a failed period test.
pub fn poincare_map(
    params: &Params,
    start: RotorStart,
    transient: u64,
    record: u64,
    opts: &SimOptions,
    test: &PeriodTest,
) -> Result<PoincareMap<U6>, OrbitError<U6, ParamError>> {
    let model = JeffcottModel::new(*params).map_err(OrbitError::Build)?;
    let y0 = start.state(&model)?;
    let orbit = analysis::strobe_orbit(&model, &y0, transient, record, opts)?;
    Ok(orbit.classify(test)?)
}
