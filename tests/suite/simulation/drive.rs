//! The non-ideal drive ([`DrivenJeffcott`]): the speed a state driven by a motor, checked
//! against truths independent of the drive's equations:
//!
//! * a drive of huge inertia whose motor holds the speed reproduces the paper's model at that
//!   constant speed ([`JeffcottModel`]: free flight in closed form, contact onsets by the
//!   certified search), with contact;
//! * the Sommerfeld effect: a motor of limited torque whose no-load speed is far above the
//!   critical speed is captured below it, and one of more torque passes it (the load curve's
//!   peak, $2\nu_1\eta A(\eta)^2$ with the steady amplitude in closed form, lies between the
//!   two motors' lines near $\eta = 1$);
//! * the Sommerfeld threshold, the stall torque between stuck and passing bisected by
//!   `numeric::bisect`, against the quasi-static one where the motor's line touches the
//!   closed-form load curve: below it with little inertia (the amplitude lags the speed),
//!   nearing it with much (the slow-passage limit, with the finite horizon's bias up by the
//!   law of a saddle-node's bottleneck); and on the ring, where only the number is reported;
//! * the energy balance with contact (`drive_energy`).

use std::convert::Infallible;

use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimOptions, StrobeRange, Trajectory};
use jeffcott::nalgebra::{SVector, U8};
use jeffcott::numeric::{bisect, illinois, Bisection, RootOptions, Side};
use jeffcott::paper::JeffcottModel;
use jeffcott::params::{Params, Preset};
use jeffcott::rotor::{DrivenJeffcott, MotorTorque, ETA, PHASE};

fn options() -> SimOptions {
    SimOptions::default().with_rtol(1e-11).with_atol(1e-12)
}

/// A drive of inertia $j = 10^{10}$ whose DC motor's no-load speed is $\eta = 2$ and whose
/// speed deviations decay with the rate $t_0/(\eta_0 j) = 0.005$: over 30 revolutions the
/// out-of-balance's load (of order $\beta\eta^2 \approx 0.5$) moves the speed by about
/// $10^{-8}$. Fig. 8a's rotor from rest at $(0.9, 0)$ hits the ring; its strobes (at the
/// shaft's turns, where its phase state is $\varphi_0 + 2\pi k$) against the paper's model's
/// at $\eta = 2$ (at $t = 2\pi k/\eta$): the times and states agree to the speed's drift.
/// Measured: see the printed line.
#[test]
fn huge_inertia_reproduces_the_constant_speed_model() {
    let eta = 2.0;
    let p = Params {
        eta,
        ..Preset::Fig8a.params()
    };
    let (j, t0) = (1e10, 1e8);
    let motor = MotorTorque::linear(t0, eta).unwrap();
    let driven = DrivenJeffcott::new(p, j, motor).unwrap().on_ring().unwrap();
    let periods = 30;
    // A quarter period more: the last turn falls a drift's worth after the last period.
    let t_end = std::f64::consts::TAU / eta * (periods as f64 + 0.25);
    let plan = OutputPlan {
        t_end,
        strobe: Some(StrobeRange {
            first: 0,
            last: periods,
        }),
        dense: None,
        events: true,
    };
    let mut traj = Trajectory::<U8>::default();
    let y0 = driven.rotor().state_at([p.ex, p.ey], [0.0, 0.0], eta);
    let stats = simulate(&driven, 0.0, &y0, &plan, &options(), &mut traj).unwrap();
    assert!(stats.transitions >= 4, "{} transitions", stats.transitions);

    let paper = JeffcottModel::new(p).unwrap();
    let y6 = paper.state_at([p.ex, p.ey], [0.0, 0.0]).unwrap();
    let (reference, _) = paper
        .run(
            0.0,
            &y6,
            &OutputPlan {
                t_end,
                ..OutputPlan::strobe(std::f64::consts::TAU / eta, 0, periods)
            },
            &options(),
        )
        .unwrap();
    assert_eq!(traj.strobe.len(), reference.strobe.len());
    assert_eq!(traj.strobe.len(), periods as usize + 1);
    let (mut worst, mut drift, mut late) = (0.0f64, 0.0f64, 0.0f64);
    for (a, b) in traj.strobe.iter().zip(&reference.strobe) {
        let turn = p.phi0 + std::f64::consts::TAU * a.k as f64;
        assert!(
            (a.y[PHASE] - turn).abs() <= 1e-12 * turn.abs().max(1.0),
            "strobe {} at the phase {} for {turn}",
            a.k,
            a.y[PHASE]
        );
        late = late.max((a.t - b.t).abs());
        for c in 0..4 {
            worst = worst.max((a.y[c] - b.y[c]).abs());
        }
        drift = drift.max((a.y[ETA] - eta).abs());
    }
    println!(
        "huge inertia: {} transitions, strobes within {worst:.2e} of the paper's model and \
         {late:.2e} in time, speed within {drift:.2e} of {eta}",
        stats.transitions
    );
    assert!(drift < 1e-7, "the speed moved by {drift:e}");
    // The turns move off the periods by the phase the drift makes over the run, at most
    // drift t_end, over the speed (twice that allowed).
    assert!(
        late < 2.0 * drift * t_end / eta,
        "the turns {late:e} off the periods"
    );
    assert!(worst < 1e-7, "the strobes differ by {worst:e}");
}

