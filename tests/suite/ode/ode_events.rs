//! Event detection and location.

use jeffcott::numeric::Direction;
use jeffcott::ode::{
    find_first_event, solve, solve_with, AnyIntegrator, Dop853, EventFns, EventHit, EventOptions,
    EventSet, EventState, Integrator, Method, OdeSystem, Options, Recorder, SolveReport, Stopped,
};
use nalgebra::{Const, SVector, U1, U2};
use std::f64::consts::PI;

type V1 = SVector<f64, 1>;
type V2 = SVector<f64, 2>;

/// $y' = \cos t$, $y(0) = 0$: $y = \sin t$ (a pure quadrature, so the
/// integration error is at round-off level and the event accuracy is the
/// root finder's).
fn quad_sin(t: f64, _y: &V1, dy: &mut V1) {
    dy[0] = t.cos();
}

/// Harmonic oscillator $x'' = -x$.
fn osc(_t: f64, y: &V2, dy: &mut V2) {
    dy[0] = y[1];
    dy[1] = -y[0];
}

/// A list of event functions given by closures.
struct Events<F> {
    fs: Vec<(F, Direction, bool)>,
}

impl<const N: usize, F: Fn(f64, &SVector<f64, N>) -> f64> EventSet<Const<N>> for Events<F> {
    fn len(&self) -> usize {
        self.fs.len()
    }
    fn direction(&self, i: usize) -> Direction {
        self.fs[i].1
    }
    fn terminal(&self, i: usize) -> bool {
        self.fs[i].2
    }
    fn value(&self, i: usize, t: f64, y: &SVector<f64, N>) -> f64 {
        (self.fs[i].0)(t, y)
    }
}

/// Single event $g = y_0$ with optional derivative $\dot g = \dot y_0$.
struct Comp0 {
    dir: Direction,
    terminal: bool,
    with_derivative: bool,
}

impl<const N: usize> EventSet<Const<N>> for Comp0 {
    fn len(&self) -> usize {
        1
    }
    fn direction(&self, _i: usize) -> Direction {
        self.dir
    }
    fn terminal(&self, _i: usize) -> bool {
        self.terminal
    }
    fn value(&self, _i: usize, _t: f64, y: &SVector<f64, N>) -> f64 {
        y[0]
    }
    fn derivative(
        &self,
        _i: usize,
        _t: f64,
        _y: &SVector<f64, N>,
        dy: &SVector<f64, N>,
    ) -> Option<f64> {
        self.with_derivative.then_some(dy[0])
    }
}

fn comp0(dir: Direction, terminal: bool) -> Comp0 {
    Comp0 {
        dir,
        terminal,
        with_derivative: false,
    }
}

/// [`comp0`] with its derivative.
fn comp0_with_derivative(dir: Direction, terminal: bool) -> Comp0 {
    Comp0 {
        with_derivative: true,
        ..comp0(dir, terminal)
    }
}

/// Solves [`quad_sin`] from $y(0) = 0$ over $[0, t_{end}]$ with `events`, recording into `rec`.
#[track_caller]
fn solve_quad_sin(
    integ: &mut impl Integrator<U1>,
    t_end: f64,
    events: &impl EventSet<U1>,
    rec: &mut Recorder<U1>,
) -> SolveReport<U1> {
    solve(integ, &quad_sin, 0.0, &V1::zeros(), t_end, events, rec).unwrap()
}

/// Solves [`osc`] from $(x, x^\prime) = (1, 0)$ ($x = \cos t$) over $[0, t_{end}]$ with
/// `events`, recording into `rec`.
#[track_caller]
fn solve_osc(
    integ: &mut impl Integrator<U2>,
    t_end: f64,
    events: &impl EventSet<U2>,
    rec: &mut Recorder<U2>,
) -> SolveReport<U2> {
    solve(integ, &osc, 0.0, &V2::new(1.0, 0.0), t_end, events, rec).unwrap()
}

/// A DOP853 that has taken one fixed step $[0, h]$ from $y(0) = $ `y0`: a step whose dense
/// output the detector then searches.
#[track_caller]
fn one_step<const N: usize>(
    sys: &impl OdeSystem<Const<N>>,
    y0: SVector<f64, N>,
    h: f64,
) -> Dop853<Const<N>> {
    let mut integ = Dop853::new(Options::fixed(h)).unwrap();
    integ.reset(sys, 0.0, &y0, false).unwrap();
    integ.step(sys, h).unwrap();
    integ
}

/// The first event of `events` on the last step of `integ`, searched with a fresh
/// [`EventState`].
#[track_caller]
fn first_event<const N: usize>(
    integ: &mut impl Integrator<Const<N>>,
    sys: &impl OdeSystem<Const<N>>,
    events: &impl EventSet<Const<N>>,
    opts: &EventOptions,
) -> Option<EventHit<Const<N>>> {
    find_first_event(integ, sys, events, opts, &mut EventState::new())
        .unwrap()
        .copied()
}

#[test]
fn sine_zero_crossings_located_to_machine_precision() {
    for method in [Method::Dop853, Method::Dopri5] {
        let mut integ = AnyIntegrator::new(method, Options::with_tol(1e-14, 1e-15)).unwrap();
        let mut rec = Recorder::default();
        let ev = comp0(Direction::Either, false);
        let rep = solve_quad_sin(&mut integ, 10.0, &ev, &mut rec);
        assert_eq!(rep.stopped, Stopped::Reached);
        // g(0) = 0 at the start does not fire; crossings at pi, 2pi, 3pi.
        let times: Vec<f64> = rec.events.iter().map(|h| h.t).collect();
        println!("{}: events {times:?}", method.name());
        assert_eq!(rec.events.len(), 3, "{times:?}");
        for (k, h) in rec.events.iter().enumerate() {
            let exact = (k + 1) as f64 * PI;
            println!("  error {:.2e}", h.t - exact);
            assert!((h.t - exact).abs() < 1e-14, "{} vs {exact}", h.t);
            let want = if k % 2 == 0 {
                Direction::Falling
            } else {
                Direction::Rising
            };
            assert_eq!(h.direction, want);
            assert_eq!(h.index, 0);
        }
        assert_eq!(rep.stats.events, 3);
    }
}

#[test]
fn oscillator_crossings_with_adaptive_dop853() {
    let mut integ = Dop853::new(Options::with_tol(1e-13, 1e-13)).unwrap();
    let mut rec = Recorder::default();
    let ev = comp0(Direction::Either, false);
    solve_osc(&mut integ, 20.0, &ev, &mut rec);
    assert_eq!(rec.events.len(), 6);
    let mut worst = 0.0f64;
    for (k, h) in rec.events.iter().enumerate() {
        let exact = PI / 2.0 + k as f64 * PI;
        worst = worst.max((h.t - exact).abs());
    }
    println!("worst event time error (x'' = -x, rtol 1e-13, DOP853): {worst:.2e}");
    assert!(worst < 1e-11);
}

