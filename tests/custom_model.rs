//! The `RotorModel` trait with a model of the user's own: a 1-DOF oscillator that meets a
//! spring stop at x = 1 (a radial cut through a rotor hitting a stator), run by the same driver
//! and events. Its period is known in closed form.

use jeffcott::hybrid::{
    Flow, ModelError, NoExactModes, OutputPlan, RotorModel, SimOptions, Trajectory,
};
use jeffcott::ode::Direction;
use nalgebra::SVector;

type S = SVector<f64, 2>;

/// $x'' + x = 0$ for $x < 1$; $x'' + x + k(x - 1) = 0$ against the stop.
struct SpringStop {
    k: f64,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Mode {
    Free,
    Stop,
}

impl RotorModel<2> for SpringStop {
    type Mode = Mode;
    type Segment = NoExactModes;
    type Cache = ();

    fn initial_mode(&self, _t: f64, y: &S) -> Result<Mode, ModelError> {
        Ok(if y[0] < 1.0 { Mode::Free } else { Mode::Stop })
    }
    fn flow(&self, _mode: Mode) -> Flow {
        Flow::Integrated
    }
    fn rhs(&self, mode: Mode, _t: f64, y: &S, dy: &mut S, _cache: &()) {
        let stop = if mode == Mode::Stop {
            self.k * (y[0] - 1.0)
        } else {
            0.0
        };
        *dy = S::new(y[1], -y[0] - stop);
    }
    fn guard_count(&self, _mode: Mode) -> usize {
        1
    }
    fn guard_direction(&self, mode: Mode, _i: usize) -> Direction {
        match mode {
            Mode::Free => Direction::Rising,
            Mode::Stop => Direction::Falling,
        }
    }
    fn guard_value(&self, _mode: Mode, _i: usize, _t: f64, y: &S, _cache: &()) -> f64 {
        y[0] - 1.0
    }
    fn guard_derivative(
        &self,
        _mode: Mode,
        _i: usize,
        _t: f64,
        y: &S,
        _dy: &S,
        _cache: &(),
    ) -> Option<f64> {
        Some(y[1])
    }
    fn guard_derivative_needs_rhs(&self) -> bool {
        false
    }
    fn guard_label(&self, mode: Mode, _i: usize) -> &'static str {
        match mode {
            Mode::Free => "hit",
            Mode::Stop => "leave",
        }
    }
    fn transition(&self, mode: Mode, _g: usize, _t: f64, _y: &mut S) -> Result<Mode, ModelError> {
        Ok(match mode {
            Mode::Free => Mode::Stop,
            Mode::Stop => Mode::Free,
        })
    }
    fn start_segment(&self, _mode: Mode, _t: f64, _y: &S) -> NoExactModes {
        NoExactModes
    }
    fn mode_label(&self, mode: Mode) -> u8 {
        match mode {
            Mode::Free => 1,
            Mode::Stop => 2,
        }
    }
    fn forcing_period(&self) -> f64 {
        std::f64::consts::TAU
    }
}

#[test]
fn a_user_model_runs_through_the_driver_with_its_exact_period() {
    let (k, v0) = (50.0, 2.0);
    let model = SpringStop { k };
    // Closed form: free arc pi + 2 asin(1/v0); against the stop an oscillation about
    // x* = k/(1+k) at omega = sqrt(1+k), entered at u0 = 1/(1+k) with speed sqrt(v0^2 - 1).
    let omega = (1.0 + k).sqrt();
    let u0 = 1.0 / (1.0 + k);
    let v1 = (v0 * v0 - 1.0f64).sqrt();
    let amp = (u0 * u0 + (v1 / omega).powi(2)).sqrt();
    let phi = (u0 / amp).asin();
    let period =
        std::f64::consts::PI + 2.0 * (1.0 / v0).asin() + (std::f64::consts::PI - 2.0 * phi) / omega;

    let plan = OutputPlan {
        t_end: 20.0 * period,
        strobe: None,
        dense: None,
        events: true,
    };
    let opts = SimOptions {
        rtol: 1e-12,
        atol: 1e-14,
        ..SimOptions::default()
    };
    let mut traj = Trajectory::default();
    jeffcott::hybrid::simulate(&model, 0.0, &S::new(0.0, v0), &plan, &opts, &mut traj).unwrap();
    let hits: Vec<f64> = traj
        .events
        .iter()
        .filter(|e| e.kind == "hit")
        .map(|e| e.t)
        .collect();
    assert!(hits.len() >= 19, "{} hits", hits.len());
    for w in hits.windows(2) {
        assert!(
            (w[1] - w[0] - period).abs() < 1e-10,
            "{} vs {period}",
            w[1] - w[0]
        );
    }
    for e in &traj.events {
        assert!((e.before[0] - 1.0).abs() < 1e-13, "{e:?}");
    }
}
