//! The three faces of rub with friction on the paper's rotor (docs/friction.md;
//! `paper::rub::rubbing_model`): a synchronous full annular rub, a forward contact that turns
//! into backward whirl, and dry whip, each against its closed form (`paper::rub`).
//!
//! The machine: the paper's rotor centred in an isotropic ring without preload ($\eta = 1.2$,
//! $\nu_1 = 0.05$, $\nu_2 = 0.002$, $K = 30$, $\beta = 0.5$), a shaft of radius $a = 5$ gaps at
//! the ring, the shaft spinning counter-clockwise.
//!
//! 1. **Synchronous rub**: friction 0.05, from rest (three times `--periods`: the light damping
//!    settles slowly); the rotor settles on the forward full annular rub, whirling with the
//!    out-of-balance (whirl ratio +1), slipping forward.
//! 2. **Into backward whirl**: the same machine with friction 0.2, from rest; the forward
//!    contacts turn the whirl backward and the rotor ends in dry whip, a backward whirl at the
//!    natural frequency of the rotor on the ring, 9.65 gaps out.
//! 3. **Dry whip** without out-of-balance ($\beta = 0$): the rotor kicked into the ring whirls
//!    backward on the closed form's whip.
//!
//! Prints per scene the final radius and whirl ratio (whirl frequency over the spin) against
//! the closed form, and writes in `--out` (default `target/figures/rub`), each with its CSV:
//! `orbit_rub.png` (scene 1's last periods, the closed form's orbit and the gap circle),
//! `orbit_whip.png` (scenes 2 and 3, the closed form's whip), `whirl.png` (the whirl
//! ratio in each forcing period, scenes 1 and 2), `slip_velocity.png` (the slip velocity $v$
//! of scene 2 while it turns: slipping forward $v > 0$, backward $v < 0$, rolling $v = 0$),
//! and `friction_bifurcation.png` (the radius at the forcing period over the last
//! `--strobes` periods of a run from rest, against the friction from 0 to `--mu-max`).
//!
//! ```text
//! cargo run --release --example rub
//! cargo run --release --example rub -- --periods 100 --mu-steps 11
//! ```
//!
//! Exit status: 0 on success; 2 with one `error: ...` line for bad flags; 1 with one line if a
//! simulation fails.

#[path = "common/mod.rs"]
mod common;

use std::f64::consts::TAU;
use std::path::PathBuf;

use clap::Parser;
use common::cli::{f64_in, parse, usize_in};
use common::plot::{self, Figure, Series};
use common::Tolerances;
use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::{DVector, Dyn, Vector2};
use jeffcott::paper::rub::{dry_whip, rubbing_model, synchronous_rub};
use jeffcott::params::Params;

/// Rub with friction on the paper's rotor: synchronous rub, backward whirl, dry whip.
#[derive(Parser)]
#[command(name = "rub")]
struct Flags {
    /// Output folder
    #[arg(long, value_name = "DIR", default_value = "target/figures/rub")]
    out: PathBuf,
    /// Forcing periods of each scene [range: 20..=100000]
    #[arg(long, value_name = "COUNT", default_value = "300", value_parser = usize_in(20, 100_000))]
    periods: usize,
    /// Largest friction coefficient of the bifurcation diagram [range: 0.01..=1]
    #[arg(long, value_name = "NUMBER", default_value = "0.3", value_parser = f64_in(0.01, 1.0))]
    mu_max: f64,
    /// Friction values of the bifurcation diagram [range: 2..=10000]
    #[arg(long, value_name = "COUNT", default_value = "61", value_parser = usize_in(2, 10_000))]
    mu_steps: usize,
    /// Periods drawn per friction value (the last of each run) [range: 1..=10000]
    #[arg(long, value_name = "COUNT", default_value = "40", value_parser = usize_in(1, 10_000))]
    strobes: usize,
    #[command(flatten)]
    tol: Tolerances,
}

const SHAFT_RADIUS: f64 = 5.0;
const SAMPLES_PER_PERIOD: usize = 256;

/// The machine of the three scenes, with out-of-balance `beta`.
fn machine(beta: f64) -> Params {
    Params {
        eta: 1.2,
        nu1: 0.05,
        nu2: 0.002,
        kx: 30.0,
        ky: 30.0,
        beta,
        dx: 0.0,
        dy: 0.0,
        ex: 0.0,
        ey: 0.0,
        phi0: 0.0,
    }
}

