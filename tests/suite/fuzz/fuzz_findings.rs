//! Regression tests for the defects the in-process fuzzer (`tests/suite/fuzz/fuzz.rs`) found, one per
//! defect, each from the case it found (shrunk by hand where that kept the failure). Every test
//! failed before its fix (docs/reliability.md, "Defects found").

use crate::rotor;

use jeffcott::hybrid::{
    simulate, DenseSampling, ExactSegment, Flow, GuardCrossing, ModelError, NoExactModes,
    OutputPlan, RotorModel, SimErrorKind, SimOptions, StrobeRange, Trajectory,
};
use jeffcott::nalgebra::{SVector, Vector2, U1, U6};
use jeffcott::numeric::Direction;
use jeffcott::ode::Method;
use jeffcott::paper::FreeOscillator;
use jeffcott::paper::{guard, JeffcottModel, State};
use jeffcott::params::Params;
use jeffcott::ring::onset::{find_onset, Onset, OnsetStats};
use jeffcott::ring::{Kinematics, Relaxation, RingAxis, RingGuard, RingMode, SnubberRing};

/// A plan over `periods` forcing periods from `t0 = 0` with strobes and events.
fn plan(p: &Params, periods: u64) -> OutputPlan {
    OutputPlan {
        t_end: p.forcing_period() * periods as f64,
        strobe: Some(StrobeRange {
            first: 0,
            last: periods,
        }),
        dense: None,
        events: true,
    }
}

/// The fuzzer's plan (`check_run` in `fuzz.rs`): `periods` forcing periods from `t0`, a strobe
/// at every whole period in that span, events, and dense samples `per_period` times a period
/// from `t0` if asked.
fn fuzzed_plan(p: &Params, t0: f64, periods: f64, per_period: Option<f64>) -> OutputPlan {
    let period = p.forcing_period();
    let t_end = t0 + periods * period;
    OutputPlan {
        t_end,
        strobe: Some(StrobeRange {
            first: (t0 / period).ceil() as u64,
            last: (t_end / period).floor() as u64,
        }),
        dense: per_period.map(|n| DenseSampling {
            t_start: t0,
            dt: period / n,
        }),
        events: true,
    }
}

/// `[rad cos(ang), rad sin(ang)]`: a position or velocity as the fuzzer draws it (`fuzz.rs`).
fn polar(rad: f64, ang: f64) -> [f64; 2] {
    [rad * ang.cos(), rad * ang.sin()]
}

/// The fuzzer's `Contact` start (`build_start` in `fuzz.rs`): the rotor $10^{-12}$ beyond the
/// gap circle at the angle `ang`, moving at `speed` in the direction `dir`, the ring at its
/// minimum-energy position.
fn contact_start(m: &JeffcottModel, ang: f64, speed: f64, dir: f64) -> State {
    m.state_at(polar(1.0 + 1e-12, ang), polar(speed, dir))
        .unwrap()
}

/// Runs `model` from `(t0, y0)` into a new trajectory and returns what it recorded; an error
/// ending goes to `on_error` first, which panics unless the test allows that error.
fn run_recorded<M: RotorModel<Dim = U6>>(
    model: &M,
    t0: f64,
    y0: &State,
    plan: &OutputPlan,
    opts: &SimOptions,
    on_error: impl FnOnce(&SimErrorKind),
) -> Trajectory<U6> {
    let mut traj = Trajectory::default();
    if let Err(e) = simulate(model, t0, y0, plan, opts, &mut traj) {
        on_error(&e.kind);
    }
    traj
}

// ---------------------------------------------------------------------------------------------
// 1. The onset search's touching start ignored the size of the closed form's terms.

/// A rest position 390 gaps out (nu2 = 0): the rotor reaches the ring at speed 24, the contact
/// is lost, and at the loss the closed form's terms (size ~780) round |r - s|^2 - 1 to
/// +4.5e-14, above the old touching tolerance 16 eps (|r| + |s|) = 3.5e-15. The separating
/// start then fired at once, the touch released the ring again, and the run ended in a false
/// `Stalled` (64 touches at one instant) where free flight parts from the ring.
fn far_rest_position() -> Params {
    Params {
        eta: 0.6625724844423002,
        nu1: 3.1129335939898386,
        nu2: 0.0,
        kx: 17.39548676458057,
        ky: 1217.5932394137853,
        beta: 0.04421381400040251,
        dx: 1.5985144703209029,
        dy: 1.5985144703209029,
        ex: 0.0,
        ey: 389.83665393624375,
        phi0: 3712.6836424090775,
    }
}

#[test]
fn separating_start_at_the_rounding_of_large_closed_form_terms_does_not_fire() {
    let p = far_rest_position();
    let m = JeffcottModel::new(p).unwrap();
    // The state at the loss: on the circle to the closed form's rounding, moving inward at 17.
    let t = 0.15624748391902768;
    let y = [
        0.0001272219034951596,
        0.9999999919072932,
        0.001380339154341887,
        -17.158464678535783,
    ];
    let flight = FreeOscillator::new(&p).segment(t, &y);
    let mut stats = OnsetStats::default();
    let found = find_onset(
        &flight,
        &Relaxation::at_rest(t),
        m.ring(),
        (t, t + 0.1),
        true,
        &mut stats,
    );
    // It comes back under its acceleration of 496 after about 17/248 = 0.069.
    match found {
        Onset::At(t1) => assert!(t1 > t + 0.05 && t1 < t + 0.09, "onset at {t1}"),
        Onset::None => panic!("the rotor comes back to the ring within the window"),
    }
}

#[test]
fn far_rest_position_runs_without_a_false_stall() {
    let p = far_rest_position();
    let m = JeffcottModel::new(p).unwrap();
    let y0 = m
        .state_at(
            polar(4.970798185389594e-7, 5.468350507140654),
            polar(8.060840684843925e-5, 3.2593507045458265),
        )
        .unwrap();
    let opts = SimOptions::default()
        .with_method(Method::Dopri5)
        .with_rtol(1.1237947268150232e-9)
        .with_atol(8.222976445674338e-14)
        .with_max_step_fraction(0.5182073218068742)
        .with_event_samples(41);
    let (traj, stats) = m
        .run(0.0, &y0, &plan(&p, 1), &opts)
        .unwrap_or_else(|f| panic!("{}", f.error));
    assert_eq!(traj.strobe.len(), 2);
    // A handful of contacts (measured: 5 transitions), not a pile of touches at one instant.
    assert!(
        stats.transitions >= 3 && stats.transitions <= 20,
        "{stats:?}"
    );
    assert!(traj.events.iter().any(|e| e.kind == guard::LOSS));
}

// ---------------------------------------------------------------------------------------------
// 2. A touch without ring damping decided by a load rate that vanishes by symmetry.

/// Without ring damping a rotor at rest on the circle, pushed outward, meets the relaxed ring
/// with zero load and a load rate that is exactly zero (the central difference is symmetric):
/// the touch was rejected, the onset fired again one ulp later, and the run ended in a false
/// `Stalled` at t = 3e-322. The load grows from its minimum: contact starts.
#[test]
fn touch_at_rest_on_the_circle_starts_contact_when_pushed_outward() {
    let ring = SnubberRing::new(
        RingAxis::new(0.0076, 0.023),
        RingAxis::new(0.0076, 0.0),
        0.0,
        1.0,
    )
    .unwrap();
    let free = RingMode::free(Relaxation::at_rest(0.0));
    let k = Kinematics::new([0.0, 1.0], [0.0, 0.0]);
    for (push, contact) in [(1.0, true), (-1.0, false)] {
        let next = ring
            .transition(&free, RingGuard::Onset, 0.0, &k, |f| {
                Vector2::new(0.0, push) - f
            })
            .unwrap();
        assert_eq!(next.mode.is_contact(), contact, "push {push}: {next:?}");
    }
}

