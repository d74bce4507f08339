//! Honest answers of the ODE layer and the hybrid driver (issue 16): a root finder that meets
//! NaN says so, the driver's event screen is off by default, outputs never change the
//! trajectory, and a guard that cannot be evaluated stops the run with a typed error.

use jeffcott::numeric::{illinois, NumericError, RootOptions};

/// NaN at an end of the initial bracket: not a bracket (a typed error, no evaluation).
#[test]
fn illinois_nan_at_a_bracket_end_is_not_a_bracket() {
    for (fa, fb) in [(f64::NAN, 1.0), (-1.0, f64::NAN)] {
        let mut calls = 0;
        let r = illinois((0.0, fa), (1.0, fb), &opts(), |t| {
            calls += 1;
            t - 0.5
        });
        assert!(
            matches!(r, Err(NumericError::NotABracket { .. })),
            "fa = {fa}, fb = {fb}: {r:?}"
        );
        assert_eq!(calls, 0);
    }
}

fn opts() -> RootOptions {
    RootOptions::default()
        .with_tol(1e-12)
        .with_max_evaluations(100)
}

/// NaN in the middle of the search: $g(t) = t - 1/2$ except NaN on $(0.45, 0.55)$, bracket
/// $[0, 1]$. The first secant point is $1/2$, where $g$ is NaN: the search cannot tell which
/// side the root is on, so it must stop there, not converged, with the NaN time reported and
/// the last bracket of numbers. (Before the fix the NaN was taken as a sign, the search went
/// on with NaN as an end value and reported convergence.)
#[test]
fn illinois_nan_mid_iteration_is_not_converged() {
    let g = |t: f64| {
        if t > 0.45 && t < 0.55 {
            f64::NAN
        } else {
            t - 0.5
        }
    };
    let r = illinois((0.0, g(0.0)), (1.0, g(1.0)), &opts(), g).unwrap();
    assert!(!r.converged, "{r:?}");
    assert_eq!(r.nan_at, Some(0.5), "{r:?}");
    assert!(!r.g_lo.is_nan() && !r.g_hi.is_nan(), "{r:?}");
    assert!(r.g_lo < 0.0 && r.g_hi > 0.0, "{r:?}");
}

use jeffcott::hybrid::{
    simulate, Flow, ModelError, NoExactModes, OutputPlan, RotorModel, SimOptions, Trajectory,
};
use jeffcott::numeric::Direction;
use jeffcott::ode::Method;
use nalgebra::{SVector, U1};

type V1 = SVector<f64, 1>;

/// A model whose one guard is a function of time only, on a unit forcing period:
/// $g(t) = 1 - b\thinspace u - a\thinspace u^2$, $u = t(1 - t)$, with its exact derivative.
/// On the step $[0, 1]$ the cubic Hermite interpolant of the step's ends is $1 - b\thinspace u$
/// (minimum $1 - b/4$) and the part it cannot see is $a\thinspace u^2$ (at most $a/16$).
struct QuarticGuard {
    b: f64,
    a: f64,
}

impl RotorModel for QuarticGuard {
    type Dim = U1;
    type Mode = ();
    type Segment = NoExactModes;
    type Cache = ();

    fn dim(&self) -> U1 {
        U1
    }
    fn new_cache(&self) {}
    fn initial_mode(&self, _t: f64, _y: &V1) -> Result<(), ModelError> {
        Ok(())
    }
    fn flow(&self, _mode: ()) -> Flow {
        Flow::Integrated
    }
    fn rhs(&self, _mode: (), _t: f64, _y: &V1, dy: &mut V1, _: &()) {
        dy[0] = 0.0;
    }
    fn guard_count(&self, _mode: ()) -> usize {
        1
    }
    fn guard_direction(&self, _mode: (), _i: usize) -> Direction {
        Direction::Falling
    }
    fn guard_value(&self, _: (), _i: usize, t: f64, _y: &V1, _: &()) -> f64 {
        let u = t * (1.0 - t);
        1.0 - self.b * u - self.a * u * u
    }
    fn guard_derivative(&self, _: (), _i: usize, t: f64, _y: &V1, _dy: &V1, _: &()) -> Option<f64> {
        let u = t * (1.0 - t);
        Some(-(self.b + 2.0 * self.a * u) * (1.0 - 2.0 * t))
    }
    fn guard_derivative_needs_rhs(&self) -> bool {
        false
    }
    fn guard_label(&self, _mode: (), _i: usize) -> &'static str {
        "dip"
    }
    fn transition(&self, _mode: (), _guard: usize, _t: f64, _y: &mut V1) -> Result<(), ModelError> {
        Ok(())
    }
    fn start_segment(&self, _: (), _t: f64, _y: &V1) -> NoExactModes {
        NoExactModes
    }
    fn mode_label(&self, _mode: ()) -> u8 {
        0
    }
    fn forcing_period(&self) -> f64 {
        1.0
    }
}

