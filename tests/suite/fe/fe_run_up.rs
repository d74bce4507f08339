//! Finite-element rotors at a varying speed ([`ProfiledLinearRotor`], issue 21), on S1's
//! rotor reduced by Craig-Bampton (node 12's x, y kept physical), against truths that do not
//! come from the integrator:
//!
//! * a constant profile at the reference speed is [`LinearRotor`]'s field bit for bit, so the
//!   same integrated run with contact is the same, bit for bit;
//! * a constant profile at another speed is the constant-speed rotor built at that speed (its
//!   $C + \Omega G$ and $m e\Omega^2$), whose free flight is in closed form;
//! * a run-up through the first critical speed without contact against the modal Duhamel
//!   integral: the state matrix's eigen-decomposition ([`eigen_decomposition`], its residual
//!   checked) and, per mode, $z_k(t) = \int_0^t e^{\lambda_k(t - s)}w_k(s)\thinspace ds$ of the
//!   forcing written out here, by the composite Gauss-Legendre rule of
//!   `tests/support/duhamel.rs`.

use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::{Complex, DMatrix, DVector, Dyn};
use jeffcott::numeric::eigen_decomposition;
use jeffcott::ode::Method;
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{
    CraigBampton, LinearRotor, LinearSystem, ProfiledLinearRotor, RingedRotor, RotorMatrices,
    SmoothRotor, SpeedProfile,
};

use super::fe_reduction_s1::reduction;
use super::fe_s1::S1;
use crate::duhamel::gauss_legendre;

/// S1 reduced to `modes` modes: the rotor at S1's speed (exact free flight off), its ring and
/// the reduced gyroscopic matrix.
pub(super) fn reduced(s1: &S1, modes: usize) -> (LinearRotor, SnubberRing, DMatrix<f64>) {
    let (cb, model) = reduction(s1, modes);
    let g = cb.project(s1.lateral().gyroscopic()).unwrap();
    let rotor = model.rotor().clone().with_exact_free_flight(false);
    (rotor, *model.ring(), g)
}

pub(super) fn run<R: SmoothRotor<Dim = Dyn>>(
    model: &RingedRotor<R>,
    y0: &DVector<f64>,
    (t_end, dt): (f64, f64),
    opts: &SimOptions,
) -> Trajectory<Dyn> {
    let plan = OutputPlan {
        t_end,
        strobe: None,
        dense: Some(DenseSampling { t_start: 0.0, dt }),
        events: true,
    };
    let mut traj = Trajectory::default();
    simulate(model, 0.0, y0, &plan, opts, &mut traj).unwrap();
    traj
}

pub(super) fn dop853(rtol: f64) -> SimOptions {
    SimOptions::default()
        .with_method(Method::Dop853)
        .with_rtol(rtol)
        .with_atol(rtol)
}

/// S1 (8 modes) on its ring for 0.2 s (contact from 0.1 s on): a constant profile at S1's
/// speed gives the same samples and events as [`LinearRotor`], bit for bit.
#[test]
fn a_constant_profile_is_the_constant_speed_rotor_bit_for_bit() {
    let s1 = S1::load();
    let (rotor, ring, g) = reduced(&s1, 8);
    let speed = rotor.system().speed();
    let profiled = rotor
        .clone()
        .with_speed_profile(&g, SpeedProfile::constant(speed).unwrap())
        .unwrap()
        .ringed(ring)
        .unwrap();
    let constant = rotor.ringed(ring).unwrap();
    let y0 = constant.rotor().rest_state();
    let span = (0.2, 5e-4);
    let a = run(&constant, &y0, span, &dop853(1e-10));
    let b = run(&profiled, &y0, span, &dop853(1e-10));
    let onsets = a.events.iter().filter(|e| e.to > e.from).count();
    println!(
        "{} samples, {} events ({onsets} onsets)",
        a.samples.len(),
        a.events.len()
    );
    assert!(
        onsets >= 2,
        "the rotor must touch the ring: {onsets} onsets"
    );
    assert_eq!(a.samples.len(), b.samples.len());
    for (p, q) in a.samples.iter().zip(&b.samples) {
        assert!(
            p.t == q.t && p.y == q.y,
            "at t = {}: {} vs {}",
            p.t,
            p.y[0],
            q.y[0]
        );
    }
    let times = |t: &Trajectory<Dyn>| t.events.iter().map(|e| e.t).collect::<Vec<_>>();
    assert_eq!(times(&a), times(&b));
}

