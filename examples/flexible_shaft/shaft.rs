//! A flexible shaft on the crate's snubber ring: a uniform, simply supported Euler-Bernoulli
//! shaft in its first `n` bending modes, an out-of-balance at one station and the ring at
//! another, written as a [`SmoothRotor`] and composed with the ring by [`RingedRotor`].
//!
//! # The shaft
//!
//! Length $L$, mass per length $\mu$, bending stiffness $EI$, pinned at both ends, no discs.
//! Its lateral deflection $(w_x, w_y)(x, t)$ is expanded in the exact bending modes of the
//! pinned-pinned beam,
//!
//! $$w(\xi, t) = \sum_{j=1}^{n} \phi_j(\xi)\thinspace q_j(t),\qquad \phi_j(\xi) = \sin(j\pi\xi),
//! \qquad \omega_j = j^2\omega_1,\qquad \omega_1 = \frac{\pi^2}{L^2}\sqrt{\frac{EI}{\mu}},$$
//!
//! $\xi = x/L$, every mode with modal mass $m_j = \mu L/2$. The stations are $n_s$ evenly
//! spaced points $\xi_i = i/(n_s + 1)$, $i = 1..n_s$; the displacement of station $i$ is
//! $\sum_j \phi_j(\xi_i) q_j$, and a point force $F$ at station $i$ enters mode $j$ as
//! $\phi_j(\xi_i) F$. With as many modes as stations the $n \times n$ matrix $\phi_j(\xi_i)$ is
//! invertible (a discrete sine transform), so the modal and the station coordinates are two
//! views of the same model.
//!
//! # Scaling (the crate's units)
//!
//! Time $\tau = \omega_1 t$ and lengths over the ring's gap $\gamma$; forces over $k_1\gamma$
//! with $k_1 = m_1\omega_1^2 = \pi^4 EI/(2L^3)$, the modal stiffness of mode 1 (1.5 % above the
//! static midspan stiffness $48EI/L^3$). Mode 1 with the ring and the out-of-balance at
//! midspan ($\phi_1 = 1$) is then the paper's Jeffcott rotor with $M \to m_1$,
//! $k_r \to k_1$, so every parameter of [`Params`] keeps its meaning:
//! $\eta = \Omega/\omega_1$, $\beta = (m_u/m_1)(\rho/\gamma)$, $K = k_s/k_1$,
//! $\nu_2 = c_s/(2\sqrt{k_1 m_1})$, and `nu1` is the **modal damping ratio** $\zeta$ of every mode
//! ($c_j = 2\zeta m_j\omega_j$, the same ratio for all modes). The eccentricity $(e_x, e_y)$ is
//! the offset of the shaft's rest line from the ring's centre at the ring's station. Mode $j$:
//!
//! $$q_j^{\prime\prime} + 2\zeta j^2 q_j^\prime + j^4 q_j = \phi_j(\xi_u)\thinspace\beta\eta^2
//! (\cos, \sin)(\varphi_0 + \eta\tau) - \phi_j(\xi_r)\thinspace f,$$
//!
//! $f$ the ring's force on the shaft at the ring station, whose position relative to the
//! ring's centre is $r = e + \sum_j \phi_j(\xi_r) q_j$.
//!
//! Why this model: the modes and frequencies of the uniform pinned-pinned beam are exact and in
//! closed form, so no eigen-solver runs and the modes kept carry no discretisation error; the
//! first mode fixes the time scale exactly (so $\eta$ keeps the paper's meaning for it); and
//! the reduction to the paper's rotor is exact, not approximate. Not modelled: shear
//! deformation, rotary inertia and the gyroscopic moments of the spinning cross-sections
//! (Timoshenko/Rayleigh corrections of relative size $(j\pi r_g/L)^2$, $r_g$ the section's
//! radius of gyration: negligible for a slender shaft; there are no discs), gravity, and the
//! modes above $n$ (a point force has modal content in every mode; the static truncation
//! error at a station is below $\sum_{j>n} j^{-4} < 1/(3n^3)$ of $f/k_1$).
//!
//! # State
//!
//! `4 n + 2` components: positions, then velocities, then the ring. Mode $j$ (1-based) holds
//! $(q_{xj}, q_{yj})$ at `2 (j - 1)`, `2 j - 1` and $(q_{xj}^\prime, q_{yj}^\prime)$ at
//! `2 n + 2 (j - 1)`, `2 n + 2 j - 1`; the ring's position $(x_s, y_s)$ is at `4 n`, `4 n + 1`.
//! With one mode this is the paper's state with $x = e_x + q_x$, $y = e_y + q_y$. The order
//! makes the field of second order in its first `4 n` components
//! ([`SmoothRotor::second_order`]), which Radau5 uses to condense its Newton systems to
//! `2 n + 2` unknowns.

