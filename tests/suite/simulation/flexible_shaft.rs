//! `examples/flexible_shaft`: a pinned-pinned Euler-Bernoulli shaft in `n` bending modes on the
//! crate's ring. Checked against what does not use its code: the beam's static influence
//! coefficients, the closed-form harmonic response of the linear shaft (no contact), the
//! paper's model (one mode at midspan), an energy balance with contact, and its own
//! convergence with the tolerance.

use crate::shaft;
use crate::support as examples;

use std::f64::consts::PI;
use std::process::Command;

use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, RotorModel, SimOptions, Trajectory};
use jeffcott::nalgebra::allocator::Allocator;
use jeffcott::nalgebra::{DVector, DefaultAllocator, Dim, OVector, SVector, Vector2};
use jeffcott::params::{Params, Preset};
use jeffcott::JeffcottModel;
use shaft::Layout;

/// Four modes at four stations (the two views equivalent), the example's default.
const FOUR: Layout = Layout {
    modes: 4,
    stations: 4,
    unbalance: 2,
    ring: 3,
};

/// Six modes at five stations (more modes than stations).
const SIX: Layout = Layout {
    modes: 6,
    stations: 5,
    unbalance: 2,
    ring: 4,
};

fn opts(rtol: f64) -> SimOptions {
    SimOptions::default().with_rtol(rtol).with_atol(rtol * 1e-2)
}

/// Strobes `first..=last` and the event log of a run from `y0`.
fn run<M: RotorModel>(
    model: &M,
    y0: &OVector<f64, M::Dim>,
    first: u64,
    last: u64,
    opts: &SimOptions,
) -> Trajectory<M::Dim>
where
    DefaultAllocator: Allocator<M::Dim>,
{
    let plan = OutputPlan {
        events: true,
        ..OutputPlan::strobe(model.forcing_period(), first, last)
    };
    let mut traj = Trajectory::default();
    simulate(model, 0.0, y0, &plan, opts, &mut traj).expect("run");
    traj
}

fn contacts<D: Dim>(t: &Trajectory<D>) -> usize
where
    DefaultAllocator: Allocator<D>,
{
    t.events
        .iter()
        .filter(|e| e.kind == "contact onset")
        .count()
}

/// A complex number as `(re, im)`; the few operations the harmonic solution needs.
type C = (f64, f64);
fn cmul(a: C, b: C) -> C {
    (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0)
}
fn cdiv(a: C, b: C) -> C {
    let d = b.0 * b.0 + b.1 * b.1;
    ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
}

/// The beam's own mode shape and frequency, written here from the Euler-Bernoulli theory of a
/// pinned-pinned uniform beam (not taken from the example).
fn phi(j: usize, xi: f64) -> f64 {
    (j as f64 * PI * xi).sin()
}

/// Static flexibility of the pinned-pinned beam at `xi` under a unit load at `a` (the
/// influence coefficient $\xi(1 - a)(2a - a^2 - \xi^2)/6$ for $\xi \le a$, in units of
/// $L^3/EI$), times $k_1 = \pi^4 EI/(2L^3)$: the shaft's scaling.
fn influence(xi: f64, a: f64) -> f64 {
    let (x, a) = if xi <= a {
        (xi, a)
    } else {
        (1.0 - xi, 1.0 - a)
    };
    PI.powi(4) / 2.0 * x * (1.0 - a) * (2.0 * a - a * a - x * x) / 6.0
}

/// The modal model's static flexibility $\sum_j \phi_j(\xi)\phi_j(a)/\omega_j^2$ tends to the
/// beam's influence coefficient: mode shapes, frequencies and the modal mass of the example are
/// those of the Euler-Bernoulli beam in the stated scaling. The tail beyond `n` modes is below
/// $\sum_{j > n} j^{-4} < 1/(3n^3)$.
#[test]
fn modal_sum_is_the_beams_static_flexibility() {
    let n = 400;
    let bound = 1.0 / (3.0 * (n as f64).powi(3));
    let mut worst: f64 = 0.0;
    for (xi, a) in [(0.5, 0.5), (0.2, 0.6), (0.8, 0.4), (0.3, 0.3), (0.1, 0.9)] {
        let sum: f64 = (1..=n)
            .map(|j| {
                shaft::mode_shape(j, xi) * shaft::mode_shape(j, a)
                    / shaft::natural_frequency(j).powi(2)
            })
            .sum();
        let err = (sum - influence(xi, a)).abs();
        worst = worst.max(err);
        assert!(err <= bound + 1e-14, "xi {xi} a {a}: {err:e}");
    }
    // One mode at midspan is 1.5 % stiffer than the beam: the scaling's k_1 vs 48 EI/L^3.
    assert!((influence(0.5, 0.5) - PI.powi(4) / 96.0).abs() < 1e-14);
    println!("static flexibility: worst {worst:.2e} (bound {bound:.2e})");
}

