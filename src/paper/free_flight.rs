use nalgebra::{Matrix4, Vector2};

use crate::params::Params;
use crate::ring::onset::{MotionBounds, RotorMotion};

/// Complex number as `(re, im)`: only the few operations the closed form needs.
#[derive(Debug, Clone, Copy, PartialEq)]
struct C(f64, f64);

impl C {
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
    fn scale(self, k: f64) -> C {
        C(self.0 * k, self.1 * k)
    }
    fn add(self, o: C) -> C {
        C(self.0 + o.0, self.1 + o.1)
    }
    fn sub(self, o: C) -> C {
        C(self.0 - o.0, self.1 - o.1)
    }
    fn norm2(self) -> f64 {
        self.0 * self.0 + self.1 * self.1
    }
}

/// The rotor's closed-form free-flight oscillator for one parameter set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeOscillator {
    nu1: f64,
    eta: f64,
    phi0: f64,
    e: C,
    /// Forcing amplitude $B = \beta\eta^2$.
    amp: f64,
    /// Complex amplitude $Z$ of the particular solution.
    z: C,
    /// $\omega_d^2 = 1 - \nu_1^2$ (negative when over-damped).
    wd2: f64,
    wd: f64,
}

/// Rotor state `[x, y, x', y']`.
pub type RotorState = [f64; 4];

impl FreeOscillator {
    /// Builds the oscillator from (already validated) parameters.
    pub fn new(p: &Params) -> Self {
        let b = p.forcing_amplitude();
        let den = C(1.0 - p.eta * p.eta, 2.0 * p.nu1 * p.eta);
        let inv = den.norm2().recip();
        let z = C(b * den.0 * inv, -b * den.1 * inv);
        let wd2 = 1.0 - p.nu1 * p.nu1;
        Self {
            nu1: p.nu1,
            eta: p.eta,
            phi0: p.phi0,
            e: C(p.ex, p.ey),
            amp: b,
            z,
            wd2,
            wd: wd2.abs().sqrt(),
        }
    }

    /// Radius $|Z|$ of the particular (steady-state) circular orbit about $e$.
    pub fn steady_radius(&self) -> f64 {
        self.z.norm2().sqrt()
    }

    /// Particular solution (position, velocity) at time `t`, and the forcing phasor
    /// $e^{i\theta(t)}$.
    fn particular(&self, t: f64) -> (C, C, C) {
        let (s, c) = (self.phi0 + self.eta * t).sin_cos();
        let p = self.z.mul(C(c, s));
        (self.e.add(p), C(-p.1, p.0).scale(self.eta), C(c, s))
    }

    /// $(c(u), S(u), d(u))$ of the homogeneous solution, whose factors are $d\thinspace c$ and
    /// $d\thinspace S$ with $d = e^{-\nu_1 u}$. When over-damped, $\cosh\omega_d u$ alone
    /// overflows for $\omega_d u > 710$ (and $e^{-\nu_1 u}$ underflows a little later), although
    /// the products decay: they are returned already multiplied, as combinations of the two
    /// decaying exponentials $e^{-(\nu_1 \mp \omega_d) u}$, with $d = 1$.
    fn cs(&self, u: f64) -> (f64, f64, f64) {
        let a = self.wd * u;
        if a.abs() < 1e-4 {
            // Series in wd2 u^2: exact to rounding for the tiny arguments where the
            // closed forms lose digits (critical damping).
            let q = self.wd2 * u * u;
            (
                1.0 - q / 2.0 + q * q / 24.0,
                u * (1.0 - q / 6.0 + q * q / 120.0),
                (-self.nu1 * u).exp(),
            )
        } else if self.wd2 > 0.0 {
            let (s, c) = a.sin_cos();
            (c, s / self.wd, (-self.nu1 * u).exp())
        } else {
            // e^{-nu u} cosh(a) = slow (1 + e^{-2a})/2 and e^{-nu u} sinh(a) = slow (1 - e^{-2a})/2
            // with slow = e^{-(nu - wd) u}, nu - wd = 1/(nu + wd) (as nu^2 - wd^2 = 1).
            let slow = (-u / (self.nu1 + self.wd)).exp();
            let m = (-2.0 * a).exp_m1();
            (slow * (1.0 + 0.5 * m), -0.5 * slow * m / self.wd, 1.0)
        }
    }