use std::f64::consts::PI;

use jeffcott::nalgebra::{Complex, DMatrix};
use jeffcott::nalgebra::{DVector, Dyn, Vector2};
use jeffcott::ode::{DiagonalSprings, JacobianMut};
use jeffcott::params::{ParamError, Params};
use jeffcott::ring::{ForceJacobian, Kinematics, RingAxis, RingError, SnubberRing};
use jeffcott::rotor::{LinearSystem, ModalRotor, RingedRotor, RotorError, SmoothRotor};

/// Why a shaft could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ShaftError {
    /// No bending mode.
    #[error("modes = 0: keep at least one bending mode")]
    NoModes,
    /// No station.
    #[error("stations = 0: place at least one station on the shaft")]
    NoStations,
    /// A station number outside `1..=stations`.
    #[error(
        "{role} station {station} is not one of the stations 1..={stations}: pick one of them"
    )]
    StationOutOfRange {
        /// `"unbalance"` or `"ring"`.
        role: &'static str,
        /// The station asked for.
        station: usize,
        /// The number of stations.
        stations: usize,
    },
    /// Undamped forcing at a natural frequency: no bounded steady response.
    #[error("undamped forcing at the natural frequency of mode {mode} (eta = {eta}): set nu1 > 0 or move eta")]
    UndampedResonance {
        /// The resonant mode (1-based).
        mode: usize,
        /// The frequency ratio.
        eta: f64,
    },
    /// Invalid forcing, damping or ring parameters.
    #[error("invalid parameters: {0}")]
    Params(#[from] ParamError),
    /// Invalid ring.
    #[error("invalid ring: {0}")]
    Ring(#[from] RingError),
    /// The shaft breaks the contract of `SmoothRotor` (checked by `RingedRotor::new`).
    #[error("the shaft on the ring: {0}")]
    Rotor(#[from] RotorError),
}

/// How the shaft is discretised and where the out-of-balance and the ring sit.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Layout {
    /// Bending modes kept (at least 1).
    pub modes: usize,
    /// Evenly spaced stations, station `i` at $\xi_i = i/(n_s + 1)$ (at least 1).
    pub stations: usize,
    /// Station of the out-of-balance (1-based).
    pub unbalance: usize,
    /// Station of the snubber ring (1-based).
    pub ring: usize,
}

impl Layout {
    /// The reduction to the paper's Jeffcott rotor: one mode, one station at midspan carrying
    /// both the out-of-balance and the ring.
    pub fn jeffcott() -> Self {
        Layout {
            modes: 1,
            stations: 1,
            unbalance: 1,
            ring: 1,
        }
    }
}

/// Mode shape $\phi_j(\xi) = \sin(j\pi\xi)$ of the pinned-pinned beam (mode `j` 1-based).
pub fn mode_shape(j: usize, xi: f64) -> f64 {
    (j as f64 * PI * xi).sin()
}

/// Natural frequency of mode `j` over that of mode 1: $\omega_j/\omega_1 = j^2$.
pub fn natural_frequency(j: usize) -> f64 {
    (j * j) as f64
}

/// The shaft without the ring (see the [module docs](self)).
#[derive(Debug, Clone, PartialEq)]
pub struct FlexibleShaft {
    params: Params,
    layout: Layout,
    /// $\omega_j/\omega_1$.
    omega: Vec<f64>,
    /// $\phi_j$ at the out-of-balance.
    at_unbalance: Vec<f64>,
    /// $\phi_j$ at the ring.
    at_ring: Vec<f64>,
    /// Whether [`SmoothRotor::error_scale`] gives [`FlexibleShaft::error_scale_vector`].
    frequency_weights: bool,
    /// $\omega_j^2$ and $2\zeta\omega_j$ per modal coordinate (twice per mode: $x$, $y$),
    /// [`SmoothRotor::diagonal_springs`].
    stiffness: Vec<f64>,
    damping: Vec<f64>,
    /// Whether [`SmoothRotor::diagonal_springs`] declares them.
    declare_springs: bool,
}

impl FlexibleShaft {
    /// A shaft with forcing, modal damping (`nu1`) and eccentricity from `params` (the ring's
    /// fields are not used here: see [`on_ring`]).
    ///
    /// # Errors
    /// [`ShaftError`] for an empty layout, a station out of range, invalid parameters, or
    /// undamped forcing at a natural frequency.
    pub fn new(params: Params, layout: Layout) -> Result<Self, ShaftError> {
        let params = params.validated()?;
        if layout.modes == 0 {
            return Err(ShaftError::NoModes);
        }
        if layout.stations == 0 {
            return Err(ShaftError::NoStations);
        }
        for (role, station) in [("unbalance", layout.unbalance), ("ring", layout.ring)] {
            if station == 0 || station > layout.stations {
                return Err(ShaftError::StationOutOfRange {
                    role,
                    station,
                    stations: layout.stations,
                });
            }
        }
        let omega: Vec<f64> = (1..=layout.modes).map(natural_frequency).collect();
        if params.nu1 == 0.0
            && let Some(j) = omega.iter().position(|w| (w - params.eta).abs() < 1e-9 * w)
        {
            return Err(ShaftError::UndampedResonance {
                mode: j + 1,
                eta: params.eta,
            });
        }
        let shapes = |station: usize| -> Vec<f64> {
            (1..=layout.modes)
                .map(|j| Self::shape_at(j, station, layout.stations))
                .collect()
        };
        let per_coordinate = |f: &dyn Fn(f64) -> f64| -> Vec<f64> {
            omega.iter().flat_map(|&w| [f(w), f(w)]).collect()
        };
        Ok(FlexibleShaft {
            stiffness: per_coordinate(&|w| w * w),
            damping: per_coordinate(&|w| 2.0 * params.nu1 * w),
            declare_springs: true,
            at_unbalance: shapes(layout.unbalance),
            at_ring: shapes(layout.ring),
            params,
            layout,
            omega,
            frequency_weights: true,
        })
    }

    /// The shaft with every error weighed by the state's scale (`false`: the runs before the
    /// modal weights, for comparison) or by [`FlexibleShaft::error_scale_vector`] (`true`, the
    /// default).
    #[must_use]
    pub fn with_frequency_weights(mut self, modal: bool) -> Self {
        self.frequency_weights = modal;
        self
    }

    /// The shaft with its diagonal springs declared (`true`, the default: RADAU5 solves its
    /// Newton systems by the Woodbury formula) or not (`false`: the dense LU, for comparison).
    #[must_use]
    pub fn with_diagonal_springs(mut self, declare: bool) -> Self {
        self.declare_springs = declare;
        self
    }

    /// $\phi_j(\xi_i)$, with the integer product $j i$ formed first so that nodes come out at
    /// rounding level.
    fn shape_at(j: usize, station: usize, stations: usize) -> f64 {
        (PI * (j * station) as f64 / (stations + 1) as f64).sin()
    }

    /// State dimension, `4 modes + 2`.
    pub fn state_len(&self) -> usize {
        4 * self.layout.modes + 2
    }

    /// Index of mode `j`'s (0-based) $a_{x,j}$ in the state (then $a_{y,j}$): the state is
    /// `[a_x1, a_y1, ..., a_xn, a_yn, a'_x1, a'_y1, ..., a'_yn, s_x, s_y]`, positions then
    /// velocities, so that Radau5 can condense its Newton systems
    /// ([`SmoothRotor::second_order`]).
    pub fn position_index(&self, j: usize) -> usize {
        2 * j
    }

    /// Index of mode `j`'s (0-based) $a_{x,j}^\prime$ in the state (then $a_{y,j}^\prime$).
    pub fn velocity_index(&self, j: usize) -> usize {
        2 * self.layout.modes + 2 * j
    }

    /// Mode `j`'s (0-based) `[a_x, a_y, a'_x, a'_y]`.
    fn modal(&self, y: &[f64], j: usize) -> [f64; 4] {
        let (p, v) = (self.position_index(j), self.velocity_index(j));
        [y[p], y[p + 1], y[v], y[v + 1]]
    }

    /// Axial position $\xi_i = i/(n_s + 1)$ of station `i` (1-based).
    pub fn station_position(&self, station: usize) -> f64 {
        station as f64 / (self.layout.stations + 1) as f64
    }

    /// Deflection $(w_x, w_y)$ and its velocity at station `i` (1-based) from the shaft's rest
    /// line (without the eccentricity).
    pub fn station_motion(&self, station: usize, y: &[f64]) -> ([f64; 2], [f64; 2]) {
        let n = self.layout.stations;
        let mut w = [0.0; 2];
        let mut v = [0.0; 2];
        for j in 1..=self.layout.modes {
            let phi = Self::shape_at(j, station, n);
            let m = self.modal(y, j - 1);
            w[0] += phi * m[0];
            w[1] += phi * m[1];
            v[0] += phi * m[2];
            v[1] += phi * m[3];
        }
        (w, v)
    }

    /// Kinetic plus strain energy of the shaft, $\sum_j \tfrac12(|q_j^\prime|^2 + j^4|q_j|^2)$
    /// (units $k_1\gamma^2$).
    pub fn energy(&self, y: &[f64]) -> f64 {
        self.omega
            .iter()
            .enumerate()
            .map(|(j, w)| {
                let m = self.modal(y, j);
                0.5 * (m[2] * m[2] + m[3] * m[3] + w * w * (m[0] * m[0] + m[1] * m[1]))
            })
            .sum()
    }

    /// Radius of the steady whirl of station `i` (1-based) without the ring: the forced
    /// circular orbit $|\sum_j \phi_j(\xi_i)\phi_j(\xi_u)\beta\eta^2/(j^4 - \eta^2 +
    /// 2i\zeta j^2\eta)|$ around the station's rest point.
    pub fn free_whirl_radius(&self, station: usize) -> f64 {
        let p = &self.params;
        let (eta, b) = (p.eta, p.forcing_amplitude());
        let (mut re, mut im) = (0.0, 0.0);
        for (j, (&w, &phi_u)) in self.omega.iter().zip(&self.at_unbalance).enumerate() {
            let gain = b * phi_u * Self::shape_at(j + 1, station, self.layout.stations);
            let (a, c) = (w * w - eta * eta, 2.0 * p.nu1 * w * eta);
            let d = a * a + c * c;
            re += gain * a / d;
            im -= gain * c / d;
        }
        re.hypot(im)
    }

    /// The unbalance force $\beta\eta^2(\cos, \sin)(\varphi_0 + \eta\tau)$ at time `t`.
    pub fn unbalance_force(&self, t: f64) -> [f64; 2] {
        let p = &self.params;
        let (sin, cos) = (p.phi0 + p.eta * t).sin_cos();
        let b = p.forcing_amplitude();
        [b * cos, b * sin]
    }

    /// The shaft's vector field without the ring (ring slots set to 0).
    pub fn rhs_slice(&self, t: f64, y: &[f64], dy: &mut [f64]) {
        let f = self.unbalance_force(t);
        let zeta = self.params.nu1;
        for (j, (&w, &phi)) in self.omega.iter().zip(&self.at_unbalance).enumerate() {
            let m = self.modal(y, j);
            let (p, v) = (self.position_index(j), self.velocity_index(j));
            dy[p] = m[2];
            dy[p + 1] = m[3];
            dy[v] = phi * f[0] - 2.0 * zeta * w * m[2] - w * w * m[0];
            dy[v + 1] = phi * f[1] - 2.0 * zeta * w * m[3] - w * w * m[1];
        }
        let [i, k] = self.ring_slots_of();
        dy[i] = 0.0;
        dy[k] = 0.0;
    }

    /// Position (eccentricity included) and velocity of the ring's station relative to the
    /// ring's centre.
    pub fn ring_kinematics(&self, y: &[f64]) -> Kinematics {
        let mut r = [self.params.ex, self.params.ey];
        let mut v = [0.0; 2];
        for (j, phi) in self.at_ring.iter().enumerate() {
            let m = self.modal(y, j);
            r[0] += phi * m[0];
            r[1] += phi * m[1];
            v[0] += phi * m[2];
            v[1] += phi * m[3];
        }
        Kinematics::new(r, v)
    }

    /// Adds a force `f` at the ring's station: $\phi_j(\xi_r) f$ on each mode (unit modal
    /// masses).
    pub fn add_ring_force(&self, f: &Vector2<f64>, dy: &mut [f64]) {
        for (j, phi) in self.at_ring.iter().enumerate() {
            let v = self.velocity_index(j);
            dy[v] += phi * f.x;
            dy[v + 1] += phi * f.y;
        }
    }

    /// The weight of each component's error ([`SmoothRotor::error_scale`]): 1 (the gap) for
    /// every modal displacement and the ring's slots, $\max(\eta, \omega_j/\omega_1)$ for
    /// mode $j$'s velocities. Mode $j$'s error is measured as the displacement amplitude it
    /// stands for, $\max(|\delta a_j|, |\delta a_j^\prime|/\max(\eta, j^2))$: a velocity
    /// error $\delta a^\prime$ rings as a free oscillation of amplitude $\delta a^\prime/j^2$
    /// (the mode's energy over its stiffness), and a station moves by at most
    /// $|\phi_j||\delta a_j| \le |\delta a_j|$. The slow modes ($j^2 \le \eta$) keep the
    /// weight $\eta$ of the forced whirl's velocity (the state's scale $\gamma\Omega$).
    pub fn error_scale_vector(&self) -> DVector<f64> {
        let eta = self.params.eta;
        let mut scale = DVector::from_element(self.state_len(), 1.0);
        for (j, w) in self.omega.iter().enumerate() {
            let v = self.velocity_index(j);
            scale[v] = eta.max(*w);
            scale[v + 1] = eta.max(*w);
        }
        scale
    }

    /// Indices of the ring's position in the state, `4 modes` and `4 modes + 1`.
    pub fn ring_slots_of(&self) -> [usize; 2] {
        let n = 4 * self.layout.modes;
        [n, n + 1]
    }
}

impl SmoothRotor for FlexibleShaft {
    /// The number of modes is chosen at run time.
    type Dim = Dyn;
    fn dim(&self) -> Dyn {
        Dyn(self.state_len())
    }
    fn rhs(&self, t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        self.rhs_slice(t, y.as_slice(), dy.as_mut_slice());
    }
    fn station(&self, y: &DVector<f64>) -> Kinematics {
        self.ring_kinematics(y.as_slice())
    }
    fn add_station_force(&self, _y: &DVector<f64>, f: &Vector2<f64>, dy: &mut DVector<f64>) {
        self.add_ring_force(f, dy.as_mut_slice());
    }
    fn ring_slots(&self) -> [usize; 2] {
        self.ring_slots_of()
    }
    fn forcing_period(&self) -> f64 {
        self.params.forcing_period()
    }
    /// The state is `[a (2 modes), a' (2 modes), s]` and `rhs` copies `a'` into `a`'s rows.
    fn second_order(&self) -> Option<usize> {
        Some(2 * self.layout.modes)
    }
    /// [`FlexibleShaft::error_scale_vector`].
    fn error_scale(&self) -> Option<DVector<f64>> {
        self.frequency_weights.then(|| self.error_scale_vector())
    }
    /// Mode $j$'s springs $\omega_j^2$ and dampers $2\zeta\omega_j$: the modes are coupled
    /// only through the ring's force at its station (rank 2).
    fn diagonal_springs(&self) -> Option<DiagonalSprings<'_>> {
        self.declare_springs.then_some(DiagonalSprings {
            stiffness: &self.stiffness,
            damping: &self.damping,
        })
    }
    /// The modal field's Jacobian (`[0 I; -diag(w^2) -diag(2 zeta w)]`) and, in contact,
    /// $-\phi_j(\xi_r)\phi_l(\xi_r)(F_r, F_v)$ between mode $j$'s velocity row and mode $l$'s
    /// position and velocity columns.
    fn jacobian(
        &self,
        _t: f64,
        _y: &DVector<f64>,
        contact: Option<&ForceJacobian>,
        jac: &mut JacobianMut<'_, Dyn>,
    ) -> bool {
        let p = 2 * self.layout.modes;
        // Column by column as slices: nalgebra's element iterator over the whole view is
        // several times slower (a fifth of RADAU5's time at 64 modes).
        for j in 0..jac.ncols() {
            jac.column_mut(j).as_mut_slice().fill(0.0);
        }
        for i in 0..p {
            jac[(i, p + i)] = 1.0;
            jac[(p + i, i)] = -self.stiffness[i];
            jac[(p + i, p + i)] = -self.damping[i];
        }
        let Some(f) = contact else {
            return true;
        };
        for (j, &phi_j) in self.at_ring.iter().enumerate() {
            for (l, &phi_l) in self.at_ring.iter().enumerate() {
                let g = phi_j * phi_l;
                for (a, b) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
                    let (row, col) = (p + 2 * j + a, 2 * l + b);
                    jac[(row, col)] -= g * f.position[(a, b)];
                    jac[(row, p + col)] -= g * f.velocity[(a, b)];
                }
            }
        }
        true
    }
}