/// The same rotor built at `speed` (rad/s) from the full matrices: $C + \Omega G$ and the
/// unbalance $m e\Omega^2$, reduced by the same basis; free flight in closed form.
fn at_speed(s1: &S1, modes: usize, speed: f64) -> LinearRotor {
    let lateral = s1.lateral();
    at_speed_with(s1, modes, speed, (lateral.stiffness(), lateral.damping()))
}

/// [`at_speed`] with the full stiffness and damping `(K, C)` in place of S1's.
pub(super) fn at_speed_with(
    s1: &S1,
    modes: usize,
    speed: f64,
    stiffness_damping: (&DMatrix<f64>, &DMatrix<f64>),
) -> LinearRotor {
    let (cb, model) = reduction(s1, modes);
    let basis = (&cb, model.rotor().ring_offset());
    reduced_at(s1, &s1.lateral(), basis, speed, stiffness_damping)
}

/// The full system of `lateral` at `speed` ($C + \Omega G$, S1's unbalance $m e\Omega^2$)
/// reduced by the basis `cb`, the ring at reduced coordinates 0 and 1 with `offset`.
pub(super) fn reduced_at(
    s1: &S1,
    lateral: &RotorMatrices,
    (cb, offset): (&CraigBampton, [f64; 2]),
    speed: f64,
    (stiffness, damping): (&DMatrix<f64>, &DMatrix<f64>),
) -> LinearRotor {
    // The expression of `LinearSystem::from_matrices`: D = C + G speed.
    let d = damping + lateral.gyroscopic() * speed;
    let mut system =
        LinearSystem::new(lateral.mass().clone(), d, stiffness.clone(), speed).unwrap();
    for u in s1.params["unbalance"].as_array().unwrap() {
        let node = u["node"].as_u64().unwrap() as usize;
        let me = u["magnitude_kg_m"].as_f64().unwrap();
        let phase = u["phase_rad"].as_f64().unwrap();
        system = system
            .with_unbalance(lateral.layout(), node, me, phase)
            .unwrap();
    }
    let reduced = cb.reduce(&system).unwrap();
    LinearRotor::new(reduced, [0, 1], offset).unwrap()
}

/// A constant profile at 1.3 times S1's speed (above the first critical: the gyroscopic
/// correction $(\Omega - \Omega_r)G$ and the force's $\Omega^2$ matter) against the rotor
/// built at that speed, free flight in closed form, on the ring for 0.15 s.
#[test]
fn a_constant_profile_off_the_reference_is_the_rotor_at_that_speed() {
    let (s1, modes) = (S1::load(), 8);
    let (rotor, ring, g) = reduced(&s1, modes);
    let speed = 1.3 * rotor.system().speed();
    let profiled = rotor
        .with_speed_profile(&g, SpeedProfile::constant(speed).unwrap())
        .unwrap()
        .ringed(ring)
        .unwrap();
    let exact = at_speed(&s1, modes, speed).ringed(ring).unwrap();
    agrees_with_the_closed_form(&exact, &profiled, s1.gap);
}