#[test]
fn direction_filtering() {
    let mut integ = Dop853::new(Options::with_tol(1e-14, 1e-15)).unwrap();
    let mut rec = Recorder::default();
    solve_quad_sin(&mut integ, 10.0, &comp0(Direction::Rising, false), &mut rec);
    assert_eq!(rec.events.len(), 1);
    assert!((rec.events[0].t - 2.0 * PI).abs() < 1e-14);
    assert_eq!(rec.events[0].direction, Direction::Rising);

    let mut rec = Recorder::default();
    solve_quad_sin(
        &mut integ,
        10.0,
        &comp0(Direction::Falling, false),
        &mut rec,
    );
    let t: Vec<f64> = rec.events.iter().map(|h| h.t).collect();
    assert_eq!(t.len(), 2);
    assert!((t[0] - PI).abs() < 1e-14 && (t[1] - 3.0 * PI).abs() < 1e-14);
}

/// One big fixed step [0, 2] of $y' = 1$ (so $y = t$), events inside it.
fn one_big_step() -> Dop853<U1> {
    let sys = |_t: f64, _y: &V1, dy: &mut V1| dy[0] = 1.0;
    let mut integ = Dop853::new(Options::fixed(2.0)).unwrap();
    integ.reset(&sys, 0.0, &V1::zeros(), false).unwrap();
    integ.step(&sys, 10.0).unwrap();
    assert_eq!(integ.t(), 2.0);
    integ
}

fn unit(_t: f64, _y: &V1, dy: &mut V1) {
    dy[0] = 1.0;
}

#[test]
fn two_events_in_one_step_earliest_wins_and_ties_go_to_lower_index() {
    type F = fn(f64, &V1) -> f64;
    let opts = EventOptions::default();
    // Same sample interval [1.2, 1.6] and different ones; both orders of indices.
    for (a, b) in [(1.5, 1.3), (1.3, 1.5), (0.5, 1.7), (1.7, 0.5)] {
        let mut integ = one_big_step();
        let fa = move |_t: f64, y: &V1| y[0] - a;
        let fb = move |_t: f64, y: &V1| y[0] - b;
        let ev = Events {
            fs: vec![
                (
                    Box::new(fa) as Box<dyn Fn(f64, &V1) -> f64>,
                    Direction::Either,
                    true,
                ),
                (Box::new(fb), Direction::Either, true),
            ],
        };
        let mut st = EventState::new();
        let hit = find_first_event(&mut integ, &unit, &ev, &opts, &mut st)
            .unwrap()
            .copied()
            .unwrap();
        let (want_idx, want_t) = if a < b { (0, a) } else { (1, b) };
        assert_eq!(hit.index, want_idx);
        assert!((hit.t - want_t).abs() < 2e-15, "{} vs {want_t}", hit.t);
        // The next call on the same step resumes after the first hit.
        let hit2 = find_first_event(&mut integ, &unit, &ev, &opts, &mut st)
            .unwrap()
            .copied()
            .unwrap();
        assert_eq!(hit2.index, 1 - want_idx);
        assert!(find_first_event(&mut integ, &unit, &ev, &opts, &mut st)
            .unwrap()
            .copied()
            .is_none());
    }
    // Tie: identical functions -> index 0, deterministically.
    let g: F = |_t, y| y[0] - 1.3;
    let ev = Events {
        fs: vec![
            (g, Direction::Either, true),
            (g, Direction::Either, true),
            (g, Direction::Either, true),
        ],
    };
    for _ in 0..3 {
        let mut integ = one_big_step();
        let hit = first_event(&mut integ, &unit, &ev, &opts).unwrap();
        assert_eq!(hit.index, 0);
    }
}

#[test]
fn event_at_start_time_does_not_refire() {
    // g(0) = 0 exactly.
    let mut integ = Dop853::new(Options::with_tol(1e-14, 1e-15)).unwrap();
    let mut rec = Recorder::default();
    solve_quad_sin(&mut integ, 4.0, &comp0(Direction::Either, true), &mut rec);
    assert_eq!(rec.events.len(), 1);
    assert!((rec.events[0].t - PI).abs() < 1e-14);

    // Start at t = pi with y = sin(pi) = 1.2e-16 > 0: it falls through zero
    // within an ulp of the start; this is the start-time zero, not an event.
    let t0 = PI;
    let y0 = V1::new(PI.sin());
    assert!(y0[0] > 0.0);
    let mut rec = Recorder::default();
    let rep = solve(
        &mut integ,
        &quad_sin,
        t0,
        &y0,
        10.0,
        &comp0(Direction::Falling, true),
        &mut rec,
    )
    .unwrap();
    assert_eq!(rep.stopped, Stopped::Event(0, rep.t));
    assert!((rep.t - 3.0 * PI).abs() < 1e-14, "{}", rep.t);

    // Restart exactly at a previous hit (reset + fresh EventState): the hit
    // does not fire again, the next crossing does.
    let mut integ = Dop853::new(Options::with_tol(1e-14, 1e-15)).unwrap();
    let ev = comp0(Direction::Either, true);
    let opts = EventOptions::default();
    integ.reset(&quad_sin, 0.0, &V1::zeros(), false).unwrap();
    let mut st = EventState::new();
    let mut hits = vec![];
    while integ.t() < 10.0 && hits.len() < 3 {
        integ.step(&quad_sin, 10.0).unwrap();
        if let Some(h) = find_first_event(&mut integ, &quad_sin, &ev, &opts, &mut st)
            .unwrap()
            .copied()
        {
            integ.truncate(&quad_sin, h.t).unwrap();
            let (t, y) = (integ.t(), *integ.y());
            integ.reset(&quad_sin, t, &y, true).unwrap();
            st.reset();
            hits.push(h.t);
        }
    }
    println!("hits with truncate + reset: {hits:?}");
    assert_eq!(hits.len(), 3);
    for (k, t) in hits.iter().enumerate() {
        assert!((t - (k + 1) as f64 * PI).abs() < 1e-14);
    }

    // Same without reset: truncate and continue, the EventState re-arms.
    integ.reset(&quad_sin, 0.0, &V1::zeros(), false).unwrap();
    let mut st = EventState::new();
    let mut hits = vec![];
    while integ.t() < 10.0 {
        integ.step(&quad_sin, 10.0).unwrap();
        if let Some(h) = find_first_event(&mut integ, &quad_sin, &ev, &opts, &mut st)
            .unwrap()
            .copied()
        {
            integ.truncate(&quad_sin, h.t).unwrap();
            hits.push(h.t);
        }
    }
    assert_eq!(hits.len(), 3, "{hits:?}");
}

/// $y' = 2(t-1)$, $y(0) = 1 - 10^{-6}$: $y = (t-1)^2 - 10^{-6}$, a dip of
/// depth $10^{-6}$ below zero around $t = 1$ with roots $1 \pm 10^{-3}$,
/// inside one step $[0, 2]$.
fn dip(t: f64, _y: &V1, dy: &mut V1) {
    dy[0] = 2.0 * (t - 1.0);
}

