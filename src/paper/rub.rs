//! Closed forms of rub with friction on the paper's rotor (`../shared/MODEL.md`, "Beyond the
//! paper: friction at the contact"): the synchronous forward full annular rub and dry whip, for
//! an isotropic ring without preload and a centred rotor ($K_x = K_y = K$, $D = 0$, $e = 0$).
//!
//! In complex notation $z = x + iy$, with $g = Ks$ on the ring's outer branch, the contact with
//! friction coefficient $\mu$ slipping forward has $s = q(1 + i\mu)\thinspace n$ and
//! $r = (1 + q(1 + i\mu))\thinspace n$, $q = N/K$, $n$ the unit contact normal.
//!
//! **Synchronous full annular rub.** $n$ turns with the forcing, $n \propto e^{i(\varphi_0 +
//! \eta\tau)}$, so $z^\prime = i\eta z$ and the equation of motion reads
//! $|P + q(1 + i\mu)(P + Q)| = \beta\eta^2$ with $P = 1 - \eta^2 + 2i\nu_1\eta$ and
//! $Q = K + 2i\nu_2\eta$: a quadratic in $q$, with up to two roots $q > 0$ (two rub branches;
//! where the free orbit's radius $\beta\eta^2/|P|$ is below 1 as well, they coexist with it: the
//! jump). The slip velocity is $\eta(1 + a) > 0$ for every shaft radius $a$. A root counts only
//! if the total normal force $n\cdot f = q(K - 2\nu_2\eta\mu)$ is positive.
//!
//! **Dry whip** ($\beta = 0$): a backward whirl $n = e^{-iw\tau}$, $w > 0$, slipping forward
//! (the shaft's surface speed $\eta a$ above $w$), with
//! $A(1 + q(1 + i\mu)) + Bq(1 + i\mu) = 0$, $A = 1 - w^2 - 2i\nu_1 w$, $B = K - 2i\nu_2 w$:
//! $q = -A/((1 + i\mu)(A + B))$ must be real and positive. Its imaginary part vanishing is the
//! quartic
//!
//! $$h(w) = -\mu w^4 - 2\nu_2 w^3 + \mu(2 + K - 4\nu_1(\nu_1 + \nu_2))w^2 +
//! 2(\nu_2 - \nu_1 K)w - \mu(1 + K) = 0,$$
//!
//! solved by the eigenvalues of its companion matrix, each real root polished by the crate's
//! root finder.

use nalgebra::{Complex, DMatrix, Vector2};

use crate::numeric::{eigen_decomposition, illinois, RootOptions};
use crate::params::{non_negative, ParamError, Params};
use crate::ring::{RingAxis, SnubberRing};
use crate::rotor::{LinearRotor, LinearSystem, RotorError, RubbingRotor};

