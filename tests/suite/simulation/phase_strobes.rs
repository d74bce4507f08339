//! Strobes at a phase in the state ([`RotorModel::strobe_phase`]): the driver locates them on
//! each step's dense output (integrated modes) or on the closed form (exact modes). A shaft
//! angle $\varphi^\prime = 2 + \cos t$ has the closed form
//! $\varphi(t) = \varphi(t_0) + 2(t - t_0) + \sin t - \sin t_0$; its strobes
//! $\varphi = 2\pi k/3$ are the roots of that, found here by bisection to adjacent floats
//! (independently of the driver's search).

use std::f64::consts::TAU;

use jeffcott::hybrid::{
    simulate, ExactSegment, Flow, GuardCrossing, ModelError, OutputPlan, RotorModel, SimOptions,
    StrobeRange, Trajectory,
};
use jeffcott::nalgebra::{SVector, U1};
use jeffcott::numeric::Direction;

type S = SVector<f64, 1>;

/// The angle alone, in one mode, integrated or in closed form.
struct Spinner {
    exact: bool,
}

/// The closed form from `(t0, phi0)`.
struct Turning {
    t0: f64,
    phi0: f64,
}

fn angle(t0: f64, phi0: f64, t: f64) -> f64 {
    phi0 + (2.0 * (t - t0) + (t.sin() - t0.sin()))
}

impl ExactSegment<U1> for Turning {
    fn eval(&self, t: f64, y: &mut S, dy: &mut S) {
        y[0] = angle(self.t0, self.phi0, t);
        dy[0] = 2.0 + t.cos();
    }
    fn next_guard(&mut self, _from: f64, _to: f64) -> Option<GuardCrossing> {
        None
    }
    fn evaluations(&self) -> u64 {
        0
    }
}

impl RotorModel for Spinner {
    type Dim = U1;
    type Mode = ();
    type Segment = Turning;
    type Cache = ();

    fn dim(&self) -> U1 {
        U1
    }
    fn new_cache(&self) {}
    fn initial_mode(&self, _t: f64, _y: &S) -> Result<(), ModelError> {
        Ok(())
    }
    fn flow(&self, _mode: ()) -> Flow {
        if self.exact {
            Flow::Exact
        } else {
            Flow::Integrated
        }
    }
    fn rhs(&self, _mode: (), t: f64, _y: &S, dy: &mut S, _cache: &()) {
        dy[0] = 2.0 + t.cos();
    }
    fn guard_count(&self, _mode: ()) -> usize {
        0
    }
    fn guard_direction(&self, _mode: (), _i: usize) -> Direction {
        Direction::Either
    }
    fn guard_value(&self, _mode: (), _i: usize, _t: f64, _y: &S, _cache: &()) -> f64 {
        1.0
    }
    fn guard_label(&self, _mode: (), _i: usize) -> &'static str {
        "none"
    }
    fn transition(&self, _mode: (), _g: usize, _t: f64, _y: &mut S) -> Result<(), ModelError> {
        Ok(())
    }
    fn start_segment(&self, _mode: (), t: f64, y: &S) -> Turning {
        Turning { t0: t, phi0: y[0] }
    }
    fn mode_label(&self, _mode: ()) -> u8 {
        1
    }
    fn forcing_period(&self) -> f64 {
        1.0
    }
    fn strobe_phase(&self, k: u64) -> Option<(usize, f64)> {
        Some((0, TAU * k as f64 / 3.0))
    }
}

/// The time where the angle from `(t0, phi0)` reaches `target`, by bisection to adjacent
/// floats (the angle increases).
fn turn_time(t0: f64, phi0: f64, target: f64) -> f64 {
    let (mut a, mut b) = (t0, t0 + (target - phi0) + 1.0);
    while b - a > f64::EPSILON * b.abs().max(1.0) {
        let m = 0.5 * (a + b);
        if angle(t0, phi0, m) < target {
            a = m;
        } else {
            b = m;
        }
    }
    b
}

fn run(exact: bool, t0: f64, phi0: f64) -> Trajectory<U1> {
    let plan = OutputPlan {
        t_end: 20.0,
        strobe: Some(StrobeRange {
            first: 0,
            last: 100,
        }),
        dense: None,
        events: false,
    };
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-12);
    let mut traj = Trajectory::<U1>::default();
    simulate(
        &Spinner { exact },
        t0,
        &S::new(phi0),
        &plan,
        &opts,
        &mut traj,
    )
    .unwrap();
    traj
}

/// Every target the angle passes between the start and the end, once, at its root; targets
/// below the start skipped, one at the start itself kept (at the start's time).
#[test]
fn strobes_at_a_phase_are_its_roots_integrated_and_exact() {
    for exact in [false, true] {
        for (t0, phi0) in [(0.0, 0.5), (1.0, TAU / 3.0)] {
            let traj = run(exact, t0, phi0);
            let first = (phi0 / (TAU / 3.0)).ceil() as u64;
            let last = (angle(t0, phi0, 20.0) / (TAU / 3.0)).floor() as u64;
            let ks: Vec<u64> = traj.strobe.iter().map(|p| p.k).collect();
            assert_eq!(ks, (first..=last).collect::<Vec<_>>(), "exact {exact}");
            let mut worst = 0.0f64;
            for p in &traj.strobe {
                let truth = turn_time(t0, phi0, TAU * p.k as f64 / 3.0);
                worst = worst.max((p.t - truth).abs());
            }
            // Exact: a few ulp of the time; integrated: the dense output's error at rtol 1e-12
            // over the angle's rate (>= 1).
            let bound = if exact { 1e-13 } else { 1e-10 };
            assert!(worst <= bound, "exact {exact}, start {t0}: {worst:e}");
            if phi0 == TAU / 3.0 {
                assert_eq!(traj.strobe[0].t, t0, "a strobe at the start, exact {exact}");
            }
        }
    }
}