    /// State-transition matrix $\Phi(u) = \partial z(\tau_0 + u)/\partial z(\tau_0)$ of the free
    /// flight over a time `u`, for the state $z = (x, y, x^\prime, y^\prime)$. The forcing is
    /// additive, so $\Phi$ does not depend on $\tau_0$ or on the state: it is $e^{A u}$ with
    /// $A = \begin{pmatrix}0 & I\\\\ -I & -2\nu_1 I\end{pmatrix}$. Per axis, with $c$ and $S$
    /// of the module docs (their hyperbolic and critical forms when $\nu_1 \ge 1$):
    ///
    /// $$\Phi^{(1)}(u) = e^{-\nu_1 u}\begin{pmatrix} c + \nu_1 S & S\\\\ -S & c - \nu_1 S
    /// \end{pmatrix}.$$
    ///
    /// The variation of a free flight started at an event whose time moves (a contact loss)
    /// is not this matrix alone: the saltation matrix of the event carries the time shift.
    pub fn transition_matrix(&self, u: f64) -> Matrix4<f64> {
        let (c, s, decay) = self.cs(u);
        let (a, b) = ((c + self.nu1 * s) * decay, s * decay);
        let d = (c - self.nu1 * s) * decay;
        Matrix4::new(
            a, 0.0, b, 0.0, //
            0.0, a, 0.0, b, //
            -b, 0.0, d, 0.0, //
            0.0, -b, 0.0, d,
        )
    }

    /// Starts a free-flight segment at time `t0` from rotor state `y0`.
    pub fn segment(&self, t0: f64, y0: &RotorState) -> FreeFlight {
        let (zp, vp, _) = self.particular(t0);
        let w0 = C(y0[0], y0[1]).sub(zp);
        let w0d = C(y0[2], y0[3]).sub(vp);
        FreeFlight {
            osc: *self,
            t0,
            w0,
            b: w0d.add(w0.scale(self.nu1)),
            energy_sqrt: (w0.norm2() + w0d.norm2()).sqrt(),
        }
    }
}

/// One free-flight segment: the exact rotor trajectory from `(t0, y0)` on.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FreeFlight {
    osc: FreeOscillator,
    t0: f64,
    w0: C,
    /// $w_0^\prime + \nu_1 w_0$.
    b: C,
    energy_sqrt: f64,
}

impl FreeFlight {
    /// Start time of the segment.
    pub fn start(&self) -> f64 {
        self.t0
    }

    /// $|e|$: distance of the rotor's rest position from the ring's centre.
    pub fn eccentricity_norm(&self) -> f64 {
        self.osc.e.norm2().sqrt()
    }

    /// Exact rotor state `[x, y, x', y']` at time `t`.
    pub fn state(&self, t: f64) -> RotorState {
        self.state_accel(t).0
    }

    /// Exact rotor state and acceleration `[x'', y'']` at time `t`.
    pub fn state_accel(&self, t: f64) -> (RotorState, [f64; 2]) {
        let o = &self.osc;
        let u = t - self.t0;
        let (zp, vp, phasor) = o.particular(t);
        let (c, s, decay) = o.cs(u);
        let w = self.w0.scale(c).add(self.b.scale(s)).scale(decay);
        // w' = e^{-nu u}((b - nu w0) c - (nu b + wd2 w0) S)
        let wd = self
            .b
            .sub(self.w0.scale(o.nu1))
            .scale(c)
            .sub(self.b.scale(o.nu1).add(self.w0.scale(o.wd2)).scale(s))
            .scale(decay);
        let z = zp.add(w);
        let v = vp.add(wd);
        // z'' = B e^{i theta} - 2 nu z' - (z - e)
        let acc = phasor
            .scale(o.amp)
            .sub(v.scale(2.0 * o.nu1))
            .sub(z.sub(o.e));
        ([z.0, z.1, v.0, v.1], [acc.0, acc.1])
    }

    /// State-transition matrix from the segment's start to time `t`:
    /// $\partial z(t)/\partial z(t_0)$ ([`FreeOscillator::transition_matrix`] of $t - t_0$).
    pub fn transition_matrix(&self, t: f64) -> Matrix4<f64> {
        self.osc.transition_matrix(t - self.t0)
    }

