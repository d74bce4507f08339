//! The crate against what a user would otherwise pick: the generic `ode_solvers` 0.6 crate.
//!
//! Scene: the paper's Fig. 8a values at eta = 2.0 (zero preload: regimes I and V only), from
//! rest over 50 forcing periods; the error is the largest component of the state error at the
//! end against the crate's own reference (DOP853, rtol 1e-13, which agrees with the
//! independent SciPy reference in tests/data to ~2e-14).
//!
//! The `ode_solvers` variant ("naive hybrid") integrates the whole hybrid system with its
//! `Dop853`, one call per mode: free flight integrates the rotor and the ring's relaxation
//! `s' = -(K / 2 nu2) s` (stiff, time constant 1.3e-4); contact integrates the rotor with the
//! ring at its closed-form location `s = r (R - 1) / R`. Events are found by a sign check of the
//! guard after each accepted step (`System::solout`), taking the end of that step as the event:
//! no root finding, which is what a user writes first.
//!
//! Before anything else the bench checks `ode_solvers` on a forced damped oscillator with a
//! known solution (from t = 0 and from t = 100) and prints the errors.
//!
//! Run: `cargo bench -p bench-compare` (prints the error/time table, then the
//! criterion timings at one tolerance pair of comparable error).

use std::hint::black_box;
use std::time::{Duration, Instant};

use criterion::Criterion;
use jeffcott::hybrid::SimOptions;
use jeffcott::paper::{JeffcottModel, State};
use jeffcott::params::{Params, Preset};
use ode_solvers::{Dop853, Dopri5, OutputType, SVector, System, Vector2 as V2};

/// State of the naive hybrid run: [x, y, x', y', x_s, y_s, t] (t only used when autonomous).
type V6<T> = SVector<T, 7>;

// ---------------------------------------------------------------------------------------------
// Sanity check of ode_solvers: x'' + 2 z x' + x = F cos(w t).

struct Forced {
    z: f64,
    f: f64,
    w: f64,
}

impl System<f64, V2<f64>> for Forced {
    fn system(&self, t: f64, y: &V2<f64>, dy: &mut V2<f64>) {
        dy[0] = y[1];
        dy[1] = self.f * (self.w * t).cos() - 2.0 * self.z * y[1] - y[0];
    }
}

/// Closed form of the forced oscillator from (t0, x0, v0).
fn forced_exact(p: &Forced, t0: f64, x0: f64, v0: f64, t: f64) -> f64 {
    // Particular: a cos(w t) + b sin(w t).
    let den = (1.0 - p.w * p.w).powi(2) + (2.0 * p.z * p.w).powi(2);
    let a = p.f * (1.0 - p.w * p.w) / den;
    let b = p.f * 2.0 * p.z * p.w / den;
    let xp = |t: f64| a * (p.w * t).cos() + b * (p.w * t).sin();
    let vp = |t: f64| p.w * (-a * (p.w * t).sin() + b * (p.w * t).cos());
    let wd = (1.0 - p.z * p.z).sqrt();
    let c1 = x0 - xp(t0);
    let c2 = (v0 - vp(t0) + p.z * c1) / wd;
    let s = t - t0;
    xp(t) + (-p.z * s).exp() * (c1 * (wd * s).cos() + c2 * (wd * s).sin())
}

/// The forced oscillator made autonomous: [x, x', t].
struct ForcedAutonomous(Forced);

impl System<f64, SVector<f64, 3>> for ForcedAutonomous {
    fn system(&self, _t: f64, y: &SVector<f64, 3>, dy: &mut SVector<f64, 3>) {
        let p = &self.0;
        dy[0] = y[1];
        dy[1] = p.f * (p.w * y[2]).cos() - 2.0 * p.z * y[1] - y[0];
        dy[2] = 1.0;
    }
}

