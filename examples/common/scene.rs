//! The scene flags of the simulation examples (those of `simulate`): the preset, every
//! parameter override, the integration options and the initial rotor state.

use jeffcott::hybrid::SimOptions;
use jeffcott::ode::Method;
use jeffcott::params::{Params, Preset};

use super::cli::{fail, Cli};

/// A scene: parameters, integration options and the initial rotor state `[x, y, x', y']`.
pub struct Scene {
    /// The parameters (preset with overrides).
    pub params: Params,
    /// The simulation options.
    pub opts: SimOptions,
    /// The initial rotor state.
    pub start: [f64; 4],
}

/// Declares the scene flags of `simulate` on `cli` (call before `cli.finish()`); the result is
/// checked by [`Scene::validate`] after it.
pub fn scene_flags(cli: &mut Cli) -> Scene {
    let preset_name = cli.string(
        "preset",
        "fig8a",
        &format!("parameter preset ({})", Preset::NAMES.join(", ")),
    );
    let preset: Preset = preset_name
        .parse()
        .unwrap_or_else(|e| fail(format!("--preset: {e}")));
    let p = preset.params();
    let eta = cli.f64("eta", p.eta, "frequency ratio eta = Omega/omega_n (> 0)");
    let nu1 = cli.f64("nu1", p.nu1, "rotor damping ratio (>= 0)");
    let nu2 = cli.f64("nu2", p.nu2, "ring damping ratio (>= 0)");
    let k = cli.f64("k", p.kx, "ring stiffness ratio K = Kx = Ky (>= 0)");
    let beta = cli.f64("beta", p.beta, "out-of-balance beta (>= 0)");
    let ex = cli.f64("ex", p.ex, "eccentricity e_x");
    let ey = cli.f64("ey", p.ey, "eccentricity e_y");
    let dx = cli.f64("delta-x", p.dx, "preload D_x (>= 0)");
    let dy = cli.f64("delta-y", p.dy, "preload D_y (>= 0)");
    let phi0 = cli.f64("phi0", p.phi0, "initial forcing phase phi0 (radians)");
    let defaults = SimOptions::default();
    let rtol = cli.f64_in("rtol", defaults.rtol, 0.0, 1.0, "relative tolerance");
    let atol = cli.f64_in("atol", defaults.atol, 0.0, 1.0, "absolute tolerance");
    let method = cli.choice(
        "method",
        "dop853",
        &["dop853", "dopri5", "rk4"],
        "integration method of contact phases",
    );
    let steps = cli.usize_in(
        "steps-per-period",
        defaults.steps_per_period as usize,
        1,
        u32::MAX as usize,
        "fixed steps per forcing period (rk4)",
    );
    let x0 = cli.f64("x0", 0.0, "initial x");
    let y0 = cli.f64("y0", 0.0, "initial y");
    let vx0 = cli.f64("vx0", 0.0, "initial x' = dx/dtau");
    let vy0 = cli.f64("vy0", 0.0, "initial y' = dy/dtau");
    Scene {
        params: Params {
            eta,
            nu1,
            nu2,
            kx: k,
            ky: k,
            beta,
            dx,
            dy,
            ex,
            ey,
            phi0,
        },
        opts: SimOptions {
            method: match method.as_str() {
                "dopri5" => Method::Dopri5,
                "rk4" => Method::Rk4,
                _ => Method::Dop853,
            },
            rtol,
            atol,
            steps_per_period: u32::try_from(steps).unwrap_or(u32::MAX),
            ..defaults
        },
        start: [x0, y0, vx0, vy0],
    }
}

impl Scene {
    /// Checks what the flags alone cannot (exits with status 2 on bad input).
    pub fn validate(&self) {
        if self.opts.rtol + self.opts.atol <= 0.0 {
            fail("--rtol and --atol cannot both be 0");
        }
        if let Err(e) = self.params.validated() {
            fail(e);
        }
    }
}