    /// Bounds on $|r|$, $|r^\prime|$, $|r^{\prime\prime}|$, $|r^{\prime\prime\prime}|$ valid for all $t \ge t_0$: the particular
    /// orbit is a circle of radius $|Z|$ about $e$ run at speed $\eta$, and the homogeneous
    /// part's energy $E_w = |w|^2 + |w^\prime|^2$ is non-increasing, so $|w|, |w^\prime| \le \sqrt{E_w}$,
    /// $|r| \le |e| + |Z| + \sqrt{E_w}$,
    /// $|w^{\prime\prime}| = |2\nu_1 w^\prime + w| \le (1 + 2\nu_1)\sqrt{E_w}$ and
    /// $|w^{\prime\prime\prime}| = |2\nu_1 w^{\prime\prime} + w^\prime| \le (1 + 2\nu_1(1 + 2\nu_1))\sqrt{E_w}$.
    pub fn bounds(&self) -> MotionBounds {
        let o = &self.osc;
        let a = o.steady_radius();
        let e = self.energy_sqrt;
        let n2 = 2.0 * o.nu1;
        MotionBounds {
            position: self.eccentricity_norm() + (a + e),
            velocity: a * o.eta + e,
            acceleration: a * o.eta * o.eta + (1.0 + n2) * e,
            jerk: a * o.eta.powi(3) + (1.0 + n2 * (1.0 + n2)) * e,
        }
    }

    /// The bounds from a later time `t` on (cheaper than a new segment: the homogeneous
    /// energy at `t` is computed from the state there).
    pub fn bounds_from(&self, t: f64, y: &RotorState) -> MotionBounds {
        self.osc.segment(t, y).bounds()
    }
}

impl RotorMotion for FreeFlight {
    fn start(&self) -> f64 {
        self.t0
    }

    fn kinematics(&self, t: f64) -> (Vector2<f64>, Vector2<f64>, Vector2<f64>) {
        let (y, a) = self.state_accel(t);
        (
            Vector2::new(y[0], y[1]),
            Vector2::new(y[2], y[3]),
            Vector2::new(a[0], a[1]),
        )
    }