/// Steps and error of ode_solvers on the forced oscillator over [0, 20] at `rtol`
/// (atol = rtol / 100), stiffness test off: time-dependent Dop853, autonomous Dop853, Dopri5.
fn forced_work(rtol: f64) {
    let p = Forced {
        z: 0.05,
        f: 1.0,
        w: 1.7,
    };
    let exact = forced_exact(&p, 0.0, 0.3, -0.2, 20.0);
    let atol = rtol * 1e-2;
    let mut a = Dop853::from_param(
        Forced { ..p },
        0.0,
        20.0,
        0.0,
        V2::new(0.3, -0.2),
        rtol,
        atol,
        0.9,
        0.0,
        0.333,
        6.0,
        20.0,
        0.0,
        100_000_000,
        u32::MAX,
        OutputType::Sparse,
    );
    let sa = a.integrate();
    let ea = (a.y_out().last().expect("output")[0] - exact).abs();
    let mut b = Dop853::from_param(
        ForcedAutonomous(Forced { ..p }),
        0.0,
        20.0,
        0.0,
        SVector::<f64, 3>::new(0.3, -0.2, 0.0),
        rtol,
        atol,
        0.9,
        0.0,
        0.333,
        6.0,
        20.0,
        0.0,
        100_000_000,
        u32::MAX,
        OutputType::Sparse,
    );
    let sb = b.integrate();
    let eb = (b.y_out().last().expect("output")[0] - exact).abs();
    let mut c = Dopri5::new(
        Forced { ..p },
        0.0,
        20.0,
        0.0,
        V2::new(0.3, -0.2),
        rtol,
        atol,
    );
    c.set_output(OutputType::Sparse);
    let sc = c.integrate();
    let ec = (c.y_out().last().expect("output")[0] - exact).abs();
    let steps =
        |s: &Result<ode_solvers::dop_shared::Stats, _>| s.as_ref().map_or(0, |s| s.accepted_steps);
    println!(
        "ode_solvers on x'' + 0.1 x' + x = cos(1.7 t), t in [0, 20], rtol {rtol:e}: \
         Dop853 {} steps, error {ea:.1e}; Dop853 with t as a state {} steps, error {eb:.1e}; \
         Dopri5 {} steps, error {ec:.1e}",
        steps(&sa),
        steps(&sb),
        steps(&sc)
    );
}

fn check_forced_oscillator() {
    let p = Forced {
        z: 0.05,
        f: 1.0,
        w: 1.7,
    };
    for (t0, dense) in [(0.0, false), (100.0, false), (0.0, true), (100.0, true)] {
        let t1 = t0 + 50.0;
        let sys = Forced { ..p };
        let mut s = Dop853::new(sys, t0, t1, 0.5, V2::new(0.3, -0.2), 1e-10, 1e-12);
        if !dense {
            s.set_output(OutputType::Sparse);
        }
        let res = s.integrate();
        let worst = s
            .x_out()
            .iter()
            .zip(s.y_out())
            .map(|(&t, y)| (y[0] - forced_exact(&p, t0, 0.3, -0.2, t)).abs())
            .fold(0.0f64, f64::max);
        let t_last = *s.x_out().last().unwrap();
        println!(
            "ode_solvers check: forced damped oscillator from t0 = {t0}, {} output, rtol 1e-10: \
             {:?}; {} outputs, last at t = {t_last}, max |x - exact| = {worst:.2e}",
            if dense { "dense" } else { "sparse" },
            res.map(|st| st.num_eval),
            s.x_out().len()
        );
    }
}

// ---------------------------------------------------------------------------------------------
// The naive hybrid simulation with ode_solvers (zero preload, isotropic K).

#[derive(Clone, Copy, PartialEq)]
enum Mode {
    Free,
    Contact,
}

struct Hybrid {
    p: Params,
    amp: f64,
    mode: Mode,
    /// Sign of the guard at the start of the phase (to detect a change).
    start_sign: bool,
    /// Time taken from the state's last component (t' = 1) instead of the solver's clock.
    autonomous: bool,
}

impl Hybrid {
    /// Ring location and velocity in contact: s = r (R - 1) / R.
    fn ring(r: (f64, f64), v: (f64, f64)) -> ((f64, f64), (f64, f64)) {
        let rr = r.0.hypot(r.1);
        let k = (rr - 1.0) / rr;
        let rv = (r.0 * v.0 + r.1 * v.1) / (rr * rr * rr);
        ((r.0 * k, r.1 * k), (v.0 * k + r.0 * rv, v.1 * k + r.1 * rv))
    }