#[test]
fn grazing_dip_found_with_derivative_missed_without() {
    let depth = 1e-6;
    let make = || {
        let integ = one_step(&dip, V1::new(1.0 - depth), 2.0);
        assert_eq!((integ.t_prev(), integ.t()), (0.0, 2.0));
        integ
    };
    let opts = EventOptions::default();

    // Plain end-point sign check: g(0) > 0 and g(2) > 0, nothing to see.
    let integ = make();
    let g0 = integ.y_prev()[0];
    let g1 = integ.y()[0];
    assert!(g0 > 0.0 && g1 > 0.0, "end points {g0} {g1}");

    // Sampled detector without derivative: all samples positive -> missed.
    let mut integ = make();
    let without = comp0(Direction::Either, true);
    assert!(first_event(&mut integ, &dip, &without, &opts).is_none());

    // With the derivative: found, both roots, to machine precision.
    let mut integ = make();
    let with = comp0_with_derivative(Direction::Either, true);
    let mut st = EventState::new();
    let h1 = find_first_event(&mut integ, &dip, &with, &opts, &mut st)
        .unwrap()
        .copied()
        .expect("dip must be found");
    let r1 = 1.0 - depth.sqrt();
    println!(
        "grazing: first root {} (exact {r1}), error {:.2e}",
        h1.t,
        h1.t - r1
    );
    // The roots are ill-conditioned (|g'| = 2e-3 there) and DOP853's dense
    // output has round-off of a few 1e-16 (its coefficients reach ~500), so
    // the time is accurate to about 1e-16 / 2e-3 * 10.
    assert_eq!(h1.direction, Direction::Falling);
    assert!((h1.t - r1).abs() < 2e-12);
    let h2 = find_first_event(&mut integ, &dip, &with, &opts, &mut st)
        .unwrap()
        .copied()
        .expect("second root");
    let r2 = 1.0 + depth.sqrt();
    assert_eq!(h2.direction, Direction::Rising);
    assert!((h2.t - r2).abs() < 2e-12, "{} vs {r2}", h2.t);

    // Only rising allowed: the second root of the pair is reported.
    let mut integ = make();
    let rising = comp0_with_derivative(Direction::Rising, true);
    let h = first_event(&mut integ, &dip, &rising, &opts).unwrap();
    assert!((h.t - r2).abs() < 2e-12);

    // A dip that stays above zero is not an event.
    let mut integ = one_step(&dip, V1::new(1.0 + depth), 2.0);
    assert!(first_event(&mut integ, &dip, &with, &opts).is_none());
}

/// A guard that leaves its zero at the start to rounding and falls back through it inside the
/// first sample interval (the friction cone's margin of a roll that starts where a slip stops,
/// `fuzz::fuzz_friction`): $g(0) = -6.7\times10^{-16}$, $\dot g(0) = 2.7\times10^{-15}$, reading
/// exactly zero next to the start (its rounding), then the hump $10^{-3}t^2 - 10^{-2}t^3$ whose
/// falling root is $t = 0.1$ (to $10^{-12}$). The grazing search's first probe lands next to
/// the start, where the guard reads zero; only a probe strictly across brackets the falling
/// root, which must be found (it was not: the zero ended the search).
struct LeavesZeroAndFalls;

impl LeavesZeroAndFalls {
    fn g(t: f64) -> f64 {
        if t > 0.0 && t <= 1e-9 {
            return 0.0;
        }
        -6.7e-16 + 2.7e-15 * t + 1e-3 * t * t - 1e-2 * t * t * t
    }
}

impl EventSet<U1> for LeavesZeroAndFalls {
    fn len(&self) -> usize {
        1
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Falling
    }
    fn value(&self, _i: usize, _t: f64, y: &V1) -> f64 {
        Self::g(y[0])
    }
    fn derivative(&self, _i: usize, _t: f64, y: &V1, _dy: &V1) -> Option<f64> {
        let t = y[0];
        Some(2.7e-15 + 2e-3 * t - 3e-2 * t * t)
    }
}

#[test]
fn a_guard_leaving_zero_by_rounding_then_falling_through_it_is_found() {
    let mut integ = one_big_step();
    let opts = EventOptions::default();
    let h = first_event(&mut integ, &unit, &LeavesZeroAndFalls, &opts).expect("the fall");
    println!("the fall at {} (error {:.1e})", h.t, h.t - 0.1);
    assert_eq!(h.direction, Direction::Falling);
    assert!((h.t - 0.1).abs() < 1e-10, "{}", h.t);
}

/// A guard that starts a segment on the right side of zero by its rounding and moving away
/// from it, then crosses back through zero inside the first sample interval: a preload
/// crossing of the ring in modal coordinates (the linear-rotor fuzzer's cases 7449 and 3755
/// of seed `0x00F02210`). On 7449 the new mode's preload distance $|s_x| - D_x$ starts at
/// $-2.6\times10^{-16}$ with $\dot g = -0.7$ and reads $+4.5\times10^{-16}$ a few ulps on (the
/// rounding of a station summed from every mode); on 3755, $-1.1\times10^{-17}$ with
/// $\dot g = -0.009$, and $+6.9\times10^{-18}$ at $5.3\times10^{-15}$, beyond the re-arm
/// window ($3.5\times10^{-15}$). Both have a kink where $s$ passes 0. Here
/// $g = c\thinspace(|t - 0.035| - 0.035) - g_0$, rising root $t = 0.07$, reading a
/// rounding `noise` on a stretch next to the start. The root search from a start that close
/// to zero lands in the rounding, and the crossing was reported there instead of at 0.07
/// (the run then left the preload at once where the reference stays in it for 0.012).
struct LeavesZeroByRoundingAndRises {
    /// $c$.
    slope: f64,
    /// $g_0$.
    offset: f64,
    /// `(a, b, v)`: the guard reads `v` on $(a, b]$.
    noise: (f64, f64, f64),
}

impl LeavesZeroByRoundingAndRises {
    fn g(&self, t: f64) -> f64 {
        let (a, b, v) = self.noise;
        if t > a && t <= b {
            return v;
        }
        self.slope * ((t - 0.035).abs() - 0.035) - self.offset
    }
}

impl EventSet<U1> for LeavesZeroByRoundingAndRises {
    fn len(&self) -> usize {
        1
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Rising
    }
    fn value(&self, _i: usize, _t: f64, y: &V1) -> f64 {
        self.g(y[0])
    }
    fn derivative(&self, _i: usize, _t: f64, y: &V1, _dy: &V1) -> Option<f64> {
        Some(self.slope * (y[0] - 0.035).signum())
    }
}