impl FlexibleShaft {
    /// The same shaft as a [`ModalRotor`] (the complex modal coordinates of its state matrix,
    /// for the exponential integrator `Etd4`): the linear system $M = I$,
    /// $D = \operatorname{diag}(2\zeta\omega_j)$, $K = \operatorname{diag}(\omega_j^2)$ in
    /// the coordinates $(q_{x1}, q_{y1}, \dots)$, the out-of-balance as the harmonic force
    /// $\phi_j(\xi_u)\beta\eta^2 e^{i\varphi_0}(1, -i)$, the ring's station at the rows
    /// $\phi_j(\xi_r)$ and the ring's centre at $-e$ from the rest line.
    ///
    /// # Errors
    /// [`RotorError`] from the system or the modal form.
    pub fn modal_rotor(&self) -> Result<ModalRotor, RotorError> {
        let n = 2 * self.layout.modes;
        let p = &self.params;
        let rate = |i: usize| self.omega[i / 2];
        let diag = |f: &dyn Fn(usize) -> f64| {
            DMatrix::from_fn(n, n, |i, j| if i == j { f(i) } else { 0.0 })
        };
        let amplitude = Complex::from_polar(p.forcing_amplitude(), p.phi0);
        let harmonic = DVector::from_fn(n, |i, _| {
            let f = amplitude * self.at_unbalance[i / 2];
            if i % 2 == 0 {
                f
            } else {
                f * Complex::new(0.0, -1.0)
            }
        });
        let system = LinearSystem::from_parts(
            diag(&|_| 1.0),
            diag(&|i| 2.0 * p.nu1 * rate(i)),
            diag(&|i| rate(i) * rate(i)),
            p.eta,
            harmonic,
            DVector::zeros(n),
        )?;
        let row = |axis: usize| {
            DVector::from_fn(n, |i, _| {
                if i % 2 == axis {
                    self.at_ring[i / 2]
                } else {
                    0.0
                }
            })
        };
        ModalRotor::from_station_rows(&system, &[row(0), row(1)], [-p.ex, -p.ey])
    }
}

