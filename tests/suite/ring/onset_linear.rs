//! The certified onset search on a linear rotor's closed form (`rotor::LinearSegment`, whose
//! bounds shrink as its modes decay: `RotorMotion::bounds_on`) against a brute-force oracle on
//! constructed near-grazing cases.
//!
//! **Rotor.** Three lumped nodes (6 coordinates, 12 states): two slow ones with gyroscopic
//! coupling and unbalance, and a stiff light one ($\omega \approx 10^3$, damping ratio about
//! 0.25) hung on the ring's node, so that a start state with content in that mode has a jerk
//! bound $10^9$ times its amplitude at the start, which decays along the window.
//!
//! **Cases.** A random start state at a random time; a window of 0.5 to 6 time units from the
//! start (or from a later time); the ring at rest at its centre or relaxing from a displaced
//! position (no preload: one smooth piece). The largest value $M$ of $|r - s|^2$ on the window
//! is measured on the closed form (dense samples, golden-section refinement of the best ones)
//! and the gap set to $\gamma^2 = M/(1 \pm d)$, $d$ log-uniform in $[10^{-10}, 10^{-4}]$: a
//! contact of depth about $d$ or a near miss by $d$.
//!
//! **Oracle.** Adaptive sampling of $h = |r - s|^2 - \gamma^2$ with the interval bound
//! $h \le \max(h(a), h(b)) + M_2 (b - a)^2/8$, $M_2 = 2Q_1^2 + 2Q_0Q_2 \ge |h''|$ on $[a, b]$
//! from the rotor's bounds on $[a, b]$ and the ring's (each $|s^{(p)}|$ decays, $\le |s(a)|/T^p$);
//! the rotor's bounds are themselves checked against dense samples of $r$, $r'$, $r''$ (and a
//! difference quotient of $r''$ for the jerk). An interval is split until its bound is below
//! $-\tau$, or it holds a sign change and is at most `RES` long (first root bisected).
//!
//! **Checks.** No contact the oracle finds is missed or reported late, and no contact is
//! reported on a window the oracle certifies clear.

use crate::rng::Rng;
use std::sync::Arc;

use jeffcott::nalgebra::{Complex, DMatrix, DVector, Vector2};
use jeffcott::ring::onset::{find_onset, MotionBounds, Onset, OnsetStats, RotorMotion};
use jeffcott::ring::{Relaxation, SnubberRing};
use jeffcott::rotor::{LinearClosedForm, LinearFreeFlight, LinearSegment, LinearSystem};

const RES: f64 = 1e-13;

fn three_node_rotor() -> Arc<LinearClosedForm> {
    let n = 6;
    let m = DMatrix::from_diagonal(&DVector::from_vec(vec![1.0, 1.0, 0.5, 0.5, 0.01, 0.01]));
    // Node springs: 0-ground 1, 0-1 1, 1-ground 0.5, 0-2 1e4 (the stiff light node).
    let mut k = DMatrix::zeros(n, n);
    let spring = |a: usize, b: Option<usize>, s: f64, k: &mut DMatrix<f64>| {
        for d in 0..2 {
            k[(2 * a + d, 2 * a + d)] += s;
            if let Some(b) = b {
                k[(2 * b + d, 2 * b + d)] += s;
                k[(2 * a + d, 2 * b + d)] -= s;
                k[(2 * b + d, 2 * a + d)] -= s;
            }
        }
    };
    spring(0, None, 1.0, &mut k);
    spring(0, Some(1), 1.0, &mut k);
    spring(1, None, 0.5, &mut k);
    spring(0, Some(2), 1e4, &mut k);
    let speed = 1.3;
    let mut d = &k * 0.02;
    for i in 0..2 {
        d[(2 * i, 2 * i + 1)] += 0.2 * speed;
        d[(2 * i + 1, 2 * i)] -= 0.2 * speed;
    }
    // Damping of the light node: ratio about 0.25 at omega ~ 1e3.
    for dd in 4..6 {
        d[(dd, dd)] += 5.0;
    }
    let b = Complex::from_polar(0.5, 0.7);
    let mut f = DVector::from_element(n, Complex::new(0.0, 0.0));
    f[0] = b;
    f[1] = b * Complex::new(0.0, -1.0);
    let lf = LinearFreeFlight::new(
        LinearSystem::from_parts(m, d, k, speed, f, DVector::zeros(n)).unwrap(),
        [0, 1],
        Vector2::new(0.1, 0.0),
    );
    Arc::new(lf.prepare().unwrap())
}