#[test]
fn a_guard_off_zero_by_rounding_is_found_at_its_root_not_in_its_rounding() {
    let opts = EventOptions::default();
    for guard in [
        LeavesZeroByRoundingAndRises {
            slope: 1.0,
            offset: 2.6e-16,
            noise: (0.0, 1e-14, 4.5e-16),
        },
        LeavesZeroByRoundingAndRises {
            slope: 0.009,
            offset: 1.1e-17,
            noise: (4e-15, 1e-14, 4.5e-17),
        },
    ] {
        let mut integ = one_big_step();
        let h = first_event(&mut integ, &unit, &guard, &opts).expect("rise");
        println!("the rise at {} (error {:.1e})", h.t, h.t - 0.07);
        assert_eq!(h.direction, Direction::Rising);
        assert!((h.t - 0.07).abs() < 1e-10, "slope {}: {}", guard.slope, h.t);
    }
}

#[test]
fn terminal_versus_non_terminal() {
    type F = fn(f64, &V2) -> f64;
    let x: F = |_t, y| y[0];
    let tstop: F = |t, _y| t - 5.0;
    // non-terminal crossings of x, terminal at t = 5
    let ev = Events {
        fs: vec![
            (x, Direction::Either, false),
            (tstop, Direction::Rising, true),
        ],
    };
    let mut integ = Dop853::new(Options::with_tol(1e-12, 1e-12)).unwrap();
    let mut rec = Recorder::with_grid(vec![1.0, 4.0, 6.0]);
    let rep = solve_osc(&mut integ, 10.0, &ev, &mut rec);
    assert_eq!(rep.stopped, Stopped::Event(1, rep.t));
    assert!((rep.t - 5.0).abs() < 1e-14);
    assert_eq!(integ.t(), rep.t);
    // x crosses zero at pi/2 and 3pi/2 before t = 5, then the terminal event.
    let idx: Vec<usize> = rec.events.iter().map(|h| h.index).collect();
    assert_eq!(idx, vec![0, 0, 1]);
    // Outputs only up to the terminal event.
    let ts: Vec<f64> = rec.outputs.iter().map(|o| o.0).collect();
    assert_eq!(ts, vec![1.0, 4.0]);
    assert!((rec.outputs[1].1[0] - 4f64.cos()).abs() < 1e-10);

    // All non-terminal: runs to the end.
    let ev = Events {
        fs: vec![
            (x, Direction::Either, false),
            (tstop, Direction::Rising, false),
        ],
    };
    let mut rec = Recorder::default();
    let rep = solve_osc(&mut integ, 10.0, &ev, &mut rec);
    assert_eq!(rep.stopped, Stopped::Reached);
    assert_eq!(rep.t, 10.0);
    assert_eq!(rec.events.len(), 4); // pi/2, 3pi/2, 5, 5pi/2
}

#[test]
fn inactive_events_are_ignored() {
    struct Switchable(bool);
    impl EventSet<U1> for Switchable {
        fn len(&self) -> usize {
            1
        }
        fn direction(&self, _i: usize) -> Direction {
            Direction::Either
        }
        fn value(&self, _i: usize, _t: f64, y: &V1) -> f64 {
            y[0]
        }
        fn terminal(&self, _i: usize) -> bool {
            false
        }
        fn active(&self, _i: usize) -> bool {
            self.0
        }
    }
    let mut integ = Dop853::new(Options::with_tol(1e-10, 1e-12)).unwrap();
    let mut rec = Recorder::default();
    solve_quad_sin(&mut integ, 10.0, &Switchable(false), &mut rec);
    assert!(rec.events.is_empty());
    solve_quad_sin(&mut integ, 10.0, &Switchable(true), &mut rec);
    assert_eq!(rec.events.len(), 3, "{:?}", rec.events);
}

#[test]
fn event_options_samples_and_tolerance() {
    // A coarse root tolerance is honoured; more samples still find the event.
    let opts = EventOptions::default()
        .with_root_tol(1e-6)
        .with_samples_per_step(16);
    let mut integ = Dop853::new(Options::with_tol(1e-14, 1e-15)).unwrap();
    let mut rec = Recorder::default();
    solve_with(
        &mut integ,
        &quad_sin,
        0.0,
        &V1::zeros(),
        4.0,
        &comp0(Direction::Either, true),
        &opts,
        &mut rec,
    )
    .unwrap();
    let t = rec.events[0].t;
    assert!((t - PI).abs() < 1e-6);
    // post-crossing side: sin(t) <= 0
    assert!(t.sin() <= 1e-15);
}

/// Use from a generic function of the trait: the system is a struct.
struct Pendulum;
impl OdeSystem<U2> for Pendulum {
    fn rhs(&self, _t: f64, y: &V2, dy: &mut V2) {
        dy[0] = y[1];
        dy[1] = -y[0].sin();
    }
}

#[test]
fn pendulum_half_period_by_symmetry() {
    // Released from rest at angle a: crosses zero (falling) at T/4 and comes to
    // rest (velocity rising through 0) at T/2; check 2 * t(x=0) = t(v=0).
    type F = fn(f64, &V2) -> f64;
    let v: F = |_t, y| y[1];
    let x: F = |_t, y| y[0];
    let ev = Events {
        fs: vec![(x, Direction::Falling, false), (v, Direction::Rising, true)],
    };
    let mut integ = Dop853::new(Options::with_tol(1e-13, 1e-13)).unwrap();
    let mut rec = Recorder::default();
    let rep = solve(
        &mut integ,
        &Pendulum,
        0.0,
        &V2::new(2.0, 0.0),
        100.0,
        &ev,
        &mut rec,
    )
    .unwrap();
    let quarter = rec.events[0].t;
    assert_eq!(rec.events.len(), 2);
    assert!((2.0 * quarter - rep.t).abs() < 1e-11, "{quarter} {}", rep.t);
}

/// With an event function of time only ($g = \sin t$), the located time is
/// limited only by the root finder: within 4 ulp of the true root.
#[test]
fn root_finder_reaches_a_few_ulp() {
    let mut integ = Dop853::new(Options::fixed(0.7)).unwrap();
    let ev = Events {
        fs: vec![(|t: f64, _y: &V1| t.sin(), Direction::Either, false)],
    };
    let mut rec = Recorder::default();
    solve(&mut integ, &unit, 0.0, &V1::zeros(), 20.0, &ev, &mut rec).unwrap();
    assert_eq!(rec.events.len(), 6);
    for (k, h) in rec.events.iter().enumerate() {
        let exact = (k + 1) as f64 * PI;
        let ulps = (h.t - exact).abs() / (f64::EPSILON * exact);
        println!("root {k}: error {:.2e} = {ulps:.1} ulp", h.t - exact);
        assert!(ulps <= 4.0);
    }
}

/// Impact times of a ball dropped from height 0.5 under unit gravity with
/// restitution `e`: $t_1 = 1$ ($v_1 = 1$), then flights of $2e^k$.
fn ball_impacts(e: f64, count: usize) -> Vec<f64> {
    let mut t = vec![1.0];
    let mut flight = 2.0 * e;
    while t.len() < count {
        t.push(t[t.len() - 1] + flight);
        flight *= e;
    }
    t
}

