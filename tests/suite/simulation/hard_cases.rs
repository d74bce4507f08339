//! Hard cases of the hybrid simulation: grazing contacts, stiff rings, vanishing damping and
//! preload, the preload corner, contact lost at a regime boundary, starts inside contact,
//! extreme frequency ratios and eccentricities, long runs and chattering.
//!
//! Every case must end in a correct, finite, bounded result or a clear typed error, within a
//! time limit (a hang fails the test instead of stalling the suite). Where an independent
//! answer exists (the closed-form free flight computed here from scratch, a much tighter
//! tolerance, another method, a nearby limit), the test compares against it.

use std::sync::mpsc;
use std::time::Duration;

use jeffcott::hybrid::{
    DenseSampling, OutputPlan, SimErrorKind, SimOptions, SimStats, StrobePoint, StrobeRange,
    Trajectory,
};
use jeffcott::nalgebra::U6;
use jeffcott::ode::Method;
use jeffcott::paper::{guard, JeffcottModel, RunFailure, State};
use jeffcott::params::{Params, Preset};
use nalgebra::Vector2;

/// Runs `f` on its own thread and fails the test if it takes longer than `secs` (a hang).
fn within<T: Send + 'static>(secs: u64, f: impl FnOnce() -> T + Send + 'static) -> T {
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = tx.send(f());
    });
    match rx.recv_timeout(Duration::from_secs(secs)) {
        Ok(v) => v,
        Err(mpsc::RecvTimeoutError::Timeout) => panic!("run did not finish within {secs} s"),
        Err(mpsc::RecvTimeoutError::Disconnected) => panic!("run panicked"),
    }
}

type Outcome = Result<(Trajectory<U6>, SimStats), Box<RunFailure>>;

/// Runs `periods` forcing periods from `(0, y0)` with events, strobing every period.
fn run(p: Params, y0: State, periods: u64, opts: SimOptions) -> Outcome {
    within(60, move || {
        let m = JeffcottModel::new(p).expect("valid parameters");
        let plan = OutputPlan {
            t_end: p.forcing_period() * periods as f64,
            strobe: Some(StrobeRange {
                first: 0,
                last: periods,
            }),
            dense: None,
            events: true,
        };
        m.run(0.0, &y0, &plan, &opts)
    })
}

fn ok(o: Outcome, what: &str) -> (Trajectory<U6>, SimStats) {
    o.unwrap_or_else(|f| panic!("{what}: {}", f.error))
}

fn tol(rtol: f64, atol: f64) -> SimOptions {
    SimOptions::default().with_rtol(rtol).with_atol(atol)
}

fn last(t: &Trajectory<U6>) -> State {
    t.strobe.last().expect("stroboscopic output").y
}

fn max_diff(a: &State, b: &State) -> f64 {
    (a - b).iter().fold(0.0f64, |m, d| m.max(d.abs()))
}

/// Largest deviation over all common stroboscopic points.
fn strobe_diff(a: &Trajectory<U6>, b: &Trajectory<U6>) -> f64 {
    assert_eq!(a.strobe.len(), b.strobe.len());
    a.strobe
        .iter()
        .zip(&b.strobe)
        .map(|(a, b)| max_diff(&a.y, &b.y))
        .fold(0.0, f64::max)
}

/// All stroboscopic states finite and the rotor within `r_max` of the centre with speed at most
/// `v_max`; the ring within the rotor's reach (`|r - s| <= 1 + 1e-7`).
fn assert_sane(t: &Trajectory<U6>, r_max: f64, v_max: f64, what: &str) {
    for StrobePoint {
        k,
        t: _,
        y,
        label: _,
    } in &t.strobe
    {
        assert!(
            y.iter().all(|v| v.is_finite()),
            "{what}: non-finite at k = {k}: {y:?}"
        );
        let r = Vector2::new(y[0], y[1]);
        let v = Vector2::new(y[2], y[3]);
        let s = Vector2::new(y[4], y[5]);
        assert!(r.norm() <= r_max, "{what}: |r| = {} at k = {k}", r.norm());
        assert!(v.norm() <= v_max, "{what}: |v| = {} at k = {k}", v.norm());
        assert!(
            (r - s).norm() <= 1.0 + 1e-7,
            "{what}: ring out of reach at k = {k}: |r - s| = {}",
            (r - s).norm()
        );
    }
}