/// The ring's position and velocity at `t` and its relaxation time.
fn ring_at(relax: &Relaxation, ring: &SnubberRing, t: f64) -> (Vector2<f64>, Vector2<f64>) {
    relax.at(ring, t)
}

fn h_of(seg: &LinearSegment, relax: &Relaxation, ring: &SnubberRing, gap2: f64, t: f64) -> f64 {
    let (r, _, _) = seg.kinematics(t);
    let (s, _) = ring_at(relax, ring, t);
    (r - s).norm_squared() - gap2
}

/// $M_2 \ge |h''|$ on $[a, b]$.
fn m2(seg: &LinearSegment, relax: &Relaxation, ring: &SnubberRing, a: f64, b: f64) -> f64 {
    let rb = seg.bounds_on(a, b);
    let tr = ring.relaxation_time().x;
    let (s, _) = ring_at(relax, ring, a);
    let sn = s.norm();
    let (q0, q1, q2) = (
        rb.position + sn,
        rb.velocity + sn / tr,
        rb.acceleration + sn / (tr * tr),
    );
    (2.0 * q1 * q1 + 2.0 * q0 * q2) * (1.0 + 1e-12)
}

enum Truth {
    Contact(f64),
    Clear,
    Ambiguous,
}

fn oracle(
    seg: &LinearSegment,
    relax: &Relaxation,
    ring: &SnubberRing,
    gap2: f64,
    (t0, t1): (f64, f64),
    tau: f64,
) -> Truth {
    let h = |t: f64| h_of(seg, relax, ring, gap2, t);
    let mut stack = vec![(t0, h(t0), t1, h(t1))];
    // Depth-first from the left: the first interval with a sign change is the first root.
    let mut touched = false;
    let mut evals = 0u64;
    while let Some((a, ha, b, hb)) = stack.pop() {
        evals += 1;
        assert!(evals < 20_000_000, "oracle too slow");
        if ha >= 0.0 {
            return Truth::Contact(a);
        }
        if hb >= 0.0 && b - a <= RES {
            return Truth::Contact(b);
        }
        let bound = ha.max(hb) + m2(seg, relax, ring, a, b) * (b - a) * (b - a) / 8.0;
        if bound < -tau {
            continue;
        }
        if b - a <= RES {
            touched = true;
            continue;
        }
        let c = 0.5 * (a + b);
        let hc = h(c);
        stack.push((c, hc, b, hb));
        stack.push((a, ha, c, hc));
    }
    if touched {
        Truth::Ambiguous
    } else {
        Truth::Clear
    }
}

/// The largest $|r - s|^2$ on the window: dense samples, golden-section refinement of the
/// best few.
fn window_max(
    seg: &LinearSegment,
    relax: &Relaxation,
    ring: &SnubberRing,
    (t0, t1): (f64, f64),
) -> f64 {
    let q2 = |t: f64| h_of(seg, relax, ring, 0.0, t);
    let n = 20_000;
    let dt = (t1 - t0) / n as f64;
    let vals: Vec<f64> = (0..=n).map(|i| q2(t0 + dt * i as f64)).collect();
    let mut best = vals[0].max(vals[n]);
    let mut order: Vec<usize> = (1..n)
        .filter(|&i| vals[i] >= vals[i - 1] && vals[i] >= vals[i + 1])
        .collect();
    order.sort_by(|&a, &b| vals[b].total_cmp(&vals[a]));
    for &i in order.iter().take(6) {
        let (mut a, mut b) = (t0 + dt * (i - 1) as f64, t0 + dt * (i + 1) as f64);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..80 {
            let (c, d) = (b - g * (b - a), a + g * (b - a));
            if q2(c) > q2(d) {
                b = d;
            } else {
                a = c;
            }
        }
        best = best.max(q2(0.5 * (a + b)));
    }
    best
}