    /// Contact force (D = 0: one unit per axis acts): K s + 2 nu2 s'.
    fn force(&self, y: &V6<f64>) -> (f64, f64) {
        let (s, sd) = Self::ring((y[0], y[1]), (y[2], y[3]));
        let k = self.p.kx;
        let c = 2.0 * self.p.nu2;
        (k * s.0 + c * sd.0, k * s.1 + c * sd.1)
    }

    /// The guard of the mode; the mode ends when its sign differs from the start's.
    fn guard(&self, y: &V6<f64>) -> bool {
        match self.mode {
            // Onset: |r - s| >= 1.
            Mode::Free => (y[0] - y[4]).hypot(y[1] - y[5]) >= 1.0,
            // Loss: the normal force (along r) is negative or |r| <= 1.
            Mode::Contact => {
                let f = self.force(y);
                y[0] * f.0 + y[1] * f.1 < 0.0 || y[0].hypot(y[1]) <= 1.0
            }
        }
    }
}

impl System<f64, V6<f64>> for Hybrid {
    fn system(&self, t: f64, y: &V6<f64>, dy: &mut V6<f64>) {
        let t = if self.autonomous { y[6] } else { t };
        let (sn, cs) = (self.p.eta * t).sin_cos();
        let mut ax = self.amp * cs - 2.0 * self.p.nu1 * y[2] - (y[0] - self.p.ex);
        let mut ay = self.amp * sn - 2.0 * self.p.nu1 * y[3] - (y[1] - self.p.ey);
        let (sdx, sdy) = match self.mode {
            Mode::Free => {
                let rate = self.p.kx / (2.0 * self.p.nu2);
                (-rate * y[4], -rate * y[5])
            }
            Mode::Contact => {
                let f = self.force(y);
                ax -= f.0;
                ay -= f.1;
                Self::ring((y[0], y[1]), (y[2], y[3])).1
            }
        };
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = ax;
        dy[3] = ay;
        dy[4] = sdx;
        dy[5] = sdy;
        dy[6] = 1.0;
    }

    fn solout(&mut self, _t: f64, y: &V6<f64>, _dy: &V6<f64>) -> bool {
        self.guard(y) != self.start_sign
    }
}

/// How the naive hybrid run uses ode_solvers.
#[derive(Clone, Copy, PartialEq, Debug)]
enum Variant {
    /// `Dop853`, forcing time from the solver (as a user writes it).
    Dop853,
    /// `Dop853` with time as an extra state (t' = 1): sidesteps its wrong c12 (see the docs).
    Dop853Autonomous,
    /// `Dopri5`, forcing time from the solver.
    Dopri5,
}

/// Naive hybrid run with ode_solvers from rest to `t_end`. Returns the final state, the
/// right-hand-side evaluations and the number of mode switches, or the solver's error.
fn naive(
    p: &Params,
    t_end: f64,
    rtol: f64,
    atol: f64,
    variant: Variant,
) -> Result<([f64; 6], u64, u64), String> {
    let mut t = 0.0;
    let mut y = V6::zeros();
    let mut mode = Mode::Free;
    let mut evals = 0u64;
    let mut switches = 0u64;
    while t < t_end {
        let mut sys = Hybrid {
            p: *p,
            amp: p.forcing_amplitude(),
            mode,
            start_sign: false,
            autonomous: variant == Variant::Dop853Autonomous,
        };
        sys.start_sign = sys.guard(&y);
        // Disable the stiffness test (the ring's relaxation is stiff by design); cap the step
        // at a quarter period like the crate.
        let h_max = 0.25 * p.forcing_period();
        let (st, tn, yn) = if variant == Variant::Dopri5 {
            let mut s = Dopri5::from_param(
                sys,
                t,
                t_end,
                0.0,
                y,
                rtol,
                atol,
                0.9,
                0.04,
                0.2,
                10.0,
                h_max,
                0.0,
                100_000_000,
                u32::MAX,
                OutputType::Sparse,
            );
            let st = s.integrate().map_err(|e| e.to_string())?;
            (
                st,
                *s.x_out().last().expect("output"),
                *s.y_out().last().expect("output"),
            )
        } else {
            let mut s = Dop853::from_param(
                sys,
                t,
                t_end,
                0.0,
                y,
                rtol,
                atol,
                0.9,
                0.0,
                0.333,
                6.0,
                h_max,
                0.0,
                100_000_000,
                u32::MAX,
                OutputType::Sparse,
            );
            let st = s.integrate().map_err(|e| e.to_string())?;
            (
                st,
                *s.x_out().last().expect("output"),
                *s.y_out().last().expect("output"),
            )
        };
        evals += u64::from(st.num_eval);
        t = tn;
        y = yn;
        if t < t_end {
            // A sign change at the end of the last step: switch mode there.
            switches += 1;
            mode = match mode {
                Mode::Free => {
                    let rr = y[0].hypot(y[1]);
                    if rr > 1.0 {
                        let (sv, _) = Hybrid::ring((y[0], y[1]), (y[2], y[3]));
                        y[4] = sv.0;
                        y[5] = sv.1;
                        Mode::Contact
                    } else {
                        y[4] = 0.0;
                        y[5] = 0.0;
                        Mode::Free
                    }
                }
                Mode::Contact => Mode::Free,
            };
        }
    }
    if mode == Mode::Contact {
        let (sv, _) = Hybrid::ring((y[0], y[1]), (y[2], y[3]));
        y[4] = sv.0;
        y[5] = sv.1;
    }
    Ok(([y[0], y[1], y[2], y[3], y[4], y[5]], evals, switches))
}