/// A run of `t_end` from $\eta = 0.1$ at rest at the centre (the static position: $e = 0$),
/// off the ring, with the DC motor $t_0(1 - \eta/3)$ of stall torque `stall` and the inertia
/// `j`, sampled every `dt`. Fig. 8a's rotor otherwise.
fn centred_run(stall: f64, j: f64, t_end: f64, dt: f64) -> Trajectory<U8> {
    let p = Params {
        eta: 1.0,
        ex: 0.0,
        ..Preset::Fig8a.params()
    };
    let motor = MotorTorque::linear(stall, 3.0).unwrap();
    let model = DrivenJeffcott::new(p, j, motor)
        .unwrap()
        .off_ring()
        .unwrap();
    let plan = OutputPlan {
        t_end,
        strobe: None,
        dense: Some(DenseSampling { t_start: 0.0, dt }),
        events: true,
    };
    let mut traj = Trajectory::<U8>::default();
    let y0: SVector<f64, 8> = model.rotor().state_at([0.0, 0.0], [0.0, 0.0], 0.1);
    simulate(&model, 0.0, &y0, &plan, &SimOptions::default(), &mut traj).unwrap();
    assert!(traj.events.is_empty(), "the ring is out of reach");
    traj
}

/// The mean speed over the last third of a run of `t_end` ([`centred_run`] with $j = 10$,
/// dense samples every 0.05) and the largest speed there.
fn mean_speed(stall: f64, t_end: f64) -> (f64, f64) {
    let traj = centred_run(stall, 10.0, t_end, 0.05);
    let late: Vec<f64> = traj
        .samples
        .iter()
        .filter(|s| s.t >= 2.0 * t_end / 3.0)
        .map(|s| s.y[ETA])
        .collect();
    let max = late.iter().copied().fold(0.0, f64::max);
    (late.iter().sum::<f64>() / late.len() as f64, max)
}

/// The steady load torque of the linear rotor at the speed $\eta$: its damping's power over
/// $\eta$, $2\nu_1\eta A^2$ with $A = \beta\eta^2/\sqrt{(1-\eta^2)^2 + (2\nu_1\eta)^2}$.
fn steady_load(p: &Params, eta: f64) -> f64 {
    let a = p.beta * eta * eta / ((1.0 - eta * eta).powi(2) + (2.0 * p.nu1 * eta).powi(2)).sqrt();
    2.0 * p.nu1 * eta * a * a
}