/// Runs the hybrid loop of a bouncing ball (impact when $x$ falls through
/// 0, velocity reversed with restitution 0.8, step size kept across
/// impacts) until `count` impacts or the ball is found below the floor;
/// returns the impact times.
fn bouncing_ball(
    method: Method,
    opts: Options<U2>,
    events: &impl EventSet<U2>,
    count: usize,
) -> Vec<f64> {
    let ball = |_t: f64, y: &V2, dy: &mut V2| {
        dy[0] = y[1];
        dy[1] = -1.0;
    };
    let e = 0.8;
    let ev_opts = EventOptions::default();
    let mut integ = AnyIntegrator::new(method, opts).unwrap();
    integ.reset(&ball, 0.0, &V2::new(0.5, 0.0), false).unwrap();
    let mut st = EventState::new();
    let mut impacts = vec![];
    while impacts.len() < count && integ.t() < 20.0 {
        integ.step(&ball, 20.0).unwrap();
        if let Some(h) = find_first_event(&mut integ, &ball, events, &ev_opts, &mut st)
            .unwrap()
            .copied()
        {
            assert_eq!(h.direction, Direction::Falling, "re-fired at {}", h.t);
            integ.truncate(&ball, h.t).unwrap();
            let y = V2::new(h.y[0], -e * h.y[1]);
            integ.reset(&ball, h.t, &y, true).unwrap();
            st.reset();
            impacts.push(h.t);
        } else if integ.y()[0] < -1e-9 {
            break; // fell through the floor: an impact was missed
        }
    }
    impacts
}

/// Hybrid use as in the rotor driver: a bouncing ball with a reset map after
/// every impact and the step size kept, so that steps soon span whole
/// flights (and with a large initial step, the first step after an impact
/// covers many flights). After each reset the floor guard is zero and moving
/// up: it must be armed at once (start-of-segment rule), or an impact inside
/// the first sample interval is missed and the ball falls through the floor
/// (6 of 10 impacts found by the module example before the rule). The event
/// direction is also tried as `Either`, so that a round-off re-crossing
/// right after the reset map would be reported if the re-arming rule
/// failed. 40 impacts against the closed form, to 1e-10.
#[test]
fn bouncing_ball_forty_impacts_with_steps_spanning_flights() {
    let count = 40;
    let exact = ball_impacts(0.8, count);
    let tol = Options::<U2>::with_tol(1e-12, 1e-12);
    let big = tol.with_h_init(Some(10.0)).with_h_max(100.0);
    let cases = [
        (Method::Dop853, tol, "default steps"),
        (Method::Dopri5, tol, "default steps"),
        (Method::Dop853, big, "h_init 10"),
        (Method::Dopri5, big, "h_init 10"),
        (Method::Rk4, Options::fixed(0.37), "fixed 0.37"),
        (Method::Radau5, tol, "default steps"),
        (Method::Radau5, big, "h_init 10"),
    ];
    for (method, opts, label) in cases {
        for dir in [Direction::Falling, Direction::Either] {
            for with_derivative in [false, true] {
                let ev = Comp0 {
                    dir,
                    terminal: true,
                    with_derivative,
                };
                let impacts = bouncing_ball(method, opts, &ev, count);
                let what = format!(
                    "{} {label} {dir:?} derivative {with_derivative}",
                    method.name()
                );
                assert_eq!(impacts.len(), count, "{what}: {impacts:?}");
                let worst = impacts
                    .iter()
                    .zip(&exact)
                    .map(|(a, b)| (a - b).abs())
                    .fold(0.0, f64::max);
                println!(
                    "{what}: {} impacts, worst time error {worst:.2e}",
                    impacts.len()
                );
                assert!(worst < 1e-10, "{what}: worst time error {worst:e}");
            }
        }
    }
}

/// A guard exactly zero at the start of a segment, inside one big step
/// ($y = t - 5t^2$ or its negative on $[0, 2]$, roots 0 and 0.2, the first
/// interior sample at 0.4): it takes the sign of its motion, so a crossing
/// back before the first sample is found in its direction; the departure
/// itself is never an event.
#[test]
fn guard_on_zero_at_the_origin_takes_the_sign_of_its_motion() {
    let up = |t: f64, _y: &V1, dy: &mut V1| dy[0] = 1.0 - 10.0 * t;
    let down = |t: f64, _y: &V1, dy: &mut V1| dy[0] = -1.0 + 10.0 * t;
    let opts = EventOptions::default();
    for with_derivative in [false, true] {
        for (sign, dir, expect) in [
            (1.0, Direction::Falling, Some(Direction::Falling)),
            (1.0, Direction::Either, Some(Direction::Falling)),
            (1.0, Direction::Rising, None),
            (-1.0, Direction::Rising, Some(Direction::Rising)),
            (-1.0, Direction::Either, Some(Direction::Rising)),
            (-1.0, Direction::Falling, None),
        ] {
            let ev = Comp0 {
                dir,
                terminal: true,
                with_derivative,
            };
            let hit = if sign > 0.0 {
                first_event(&mut one_step(&up, V1::zeros(), 2.0), &up, &ev, &opts)
            } else {
                first_event(&mut one_step(&down, V1::zeros(), 2.0), &down, &ev, &opts)
            };
            let case = format!("sign {sign} {dir:?} derivative {with_derivative}");
            assert_eq!(hit.map(|h| h.direction), expect, "{case}");
            if let Some(h) = hit {
                assert!((h.t - 0.2).abs() < 1e-14, "{case}: {}", h.t);
            }
        }
    }
}

/// Sets larger than the old limit of 16 events: every event is considered
/// (event 39 crosses first, event 0 last).
#[test]
fn events_beyond_sixteen_are_all_found() {
    let level = |i: usize| 0.05 * (40 - i) as f64;
    let ev = Events {
        fs: (0..40)
            .map(|i| {
                let c = level(i);
                (
                    Box::new(move |_t: f64, y: &V1| y[0] - c) as Box<dyn Fn(f64, &V1) -> f64>,
                    Direction::Rising,
                    false,
                )
            })
            .collect(),
    };
    let mut integ = one_big_step();
    let mut st = EventState::new();
    let opts = EventOptions::default();
    let mut found = vec![];
    while let Some(h) = find_first_event(&mut integ, &unit, &ev, &opts, &mut st).unwrap() {
        found.push((h.index, h.t));
    }
    assert_eq!(found.len(), 40, "{found:?}");
    for (k, (i, t)) in found.iter().enumerate() {
        assert_eq!(*i, 39 - k);
        assert!((t - level(*i)).abs() < 1e-14, "event {i} at {t}");
    }
    // Through solve, non-terminal: all 40 recorded.
    let mut integ = Dop853::new(Options::fixed(2.0)).unwrap();
    let mut rec = Recorder::default();
    solve(&mut integ, &unit, 0.0, &V1::zeros(), 2.0, &ev, &mut rec).unwrap();
    assert_eq!(rec.events.len(), 40);
}