/// The first crossing of the guard of [`QuarticGuard`] (closed form: it has one when
/// $1 - b/4 - a/16 < 0$).
fn quartic_first_root(b: f64, a: f64) -> f64 {
    let u = (-b + (b * b + 4.0 * a).sqrt()) / (2.0 * a);
    0.5 * (1.0 - (1.0 - 4.0 * u).sqrt())
}

/// The events of one run of [`QuarticGuard`] over $[0, 1]$ in one fixed RK4 step (the step
/// is the forcing period), with the driver's options otherwise as given.
fn quartic_events(b: f64, a: f64, base: SimOptions) -> Vec<f64> {
    let model = QuarticGuard { b, a };
    let plan = OutputPlan {
        t_end: 1.0,
        strobe: None,
        dense: None,
        events: true,
    };
    let opts = base.with_method(Method::Rk4).with_steps_per_period(1);
    let mut traj = Trajectory::default();
    simulate(&model, 0.0, &V1::zeros(), &plan, &opts, &mut traj).unwrap();
    traj.events.iter().map(|e| e.t).collect()
}

/// The driver samples every step. The step-end screen of 0.2.0 (removed, issue 16) was sound
/// only while the cubic Hermite interpolant of the step's ends is within half the smaller end
/// value of the guard; here (one step, $b = 2(1 - 10^{-6})$, $a/16 = 1.001/2$) the guard dips
/// $5\cdot10^{-4}$ below zero between the ends, the interpolant stays at $1/2 + 5\cdot10^{-7}$:
/// the ends' test cleared the step. The first crossing is found at its closed-form time.
/// (Before the fix the default had the screen on and the run reported no event.)
#[test]
fn the_driver_default_finds_a_dip_the_step_end_screen_misses() {
    let b = 2.0 * (1.0 - 1e-6);
    let a = 8.0 * (1.0 + 1e-3);
    assert!(
        1.0 - b / 4.0 - a / 16.0 < -4e-4,
        "the guard dips below zero"
    );
    let exact = quartic_first_root(b, a);

    let found = quartic_events(b, a, SimOptions::default());
    assert!(!found.is_empty(), "default options missed the dip");
    assert!((found[0] - exact).abs() < 1e-12, "{} vs {exact}", found[0]);
}

use jeffcott::hybrid::{DenseSampling, StrobeRange};
use jeffcott::paper::{JeffcottModel, State};
use jeffcott::params::Preset;

/// Asking for outputs never changes the trajectory, for every method: 50 forcing periods of
/// the Fig. 8b scene (eta = 3, period 2, contacts with the preload crossed) from rest, once
/// with only the final state and the event log, once with a stroboscopic point every period
/// and dense samples every 0.37 time units as well. The final state and every event time must
/// be bitwise the same. (Before the fix DOPRI5 and RK4 clipped their steps at the strobe
/// times: the final states differed by 4.5e-11 and 1.5e-9.)
#[test]
fn outputs_never_change_the_trajectory() {
    let model = JeffcottModel::new(Preset::Fig8b.params().with_eta(3.0)).unwrap();
    let period = model.params().forcing_period();
    let periods = 50u64;
    let t_end = period * periods as f64;
    let bare = OutputPlan {
        t_end,
        strobe: Some(StrobeRange {
            first: periods,
            last: periods,
        }),
        dense: None,
        events: true,
    };
    let busy = OutputPlan {
        strobe: Some(StrobeRange {
            first: 0,
            last: periods,
        }),
        dense: Some(DenseSampling {
            t_start: 0.1,
            dt: 0.37,
        }),
        ..bare
    };
    for method in Method::ALL {
        let opts = SimOptions::default().with_method(method);
        let (a, sa) = model.run(0.0, &State::zeros(), &bare, &opts).unwrap();
        let (b, sb) = model.run(0.0, &State::zeros(), &busy, &opts).unwrap();
        assert_eq!(b.strobe.len(), periods as usize + 1);
        assert!(b.samples.len() > 100);
        let (ya, yb) = (a.strobe[0].y, b.strobe.last().unwrap().y);
        assert!(
            ya == yb,
            "{method:?}: final states differ by {:e}",
            (ya - yb).norm()
        );
        assert_eq!(sa.steps, sb.steps, "{method:?}: steps");
        assert!(a.events.len() > 10, "{method:?}: contacts");
        let ta: Vec<f64> = a.events.iter().map(|e| e.t).collect();
        let tb: Vec<f64> = b.events.iter().map(|e| e.t).collect();
        assert_eq!(ta, tb, "{method:?}: event times");
    }
}