#[test]
fn rotor_at_rest_on_the_circle_runs_into_contact() {
    let p = Params {
        eta: 13.650920802696696,
        nu1: 0.05671757645996835,
        nu2: 0.0,
        kx: 0.007569438357994995,
        ky: 0.007569438357994995,
        beta: 0.22677848281592133,
        dx: 0.023471471235399378,
        dy: 0.0,
        ex: 0.3405069466437222,
        ey: 0.0,
        phi0: -4628.288089005627,
    };
    let m = JeffcottModel::new(p).unwrap();
    let y0 = m.state_at([0.0, 1.0], [0.0, 0.0]).unwrap();
    let (traj, _) = m
        .run(0.0, &y0, &plan(&p, 1), &SimOptions::default())
        .unwrap_or_else(|f| panic!("{}", f.error));
    let first = traj.events.first().expect("a contact");
    assert_eq!((first.t, first.kind, first.from), (0.0, guard::ONSET, 1));
    assert!(first.to > 1, "{first:?}");
}

// ---------------------------------------------------------------------------------------------
// 3. An event located on a dense output that is not finite.

/// The finding: DOP853 with rtol = 1 on a rotor whose cubic bearing, 790 gaps from its rest
/// position, is stiff beyond resolution. A step was accepted with finite ends while the dense
/// output inside it overflowed (its extra stages), and the guard located there handed a NaN
/// state to the transition: `Model(Transition)` with "no ring placement at r = (NaN, NaN)"
/// and a NaN "last good state". It is `NonFinite`, with the finite state at the start of that
/// step. With DOP853's error estimate per component that rotor's run no longer accepts such
/// a step (it chatters, with 1 to 32 samples a step and `atol` from $10^{-7}$ to 1; so does
/// DOPRI5), so the situation is built here directly: a clock $y^\prime = 1$ whose right-hand
/// side overflows on a window of $y$ that only the dense output's stage at $c = 7/9$ of one
/// step reaches (the step's own stages lie at $c \le 0.6513$ and $c \ge 0.857$ around it),
/// with a guard crossing inside that step.
struct DenseOverflow {
    /// The window of $y$ where the right-hand side is infinite.
    window: (f64, f64),
    /// Where the guard $y - $ `crossing` rises through zero.
    crossing: f64,
    /// The times of the right-hand side's evaluations.
    calls: std::sync::Mutex<Vec<f64>>,
}

impl RotorModel for DenseOverflow {
    type Dim = U1;
    type Mode = u8;
    type Segment = NoExactModes;
    type Cache = ();

    fn dim(&self) -> U1 {
        U1
    }
    fn new_cache(&self) {}
    fn initial_mode(&self, _t: f64, _y: &SVector<f64, 1>) -> Result<u8, ModelError> {
        Ok(1)
    }
    fn flow(&self, _mode: u8) -> Flow {
        Flow::Integrated
    }
    fn rhs(&self, _m: u8, t: f64, y: &SVector<f64, 1>, dy: &mut SVector<f64, 1>, _c: &()) {
        self.calls.lock().unwrap().push(t);
        let inside = y[0] > self.window.0 && y[0] < self.window.1;
        dy[0] = if inside { f64::INFINITY } else { 1.0 };
    }
    fn guard_count(&self, _mode: u8) -> usize {
        1
    }
    fn guard_direction(&self, _mode: u8, _i: usize) -> Direction {
        Direction::Rising
    }
    fn guard_value(&self, _m: u8, _i: usize, _t: f64, y: &SVector<f64, 1>, _c: &()) -> f64 {
        y[0] - self.crossing
    }
    fn guard_label(&self, _mode: u8, _i: usize) -> &'static str {
        "mark"
    }
    fn transition(
        &self,
        mode: u8,
        _g: usize,
        _t: f64,
        _y: &mut SVector<f64, 1>,
    ) -> Result<u8, ModelError> {
        Ok(mode + 1)
    }
    fn start_segment(&self, _mode: u8, _t: f64, _y: &SVector<f64, 1>) -> NoExactModes {
        NoExactModes
    }
    fn mode_label(&self, mode: u8) -> u8 {
        mode
    }
    fn forcing_period(&self) -> f64 {
        1.0
    }
}

#[test]
fn event_on_a_non_finite_dense_output_is_non_finite_with_a_good_last_state() {
    let plan = OutputPlan {
        t_end: 2.0,
        strobe: None,
        dense: None,
        events: true,
    };
    let opts = SimOptions::default().with_method(Method::Dop853);
    let run = |m: &DenseOverflow| simulate(m, 0.0, &SVector::zeros(), &plan, &opts, &mut ());
    // A first run without the window: its steps, from the dense output's stages
    // (t0 + h/10, t0 + h/5, t0 + 7h/9, evaluated in turn when the event scan samples a step).
    let clock = DenseOverflow {
        window: (f64::NAN, f64::NAN),
        crossing: 10.0,
        calls: Default::default(),
    };
    run(&clock).expect("the clock runs");
    let calls = clock.calls.into_inner().unwrap();
    let (t0, h) = calls
        .windows(3)
        .map(|w| (w[0] - (w[1] - w[0]), 10.0 * (w[1] - w[0]), w[2]))
        .find(|&(t0, h, c)| t0 > 0.5 && h > 0.0 && (c - (t0 + 7.0 * h / 9.0)).abs() < 1e-9 * h)
        .map(|(t0, h, _)| (t0, h))
        .expect("a step's dense output stages");
    // The same steps up to that one (the clock's y is its time), which now overflows inside.
    let model = DenseOverflow {
        window: (t0 + 0.74 * h, t0 + 0.82 * h),
        crossing: t0 + 0.5 * h,
        calls: Default::default(),
    };
    let e = run(&model).unwrap_err();
    assert_eq!(e.kind, SimErrorKind::NonFinite, "{e}");
    assert!(
        e.t.is_finite() && e.y.iter().all(|v| v.is_finite()),
        "{e:?}"
    );
    // At the start of that step (a window that the step's own stages reach fails elsewhere:
    // measured, at 0.72 for the step at 0.62).
    assert!(
        (e.t - t0).abs() < 1e-9 && e.y[0] < t0 + 0.5 * h,
        "{e:?} for the step at {t0}"
    );
}

// ---------------------------------------------------------------------------------------------
// 4. Chattering reported at an instant where the run then stalls.

/// Exact modes numbered by the transitions so far: the first `advancing` transitions are
/// 0.01 apart, every later one a single ulp after the previous.
struct Slowdown {
    advancing: u32,
}

struct SlowdownSegment {
    next: f64,
}

impl ExactSegment<U1> for SlowdownSegment {
    fn eval(&self, _t: f64, _y: &mut SVector<f64, 1>, dy: &mut SVector<f64, 1>) {
        dy.fill(0.0);
    }
    fn next_guard(&mut self, _t_from: f64, t_to: f64) -> Option<GuardCrossing> {
        (self.next <= t_to).then_some(GuardCrossing {
            guard: 0,
            t: self.next,
        })
    }
    fn evaluations(&self) -> u64 {
        0
    }
}

impl RotorModel for Slowdown {
    type Dim = U1;
    type Mode = u32;
    type Segment = SlowdownSegment;
    type Cache = ();

    fn dim(&self) -> U1 {
        U1
    }
    fn new_cache(&self) {}
    fn initial_mode(&self, _t: f64, _y: &SVector<f64, 1>) -> Result<u32, ModelError> {
        Ok(0)
    }
    fn flow(&self, _mode: u32) -> Flow {
        Flow::Exact
    }
    fn rhs(&self, _m: u32, _t: f64, _y: &SVector<f64, 1>, dy: &mut SVector<f64, 1>, _c: &()) {
        dy.fill(0.0);
    }
    fn guard_count(&self, _mode: u32) -> usize {
        1
    }
    fn guard_direction(&self, _mode: u32, _i: usize) -> Direction {
        Direction::Rising
    }
    fn guard_value(&self, _m: u32, _i: usize, _t: f64, _y: &SVector<f64, 1>, _c: &()) -> f64 {
        -1.0
    }
    fn guard_label(&self, _mode: u32, _i: usize) -> &'static str {
        "tick"
    }
    fn transition(
        &self,
        mode: u32,
        _g: usize,
        _t: f64,
        _y: &mut SVector<f64, 1>,
    ) -> Result<u32, ModelError> {
        Ok(mode + 1)
    }
    fn start_segment(&self, mode: u32, t: f64, _y: &SVector<f64, 1>) -> SlowdownSegment {
        SlowdownSegment {
            next: if mode < self.advancing {
                t + 0.01
            } else {
                t.next_up()
            },
        }
    }
    fn mode_label(&self, _mode: u32) -> u8 {
        0
    }
    fn forcing_period(&self) -> f64 {
        1.0
    }
}