/// Without contact the shaft is linear. With $z = w_x + i w_y$ each mode obeys
/// $z_j^{\prime\prime} + 2\zeta j^2 z_j^\prime + j^4 z_j = \phi_j(\xi_u) B e^{i\theta}$,
/// $\theta = \varphi_0 + \eta\tau$, so the steady orbit of station $i$ is
/// $w_i = e^{i\theta}\sum_j \phi_j(\xi_i)\phi_j(\xi_u) B/(j^4 - \eta^2 + 2i\zeta j^2\eta)$:
/// the solution of $(K - \eta^2 M + i\eta C)Z = F$ in modal coordinates. Checked at every
/// station, positions and velocities, below, at, between and above the resonances, for four
/// modes at four stations and for six modes at five stations.
#[test]
fn steady_unbalance_response_matches_the_harmonic_solution() {
    let six = Layout {
        unbalance: 1,
        ..SIX
    };
    let mut base = Preset::Fig8a.params();
    base.beta = 0.01;
    base.ex = 0.3;
    base.ey = -0.2;
    base.phi0 = 0.7;
    let zeta = base.nu1;
    let mut report = Vec::new();
    let etas = [0.5, 1.0, 2.5, 4.0, 6.5, 9.0, 12.0, 20.0];
    for (layout, extra) in [(FOUR, &[][..]), (six, &[36.0, 50.0][..])] {
        let (n, ns) = (layout.modes, layout.stations);
        let xi = |i: usize| i as f64 / (ns + 1) as f64;
        for &eta in etas.iter().chain(extra) {
            let p = base.with_eta(eta);
            let model = shaft::on_ring(p, layout).unwrap();
            let b = p.forcing_amplitude();
            // Modal amplitudes Z_j.
            let z: Vec<C> = (1..=n)
                .map(|j| {
                    let w = (j * j) as f64;
                    cdiv(
                        (phi(j, xi(layout.unbalance)) * b, 0.0),
                        (w * w - eta * eta, 2.0 * zeta * w * eta),
                    )
                })
                .collect();
            // The slowest transient decays like exp(-zeta tau): 260 time units leave e^-32.
            let period = p.forcing_period();
            let last = (260.0 / period).ceil() as u64 + 3;
            let y0 = DVector::zeros(4 * n + 2);
            let traj = run(&model, &y0, last - 3, last, &opts(1e-12));
            assert!(traj.events.is_empty(), "eta {eta}: no contact expected");
            let mut err: f64 = 0.0;
            let mut size: f64 = 0.0;
            for sp in &traj.strobe {
                let rot = p.phi0 + eta * sp.t;
                let e = (rot.cos(), rot.sin());
                for i in 1..=ns {
                    let w = (1..=n).fold((0.0, 0.0), |acc, j| {
                        let c = cmul(z[j - 1], (phi(j, xi(i)), 0.0));
                        (acc.0 + c.0, acc.1 + c.1)
                    });
                    let pos = cmul(w, e);
                    let vel = cmul((0.0, eta), pos);
                    let (sim_w, sim_v) = model.rotor().station_motion(i, sp.y.as_slice());
                    for (a, b) in [
                        (sim_w[0], pos.0),
                        (sim_w[1], pos.1),
                        (sim_v[0], vel.0),
                        (sim_v[1], vel.1),
                    ] {
                        err = err.max((a - b).abs());
                    }
                    size = size.max(pos.0.hypot(pos.1));
                    if i == layout.ring {
                        let k = model.rotor().ring_kinematics(sp.y.as_slice());
                        err = err.max((k.r.x - p.ex - pos.0).abs());
                        err = err.max((k.r.y - p.ey - pos.1).abs());
                        assert!(k.r.norm() < 0.9, "eta {eta}: must stay out of contact");
                    }
                }
            }
            report.push(format!("{n} modes, eta {eta}: {err:.1e} (|w| {size:.3})"));
            assert!(err <= 1e-10, "{n} modes, eta {eta}: {err:e}");
        }
    }
    println!(
        "harmonic response, max error over stations:\n  {}",
        report.join("\n  ")
    );
}

