//! Parameters of the rotor-ring system: the non-dimensional set the equations use, the
//! dimensional (SI) set an engineer measures, the conversion between them, validation, and
//! named presets for every parameter set of the paper.
//!
//! Scaling (gap $\gamma$ = 1): $\tau = \omega_n t$, $\omega_n = \sqrt{k_r/M}$, lengths over
//! $\gamma$, forces over $k_r\gamma$:
//!
//! $$\eta = \Omega/\omega_n,\quad \nu_1 = \frac{c_r}{2\sqrt{k_r M}},\quad
//! \nu_2 = \frac{c_s}{2\sqrt{k_r M}},\quad K = k_s/k_r,\quad
//! \beta = \frac{m}{M}\frac{\rho}{\gamma},\quad D_{x,y} = \Delta_{x,y}/\gamma,\quad
//! e_{x,y} = \varepsilon_{x,y}/\gamma.$$
//!
//! The paper's nomenclature puts an extra $\gamma$ under the square roots of $\nu_1, \nu_2$:
//! a typo (it would not be dimensionless).

use std::fmt;
use std::str::FromStr;

use thiserror::Error;

/// Invalid parameter: the field and the value are named.
#[derive(Debug, Clone, PartialEq, Error)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum ParamError {
    /// A value is NaN or infinite.
    #[error("parameter `{field}` must be finite, got {value}")]
    NotFinite {
        /// Field name.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// Offending value.
        value: f64,
    },
    /// A value that must be non-negative is negative.
    #[error("parameter `{field}` must be >= 0, got {value}")]
    Negative {
        /// Field name.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// Offending value.
        value: f64,
    },
    /// A value that must be strictly positive is not.
    #[error("parameter `{field}` must be > 0, got {value}")]
    NotPositive {
        /// Field name.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// Offending value.
        value: f64,
    },
    /// Undamped forcing exactly at resonance: the free-flight solution has no bounded
    /// harmonic part (secular growth), which the exact free flight does not model.
    #[error("undamped resonance: nu1 = {nu1} and eta = {eta} (|1 - eta^2 + 2i nu1 eta| < 1e-9); add rotor damping or move eta")]
    UndampedResonance {
        /// Rotor damping ratio.
        nu1: f64,
        /// Frequency ratio.
        eta: f64,
    },
    /// A closed form that holds for a narrower model than these parameters: the field, its
    /// value and what the closed form needs.
    #[error("parameter `{field}` = {value}: the closed form needs {needs}")]
    OutsideClosedForm {
        /// Field name.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        field: crate::StaticStr,
        /// Offending value.
        value: f64,
        /// What the closed form needs of it.
        #[cfg_attr(
            feature = "serde",
            serde(deserialize_with = "crate::serde_util::label")
        )]
        needs: crate::StaticStr,
    },
    /// A preset name that is not known.
    #[error("unknown preset `{0}`; known: {known}", known = Preset::NAMES.join(", "))]
    UnknownPreset(String),
}

fn finite(field: &'static str, value: f64) -> Result<f64, ParamError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(ParamError::NotFinite { field, value })
    }
}

pub(crate) fn non_negative(field: &'static str, value: f64) -> Result<f64, ParamError> {
    finite(field, value)?;
    if value < 0.0 {
        Err(ParamError::Negative { field, value })
    } else {
        Ok(value)
    }
}

fn positive(field: &'static str, value: f64) -> Result<f64, ParamError> {
    finite(field, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(ParamError::NotPositive { field, value })
    }
}