fn slowdown(advancing: u32, bound: u32) -> Result<u64, SimErrorKind> {
    let plan = OutputPlan {
        t_end: 2.0,
        strobe: None,
        dense: None,
        events: false,
    };
    let opts = SimOptions::default().with_max_events_per_period(bound);
    simulate(
        &Slowdown { advancing },
        0.0,
        &SVector::zeros(),
        &plan,
        &opts,
        &mut (),
    )
    .map(|s| s.transitions)
    .map_err(|e| e.kind)
}

/// Ten transitions 0.01 apart, then transitions one ulp apart at t = 0.1. With a chattering
/// bound of 12 the old driver reported chattering at t = 0.1, where every larger bound ends in
/// `Stalled` at the same instant: the advice "raise max_events_per_period" was false. Now the
/// stall guard decides while time does not advance.
#[test]
fn chattering_is_not_reported_where_the_run_stalls() {
    for bound in [12, 30, 1000] {
        match slowdown(10, bound) {
            Err(SimErrorKind::Stalled { t, .. }) => {
                assert!((t - 0.1).abs() < 1e-12, "bound {bound}: {t}");
            }
            other => panic!("bound {bound}: {other:?}"),
        }
    }
    // Transitions that keep advancing time are still chattering, and a larger bound runs.
    assert!(matches!(
        slowdown(u32::MAX, 50),
        Err(SimErrorKind::Chattering { bound: 50, .. })
    ));
    let n = slowdown(u32::MAX, 150).unwrap();
    assert!((199..=200).contains(&n), "{n}");
}

// ---------------------------------------------------------------------------------------------
// 5. A single transition at the start instant reported as a stall under a low chattering bound.

/// With `max_events_per_period = 1` the stall bound was lowered to 1, so the contact onset of a
/// start on the gap circle moving outward (a transition at the start instant, as it must be)
/// ended the run at once in `Stalled { transitions: 1 }`, whose advice ("raising
/// max_events_per_period will not help") was false. A stall now needs 64 transitions at one
/// instant whatever the bound; the low bound gives chattering once time advances.
#[test]
fn one_transition_at_the_start_is_not_a_stall() {
    let p = Params::default();
    let m = JeffcottModel::new(p).unwrap();
    let y0 = m.state_at([0.0, 1.0], [0.0, 0.5]).unwrap();
    let run = |bound: u32| {
        let opts = SimOptions::default().with_max_events_per_period(bound);
        m.run(0.0, &y0, &plan(&p, 2), &opts)
    };
    match run(1) {
        Err(f) => match f.error.kind {
            SimErrorKind::Chattering { bound: 1, .. } => assert!(f.error.t > 0.0, "{}", f.error),
            other => panic!("{other}"),
        },
        Ok((traj, _)) => panic!(
            "more than one transition per period expected: {:?}",
            traj.events.len()
        ),
    }
    let (traj, _) = run(1000).unwrap_or_else(|f| panic!("{}", f.error));
    assert_eq!(traj.events[0].t, 0.0);
    assert!(traj.events[0].to > 1);
}

// ---------------------------------------------------------------------------------------------
// 6. The ring's location under extreme anisotropy depended on the warm start.

/// With $K_y/K_x = 10^7$ the multiplier solver stopped on a Newton step relative to the stiff
/// axis, which left the soft axis' position off by up to 5e-7, differently for each warm start:
/// the guards (warm-started from the cache) and the transitions (cold) placed the ring
/// differently, and a preload of 1e-10 was "crossed" at a contact's start (a fuzz case ran a
/// contact in regime II with the ring beyond its y preload). The tolerance is now relative to
/// the soft axis: warm and cold starts agree to rounding.
#[test]
fn ring_location_does_not_depend_on_the_warm_start_under_extreme_anisotropy() {
    let ring = SnubberRing::new(
        RingAxis::new(1e-3, 0.3),
        RingAxis::new(1e4, 1e-10),
        0.0,
        1.0,
    )
    .unwrap();
    let b = jeffcott::ring::Branches {
        x: jeffcott::ring::Branch::Inner,
        y: jeffcott::ring::Branch::Inner,
    };
    let mut worst = 0.0f64;
    for i in 0..2000 {
        let ang = i as f64 * 0.0031;
        let rad = 1.0 + 1e-9 * (i % 13) as f64 + 0.01 * (i % 7) as f64;
        let r = Vector2::new(rad * ang.cos(), rad * ang.sin());
        let cold = ring.locate_on(&r, b, f64::NAN).unwrap();
        for hint in [
            cold.mu * (1.0 + 1e-3),
            cold.mu + 1.0,
            cold.mu - 1e-6,
            0.0,
            1e4,
        ] {
            let warm = ring.locate_on(&r, b, hint).unwrap();
            worst = worst.max((warm.s - cold.s).norm());
        }
    }
    // Measured 3.8e-14 (before: 4.9e-7).
    assert!(worst <= 1e-12, "warm and cold starts differ by {worst:e}");
}

// ---------------------------------------------------------------------------------------------
// 7. The onset lost at a touching start of an integrated free flight (open defect A before
//    0.2.0: `RingMode::Free::onset_margin`, `SnubberRing::start_mode`).

/// Runs the custom rotor (`examples/custom_rotor`, integrated free flight) from `(t0, y0)` over
/// `periods` forcing periods, with dense samples, and returns the largest $|r - s| - \gamma$ at
/// a free-flight sample (the rotor beyond the ring in free flight, which must not happen) and
/// the number of contact onsets.
fn free_excursion(
    p: Params,
    (q, k3): (f64, f64),
    opts: &SimOptions,
    t0: f64,
    y0: [f64; 6],
    periods: f64,
) -> (f64, usize) {
    let m = rotor::on_ring(p, q, k3).unwrap();
    let plan = OutputPlan {
        strobe: None,
        ..fuzzed_plan(&p, t0, periods, Some(400.0))
    };
    let traj = run_recorded(&m, t0, &y0.into(), &plan, opts, below_resolution_or_panic);
    let beyond = traj
        .samples
        .iter()
        .filter(|s| s.label == 1)
        .map(|s| Vector2::new(s.y[0] - s.y[4], s.y[1] - s.y[5]).norm() - 1.0)
        .fold(f64::NEG_INFINITY, f64::max);
    let onsets = traj
        .events
        .iter()
        .filter(|e| e.kind == guard::ONSET)
        .count();
    (beyond, onsets)
}

/// A start on the gap circle moving outward (h = 2e-16, h' = 1.5e-3) at t0 = 6.3e5: the free
/// mode's onset guard started on zero and left it rising, which the event detector takes for
/// the zero at the start time. Within one period the rotor was 1.4e3 gaps beyond the ring in
/// free flight, silently.
/// The start now begins with the touch.
#[test]
fn start_on_the_circle_moving_outward_touches_the_ring() {
    let p = Params {
        eta: 1.8179278340216039,
        nu1: 1.0,
        nu2: 0.007782008966853292,
        kx: 3.701706024710605,
        ky: 0.5074476428029424,
        beta: 0.0,
        dx: 1.0072198085363526,
        dy: 2.879600630688667e-6,
        ex: 718.6830919807579,
        ey: 1.1722783136046109,
        phi0: 1.3080873171970364,
    };
    let y0 = [
        0.9997984176485873,
        0.020077949780318082,
        0.0007384722117438068,
        -3.052862605027371e-5,
        0.0,
        0.0,
    ];
    let (beyond, onsets) = free_excursion(
        p,
        (0.40296995592105744, 0.09172919400476057),
        &SimOptions::default(),
        633724.2048084231,
        y0,
        1.0,
    );
    assert!(
        beyond <= 1e-9,
        "rotor {beyond:e} beyond the ring in free flight"
    );
    assert!(onsets >= 1 || beyond < 0.0, "{onsets} onsets");
}