/// One mode at midspan ($\phi_1 = 1$) with the paper's parameters is the paper's model,
/// integrated instead of in closed form: the same strobes over 300 periods, the same contacts.
#[test]
fn one_mode_at_midspan_is_the_paper_model() {
    for (preset, eta) in [
        (Preset::Fig8a, 2.0),
        (Preset::Fig8b, 2.0),
        (Preset::Fig8b, 3.0),
    ] {
        let p = preset.params().with_eta(eta);
        let tight = opts(1e-12);
        let paper = run(
            &JeffcottModel::new(p).unwrap(),
            &SVector::zeros(),
            0,
            300,
            &tight,
        );
        let model = shaft::on_ring(p, Layout::jeffcott()).unwrap();
        // The paper's rotor starts at the ring's centre: q = -e.
        let y0 = DVector::from_column_slice(&[-p.ex, -p.ey, 0.0, 0.0, 0.0, 0.0]);
        let flex = run(&model, &y0, 0, 300, &tight);
        assert_eq!(paper.strobe.len(), 301);
        assert_eq!(flex.strobe.len(), 301);
        let offset = DVector::from_column_slice(&[p.ex, p.ey, 0.0, 0.0, 0.0, 0.0]);
        let worst = paper
            .strobe
            .iter()
            .zip(&flex.strobe)
            .map(|(a, b)| (a.y - (&b.y + &offset)).amax())
            .fold(0.0f64, f64::max);
        println!(
            "{preset:?} eta {eta}: max strobe difference {worst:.2e}, contacts {} / {}",
            contacts(&paper),
            contacts(&flex)
        );
        assert!(worst <= 1e-10, "{preset:?} eta {eta}: {worst:e}");
        assert_eq!(contacts(&paper), contacts(&flex));
        assert!(contacts(&paper) > 100);
    }
}