/// The paper's rotor on its ring with Coulomb friction `friction` $\mu_f$ between the ring and a
/// shaft of radius `shaft_radius` $a$ (in gaps) at the ring (`../shared/MODEL.md`, "Beyond the
/// paper: friction at the contact"): a [`RubbingRotor`] over the paper's equations written as a
/// 2-DOF [`LinearRotor`] (unit mass and stiffness per axis, damping $2\nu_1$, the
/// out-of-balance $\beta\eta^2(\cos(\varphi_0 + \eta\tau), \sin(\varphi_0 + \eta\tau))$, the
/// constant force $e$ that puts the rotor's rest at $e$ from the ring's centre) and the ring of
/// `params` (gap 1). Its state is the paper's, $(x, y, x^\prime, y^\prime, x_s, y_s)$, as
/// [`JeffcottModel`](crate::JeffcottModel)'s; mode labels 1 to 5 are the regimes, 6, 7 and 8
/// slipping forward, slipping backward and rolling. With `friction` 0 it is the paper's model
/// through another implementation (the checks compare the two).
///
/// ```
/// use jeffcott::hybrid::{simulate, OutputPlan, SimOptions, Trajectory};
/// use jeffcott::nalgebra::DVector;
/// use jeffcott::paper::rub::rubbing_model;
/// use jeffcott::params::Params;
///
/// let p = Params { eta: 2.5, ..Params::default() };
/// let model = rubbing_model(&p, 0.3, 10.0)?;
/// let mut run = Trajectory::default();
/// let plan = OutputPlan { t_end: 20.0, strobe: None, dense: None, events: true };
/// simulate(&model, 0.0, &DVector::zeros(6), &plan, &SimOptions::default(), &mut run).unwrap();
/// assert!(run.events.iter().any(|e| e.to >= 6)); // contacts, with friction
/// # Ok::<(), jeffcott::rotor::RotorError>(())
/// ```
///
/// # Errors
/// [`RotorError::Params`] for invalid parameters; those of [`RubbingRotor::new`] for the
/// friction coefficient and the shaft radius.
pub fn rubbing_model(
    params: &Params,
    friction: f64,
    shaft_radius: f64,
) -> Result<RubbingRotor<LinearRotor>, RotorError> {
    let p = params.validated()?;
    let eye = DMatrix::<f64>::identity(2, 2);
    let force = Complex::from_polar(p.beta * p.eta * p.eta, p.phi0);
    let system = LinearSystem::new(eye.clone(), &eye * (2.0 * p.nu1), eye, p.eta)?
        .with_harmonic_force(0, force)?
        .with_harmonic_force(1, force * Complex::new(0.0, -1.0))?
        .with_constant_force(0, p.ex)?
        .with_constant_force(1, p.ey)?;
    let ring = SnubberRing::new(
        RingAxis::new(p.kx, p.dx),
        RingAxis::new(p.ky, p.dy),
        p.nu2,
        1.0,
    )?;
    let rotor = LinearRotor::new(system, [0, 1], [0.0, 0.0])?.ringed(ring)?;
    RubbingRotor::new(rotor, friction, shaft_radius)
}

/// A synchronous forward full annular rub ([`synchronous_rub`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnnularRub {
    /// The elastic normal force $N = Kq$ (in $k_r\gamma$).
    pub normal_force: f64,
    /// The total normal force $n\cdot f = q(K - 2\nu_2\eta\mu)$, dampers included.
    pub contact_force: f64,
    /// The rotor's orbit radius $|r| = |1 + q(1 + i\mu)|$ (in gaps).
    pub radius: f64,
    /// $r = Z e^{i(\varphi_0 + \eta\tau)}$: the complex amplitude $Z$, whose argument is minus
    /// the rotor's phase lag behind the out-of-balance.
    pub amplitude: Complex<f64>,
    /// $s = Z_s e^{i(\varphi_0 + \eta\tau)}$: the ring's complex amplitude.
    pub ring_amplitude: Complex<f64>,
    eta: f64,
    phi0: f64,
}

impl AnnularRub {
    /// The rotor's position and velocity at time `tau`.
    pub fn rotor(&self, tau: f64) -> (Vector2<f64>, Vector2<f64>) {
        let z = self.amplitude * Complex::from_polar(1.0, self.phi0 + self.eta * tau);
        let v = z * Complex::new(0.0, self.eta);
        (Vector2::new(z.re, z.im), Vector2::new(v.re, v.im))
    }

    /// The ring's centre at time `tau`.
    pub fn ring(&self, tau: f64) -> Vector2<f64> {
        let s = self.ring_amplitude * Complex::from_polar(1.0, self.phi0 + self.eta * tau);
        Vector2::new(s.re, s.im)
    }
}

/// A dry whip orbit ([`dry_whip`]), at phase 0: $n = e^{-iw\tau}$.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DryWhip {
    /// The backward whirl frequency $w > 0$ (over $\omega_n$); it is sustained while the shaft's
    /// surface speed $\eta a$ exceeds it (the slip is forward).
    pub frequency: f64,
    /// The elastic normal force $N = Kq$.
    pub normal_force: f64,
    /// The orbit radius $|1 + q(1 + i\mu)|$.
    pub radius: f64,
    /// $1 + q(1 + i\mu)$: $r = $ this $\times\thinspace e^{-iw\tau}$.
    pub amplitude: Complex<f64>,
    /// $q(1 + i\mu)$: $s = $ this $\times\thinspace e^{-iw\tau}$.
    pub ring_amplitude: Complex<f64>,
}