/// Contact with heavy cross coupling and a cubic bearing, lost and touched again without load
/// (a touch that did not start contact, h' = -1.8e-7 after it): the rotor then curves back
/// into the ring with a dip of h far below the detector's probe. The onset guard left zero
/// falling and came back within the probe, unseen, and the rotor ran 0.97 gaps into the ring in
/// free flight. The onset guard of a free flight that starts touching now starts below zero by
/// its margin.
#[test]
fn rotor_curving_back_after_a_touch_without_load_meets_the_ring() {
    let p = Params {
        eta: 0.7651912693916786,
        nu1: 0.056515211043435314,
        nu2: 0.07964026905513193,
        kx: 0.04371170298873562,
        ky: 0.04371170298873562,
        beta: 0.4968970340362575,
        dx: 0.0,
        dy: 1.1553842745742553e-8,
        ex: -0.37735206776232294,
        ey: 0.0,
        phi0: 0.8014996661189521,
    };
    let y0 = [
        -1.000000000001,
        1.224646799148578e-16,
        -0.007571582240769815,
        0.0021629727941379065,
        -1.000088900582341e-12,
        6.123532776778104e-29,
    ];
    let opts = SimOptions::default()
        .with_method(Method::Dopri5)
        .with_rtol(1.0569511298034146e-6)
        .with_atol(3.070137861527155e-8);
    let (beyond, _) = free_excursion(
        p,
        (-0.47048397918170715, 1.868724081889459),
        &opts,
        0.0,
        y0,
        3.0,
    );
    assert!(
        beyond <= 1e-9,
        "rotor {beyond:e} beyond the ring in free flight"
    );
}

// ---------------------------------------------------------------------------------------------
// 8. A preload the ring passes within the time resolution (open defect D before 0.2.0:
//    `ode` (Events) rule 4 limited to zeros at the start, `SnubberRing` branches within the
//    time resolution).

/// A run may end in the typed error of a preload below the resolution of the run (issue 16:
/// the open class of 0.2.0 turned into an error), with what it recorded before consistent;
/// any other error fails the test.
fn below_resolution_or_panic(kind: &SimErrorKind) {
    match kind {
        SimErrorKind::Model(ModelError::Transition { reason, .. })
            if reason.contains("below the resolution") => {}
        other => panic!("{other}"),
    }
}

/// Over the strobes and dense samples in contact: the largest distance between the ring in the
/// state and its minimum-energy position $s^*(r)$, and the number of outputs whose label is not
/// the regime of the ring's position (more than $10^{-6}$ from a preload). Both are zero when
/// every contact runs on the right branches (the branches also set the ring's damping).
fn contact_errors(ring: &SnubberRing, traj: &Trajectory<jeffcott::nalgebra::U6>) -> (f64, usize) {
    let near = |axis: &RingAxis, v: f64| {
        axis.preload > 0.0 && (v.abs() - axis.preload).abs() <= 1e-6 * (1.0 + axis.preload)
    };
    let outputs: Vec<_> = traj
        .strobe
        .iter()
        .map(|p| (p.label, &p.y))
        .chain(traj.samples.iter().map(|s| (s.label, &s.y)))
        .filter(|(label, _)| *label > 1)
        .collect();
    let worst = outputs
        .iter()
        .map(|(_, y)| {
            let s = ring.locate(&Vector2::new(y[0], y[1])).unwrap().s;
            (Vector2::new(y[4], y[5]) - s).norm()
        })
        .fold(0.0, f64::max);
    let mislabelled = outputs
        .iter()
        .filter(|(label, y)| {
            let s = Vector2::new(y[4], y[5]);
            ring.regime_of_ring(&s).number() != *label
                && !(near(&ring.x, s.x) || near(&ring.y, s.y))
        })
        .count();
    (worst, mislabelled)
}

/// A run started at t = 3.5e5 on the gap circle at speed 40, with both preloads 3.8e-11: the
/// ring crosses them 3e-12 after the contact onset, less than one ulp of time (5.8e-11). The
/// preload guards started at -D, moving away (|s| falls to 0 before it rises to D), and their
/// roots within the start-of-segment window were taken for the zero at the start time: the
/// contact ran on the inner branches (regime II, twice the ring damping) with the ring beyond
/// its preloads.
#[test]
fn preloads_crossed_within_one_ulp_of_the_onset_switch_the_branches() {
    let p = Params {
        eta: 19.189417932901375,
        nu1: 0.16221721434394215,
        nu2: 0.03934731885351604,
        kx: 2.6759667021611397,
        ky: 0.8068550073007944,
        beta: 2.0539705771890433,
        dx: 3.7903965444368754e-11,
        dy: 3.7903965444368754e-11,
        ex: 551.324845817604,
        ey: 1.3636017217924248,
        phi0: 3.016672117375617,
    };
    let m = JeffcottModel::new(p).unwrap();
    let t0 = 353543.8440116018;
    let y0 = SVector::from([
        -0.9950236935917485,
        0.0996385928796378,
        -15.97948121019019,
        -36.649355791338024,
        0.0,
        0.0,
    ]);
    // The strobes as the fuzzer asked for them (DOPRI5 landed its steps on them then).
    let plan = OutputPlan {
        events: false,
        ..fuzzed_plan(&p, t0, 3.0, None)
    };
    let opts = SimOptions::default()
        .with_method(Method::Dopri5)
        .with_rtol(4.140347919517178e-9)
        .with_atol(3.846675761683378e-12)
        .with_max_step_fraction(0.004575233048964348)
        .with_event_samples(1);
    let traj = match m.run(t0, &y0, &plan, &opts) {
        Ok((traj, _)) => traj,
        Err(f) => {
            below_resolution_or_panic(&f.error.kind);
            f.partial
        }
    };
    let (worst, mislabelled) = contact_errors(m.ring(), &traj);
    assert!(worst <= 1e-6, "ring {worst:e} from s*(r)");
    assert_eq!(mislabelled, 0, "outputs in contact with the wrong regime");
}

/// The custom rotor at t = 9.1e5 with preloads 7.4e-9: the ring crosses the whole inner region
/// (1.5e-8) in 7e-10 of time, within the start-of-segment window (1.6e-9). After an inward
/// crossing the contact stayed on the inner branch while the ring was already beyond the
/// opposite preload, 0.03 gaps from s*(r).
#[test]
fn a_ring_through_its_inner_region_within_the_time_resolution_takes_the_far_branch() {
    let p = Params {
        eta: 1.054338695357757,
        nu1: 0.35591445021978046,
        nu2: 8.677115072048805e-7,
        kx: 0.8629761156047014,
        ky: 0.0059071402555884115,
        beta: 1.9194008664156064,
        dx: 7.393915934856934e-9,
        dy: 7.393915934856934e-9,
        ex: 0.0,
        ey: -417.46553437430345,
        phi0: 6458.897157350589,
    };
    let m = rotor::on_ring(p, 0.3387797602609315, 0.45453609146301244).unwrap();
    let t0 = 913572.5045672568;
    let y0 = SVector::from([
        -0.0,
        0.0,
        -0.5459668736363191,
        0.06477298922061925,
        0.0001749394416662647,
        -8.02554528259491e-5,
    ]);
    let plan = OutputPlan {
        strobe: None,
        events: false,
        ..fuzzed_plan(&p, t0, 1.0, Some(200.0))
    };
    let opts = SimOptions::default()
        .with_method(Method::Dopri5)
        .with_rtol(4.1252693824424665e-6)
        .with_atol(8.731740900609176e-5)
        .with_max_step_fraction(0.010815520387604064)
        .with_event_samples(14)
        .with_max_events_per_period(10_000);
    let traj = run_recorded(&m, t0, &y0, &plan, &opts, below_resolution_or_panic);
    let (worst, mislabelled) = contact_errors(m.ring(), &traj);
    assert!(worst <= 1e-6, "ring {worst:e} from s*(r)");
    assert_eq!(mislabelled, 0, "outputs in contact with the wrong regime");
}

// ---------------------------------------------------------------------------------------------
// 9. The ring's location next to a branch's pole (issue 16, item 3).