/// Sommerfeld: the load curve peaks at 0.057 near $\eta = 1$ (closed form above). A motor of
/// stall torque 0.05 (no-load speed 3) gives less than that there and is captured below the
/// critical speed; one of 0.2 passes it and runs near where its line meets the load far
/// above (about 2.8).
#[test]
fn sommerfeld_capture_and_passage() {
    let p = Preset::Fig8a.params();
    let peak = (500..2000)
        .map(|i| steady_load(&p, f64::from(i) * 1e-3))
        .fold(0.0, f64::max);
    let weak = MotorTorque::linear(0.05, 3.0).unwrap();
    let strong = MotorTorque::linear(0.2, 3.0).unwrap();
    // The premise, in closed form: the weak motor is below the load's peak near eta = 1, the
    // strong one above it everywhere up to 1.5.
    assert!(weak.torque(1.0) < peak && (0.9..1.5).all_below(&p, &strong));
    let (captured, captured_max) = mean_speed(0.05, 1500.0);
    let (passed, _) = mean_speed(0.2, 1500.0);
    println!(
        "Sommerfeld: load peak {peak:.4}; stall 0.05: mean eta {captured:.4} (max {captured_max:.4}); \
         stall 0.2: mean eta {passed:.4}"
    );
    assert!(
        captured < 1.1 && captured_max < 1.1,
        "not captured: {captured}"
    );
    // With the rest at the centre the steady orbit is a circle: the reaction torque is
    // constant and the captured speed is where the motor's line meets the closed-form load.
    let g = |eta: f64| weak.torque(eta) - steady_load(&p, eta);
    let opts = RootOptions::default().with_tol(1e-12);
    let meet = illinois((0.5, g(0.5)), (1.0, g(1.0)), &opts, g).unwrap().hi;
    println!("  the weak motor's line meets the load at {meet:.6}");
    assert!(
        (captured - meet).abs() < 1e-6 && (captured_max - meet).abs() < 1e-6,
        "captured at {captured} (max {captured_max}), the closed form meets at {meet}"
    );
    assert!(passed > 1.5, "did not pass: {passed}");
}

trait AllBelow {
    fn all_below(&self, p: &Params, motor: &MotorTorque) -> bool;
}

/// The steady load stays below the motor's torque on the range (sampled every 0.001).
impl AllBelow for std::ops::Range<f64> {
    fn all_below(&self, p: &Params, motor: &MotorTorque) -> bool {
        let n = ((self.end - self.start) * 1e3) as usize;
        (0..=n)
            .map(|i| self.start + i as f64 * 1e-3)
            .all(|eta| steady_load(p, eta) < motor.torque(eta))
    }
}

/// The speed a passing run exceeds: well above the resonance, where the motor's line at the
/// thresholds found (stall near 0.09: 0.045 at 1.5) is about three times the steady load
/// (0.016), so that a run which gets there is not captured again.
const PASSED: f64 = 1.5;

/// The rule: a run passes ([`Side::Far`]) when a dense sample of its speed exceeds `level`
/// before its end, and is stuck ([`Side::Near`]) otherwise: captured below the resonance, or
/// still in its bottleneck at the end.
fn stuck_or_passes(traj: &Trajectory<U8>, level: f64) -> Side {
    if traj.samples.iter().any(|s| s.y[ETA] > level) {
        Side::Far
    } else {
        Side::Near
    }
}

/// Off the ring: [`centred_run`] with dense samples every 0.5, by [`stuck_or_passes`] at
/// [`PASSED`].
fn centred_side(stall: f64, j: f64, t_end: f64) -> Side {
    stuck_or_passes(&centred_run(stall, j, t_end, 0.5), PASSED)
}

/// The stuck/passes threshold in stall torque of the classification `side`, bisected by
/// `numeric::bisect` to `tol` on the bracket `(stuck, passes)`, whose ends are run and
/// checked first (two runs more than the bisection's evaluations).
fn threshold(side: impl Fn(f64) -> Side, (stuck, passes): (f64, f64), tol: f64) -> Bisection {
    assert_eq!(side(stuck), Side::Near, "{stuck} passes");
    assert_eq!(side(passes), Side::Far, "{passes} is stuck");
    let b = bisect(stuck, passes, tol, 60, |stall| {
        Ok::<_, Infallible>(side(stall))
    })
    .unwrap();
    assert!(b.converged, "{b:?}");
    b
}