/// Non-dimensional parameters of the model (gap = 1). These are what the equations use:
///
/// $$x^{\prime\prime} + 2\nu_1 x^\prime + (x - e_x) + f_x = \beta\eta^2\cos(\varphi_0 + \eta\tau),$$
/// $$y^{\prime\prime} + 2\nu_1 y^\prime + (y - e_y) + f_y = \beta\eta^2\sin(\varphi_0 + \eta\tau),$$
///
/// with $f$ the snubber ring's force (zero out of contact).
///
/// `Default` is the paper's Fig. 8a set at $\eta = 2$.
// serde always, not only with the feature: the sweeps of `global` record it.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Params {
    /// Frequency ratio $\eta = \Omega/\omega_n$ (> 0). Default 2.0.
    pub eta: f64,
    /// Rotor damping ratio $\nu_1 = c_r/(2\sqrt{k_r M})$ (>= 0). Default 0.125.
    pub nu1: f64,
    /// Ring damping ratio $\nu_2 = c_s/(2\sqrt{k_r M})$ per spring-damper unit (>= 0). Default 0.002.
    pub nu2: f64,
    /// Ring unit stiffness ratio along x, $K_x = k_{sx}/k_r$ (> 0). Default 30.
    pub kx: f64,
    /// Ring unit stiffness ratio along y, $K_y = k_{sy}/k_r$ (> 0). Default 30.
    pub ky: f64,
    /// Out-of-balance $\beta = (m/M)(\rho/\gamma)$ (>= 0); the forcing amplitude is $\beta\eta^2$.
    /// Default 0.119 (= 70 x 0.0017).
    pub beta: f64,
    /// Preload along x over the gap, $D_x = \Delta_x/\gamma$ (>= 0). Default 0.
    pub dx: f64,
    /// Preload along y over the gap, $D_y = \Delta_y/\gamma$ (>= 0). Default 0.
    pub dy: f64,
    /// Eccentricity of the rotor's rest position along x, $e_x = \varepsilon_x/\gamma$. Default 0.9.
    pub ex: f64,
    /// Eccentricity of the rotor's rest position along y, $e_y = \varepsilon_y/\gamma$. Default 0.
    pub ey: f64,
    /// Initial phase of the out-of-balance $\varphi_0$ in radians. Default 0 (the paper gives none).
    pub phi0: f64,
}

impl Default for Params {
    fn default() -> Self {
        Preset::Fig8a.params()
    }
}

impl Params {
    /// Sets an isotropic ring stiffness $K_x = K_y = K$.
    #[must_use]
    pub fn with_stiffness(mut self, k: f64) -> Self {
        self.kx = k;
        self.ky = k;
        self
    }

    /// Sets equal preloads $D_x = D_y = D$.
    #[must_use]
    pub fn with_preload(mut self, d: f64) -> Self {
        self.dx = d;
        self.dy = d;
        self
    }

    /// Sets the frequency ratio $\eta$.
    #[must_use]
    pub fn with_eta(mut self, eta: f64) -> Self {
        self.eta = eta;
        self
    }

    /// Checks every field; returns the parameters unchanged when valid.
    ///
    /// # Errors
    /// [`ParamError`] naming the first offending field: NaN or infinite values, negative
    /// damping, stiffness, preload or unbalance, a non-positive frequency ratio, or undamped
    /// forcing at resonance.
    pub fn validated(self) -> Result<Self, ParamError> {
        positive("eta", self.eta)?;
        non_negative("nu1", self.nu1)?;
        non_negative("nu2", self.nu2)?;
        positive("kx", self.kx)?;
        positive("ky", self.ky)?;
        non_negative("beta", self.beta)?;
        non_negative("dx", self.dx)?;
        non_negative("dy", self.dy)?;
        finite("ex", self.ex)?;
        finite("ey", self.ey)?;
        finite("phi0", self.phi0)?;
        let re = 1.0 - self.eta * self.eta;
        let im = 2.0 * self.nu1 * self.eta;
        if re.hypot(im) < 1e-9 {
            return Err(ParamError::UndampedResonance {
                nu1: self.nu1,
                eta: self.eta,
            });
        }
        Ok(self)
    }

    /// Forcing amplitude $\beta\eta^2$.
    pub fn forcing_amplitude(&self) -> f64 {
        self.beta * self.eta * self.eta
    }

    /// Forcing period $2\pi/\eta$ in non-dimensional time.
    pub fn forcing_period(&self) -> f64 {
        std::f64::consts::TAU / self.eta
    }

    /// Whether the ring has the same stiffness on both axes.
    pub fn is_isotropic(&self) -> bool {
        self.kx == self.ky
    }

    /// Whether any axis is preloaded.
    pub fn has_preload(&self) -> bool {
        self.dx > 0.0 || self.dy > 0.0
    }

    /// Converts back to SI given the reference scales. The non-dimensional set fixes only the
    /// product $m\rho$; the out-of-balance mass follows from `scales.unbalance_radius`.
    ///
    /// # Errors
    /// [`ParamError`] when the parameters or the scales are invalid.
    pub fn to_dimensional(&self, scales: &Scales) -> Result<DimensionalParams, ParamError> {
        let p = self.validated()?;
        scales.validated()?;
        let omega_n = (scales.rotor_stiffness / scales.rotor_mass).sqrt();
        let crit = 2.0 * (scales.rotor_stiffness * scales.rotor_mass).sqrt();
        Ok(DimensionalParams {
            rotor_mass: scales.rotor_mass,
            unbalance_mass: p.beta * scales.rotor_mass * scales.gap / scales.unbalance_radius,
            unbalance_radius: scales.unbalance_radius,
            rotor_stiffness: scales.rotor_stiffness,
            rotor_damping: p.nu1 * crit,
            ring_stiffness_x: p.kx * scales.rotor_stiffness,
            ring_stiffness_y: p.ky * scales.rotor_stiffness,
            ring_damping: p.nu2 * crit,
            gap: scales.gap,
            preload_x: p.dx * scales.gap,
            preload_y: p.dy * scales.gap,
            eccentricity_x: p.ex * scales.gap,
            eccentricity_y: p.ey * scales.gap,
            spin_speed: p.eta * omega_n,
            phase: p.phi0,
        })
    }
}