impl DryWhip {
    /// The rotor's position and velocity at time `tau`.
    pub fn rotor(&self, tau: f64) -> (Vector2<f64>, Vector2<f64>) {
        let z = self.amplitude * Complex::from_polar(1.0, -self.frequency * tau);
        let v = z * Complex::new(0.0, -self.frequency);
        (Vector2::new(z.re, z.im), Vector2::new(v.re, v.im))
    }

    /// The ring's centre at time `tau`.
    pub fn ring(&self, tau: f64) -> Vector2<f64> {
        let s = self.ring_amplitude * Complex::from_polar(1.0, -self.frequency * tau);
        Vector2::new(s.re, s.im)
    }
}

/// The synchronous forward full annular rubs of the paper's rotor at `params` with friction
/// coefficient `friction` (module docs): none, one or two, by increasing normal force.
///
/// ```
/// use jeffcott::paper::rub::synchronous_rub;
/// use jeffcott::params::Params;
///
/// let p = Params { eta: 1.2, dx: 0.0, dy: 0.0, ex: 0.0, ey: 0.0, beta: 0.3, ..Params::default() };
/// let rubs = synchronous_rub(&p, 0.2)?;
/// assert!(!rubs.is_empty() && rubs.iter().all(|r| r.radius > 1.0 && r.normal_force > 0.0));
/// # Ok::<(), jeffcott::params::ParamError>(())
/// ```
///
/// # Errors
/// [`ParamError`] for invalid parameters or a negative or non-finite `friction`;
/// [`ParamError::OutsideClosedForm`] for an anisotropic ring (`"ky"`), a preload (`"dx"`,
/// `"dy"`) or an eccentric rotor (`"ex"`, `"ey"`).
pub fn synchronous_rub(params: &Params, friction: f64) -> Result<Vec<AnnularRub>, ParamError> {
    check_scope(params, friction)?;
    let (eta, k, mu) = (params.eta, params.kx, friction);
    let p = Complex::new(1.0 - eta * eta, 2.0 * params.nu1 * eta);
    let q_ring = Complex::new(k, 2.0 * params.nu2 * eta);
    let slip = Complex::new(1.0, mu);
    let b = slip * (p + q_ring);
    let c = params.beta * eta * eta;
    // |p + q b|^2 = c^2: |b|^2 q^2 + 2 Re(p conj b) q + |p|^2 - c^2 = 0.
    let (b2, half) = (b.norm_sqr(), (p * b.conj()).re);
    let rest = (p.norm() - c) * (p.norm() + c);
    let disc = half * half - b2 * rest;
    let mut roots = Vec::new();
    if disc >= 0.0 {
        let root = disc.sqrt();
        // The pair without cancellation: q1 q2 = rest/b2.
        let big = -(half + root.copysign(half));
        for q in [big / b2, if big != 0.0 { rest / big } else { f64::NAN }] {
            if q > 0.0 && !roots.contains(&q) {
                roots.push(q);
            }
        }
    }
    roots.sort_by(f64::total_cmp);
    let contact = |q: f64| q * (k - 2.0 * params.nu2 * eta * mu);
    Ok(roots
        .into_iter()
        .filter(|&q| contact(q) > 0.0)
        .map(|q| {
            let n = Complex::from(c) / (p + b * q);
            AnnularRub {
                normal_force: k * q,
                contact_force: contact(q),
                radius: (Complex::from(1.0) + slip * q).norm(),
                amplitude: (Complex::from(1.0) + slip * q) * n,
                ring_amplitude: slip * q * n,
                eta,
                phi0: params.phi0,
            }
        })
        .collect())
}