// ---------------------------------------------------------------------------------------------
// The careful hybrid simulation with ode_solvers (zero preload, isotropic K): what a careful
// user writes with a generic crate.
//
// * Time is carried as a state (t' = 1), which sidesteps the DOP853 tableau bug (c12 = 0).
// * The ring's relaxation in free flight, s' = -(K / 2 nu2) s with time constant 1.3e-4, is
//   stiff for an explicit method (ode_solvers has no implicit one): a careful user solves it in
//   closed form, s(t) = s0 exp(-(t - t0) / T), and uses it in the onset guard only; the rotor's
//   free flight is integrated.
// * Contact: the rotor with the ring at its closed-form location s = r (R - 1) / R (regime V of
//   the paper, zero preload), force K s + 2 nu2 s'.
// * Events: `solout` stops the integration at the first accepted step whose end has crossed the
//   guard (onset: |r - s(t)| reaches 1 after being below; loss: the normal force n . f falls
//   below 0, or |r| reaches 1); the crossing is then located by bisection to 1e-12, each
//   bisection point reached by restarting the integrator from the last point before the
//   crossing with one step of the bracket's half (its initial step given, no automatic choice).
//   The new mode starts at the end of the final bracket (after the crossing).

/// State of the careful run: [x, y, x', y', t].
type V5 = SVector<f64, 5>;

#[derive(Clone, Copy, PartialEq)]
enum CarefulMode {
    /// Free flight, the ring relaxing from `s0` since `t0`.
    Free {
        t0: f64,
        s0: (f64, f64),
    },
    Contact,
}

struct Careful {
    p: Params,
    amp: f64,
    mode: CarefulMode,
    /// The guard has been on its pre-crossing side in this phase (armed).
    armed: bool,
    /// Stop at the first step end where the event has happened.
    stop: bool,
}

impl Careful {
    fn relax_time(&self) -> f64 {
        2.0 * self.p.nu2 / self.p.kx
    }

    /// The ring's position in free flight at time `t`.
    fn free_ring(&self, t0: f64, s0: (f64, f64), t: f64) -> (f64, f64) {
        let e = (-(t - t0) / self.relax_time()).exp();
        (s0.0 * e, s0.1 * e)
    }

    /// Whether the mode's event has happened at `y` (past the guard), and whether the guard is
    /// strictly on its pre-crossing side.
    fn event(&self, y: &V5) -> (bool, bool) {
        match self.mode {
            CarefulMode::Free { t0, s0 } => {
                let s = self.free_ring(t0, s0, y[4]);
                let h = (y[0] - s.0).powi(2) + (y[1] - s.1).powi(2) - 1.0;
                (h >= 0.0, h < 0.0)
            }
            CarefulMode::Contact => {
                let (_, f) = Hybrid::ring_force(&self.p, y);
                let rr = y[0].hypot(y[1]);
                let normal = (y[0] * f.0 + y[1] * f.1) / rr;
                let lost = normal < 0.0 || rr <= 1.0;
                (lost, !lost)
            }
        }
    }
}