/// The rotor's free flight from scratch (not the library's code): for z = x + i y,
/// z'' + 2 nu1 z' + z = e + F exp(i (phi0 + eta t)). Returns [x, y, x', y'] at `t`.
fn free_flight(p: &Params, z0: [f64; 4], t: f64) -> [f64; 4] {
    type C = (f64, f64);
    let mul = |a: C, b: C| (a.0 * b.0 - a.1 * b.1, a.0 * b.1 + a.1 * b.0);
    let div = |a: C, b: C| {
        let d = b.0 * b.0 + b.1 * b.1;
        ((a.0 * b.0 + a.1 * b.1) / d, (a.1 * b.0 - a.0 * b.1) / d)
    };
    let f = p.beta * p.eta * p.eta;
    // Particular solution e + Z exp(i eta t), Z = F e^{i phi0} / (1 - eta^2 + 2 i nu1 eta).
    let zc = div(
        (f * p.phi0.cos(), f * p.phi0.sin()),
        (1.0 - p.eta * p.eta, 2.0 * p.nu1 * p.eta),
    );
    let iez = mul((0.0, p.eta), zc);
    // Homogeneous part exp(-nu1 t) (A cos(wd t) + B sin(wd t)), underdamped (nu1 < 1).
    let wd = (1.0 - p.nu1 * p.nu1).sqrt();
    let a = (z0[0] - p.ex - zc.0, z0[1] - p.ey - zc.1);
    let ad = (z0[2] - iez.0, z0[3] - iez.1);
    let b = ((ad.0 + p.nu1 * a.0) / wd, (ad.1 + p.nu1 * a.1) / wd);
    let (sw, cw) = (wd * t).sin_cos();
    let ex = (-p.nu1 * t).exp();
    let h = (ex * (a.0 * cw + b.0 * sw), ex * (a.1 * cw + b.1 * sw));
    let hd = (
        ex * ((-p.nu1 * a.0 + wd * b.0) * cw + (-p.nu1 * b.0 - wd * a.0) * sw),
        ex * ((-p.nu1 * a.1 + wd * b.1) * cw + (-p.nu1 * b.1 - wd * a.1) * sw),
    );
    let ph = mul(zc, ((p.eta * t).cos(), (p.eta * t).sin()));
    let phd = mul(iez, ((p.eta * t).cos(), (p.eta * t).sin()));
    [
        p.ex + ph.0 + h.0,
        p.ey + ph.1 + h.1,
        phd.0 + hd.0,
        phd.1 + hd.1,
    ]
}

/// The steady free orbit's state at t = 0 and its largest radius |e| + |Z|.
fn steady_orbit(p: &Params) -> (State, f64) {
    // The particular solution alone: e + Z exp(i eta t).
    let f = p.beta * p.eta * p.eta;
    let den = (1.0 - p.eta * p.eta).hypot(2.0 * p.nu1 * p.eta);
    let zr = f / den;
    let arg = p.phi0 - (2.0 * p.nu1 * p.eta).atan2(1.0 - p.eta * p.eta);
    let y0 = State::from([
        p.ex + zr * arg.cos(),
        p.ey + zr * arg.sin(),
        -p.eta * zr * arg.sin(),
        p.eta * zr * arg.cos(),
        0.0,
        0.0,
    ]);
    (y0, p.ex.hypot(p.ey) + zr)
}

/// Fig. 8 values with beta chosen so that the steady free orbit's largest radius is `radius`.
fn grazing_params(radius: f64) -> Params {
    let p = Preset::Fig8a.params();
    let den = (1.0 - p.eta * p.eta).hypot(2.0 * p.nu1 * p.eta);
    let zr = radius - p.ex.hypot(p.ey);
    Params {
        beta: zr * den / (p.eta * p.eta),
        ..p
    }
}

