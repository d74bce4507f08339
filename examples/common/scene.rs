//! The scene flags of the simulation examples (those of `simulate`): the preset, every
//! parameter override, the integration options and the initial rotor state.

use clap::Args;
use jeffcott::hybrid::SimOptions;
use jeffcott::ode::Method;
use jeffcott::params::{Params, Preset};

use super::cli::{fail, finite, num, usize_in};
use super::Tolerances;

/// A scene: parameters, integration options and the initial rotor state `[x, y, x', y']`.
pub struct Scene {
    /// The parameters (preset with overrides).
    pub params: Params,
    /// The simulation options.
    pub opts: SimOptions,
    /// The initial rotor state.
    pub start: [f64; 4],
}

/// The integration method of contact phases.
#[derive(clap::ValueEnum, Clone, Copy, Debug)]
pub enum MethodFlag {
    /// Dormand-Prince 8(5,3), adaptive
    Dop853,
    /// Dormand-Prince 5(4), adaptive
    Dopri5,
    /// Classical Runge-Kutta, fixed steps (--steps-per-period)
    Rk4,
    /// Radau IIA of order 5, implicit, adaptive: for stiff models (many modes, stiff contacts)
    Radau5,
    /// Exponential (ETDRK4), adaptive: for a model in modal coordinates (ross_rotor puts the
    /// rotor in its modal form); other models refuse it
    Etd4,
}

impl MethodFlag {
    /// The crate's method.
    pub fn method(self) -> Method {
        match self {
            MethodFlag::Dop853 => Method::Dop853,
            MethodFlag::Dopri5 => Method::Dopri5,
            MethodFlag::Rk4 => Method::Rk4,
            MethodFlag::Radau5 => Method::Radau5,
            MethodFlag::Etd4 => Method::Etd4,
        }
    }
}

/// The scene flags of `simulate` (`#[command(flatten)]`); [`SceneFlags::scene`] checks and
/// assembles them.
#[derive(Args, Debug, Clone)]
pub struct SceneFlags {
    /// Parameter preset
    #[arg(long, default_value = "fig8a", value_parser = Preset::NAMES)]
    pub preset: String,
    /// Frequency ratio eta = Omega/omega_n (> 0) [default: the preset's]
    #[arg(long, value_name = "NUMBER", value_parser = finite)]
    pub eta: Option<f64>,
    /// Rotor damping ratio (>= 0) [default: the preset's]
    #[arg(long, value_name = "NUMBER", value_parser = finite)]
    pub nu1: Option<f64>,
    /// Ring damping ratio (>= 0) [default: the preset's]
    #[arg(long, value_name = "NUMBER", value_parser = finite)]
    pub nu2: Option<f64>,
    /// Ring stiffness ratio K = Kx = Ky (>= 0) [default: the preset's]
    #[arg(long, value_name = "NUMBER", value_parser = finite)]
    pub k: Option<f64>,
    /// Out-of-balance beta (>= 0) [default: the preset's]
    #[arg(long, value_name = "NUMBER", value_parser = finite)]
    pub beta: Option<f64>,
    /// Eccentricity e_x [default: the preset's]
    #[arg(long, value_name = "NUMBER", value_parser = finite)]
    pub ex: Option<f64>,
    /// Eccentricity e_y [default: the preset's]
    #[arg(long, value_name = "NUMBER", value_parser = finite)]
    pub ey: Option<f64>,
    /// Preload D_x (>= 0) [default: the preset's]
    #[arg(long = "delta-x", value_name = "NUMBER", value_parser = finite)]
    pub dx: Option<f64>,
    /// Preload D_y (>= 0) [default: the preset's]
    #[arg(long = "delta-y", value_name = "NUMBER", value_parser = finite)]
    pub dy: Option<f64>,
    /// Initial forcing phase phi0 (radians) [default: the preset's]
    #[arg(long, value_name = "NUMBER", value_parser = finite)]
    pub phi0: Option<f64>,
    #[command(flatten)]
    pub tol: Tolerances,
    /// Integration method of contact phases
    #[arg(long, value_enum, default_value = "dop853")]
    pub method: MethodFlag,
    /// Fixed steps per forcing period (rk4) [range: 1..=4294967295]
    #[arg(long, value_name = "COUNT", value_parser = usize_in(1, u32::MAX as usize),
          default_value = SimOptions::default().steps_per_period.to_string())]
    pub steps_per_period: usize,
    /// Initial x
    #[arg(long, value_name = "NUMBER", value_parser = finite, default_value = num(0.0))]
    pub x0: f64,
    /// Initial y
    #[arg(long, value_name = "NUMBER", value_parser = finite, default_value = num(0.0))]
    pub y0: f64,
    /// Initial x' = dx/dtau
    #[arg(long, value_name = "NUMBER", value_parser = finite, default_value = num(0.0))]
    pub vx0: f64,
    /// Initial y' = dy/dtau
    #[arg(long, value_name = "NUMBER", value_parser = finite, default_value = num(0.0))]
    pub vy0: f64,
}

impl SceneFlags {
    /// The scene, checked (exits with status 2 on bad input).
    pub fn scene(&self) -> Scene {
        let preset: Preset = self
            .preset
            .parse()
            .unwrap_or_else(|e| fail(format!("--preset: {e}")));
        let p = preset.params();
        let k = self.k.unwrap_or(p.kx);
        let params = Params {
            eta: self.eta.unwrap_or(p.eta),
            nu1: self.nu1.unwrap_or(p.nu1),
            nu2: self.nu2.unwrap_or(p.nu2),
            kx: k,
            ky: k,
            beta: self.beta.unwrap_or(p.beta),
            dx: self.dx.unwrap_or(p.dx),
            dy: self.dy.unwrap_or(p.dy),
            ex: self.ex.unwrap_or(p.ex),
            ey: self.ey.unwrap_or(p.ey),
            phi0: self.phi0.unwrap_or(p.phi0),
        };
        if let Err(e) = params.validated() {
            fail(e);
        }
        let (rtol, atol) = self.tol.get();
        let opts = SimOptions::default()
            .with_method(self.method.method())
            .with_rtol(rtol)
            .with_atol(atol)
            .with_steps_per_period(u32::try_from(self.steps_per_period).unwrap_or(u32::MAX));
        Scene {
            params,
            opts,
            start: [self.x0, self.y0, self.vx0, self.vy0],
        }
    }
}