/// Runs `exact` (free flight in closed form) and `other` from rest on the ring for 0.15 s
/// (DOP853 at 1e-12) and checks that they agree: the same events (at least 4) within 1e-8 s,
/// the station's samples within 1e-7 of the `gap`. Returns `exact`'s run.
pub(super) fn agrees_with_the_closed_form<R: SmoothRotor<Dim = Dyn>>(
    exact: &RingedRotor<LinearRotor>,
    other: &RingedRotor<R>,
    gap: f64,
) -> Trajectory<Dyn> {
    let y0 = exact.rotor().rest_state();
    let span = (0.15, 5e-4);
    let a = run(exact, &y0, span, &dop853(1e-12));
    let b = run(other, &y0, span, &dop853(1e-12));
    assert!(a.events.len() >= 4, "{} events", a.events.len());
    assert_eq!(a.events.len(), b.events.len());
    let mut worst = 0.0f64;
    for (p, q) in a.samples.iter().zip(&b.samples) {
        let [x, y] = exact.rotor().station_displacement(&p.y);
        let [u, v] = exact.rotor().station_displacement(&q.y);
        worst = worst.max((x - u).hypot(y - v) / gap);
    }
    let dt = a
        .events
        .iter()
        .zip(&b.events)
        .fold(0.0f64, |m, (e, f)| m.max((e.t - f.t).abs()));
    println!(
        "{} events; samples within {worst:.2e} of the gap, events within {dt:.1e} s",
        a.events.len()
    );
    assert!(worst < 1e-7, "{worst:e} of the gap");
    assert!(dt < 1e-8, "{dt:e} s");
    a
}

/// The out-of-balance per unit squared speed's forcing
/// $\operatorname{Re}(\hat U(\Omega^2 - i\Omega^\prime)e^{i\Phi})$ on the ramp
/// $\Omega = \Omega_0 + R s$, $\Phi = \Omega_0 s + R s^2/2$, written from the formula as its
/// two real weights $(\Omega^2\cos\Phi + \Omega^\prime\sin\Phi, \Omega^2\sin\Phi -
/// \Omega^\prime\cos\Phi)$ of $\operatorname{Re}\hat U$ and $-\operatorname{Im}\hat U$.
fn ramp_weights(w0: f64, rate: f64, s: f64, tangential: bool) -> [f64; 2] {
    let w = w0 + rate * s;
    let (sin, cos) = (w0 * s + 0.5 * rate * s * s).sin_cos();
    let r = if tangential { rate } else { 0.0 };
    [w * w * cos + r * sin, w * w * sin - r * cos]
}

/// The station's x and y at `t` by the modal Duhamel integral of the rotor `system` (rest at
/// 0) on the ramp, `per_unit` Gauss-Legendre panels per unit of $|\lambda_k| t$.
struct Modal {
    values: Vec<Complex<f64>>,
    /// The station rows of $DV$ (x, y) and $V^{-1}D^{-1}$ applied to $(0, M^{-1}\hat U)$'s
    /// real and $-$imaginary parts.
    rows: [Vec<Complex<f64>>; 2],
    inputs: [Vec<Complex<f64>>; 2],
}

impl Modal {
    fn new(system: &LinearSystem) -> Self {
        let n = system.dofs();
        let minv = system.mass().clone().try_inverse().unwrap();
        let mut a = DMatrix::zeros(2 * n, 2 * n);
        a.view_mut((0, n), (n, n)).fill_diagonal(1.0);
        a.view_mut((n, 0), (n, n))
            .copy_from(&(-&minv * system.stiffness()));
        a.view_mut((n, n), (n, n))
            .copy_from(&(-&minv * system.damping()));
        let e = eigen_decomposition(&a).unwrap();
        assert!(e.residual < 1e-13, "eigenpairs' residual {:e}", e.residual);
        let w2 = system.speed() * system.speed();
        let u = system.harmonic_force().map(|z| z / w2);
        let input = |part: DVector<f64>| {
            let mut g = DVector::zeros(2 * n);
            g.rows_mut(n, n).copy_from(&(&minv * part));
            let g = g.component_div(&e.scale).map(|v| Complex::new(v, 0.0));
            (&e.inverse * g).iter().copied().collect::<Vec<_>>()
        };
        let row = |i: usize| (0..2 * n).map(|k| e.vectors[(i, k)] * e.scale[i]).collect();
        Self {
            values: e.values.iter().copied().collect(),
            rows: [row(0), row(1)],
            inputs: [input(u.map(|z| z.re)), input(u.map(|z| -z.im))],
        }
    }