impl Hybrid {
    /// Ring location and force in contact (zero preload, isotropic): s = r (R - 1) / R,
    /// f = K s + 2 nu2 s'.
    fn ring_force(p: &Params, y: &V5) -> ((f64, f64), (f64, f64)) {
        let (s, sd) = Self::ring((y[0], y[1]), (y[2], y[3]));
        let c = 2.0 * p.nu2;
        (s, (p.kx * s.0 + c * sd.0, p.kx * s.1 + c * sd.1))
    }
}

impl System<f64, V5> for Careful {
    fn system(&self, _t: f64, y: &V5, dy: &mut V5) {
        let t = y[4];
        let (sn, cs) = (self.p.eta * t).sin_cos();
        let mut ax = self.amp * cs - 2.0 * self.p.nu1 * y[2] - (y[0] - self.p.ex);
        let mut ay = self.amp * sn - 2.0 * self.p.nu1 * y[3] - (y[1] - self.p.ey);
        if self.mode == CarefulMode::Contact {
            let (_, f) = Hybrid::ring_force(&self.p, y);
            ax -= f.0;
            ay -= f.1;
        }
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = ax;
        dy[3] = ay;
        dy[4] = 1.0;
    }

    fn solout(&mut self, _t: f64, y: &V5, _dy: &V5) -> bool {
        let (happened, before) = self.event(y);
        if before {
            self.armed = true;
        }
        self.stop && self.armed && happened
    }
}

/// The last two step points of a leg, `(t, y)`, and its right-hand-side evaluations.
type Leg = ((f64, V5), (f64, V5), u64);

/// One Dop853 integration of the careful system from (t, y) to `t_end` (with the given initial
/// step, 0 = automatic), stopping at the event if the system says so. Returns the last two step
/// points and the evaluations.
fn careful_leg(sys: Careful, t: f64, y: V5, t_end: f64, h0: f64, tol: f64) -> Result<Leg, String> {
    let h_max = 0.25 * sys.p.forcing_period();
    let mut s = Dop853::from_param(
        sys,
        t,
        t_end,
        0.0,
        y,
        tol,
        tol,
        0.9,
        0.0,
        0.333,
        6.0,
        h_max,
        h0,
        100_000_000,
        u32::MAX,
        OutputType::Sparse,
    );
    let st = s.integrate().map_err(|e| e.to_string())?;
    let (xs, ys) = (s.x_out(), s.y_out());
    let n = xs.len();
    let last = (xs[n - 1], ys[n - 1]);
    let prev = if n >= 2 { (xs[n - 2], ys[n - 2]) } else { last };
    Ok((prev, last, u64::from(st.num_eval)))
}

