//! The energy balance of runs with friction at the ring, computed here from the samples alone
//! (the rotor's and the ring's positions and velocities, the ring's force law written out):
//!
//! $$W_\text{in} = \Delta(E_\text{kin} + E_\text{rotor} + E_\text{ring})
//!   + D_\text{rotor} + D_\text{ring} + D_\text{slip},$$
//!
//! with the rotor's dissipation $\int 2\nu_1|r^\prime|^2$, the ring dampers'
//! $\int s^\prime\cdot Cs^\prime$ and the slip's $\int (t\cdot f)v$: the rotor's equation of
//! motion dotted with $r^\prime$, and $f\cdot r^\prime = f\cdot s^\prime +
//! (t\cdot f)\gamma\theta^\prime$ with $\gamma\theta^\prime = v - \eta a$. At constant speed the
//! work put in is the out-of-balance's $\int F\cdot r^\prime$ and the drive's
//! $\int (t\cdot f)\eta a$ (it holds the speed against the rub torque $-a\thinspace t\cdot f$);
//! on a non-ideal drive it is the motor's $\int t(\eta)\eta$ alone, the spin's and the
//! out-of-balance's kinetic energy $\tfrac12 j\eta^2 + \beta\eta\thinspace r^\prime\cdot
//! t_\varphi$ joining $E_\text{kin}$ (`tests/suite/simulation/drive_energy.rs`), so the rub
//! torque is checked by its work on the spin. Each smooth piece of a run (between two events)
//! is integrated by local polynomials through its samples, so the ring's jumps of velocity at
//! the events do not enter a quadrature.

use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, RotorModel, SimOptions, Trajectory};
use jeffcott::nalgebra::allocator::Allocator;
use jeffcott::nalgebra::{DVector, DefaultAllocator, OVector, Vector2};
use jeffcott::paper::rub::rubbing_model;
use jeffcott::params::Params;
use jeffcott::rotor::{DrivenJeffcott, MotorTorque, RubbingRotor};

/// The integral over `[a, b]` of the polynomial through `(x_i, y_i)` (Lagrange weights from
/// the moments, the nodes centred and scaled for conditioning).
fn integrate_interpolant(x: &[f64], y: &[f64], a: f64, b: f64) -> f64 {
    let n = x.len();
    let (c, h) = (
        0.5 * (x[0] + x[n - 1]),
        (0.5 * (x[n - 1] - x[0])).max(f64::MIN_POSITIVE),
    );
    let u: Vec<f64> = x.iter().map(|&xi| (xi - c) / h).collect();
    let (ua, ub) = ((a - c) / h, (b - c) / h);
    // Vandermonde V[k][i] = u_i^k, moments m_k = (ub^{k+1} - ua^{k+1})/(k+1); solve V w = m.
    let mut v: Vec<Vec<f64>> = (0..n)
        .map(|k| u.iter().map(|&ui| ui.powi(k as i32)).collect())
        .collect();
    let mut m: Vec<f64> = (0..n)
        .map(|k| (ub.powi(k as i32 + 1) - ua.powi(k as i32 + 1)) / (k as f64 + 1.0))
        .collect();
    for col in 0..n {
        let pivot = (col..n)
            .max_by(|&i, &j| v[i][col].abs().total_cmp(&v[j][col].abs()))
            .unwrap();
        v.swap(col, pivot);
        m.swap(col, pivot);
        for row in col + 1..n {
            let f = v[row][col] / v[col][col];
            for k in col..n {
                v[row][k] -= f * v[col][k];
            }
            m[row] -= f * m[col];
        }
    }
    let mut w = vec![0.0; n];
    for row in (0..n).rev() {
        let s: f64 = (row + 1..n).map(|k| v[row][k] * w[k]).sum();
        w[row] = (m[row] - s) / v[row][row];
    }
    h * w.iter().zip(y).map(|(wi, yi)| wi * yi).sum::<f64>()
}

/// The integral of the samples' values `y` at times `x` over `[a, b]` (one smooth piece, the
/// samples inside it): each gap between nodes (and the ends, up to `a` and `b`) by the
/// polynomial through the 7 nearest samples (all of them when fewer).
fn integrate_piece(x: &[f64], y: &[f64], a: f64, b: f64) -> f64 {
    let n = x.len();
    assert!(n >= 2, "a smooth piece with {n} samples in [{a}, {b}]");
    let window = 7.min(n);
    let mut bounds = vec![a];
    bounds.extend_from_slice(x);
    bounds.push(b);
    let mut total = 0.0;
    for (k, gap) in bounds.windows(2).enumerate() {
        // Gap k lies between node k - 1 and node k: centre the window there.
        let first = (k as isize - (window as isize) / 2).clamp(0, (n - window) as isize) as usize;
        let idx = first..first + window;
        total += integrate_interpolant(&x[idx.clone()], &y[idx], gap[0], gap[1]);
    }
    total
}