/// The quasi-static threshold, independent of the simulation: the least stall torque whose
/// line $t_0(1 - \eta/3)$ stays above the steady load $2\nu_1\eta A^2$ all the way up from
/// 0.1 past the resonance (to [`PASSED`]), i.e. the largest
/// $R(\eta) = 2\nu_1\eta A^2/(1 - \eta/3)$ there, where that line touches the load curve.
/// Scanned every $10^{-3}$, then refined by `numeric::illinois` on the closed-form slope
/// $(\ln R)' = 5/\eta - D'/D + 1/(3 - \eta)$ (as $R = 2\nu_1\beta^2\eta^5/(D(1 - \eta/3))$
/// with $D = (1 - \eta^2)^2 + (2\nu_1\eta)^2$). Returns the tangency's speed and $t_0$.
fn quasi_static_threshold(p: &Params) -> (f64, f64) {
    let ratio = |eta: f64| steady_load(p, eta) / (1.0 - eta / 3.0);
    let n = ((PASSED - 0.1) * 1e3).round() as usize;
    let grid = |i: usize| 0.1 + i as f64 * 1e-3;
    let top = (0..=n)
        .max_by(|&a, &b| ratio(grid(a)).total_cmp(&ratio(grid(b))))
        .unwrap();
    assert!(top > 0 && top < n, "the largest ratio is inside the range");
    let slope = |eta: f64| {
        let d = (1.0 - eta * eta).powi(2) + (2.0 * p.nu1 * eta).powi(2);
        let d_prime = -4.0 * eta * (1.0 - eta * eta) + 8.0 * p.nu1 * p.nu1 * eta;
        5.0 / eta - d_prime / d + 1.0 / (3.0 - eta)
    };
    let (a, b) = (grid(top - 1), grid(top + 1));
    let opts = RootOptions::default().with_tol(1e-13);
    let root = illinois((a, slope(a)), (b, slope(b)), &opts, slope).unwrap();
    assert!(root.converged);
    let eta = 0.5 * (root.lo + root.hi);
    assert!(
        ratio(eta) >= ratio(grid(top)),
        "the refined tangency is the top"
    );
    (eta, ratio(eta))
}

/// The Sommerfeld threshold with little inertia, below the quasi-static one: the speed runs
/// through the resonance faster than the rotor's amplitude builds up (on its time scale
/// $1/\nu_1 = 8$), so the load stays below the steady curve on the way (a passage through
/// resonance at a finite rate peaks lower than the steady amplitude, Lewis 1932) and the
/// motor passes with less torque than [`quasi_static_threshold`]; the more inertia, the
/// slower the passage and the nearer the threshold to the quasi-static one.
///
/// For $j$ = 0.3, 1, 3 (Fig. 8a off the ring, rest at the centre, no-load speed 3): the
/// threshold ([`centred_side`]) bisected by [`threshold`] to $10^{-6}$ on the bracket 0.04 to
/// $1.02\thinspace t_{qs}$, horizon 2000, lies below $t_{qs}$, and the gap shrinks as $j$
/// grows. The horizon: the final bracket's stuck end, run again for 8000, is still stuck, so
/// the threshold at the horizon 8000 is in the same bracket (a run that passes by 2000
/// passes by 8000).
#[test]
fn sommerfeld_threshold_with_little_inertia_is_below_the_quasi_static_one() {
    let (eta_star, qs) = quasi_static_threshold(&Preset::Fig8a.params());
    println!("little inertia: quasi-static threshold {qs:.8} (tangency at {eta_star:.6})");
    let t_end = 2000.0;
    let mut last_gap = f64::INFINITY;
    for j in [0.3, 1.0, 3.0] {
        let b = threshold(|t0| centred_side(t0, j, t_end), (0.04, 1.02 * qs), 1e-6);
        let longer = centred_side(b.near, j, 4.0 * t_end);
        let gap = 1.0 - b.far / qs;
        println!(
            "little inertia: j = {j}: threshold in [{:.7}, {:.7}] (horizon {t_end}; {} runs), \
             t0*/t_qs = {:.5}; stuck end for {}: {longer:?}",
            b.near,
            b.far,
            b.evaluations + 3,
            b.midpoint() / qs,
            4.0 * t_end
        );
        assert_eq!(longer, Side::Near, "j = {j}: {} passes later", b.near);
        assert!(gap > 0.0, "j = {j}: the threshold {} is above {qs}", b.far);
        assert!(gap < last_gap, "j = {j}: the gap {gap} did not shrink");
        last_gap = gap;
    }
}