/// The rotor's bounds hold along the segment: dense samples of $r, r', r''$ and difference
/// quotients of $r''$ against `bounds_on` from a few later times.
fn check_bounds(seg: &LinearSegment, t0: f64, t1: f64) {
    for from in [t0, t0 + 0.001 * (t1 - t0), t0 + 0.3 * (t1 - t0)] {
        let b: MotionBounds = seg.bounds_on(from, t1);
        let n = 4000;
        let dt = (t1 - from) / n as f64;
        let mut prev = seg.kinematics(from).2;
        for i in 1..=n {
            let t = from + dt * i as f64;
            let (r, v, a) = seg.kinematics(t);
            assert!(r.norm() <= b.position && v.norm() <= b.velocity && a.norm() <= b.acceleration);
            assert!((a - prev).norm() / dt <= b.jerk * (1.0 + 1e-9));
            prev = a;
        }
    }
}

#[test]
fn onset_search_on_linear_rotors_agrees_with_brute_force() {
    let form = three_node_rotor();
    let ring = SnubberRing::isotropic(20.0, 0.0, 0.05).unwrap();
    let mut rng = Rng(2024);
    let (mut contacts, mut clear, mut ambiguous) = (0, 0, 0);
    let mut evaluations = 0;
    let mut worst_timing = 0.0f64;
    for case in 0..1000 {
        let t_seg = rng.uniform(0.0, 10.0);
        let x0: Vec<f64> = (0..12)
            .map(|i| {
                // The light node's coordinates and velocities: small, the velocities large.
                let s = match i {
                    4 | 5 => 1e-3,
                    10 | 11 => 0.5,
                    _ => 0.8,
                };
                s * rng.uniform(-1.0, 1.0)
            })
            .collect();
        let seg = form.segment(t_seg, &x0);
        let relax = if case % 2 == 0 {
            Relaxation::at_rest(t_seg)
        } else {
            Relaxation {
                t0: t_seg,
                s0: Vector2::new(rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)),
            }
        };
        let w_start = if case % 3 == 0 {
            t_seg + rng.uniform(0.0, 1.0)
        } else {
            t_seg
        };
        let w_end = w_start + rng.uniform(0.5, 6.0);
        if case % 20 == 0 {
            check_bounds(&seg, t_seg, w_end);
        }
        let m = window_max(&seg, &relax, &ring, (w_start, w_end));
        let d = (rng.uniform((1e-10f64).ln(), (1e-4f64).ln())).exp();
        let hit = case % 4 < 2;
        let gap2 = if hit { m / (1.0 + d) } else { m / (1.0 - d) };
        let gap = gap2.sqrt();
        // The window's start must be clearly out of contact.
        if h_of(&seg, &relax, &ring, gap2, w_start) > -1e-6 * gap2 {
            continue;
        }
        let ring_g = SnubberRing { gap, ..ring };
        let size = seg.bounds_on(w_start, w_end).position + 0.5;
        let tau = 4.0 * f64::EPSILON * gap2 + 256.0 * f64::EPSILON * gap * size;
        let truth = oracle(&seg, &relax, &ring_g, gap2, (w_start, w_end), tau);
        let mut stats = OnsetStats::default();
        let found = find_onset(&seg, &relax, &ring_g, (w_start, w_end), false, &mut stats);
        evaluations += stats.evaluations;
        match truth {
            Truth::Contact(t_o) => {
                contacts += 1;
                let Onset::At(t_s) = found else {
                    panic!("case {case}: contact at {t_o} (depth {d:e}) missed");
                };
                // The stated timing bound: the search stops at the first node with
                // h >= -eps_h, both read through the closed form's rounding delta_h (here
                // tau - eps_h), so |t_s - t_o| <= (eps_h + 2 delta_h)/h'(t_o) + 2 ulp + RES.
                let (r, v, _) = seg.kinematics(t_o);
                let (s, sd) = ring_at(&relax, &ring_g, t_o);
                let slope = 2.0 * (r - s).dot(&(v - sd));
                let eps_h = 4.0 * f64::EPSILON * gap2;
                let within = (eps_h + 2.0 * (tau - eps_h)) / slope.max(1e-300)
                    + 2.0 * f64::EPSILON * t_o.abs()
                    + RES;
                worst_timing = worst_timing.max((t_s - t_o).abs() / within);
                assert!(
                    (t_s - t_o).abs() <= within,
                    "case {case}: onset {t_s}, root {t_o}, allowed {within:e} (slope {slope:e}, depth {d:e})"
                );
            }
            Truth::Clear => {
                clear += 1;
                assert_eq!(
                    found,
                    Onset::None,
                    "case {case}: false alarm (miss by {d:e})"
                );
            }
            Truth::Ambiguous => ambiguous += 1,
        }
    }
    eprintln!("linear rotor onsets: {contacts} contacts, {clear} clear, {ambiguous} ambiguous; {evaluations} search evaluations; worst timing error / bound {worst_timing:.2}");
    assert!(contacts > 200 && clear > 200);
}