/// The ring's elastic energy of one axis: $Ks^2$ inside the preload, $\tfrac12K(|s| + D)^2 -
/// KD^2$ beyond (continuous at $|s| = D$); its force $g$ and damping coefficient.
fn axis(k: f64, d: f64, nu2: f64, s: f64) -> (f64, f64, f64) {
    if s.abs() <= d {
        (k * s * s, 2.0 * k * s, 4.0 * nu2)
    } else {
        let a = s.abs() + d;
        (
            0.5 * k * a * a - k * d * d,
            k * (s + d.copysign(s)),
            2.0 * nu2,
        )
    }
}

/// The energy terms at a sample, the ring's energy left out: the energy, the power in, the
/// power out (the dissipations), the slip's dissipation alone and the rub torque's power
/// $-a\eta\thinspace t\cdot f$ on the spin; in free flight without the ring's dampers
/// (`contact` false: see [`balance`]).
type Terms<'a> = dyn Fn(f64, &[f64], &[f64], bool) -> [f64; 5] + 'a;

/// The ring's part of the terms at a sample in contact, the speed `eta` and the shaft radius
/// `a`: its dampers' power, $t\cdot f$ and the slip velocity $v$.
fn ring_terms(p: &Params, a: f64, eta: f64, y: &[f64], dy: &[f64]) -> (f64, f64, f64) {
    let (r, v) = (Vector2::new(y[0], y[1]), Vector2::new(y[2], y[3]));
    let (s, s_dot) = (Vector2::new(y[4], y[5]), Vector2::new(dy[4], dy[5]));
    let (_, gx, cx) = axis(p.kx, p.dx, p.nu2, s.x);
    let (_, gy, cy) = axis(p.ky, p.dy, p.nu2, s.y);
    let ring_loss = cx * s_dot.x * s_dot.x + cy * s_dot.y * s_dot.y;
    let f = Vector2::new(gx + cx * s_dot.x, gy + cy * s_dot.y);
    let n = r - s;
    let tangent = Vector2::new(-n.y, n.x);
    let v_slip = (v - s_dot).dot(&tangent) + eta * a;
    (ring_loss, tangent.dot(&f), v_slip)
}

/// The terms of the paper's rotor at constant speed (`p.eta`).
fn constant_speed(p: &Params, a: f64, t: f64, y: &[f64], dy: &[f64], contact: bool) -> [f64; 5] {
    let (r, v) = (Vector2::new(y[0], y[1]), Vector2::new(y[2], y[3]));
    let e = Vector2::new(p.ex, p.ey);
    let energy = 0.5 * v.norm_squared() + 0.5 * (r - e).norm_squared();
    let phase = p.phi0 + p.eta * t;
    let unbalance = Vector2::new(phase.cos(), phase.sin()) * (p.beta * p.eta * p.eta);
    let (mut ring_loss, mut friction, mut v_slip) = (0.0, 0.0, 0.0);
    if contact {
        (ring_loss, friction, v_slip) = ring_terms(p, a, p.eta, y, dy);
    }
    let torque = -friction * p.eta * a;
    // The drive holds the speed: its power is minus the rub torque's.
    let power_in = unbalance.dot(&v) - torque;
    let power_out = 2.0 * p.nu1 * v.norm_squared() + ring_loss + friction * v_slip;
    [energy, power_in, power_out, friction * v_slip, torque]
}

/// The terms of the paper's rotor on a non-ideal drive (state `[r, r', s, eta, phi]`) with
/// the polar inertia `j` and the DC motor `stall` $(1 - \eta/$`no_load`$)$.
fn driven(p: &Params, a: f64, drive: [f64; 3], y: &[f64], dy: &[f64], contact: bool) -> [f64; 5] {
    let [j, stall, no_load] = drive;
    let (r, v) = (Vector2::new(y[0], y[1]), Vector2::new(y[2], y[3]));
    let (eta, phi) = (y[6], y[7]);
    let e = Vector2::new(p.ex, p.ey);
    let spin_tangent = Vector2::new(-phi.sin(), phi.cos());
    let energy = 0.5 * v.norm_squared()
        + 0.5 * j * eta * eta
        + p.beta * eta * v.dot(&spin_tangent)
        + 0.5 * (r - e).norm_squared();
    let (mut ring_loss, mut friction, mut v_slip) = (0.0, 0.0, 0.0);
    if contact {
        (ring_loss, friction, v_slip) = ring_terms(p, a, eta, y, dy);
    }
    let power_in = stall * (1.0 - eta / no_load) * eta;
    let power_out = 2.0 * p.nu1 * v.norm_squared() + ring_loss + friction * v_slip;
    [
        energy,
        power_in,
        power_out,
        friction * v_slip,
        -friction * eta * a,
    ]
}