/// The Sommerfeld threshold with much inertia: the slow-passage limit, where the threshold
/// is the quasi-static one and a finite horizon $T$ biases the bisected threshold upwards.
/// Just above $t_{qs}$ by $\delta$ the motor's line clears the load by
/// $a = \delta(1 - \eta_*/3)$ at the tangency and by $a + c(\eta - \eta_*)^2/2$ around it
/// ($c = -L''(\eta_*)$), so the speed crawls through this bottleneck in the time
/// $\pi j/\sqrt{ac/2}$ (a saddle-node's ghost): a run that has not passed by $T$ is taken for
/// stuck, and the threshold found at the horizon $T$ is above $t_{qs}$ by
/// $\delta(T) = K/(T - T_a)^2$ with $K = 2\pi^2 j^2/(c(1 - \eta_*/3))$ and $T_a$ the time of
/// the climb to the bottleneck.
///
/// For $j$ = 10 and 20, bisected (to $2.5\times10^{-7}$, on the bracket
/// $t_{qs}(1 \mp 0.02)$) at the horizons $T = 400j$ and $2T$: each threshold is above
/// $t_{qs}$ (the horizon's bias exceeds the amplitude's lag, which the test above shows
/// falling fast with $j$), the longer horizon's lower, and the ratio of their excesses over
/// $t_{qs}$ between $1/9$ and $1/4$ (the law above with $0 \le T_a \le T/2$; the climb from
/// 0.1 at about $0.03/j$ takes near $30j$), with 0.02 of slack for the bisection's width.
/// $K$ and $T_a$ fitted to the two horizons are printed with $K$ over the quasi-static
/// estimate: measured 1.22 at $j = 10$ and 1.12 at 20, as if the inertia were $j + 1.1$ (the
/// estimate leaves out the inertia of the rotor's orbit and its lag, a correction of order
/// $1/j$ in the slow-passage limit); asserted only that it nears 1 as $j$ grows (an assertion
/// of the limit's form, added after seeing these numbers).
#[test]
fn sommerfeld_threshold_with_much_inertia_nears_the_quasi_static_one() {
    let p = Preset::Fig8a.params();
    let (eta_star, qs) = quasi_static_threshold(&p);
    let h = 1e-4;
    let c = -(steady_load(&p, eta_star + h) - 2.0 * steady_load(&p, eta_star)
        + steady_load(&p, eta_star - h))
        / (h * h);
    println!("much inertia: quasi-static threshold {qs:.8} at {eta_star:.6}, c = {c:.4}");
    let mut last_miss = f64::INFINITY;
    for j in [10.0, 20.0] {
        let t_end = 400.0 * j;
        let [short, long] = [t_end, 2.0 * t_end].map(|t| {
            let b = threshold(|t0| centred_side(t0, j, t), (0.98 * qs, 1.02 * qs), 2.5e-7);
            println!(
                "much inertia: j = {j}, horizon {t}: threshold in [{:.8}, {:.8}] ({} runs), \
                 t0*/t_qs = {:.6}",
                b.near,
                b.far,
                b.evaluations + 2,
                b.midpoint() / qs
            );
            b.midpoint() - qs
        });
        let ratio = long / short;
        let t_a = (2.0 - ratio.sqrt().recip()) * t_end / (1.0 - ratio.sqrt().recip());
        let k = short * (t_end - t_a).powi(2);
        let k_qs = 2.0 * std::f64::consts::PI.powi(2) * j * j / (c * (1.0 - eta_star / 3.0));
        println!(
            "much inertia: j = {j}: excess {short:.3e} -> {long:.3e}, ratio {ratio:.4}; \
             T_a = {t_a:.0}, K = {k:.1} = {:.3} of 2 pi^2 j^2/(c (1 - eta*/3))",
            k / k_qs
        );
        assert!(
            short > 0.0 && long > 0.0,
            "below the quasi-static threshold"
        );
        assert!(
            long < short,
            "the longer horizon did not lower the threshold"
        );
        assert!(
            (1.0 / 9.0 - 0.02..=0.25 + 0.02).contains(&ratio),
            "the excesses' ratio {ratio}"
        );
        let miss = (k / k_qs - 1.0).abs();
        assert!(miss < last_miss, "K / K_qs - 1 = {miss} did not shrink");
        last_miss = miss;
    }
}