/// A run of the machine with friction `mu` from `y0` for `periods`, samples every 1/256 period.
fn run(p: &Params, mu: f64, y0: [f64; 6], periods: usize, opts: &SimOptions) -> Trajectory<Dyn> {
    let model = common::or_exit(rubbing_model(p, mu, SHAFT_RADIUS));
    let period = TAU / p.eta;
    let plan = OutputPlan {
        t_end: periods as f64 * period,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: period / SAMPLES_PER_PERIOD as f64,
        }),
        events: true,
    };
    let mut traj = Trajectory::default();
    if let Err(e) = simulate(
        &model,
        0.0,
        &DVector::from_row_slice(&y0),
        &plan,
        opts,
        &mut traj,
    ) {
        eprintln!("error: the run with friction {mu} failed: {e}");
        std::process::exit(1);
    }
    traj
}

/// The whirl ratio in each forcing period: the turn of the rotor's angle over the period,
/// in turns (the whirl frequency over the spin); with the period's end time.
fn whirl_ratios(traj: &Trajectory<Dyn>) -> Vec<(f64, f64)> {
    let mut angle = Vec::with_capacity(traj.samples.len());
    let mut last = 0.0;
    for s in &traj.samples {
        let a = s.y[1].atan2(s.y[0]);
        let step = (a - last + TAU / 2.0).rem_euclid(TAU) - TAU / 2.0;
        angle.push(angle.last().map_or(a, |&u: &f64| u + step));
        last = a;
    }
    (SAMPLES_PER_PERIOD..angle.len())
        .step_by(SAMPLES_PER_PERIOD)
        .map(|k| {
            let turn = (angle[k] - angle[k - SAMPLES_PER_PERIOD]) / TAU;
            (traj.samples[k].t, turn)
        })
        .collect()
}

/// The slip velocity $v = (r^\prime - s^\prime)\cdot t + \eta a$ at the samples in contact (NaN
/// in free flight), from the rotor's and the ring's positions and velocities.
fn slip_velocities(traj: &Trajectory<Dyn>, eta: f64) -> Vec<(f64, f64)> {
    traj.samples
        .iter()
        .map(|s| {
            if s.label < 6 {
                return (s.t, f64::NAN);
            }
            let n = Vector2::new(s.y[0] - s.y[4], s.y[1] - s.y[5]);
            let rel = Vector2::new(s.y[2] - s.dy[4], s.y[3] - s.dy[5]);
            (s.t, rel.dot(&Vector2::new(-n.y, n.x)) + eta * SHAFT_RADIUS)
        })
        .collect()
}

/// The rotor's radius at the last sample and its mean over the last period.
fn final_radius(traj: &Trajectory<Dyn>) -> (f64, f64) {
    let n = traj.samples.len();
    let radius = |k: usize| traj.samples[k].y[0].hypot(traj.samples[k].y[1]);
    let mean = (n - SAMPLES_PER_PERIOD..n).map(radius).sum::<f64>() / SAMPLES_PER_PERIOD as f64;
    (radius(n - 1), mean)
}

/// The last `periods` periods of the rotor's orbit.
fn tail(traj: &Trajectory<Dyn>, periods: usize) -> Vec<(f64, f64)> {
    let n = traj.samples.len();
    traj.samples[n.saturating_sub(periods * SAMPLES_PER_PERIOD + 1)..]
        .iter()
        .map(|s| (s.y[0], s.y[1]))
        .collect()
}

fn circle(radius: f64) -> Vec<(f64, f64)> {
    (0..=360)
        .map(|k| {
            let a = TAU * k as f64 / 360.0;
            (radius * a.cos(), radius * a.sin())
        })
        .collect()
}