use jeffcott::hybrid::SimErrorKind;

/// A model whose guard $g = y - 1/2$ (with $y^\prime = 1$, $y(0) = 0$: $g$ crosses zero at
/// $t = 1/2$) cannot be evaluated for $y \in (0.3, 0.7)$: it returns NaN there, as a contact
/// guard does where the ring cannot be placed.
struct NanWindow;

impl RotorModel for NanWindow {
    type Dim = U1;
    type Mode = ();
    type Segment = NoExactModes;
    type Cache = ();

    fn dim(&self) -> U1 {
        U1
    }
    fn new_cache(&self) {}
    fn initial_mode(&self, _t: f64, _y: &V1) -> Result<(), ModelError> {
        Ok(())
    }
    fn flow(&self, _mode: ()) -> Flow {
        Flow::Integrated
    }
    fn rhs(&self, _mode: (), _t: f64, _y: &V1, dy: &mut V1, _: &()) {
        dy[0] = 1.0;
    }
    fn guard_count(&self, _mode: ()) -> usize {
        1
    }
    fn guard_direction(&self, _mode: (), _i: usize) -> Direction {
        Direction::Rising
    }
    fn guard_value(&self, _: (), _i: usize, _t: f64, y: &V1, _: &()) -> f64 {
        if y[0] > 0.3 && y[0] < 0.7 {
            f64::NAN
        } else {
            y[0] - 0.5
        }
    }
    fn guard_label(&self, _mode: (), _i: usize) -> &'static str {
        "window"
    }
    fn transition(&self, _mode: (), _guard: usize, _t: f64, _y: &mut V1) -> Result<(), ModelError> {
        Ok(())
    }
    fn start_segment(&self, _: (), _t: f64, _y: &V1) -> NoExactModes {
        NoExactModes
    }
    fn mode_label(&self, _mode: ()) -> u8 {
        0
    }
    fn forcing_period(&self) -> f64 {
        1.0
    }
}

/// NaN is not an error channel: a guard that cannot be evaluated where the detector needs it
/// stops the run with a typed error naming the guard and the time, and the last good time and
/// state (before the NaN window, where the guard had a value). (Before the fix the NaN samples
/// were skipped and the root finder bracketed the NaN: an event was reported inside the window,
/// at a time where the guard has no value.)
#[test]
fn a_guard_that_cannot_be_evaluated_stops_the_run_with_a_typed_error() {
    let plan = OutputPlan {
        t_end: 1.0,
        strobe: None,
        dense: None,
        events: true,
    };
    for method in Method::ALL {
        let opts = SimOptions::default().with_method(method);
        let mut traj = Trajectory::default();
        let r = simulate(&NanWindow, 0.0, &V1::zeros(), &plan, &opts, &mut traj);
        let e = match r {
            Ok(_) => panic!(
                "{method:?}: no error, events at {:?}",
                traj.events.iter().map(|e| e.t).collect::<Vec<_>>()
            ),
            Err(e) => e,
        };
        match &e.kind {
            SimErrorKind::Guard { guard, t, .. } => {
                assert_eq!(*guard, "window");
                assert!(*t > 0.3 && *t < 0.7, "{e}");
            }
            other => panic!("{method:?}: {other:?}"),
        }
        // The last good point: the start of the step with the NaN, before the window.
        assert!(e.t <= 0.3 && (e.y[0] - e.t).abs() < 1e-12, "{e:?}");
        assert!(traj.events.is_empty(), "{:?}", traj.events);
    }
}

use jeffcott::ring::{Branch, Branches, Kinematics, RingCache, RingError, RingGuard, RingMode};