/// On the ring (no closed form: the number is reported): Fig. 8a's rotor and ring from rest at
/// $(0.9, 0)$, $j = 10$, the DC motor of no-load speed 3 (the drive of docs/run-up.md's
/// table), from $\eta = 0.1$, dense samples every 0.5, passing when the speed
/// exceeds 2.2: above the band where the ring holds the rotor (1.5 to 1.8) and below the
/// speeds of the runs that pass (2.7 to 2.83, in contact all the while: the rest at 0.9 of
/// the gap). Bisected to $10^{-5}$ on the bracket 0.2 (held, as in the table) to 0.3 at the
/// horizons 3000 and 6000: a bottleneck as off the ring makes the longer horizon's threshold
/// lower (by $5\times10^{-5}$; by the $T^{-2}$ law of the test above about a third of that is
/// left at 6000). Asserted: the longer horizon's bracket is not above the shorter one's, and
/// the threshold lies above the off-ring quasi-static one (the ring absorbs power besides the
/// rotor's damping). Contact could make the answer change more than once with the torque; a
/// sweep every $10^{-3}$ from 0.225 to 0.25 (made while writing this test, horizons 3000 and
/// 12000) found one change, between 0.242 and 0.243.
#[test]
fn sommerfeld_threshold_on_the_ring() {
    let (_, qs) = quasi_static_threshold(&Preset::Fig8a.params());
    let side = |stall: f64, t_end: f64| {
        let p = Params {
            eta: 3.0,
            ..Preset::Fig8a.params()
        };
        let motor = MotorTorque::linear(stall, 3.0).unwrap();
        let rotor = DrivenJeffcott::new(p, 10.0, motor).unwrap();
        let model = rotor.on_ring().unwrap();
        let mut y0: SVector<f64, 8> = rotor.state_at([0.9, 0.0], [0.0, 0.0], 0.1);
        model.make_consistent(&mut y0).unwrap();
        let plan = OutputPlan {
            t_end,
            strobe: None,
            dense: Some(DenseSampling {
                t_start: 0.0,
                dt: 0.5,
            }),
            events: true,
        };
        let mut traj = Trajectory::<U8>::default();
        simulate(&model, 0.0, &y0, &plan, &SimOptions::default(), &mut traj).unwrap();
        stuck_or_passes(&traj, 2.2)
    };
    let [short, long] = [3000.0, 6000.0].map(|t_end| {
        let b = threshold(|t0| side(t0, t_end), (0.2, 0.3), 1e-5);
        println!(
            "on the ring, j = 10, horizon {t_end}: threshold in [{:.6}, {:.6}] ({} runs), \
             {:.4} times the off-ring quasi-static {qs:.6}",
            b.near,
            b.far,
            b.evaluations + 2,
            b.midpoint() / qs
        );
        b
    });
    // A run that passes by 3000 passes by 6000: the longer horizon's bracket is not above.
    assert!(long.near <= short.far, "{long:?} above {short:?}");
    let b = long;
    assert!(b.near > qs, "the ring lowered the threshold");
}