/// With contact and several modes the shaft's energy plus the ring's elastic energy changes
/// by the unbalance's work minus the modal damping's and the ring's dissipation:
///
/// $$\Delta E = \int \Big(F\cdot w_u^\prime - \sum_j 2\zeta j^2|q_j^\prime|^2\Big)
/// \thinspace d\tau - W_{ring},$$
///
/// the integral by the trapezoidal rule on dense samples. An undamped ring ($\nu_2 = 0$)
/// dissipates nothing, so the balance is exact (to quadrature error). A damped ring's force
/// $g(s) + C(s)s^\prime$ takes $g\cdot r^\prime = g\cdot s^\prime$ (its elastic energy's rate:
/// $g$ is normal to the ring and $r^\prime - s^\prime$ tangential) plus
/// $(C s^\prime)\cdot r^\prime$ in contact (integrated on the samples, which carry the ring's
/// velocity); in free flight the ring dissipates the elastic energy it had when it was
/// released (it relaxes in $2\nu_2/K \approx 10^{-4}$, between two samples). Cases: four
/// modes at four stations with an undamped and a damped ring, six modes at five stations with
/// the ring preloaded to $D = 0.02$, so that contact crosses the preload (regimes II and III). The ring's
/// station never goes beyond the ring.
#[test]
fn energy_balance_with_contact_and_several_modes() {
    let undamped = Params {
        nu2: 0.0,
        ..Preset::Fig8a.params()
    };
    for (layout, base) in [
        (FOUR, undamped),
        (FOUR, Preset::Fig8a.params()),
        (SIX, Preset::Fig8b.params().with_preload(0.02)),
    ] {
        let p = base.with_eta(3.0);
        let model = shaft::on_ring(p, layout).unwrap();
        let s = model.rotor();
        let [ix, iy] = s.ring_slots_of();
        let ring = shaft::ring_of(&p).unwrap();
        let ring_pos = |y: &DVector<f64>| Vector2::new(y[ix], y[iy]);
        let period = p.forcing_period();
        let (t0, t1) = (20.0 * period, 40.0 * period);
        let plan = OutputPlan {
            t_end: t1,
            strobe: None,
            dense: Some(DenseSampling {
                t_start: t0,
                dt: period / 4000.0,
            }),
            events: true,
        };
        let mut traj = Trajectory::default();
        let y0 = DVector::zeros(4 * layout.modes + 2);
        simulate(&model, 0.0, &y0, &plan, &opts(1e-11), &mut traj).expect("run");
        let (samples, events) = (&traj.samples, &traj.events);
        let onsets = events
            .iter()
            .filter(|e| e.kind == "contact onset" && e.t >= t0)
            .count();
        assert!(onsets >= 5, "contacts in the window: {onsets}");
        let mut regimes: Vec<u8> = samples.iter().map(|x| x.label).collect();
        regimes.sort_unstable();
        regimes.dedup();

        let energy = |y: &DVector<f64>| s.energy(y.as_slice()) + ring.energy(&ring_pos(y));
        let input = |t: f64, y: &DVector<f64>| {
            let f = s.unbalance_force(t);
            let (_, v) = s.station_motion(layout.unbalance, y.as_slice());
            f[0] * v[0] + f[1] * v[1]
        };
        let modal_damping = |y: &DVector<f64>| -> f64 {
            (1..=layout.modes)
                .map(|j| {
                    let w = (j * j) as f64;
                    let v = s.velocity_index(j - 1);
                    2.0 * p.nu1 * w * (y[v].powi(2) + y[v + 1].powi(2))
                })
                .sum()
        };
        // The power of the ring's damping force on the rotor, zero out of contact.
        let ring_damping = |x: &jeffcott::hybrid::Sample<jeffcott::nalgebra::Dyn>| {
            if x.label == 1 {
                return 0.0;
            }
            let r_dot = s.ring_kinematics(x.y.as_slice()).v;
            let damping = ring
                .damping_coefficients(&ring_pos(&x.y))
                .component_mul(&ring_pos(&x.dy));
            damping.dot(&r_dot)
        };
        let (mut work, mut ring_work, mut scale) = (0.0, 0.0, 0.0f64);
        for w in samples.windows(2) {
            let (a, b) = (&w[0], &w[1]);
            let h = 0.5 * (b.t - a.t);
            work += h
                * (input(a.t, &a.y) - modal_damping(&a.y) + input(b.t, &b.y) - modal_damping(&b.y));
            let inside: Vec<f64> = events
                .iter()
                .filter(|e| e.t > a.t && e.t < b.t)
                .map(|e| e.t)
                .collect();
            match (inside.first(), inside.last()) {
                (None, _) | (_, None) => {
                    ring_work += h * (ring_damping(a) + ring_damping(b));
                }
                // Events inside (onset, loss, preload crossings): each end's part, to first
                // order in the step.
                (Some(first), Some(last)) => {
                    ring_work += (first - a.t) * ring_damping(a) + (b.t - last) * ring_damping(b);
                }
            }
            scale = scale.max(input(a.t, &a.y).abs());
        }
        // Free flight: the ring's elastic energy at release is dissipated by the next touch.
        let (first, last) = (samples.first().unwrap(), samples.last().unwrap());
        let free_energy = |label: u8, y: &DVector<f64>| {
            if label == 1 {
                ring.energy(&ring_pos(y))
            } else {
                0.0
            }
        };
        ring_work += free_energy(first.label, &first.y) - free_energy(last.label, &last.y);
        for e in events.iter().filter(|e| e.t > t0 && e.t < t1) {
            ring_work += free_energy(e.to, &e.after) - free_energy(e.from, &e.before);
        }
        let change = energy(&last.y) - energy(&first.y);
        let scale = scale * (t1 - t0);
        let residual = (change - work + ring_work) / scale;
        let mut gap_excess: f64 = 0.0;
        for smp in samples {
            let r = s.ring_kinematics(smp.y.as_slice()).r;
            gap_excess = gap_excess.max((r - ring_pos(&smp.y)).norm() - 1.0);
        }
        println!(
            "{} modes, nu2 {}, D {}: energy change {change:.6e}, net work {work:.6e}, ring dissipation {ring_work:.6e}, residual {residual:.2e} of the input scale, contacts {onsets}, regimes {regimes:?}, max |r - s| - 1 = {gap_excess:.1e}",
            layout.modes, p.nu2, p.dx
        );
        assert!(gap_excess <= 1e-12, "{gap_excess:e}");
        if p.dx > 0.0 {
            assert!(
                regimes.iter().any(|&r| r >= 3),
                "crosses the preload: {regimes:?}"
            );
        }
        if p.nu2 == 0.0 {
            assert_eq!(ring_work, 0.0);
        } else {
            // The ring's dissipation matters at this scale.
            assert!(ring_work / scale > 1e-5, "{ring_work:e}");
        }
        assert!(residual.abs() <= 1e-9, "{residual:e}");
    }
}