    fn station(&self, t: f64, (w0, rate, tangential): (f64, f64, bool), per_unit: f64) -> [f64; 2] {
        let mut out = [0.0; 2];
        for (k, &l) in self.values.iter().enumerate() {
            // Older forcing is forgotten below e^-40 (a strongly damped high mode).
            let start = if l.re < 0.0 {
                (t + 40.0 / l.re).max(0.0)
            } else {
                0.0
            };
            let width = t - start;
            let panels = ((width * l.norm().max(w0 + rate * t)) * per_unit)
                .ceil()
                .max(8.0) as usize;
            let mut z = Complex::new(0.0, 0.0);
            for (c, input) in self.inputs.iter().enumerate() {
                let part = |im: bool| {
                    let f = |s: f64| {
                        let e = (l * (t - s)).exp();
                        let w = ramp_weights(w0, rate, s, tangential)[c];
                        if im {
                            e.im * w
                        } else {
                            e.re * w
                        }
                    };
                    gauss_legendre(f, start, t, panels)
                };
                z += input[k] * Complex::new(part(false), part(true));
            }
            for (i, o) in out.iter_mut().enumerate() {
                *o += (self.rows[i][k] * z).re;
            }
        }
        out
    }
}

/// S1 reduced to 4 modes, without the ring, run up from 100 to 260 rad/s at 400 rad/s² (0.4
/// s, through the first critical near 182 rad/s) from rest, $G$ given as zero (the damping
/// then stays $C + \Omega_r G$: constant coefficients, for Duhamel), `rtol` $10^{-12}$: within
/// $10^{-9}$ of the peak at the samples around it; the same integral without the
/// $\Omega^\prime$ terms is told apart.
#[test]
fn a_fe_run_up_without_contact_matches_the_modal_duhamel_integral() {
    let s1 = S1::load();
    let (rotor, ring, g) = reduced(&s1, 4);
    let (w0, w1, rate) = (100.0, 260.0, 400.0);
    let far = SnubberRing::from_units(ring.x.stiffness, 2.0 * ring.damping, [0.0; 2], 1.0);
    let system = rotor.system().clone();
    let model = rotor
        .with_speed_profile(&(g * 0.0), SpeedProfile::ramp(w0, w1, rate).unwrap())
        .unwrap()
        .ringed(far.unwrap())
        .unwrap();
    let y0 = model.rotor().rotor().rest_state();
    let traj = run(&model, &y0, ((w1 - w0) / rate, 2e-3), &dop853(1e-12));
    assert!(traj.events.is_empty(), "the ring is out of reach");
    let radius = |i: usize| traj.samples[i].y[0].hypot(traj.samples[i].y[1]);
    let peak = (0..traj.samples.len())
        .max_by(|&a, &b| radius(a).total_cmp(&radius(b)))
        .unwrap();
    let amplitude = radius(peak);
    let modal = Modal::new(&system);
    let (mut worst, mut quadrature, mut without) = (0.0f64, 0.0f64, 0.0f64);
    for i in [peak / 2, peak - 10, peak, peak + 10, traj.samples.len() - 1] {
        let s = &traj.samples[i];
        let truth = modal.station(s.t, (w0, rate, true), 2.0);
        let finer = modal.station(s.t, (w0, rate, true), 4.0);
        let radial = modal.station(s.t, (w0, rate, false), 1.0);
        for c in 0..2 {
            quadrature = quadrature.max((truth[c] - finer[c]).abs());
            worst = worst.max((s.y[c] - finer[c]).abs());
            without = without.max((s.y[c] - radial[c]).abs());
        }
    }
    println!(
        "peak {amplitude:.6e} m at t = {:.4} s (speed {:.2} rad/s); simulation within \
         {:.2e} of the peak, quadrature's halving {:.1e}; without the tangential terms {:.2e}",
        traj.samples[peak].t,
        w0 + rate * traj.samples[peak].t,
        worst / amplitude,
        quadrature / amplitude,
        without / amplitude
    );
    assert!(quadrature < 1e-11 * amplitude, "quadrature {quadrature:e}");
    assert!(
        worst < 1e-9 * amplitude,
        "{:e} of the peak",
        worst / amplitude
    );
    assert!(
        without > 1e-6 * amplitude,
        "the check must see the tangential terms"
    );
}