/// The dimensional reference quantities needed to convert non-dimensional results back to SI.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Scales {
    /// Rotor mass $M$ in kg (> 0).
    pub rotor_mass: f64,
    /// Rotor stiffness $k_r$ in N/m (> 0).
    pub rotor_stiffness: f64,
    /// Radial clearance $\gamma$ in m (> 0).
    pub gap: f64,
    /// Radius of the out-of-balance mass $\rho$ in m (> 0).
    pub unbalance_radius: f64,
}

impl Scales {
    /// Checks that every scale is finite and positive.
    ///
    /// # Errors
    /// [`ParamError::NotPositive`] or [`ParamError::NotFinite`] naming the field.
    pub fn validated(self) -> Result<Self, ParamError> {
        positive("rotor_mass", self.rotor_mass)?;
        positive("rotor_stiffness", self.rotor_stiffness)?;
        positive("gap", self.gap)?;
        positive("unbalance_radius", self.unbalance_radius)?;
        Ok(self)
    }

    /// Natural frequency $\omega_n = \sqrt{k_r/M}$ in rad/s: one unit of non-dimensional time
    /// is $1/\omega_n$ seconds.
    pub fn natural_frequency(&self) -> f64 {
        (self.rotor_stiffness / self.rotor_mass).sqrt()
    }

    /// Force scale $k_r\gamma$ in N: a non-dimensional force times this is newtons.
    pub fn force_scale(&self) -> f64 {
        self.rotor_stiffness * self.gap
    }
}

/// Dimensional parameters in SI units, as measured on a rig.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DimensionalParams {
    /// Rotor mass $M$, kg (> 0).
    pub rotor_mass: f64,
    /// Out-of-balance mass $m$, kg (>= 0).
    pub unbalance_mass: f64,
    /// Radius of the out-of-balance mass $\rho$, m (> 0).
    pub unbalance_radius: f64,
    /// Rotor stiffness $k_r$, N/m (> 0).
    pub rotor_stiffness: f64,
    /// Rotor damping $c_r$, N s/m (>= 0).
    pub rotor_damping: f64,
    /// Stiffness of one ring spring unit along x, $k_{sx}$, N/m (>= 0).
    pub ring_stiffness_x: f64,
    /// Stiffness of one ring spring unit along y, $k_{sy}$, N/m (>= 0).
    pub ring_stiffness_y: f64,
    /// Damping of one ring unit $c_s$, N s/m (>= 0).
    pub ring_damping: f64,
    /// Radial clearance $\gamma$ between rotor and ring, m (> 0).
    pub gap: f64,
    /// Preload displacement along x, $\Delta_x$, m (>= 0).
    pub preload_x: f64,
    /// Preload displacement along y, $\Delta_y$, m (>= 0).
    pub preload_y: f64,
    /// Eccentricity of the rotor's rest position along x, $\varepsilon_x$, m.
    pub eccentricity_x: f64,
    /// Eccentricity of the rotor's rest position along y, $\varepsilon_y$, m.
    pub eccentricity_y: f64,
    /// Shaft speed $\Omega$, rad/s (> 0).
    pub spin_speed: f64,
    /// Initial phase $\varphi_0$ of the out-of-balance, rad.
    pub phase: f64,
}

impl DimensionalParams {
    /// Checks every field.
    ///
    /// # Errors
    /// [`ParamError`] naming the first offending field.
    pub fn validated(self) -> Result<Self, ParamError> {
        positive("rotor_mass", self.rotor_mass)?;
        non_negative("unbalance_mass", self.unbalance_mass)?;
        positive("unbalance_radius", self.unbalance_radius)?;
        positive("rotor_stiffness", self.rotor_stiffness)?;
        non_negative("rotor_damping", self.rotor_damping)?;
        non_negative("ring_stiffness_x", self.ring_stiffness_x)?;
        non_negative("ring_stiffness_y", self.ring_stiffness_y)?;
        non_negative("ring_damping", self.ring_damping)?;
        positive("gap", self.gap)?;
        non_negative("preload_x", self.preload_x)?;
        non_negative("preload_y", self.preload_y)?;
        finite("eccentricity_x", self.eccentricity_x)?;
        finite("eccentricity_y", self.eccentricity_y)?;
        positive("spin_speed", self.spin_speed)?;
        finite("phase", self.phase)?;
        Ok(self)
    }