fn main() {
    let flags: Flags = parse();
    let (rtol, atol) = flags.tol.get();
    let opts = SimOptions::default().with_rtol(rtol).with_atol(atol);
    let out = &flags.out;
    let periods = flags.periods;
    let p = machine(0.5);

    // The synchronous rub is approached slowly (light damping): three times as long.
    let sync = run(&p, 0.05, [0.0; 6], 3 * periods, &opts);
    let closed = common::or_exit(synchronous_rub(&p, 0.05));
    let (r_end, _) = final_radius(&sync);
    let whirl_sync = whirl_ratios(&sync);
    println!(
        "1. synchronous rub (friction 0.05, from rest, {} periods): radius {r_end:.8}, whirl ratio {:+.6}; closed form: radii {}",
        3 * periods,
        whirl_sync.last().map_or(f64::NAN, |w| w.1),
        closed.iter().map(|r| format!("{:.8}", r.radius)).collect::<Vec<_>>().join(", ")
    );

    let backward = run(&p, 0.2, [0.0; 6], periods, &opts);
    let (_, r_mean) = final_radius(&backward);
    let whirl_back = whirl_ratios(&backward);
    println!(
        "2. into backward whirl (friction 0.2, from rest): radius {r_mean:.6}, whirl ratio {:+.6} (a backward whirl at {:.6} times the spin)",
        whirl_back.last().map_or(f64::NAN, |w| w.1),
        whirl_back.last().map_or(f64::NAN, |w| -w.1),
    );

    let still = machine(0.0);
    let whip = run(&still, 0.2, [1.0, 0.0, 0.0, -2.0, 0.0, 0.0], periods, &opts);
    let whips = common::or_exit(dry_whip(&still, 0.2));
    let (r_whip, _) = final_radius(&whip);
    let whirl_whip = whirl_ratios(&whip);
    println!(
        "3. dry whip (no out-of-balance, kicked backward into the ring): radius {r_whip:.8}, whirl frequency {:.8}; closed form: {}",
        -whirl_whip.last().map_or(f64::NAN, |w| w.1) * still.eta,
        whips
            .iter()
            .map(|w| format!("radius {:.8} at frequency {:.8}", w.radius, w.frequency))
            .collect::<Vec<_>>()
            .join(", ")
    );

    let sync_radius = closed.iter().map(|r| r.radius).fold(f64::NAN, f64::max);
    let orbits = [
        Series::new("1. synchronous rub (μ = 0.05)", tail(&sync, 3)),
        Series::new("the closed form's rub", circle(sync_radius)),
        Series::new("the gap circle", circle(1.0)),
    ];
    let fig = Figure::new(
        &format!(
            "Synchronous full annular rub: the last 3 periods of {}; η = 1.2, K = 30, a = 5 gaps",
            3 * periods
        ),
        "x (units of the gap γ)",
        "y (units of the gap γ)",
    )
    .with_size(1000, 1000);
    common::or_exit(plot::lines(out.join("orbit_rub.png"), &fig, &orbits));
    let whip_radius = whips.iter().map(|w| w.radius).fold(f64::NAN, f64::max);
    let orbits = [
        Series::new("2. backward whirl (β = 0.5, μ = 0.2)", tail(&backward, 1)),
        Series::new("3. dry whip (β = 0, μ = 0.2)", tail(&whip, 1)),
        Series::new("the closed form's whip (β = 0)", circle(whip_radius)),
        Series::new("the gap circle", circle(1.0)),
    ];
    let fig = Figure::new(
        &format!("Backward whirl and dry whip: the last period of {periods}; η = 1.2, K = 30, a = 5 gaps"),
        "x (units of the gap γ)",
        "y (units of the gap γ)",
    )
    .with_size(1000, 1000);
    common::or_exit(plot::lines(out.join("orbit_whip.png"), &fig, &orbits));

    let fig = Figure::new(
        "Whirl ratio in each forcing period (+1: forward synchronous, < 0: backward)",
        "τ (time, 1/ω₁)",
        "whirl frequency / spin",
    )
    .with_columns("tau", "whirl_ratio");
    let whirl = [
        Series::new("1. μ = 0.05", whirl_sync),
        Series::new("2. μ = 0.2", whirl_back),
    ];
    common::or_exit(plot::lines(out.join("whirl.png"), &fig, &whirl));

    let slip = slip_velocities(&backward, p.eta);
    let turn = slip.len().min(40 * SAMPLES_PER_PERIOD);
    let fig = Figure::new(
        "Scene 2: slip velocity v while the whirl turns backward (v > 0 slipping forward, v = 0 rolling)",
        "τ (time, 1/ω₁)",
        "v (gaps per unit time)",
    )
    .with_columns("tau", "v");
    common::or_exit(plot::lines(
        out.join("slip_velocity.png"),
        &fig,
        &[Series::new("", slip[..turn].to_vec())],
    ));

    let mut points = Vec::new();
    for k in 0..flags.mu_steps {
        let mu = flags.mu_max * k as f64 / (flags.mu_steps - 1) as f64;
        let traj = run(&p, mu, [0.0; 6], periods, &opts);
        let n = traj.samples.len();
        for s in traj.samples[..n]
            .iter()
            .step_by(SAMPLES_PER_PERIOD)
            .rev()
            .take(flags.strobes)
        {
            points.push((mu, s.y[0].hypot(s.y[1])));
        }
        eprintln!("friction {mu:.4}: {} of {}", k + 1, flags.mu_steps);
    }
    let fig = Figure::new(
        &format!("Radius at the forcing period, last {} of {periods} periods from rest, against the friction", flags.strobes),
        "friction coefficient μ",
        "|r| (units of the gap γ)",
    )
    .with_columns("mu", "radius")
    .with_log(false, true);
    common::or_exit(plot::bifurcation(
        out.join("friction_bifurcation.png"),
        &fig,
        &points,
    ));
    println!("pictures in {}", out.display());
}