/// The ring's elastic energy at the ring position held in `y`.
fn ring_energy(p: &Params, y: &[f64]) -> f64 {
    axis(p.kx, p.dx, p.nu2, y[4]).0 + axis(p.ky, p.dy, p.nu2, y[5]).0
}

/// The Fig. 8 rotor on an anisotropic ring, preloaded or not, with friction (the scenes of
/// `ring::rub_drive` and `stability::stability_friction` too).
pub(crate) fn scene(eta: f64, preload: [f64; 2]) -> Params {
    Params {
        eta,
        nu1: 0.125,
        nu2: 0.002,
        kx: 30.0,
        ky: 20.0,
        beta: 0.119,
        dx: preload[0],
        dy: preload[1],
        ex: 0.9,
        ey: 0.1,
        phi0: 0.0,
    }
}

/// A run's samples and events as plain vectors: (t, label, y, dy) and (t, before, after).
#[derive(Default)]
struct Run {
    samples: Vec<(f64, u8, Vec<f64>, Vec<f64>)>,
    events: Vec<(f64, Vec<f64>, Vec<f64>)>,
    kinds: std::collections::BTreeSet<&'static str>,
}

/// `model` from `y0` sampled every `dt` from `from` up to `to`, at tight tolerances.
fn sampled<M: RotorModel>(model: &M, y0: &OVector<f64, M::Dim>, from: f64, dt: f64, to: f64) -> Run
where
    DefaultAllocator: Allocator<M::Dim>,
{
    let plan = OutputPlan {
        t_end: to,
        strobe: None,
        dense: Some(DenseSampling { t_start: from, dt }),
        events: true,
    };
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-13);
    let mut traj: Trajectory<M::Dim> = Trajectory::default();
    simulate(model, 0.0, y0, &plan, &opts, &mut traj).unwrap();
    let vec = |v: &OVector<f64, M::Dim>| v.iter().copied().collect::<Vec<f64>>();
    Run {
        samples: traj
            .samples
            .iter()
            .map(|s| (s.t, s.label, vec(&s.y), vec(&s.dy)))
            .collect(),
        events: traj
            .events
            .iter()
            .map(|e| (e.t, vec(&e.before), vec(&e.after)))
            .collect(),
        kinds: traj.events.iter().map(|e| e.kind).collect(),
    }
}

/// The balance of a run of `periods` forcing periods from `y0`: (work in, energy change,
/// dissipation, the slip's dissipation, the rub torque's work on the spin).
fn balance<M: RotorModel>(
    model: &M,
    y0: &OVector<f64, M::Dim>,
    periods: f64,
    p: &Params,
    terms: &Terms<'_>,
) -> ([f64; 5], Run)
where
    DefaultAllocator: Allocator<M::Dim>,
{
    let period = std::f64::consts::TAU / p.eta;
    let run = sampled(model, y0, 0.0, period / 2048.0, periods * period);
    let start: Vec<f64> = y0.iter().copied().collect();
    // The smooth pieces: from the start or an event's state after it to the next event's
    // state before it (or the end).
    let mut ends = vec![(0.0, start.as_slice())];
    for (t, before, after) in &run.events {
        ends.push((*t, before.as_slice()));
        ends.push((*t, after.as_slice()));
    }
    let last = run.samples.last().unwrap();
    ends.push((last.0, last.2.as_slice()));
    let (mut work, mut loss, mut slip_loss, mut torque_work) = (0.0, 0.0, 0.0, 0.0);
    for piece in ends.chunks(2) {
        let [(a_t, a_y), (b_t, b_y)] = [piece[0], piece[1]];
        let within = |r: &Run| -> Vec<_> {
            let inside = r.samples.iter().filter(|s| s.0 > a_t && s.0 < b_t);
            inside.cloned().collect()
        };
        let mut inside = within(&run);
        if inside.len() < 7 {
            // A short piece: the same run, sampled 16 times across it.
            let dt = (b_t - a_t) / 16.0;
            inside = within(&sampled(model, y0, a_t + 0.5 * dt, dt, b_t));
        }
        let contact = inside[0].1 >= 2;
        let times: Vec<f64> = inside.iter().map(|s| s.0).collect();
        let values: Vec<[f64; 5]> = inside
            .iter()
            .map(|s| terms(s.0, &s.2, &s.3, contact))
            .collect();
        let integral = |k: usize| {
            let y: Vec<f64> = values.iter().map(|v| v[k]).collect();
            integrate_piece(&times, &y, a_t, b_t)
        };
        work += integral(1);
        loss += integral(2);
        slip_loss += integral(3);
        torque_work += integral(4);
        if !contact {
            // The released ring relaxes on its own: its energy goes into its dampers.
            loss += ring_energy(p, a_y) - ring_energy(p, b_y);
        }
    }
    let energy = |y: &[f64]| terms(0.0, y, y, false)[0] + ring_energy(p, y);
    let change = energy(&last.2) - energy(&start);
    ([work, change, loss, slip_loss, torque_work], run)
}