/// Closures as an event set give the same hits as the equivalent trait
/// implementation.
#[test]
fn event_fns_match_a_trait_implementation() {
    let closures = EventFns::new([Direction::Either], |_i, _t, y: &V2| y[0])
        .with_derivative(|_i, _t, _y: &V2, dy: &V2| dy[0])
        .non_terminal();
    let with_trait = comp0_with_derivative(Direction::Either, false);
    let run = |ev: &dyn Fn(&mut Recorder<U2>, &mut Dop853<U2>)| {
        let mut integ = Dop853::new(Options::with_tol(1e-10, 1e-12)).unwrap();
        let mut rec = Recorder::default();
        ev(&mut rec, &mut integ);
        rec.events
            .iter()
            .map(|h| (h.index, h.t.to_bits(), h.direction))
            .collect::<Vec<_>>()
    };
    let a = run(&|rec, integ| {
        solve_osc(integ, 20.0, &closures, rec);
    });
    let b = run(&|rec, integ| {
        solve_osc(integ, 20.0, &with_trait, rec);
    });
    assert_eq!(a.len(), 6);
    assert_eq!(a, b);
}

/// The dip event with its derivative computed from the time alone
/// ($\dot g = 2(t - 1)$), so the detector need not evaluate the right-hand side.
struct DipFromState;

impl EventSet<U1> for DipFromState {
    fn len(&self) -> usize {
        1
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Either
    }
    fn value(&self, _i: usize, _t: f64, y: &V1) -> f64 {
        y[0]
    }
    fn derivative(&self, _i: usize, t: f64, _y: &V1, _dy: &V1) -> Option<f64> {
        Some(2.0 * (t - 1.0))
    }
    fn derivative_needs_rhs(&self) -> bool {
        false
    }
}

#[test]
fn derivatives_from_the_state_alone_save_right_hand_sides() {
    let depth = 1e-6;
    let run = |with_rhs: bool| {
        let mut integ = one_step(&dip, V1::new(1.0 - depth), 2.0);
        let before = integ.stats().rhs_evals;
        let opts = EventOptions::default();
        let hit = if with_rhs {
            let ev = comp0_with_derivative(Direction::Either, true);
            first_event(&mut integ, &dip, &ev, &opts)
        } else {
            first_event(&mut integ, &dip, &DipFromState, &opts)
        };
        (hit.expect("dip found").t, integ.stats().rhs_evals - before)
    };
    let (t_rhs, evals_rhs) = run(true);
    let (t_state, evals_state) = run(false);
    assert!((t_rhs - t_state).abs() < 2e-12, "{t_rhs} vs {t_state}");
    // Only the dense output's three extra stages remain.
    assert_eq!(evals_state, 3, "{evals_state}");
    assert!(evals_rhs > evals_state, "{evals_rhs} vs {evals_state}");
}

/// $g = y_0 - c$ with its derivative, counting evaluations of $g$.
struct CountingLevel {
    level: f64,
    calls: std::cell::Cell<u32>,
}

impl EventSet<U1> for CountingLevel {
    fn len(&self) -> usize {
        1
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Either
    }
    fn value(&self, _i: usize, _t: f64, y: &V1) -> f64 {
        self.calls.set(self.calls.get() + 1);
        y[0] - self.level
    }
    fn derivative(&self, _i: usize, t: f64, _y: &V1, _dy: &V1) -> Option<f64> {
        Some(2.0 * (t - 1.0))
    }
    fn derivative_needs_rhs(&self) -> bool {
        false
    }
}

#[test]
fn extrema_far_from_zero_are_not_searched_near_ones_are() {
    // y = (t - 1)^2 + y0 - 1 over one step [0, 2]; minimum y0 - 1 at t = 1.
    let calls_for = |clearance: f64| {
        let mut integ = one_step(&dip, V1::new(1.0 + clearance), 2.0);
        let ev = CountingLevel {
            level: 0.0,
            calls: std::cell::Cell::new(0),
        };
        let hit = first_event(&mut integ, &dip, &ev, &EventOptions::default());
        (hit.is_some(), ev.calls.get())
    };
    let samples = EventOptions::default().samples_per_step as u32 + 2;
    // Minimum 0.5 above zero: the samples are evaluated, and the guard once at the extremum
    // of the interpolant of the interval that holds it, which confirms the interpolant.
    assert_eq!(calls_for(0.5), (false, samples + 1));
    // Minimum 1e-3 above zero: the extremum is searched, nothing found.
    let (hit, calls) = calls_for(1e-3);
    assert!(!hit && calls > samples, "{calls}");
    // Minimum 1e-6 below zero: found.
    assert!(calls_for(-1e-6).0);
}

/// The guard $g = y_0$ with its derivative, counting its evaluations.
#[derive(Default)]
struct CountedLevel {
    calls: std::cell::Cell<usize>,
}

impl EventSet<U1> for CountedLevel {
    fn len(&self) -> usize {
        1
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Either
    }
    fn value(&self, _i: usize, _t: f64, y: &V1) -> f64 {
        self.calls.set(self.calls.get() + 1);
        y[0]
    }
    fn derivative(&self, _i: usize, _t: f64, _y: &V1, dy: &V1) -> Option<f64> {
        Some(dy[0])
    }
}

/// One DOP853 step $[0, 1]$ of $y^\prime = g^\prime(t)$, $y(0) = 1$, for the quartic
/// $g(t) = 1 - b\thinspace u - a\thinspace u^2$, $u = t(1 - t)$: the step and its dense output
/// are exact to rounding, $g = 1$ at both ends with $g^\prime = \mp b$, so the cubic Hermite
/// interpolant of the ends is $p = 1 - b\thinspace u$ (minimum $1 - b/4$) and the part it
/// cannot see is $a\thinspace u^2$ (at most $a/16$). Returns the first crossing found and the
/// number of guard evaluations.
fn quartic_step(b: f64, a: f64) -> (Option<f64>, usize) {
    let sys = move |t: f64, _y: &V1, dy: &mut V1| {
        let u = t * (1.0 - t);
        dy[0] = -(b + 2.0 * a * u) * (1.0 - 2.0 * t);
    };
    let mut integ = one_step(&sys, V1::new(1.0), 1.0);
    let ev = CountedLevel::default();
    let opts = EventOptions::default();
    let hit = first_event(&mut integ, &sys, &ev, &opts).map(|h| h.t);
    (hit, ev.calls.get())
}

/// The first root of the quartic of [`quartic_step`] (it has one when $1 - b/4 - a/16 < 0$).
fn quartic_first_root(b: f64, a: f64) -> f64 {
    let u = (-b + (b * b + 4.0 * a).sqrt()) / (2.0 * a);
    0.5 * (1.0 - (1.0 - 4.0 * u).sqrt())
}