/// The careful hybrid run from rest to `t_end`. Returns the final state [x, y, x', y', xs, ys],
/// the right-hand-side evaluations and the number of mode switches.
fn careful(p: &Params, t_end: f64, tol: f64) -> Result<([f64; 6], u64, u64), String> {
    let amp = p.forcing_amplitude();
    let mut t = 0.0;
    let mut y = V5::zeros();
    let mut mode = CarefulMode::Free {
        t0: 0.0,
        s0: (0.0, 0.0),
    };
    let mut evals = 0u64;
    let mut switches = 0u64;
    let make = |mode, stop| Careful {
        p: *p,
        amp,
        mode,
        armed: false,
        stop,
    };
    while t < t_end {
        let (prev, last, e) = careful_leg(make(mode, true), t, y, t_end, 0.0, tol)?;
        evals += e;
        let probe = make(mode, false);
        if last.0 >= t_end {
            // Reached the end (solout stops only at an event).
            t = last.0;
            y = last.1;
            continue;
        }
        // Bisection by restarting from the last point before the crossing.
        let (mut ta, mut ya) = prev;
        let mut tb = last.0;
        let mut yb = last.1;
        while tb - ta > 1e-12 {
            let m = 0.5 * (ta + tb);
            let (_, end, e) = careful_leg(make(mode, false), ta, ya, m, m - ta, tol)?;
            evals += e;
            if probe.event(&end.1).0 {
                tb = m;
                yb = end.1;
            } else {
                ta = m;
                ya = end.1;
            }
        }
        t = tb;
        y = yb;
        switches += 1;
        mode = match mode {
            CarefulMode::Free { .. } => {
                let rr = y[0].hypot(y[1]);
                let (_, f) = Hybrid::ring_force(p, &y);
                if rr > 1.0 && y[0] * f.0 + y[1] * f.1 > 0.0 {
                    CarefulMode::Contact
                } else {
                    // A touch without load: the ring stays relaxed at its centre.
                    CarefulMode::Free {
                        t0: t,
                        s0: (0.0, 0.0),
                    }
                }
            }
            CarefulMode::Contact => {
                let (s, _) = Hybrid::ring((y[0], y[1]), (y[2], y[3]));
                CarefulMode::Free { t0: t, s0: s }
            }
        };
    }
    let s = match mode {
        CarefulMode::Contact => Hybrid::ring((y[0], y[1]), (y[2], y[3])).0,
        CarefulMode::Free { t0, s0 } => make(mode, false).free_ring(t0, s0, t),
    };
    Ok(([y[0], y[1], y[2], y[3], s.0, s.1], evals, switches))
}

fn crate_run(m: &JeffcottModel, periods: u64, rtol: f64, atol: f64) -> (State, u64) {
    let opts = SimOptions::default().with_rtol(rtol).with_atol(atol);
    let (t, s) = m
        .strobe_range(&State::zeros(), periods, periods, &opts)
        .expect("crate run");
    (t.strobe[0].y, s.rhs_evals)
}

fn min_time<T>(reps: usize, mut f: impl FnMut() -> T) -> (f64, T) {
    let mut best = f64::INFINITY;
    let mut out = None;
    for _ in 0..reps {
        let t0 = Instant::now();
        let r = f();
        best = best.min(t0.elapsed().as_secs_f64());
        out = Some(r);
    }
    (best, out.expect("reps >= 1"))
}

/// The crate against the careful ode_solvers run, side by side in one run: for each tolerance
/// of the careful run, its error and time per period, and the crate's cheapest run (over
/// tolerances 1e-3 .. 1e-12) at least as accurate; their time ratio.
fn careful_table(m: &JeffcottModel, p: &Params, periods: u64, err: &dyn Fn(&[f64]) -> f64) {
    let t_end = p.forcing_period() * periods as f64;
    let per = |t: f64| t / periods as f64 * 1e6;
    println!(
        "\nCareful ode_solvers (Dop853, time as a state, closed-form ring relaxation, events \
         bisected to 1e-12 by restarting) against the crate, Fig. 8a, eta = 2.0, {periods} periods \
         from rest; times per forcing period (minimum of 5 runs); load average {:.1}",
        load()
    );
    let crate_rows: Vec<(f64, f64, f64, u64)> = (3..=12)
        .map(|e| {
            let tol = 10f64.powi(-e);
            let (tc, (yc, rc)) = min_time(5, || crate_run(m, periods, tol, tol));
            (tol, err(yc.as_slice()), tc, rc)
        })
        .collect();
    println!("crate DOP853: tol, error, us/period, rhs");
    for (tol, e, t, r) in &crate_rows {
        println!("  {tol:6.0e} {e:9.2e} {:8.3} {r:7}", per(*t));
    }
    println!(
        "careful ode_solvers: tol, error, us/period, rhs, switches | crate's cheapest run at least \
         as accurate: tol, error, us/period | time ratio"
    );
    for e in 6..=12 {
        let tol = 10f64.powi(-e);
        let (tn, rn) = min_time(5, || careful(p, t_end, tol));
        match rn {
            Ok((yn, evals, sw)) => {
                let en = err(&yn);
                let best = crate_rows
                    .iter()
                    .filter(|r| r.1 <= en)
                    .min_by(|a, b| a.2.total_cmp(&b.2));
                let cmp = match best {
                    Some((ct, ce, ctime, _)) => format!(
                        "{ct:6.0e} {ce:9.2e} {:8.3} | {:6.1}x",
                        per(*ctime),
                        tn / ctime
                    ),
                    None => "not reached by the crate".into(),
                };
                println!(
                    "  {tol:6.0e} {en:9.2e} {:9.2} {evals:8} {sw:4} | {cmp}",
                    per(tn)
                );
            }
            Err(e) => println!("  {tol:6.0e} failed: {e}"),
        }
    }
}