/// On fixed branches an axis' distance is $d_i = \alpha_i/(\beta_i + \mu)$, with a pole at
/// $\mu = -\beta_i$. On branches that hold the root beyond the stiff axis' reach (here the
/// y axis on its outer branch on the far side of the centre), the root sits next to the soft
/// axis' pole, $\beta_x + \mu \approx |\alpha_x|/d_x$: with $r_x = 3.5\times10^{-17}$ that is
/// far below one ulp of $\mu$, and the solver, iterating on $\mu$, returned `NotConverged`
/// (which its docs called impossible); at $r_x = 0$ an exact `== 0.0` shortcut returned
/// another root (the ring with $d_x = 0$ beyond the pole), so the answer jumped in $r_x$.
///
/// The expected position is independent of the solver: at the pole $\mu = -\beta_x$ the
/// stiff axis' distance is $d_y = \alpha_y/(\beta_y - \beta_x)$ and the soft axis takes the
/// rest of the length, $d_x = \operatorname{sign}(r_x)\sqrt{\gamma^2 - d_y^2}$; for
/// $|r_x| \to 0$ the root tends to it, at a rate bounded by the Jacobian (order 1 here).
#[test]
fn ring_next_to_a_branch_pole_is_placed_continuously_in_r() {
    use jeffcott::ring::{Branch, Branches, RingError};
    let (kx, ky, d) = (1.0813235859593051, 2.2087045555397626, 0.21104992476420698);
    let ring = SnubberRing::new(RingAxis::new(kx, d), RingAxis::new(ky, d), 0.1, 1.0).unwrap();
    let b = Branches {
        x: Branch::Inner,
        y: Branch::Outer(0),
    };
    let ry = 0.016991106264126143;
    // The limit at the pole, from the branch formulas alone: inner x (beta_x = K_x), outer y
    // without side (alpha_y = K_y r_y / 2, beta_y = K_y / 2).
    let dy0 = 0.5 * ky * ry / (0.5 * ky - kx);
    let dx0 = (1.0 - dy0 * dy0).sqrt();
    assert!(dy0.abs() < 1.0);
    for rx in [3.5e-17, -3.5e-17, 1e-20, -1e-20, 0.0, -0.0, 1e-300] {
        let r = Vector2::new(rx, ry);
        for hint in [f64::NAN, -kx, -kx + 1e-9, 0.0, 30.0] {
            let c = match ring.locate_on(&r, b, hint) {
                Ok(c) => c,
                Err(e @ RingError::NotConverged { .. }) => {
                    panic!("r.x = {rx:e}, hint {hint}: {e}")
                }
                Err(e) => panic!("r.x = {rx:e}, hint {hint}: unexpected {e}"),
            };
            let dn = r - c.s;
            assert!(
                (dn.norm() - 1.0).abs() <= 1e-14,
                "constraint {:e}",
                dn.norm() - 1.0
            );
            let sign = if rx.is_sign_negative() { -1.0 } else { 1.0 };
            let expected = Vector2::new(sign * dx0, dy0);
            let off = (dn - expected).norm();
            assert!(
                off <= 1e-12,
                "r.x = {rx:e}, hint {hint}: r - s = {dn:?}, the pole's limit {expected:?} ({off:e} away)"
            );
            assert!(c.jacobian.iter().all(|v| v.is_finite()), "{:?}", c.jacobian);
        }
    }
}

/// The fuzzer's ring cases (seed 4) found warm and cold starts $6.3\times10^{-8}$ apart with
/// $K_y/K_x = 3.5\times10^4$ and the soft axis next to its pole ($r_x = 6\times10^{-17}$,
/// the y axis on its outer branch on the far side): iterating on $\mu$ cannot resolve
/// $\beta_x + \mu \approx 10^{-17}$, so each start stopped somewhere else in that ulp. (The
/// docs promised agreement to $4\times10^{-14}$.)
#[test]
fn warm_and_cold_starts_agree_next_to_a_pole_under_anisotropy() {
    use jeffcott::ring::{Branch, Branches};
    let ring = SnubberRing::new(
        RingAxis::new(0.24009143467938432, 0.0),
        RingAxis::new(8312.502750502606, 0.25230395558520735),
        1.6052530072191538e-10,
        1.0,
    )
    .unwrap();
    let b = Branches {
        x: Branch::Inner,
        y: Branch::Outer(-1),
    };
    let mut worst = 0.0f64;
    for rx in [6.125191028758804e-17, 1e-16, 3e-15, 1e-13] {
        let r = Vector2::new(rx, 1.0003196077470502);
        let cold = ring.locate_on(&r, b, f64::NAN).unwrap();
        for hint in [1527.0035500571137, -0.2, 0.0, -1e3, cold.mu + 1e-9] {
            let warm = ring.locate_on(&r, b, hint).unwrap();
            worst = worst.max((warm.s - cold.s).norm());
        }
    }
    assert!(worst <= 1e-13, "warm and cold starts differ by {worst:e}");
}

// ---------------------------------------------------------------------------------------------
// 10. Unresolved RK4 and preloads below the resolution of the run (issue 16, item 4).

/// The largest inconsistency of a paper-model trajectory's outputs and event records: in free
/// flight how far the rotor is beyond the ring, in contact how far the ring is from $s^*(r)$.
fn worst_inconsistency(ring: &SnubberRing, traj: &Trajectory<jeffcott::nalgebra::U6>) -> f64 {
    let points = traj
        .strobe
        .iter()
        .map(|p| (p.label, p.y))
        .chain(traj.samples.iter().map(|s| (s.label, s.y)))
        .chain(
            traj.events
                .iter()
                .flat_map(|e| [(e.from, e.before), (e.to, e.after)]),
        );
    points
        .map(|(label, y)| {
            let (r, s) = (Vector2::new(y[0], y[1]), Vector2::new(y[4], y[5]));
            if label == 1 {
                (r - s).norm() - ring.gap
            } else {
                ring.locate(&r).map_or(0.0, |c| (c.s - s).norm())
            }
        })
        .fold(0.0, f64::max)
}

/// A fuzz case (seed 0x00F02210): RK4 at 2 steps per forcing period ($h = 7.3$, against the
/// contact's rate $\sqrt{1 + 2K_x} + 2\nu_1 = 4.2$ and the forcing's $\eta = 0.43$) from a start in
/// contact. The run returned `Ok` with the ring off its minimum-energy position, and nothing
/// told the caller that the fixed step resolved nothing. The run's statistics now count the
/// unresolved steps (`SimStats::unresolved_steps`, from `RotorModel::max_rate`).
#[test]
fn unresolved_rk4_is_flagged_in_the_run_statistics() {
    let p = Params {
        eta: 0.4293363198007349,
        nu1: 1.0,
        nu2: 0.0,
        kx: 1.8787053313903253,
        ky: 0.04189614751011124,
        beta: 0.19527375640602046,
        dx: 2.5549268424925526,
        dy: 0.17450925165544648,
        ex: 1.2973612936305643,
        ey: 0.0,
        phi0: 6233.100750082036,
    };
    let m = JeffcottModel::new(p).unwrap();
    let y0 = contact_start(
        &m,
        1.4949077148689516,
        2.7384895452314577,
        2.666265055456449,
    );
    let opts = SimOptions::default()
        .with_method(Method::Rk4)
        .with_steps_per_period(2)
        .with_event_samples(41)
        .with_max_events_per_period(62);
    let (traj, stats) = match m.run(0.0, &y0, &plan(&p, 3), &opts) {
        Ok(ok) => ok,
        Err(f) => (f.partial, *f.error.stats),
    };
    let worst = worst_inconsistency(m.ring(), &traj);
    // When found, the outputs were inconsistent (8.7e-2, all 16 steps unresolved). Since
    // outputs no longer end RK4 steps (issue 16 item 7) the same run happens to give outputs
    // consistent to 8e-9: what an unresolved run outputs is luck either way, and the run must
    // say it was not resolved.
    println!("unresolved run: outputs inconsistent by {worst:e}");
    assert!(
        stats.unresolved_steps > 0,
        "inconsistent outputs ({worst:e}) from a run with no unresolved step: {stats:?}"
    );
    // The same run resolved: no step flagged.
    let fine = opts.with_steps_per_period(2000);
    let stats = match m.run(0.0, &y0, &plan(&p, 3), &fine) {
        Ok((_, stats)) => stats,
        Err(f) => *f.error.stats,
    };
    assert_eq!(stats.unresolved_steps, 0, "{stats:?}");
}