/// [`ProfiledLinearRotor`] keeps the strobes on the phases: output `k` where
/// $\Omega_0 t + R t^2/2 = 2\pi k/S$.
#[test]
fn fe_strobes_fall_on_the_phases() {
    let s1 = S1::load();
    let (rotor, ring, g) = reduced(&s1, 4);
    let (w0, rate, samples) = (100.0, 400.0, 8u32);
    let model: RingedRotor<ProfiledLinearRotor> = rotor
        .with_speed_profile(&g, SpeedProfile::ramp(w0, 140.0, rate).unwrap())
        .unwrap()
        .with_strobes_per_revolution(samples)
        .unwrap()
        .ringed(ring)
        .unwrap();
    for k in [1u64, 7, 15] {
        let t = jeffcott::hybrid::RotorModel::strobe_time(&model, k);
        let phase = w0 * t + 0.5 * rate * t * t;
        let want = std::f64::consts::TAU * k as f64 / f64::from(samples);
        assert!((phase - want).abs() < 1e-12 * want, "{phase} vs {want}");
    }
}

/// A unit mass on a unit spring (no damping, no out-of-balance) as a [`LinearSystem`] on a
/// ramp, the ring's centre 0.5 from the node's rest, started on the circle of radius
/// $a = 0.5 + d$ about the rest: the largest distance from the ring's centre is $1 + d$ at
/// $t = \pi$ (gap 1). The number of events of the run to $2\pi$ (`rtol` $10^{-12}$).
fn fe_touch_run(depth: f64) -> usize {
    let eye = DMatrix::<f64>::identity(2, 2);
    let system = LinearSystem::new(eye.clone(), eye.clone() * 0.0, eye.clone(), 2.0).unwrap();
    let ring = SnubberRing::from_units(30.0, 0.004, [0.0; 2], 1.0).unwrap();
    let profile = SpeedProfile::ramp(1.0, 3.0, 0.5).unwrap();
    let model = LinearRotor::new(system, [0, 1], [-0.5, 0.0])
        .unwrap()
        .with_speed_profile(&(eye * 0.0), profile)
        .unwrap()
        .ringed(ring)
        .unwrap();
    let a = 0.5 + depth;
    let y0 = DVector::from_vec(vec![-a, 0.0, 0.0, -a, 0.0, 0.0]);
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-13);
    let plan = OutputPlan {
        t_end: std::f64::consts::TAU,
        strobe: None,
        dense: None,
        events: true,
    };
    let mut traj = Trajectory::<Dyn>::default();
    simulate(&model, 0.0, &y0, &plan, &opts, &mut traj).unwrap();
    for e in &traj.events {
        assert!(
            (e.t - std::f64::consts::PI).abs() < 1e-3,
            "event at {}",
            e.t
        );
    }
    traj.events.len()
}

/// The onset guarantee of integrated free flight, measured for [`ProfiledLinearRotor`] as
/// `tests/suite/simulation/run_up.rs` measures it for the paper's model: a touch $10^{-9}$ of the
/// gap deep is found, a miss by $10^{-9}$ is not taken for a touch; the depths found down to
/// $10^{-13}$ are printed.
#[test]
fn a_fe_touch_of_a_billionth_of_the_gap_is_found_in_integrated_free_flight() {
    assert!(fe_touch_run(1e-9) > 0, "a touch 1e-9 deep was missed");
    assert_eq!(
        fe_touch_run(-1e-9),
        0,
        "a miss by 1e-9 was taken for a touch"
    );
    let found: Vec<_> = (9..=13)
        .map(|e| (e, fe_touch_run(10f64.powi(-e)) > 0))
        .collect();
    println!("touch depth 1e-N found (rtol 1e-12): {found:?}");
}