/// A scene that never reaches the ring from rest at its rest position (ex = 0.5, beta = 0.02).
fn quiet_params() -> Params {
    Params {
        beta: 0.02,
        ex: 0.5,
        ..Preset::Fig8a.params()
    }
}

fn contact_events(t: &Trajectory<U6>) -> usize {
    t.events
        .iter()
        .filter(|e| e.kind == guard::ONSET || e.kind == guard::LOSS)
        .count()
}

// ---------------------------------------------------------------------------------------------
// Grazing

#[test]
fn free_flight_matches_closed_form_computed_here() {
    // Small forcing from rest at the rest position: the orbit stays within |r| < 0.65, never
    // reaches the ring; compare every period with the closed form.
    let p = quiet_params();
    let y0 = State::from([p.ex, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let (t, _) = ok(run(p, y0, 40, SimOptions::default()), "free");
    assert_eq!(t.events.len(), 0);
    for StrobePoint { k, t: tk, y, label } in &t.strobe {
        let e = free_flight(&p, [p.ex, 0.0, 0.0, 0.0], *tk);
        for i in 0..4 {
            assert!(
                (y[i] - e[i]).abs() < 1e-12,
                "k = {k}, i = {i}: {} vs {}",
                y[i],
                e[i]
            );
        }
        assert_eq!(*label, 1);
    }
}

#[test]
fn grazing_orbit_just_inside_never_touches() {
    // Steady orbit of largest radius 1 - 1e-9: exact free flight, no contact, for 200 periods.
    let p = grazing_params(1.0 - 1e-9);
    let (y0, rmax) = steady_orbit(&p);
    assert!((rmax - (1.0 - 1e-9)).abs() < 1e-15);
    let (t, _) = ok(run(p, y0, 200, SimOptions::default()), "inside");
    assert_eq!(t.events.len(), 0, "{:?}", t.events.first());
    let z0 = [y0[0], y0[1], y0[2], y0[3]];
    for StrobePoint {
        k,
        t: tk,
        y,
        label: _,
    } in &t.strobe
    {
        let e = free_flight(&p, z0, *tk);
        for i in 0..4 {
            assert!((y[i] - e[i]).abs() < 1e-11, "k = {k}, i = {i}");
        }
        assert!(y[4] == 0.0 && y[5] == 0.0);
    }
}

#[test]
fn grazing_orbit_just_outside_touches_every_period() {
    // Largest radius 1 + 1e-9: a contact of depth ~1e-9 once per period. The contact force
    // ~ K * 1e-9 barely changes the orbit: compare with the free closed form, and with a run at
    // a much tighter tolerance.
    let p = grazing_params(1.0 + 1e-9);
    let (y0, _) = steady_orbit(&p);
    let n = 50;
    let (t, _) = ok(run(p, y0, n, SimOptions::default()), "outside");
    let (tt, _) = ok(run(p, y0, n, tol(1e-13, 1e-15)), "outside tight");
    assert!(
        contact_events(&t) as u64 >= 2 * (n - 1),
        "{}",
        contact_events(&t)
    );
    assert_sane(&t, 1.0 + 1e-6, 1.0, "outside");
    let z0 = [y0[0], y0[1], y0[2], y0[3]];
    for StrobePoint {
        k,
        t: tk,
        y,
        label: _,
    } in &t.strobe
    {
        let e = free_flight(&p, z0, *tk);
        for i in 0..4 {
            assert!((y[i] - e[i]).abs() < 1e-6, "k = {k}, i = {i}");
        }
    }
    assert!(strobe_diff(&t, &tt) < 1e-9, "{}", strobe_diff(&t, &tt));
}

#[test]
fn tangential_touch_at_start() {
    // Rotor on the gap circle moving tangentially, ring at rest at the centre: a touch of zero
    // depth at t = 0. Outward acceleration (forcing pushes out) must give contact, inward not.
    let base = Preset::Fig8a.params();
    for (phi0, what) in [(0.0, "pushed out"), (std::f64::consts::PI, "pulled in")] {
        let p = Params {
            phi0,
            ex: 0.0,
            ..base
        };
        let y0 = State::from([1.0, 0.0, 0.0, 0.3, 0.0, 0.0]);
        let (t, _) = ok(run(p, y0, 5, SimOptions::default()), what);
        let (tt, _) = ok(run(p, y0, 5, tol(1e-13, 1e-15)), what);
        assert_sane(&t, 1.5, 2.0, what);
        assert!(
            strobe_diff(&t, &tt) < 1e-7,
            "{what}: {}",
            strobe_diff(&t, &tt)
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Stiff ring, damping and preload limits

#[test]
fn very_stiff_ring() {
    for k in [1e3, 1e5] {
        let p = Preset::Fig8a.params().with_stiffness(k);
        let (t, s) = ok(run(p, State::zeros(), 20, SimOptions::default()), "stiff");
        let (tt, _) = ok(run(p, State::zeros(), 20, tol(1e-13, 1e-15)), "stiff tight");
        assert!(s.transitions > 0, "K = {k}: no contact");
        // Penetration shrinks like 1/K: the rotor stays within a hair of the gap circle.
        assert_sane(&t, 1.0 + 50.0 / k, 2.0, "stiff");
        let d = strobe_diff(&t, &tt);
        println!("K = {k}: {s:?}, deviation from rtol 1e-13: {d:.2e}");
        assert!(d < 1e-7, "K = {k}: {d:e}");
    }
}

#[test]
fn tiny_and_zero_ring_damping() {
    // nu2 -> 0: the ring relaxes ever faster; nu2 = 0 must work (instant relaxation) and be the
    // limit of small nu2.
    let base = Preset::Fig8b.params();
    let mut runs = Vec::new();
    for nu2 in [2e-3, 1e-6, 1e-10, 0.0] {
        let p = Params { nu2, ..base };
        let (t, _) = ok(run(p, State::zeros(), 20, SimOptions::default()), "nu2");
        assert_sane(&t, 1.5, 2.0, "nu2");
        runs.push((nu2, t));
    }
    let d_small = strobe_diff(&runs[2].1, &runs[3].1);
    let d_mid = strobe_diff(&runs[1].1, &runs[3].1);
    println!("nu2 1e-10 vs 0: {d_small:.2e}; 1e-6 vs 0: {d_mid:.2e}");
    assert!(d_small < 1e-7, "{d_small:e}");
    assert!(d_mid < 1e-3, "{d_mid:e}");
}

#[test]
fn preload_to_zero_is_continuous() {
    let base = Preset::Fig8a.params();
    let (t0, s0) = ok(
        run(base, State::zeros(), 30, SimOptions::default()),
        "D = 0",
    );
    for d in [1e-12, 1e-8] {
        let (t, s) = ok(
            run(
                base.with_preload(d),
                State::zeros(),
                30,
                SimOptions::default(),
            ),
            "D > 0",
        );
        let diff = strobe_diff(&t0, &t);
        println!("D = {d}: deviation from D = 0: {diff:.2e}; {s:?} vs {s0:?}");
        // The force law differs from D = 0 by O(K D).
        assert!(diff < 1e4 * d + 1e-9, "D = {d}: {diff:e}");
    }
}

// ---------------------------------------------------------------------------------------------
// Regime boundaries

#[test]
fn corner_of_both_preloads_at_once() {
    // Start in contact with the ring exactly at (Dx, Dy): r - s is along (1, 1) there. Moving
    // outward along the diagonal crosses both preload boundaries at the same instant.
    let d = 0.1;
    let p = Preset::Fig8a.params().with_preload(d);
    let m = JeffcottModel::new(p).unwrap();
    let r = [d + 0.5f64.sqrt(), d + 0.5f64.sqrt()];
    for v in [[0.2, 0.2], [-0.2, -0.2], [0.2, -0.2], [0.0, 0.0]] {
        let y0 = m.state_at(r, v).unwrap();
        assert!(
            (y0[4] - d).abs() < 1e-12 && (y0[5] - d).abs() < 1e-12,
            "{y0:?}"
        );
        let (t, _) = ok(run(p, y0, 5, SimOptions::default()), "corner");
        let (tt, _) = ok(run(p, y0, 5, tol(1e-13, 1e-15)), "corner tight");
        let (t5, _) = ok(
            run(p, y0, 5, tol(1e-12, 1e-14).with_method(Method::Dopri5)),
            "corner dopri5",
        );
        assert_sane(&t, 2.0, 2.0, "corner");
        let d1 = strobe_diff(&t, &tt);
        let d2 = strobe_diff(&tt, &t5);
        // Nearby starts off the corner give nearby results (the flow is continuous).
        let y1 = m.state_at([r[0] + 1e-9, r[1] - 1e-9], v).unwrap();
        let (t1, _) = ok(run(p, y1, 5, tol(1e-13, 1e-15)), "near corner");
        let d3 = strobe_diff(&tt, &t1);
        assert!(d1 < 1e-7 && d2 < 1e-8, "v = {v:?}: {d1:e} {d2:e}");
        // Outward along the diagonal: see corner_outward_is_continuous_in_the_start.
        if v != [0.2, 0.2] {
            assert!(d3 < 1e-6, "v = {v:?}: {d3:e}");
        }
    }
}

#[test]
fn corner_outward_is_continuous_in_the_start() {
    let d = 0.1;
    let p = Preset::Fig8a.params().with_preload(d);
    let m = JeffcottModel::new(p).unwrap();
    let r = [d + 0.5f64.sqrt(), d + 0.5f64.sqrt()];
    let v = [0.2, 0.2];
    let y0 = m.state_at(r, v).unwrap();
    let (t0, _) = ok(run(p, y0, 5, tol(1e-13, 1e-15)), "corner");
    let first: Vec<u8> = t0.events.iter().take(2).map(|e| e.to).collect();
    for dr in [[1e-9, -1e-9], [-1e-9, 1e-9], [1e-9, 1e-9]] {
        let y1 = m.state_at([r[0] + dr[0], r[1] + dr[1]], v).unwrap();
        let (t1, _) = ok(run(p, y1, 5, tol(1e-13, 1e-15)), "near corner");
        let d3 = strobe_diff(&t0, &t1);
        assert!(
            d3 < 1e-6,
            "offset {dr:?}: {d3:e}; regimes at the corner {first:?}"
        );
    }
}

/// A start in contact with x_s exactly at its preload and an inward velocity `scale` times the
/// one that makes the normal contact force exactly zero (ring damping raised to nu2 = 0.5 so that
/// this speed is moderate): contact loss and the regime boundary coincide at t = 0.
fn loss_at_boundary_runs(scales: &[f64]) -> Vec<Trajectory<U6>> {
    let d = 0.1;
    let p = Params {
        nu2: 0.5,
        ..Preset::Fig8a.params().with_preload(d)
    };
    let m = JeffcottModel::new(p).unwrap();
    let ring = *m.ring();
    let s = Vector2::new(d, 0.05);
    // Inner branches: grad E = 2 K s, so r - s is along s.
    let r = s + s.normalize();
    let c = ring.locate(&r).unwrap();
    assert!((c.s - s).norm() < 1e-12, "{:?}", c.s);
    let n = c.normal;
    let f0 = c.normal_force(&Vector2::zeros());
    let f1 = c.normal_force(&(-n));
    let speed = f0 / (f0 - f1);
    assert!(speed > 0.0 && speed.is_finite(), "{speed}");
    scales
        .iter()
        .map(|&scale| {
            let v = -n * speed * scale;
            let y0 = m.state_at([r.x, r.y], [v.x, v.y]).unwrap();
            let (t, _) = ok(run(p, y0, 4, tol(1e-12, 1e-14)), "loss at boundary");
            assert_sane(&t, 2.0, 5.0, "loss at boundary");
            t
        })
        .collect()
}

#[test]
fn contact_lost_exactly_at_a_regime_boundary() {
    // Finite and bounded whether the start's force is a hair compressive, zero or tensile; with
    // a compressive force contact is lost at once (first event: loss within 1e-9).
    let runs = loss_at_boundary_runs(&[1.0 - 1e-9, 1.0, 1.0 + 1e-9]);
    let first = runs[0].events.first().expect("events");
    assert_eq!(first.kind, guard::LOSS);
    assert!(first.t < 1e-9, "{}", first.t);
}

#[test]
fn tensile_start_in_contact_is_continuous() {
    let runs = loss_at_boundary_runs(&[1.0 - 1e-9, 1.0, 1.0 + 1e-9]);
    let ends: Vec<State> = runs.iter().map(last).collect();
    assert!(
        max_diff(&ends[0], &ends[1]) < 1e-6,
        "{:e}",
        max_diff(&ends[0], &ends[1])
    );
    assert!(
        max_diff(&ends[2], &ends[1]) < 1e-6,
        "{:e}",
        max_diff(&ends[2], &ends[1])
    );
}

#[test]
fn start_inside_contact() {
    let p = Preset::Fig8b.params();
    let m = JeffcottModel::new(p).unwrap();
    for (r, v) in [
        ([1.05, 0.0], [0.0, 0.0]),
        ([0.3, -1.1], [0.5, 0.1]),
        ([1.2, 1.2], [0.0, 0.0]),
    ] {
        let y0 = m.state_at(r, v).unwrap();
        let (t, _) = ok(run(p, y0, 10, SimOptions::default()), "inside");
        let (t5, _) = ok(
            run(p, y0, 10, tol(1e-13, 1e-15).with_method(Method::Dopri5)),
            "inside dopri5",
        );
        assert_sane(&t, 2.5, 3.0, "inside");
        let d = strobe_diff(&t, &t5);
        assert!(d < 1e-7, "r = {r:?}: {d:e}");
    }
    // A ring that is not where contact puts it is a typed error, not a silent fix.
    // (Rotor and ring shifted together tangentially: |r - s| = 1 still, but s is not s*(r).)
    let mut y = m.state_at([1.05, 0.0], [0.0, 0.0]).unwrap();
    y[1] += 1e-3;
    y[5] += 1e-3;
    match run(p, y, 1, SimOptions::default()) {
        Err(f) => assert!(
            matches!(f.error.kind, SimErrorKind::Model(_)),
            "{}",
            f.error
        ),
        Ok(_) => panic!("inconsistent ring accepted"),
    }
}

// ---------------------------------------------------------------------------------------------
// Extreme parameters

#[test]
fn small_and_large_eta() {
    // eta = 0.1: slow forcing of amplitude beta * 0.01, no contact: the closed form applies.
    // Started at rest at the rest position (from the origin the transient would reach the ring).
    let p = Preset::Fig8a.params().with_eta(0.1);
    let y0 = State::from([p.ex, 0.0, 0.0, 0.0, 0.0, 0.0]);
    let (t, _) = ok(run(p, y0, 5, SimOptions::default()), "eta 0.1");
    assert_eq!(contact_events(&t), 0);
    for StrobePoint {
        k,
        t: tk,
        y,
        label: _,
    } in &t.strobe
    {
        let e = free_flight(&p, [p.ex, 0.0, 0.0, 0.0], *tk);
        for i in 0..4 {
            assert!((y[i] - e[i]).abs() < 1e-11, "k = {k}");
        }
    }
    // eta = 0.1 with the rest position beyond the gap (ex = 1.5): slow quasi-static contact.
    let p = Params {
        ex: 1.5,
        ..Preset::Fig8a.params().with_eta(0.1)
    };
    let (t, _) = ok(
        run(p, State::zeros(), 3, SimOptions::default()),
        "eta 0.1 contact",
    );
    let (tt, _) = ok(run(p, State::zeros(), 3, tol(1e-13, 1e-15)), "tight");
    assert!(contact_events(&t) > 0);
    assert_sane(&t, 1.5, 1.0, "eta 0.1 contact");
    assert!(strobe_diff(&t, &tt) < 1e-7);
    // eta = 10: forcing amplitude 11.9, orbit radius ~1.02 about ex = 0.9: contact each period.
    let p = Preset::Fig8a.params().with_eta(10.0);
    let (t, _) = ok(run(p, State::zeros(), 100, SimOptions::default()), "eta 10");
    let (tt, _) = ok(
        run(p, State::zeros(), 100, tol(1e-13, 1e-15)),
        "eta 10 tight",
    );
    assert!(contact_events(&t) > 0);
    assert_sane(&t, 1.5, 5.0, "eta 10");
    let d = strobe_diff(&t, &tt);
    assert!(d < 1e-7, "eta 10: {d:e}");
}

#[test]
fn huge_eccentricity() {
    // Rest position far beyond the gap: the rotor slams into the ring and stays pressed into it.
    // Finite, bounded, and near the static balance. (The comparison with a tighter tolerance
    // is `huge_eccentricity_converges_with_tolerance`.)
    for ex in [10.0, 1e3] {
        let p = Params {
            ex,
            ..Preset::Fig8a.params()
        };
        let (t, s) = ok(run(p, State::zeros(), 10, SimOptions::default()), "huge e");
        // Static balance along x with zero preload (regime V, one unit per axis):
        // (x - ex) + K (x - 1) = 0; the transient overshoots it at most twofold.
        let x_static = (ex + p.kx) / (1.0 + p.kx);
        assert_sane(&t, 2.0 * x_static, 10.0 * ex, "huge e");
        let y = last(&t);
        assert!(
            (y[0] - x_static).abs() < 0.2 * x_static,
            "{} vs {x_static}",
            y[0]
        );
        println!("ex = {ex}: {s:?}");
    }
}

#[test]
fn huge_eccentricity_converges_with_tolerance() {
    for ex in [10.0, 1e3] {
        let p = Params {
            ex,
            ..Preset::Fig8a.params()
        };
        let (t, _) = ok(run(p, State::zeros(), 10, SimOptions::default()), "huge e");
        let (tt, _) = ok(
            run(p, State::zeros(), 10, tol(1e-13, 1e-15)),
            "huge e tight",
        );
        let d = strobe_diff(&t, &tt);
        assert!(d < 1e-7 * ex, "ex = {ex}: {d:e}");
    }
}

#[test]
fn no_contact_mode_inside_the_gap_circle() {
    let p = Params {
        ex: 10.0,
        ..Preset::Fig8a.params()
    };
    let (t, _) = within(60, move || {
        let m = JeffcottModel::new(p).unwrap();
        let plan = OutputPlan {
            t_end: 10.0,
            strobe: None,
            dense: Some(DenseSampling {
                t_start: 0.0,
                dt: 0.005,
            }),
            events: true,
        };
        m.run(0.0, &State::zeros(), &plan, &SimOptions::default())
            .unwrap_or_else(|f| panic!("{}", f.error))
    });
    for s in &t.samples {
        let r = s.y[0].hypot(s.y[1]);
        assert!(
            s.label == 1 || r >= 1.0 - 1e-9,
            "t = {}: regime {} with |r| - 1 = {:e}",
            s.t,
            s.label,
            r - 1.0
        );
    }
}

#[test]
fn no_onset_at_the_instant_of_contact_loss() {
    let p = grazing_params(1.0 + 1e-9);
    let (y0, _) = steady_orbit(&p);
    let n = 50;
    let (t, _) = ok(run(p, y0, n, SimOptions::default()), "outside");
    for w in t.events.windows(2) {
        assert!(
            !(w[0].kind == guard::LOSS && w[1].kind == guard::ONSET && w[1].t == w[0].t),
            "onset at the instant of loss, t = {}",
            w[0].t
        );
    }
    let onsets = t.events.iter().filter(|e| e.kind == guard::ONSET).count();
    assert!(
        onsets as u64 >= n - 1 && onsets as u64 <= n + 1,
        "{onsets} onsets in {n} periods"
    );
}

// ---------------------------------------------------------------------------------------------
// Long runs

fn energy(p: &Params, y: &State) -> f64 {
    0.5 * (y[2] * y[2] + y[3] * y[3]) + 0.5 * ((y[0] - p.ex).powi(2) + (y[1] - p.ey).powi(2))
}

fn long_run(p: Params, y0: State, periods: u64, secs: u64) -> (f64, SimStats) {
    within(secs, move || {
        let m = JeffcottModel::new(p).unwrap();
        let (t, s) = m
            .strobe_range(&y0, 0, periods, &SimOptions::default())
            .unwrap_or_else(|f| panic!("{}", f.error));
        assert_eq!(t.strobe.len() as u64, periods + 1);
        let mut e_max = 0.0f64;
        for StrobePoint {
            k,
            t: _,
            y,
            label: _,
        } in &t.strobe
        {
            assert!(y.iter().all(|v| v.is_finite()), "k = {k}");
            e_max = e_max.max(energy(&p, y));
        }
        (e_max, s)
    })
}

#[test]
fn long_run_short_always_on() {
    // 10^4 periods of the chaotic Fig. 9c scene (contact every period) and 10^5 periods of a
    // non-contact scene (exact free flight): finite, bounded energy.
    let (e, s) = long_run(Preset::Fig9c.params(), State::zeros(), 10_000, 120);
    println!("chaos 1e4 periods: max energy {e:.3}; {s:?}");
    assert!(e < 1.0, "{e}");
    let p = quiet_params();
    let (e, s) = long_run(
        p,
        State::from([p.ex, 0.0, 0.0, 0.0, 0.0, 0.0]),
        100_000,
        120,
    );
    println!("free 1e5 periods: max energy {e:.3}; {s:?}");
    assert_eq!(s.transitions, 0);
    assert!(e < 0.5, "{e}");
}

#[test]
fn long_run_1e5_periods_with_contact() {
    for preset in [Preset::Fig9c, Preset::Fig9d] {
        let (e, s) = long_run(preset.params(), State::zeros(), 100_000, 900);
        println!("{preset} 1e5 periods: max energy {e:.3}; {s:?}");
        assert!(e < 1.0, "{e}");
    }
}

// ---------------------------------------------------------------------------------------------
// Chattering and bad options

#[test]
fn chattering_bound_ends_in_typed_error() {
    // The grazing orbit has two transitions per period; a bound of 1 must stop it with the
    // typed chattering error, carrying the state reached and the partial output.
    let p = grazing_params(1.0 + 1e-9);
    let (y0, _) = steady_orbit(&p);
    let opts = SimOptions::default().with_max_events_per_period(1);
    match run(p, y0, 50, opts) {
        Err(f) => {
            assert!(
                matches!(f.error.kind, SimErrorKind::Chattering { bound: 1, .. }),
                "{}",
                f.error
            );
            assert!(f.error.y.iter().all(|v| v.is_finite()));
            assert!(f.error.t > 0.0 && f.error.t < 50.0 * p.forcing_period());
        }
        Ok((t, _)) => panic!("no chattering error; {} events", t.events.len()),
    }
    // With the default bound the same run succeeds.
    ok(run(p, y0, 50, SimOptions::default()), "default bound");
}

#[test]
fn invalid_options_are_typed_errors() {
    let p = Preset::Fig8a.params();
    for opts in [
        SimOptions::default().with_rtol(f64::NAN),
        SimOptions::default()
            .with_steps_per_period(0)
            .with_method(Method::Rk4),
        SimOptions::default().with_max_step_fraction(0.0),
    ] {
        match run(p, State::zeros(), 1, opts) {
            Err(f) => assert!(
                matches!(
                    f.error.kind,
                    SimErrorKind::InvalidOption { .. } | SimErrorKind::Integrator(_)
                ),
                "{}",
                f.error
            ),
            Ok(_) => panic!("accepted {opts:?}"),
        }
    }
}

#[test]
fn rk4_and_adaptive_agree_on_contact_scene() {
    // Fixed-step RK4 with many steps against DOP853 on the Fig. 8b orbit (independent methods).
    let p = Preset::Fig8b.params();
    let (a, _) = ok(run(p, State::zeros(), 10, tol(1e-12, 1e-14)), "dop853");
    let (b, _) = ok(
        run(
            p,
            State::zeros(),
            10,
            SimOptions::default()
                .with_method(Method::Rk4)
                .with_steps_per_period(4000),
        ),
        "rk4",
    );
    let d = strobe_diff(&a, &b);
    assert!(d < 1e-7, "{d:e}");
}