/// The dip that the step-end screen of 0.2.0 cleared (issue 16's class S; the screen is
/// removed): the cubic Hermite interpolant of the step's ends sits at $1/2 + 5\cdot10^{-7}$
/// ($b = 2(1 - 10^{-6})$), the part the ends cannot see, $a u^2$, takes the guard
/// $5\cdot10^{-4}$ below zero ($a/16 = 1.001/2$). The samples find its first root at its
/// closed-form time to $10^{-12}$; without the dip ($a = 0$, the same ends) nothing is found,
/// after the 4 interior samples, the end and the guard at the interpolant's extremum.
#[test]
fn a_dip_between_quiet_step_ends_is_found_by_the_samples() {
    let b = 2.0 * (1.0 - 1e-6);
    assert_eq!(quartic_step(b, 0.0), (None, 7));
    let outside = 8.0 * (1.0 + 1e-3);
    assert!(1.0 - b / 4.0 - outside / 16.0 < -4e-4);
    let exact = quartic_first_root(b, outside);
    let found = quartic_step(b, outside).0.expect("the dip is missed");
    assert!((found - exact).abs() < 1e-12, "{found} vs {exact}");
}

/// A guard on zero at the start, moving away from its crossing direction, that comes back
/// through zero (in its allowed direction) sooner than the probe offset
/// $\delta = \max(4w, 2^{-20} s)$ after the origin: $g = t(bt - a)$ with $a = 1$, $b = 10^7$
/// returns at $t^\ast = 10^{-7}$, below $\delta \approx 9.5\times10^{-7}$ on a unit step. The
/// probe alone sees $g(\delta) > 0$ and took the excursion for the start; the detector now halves
/// the offset until it sees the departure, and locates the return.
#[test]
fn a_return_through_zero_inside_the_probe_offset_is_found() {
    let (a, b) = (1.0, 1e7);
    let rhs = move |t: f64, _y: &V1, dy: &mut V1| {
        dy[0] = -a + 2.0 * b * t;
    };
    let events = comp0_with_derivative(Direction::Rising, false);
    let mut integ = AnyIntegrator::new(Method::Dop853, Options::fixed(1.0)).unwrap();
    integ.reset(&rhs, 0.0, &V1::zeros(), false).unwrap();
    integ.step(&rhs, 1.0).unwrap();
    let hit = first_event(&mut integ, &rhs, &events, &EventOptions::default())
        .expect("the return through zero");
    assert_eq!(hit.direction, Direction::Rising);
    let exact = a / b;
    assert!((hit.t - exact).abs() <= 1e-9 * exact, "t = {:e}", hit.t);
}

/// The first crossing of [`CountedLevel`] ($g = y_0$) that the detector finds with one
/// interior sample on one DOP853 step $[0, 1]$ of `sys` from $y(0) = 1$.
#[track_caller]
fn crossing_on_one_sampled_step(sys: &impl OdeSystem<U1>) -> EventHit<U1> {
    let mut integ = one_step(sys, V1::new(1.0), 1.0);
    let opts = EventOptions::default().with_samples_per_step(1);
    first_event(&mut integ, sys, &CountedLevel::default(), &opts).expect("a crossing")
}

/// The first point of the grid $t_k = k \cdot 0.5\times10^{-4}$, $k < 10^4$, where
/// $g(t_k) \le 0$: the first root of `g` to the grid's spacing.
fn first_grid_point_not_above_zero(g: impl Fn(f64) -> f64) -> f64 {
    (0..10_000)
        .map(|k| f64::from(k) * 0.5e-4)
        .find(|&t| g(t) <= 0.0)
        .unwrap()
}

/// A crossing pair that the cubic Hermite interpolant of its sample interval cannot see
/// (issue 16: a preload crossing inside one long step of a loose tolerance, the fuzzer's
/// "contacts on the wrong branch"): one DOP853 step $[0, 1]$, one interior sample, and the
/// guard $g = 1 + \alpha u - \beta u^2$, $u = s(1 - s)$, $s = 2t$, exact on the dense output
/// (a polynomial of degree 4). On the first sample interval $[0, 1/2]$ its ends are $g = 1$
/// with $g^\prime = \pm 2\alpha$, so the interpolant is $1 + \alpha u$ (maximum $1.25$, far
/// from zero), while the guard falls to $1 + \alpha/4 - \beta/16 = -1.25$ in between. The
/// detector checks the interpolant against the guard at its extremum and finds the first
/// root, $u = (\alpha + \sqrt{\alpha^2 + 4\beta})/(2\beta)$ (closed form); before, the pair
/// was skipped and the first root reported was the one in $[1/2, 1]$ ($t = 0.77$).
#[test]
fn a_crossing_pair_the_interpolant_cannot_see_is_found() {
    let (alpha, beta) = (1.0f64, 40.0f64);
    let sys = move |t: f64, _y: &V1, dy: &mut V1| {
        let s = 2.0 * t;
        let u = s * (1.0 - s);
        dy[0] = (alpha - 2.0 * beta * u) * 2.0 * (1.0 - 2.0 * s);
    };
    let hit = crossing_on_one_sampled_step(&sys);
    let u = (alpha + (alpha * alpha + 4.0 * beta).sqrt()) / (2.0 * beta);
    let t_root = 0.25 * (1.0 - (1.0 - 4.0 * u).sqrt());
    assert!(
        (hit.t - t_root).abs() <= 1e-12,
        "{} against {t_root}",
        hit.t
    );
    assert_eq!(hit.direction, Direction::Falling);
}

/// The same with end derivatives of the same sign: on the first sample interval ($s = 2t$)
/// the guard $g = 1 - s/10 + s(1 - s)(1 - 2s) - \beta s^2(1 - s)^2$ has $g^\prime = 0.9$ per
/// unit $s$ at both ends while its value falls from 1 to 0.9, so its interpolant (the cubic
/// part) has two interior extrema, the lower $0.82$ at $s = 0.82$, where the quartic part
/// takes the guard to $-0.98$ ($\beta = 80$). Before, an interval without a derivative sign
/// change was never searched, and the first root reported was one in $[1/2, 1]$. The truth
/// is the polynomial itself: zero at the hit, positive on a fine grid before it.
#[test]
fn a_crossing_pair_between_slopes_of_the_same_sign_is_found() {
    let beta = 80.0f64;
    let g = move |t: f64| {
        let s = 2.0 * t;
        let u = s * (1.0 - s);
        1.0 - 0.1 * s + u * (1.0 - 2.0 * s) - beta * u * u
    };
    let sys = move |t: f64, _y: &V1, dy: &mut V1| {
        let s = 2.0 * t;
        let u = s * (1.0 - s);
        let du = 1.0 - 2.0 * s;
        // d/ds, times ds/dt = 2.
        dy[0] = 2.0 * (-0.1 + du * (1.0 - 2.0 * s) - 2.0 * u - 2.0 * beta * u * du);
    };
    let hit = crossing_on_one_sampled_step(&sys);
    assert!(g(hit.t).abs() <= 1e-12, "g = {:e} at {}", g(hit.t), hit.t);
    let first = first_grid_point_not_above_zero(g);
    assert!((hit.t - first).abs() <= 0.5e-4, "{} against {first}", hit.t);
}

