//! The energy balance of runs with friction at the ring, computed here from the samples alone
//! (the rotor's and the ring's positions and velocities, the ring's force law written out):
//!
//! $$W_\text{unbalance} + W_\text{drive} = \Delta(E_\text{kin} + E_\text{rotor} + E_\text{ring})
//!   + D_\text{rotor} + D_\text{ring} + D_\text{slip},$$
//!
//! with the out-of-balance's work $\int F\cdot r^\prime$, the drive's $\int (t\cdot f)\eta a$ (the
//! rub torque's work at constant speed), the rotor's dissipation $\int 2\nu_1|r^\prime|^2$, the
//! ring dampers' $\int s^\prime\cdot Cs^\prime$ and the slip's $\int (t\cdot f)v$: the rotor's
//! equation of motion dotted with $r^\prime$, and $f\cdot r^\prime = f\cdot s^\prime +
//! (t\cdot f)\gamma\theta^\prime$ with $\gamma\theta^\prime = v - \eta a$. Each smooth piece of
//! a run (between two events) is integrated by local polynomials through its samples, so the
//! ring's jumps of velocity at the events do not enter a quadrature.

use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::{DVector, Dyn, Vector2};
use jeffcott::paper::rub::rubbing_model;
use jeffcott::params::Params;

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

/// The energy terms at a sample: the energy, the power in (the out-of-balance's and the
/// drive's), the power out (the dissipations) and the slip's dissipation alone; in free flight
/// without the ring's energy and dampers (`contact` false: see the test).
fn terms(
    p: &Params,
    a: f64,
    t: f64,
    y: &DVector<f64>,
    dy: &DVector<f64>,
    contact: bool,
) -> [f64; 4] {
    let (r, v) = (Vector2::new(y[0], y[1]), Vector2::new(y[2], y[3]));
    let (s, s_dot) = (Vector2::new(y[4], y[5]), Vector2::new(dy[4], dy[5]));
    let (ex, gx, cx) = axis(p.kx, p.dx, p.nu2, s.x);
    let (ey, gy, cy) = axis(p.ky, p.dy, p.nu2, s.y);
    let e = Vector2::new(p.ex, p.ey);
    let ring = if contact { ex + ey } else { 0.0 };
    let energy = 0.5 * v.norm_squared() + 0.5 * (r - e).norm_squared() + ring;
    let phase = p.phi0 + p.eta * t;
    let unbalance = Vector2::new(phase.cos(), phase.sin()) * (p.beta * p.eta * p.eta);
    let (mut drive, mut slip, mut ring_loss) = (0.0, 0.0, 0.0);
    if contact {
        ring_loss = cx * s_dot.x * s_dot.x + cy * s_dot.y * s_dot.y;
        let f = Vector2::new(gx + cx * s_dot.x, gy + cy * s_dot.y);
        let n = r - s;
        let tangent = Vector2::new(-n.y, n.x);
        let surface = p.eta * a;
        let v_slip = (v - s_dot).dot(&tangent) + surface;
        drive = tangent.dot(&f) * surface;
        slip = tangent.dot(&f) * v_slip;
    }
    let power_in = unbalance.dot(&v) + drive;
    let power_out = 2.0 * p.nu1 * v.norm_squared() + ring_loss + slip;
    [energy, power_in, power_out, slip]
}

/// The ring's elastic energy at the ring position held in `y`.
fn ring_energy(p: &Params, y: &DVector<f64>) -> f64 {
    axis(p.kx, p.dx, p.nu2, y[4]).0 + axis(p.ky, p.dy, p.nu2, y[5]).0
}

/// The Fig. 8 rotor on an anisotropic ring, preloaded or not, with friction.
fn scene(eta: f64, preload: [f64; 2]) -> Params {
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
        let period = std::f64::consts::TAU / p.eta;
        // The run sampled every `dt` from `from` up to `to`.
        let sampled = |from: f64, dt: f64, to: f64| {
            let plan = OutputPlan {
                t_end: to,
                strobe: None,
                dense: Some(DenseSampling { t_start: from, dt }),
                events: true,
            };
            let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-13);
            let mut traj: Trajectory<Dyn> = Trajectory::default();
            simulate(&model, 0.0, &DVector::zeros(6), &plan, &opts, &mut traj).unwrap();
            traj
        };
        let traj = sampled(0.0, period / 2048.0, 20.0 * period);
        // The smooth pieces: from the start or an event's state after it to the next event's
        // state before it (or the end).
        let y0 = DVector::zeros(6);
        let mut ends = vec![(0.0, &y0)];
        for e in &traj.events {
            ends.push((e.t, &e.before));
            ends.push((e.t, &e.after));
        }
        let last = traj.samples.last().unwrap();
        ends.push((last.t, &last.y));
        let (mut work, mut loss, mut slip_loss) = (0.0, 0.0, 0.0);
        for piece in ends.chunks(2) {
            let [(a_t, a_y), (b_t, b_y)] = [piece[0], piece[1]];
            let within = |t: &Trajectory<Dyn>| -> Vec<_> {
                let inside = t.samples.iter().filter(|s| s.t > a_t && s.t < b_t);
                inside.cloned().collect()
            };
            let mut inside = within(&traj);
            if inside.len() < 7 {
                // A short piece: the same run, sampled 16 times across it.
                let dt = (b_t - a_t) / 16.0;
                inside = within(&sampled(a_t + 0.5 * dt, dt, b_t));
            }
            let contact = inside[0].label >= 2;
            let times: Vec<f64> = inside.iter().map(|s| s.t).collect();
            let values: Vec<[f64; 4]> = inside
                .iter()
                .map(|s| terms(&p, a, s.t, &s.y, &s.dy, contact))
                .collect();
            let integral = |k: usize| {
                let y: Vec<f64> = values.iter().map(|v| v[k]).collect();
                integrate_piece(&times, &y, a_t, b_t)
            };
            work += integral(1);
            loss += integral(2);
            slip_loss += integral(3);
            if !contact {
                // The released ring relaxes on its own: its energy goes into its dampers.
                loss += ring_energy(&p, a_y) - ring_energy(&p, b_y);
            }
        }
        let z = DVector::zeros(6);
        let energy = |y: &DVector<f64>| terms(&p, a, 0.0, y, &z, false)[0] + ring_energy(&p, y);
        let change = energy(&last.y) - energy(&y0);
        let residual = work - change - loss;
        let mut kinds = std::collections::BTreeSet::new();
        kinds.extend(traj.events.iter().map(|e| e.kind));
        println!(
            "mu {mu}, a {a}, D ({}, {}): work {work:.6}, energy change {change:.6}, dissipated {loss:.6} (slip {slip_loss:.6}); residual {:.1e} of the work; events {kinds:?}",
            p.dx, p.dy, residual / work
        );
        assert!(slip_loss > 0.0);
        assert!(residual.abs() <= 1e-9 * work, "{residual} of {work}");
    }
}
