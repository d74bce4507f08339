//! The flexible shaft (`examples/flexible_shaft`) in its complex modal coordinates with the
//! exponential integrator ETD4, against the same shaft in its real modal coordinates with
//! DOP853 at rtol 1e-12 (another representation, another method), and the cost per
//! revolution against the modes kept.

use std::time::Instant;

use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimOptions, SimStats, Trajectory};
use jeffcott::nalgebra::{DVector, Dyn};
use jeffcott::ode::Method;
use jeffcott::params::Preset;
use jeffcott::rotor::{ModalRotor, RingedRotor, SmoothRotor};

use crate::shaft::{self, Layout};

/// A run of a model: options and periods to the trajectory, its statistics and seconds.
type BoxedRun = Box<dyn Fn(&SimOptions, f64) -> (Trajectory<Dyn>, SimStats, f64)>;

/// The shaft in `modes` modes, ring at station 3 of 8, out-of-balance at 2, eta 1.1 (as
/// `ode_radau_contacts`): the physical model and its modal form, each with its consistent
/// start from rest.
fn both(modes: usize) -> [(BoxedRun, &'static str); 2] {
    let params = Preset::Fig8a.params().with_eta(1.1);
    let layout = Layout {
        modes,
        stations: 8,
        unbalance: 2,
        ring: 3,
    };
    let physical = shaft::on_ring(params, layout).expect("shaft");
    let modal: RingedRotor<ModalRotor> = physical
        .rotor()
        .modal_rotor()
        .expect("modal form")
        .ringed(*physical.ring())
        .expect("ringed");
    let period = physical.rotor().forcing_period();
    let run_physical = move |opts: &SimOptions, periods: f64| {
        let mut y0 = DVector::zeros(physical.rotor().state_len());
        physical.make_consistent(&mut y0).unwrap();
        run(&physical, &y0, opts, periods * period)
    };
    let run_modal = move |opts: &SimOptions, periods: f64| {
        let mut y0 = modal.rotor().rest_state();
        modal.make_consistent(&mut y0).unwrap();
        run(&modal, &y0, opts, periods * period)
    };
    [
        (Box::new(run_physical), "physical"),
        (Box::new(run_modal), "modal"),
    ]
}

/// A run to `t_end` sampled at the ring's station (`r` relative to the ring's centre, put in
/// each sample's first two components), with its statistics and wall time.
fn run<R: SmoothRotor<Dim = Dyn>>(
    model: &RingedRotor<R>,
    y0: &DVector<f64>,
    opts: &SimOptions,
    t_end: f64,
) -> (Trajectory<Dyn>, SimStats, f64) {
    let plan = OutputPlan {
        t_end,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: t_end / 400.0,
        }),
        events: true,
    };
    let mut trajectory = Trajectory::default();
    let start = Instant::now();
    let stats = simulate(model, 0.0, y0, &plan, opts, &mut trajectory).expect("run");
    let seconds = start.elapsed().as_secs_f64();
    for s in &mut trajectory.samples {
        let r = model.rotor().station(&s.y).r;
        s.y[0] = r.x;
        s.y[1] = r.y;
    }
    (trajectory, stats, seconds)
}

fn opts(method: Method, rtol: f64) -> SimOptions {
    SimOptions::default()
        .with_method(method)
        .with_rtol(rtol)
        .with_atol(rtol)
}

fn onsets(t: &Trajectory<Dyn>) -> usize {
    t.events
        .iter()
        .filter(|e| e.kind == "contact onset")
        .count()
}

/// 8 modes, 4 periods from rest: ETD4 on the modal form at rtol 1e-9 within 1e-6 of the gap
/// of DOP853 at rtol 1e-12 on the physical shaft at every sample, with the same contacts.
#[test]
fn the_modal_shaft_with_etd4_follows_the_physical_one() {
    let [(physical, _), (modal, _)] = both(8);
    let (reference, _, _) = physical(&opts(Method::Dop853, 1e-12), 4.0);
    let (got, stats, _) = modal(&opts(Method::Etd4, 1e-9), 4.0);
    assert_eq!(got.samples.len(), reference.samples.len());
    let worst = got
        .samples
        .iter()
        .zip(&reference.samples)
        .map(|(a, b)| (a.y[0] - b.y[0]).hypot(a.y[1] - b.y[1]))
        .fold(0.0, f64::max);
    println!(
        "8 modes, ETD4 rtol 1e-9: {} steps, {} onsets; {worst:.2e} of the gap",
        stats.steps,
        onsets(&got)
    );
    assert!(onsets(&reference) >= 3);
    assert_eq!(onsets(&got), onsets(&reference));
    assert!(worst <= 1e-6, "{worst:e}");
}

/// The cost per revolution against the modes kept: ETD4 (modal form) at rtol 1e-8 and 1e-10,
/// DOP853 (physical) at 1e-8 up to 64 modes, 10 periods from rest, each against DOP853 at
/// rtol 1e-12; the wall time the least of 3 runs (a shared machine).
#[test]
#[ignore = "a measurement: cargo test --release --test suite ode::ode_etd4_shaft -- --ignored --nocapture"]
fn shaft_cost_against_modes() {
    let periods = 10.0;
    println!(
        "modes (states) | method, rtol | steps | onsets | µs per revolution | max error / gap"
    );
    for modes in [8, 16, 32, 64, 96, 128] {
        let [(physical, _), (modal, _)] = both(modes);
        let (reference, _, _) = physical(&opts(Method::Dop853, 1e-12), periods);
        type Runner<'a> = &'a dyn Fn(&SimOptions, f64) -> (Trajectory<Dyn>, SimStats, f64);
        let mut runs: Vec<(Runner, Method, f64)> = vec![
            (&*modal, Method::Etd4, 1e-8),
            (&*modal, Method::Etd4, 1e-10),
        ];
        if modes <= 64 {
            runs.push((&*physical, Method::Dop853, 1e-8));
        }
        for (runner, method, rtol) in runs {
            let (got, stats, mut seconds) = runner(&opts(method, rtol), periods);
            for _ in 0..2 {
                seconds = seconds.min(runner(&opts(method, rtol), periods).2);
            }
            let worst = got
                .samples
                .iter()
                .zip(&reference.samples)
                .map(|(a, b)| (a.y[0] - b.y[0]).hypot(a.y[1] - b.y[1]))
                .fold(0.0, f64::max);
            println!(
                "{modes} ({}) | {} {rtol:.0e} | {} | {} | {:.0} | {worst:.1e}",
                4 * modes + 2,
                method.name(),
                stats.steps,
                onsets(&got),
                1e6 * seconds / periods,
            );
        }
    }
}