    /// The reference scales of this rig.
    pub fn scales(&self) -> Scales {
        Scales {
            rotor_mass: self.rotor_mass,
            rotor_stiffness: self.rotor_stiffness,
            gap: self.gap,
            unbalance_radius: self.unbalance_radius,
        }
    }

    /// Non-dimensionalises (see the module docs for the scaling).
    ///
    /// # Errors
    /// [`ParamError`] when a field is invalid, in SI or after scaling.
    pub fn to_nondimensional(&self) -> Result<Params, ParamError> {
        let d = self.validated()?;
        let crit = 2.0 * (d.rotor_stiffness * d.rotor_mass).sqrt();
        let omega_n = (d.rotor_stiffness / d.rotor_mass).sqrt();
        Params {
            eta: d.spin_speed / omega_n,
            nu1: d.rotor_damping / crit,
            nu2: d.ring_damping / crit,
            kx: d.ring_stiffness_x / d.rotor_stiffness,
            ky: d.ring_stiffness_y / d.rotor_stiffness,
            beta: (d.unbalance_mass / d.rotor_mass) * (d.unbalance_radius / d.gap),
            dx: d.preload_x / d.gap,
            dy: d.preload_y / d.gap,
            ex: d.eccentricity_x / d.gap,
            ey: d.eccentricity_y / d.gap,
            phi0: d.phase,
        }
        .validated()
    }
}

/// The parameter sets of the paper's figures.
///
/// Fig. 8 (bifurcation diagrams over $\eta \in [2, 5]$; the preset fixes $\eta = 2$):
/// $\nu_1 = 0.125$, $\nu_2 = 0.002$, $K = 30$, $e_x = 0.9$, $e_y = 0$,
/// $\beta = 70 \times 0.0017 = 0.119$ (the text and caption swap $\eta_m$ and $\hat\rho$;
/// only the product enters). $D = 0$ (a) or $0.1$ (b).
/// Fig. 9: Fig. 8 values at $\eta = 2.223$ (a, $D=0$), $2.181$ (b, $D=0.1$), $2.442$ (c, $D=0$; d, $D=0.1$).
/// Fig. 10 (a, b): $\nu_1 = 0.06$, $\nu_2 = 0.002$, $\eta = 2.5$, $K = 30$, $e_x = 0.4$,
/// $e_y = 0.5$, $\beta = 70 \times 0.00289$, $D = 0$ (a) or $0.05$ (b); (c, d): Fig. 8 values at
/// $\eta = 3$ with $D = 0$ (c) or $0.03$ (d).
/// Fig. 7 (restoring force surfaces): $D_x = 1.5$, $D_y = 1.1$, $K = 30$, other values as Fig. 8
/// with $e_x = e_y = 0$ (the force is plotted about the ring's centre).
/// $\varphi_0$ is given nowhere in the paper: 0 throughout.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[non_exhaustive]
pub enum Preset {
    /// Fig. 7: restoring force surfaces.
    Fig7,
    /// Fig. 8a: zero preload, $\eta = 2$.
    Fig8a,
    /// Fig. 8b: preload 0.1, $\eta = 2$.
    Fig8b,
    /// Fig. 9a: zero preload, $\eta = 2.223$.
    Fig9a,
    /// Fig. 9b: preload 0.1, $\eta = 2.181$.
    Fig9b,
    /// Fig. 9c: zero preload, $\eta = 2.442$ (chaotic).
    Fig9c,
    /// Fig. 9d: preload 0.1, $\eta = 2.442$ (chaotic).
    Fig9d,
    /// Fig. 10a: ring phase portrait, zero preload.
    Fig10a,
    /// Fig. 10b: ring phase portrait, preload 0.05.
    Fig10b,
    /// Fig. 10c: ring phase portrait, Fig. 8 values, $\eta = 3$, zero preload.
    Fig10c,
    /// Fig. 10d: ring phase portrait, Fig. 8 values, $\eta = 3$, preload 0.03.
    Fig10d,
}

impl Preset {
    /// Every preset, in figure order.
    pub const ALL: [Preset; 11] = [
        Preset::Fig7,
        Preset::Fig8a,
        Preset::Fig8b,
        Preset::Fig9a,
        Preset::Fig9b,
        Preset::Fig9c,
        Preset::Fig9d,
        Preset::Fig10a,
        Preset::Fig10b,
        Preset::Fig10c,
        Preset::Fig10d,
    ];