/// An unstable rotor (negative damping, $\nu_1 = -0.02$): its bounds hold on finite windows
/// only ([`RotorMotion::bounds_on`] with the window's end for growing modes), and the search
/// finds the first contact of the growing orbit, against dense sampling with bisection.
#[test]
fn onset_search_on_an_unstable_rotor_finds_the_first_contact() {
    let nu1 = -0.02;
    let lf = LinearFreeFlight::new(
        LinearSystem::from_parts(
            DMatrix::identity(2, 2),
            DMatrix::identity(2, 2) * (2.0 * nu1),
            DMatrix::identity(2, 2),
            1.7,
            DVector::from_vec(vec![Complex::new(0.01, 0.0), Complex::new(0.0, -0.01)]),
            DVector::zeros(2),
        )
        .unwrap(),
        [0, 1],
        Vector2::zeros(),
    );
    let form = Arc::new(lf.prepare().unwrap());
    let seg = form.segment(0.0, &[0.05, 0.0, 0.0, 0.03]);
    assert!(seg.bounds().position.is_infinite());
    let ring = SnubberRing::isotropic(20.0, 0.0, 0.05).unwrap();
    let relax = Relaxation::at_rest(0.0);
    let t_end = 300.0;
    let mut stats = OnsetStats::default();
    let Onset::At(t_s) = find_onset(&seg, &relax, &ring, (0.0, t_end), false, &mut stats) else {
        panic!("the growing orbit must reach the gap");
    };
    // Dense sampling (step 1e-3; |h''| <= 2(|r'|^2 + |r| |r''|), about 10 here, so an
    // excursion between samples is at most 1.3e-6 deep) and bisection of the first crossing.
    let h = |t: f64| seg.kinematics(t).0.norm_squared() - 1.0;
    let dt = 1e-3;
    let mut t = 0.0;
    while h(t + dt) < 0.0 {
        t += dt;
    }
    let (mut a, mut b) = (t, t + dt);
    for _ in 0..60 {
        let c = 0.5 * (a + b);
        if h(c) < 0.0 {
            a = c;
        } else {
            b = c;
        }
    }
    eprintln!(
        "unstable rotor: onset {t_s} (sampled {b}), {} evaluations",
        stats.evaluations
    );
    assert!(t_s <= b + 1e-9 && t_s >= b - 1e-6, "{t_s} vs {b}");
}