/// A fuzz case (seed 2): the custom rotor with preloads $1.7\times10^{-12}$ and a rest position
/// 222 gaps out, moving at $2\times10^4$ with the ring up to 300 gaps from its centre. The
/// rounding of the ring's position ($64\varepsilon|r| \approx 4\times10^{-12}$) exceeds the
/// whole inner region: the y axis hovered at its preload, crossing back and forth within
/// rounding, until a crossing was lost, and the contact ran on the inner branch with the ring
/// 38 gaps beyond the preload, 0.28 from $s^*(r)$ at a strobe. Such a transition is now the
/// typed error `RingError::PreloadBelowResolution` (in `ModelError::Transition`), and what was
/// recorded before it is consistent.
#[test]
fn a_preload_below_the_rounding_of_the_ring_position_is_a_typed_error() {
    let p = Params {
        eta: 3.462266724068028,
        nu1: 0.14915655580950976,
        nu2: 0.025829978595550855,
        kx: 481.736231419149,
        ky: 2375.7619144085797,
        beta: 2.041337774855918,
        dx: 1.6826827198743493e-12,
        dy: 1.6826827198743493e-12,
        ex: -221.94949895229098,
        ey: -0.8915492326421556,
        phi0: 5845.364383598749,
    };
    let m = rotor::on_ring(p, -0.16674255294477353, 0.5506916622927115).unwrap();
    let (speed, dir) = (1.526470520501915e-6f64, 0.054227660851708895f64);
    let y0 = SVector::from([0.0, 0.0, speed * dir.cos(), speed * dir.sin(), 0.0, 0.0]);
    let opts = SimOptions::default()
        .with_method(Method::Dop853)
        .with_rtol(3.9459873847590993e-10)
        .with_atol(7.170878364034749e-6)
        .with_steps_per_period(10)
        .with_max_step_fraction(0.001725827382784153)
        .with_event_samples(41)
        .with_max_events_per_period(1000)
        .with_max_steps(48401);
    let mut traj = Trajectory::default();
    let res = simulate(&m, 0.0, &y0, &plan(&p, 2), &opts, &mut traj);
    let worst = worst_inconsistency(m.ring(), &traj);
    assert!(worst <= 1e-6, "ring {worst:e} off where its mode puts it");
    match res {
        Err(e) => below_resolution_or_panic(&e.kind),
        Ok(stats) => panic!("the run succeeded ({stats:?}): expected the typed error"),
    }
}

/// A fuzz case (seed 2; found by checking every event record): the paper's model without ring
/// damping touches the relaxed ring with the rotor $4.3\times10^{-15}$ inside the gap circle
/// (within the touch tolerance) and moving outward at 1.3. On the smooth extension there
/// $\mu \approx -K\cdot4.3\times10^{-15}$, a load below its rounding estimate, so the touch was
/// rejected and the separating free flight ran on until the next onset, with the rotor
/// $2.9\times10^{-9}$ beyond the ring. The deficit of a rotor inside the circle within the
/// touch tolerance now counts as zero load, and the load's rise decides: contact starts.
#[test]
fn a_touch_a_hair_inside_the_circle_moving_outward_starts_contact() {
    let p = Params {
        eta: 1.0708489957908562,
        nu1: 0.09120843157122241,
        nu2: 0.0,
        kx: 28.702618999845047,
        ky: 28.702618999845047,
        beta: 2.2647658352696896,
        dx: 0.21363401211192354,
        dy: 0.21363401211192354,
        ex: 0.9979955948186914,
        ey: -0.2690879492423149,
        phi0: -2.9308844040897273,
    };
    let m = JeffcottModel::new(p).unwrap();
    let y0 = contact_start(
        &m,
        1.1356288715427505,
        6.440870855099381e-5,
        3.663708422489889,
    );
    let t0 = 42.85066978428691;
    // The strobes as the fuzzer asked for them (RK4 lands its steps on them).
    let plan = fuzzed_plan(&p, t0, 2.0, None);
    let opts = SimOptions::default()
        .with_method(Method::Rk4)
        .with_rtol(4.579066598091129e-6)
        .with_atol(8.121132758309089e-6)
        .with_steps_per_period(454)
        .with_max_step_fraction(0.21273644290132865)
        .with_event_samples(41)
        .with_max_events_per_period(1000)
        .with_max_steps(65047);
    let (traj, stats) = m
        .run(t0, &y0, &plan, &opts)
        .unwrap_or_else(|f| panic!("{}", f.error));
    assert_eq!(stats.unresolved_steps, 0);
    let worst = worst_inconsistency(m.ring(), &traj);
    assert!(
        worst <= 1e-9,
        "rotor or ring {worst:e} off where the mode puts it"
    );
}

// ---------------------------------------------------------------------------------------------
// 11. The event screen clears a crossing (issue 16's class S; the screen is removed).

/// A fuzz case (seed 777, found by checking every event record): with the event screen on
/// (`SimOptions::screen_events` of 0.2.0, removed in issue 16), the paper model's contact
/// guard was cleared over steps on which it crossed: a stiff contact (K = 303) under a loose
/// `atol` (9e-4) takes steps of 0.8 of its oscillation period, whose dense output swings
/// through zero (0.32 and 0.25 at the ends, -0.10 at mid-step) while the ends' values and
/// derivatives look quiet, so the cubic Hermite interpolant of the ends is far from the guard
/// and its bound proves nothing. The next onset found the rotor $1.7\times10^{-5}$ beyond the
/// ring; with every step sampled (the only path now) $5\times10^{-13}$. Kept as the
/// regression test that the samples find these crossings. At this `atol` the contact's
/// force is not resolved: the run makes spurious losses with an onset at the same instant
/// (at most 13 transitions a forcing period with DOP853's combined error estimate, 65 with
/// its estimate per component; 6 with either at `atol` $10^{-6}$, $10^{-9}$, $10^{-12}$, all
/// alike), so the finding's bound of 48 transitions a period is raised: the chattering guard
/// is not what this checks.
#[test]
fn the_event_screen_does_not_clear_a_crossing() {
    let p = Params {
        eta: 1.000001,
        nu1: 0.2644262900836974,
        nu2: 18.581640394368485,
        kx: 303.5460041812279,
        ky: 303.5460041812279,
        beta: 0.4778906670584586,
        dx: 0.0,
        dy: 0.0,
        ex: 0.46373481098207564,
        ey: -0.024712567647993608,
        phi0: 6313.669037864115,
    };
    let m = JeffcottModel::new(p).unwrap();
    let y0 = contact_start(
        &m,
        3.6679441733133755,
        0.00043863967322860134,
        0.26853541169432377,
    );
    let t0 = 91.92633304343948;
    let plan = fuzzed_plan(&p, t0, 3.0, None);
    let opts = SimOptions::default()
        .with_method(Method::Dop853)
        .with_rtol(2.4485229992722414e-11)
        .with_atol(0.0008890410066892507)
        .with_steps_per_period(10)
        .with_max_step_fraction(0.09872976906416432)
        .with_event_samples(18)
        .with_max_events_per_period(1000)
        .with_max_steps(79607);
    let (traj, _) = m
        .run(t0, &y0, &plan, &opts)
        .unwrap_or_else(|f| panic!("{}", f.error));
    let worst = worst_inconsistency(m.ring(), &traj);
    assert!(worst <= 1e-9, "{worst:e} off");
}

/// A fuzz case (seed 777): the custom rotor at rest on the gap circle at $t_0 = 1.3\times10^5$,
/// its cubic bearing pulling it at $10^7$ towards a rest position 197 gaps out. The onset guard
/// $h - m$ of the touching start (margin $m = 1.4\times10^{-14}$, the rounding alone: the rate
/// is zero) crossed zero $3\times10^{-11}$ after the start, inside the event detector's
/// start-of-segment window ($2\times10^{-10}$ there): no event, and the rotor ended 187 gaps
/// beyond the ring in free flight, silently. A start touching the ring at rest relative to it
/// but accelerated into it ($h^{\prime\prime} > 0$) now begins with the touch. (The preloads,
/// $4.9\times10^{-9}$, are below the resolution there: the run then ends in that typed error.)
#[test]
fn a_start_on_the_circle_accelerated_outward_touches_the_ring() {
    let p = Params {
        eta: 7.287078531856548,
        nu1: 0.28704646824984587,
        nu2: 0.0001107071654938028,
        kx: 0.569707051220153,
        ky: 0.569707051220153,
        beta: 0.2569784821708299,
        dx: 4.9436962441037195e-9,
        dy: 4.9436962441037195e-9,
        ex: -196.96049351820622,
        ey: -0.29587893441891916,
        phi0: -9429.594455455182,
    };
    let m = rotor::on_ring(p, 0.10646495618094938, 1.4904665233746726).unwrap();
    let ang = 3.9089143892087774f64;
    let y0 = SVector::from([ang.cos(), ang.sin(), 0.0, 0.0, 0.0, 0.0]);
    let t0 = 128274.73172044598;
    let plan = fuzzed_plan(&p, t0, 3.0, None);
    let opts = SimOptions::default()
        .with_method(Method::Dop853)
        .with_rtol(4.993687308337673e-13)
        .with_atol(2.0228944270706403e-9)
        .with_steps_per_period(5)
        .with_max_step_fraction(0.1043659477653059)
        .with_event_samples(1)
        .with_max_events_per_period(1000)
        .with_max_steps(83257);
    let traj = run_recorded(&m, t0, &y0, &plan, &opts, below_resolution_or_panic);
    let worst = worst_inconsistency(m.ring(), &traj);
    assert!(
        worst <= 1e-6,
        "rotor or ring {worst:e} off where the mode puts it"
    );
}