/// The ring's typed error reaches the driver's error channel: a contact guard of the paper's
/// model (Fig. 8b, ring on its inner branches) asked at the rotor position $r = 0$, the centre
/// of both inner branches, where the branch formulas have no solution, has no value; the ring
/// element says why ([`RingError::NoPlacement`]), and the model hands that error to the driver
/// ([`RotorModel::guard_error`] gives [`ModelError::Ring`]), which puts it in
/// `SimErrorKind::Guard` (the previous test shows the driver's side).
#[test]
fn a_contact_guard_without_a_ring_placement_gives_the_rings_error() {
    let model = JeffcottModel::new(Preset::Fig8b.params()).unwrap();
    let mode = RingMode::Contact(Branches {
        x: Branch::Inner,
        y: Branch::Inner,
    });
    let y = State::from([0.0, 0.0, 0.3, 1.0, 0.0, 0.0]);
    let cache = model.new_cache();
    let k = Kinematics::new([0.0, 0.0], [0.3, 1.0]);
    let ring = model.ring();
    let expected = RingError::NoPlacement { x: 0.0, y: 0.0 };
    let loss = 0; // the loss guard, first of a contact mode
    assert_eq!(ring.guard(&mode, loss), Some(RingGuard::Loss));
    assert!(model.guard_value(mode, loss, 1.0, &y, &cache).is_nan());
    assert_eq!(
        ring.try_guard_value(&mode, RingGuard::Loss, 1.0, &k, &RingCache::default()),
        Err(expected)
    );
    assert_eq!(
        model.guard_error(mode, loss, 1.0, &y, &cache),
        ModelError::Ring {
            t: 1.0,
            source: Box::new(expected)
        }
    );
    // The gap guard needs no placement: it has a value there.
    assert_eq!(
        ring.try_guard_value(&mode, RingGuard::Gap, 1.0, &k, &RingCache::default()),
        Ok(-1.0)
    );
}

use jeffcott::ode::{
    find_first_event, Dop853, EventOptions, EventSet, EventState, Integrator, OdeError, Options,
};

/// Two events on $y^\prime = 1$, $y(0) = 0$: event 0 is $y - \ell$ (rising, at $t = \ell$,
/// `level`); event 1 is $0.7 - y$ except that it has no value (NaN) for $y$ in `nan`.
struct TwoEvents {
    level: f64,
    nan: (f64, f64),
}

impl EventSet<U1> for TwoEvents {
    fn len(&self) -> usize {
        2
    }
    fn direction(&self, i: usize) -> Direction {
        [Direction::Rising, Direction::Falling][i]
    }
    fn value(&self, i: usize, _t: f64, y: &V1) -> f64 {
        match i {
            0 => y[0] - self.level,
            _ if y[0] > self.nan.0 && y[0] < self.nan.1 => f64::NAN,
            _ => 0.7 - y[0],
        }
    }
}

/// One DOP853 step over $[0, 1]$ and the first event on it.
fn first_event(events: &TwoEvents) -> Result<Option<(usize, f64)>, OdeError> {
    let sys = |_t: f64, _y: &V1, dy: &mut V1| dy[0] = 1.0;
    let mut integ = Dop853::new(Options::fixed(1.0)).unwrap();
    integ.reset(&sys, 0.0, &V1::zeros(), false).unwrap();
    integ.step(&sys, 1.0).unwrap();
    let mut st = EventState::new();
    let hit = find_first_event(&mut integ, &sys, events, &EventOptions::default(), &mut st)?;
    Ok(hit.map(|h| (h.index, h.t)))
}

/// An event without a value where the detector needs its sign is an error of the ODE layer,
/// naming the event and the time; one without a value only beyond another event's crossing is
/// not (a contact force once the contact is lost). (Before the fix the first case reported
/// event 1 at the end of the root finder's bracket, at a time where it is not zero.)
#[test]
fn the_detector_reports_an_event_without_a_value_unless_another_crossed_first() {
    // Event 1 crosses at 0.7, inside its NaN window (0.65, 0.75), and nothing else crosses
    // (level 2): the samples at 0.6 and 0.8 bracket the crossing, the root finder meets the NaN.
    let lone = TwoEvents {
        level: 2.0,
        nan: (0.65, 0.75),
    };
    match first_event(&lone) {
        Err(OdeError::EventNotANumber { index: 1, t }) => assert!(t > 0.65 && t < 0.75),
        other => panic!("{other:?}"),
    }
    // NaN beyond y = 1/2, where event 0 crosses first: event 0 at 1/2, no error.
    let after = TwoEvents {
        level: 0.5,
        nan: (0.5, 2.0),
    };
    let (i, t) = first_event(&after).unwrap().unwrap();
    assert_eq!(i, 0);
    assert!((t - 0.5).abs() < 1e-14, "{t}");
}