/// The dry whip orbits of the paper's rotor at `params` (with $\beta = 0$) and friction
/// coefficient `friction` (module docs), by increasing frequency; none without friction
/// (nothing feeds a whirl against the dampers).
///
/// ```
/// use jeffcott::paper::rub::dry_whip;
/// use jeffcott::params::Params;
///
/// let p = Params { beta: 0.0, nu1: 0.01, nu2: 0.002, dx: 0.0, dy: 0.0, ex: 0.0, ey: 0.0, ..Params::default() };
/// let whips = dry_whip(&p, 0.3)?;
/// // Near the natural frequency of the rotor on the ring, sqrt(1 + K) for K = 30.
/// assert!(whips.iter().any(|w| (w.frequency - 31f64.sqrt()).abs() < 0.1));
/// # Ok::<(), jeffcott::params::ParamError>(())
/// ```
///
/// # Errors
/// As [`synchronous_rub`], and [`ParamError::OutsideClosedForm`] (`"beta"`) for an
/// out-of-balance.
pub fn dry_whip(params: &Params, friction: f64) -> Result<Vec<DryWhip>, ParamError> {
    check_scope(params, friction)?;
    if params.beta != 0.0 {
        return Err(ParamError::OutsideClosedForm {
            field: "beta",
            value: params.beta,
            needs: "beta = 0 (dry whip is unforced)",
        });
    }
    let (nu1, nu2, k, mu) = (params.nu1, params.nu2, params.kx, friction);
    if mu == 0.0 {
        return Ok(Vec::new());
    }
    // h(w) / (-mu) = w^4 + a3 w^3 + a2 w^2 + a1 w + a0.
    let a = [
        1.0 + k,
        -2.0 * (nu2 - nu1 * k) / mu,
        -(2.0 + k - 4.0 * nu1 * (nu1 + nu2)),
        2.0 * nu2 / mu,
    ];
    let h = |w: f64| (((w + a[3]) * w + a[2]) * w + a[1]) * w + a[0];
    let mut companion = DMatrix::zeros(4, 4);
    for (j, aj) in a.iter().enumerate() {
        companion[(0, 3 - j)] = -aj;
    }
    for i in 1..4 {
        companion[(i, i - 1)] = 1.0;
    }
    // Not expected for a finite quartic; said rather than returning no whip.
    let values = eigen_decomposition(&companion)
        .map_err(|_| ParamError::OutsideClosedForm {
            field: "friction",
            value: mu,
            needs: "a quartic whose companion matrix the eigen-solver resolves",
        })?
        .values;
    let slip = Complex::new(1.0, mu);
    let mut whips: Vec<DryWhip> = Vec::new();
    for lambda in values.iter() {
        if !(lambda.re > 0.0 && lambda.im.abs() <= 1e-6 * lambda.re) {
            continue;
        }
        let w = polish(&h, lambda.re);
        let big_a = Complex::new(1.0 - w * w, -2.0 * nu1 * w);
        let big_b = Complex::new(k, -2.0 * nu2 * w);
        let q = -(big_a / (slip * (big_a + big_b))).re;
        if q > 0.0 && whips.iter().all(|o| o.frequency != w) {
            whips.push(DryWhip {
                frequency: w,
                normal_force: k * q,
                radius: (Complex::from(1.0) + slip * q).norm(),
                amplitude: Complex::from(1.0) + slip * q,
                ring_amplitude: slip * q,
            });
        }
    }
    whips.sort_by(|x, y| x.frequency.total_cmp(&y.frequency));
    Ok(whips)
}

/// A real root `w0` of `h` from its eigenvalue, refined on a sign change nearby (the
/// eigenvalue itself where `h` does not change sign there: a double root).
fn polish(h: &impl Fn(f64) -> f64, w0: f64) -> f64 {
    let width = 1e-6 * w0;
    let (lo, hi) = (w0 - width, w0 + width);
    let opts = RootOptions::default().with_tol(4.0 * f64::EPSILON * w0);
    match illinois((lo, h(lo)), (hi, h(hi)), &opts, h) {
        Ok(b) if b.converged && b.g_hi == 0.0 => b.hi,
        Ok(b) if b.converged => 0.5 * (b.lo + b.hi),
        _ => w0,
    }
}

/// The closed forms' scope: an isotropic ring without preload, a centred rotor, $\mu \ge 0$.
fn check_scope(params: &Params, friction: f64) -> Result<(), ParamError> {
    params.validated()?;
    non_negative("friction", friction)?;
    let outside = |field, value, needs| {
        Err(ParamError::OutsideClosedForm {
            field,
            value,
            needs,
        })
    };
    if params.ky != params.kx {
        return outside("ky", params.ky, "ky = kx (an isotropic ring)");
    }
    for (field, value) in [("dx", params.dx), ("dy", params.dy)] {
        if value != 0.0 {
            return outside(field, value, "no preload");
        }
    }
    for (field, value) in [("ex", params.ex), ("ey", params.ey)] {
        if value != 0.0 {
            return outside(field, value, "a centred rotor (ex = ey = 0)");
        }
    }
    Ok(())
}