// ---------------------------------------------------------------------------------------------
// 14. A crossing pair inside one sample interval that the interpolant of its ends cannot see.

/// A fuzz case (seed 1057, one of the "contacts on the wrong branch at loose tolerances"):
/// the custom rotor at about $10^5$ gaps per time unit 430 gaps out, DOPRI5 with `rtol`
/// $2.6\times10^{-4}$ and one event sample per step. A contact on the regime-III branches
/// runs over one step of $9.5\times10^{-5}$ in which the ring's $y$ crosses its preload
/// ($|s_y| - D_y$ from $-0.13$ to $+0.33$) and the contact is lost; at the step's sample the
/// preload guard is back at $-0.12$. Its end values and derivatives ($\pm 2\times10^3$) put
/// the cubic Hermite interpolant's maximum at $-0.085$, not halfway to zero, so the pair was
/// not searched: the loss fired first, with the ring on the inner branch $2.6\times10^{-2}$
/// from $s^*(r)$ (truth: the minimiser of the ring's energy, `SnubberRing::locate`, checked
/// against a brute-force minimiser in `tests/suite/ring/ring_locate.rs`). The detector now checks
/// the interpolant against the guard at its extremum before trusting it (`ode` (Events),
/// "Detection").
#[test]
fn a_preload_crossing_pair_the_interpolant_misses_is_found() {
    let p = Params {
        eta: 1.000001,
        nu1: 0.13408203064971536,
        nu2: 0.02532400775668012,
        kx: 0.11064957794414593,
        ky: 1022.8236261192671,
        beta: 0.49788820075718315,
        dx: 0.14598729331926286,
        dy: 0.14598729331926286,
        ex: -267.4707833288685,
        ey: -780.0807561075859,
        phi0: 0.6877062603999753,
    };
    let m = rotor::on_ring(p, 0.06737487464393964, 1.5571924493194058).unwrap();
    // A start inside contact, 1e-12 beyond the gap circle (the fuzzer's `Contact` start).
    let r0 = Vector2::from(polar(1.0 + 1e-12, 4.3319386480187));
    let v0 = polar(0.003904002048656303, 1.819857677603437);
    let s0 = m.ring().locate(&r0).unwrap().s;
    let y0 = SVector::from([r0.x, r0.y, v0[0], v0[1], s0.x, s0.y]);
    let t0 = 29.118319541029813;
    let plan = fuzzed_plan(&p, t0, 2.0, None);
    let opts = SimOptions::default()
        .with_method(Method::Dopri5)
        .with_rtol(0.0002586272338551919)
        .with_atol(1.219811436710111e-8)
        .with_steps_per_period(2)
        .with_max_step_fraction(0.13858953303811822)
        .with_event_samples(1)
        .with_max_events_per_period(1000)
        .with_max_steps(61668);
    let traj = run_recorded(&m, t0, &y0, &plan, &opts, |kind| panic!("{kind}"));
    let worst = worst_inconsistency(m.ring(), &traj);
    // The rotor moves 1e5 gaps per time unit: its event resolution there is ~1e-6 gaps.
    assert!(worst <= 1e-6, "ring {worst:e} off where the mode puts it");
}

// ---------------------------------------------------------------------------------------------
// 16. The gap guard fired by rounding on a rotor moving out (issue 16).