/// The one-minute load average (Linux), NaN elsewhere.
fn load() -> f64 {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().and_then(|x| x.parse().ok()))
        .unwrap_or(f64::NAN)
}

fn main() {
    let p = Preset::Fig8a.params();
    let periods = 50u64;
    let t_end = p.forcing_period() * periods as f64;
    let m = JeffcottModel::new(p).expect("params");
    let (reference, _) = crate_run(&m, periods, 1e-13, 1e-15);
    let err = |y: &[f64]| {
        y.iter()
            .zip(reference.iter())
            .map(|(a, b)| (a - b).abs())
            .fold(0.0f64, f64::max)
    };
    careful_table(&m, &p, periods, &err);
    if std::env::var("COMPARE_CAREFUL_ONLY").is_ok() {
        return;
    }

    check_forced_oscillator();
    for rtol in [1e-6, 1e-10] {
        forced_work(rtol);
    }
    println!("\nFig. 8a, eta = 2.0, {periods} periods from rest; error = max |state - reference|");
    let variants = [Variant::Dop853, Variant::Dop853Autonomous, Variant::Dopri5];
    let only_fast = std::env::var("COMPARE_FULL").is_err();
    println!(
        "tol    | crate DOP853: error, time, rhs | ode_solvers naive ({:?}, {:?}, {:?}): error, time, rhs, switches",
        variants[0], variants[1], variants[2]
    );
    for e in 3..=12 {
        let tol = 10f64.powi(-e);
        let (tc, (yc, rc)) = min_time(5, || crate_run(&m, periods, tol, tol));
        let mut naive_txt = String::new();
        for v in variants {
            // The time-dependent Dop853 needs minutes below 1e-9: skipped unless COMPARE_FULL.
            if v == Variant::Dop853 && e > 9 && only_fast {
                naive_txt += " | (skipped)";
                continue;
            }
            let reps = if e > 8 { 1 } else { 3 };
            let (tn, rn) = min_time(reps, || naive(&p, t_end, tol, tol, v));
            naive_txt += &match rn {
                Ok((yn, evals, sw)) => format!(
                    " | {:8.2e} {:9.3} ms {:9} {:4}",
                    err(&yn),
                    tn * 1e3,
                    evals,
                    sw
                ),
                Err(e) => format!(" | failed: {e}"),
            };
        }
        println!(
            "{tol:6.0e} | {:9.2e} {:8.3} ms {:7}{naive_txt}",
            err(yc.as_slice()),
            tc * 1e3,
            rc
        );
    }

    let mut c = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3))
        .configure_from_args();
    let mut g = c.benchmark_group("compare_fig8a_50_periods");
    g.bench_function("jeffcott_dop853_rtol1e-9", |b| {
        b.iter(|| crate_run(&m, black_box(periods), 1e-9, 1e-9))
    });
    g.bench_function("jeffcott_dop853_rtol1e-5", |b| {
        b.iter(|| crate_run(&m, black_box(periods), 1e-5, 1e-5))
    });
    g.bench_function("ode_solvers_dop853_autonomous_naive_rtol1e-9", |b| {
        b.iter(|| naive(&p, black_box(t_end), 1e-9, 1e-9, Variant::Dop853Autonomous))
    });
    g.bench_function("ode_solvers_dopri5_naive_rtol1e-9", |b| {
        b.iter(|| naive(&p, black_box(t_end), 1e-9, 1e-9, Variant::Dopri5))
    });
    g.bench_function("ode_solvers_dop853_careful_rtol1e-10", |b| {
        b.iter(|| careful(&p, black_box(t_end), 1e-10))
    });
    g.finish();
    c.final_summary();
}