/// With contact the strobes converge as the tolerance is tightened: four modes on the ring of
/// Fig. 8a, six modes at five stations on a preloaded ring.
#[test]
fn contact_run_converges_with_the_tolerance() {
    for (layout, base) in [
        (FOUR, Preset::Fig8a.params()),
        (SIX, Preset::Fig8b.params().with_preload(0.02)),
    ] {
        let p = base.with_eta(3.0);
        let model = shaft::on_ring(p, layout).unwrap();
        let y0 = DVector::zeros(4 * layout.modes + 2);
        let at = |rtol: f64| {
            let t = run(&model, &y0, 40, 40, &opts(rtol));
            (t.strobe[0].y.clone(), contacts(&t))
        };
        let (reference, n_ref) = at(1e-13);
        let mut errs = Vec::new();
        for rtol in [1e-7, 1e-9, 1e-11] {
            let (y, n) = at(rtol);
            let err = (&y - &reference).amax();
            println!(
                "{} modes, rtol {rtol:.0e}: error {err:.2e} against rtol 1e-13, contacts {n} / {n_ref}",
                layout.modes
            );
            assert_eq!(n, n_ref, "rtol {rtol:e}");
            errs.push(err);
        }
        assert!(n_ref >= 20, "{n_ref}");
        assert!(errs[1] < errs[0] && errs[2] < errs[1], "{errs:?}");
        assert!(errs[2] <= 1e-12, "{errs:?}");
    }
}

/// The example reads its size at run time, writes its two figures with their data, and rejects
/// a station that is not on the shaft.
#[test]
fn example_runs_with_the_size_read_at_run_time() {
    let exe = examples::example_exe("flexible_shaft");
    let out = std::env::temp_dir().join(format!("flexible_shaft_{}", std::process::id()));
    let small = [
        "--transient",
        "20",
        "--periods",
        "2",
        "--steps",
        "3",
        "--bif-transient",
        "20",
        "--record",
        "4",
    ];
    let run = Command::new(&exe)
        .args(["--modes", "6", "--stations", "5", "--ring", "4", "--out"])
        .arg(&out)
        .args(small)
        .output()
        .expect("run the example");
    let stdout = String::from_utf8_lossy(&run.stdout);
    assert_eq!(run.status.code(), Some(0), "{run:?}");
    assert!(
        stdout.contains("6 modes (state size 26), 5 stations"),
        "{stdout}"
    );
    assert!(stdout.contains("bifurcation: 3 values"), "{stdout}");
    for file in [
        "orbit.png",
        "orbit.csv",
        "bifurcation.png",
        "bifurcation.csv",
    ] {
        let len = std::fs::metadata(out.join(file)).map_or(0, |m| m.len());
        assert!(len > 0, "{file} not written in {}", out.display());
    }
    std::fs::remove_dir_all(&out).ok();

    let bad = Command::new(&exe)
        .args(["--ring", "7"])
        .args(small)
        .output()
        .expect("run the example");
    assert_eq!(bad.status.code(), Some(1), "{bad:?}");
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(
        stderr.contains("ring station 7 is not one of the stations 1..=4"),
        "{stderr}"
    );
}

/// Bad layouts and parameters are typed errors naming what is wrong.
#[test]
fn bad_input_is_a_typed_error() {
    use shaft::ShaftError;
    let p = Preset::Fig8a.params();
    let with = |f: fn(&mut Layout)| {
        let mut l = FOUR;
        f(&mut l);
        shaft::on_ring(p, l).err()
    };
    assert_eq!(with(|l| l.modes = 0), Some(ShaftError::NoModes));
    assert_eq!(with(|l| l.stations = 0), Some(ShaftError::NoStations));
    assert_eq!(
        with(|l| l.unbalance = 0),
        Some(ShaftError::StationOutOfRange {
            role: "unbalance",
            station: 0,
            stations: 4
        })
    );
    assert_eq!(
        with(|l| l.ring = 5),
        Some(ShaftError::StationOutOfRange {
            role: "ring",
            station: 5,
            stations: 4
        })
    );
    let undamped = Params {
        nu1: 0.0,
        ..p.with_eta(4.0)
    };
    assert_eq!(
        shaft::on_ring(undamped, FOUR).err(),
        Some(ShaftError::UndampedResonance { mode: 2, eta: 4.0 })
    );
    assert!(matches!(
        shaft::on_ring(Params { kx: -1.0, ..p }, FOUR),
        Err(ShaftError::Params(_))
    ));
}