/// A fuzz case (seed 12345, case 5406 of the run after the screen's removal): the paper's model
/// from a start on the gap circle at $t_0 = 28.1$, the rotor moving out at $2r\cdot r^\prime =
/// 9.2\times10^{-4}$ (an anisotropic ring, $K_y/K_x = 5\times10^5$, preloads beyond the gap).
/// Contact starts at $t_0$; $8\times10^{-14}$ later the gap guard $|r|^2 - \gamma^2$, still
/// within its rounding of zero ($7\times10^{-17}$ of motion against an ulp of $2.2\times10^{-16}$),
/// was taken for a fall through zero, and the contact released the ring as a parting one
/// while the rotor moved into it: the next onset found the rotor $2.1\times10^{-8}$ beyond the
/// ring (with every method; Radau5 did the same in seed 777's case 5729, its step under a loose
/// `atol` moving the rotor $10^{-12}$ inward while its velocity pointed out). A gap crossing
/// whose rotor moves out is a touch, not a parting.
#[test]
fn a_gap_crossing_with_the_rotor_moving_out_is_not_a_parting() {
    let p = Params {
        eta: 0.9075839919299397,
        nu1: 0.0,
        nu2: 0.001023047776291775,
        kx: 0.002308834501275947,
        ky: 1110.779179406825,
        beta: 4.47318395103082,
        dx: 1.2506957122385163,
        dy: 1.2506957122385163,
        ex: 0.936703900764891,
        ey: 0.43202242823351844,
        phi0: -0.6431782592388696,
    };
    let m = JeffcottModel::new(p).unwrap();
    let y0 = SVector::from([
        -0.019061058692504313,
        0.9998183215172249,
        0.05902650523605695,
        0.001585692447943762,
        0.0,
        0.0,
    ]);
    let t0 = 28.11850030041553;
    let plan = OutputPlan {
        t_end: t0 + 0.02,
        strobe: None,
        dense: None,
        events: true,
    };
    for method in [Method::Dop853, Method::Dopri5] {
        let opts = SimOptions::default()
            .with_method(method)
            .with_rtol(4.131320456574103e-12)
            .with_atol(0.0)
            .with_steps_per_period(13)
            .with_max_step_fraction(5.047042980046361)
            .with_event_samples(14);
        let traj = run_recorded(&m, t0, &y0, &plan, &opts, |kind| {
            panic!("{method:?}: {kind}")
        });
        let worst = worst_inconsistency(m.ring(), &traj);
        assert!(
            worst <= 1e-9,
            "{method:?}: rotor or ring {worst:e} off where the mode puts it"
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 17. An onset guard off zero by its margin, with a rate of exactly zero, taken for on zero.

/// A fuzz case (seed `12345`, case 45235 of the $10^5$-case run): the custom rotor with a
/// softening bearing ($k_3 = -0.087$), Radau5 at `rtol` $8.3\times10^{-4}$, one event sample a
/// step, from a relaxing ring at $t_0 = 465296$. The rotor slides along the ring without load
/// (contact losses and touches every $7\times10^{-8}$); at one loss it moves exactly
/// tangentially, and the onset guard of the free flight, $h - m$, starts at $-m =
/// -1.4\times10^{-14}$ with its rate rounded to exactly 0. The detector took that zero for "no
/// derivative", hence a guard that may have left zero, and dropped its crossing (one ulp after
/// the start, inside the start-of-segment window, the dense output moving the rotor outward)
/// as the zero at the start: the free flight ran on with the rotor $5.6\times10^{-3}$ gaps
/// beyond the ring at the next strobe (the truth: a free flight has $|r - s| \le \gamma$, the
/// model's definition). A guard with a derivative of exactly zero is now on zero only within
/// `value_tol` (`ode` (Events), rule 3): the crossing is an event and the slide goes on, until
/// the chattering bound ends the run (a larger bound goes further).
#[test]
fn an_onset_guard_off_zero_with_a_zero_rate_is_not_taken_for_the_start() {
    let p = Params {
        eta: 0.934174959804055,
        nu1: 0.1633519252738614,
        nu2: 9856.217981886122,
        kx: 1125.0505871808293,
        ky: 0.010809457237127604,
        beta: 0.0,
        dx: 0.2972488150886696,
        dy: 0.06204196761404997,
        ex: -0.5739944688356172,
        ey: -1.2263930124353026,
        phi0: -0.16679672740532314,
    };
    let m = rotor::on_ring(p, -0.4697926230099876, -0.0873783684095446).unwrap();
    // The fuzzer's `Relaxing` start: the rotor inside the ring, the ring displaced.
    let [r, d, v] = [
        polar(0.81251394509214, 5.458757238982963),
        polar(0.9940051820535274, 4.9629955550033955),
        polar(4.4044613502609805e-5, 4.58532522599548),
    ];
    let y0 = SVector::from([r[0], r[1], v[0], v[1], r[0] - d[0], r[1] - d[1]]);
    let t0 = 465295.93139095145;
    let plan = fuzzed_plan(&p, t0, 2.0, Some(27.0));
    let opts = SimOptions::default()
        .with_method(Method::Radau5)
        .with_rtol(0.0008320758574985395)
        .with_atol(2.0056992341239783e-9)
        .with_steps_per_period(694)
        .with_max_step_fraction(99.91358253139299)
        .with_event_samples(1)
        .with_max_events_per_period(1000)
        .with_max_steps(39757);
    let traj = run_recorded(&m, t0, &y0, &plan, &opts, |kind| {
        assert!(matches!(kind, SimErrorKind::Chattering { .. }), "{kind}")
    });
    let worst = worst_inconsistency(m.ring(), &traj);
    assert!(
        worst <= 1e-6,
        "rotor or ring {worst:e} off where the mode puts it"
    );
}

// ---------------------------------------------------------------------------------------------
// 18. A grazing pair of the onset guard on Radau5's dense output, right after a contact loss.

/// A fuzz case (seed 777, case 54719 of the $10^5$-case run after fix 17): the custom rotor
/// ($k_3 = 1.46$) from a start in contact, Radau5 at `rtol` $2.3\times10^{-5}$, `atol`
/// $6.2\times10^{-4}$, one event sample a step. At the contact loss at $t = 1.5395$ the load is
/// zero and the released flight's onset guard starts at $-m$ with a rate along the flow of
/// exactly 0; Radau5's collocation polynomial is not tangent to $f$ at its step's start, and on
/// it the guard rose through zero and back inside the first sample interval, whose cubic Hermite
/// interpolant (slope 0 at the start, from $f$) has no interior extremum: the free flight ran
/// with the rotor $1.6\times10^{-6}$ gaps beyond the ring at a dense sample (the truth: a free
/// flight has $|r - s| \le \gamma$, the model's definition; $10^{-6}$ is the fuzzer's bound for
/// the custom rotor). Fix 18 first made the detector take the slope at a step's start from the
/// dense output: the pair was found, and the rotor slid along the ring without load (a loss and
/// a touch again and again) until the run's chattering bound ended it; on the flexible shaft
/// the same rule made spurious onsets after tangential losses
/// (`radau5_has_the_reference_transitions_on_the_shaft_after_tangential_losses`). Now
/// Radau5's first step after a reset leaves its start tangent to $f$: the polynomial no longer
/// rises, and the run completes (15 transitions) with every dense sample consistent (measured
/// $9\cdot10^{-15}$).
#[test]
fn a_grazing_onset_pair_on_radau5_dense_output_after_a_loss_is_found() {
    let p = Params {
        eta: 1.0182361437802403,
        nu1: 0.0,
        nu2: 578.6736522513077,
        kx: 4.396350850875155,
        ky: 1090.352331933907,
        beta: 0.0643160993207508,
        dx: 0.18949373100458725,
        dy: 0.27920832096788345,
        ex: -0.7038098091804259,
        ey: -0.07628791105925231,
        phi0: -2.811747357274671,
    };
    let m = rotor::on_ring(p, -0.009262477743905212, 1.4599735756097554).unwrap();
    // The fuzzer's `Contact` start: the rotor 4.2e-4 beyond the gap circle, the ring placed.
    let paper = JeffcottModel::new(p).unwrap();
    let y0 = paper
        .state_at(
            polar(1.0 + 0.0004221914351150468, 0.4017498168213691),
            polar(0.04547012283351574, 5.876648034168278),
        )
        .unwrap();
    let plan = fuzzed_plan(&p, 0.0, 3.0, Some(24.0));
    let opts = SimOptions::default()
        .with_method(Method::Radau5)
        .with_rtol(2.3017109431585863e-5)
        .with_atol(0.0006223066471539078)
        .with_steps_per_period(1441)
        .with_max_step_fraction(60.1167905476454)
        .with_event_samples(1)
        .with_max_events_per_period(1000)
        .with_max_steps(3975);
    let mut traj = Trajectory::default();
    let stats = simulate(&m, 0.0, &y0, &plan, &opts, &mut traj).expect("the run");
    let worst = worst_inconsistency(m.ring(), &traj);
    println!(
        "{} transitions, the worst inconsistency {worst:e}",
        stats.transitions
    );
    assert!(
        worst <= 1e-6,
        "rotor or ring {worst:e} off where the mode puts it"
    );
}

// ---------------------------------------------------------------------------------------------
// 19. The restart's tangency term of Radau5's dense output, spread over the whole step.

/// A fuzz case (seed 777, case 21024 of the $10^5$-case run after fix 19's first form): the
/// custom rotor ($k_3 = 0.90$) from a start $4.6\times10^{-4}$ beyond the gap circle at rest,
/// Radau5 at `rtol` $8.9\times10^{-11}$, `atol` $1.9\times10^{-4}$, one event sample a step. The
/// rotor slides along the ring without load (a touch and a loss every $10^{-3}$ or less), then
/// leaves it; the first step after the last restart is 0.33 long. Fix 19 first made Radau5's
/// dense output tangent at a restart by the quartic $\theta(\theta - c_1)(\theta - c_2)
/// (\theta - 1)d_4$, which reaches 0.18 of the slope mismatch inside the step: on it the free
/// flight went $3.75\times10^{-6}$ beyond the ring at $t = 109.8126$, 0.04 after the restart, and
/// back, inside one sample interval, with nothing for the screen to see (the truth: a free
/// flight has $|r - s| \le \gamma$; $10^{-6}$ is the fuzzer's bound). The collocation
/// polynomial alone (before fix 19) has no such excursion here; the term is now local to
/// $[0, c_1]$ of the step and at most 0.0163 of the mismatch.
#[test]
fn the_restart_tangency_of_radau5_stays_local_to_the_start() {
    let p = Params {
        eta: 1.000001,
        nu1: 0.0,
        nu2: 327.68554669498775,
        kx: 814.9285375348251,
        ky: 814.9285375348251,
        beta: 0.1272470436293462,
        dx: 1.2542529156313191,
        dy: 1.2542529156313191,
        ex: 0.4386065194363236,
        ey: -0.08749098343380324,
        phi0: 9310.70024583924,
    };
    let m = rotor::on_ring(p, -0.3979442931159012, 0.9000655272445862).unwrap();
    // The fuzzer's `Contact` start: 4.6e-4 beyond the gap circle, at rest.
    let paper = JeffcottModel::new(p).unwrap();
    let y0 = paper
        .state_at(
            polar(1.0 + 0.0004561695685422969, std::f64::consts::FRAC_PI_2),
            polar(0.0, 4.310903264865449),
        )
        .unwrap();
    let t0 = 99.69821629030982;
    let plan = fuzzed_plan(&p, t0, 2.0, Some(41.0));
    let opts = SimOptions::default()
        .with_method(Method::Radau5)
        .with_rtol(8.876046138168863e-11)
        .with_atol(0.00018628557203949694)
        .with_steps_per_period(362)
        .with_max_step_fraction(0.8857818020838881)
        .with_event_samples(1)
        .with_max_events_per_period(1000)
        .with_max_steps(69415);
    let mut traj = Trajectory::default();
    let stats = simulate(&m, t0, &y0, &plan, &opts, &mut traj).expect("the run");
    let worst = worst_inconsistency(m.ring(), &traj);
    println!(
        "{} transitions, the worst inconsistency {worst:e}",
        stats.transitions
    );
    assert!(
        worst <= 1e-6,
        "rotor or ring {worst:e} off where the mode puts it"
    );
}