/// Along runs with onsets, losses, slip in both senses, rolling and preload crossings, the work
/// put in equals the change of energy and the dissipation to 1e-9 of the work.
#[test]
fn the_work_of_the_unbalance_and_the_drive_is_the_energy_and_the_dissipation() {
    for (mu, a, p) in [
        (0.3, 0.05, scene(2.5, [0.0, 0.0])),
        (0.5, 0.2, scene(3.0, [0.05, 0.02])),
        (0.3, 0.05, scene(2.5, [0.05, 0.02])),
    ] {
        let model = rubbing_model(&p, mu, a).unwrap();
        let terms =
            |t: f64, y: &[f64], dy: &[f64], contact: bool| constant_speed(&p, a, t, y, dy, contact);
        let ([work, change, loss, slip_loss, _], run) =
            balance(&model, &DVector::zeros(6), 20.0, &p, &terms);
        let residual = work - change - loss;
        println!(
            "mu {mu}, a {a}, D ({}, {}): work {work:.6}, energy change {change:.6}, dissipated {loss:.6} (slip {slip_loss:.6}); residual {:.1e} of the work; events {:?}",
            p.dx, p.dy, residual / work, run.kinds
        );
        assert!(slip_loss > 0.0);
        assert!(residual.abs() <= 1e-9 * work, "{residual} of {work}");
    }
}

/// On a non-ideal drive the motor's work alone goes in: the rub torque brakes the spin, whose
/// kinetic energy is in the balance (a drive that ignored the torque would be off by the
/// torque's work, checked to be far above the tolerance).
#[test]
fn on_a_non_ideal_drive_the_motors_work_is_the_energy_and_the_dissipation() {
    // (mu, a, scene, [j, stall, no-load speed]).
    for (mu, a, p, drive) in [
        (0.3, 0.5, scene(2.5, [0.0, 0.0]), [2.0, 3.0, 2.7]),
        (0.5, 0.2, scene(3.0, [0.05, 0.02]), [1.0, 2.0, 3.2]),
        (0.3, 0.05, scene(2.5, [0.0, 0.0]), [1.0, 2.0, 2.7]),
    ] {
        let [j, stall, no_load] = drive;
        let motor = MotorTorque::linear(stall, no_load).unwrap();
        let rotor = DrivenJeffcott::new(p, j, motor).unwrap();
        let model = RubbingRotor::new(rotor.on_ring().unwrap(), mu, a).unwrap();
        let y0 = rotor.state_at([0.0, 0.0], [0.0, 0.0], p.eta);
        let terms =
            |_t: f64, y: &[f64], dy: &[f64], contact: bool| driven(&p, a, drive, y, dy, contact);
        let ([work, change, loss, slip_loss, torque_work], run) =
            balance(&model, &y0, 20.0, &p, &terms);
        let residual = work - change - loss;
        let speeds = run.samples.iter().map(|s| s.2[6]);
        let (lo, hi) = speeds.fold((f64::INFINITY, 0.0f64), |(l, h), e| (l.min(e), h.max(e)));
        println!(
            "mu {mu}, a {a}, D ({}, {}), j {j}: motor's work {work:.6}, energy change {change:.6}, dissipated {loss:.6} (slip {slip_loss:.6}), rub torque's work {torque_work:.3e}; speed {lo:.4}..{hi:.4}; residual {:.1e} of the work; events {:?}",
            p.dx, p.dy, residual / work, run.kinds
        );
        assert!(slip_loss > 0.0);
        assert!(
            torque_work.abs() > 1e-4 * work,
            "the rub torque does too little work to check: {torque_work}"
        );
        assert!(residual.abs() <= 1e-9 * work, "{residual} of {work}");
    }
}