    fn bounds(&self) -> MotionBounds {
        FreeFlight::bounds(self)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::params::Preset;

    /// Integrates the free oscillator with a tiny-step RK4 and compares with the closed form.
    fn check(p: Params) {
        let osc = FreeOscillator::new(&p);
        let y0 = [0.3, -0.2, 0.5, 0.1];
        let seg = osc.segment(0.7, &y0);
        let f = |t: f64, y: &[f64; 4]| {
            let b = p.forcing_amplitude();
            let th = p.phi0 + p.eta * t;
            [
                y[2],
                y[3],
                b * th.cos() - 2.0 * p.nu1 * y[2] - (y[0] - p.ex),
                b * th.sin() - 2.0 * p.nu1 * y[3] - (y[1] - p.ey),
            ]
        };
        let mut y = y0;
        let (mut t, h) = (0.7, 1e-3);
        for _ in 0..5000 {
            let k1 = f(t, &y);
            let a = |k: &[f64; 4], c: f64| std::array::from_fn::<f64, 4, _>(|i| y[i] + c * k[i]);
            let k2 = f(t + h / 2.0, &a(&k1, h / 2.0));
            let k3 = f(t + h / 2.0, &a(&k2, h / 2.0));
            let k4 = f(t + h, &a(&k3, h));
            for i in 0..4 {
                y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
            }
            t += h;
        }
        let ex = seg.state(t);
        for i in 0..4 {
            assert!((ex[i] - y[i]).abs() < 1e-10, "{i}: {} vs {}", ex[i], y[i]);
        }
        let (_, acc) = seg.state_accel(t);
        let fy = f(t, &ex);
        assert!((acc[0] - fy[2]).abs() < 1e-12 && (acc[1] - fy[3]).abs() < 1e-12);
    }

    #[test]
    fn closed_form_matches_integration_in_every_damping_case() {
        let base = Preset::Fig10b.params();
        check(base);
        check(Params { nu1: 0.0, ..base });
        check(Params { nu1: 1.0, ..base });
        check(Params {
            nu1: 1.0 + 1e-9,
            ..base
        });
        check(Params { nu1: 2.5, ..base });
    }

    #[test]
    fn over_damped_closed_form_stays_finite_and_decays_in_long_flights() {
        // cosh(wd u) alone overflows at wd u = 710: u = 310 here.
        let p = Params {
            nu1: 2.5,
            ..Preset::Fig8a.params()
        };
        let osc = FreeOscillator::new(&p);
        let seg = osc.segment(0.0, &[0.3, -0.2, 0.5, 0.1]);
        let steady = osc.segment(1000.0, &seg.state(1000.0));
        for u in [100.0, 400.0, 1000.0, 5000.0] {
            let y = seg.state(u);
            assert!(y.iter().all(|c| c.is_finite()), "u = {u}: {y:?}");
            // Far beyond the transient the state is the particular orbit: restarting the
            // closed form there gives the same state to rounding.
            if u >= 1000.0 {
                let z = steady.state(u);
                for i in 0..4 {
                    assert!(
                        (y[i] - z[i]).abs() < 1e-12,
                        "u = {u}, {i}: {} vs {}",
                        y[i],
                        z[i]
                    );
                }
            }
        }
        // And the products match the direct formula where that does not overflow.
        let (c, s, d) = osc.cs(50.0);
        let (ch, sh) = ((osc.wd * 50.0).cosh(), (osc.wd * 50.0).sinh() / osc.wd);
        let decay = (-p.nu1 * 50.0).exp();
        assert!((c * d - ch * decay).abs() <= 1e-14 * ch * decay);
        assert!((s * d - sh * decay).abs() <= 1e-14 * sh * decay);
    }

    #[test]
    fn transition_matrix_matches_finite_differences_in_every_damping_case() {
        let base = Preset::Fig8a.params();
        let y0 = [0.3, -0.2, 0.5, 0.1];
        let mut worst = 0.0f64;
        for nu1 in [0.125, 0.0, 1.0, 1.0 + 1e-9, 2.5] {
            let osc = FreeOscillator::new(&Params { nu1, ..base });
            for u in [0.0, 1e-3, 0.7, 3.0, 40.0] {
                let phi = osc.segment(0.4, &y0).transition_matrix(0.4 + u);
                // Central differences of the closed form; it is linear in the start state, so
                // only rounding (eps |state| / h) limits them.
                let h = 1e-4;
                for j in 0..4 {
                    let (mut p, mut m) = (y0, y0);
                    p[j] += h;
                    m[j] -= h;
                    let (sp, sm) = (
                        osc.segment(0.4, &p).state(0.4 + u),
                        osc.segment(0.4, &m).state(0.4 + u),
                    );
                    for i in 0..4 {
                        let fd = (sp[i] - sm[i]) / (2.0 * h);
                        worst = worst.max((fd - phi[(i, j)]).abs());
                    }
                }
                // The semigroup property Phi(a + b) = Phi(a) Phi(b).
                let split = osc.transition_matrix(0.3 * u) * osc.transition_matrix(0.7 * u);
                assert!(
                    (split - osc.transition_matrix(u)).norm() < 1e-13,
                    "nu1 {nu1}, u {u}"
                );
            }
            assert_eq!(osc.transition_matrix(0.0), Matrix4::identity());
        }
        eprintln!("free-flight STM vs FD: {worst:e}");
        // Measured: 9.2e-13 (rounding of the states over the step).
        assert!(worst < 1e-11, "{worst:e}");
    }

    #[test]
    fn bounds_hold_along_the_trajectory() {
        // Every damping case (the energy argument holds for all nu1 >= 0), from a start far from
        // the steady orbit, the jerk from the differentiated equation of motion.
        for nu1 in [0.125, 0.0, 1.0, 2.5] {
            let p = Params {
                nu1,
                ..Preset::Fig8a.params()
            };
            let seg = FreeOscillator::new(&p).segment(0.0, &[-0.8, 0.6, 1.5, -2.0]);
            let b = seg.bounds();
            let amp = p.forcing_amplitude();
            for k in 0..2000 {
                let t = k as f64 * 0.01;
                let (y, a) = seg.state_accel(t);
                let th = p.phi0 + p.eta * t;
                let jerk = [
                    -amp * p.eta * th.sin() - 2.0 * nu1 * a[0] - y[2],
                    amp * p.eta * th.cos() - 2.0 * nu1 * a[1] - y[3],
                ];
                assert!(y[0].hypot(y[1]) <= b.position);
                assert!(y[2].hypot(y[3]) <= b.velocity);
                assert!(a[0].hypot(a[1]) <= b.acceleration);
                assert!(jerk[0].hypot(jerk[1]) <= b.jerk, "nu1 {nu1}, t {t}");
            }
        }
    }
}