/// The ring of `params` (stiffness, preload, damping; gap 1).
pub fn ring_of(params: &Params) -> Result<SnubberRing, RingError> {
    SnubberRing::new(
        RingAxis::new(params.kx, params.dx),
        RingAxis::new(params.ky, params.dy),
        params.nu2,
        1.0,
    )
}

/// The shaft of `layout` on the ring of `params`.
///
/// # Errors
/// [`ShaftError`] from [`FlexibleShaft::new`] or the ring's.
pub fn on_ring(params: Params, layout: Layout) -> Result<RingedRotor<FlexibleShaft>, ShaftError> {
    on_ring_with_weights(params, layout, true)
}

/// [`on_ring`] with the errors weighed modally or by the state's scale
/// ([`FlexibleShaft::with_frequency_weights`]).
///
/// # Errors
/// As [`on_ring`].
pub fn on_ring_with_weights(
    params: Params,
    layout: Layout,
    frequency_weights: bool,
) -> Result<RingedRotor<FlexibleShaft>, ShaftError> {
    on_ring_with(params, layout, frequency_weights, true)
}

/// [`on_ring_with_weights`] with the diagonal springs declared or not
/// ([`FlexibleShaft::with_diagonal_springs`]).
///
/// # Errors
/// As [`on_ring`].
pub fn on_ring_with(
    params: Params,
    layout: Layout,
    frequency_weights: bool,
    diagonal_springs: bool,
) -> Result<RingedRotor<FlexibleShaft>, ShaftError> {
    let shaft = FlexibleShaft::new(params, layout)?
        .with_frequency_weights(frequency_weights)
        .with_diagonal_springs(diagonal_springs);
    Ok(RingedRotor::new(shaft, ring_of(&params)?)?)
}