/// The interpolant confirmed in value but not in slope: on the first sample interval
/// ($s = 2t$) the guard $g = 1 + u - \beta u^2 (s - 1/2)$, $u = s(1 - s)$, has ends $g = 1$,
/// $g^\prime = \pm 2$, and at the interpolant's maximum ($s = 1/2$) exactly its value $1.25$;
/// but its slope there is $-\beta/8$ per unit $t$, and on the second half it dips to
/// $1.19 - 1.76\beta/200$ ($\beta = 200$). The check compares the slope too and splits the
/// interval, whose second half holds the crossing. Truth: the polynomial, as above.
#[test]
fn a_crossing_pair_off_the_interpolant_in_slope_only_is_found() {
    let beta = 200.0f64;
    let g = move |t: f64| {
        let s = 2.0 * t;
        let u = s * (1.0 - s);
        1.0 + u - beta * u * u * (s - 0.5)
    };
    let sys = move |t: f64, _y: &V1, dy: &mut V1| {
        let s = 2.0 * t;
        let u = s * (1.0 - s);
        let du = 1.0 - 2.0 * s;
        dy[0] = 2.0 * (du - beta * (2.0 * u * du * (s - 0.5) + u * u));
    };
    let hit = crossing_on_one_sampled_step(&sys);
    assert!(g(hit.t).abs() <= 1e-12, "g = {:e} at {}", g(hit.t), hit.t);
    let first = first_grid_point_not_above_zero(g);
    assert!((hit.t - first).abs() <= 0.5e-4, "{} against {first}", hit.t);
}

/// A guard clearly off zero at the origin whose derivative there is exactly zero, curving
/// into zero within the re-arm window (issue 16, the fuzzer's last class A: an integrated free
/// flight released at a tangential contact loss, its onset guard $h - m$ offset by the onset
/// margin, $h^\prime$ rounded to exactly 0, and the rotor curving into the ring). The detector
/// took a derivative of exactly zero for no derivative, so the guard "may have left zero"
/// (start-of-segment rule 3), and its root, inside the window, was dropped as the zero at the
/// start: the rotor ran on 5.6e-3 gaps beyond the ring. Rule 3 calls a guard on zero only if
/// $|g| \le$ `value_tol` or $g\dot g < 0$ within the window: with $\dot g = 0$ and $g \ne 0$
/// it is armed, and its crossing is an event. Here $g = -m + c\tau^2/2$, $\tau = t - t_0$,
/// exact on the dense output (a quadratic), $t_0 = 10^6$ (window $w \approx 1.8\times10^{-9}$),
/// $m = 10^{-14}$, $c = 10^6$: the root $\tau^\ast = \sqrt{2m/c} = 1.4\times10^{-10}$ (closed
/// form) lies inside the window.
#[test]
fn a_guard_off_zero_with_a_zero_derivative_crossing_inside_the_window_is_found() {
    let (t0, m, c) = (1e6f64, 1e-14f64, 1e6f64);
    let rhs = move |t: f64, _y: &V1, dy: &mut V1| {
        dy[0] = c * (t - t0);
    };
    let events = comp0_with_derivative(Direction::Rising, true);
    let mut integ = AnyIntegrator::new(Method::Dop853, Options::fixed(1.0)).unwrap();
    integ.reset(&rhs, t0, &V1::new(-m), false).unwrap();
    integ.step(&rhs, t0 + 1.0).unwrap();
    let hit = first_event(&mut integ, &rhs, &events, &EventOptions::default())
        .expect("the crossing 1.4e-10 after the origin");
    assert_eq!(hit.direction, Direction::Rising);
    let exact = t0 + (2.0 * m / c).sqrt();
    // Located to the detector's time tolerance, 4 eps |t|.
    assert!(
        (hit.t - exact).abs() <= 4.0 * f64::EPSILON * t0,
        "t - t0 = {:e}, exact {:e}",
        hit.t - t0,
        exact - t0
    );
}

/// Radau5's collocation polynomial satisfies the ODE at its nodes $c_1, c_2, 1$ only; at a
/// step's start its slope is not $f(y_0)$. The oscillator $x^{\prime\prime} = 1 - x$ from its
/// turning point $x(0) = m = 10^{-14}$, $x^\prime(0) = 0$ has the guard $g = x$ at $m$ with a rate
/// along the flow of exactly 0, as a released rotor's onset guard at a tangential contact loss;
/// the exact solution $x = 1 - (1 - m)\cos t$ never reaches zero. On one long step
/// (`rtol` = `atol` = $10^{-2}$, $h = 1$) the collocation polynomial alone started off tangent,
/// fell through zero and came back within the first sample interval (a spurious pair; on the
/// flexible shaft at the same kind of restart it made a contact onset $2\cdot10^{-11}$ after
/// each loss, 1000 transitions and a chattering error where the run has 18). The first step
/// after a reset now leaves the start tangent to $f$: its dense output has slope $f(y_0)$
/// there (one-sided difference over $\delta = 10^{-7}$: within $\delta$, the curvature being
/// about 1), stays positive on a grid of $2^{14}$ points of the first sample interval, as the
/// exact solution does, and the detector reports no event. Before: the slope was
/// $-1.3\cdot10^{-2}$ ("slope -1.33e-2 at the start") and the polynomial crossed zero.
#[test]
fn radau5_dense_output_leaves_a_restart_tangent_to_the_flow() {
    let m = 1e-14;
    let rhs = |_t: f64, y: &V2, dy: &mut V2| {
        dy[0] = y[1];
        dy[1] = 1.0 - y[0];
    };
    let opts = Options::with_tol(1e-2, 1e-2).with_h_init(1.0);
    let mut integ = AnyIntegrator::new(Method::Radau5, opts).unwrap();
    integ.reset(&rhs, 0.0, &V2::new(m, 0.0), false).unwrap();
    integ.step(&rhs, 10.0).unwrap();
    let mut u = V2::zeros();
    let delta = 1e-7;
    integ.dense(&rhs, delta, &mut u);
    let slope = (u[0] - m) / delta;
    assert!(slope.abs() <= delta, "slope {slope:e} at the start, f = 0");
    let t1 = 0.5 * integ.t();
    let below = (1..=1 << 14).map(|k| t1 * k as f64 / 16384.0).find(|&t| {
        integ.dense(&rhs, t, &mut u);
        u[0] <= 0.0
    });
    assert_eq!(below, None, "the dense output crosses zero");
    let events = comp0_with_derivative(Direction::Either, true);
    let eo = EventOptions::default().with_samples_per_step(1);
    let hit = first_event(&mut integ, &rhs, &events, &eo);
    assert!(hit.is_none(), "a spurious event at {:e}", hit.unwrap().t);
}