    /// The names accepted by [`FromStr`], in the order of [`Preset::ALL`].
    pub const NAMES: [&'static str; 11] = [
        "fig7", "fig8a", "fig8b", "fig9a", "fig9b", "fig9c", "fig9d", "fig10a", "fig10b", "fig10c",
        "fig10d",
    ];

    /// The preset's name, e.g. `"fig8b"`.
    pub fn name(self) -> &'static str {
        let i = Self::ALL.iter().position(|&p| p == self).unwrap_or(0);
        Self::NAMES[i]
    }

    /// The parameter set.
    pub fn params(self) -> Params {
        let fig8 = Params {
            eta: 2.0,
            nu1: 0.125,
            nu2: 0.002,
            kx: 30.0,
            ky: 30.0,
            beta: 70.0 * 0.0017,
            dx: 0.0,
            dy: 0.0,
            ex: 0.9,
            ey: 0.0,
            phi0: 0.0,
        };
        let fig10ab = Params {
            eta: 2.5,
            nu1: 0.06,
            ex: 0.4,
            ey: 0.5,
            beta: 70.0 * 0.00289,
            ..fig8
        };
        match self {
            Preset::Fig7 => Params {
                dx: 1.5,
                dy: 1.1,
                ex: 0.0,
                ..fig8
            },
            Preset::Fig8a => fig8,
            Preset::Fig8b => fig8.with_preload(0.1),
            Preset::Fig9a => fig8.with_eta(2.223),
            Preset::Fig9b => fig8.with_eta(2.181).with_preload(0.1),
            Preset::Fig9c => fig8.with_eta(2.442),
            Preset::Fig9d => fig8.with_eta(2.442).with_preload(0.1),
            Preset::Fig10a => fig10ab,
            Preset::Fig10b => fig10ab.with_preload(0.05),
            Preset::Fig10c => fig8.with_eta(3.0),
            Preset::Fig10d => fig8.with_eta(3.0).with_preload(0.03),
        }
    }
}

impl fmt::Display for Preset {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Preset {
    type Err = ParamError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let lower = s.to_ascii_lowercase();
        Self::NAMES
            .iter()
            .position(|&n| n == lower)
            .map(|i| Self::ALL[i])
            .ok_or_else(|| ParamError::UnknownPreset(s.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_are_valid_and_named() {
        for p in Preset::ALL {
            assert!(p.params().validated().is_ok(), "{p}");
            assert_eq!(p.name().parse::<Preset>().unwrap(), p);
        }
        assert!(matches!(
            "fig99".parse::<Preset>(),
            Err(ParamError::UnknownPreset(_))
        ));
    }

    #[test]
    fn validation_names_field_and_value() {
        let e = Params {
            nu2: -1.0,
            ..Params::default()
        }
        .validated()
        .unwrap_err();
        assert_eq!(
            e,
            ParamError::Negative {
                field: "nu2",
                value: -1.0
            }
        );
        assert!(e.to_string().contains("nu2"));
        let e = Params::default()
            .with_eta(f64::NAN)
            .validated()
            .unwrap_err();
        assert!(matches!(e, ParamError::NotFinite { field: "eta", .. }));
        let e = Params::default().with_eta(0.0).validated().unwrap_err();
        assert!(matches!(e, ParamError::NotPositive { field: "eta", .. }));
        let e = Params {
            nu1: 0.0,
            ..Params::default().with_eta(1.0)
        }
        .validated()
        .unwrap_err();
        assert!(matches!(e, ParamError::UndampedResonance { .. }));
    }

    #[test]
    fn dimensional_round_trip() {
        let p = Preset::Fig10b.params().with_stiffness(25.0);
        let scales = Scales {
            rotor_mass: 12.0,
            rotor_stiffness: 3.0e5,
            gap: 2.0e-4,
            unbalance_radius: 0.05,
        };
        let d = p.to_dimensional(&scales).unwrap();
        let q = d.to_nondimensional().unwrap();
        for (a, b) in [
            (p.eta, q.eta),
            (p.nu1, q.nu1),
            (p.nu2, q.nu2),
            (p.kx, q.kx),
            (p.beta, q.beta),
            (p.dx, q.dx),
            (p.ex, q.ex),
            (p.ey, q.ey),
        ] {
            assert!((a - b).abs() <= 1e-14 * a.abs().max(1.0), "{a} vs {b}");
        }
        let bad = DimensionalParams { gap: 0.0, ..d };
        assert!(matches!(
            bad.to_nondimensional(),
            Err(ParamError::NotPositive { field: "gap", .. })
        ));
    }
}
