//! A run-up (or run-down) of the paper's rotor through its critical speed, with or without the
//! snubber ring: the speed ramps at the constant rate `--rate` $R = d\eta/d\tau$ from
//! `--eta-from` $A$ to `--eta-to` $B$ ($R < 0$ for a run-down, $A > B$), and the run stops when
//! it reaches $B$, at $\tau = (B - A)/R$.
//!
//! With `--csv`, prints the CSV `tau,eta,x,y` at `--samples-per-period` $S$ equally spaced
//! phases per revolution of the out-of-balance: row `k` is at the time where the forcing phase
//! $\varphi(\tau) = \varphi_0 + A\tau + R\tau^2/2$ reaches $\varphi_0 + 2\pi k/S$ (closed
//! form), for every such time up to the end. Without `--csv`, prints one summary line: the
//! largest radius $|r|$ from the ring's centre, the speed and time where it occurred, the number
//! of samples and of contacts. With `--out DIR` the run goes up and comes back in one piecewise
//! profile (from $A$ to $B$ at $R$, then to $A$ at $-R$: the down leg starts where the up leg
//! ended, so the envelopes show the hysteresis), prints a summary line per leg, and writes in
//! `DIR`: `envelope.png` (with `envelope.csv`), the largest radius in each revolution against
//! the speed for both legs; `revolutions.csv`, per revolution its start, mean speed, largest
//! radius, time in contact and fraction of time in each regime; and for the up leg (with
//! $S \ge 8$) `orders.png`, the whirl radii of the orders 1/2, 1, 3/2, 2 and 3 against the
//! speed (windows of 8 revolutions, Hann), and `waterfall.png`, the windows' full spectra.
//! With `--peak-rates LIST` the example runs from $A$ to $B$ at each rate instead (the sign
//! of $B - A$; `--rate` is then not used), prints the peak radius and its speed for each, and
//! with `--out DIR` draws `DIR/peak_vs_rate.png`.
//!
//! With `--motor T0,OMEGA0,INERTIA` the speed is not prescribed but driven (the non-ideal drive,
//! `rotor::DrivenJeffcott`): the DC motor $t = T_0(1 - \eta/\Omega_0)$ through the polar inertia
//! $j$ = INERTIA, from $\eta = A$ for `--duration` (default 1500); it prints $\eta(\tau)$ at
//! every tenth of the run, the mean and largest speed over its last third and the contacts,
//! and with `--out DIR` draws `DIR/speed.png` ($\eta(\tau)$) and `DIR/drive_envelope.png`
//! (the largest radius in each revolution against its mean speed), each with its CSV. With
//! `--friction MU --shaft-radius A` (A in gaps) Coulomb friction acts at the ring
//! (`rotor::RubbingRotor`, docs/friction.md) and its rub torque $-a\thinspace t\cdot f$ brakes
//! the drive; the summary then counts the slip stops and the ends of rolling.
//!
//! With `--fe` a finite-element rotor runs instead (`rotor::ProfiledLinearRotor`): ROSS's
//! 204-DOF `rotor_example_with_damping` (`--fe-mat`, default the repository's copy of
//! `../shared/rotors/rotor_example_with_damping_1200rpm.mat`) with case S1's ring at node 12,
//! reduced to 24 Craig-Bampton modes (each of these a flag: `--fe-ring-node`, `--fe-gap`,
//! `--fe-ring-stiffness`, `--fe-ring-damping`, `--fe-unbalance`, `--fe-modes`), from
//! `--fe-from` (100) to `--fe-to` (260) rad/s at `--fe-rate` (50) rad/s² and back, with and without the ring: a line per run and leg, and
//! `fe_envelope.png` (with its CSV) in `--out` (default `target/run_up`). The speed may instead
//! follow the user's table (`--fe-profile FILE`: `time,speed` rows, s and rad/s, linear
//! between them) or be driven by a DC motor (`--fe-motor T0,OMEGA0,J`: $T = T_0(1 -
//! \Omega/\Omega_0)$ N m through the polar inertia $J$ kg m², from `--fe-from` for
//! `--fe-duration` s, `rotor::DrivenLinearRotor`); the bearings may follow the speed
//! (`--fe-bearing-mat SPEED:FILE`, repeated: ROSS exports of the rotor at several speeds, their
//! lateral stiffness and damping linear between the speeds, `rotor::BearingTable`). With
//! `--fe-rub-map` the sweep's rotor's rub map too (`stability::rub_map`: its steady orbits on
//! the ring continued in speed from `--fe-from`, below the first contact, to `--fe-to`, with
//! their stability and every grazing, fold, flip and Neimark-Sacker point printed), drawn over
//! the envelopes (docs/rub-map.md).
//!
//! The scene flags are `simulate`'s (`--preset`, parameter overrides, `--rtol`, `--atol`,
//! `--method`, the initial rotor state `--x0 --y0 --vx0 --vy0`, default at rest at the origin;
//! the ring starts at its centre, or at its minimum-energy position if the rotor starts in
//! contact). `--eta` is accepted but unused: the ramp sets the speed. `--no-ring` puts the ring
//! out of reach (a gap of 1e6). The out-of-balance force includes the terms of the speed's rate,
//! $\beta(\eta^2\cos\varphi + \eta^\prime\sin\varphi, \eta^2\sin\varphi - \eta^\prime\cos\varphi)$.
//!
//! Exit status: 0 on success; 2 with one `error: ...` line on standard error for bad input;
//! 1 with one line on standard error if the simulation fails (after the rows computed so far).
//!
//! Without arguments the example runs a tour, with a line of progress per run: Fig. 8a's rotor
//! (`--x0 0.9`) from $\eta$ 0.3 to 3 and back at the rates 0.01 and 0.002, on the ring and
//! without it, each run's pictures in `target/run_up/{ring,no_ring}_rate_R/`, then the
//! finite-element rotor's `--fe` run into `target/run_up`.
//!
//! ```text
//! cargo run --release --example run_up
//! cargo run --release --example run_up -- --preset fig8a --eta-from 0.3 --eta-to 3 --rate 0.01 --samples-per-period 16 --csv
//! ```

#[path = "../common/mod.rs"]
mod common;
mod drive;
mod envelope;
mod fe;
mod orders;
mod rub_map;
mod tour;

use std::io::{self, BufWriter, Write};
use std::path::{Path, PathBuf};

use clap::Parser;
use common::cli::{f64_in, fail, parse, usize_in};
use common::csv::write_f64;
use common::scene::{Scene, SceneFlags};
use jeffcott::analysis::{per_revolution, Revolution};
use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimError, Trajectory};
use jeffcott::nalgebra::{SVector, U6};
use jeffcott::rotor::{ProfiledJeffcott, Segment, SmoothRotor, SpeedProfile};
use jeffcott::JeffcottModel;

/// A run-up or run-down of the paper's rotor at a constant rate R = d eta / d tau from eta = A
/// to eta = B: CSV tau,eta,x,y at S phases per revolution (--csv), or one summary line.
#[derive(Parser)]
#[command(name = "run_up")]
struct Flags {
    #[command(flatten)]
    scene: SceneFlags,
    /// Put the ring out of reach (no contact)
    #[arg(long)]
    no_ring: bool,
    /// Speed A at the start [range: 0..=1000] (not with --fe)
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(0.0, 1e3), required_unless_present = "fe")]
    eta_from: Option<f64>,
    /// Speed B at the end [range: 0..=1000] (not with --motor)
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(0.0, 1e3), required_unless_present_any = ["motor", "fe"], conflicts_with = "motor")]
    eta_to: Option<f64>,
    /// Rate R = d eta / d tau, not 0, < 0 for a run-down [range: -1000..=1000] (not with --motor)
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(-1e3, 1e3), required_unless_present_any = ["motor", "fe"], conflicts_with = "motor")]
    rate: Option<f64>,
    /// A non-ideal drive instead of a ramp: the DC motor t = T0 (1 - eta/OMEGA0) with the polar
    /// inertia j = INERTIA (non-dimensional), from eta = A for --duration
    #[arg(long, value_name = "T0,OMEGA0,INERTIA", value_delimiter = ',', value_parser = f64_in(-1e6, 1e12), conflicts_with_all = ["csv", "peak_rates"])]
    motor: Vec<f64>,
    /// With --motor: Coulomb friction between ring and shaft (>= 0; 0: frictionless), whose rub
    /// torque brakes the drive
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(0.0, 1e3), default_value_t = 0.0)]
    friction: f64,
    /// With --motor and --friction > 0: the shaft's radius at the ring, in gaps [range: 0..=1000]
    #[arg(long, value_name = "NUMBER", value_parser = f64_in(0.0, 1e3))]
    shaft_radius: Option<f64>,
    /// With --motor: how long the run lasts, tau [range: 0..=1000000]
    #[arg(long, value_name = "NUMBER", default_value_t = 1500.0, value_parser = f64_in(0.0, 1e6))]
    duration: f64,
    /// Samples S per revolution of the out-of-balance [range: 1..=1000000] (not with --fe)
    #[arg(long, value_name = "COUNT", value_parser = usize_in(1, 1_000_000), required_unless_present = "fe")]
    samples_per_period: Option<usize>,
    /// Print the samples as CSV tau,eta,x,y
    #[arg(long)]
    csv: bool,
    /// Instead of one run: run up at each of these rates (|R|, the sign of B - A), print the
    /// peak radius and its speed for each, and with --out draw peak_vs_rate.png
    #[arg(long, value_name = "LIST", value_delimiter = ',', value_parser = f64_in(1e-6, 1e3), conflicts_with = "csv")]
    peak_rates: Vec<f64>,
    /// Without --csv: run up and back, draw the envelope, the orders and the waterfall here
    #[arg(long, value_name = "DIR", conflicts_with = "csv")]
    out: Option<PathBuf>,
    /// Instead: a finite-element rotor (by default ROSS's 204-DOF rotor with S1's ring at node
    /// 12, reduced to 24 modes) up from --fe-from to --fe-to and back, with and without the ring;
    /// writes fe_envelope.png in --out (default target/run_up)
    #[arg(long, conflicts_with_all = ["csv", "motor", "peak_rates"])]
    fe: bool,
    /// With --fe: the rotor's ROSS .mat [default: tests/data/rotors/rotor_example_with_damping_1200rpm.mat,
    /// a copy of ../shared/rotors/]
    #[arg(long, value_name = "FILE", requires = "fe")]
    fe_mat: Option<PathBuf>,
    /// With --fe: the speed at the start and end, rad/s [range: 1..=10000]
    #[arg(long, value_name = "NUMBER", default_value_t = 100.0, value_parser = f64_in(1.0, 1e4))]
    fe_from: f64,
    /// With --fe: the top speed, rad/s [range: 1..=10000]
    #[arg(long, value_name = "NUMBER", default_value_t = 260.0, value_parser = f64_in(1.0, 1e4))]
    fe_to: f64,
    /// With --fe: the rate, rad/s² [range: 1..=100000]
    #[arg(long, value_name = "NUMBER", default_value_t = 50.0, value_parser = f64_in(1.0, 1e5))]
    fe_rate: f64,
    /// With --fe: the ring's node (0-based)
    #[arg(long, value_name = "NODE", default_value_t = 12)]
    fe_ring_node: usize,
    /// With --fe: the ring's radial gap, m [range: 1e-9..=1]
    #[arg(long, value_name = "NUMBER", default_value = "7.95e-5", value_parser = f64_in(1e-9, 1.0))]
    fe_gap: f64,
    /// With --fe: the ring's unit stiffness, N/m [range: 1..=1e12]
    #[arg(long, value_name = "NUMBER", default_value_t = 1.1e6, value_parser = f64_in(1.0, 1e12))]
    fe_ring_stiffness: f64,
    /// With --fe: the ring's unit damping, N s/m [range: 0..=1e9]
    #[arg(long, value_name = "NUMBER", default_value_t = 0.01, value_parser = f64_in(0.0, 1e9))]
    fe_ring_damping: f64,
    /// With --fe: the out-of-balance's node, m e (kg m) and phase (rad)
    #[arg(
        long,
        value_name = "NODE,ME,PHASE",
        num_args = 1,
        value_delimiter = ',',
        default_value = "12,2e-3,-1.5707963267948966"
    )]
    fe_unbalance: Vec<f64>,
    /// With --fe: the Craig-Bampton modes kept [range: 1..=10000]
    #[arg(long, value_name = "COUNT", default_value_t = 24, value_parser = usize_in(1, 10_000))]
    fe_modes: usize,
    /// With --fe: the speed through a table instead of up and back: a CSV of time,speed rows
    /// (s, rad/s; the first time 0; a header line allowed), linear between them, held after
    #[arg(
        long,
        value_name = "FILE",
        requires = "fe",
        conflicts_with = "fe_motor"
    )]
    fe_profile: Option<PathBuf>,
    /// With --fe: the speed driven instead (the non-ideal drive): the DC motor
    /// T = T0 (1 - Omega/OMEGA0) (N m) through the polar inertia J (kg m²), from --fe-from
    /// for --fe-duration
    #[arg(long, value_name = "T0,OMEGA0,J", value_delimiter = ',', value_parser = f64_in(-1e12, 1e12), requires = "fe")]
    fe_motor: Vec<f64>,
    /// With --fe-motor: how long the run lasts, s [range: 0..=1000]
    #[arg(long, value_name = "NUMBER", default_value_t = 2.0, value_parser = f64_in(0.0, 1e3))]
    fe_duration: f64,
    /// With --fe: bearings that follow the speed: the rotor exported by ROSS at SPEED (rad/s),
    /// its lateral stiffness and damping taken (repeat for each speed; linear between the
    /// speeds, held beyond them)
    #[arg(long, value_name = "SPEED:FILE", requires = "fe")]
    fe_bearing_mat: Vec<String>,
    /// With --fe: also the rub map of the same rotor from --fe-from to --fe-to (its steady
    /// orbits on the ring continued in speed, with their stability, grazings, folds, flips and
    /// Neimark-Sacker points; stability::rub_map), drawn over the envelopes. --fe-from must be
    /// below the first contact
    #[arg(long, requires = "fe", conflicts_with_all = ["fe_profile", "fe_motor"])]
    fe_rub_map: bool,
}

impl Flags {
    /// `--eta-from` (clap requires it without `--fe`).
    fn eta_from(&self) -> f64 {
        self.eta_from
            .unwrap_or_else(|| fail("--eta-from is required"))
    }

    /// `--samples-per-period` (clap requires it without `--fe`).
    fn samples_per_period(&self) -> usize {
        self.samples_per_period
            .unwrap_or_else(|| fail("--samples-per-period is required"))
    }

    /// `--eta-to` (clap requires it without `--motor`).
    fn eta_to(&self) -> f64 {
        self.eta_to.unwrap_or_else(|| fail("--eta-to is required"))
    }

    /// `--rate` (clap requires it without `--motor`).
    fn rate(&self) -> f64 {
        self.rate.unwrap_or_else(|| fail("--rate is required"))
    }
}

/// The ramp of the flags, or exit with status 2.
fn ramp(flags: &Flags) -> SpeedProfile {
    if flags.eta_from() == flags.eta_to() {
        fail("--eta-from and --eta-to must differ (a ramp)");
    }
    SpeedProfile::ramp(flags.eta_from(), flags.eta_to(), flags.rate())
        .unwrap_or_else(|e| fail(format!("--rate: {e}")))
}

/// The rotor at `profile` and its consistent initial state, or exit with status 2.
fn setup(
    flags: &Flags,
    scene: &Scene,
    profile: SpeedProfile,
) -> (ProfiledJeffcott, SVector<f64, 6>) {
    let samples = u32::try_from(flags.samples_per_period()).unwrap_or(u32::MAX);
    let rotor = ProfiledJeffcott::new(scene.params, profile)
        .unwrap_or_else(|e| fail(e))
        .with_strobes_per_revolution(samples)
        .unwrap_or_else(|e| fail(e));
    let [x0, y0, vx0, vy0] = scene.start;
    let mut start = SVector::<f64, 6>::from([x0, y0, vx0, vy0, 0.0, 0.0]);
    if !flags.no_ring {
        // The paper's model places the ring for a start in contact; it has the same ring.
        let paper = JeffcottModel::new(*rotor.params()).unwrap_or_else(|e| fail(e));
        start = paper
            .state_at([x0, y0], [vx0, vy0])
            .unwrap_or_else(|e| fail(format!("initial state: {e}")));
    }
    (rotor, start)
}

/// Runs `profile` to its end with the strobes at the sampled phases.
fn run(
    flags: &Flags,
    scene: &Scene,
    profile: SpeedProfile,
) -> (ProfiledJeffcott, Trajectory<U6>, Option<SimError<U6>>) {
    let (rotor, start) = setup(flags, scene, profile);
    let model = if flags.no_ring {
        rotor.off_ring()
    } else {
        rotor.on_ring()
    }
    .unwrap_or_else(|e| fail(e));
    let mut plan = OutputPlan::every_strobe(rotor.profile().ramp_time());
    // Dense samples 256 a revolution at the top speed: knots of the per-revolution peak (on
    // the ring the station moves faster than the strobes resolve; analysis::per_revolution).
    plan.dense = Some(DenseSampling {
        t_start: 0.0,
        dt: std::f64::consts::TAU / rotor.profile().eta_max() / 256.0,
    });
    let mut traj = Trajectory::default();
    let error = simulate(&model, 0.0, &start, &plan, &scene.opts, &mut traj).err();
    (rotor, traj, error)
}

fn write_csv(
    out: &mut impl Write,
    rotor: &ProfiledJeffcott,
    traj: &Trajectory<U6>,
) -> io::Result<()> {
    writeln!(out, "tau,eta,x,y")?;
    for p in &traj.strobe {
        for (i, v) in [p.t, rotor.profile().eta(p.t), p.y[0], p.y[1]]
            .into_iter()
            .enumerate()
        {
            if i > 0 {
                out.write_all(b",")?;
            }
            write_f64(out, v)?;
        }
        writeln!(out)?;
    }
    Ok(())
}

/// One summary line for the strobes and events within `[from, to]`.
fn write_summary(
    out: &mut impl Write,
    rotor: &ProfiledJeffcott,
    traj: &Trajectory<U6>,
    (from, to): (f64, f64),
) -> io::Result<()> {
    let strobes: Vec<_> = traj
        .strobe
        .iter()
        .filter(|p| p.t >= from && p.t <= to)
        .collect();
    let radius = |i: usize| strobes[i].y[0].hypot(strobes[i].y[1]);
    let peak = (0..strobes.len()).max_by(|&a, &b| radius(a).total_cmp(&radius(b)));
    let contacts = traj
        .events
        .iter()
        .filter(|e| e.kind == "contact onset" && e.t >= from && e.t <= to)
        .count();
    let n = strobes.len();
    match peak {
        Some(i) => {
            let t = strobes[i].t;
            let eta = rotor.profile().eta(t);
            writeln!(
                out,
                "peak radius {} at eta {eta} (tau {t}); {n} samples, {contacts} contacts",
                radius(i)
            )
        }
        None => writeln!(out, "no samples; {contacts} contacts"),
    }
}

fn main() {
    if std::env::args_os().len() == 1 {
        run_tour();
        return;
    }
    let flags: Flags = parse();
    let scene = flags.scene.scene();
    if flags.fe {
        fe_run(&flags);
        return;
    }
    if flags.motor.is_empty() && (flags.friction > 0.0 || flags.shaft_radius.is_some()) {
        fail("--friction and --shaft-radius need --motor (a ramp's run-up with friction is not built yet)");
    }
    if !flags.motor.is_empty() {
        let friction = (flags.friction > 0.0).then(|| {
            let radius = flags.shaft_radius.unwrap_or_else(|| {
                fail("--friction needs --shaft-radius (the shaft's radius at the ring, in gaps)")
            });
            (flags.friction, radius)
        });
        drive::run(
            &flags.motor,
            friction,
            flags.eta_from(),
            flags.duration,
            flags.no_ring,
            &scene,
            flags.samples_per_period(),
            flags.out.as_deref(),
        );
        return;
    }
    if !flags.peak_rates.is_empty() {
        peak_against_rate(&flags, &scene);
        return;
    }
    if let Some(dir) = &flags.out {
        up_and_back(&flags, &scene, dir);
        return;
    }
    let (rotor, traj, error) = run(&flags, &scene, ramp(&flags));
    let stdout = io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let written = if flags.csv {
        write_csv(&mut out, &rotor, &traj)
    } else {
        write_summary(&mut out, &rotor, &traj, (0.0, f64::INFINITY))
    }
    .and_then(|_| out.flush());
    if let Err(e) = written {
        // A closed pipe (e.g. `| head`) is not an error of the simulation.
        if e.kind() != io::ErrorKind::BrokenPipe {
            eprintln!("error: writing the output: {e}");
            std::process::exit(1);
        }
    }
    if let Some(e) = error {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
}

/// The sweep from A to B and back to A at the same rate, in one run (the down leg starts where
/// the up leg ended): a summary line per leg, the envelope of both, the per-revolution table,
/// and the order tracking and waterfall of each leg.
/// Without arguments: the tour of [`tour`], a line of progress before each run.
fn run_tour() {
    let runs = tour::paper_runs();
    let total = runs.len() + 1;
    for (i, args) in runs.iter().enumerate() {
        println!("[{}/{total}] {}", i + 1, args[1..].join(" "));
        let flags = Flags::try_parse_from(args).unwrap_or_else(|e| fail(e));
        let scene = flags.scene.scene();
        let dir = flags.out.clone().unwrap_or_default();
        up_and_back(&flags, &scene, &dir);
    }
    println!("[{total}/{total}] --fe --out target/run_up");
    let flags = Flags::try_parse_from(["run_up", "--fe"]).unwrap_or_else(|e| fail(e));
    fe_run(&flags);
}

/// `--fe`: the finite-element rotor up and back (or through a table, or on a motor), with
/// and without the ring.
fn fe_run(flags: &Flags) {
    let law = fe_law(flags);
    let setup = fe_setup(flags);
    let mat = flags.fe_mat.clone().unwrap_or_else(fe::default_mat);
    let dir = flags
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from("target/run_up"));
    common::or_exit(std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display())));
    // Bad files are bad input (status 2), found before the runs.
    fe::check(&mat, &setup).unwrap_or_else(|e| fail(e));
    common::or_exit(fe::run(&mat, (&law, &setup), &dir));
}

/// How the speed of `--fe` goes, from its flags.
fn fe_law(flags: &Flags) -> fe::Law {
    if let Some(path) = &flags.fe_profile {
        return fe::Law::Table(fe::read_table(path).unwrap_or_else(|e| fail(e)));
    }
    if !flags.fe_motor.is_empty() {
        let &[stall, no_load, inertia] = flags.fe_motor.as_slice() else {
            fail("--fe-motor takes three numbers: T0,OMEGA0,J");
        };
        return fe::Law::Motor {
            stall,
            no_load,
            inertia,
            from: flags.fe_from,
            duration: flags.fe_duration,
        };
    }
    if flags.fe_to <= flags.fe_from {
        fail("--fe-to must be above --fe-from");
    }
    fe::Law::Sweep {
        from: flags.fe_from,
        to: flags.fe_to,
        rate: flags.fe_rate,
    }
}

/// `--fe-bearing-mat SPEED:FILE`, each.
fn fe_bearings(flags: &Flags) -> Vec<(f64, PathBuf)> {
    let parse = |item: &String| {
        let (speed, file) = item
            .split_once(':')
            .unwrap_or_else(|| fail(format!("--fe-bearing-mat {item}: not SPEED:FILE")));
        let speed: f64 = speed.parse().unwrap_or_else(|_| {
            fail(format!(
                "--fe-bearing-mat {item}: the speed is not a number"
            ))
        });
        (speed, PathBuf::from(file))
    };
    flags.fe_bearing_mat.iter().map(parse).collect()
}

/// The ring, out-of-balance and reduction of `--fe` from its flags.
fn fe_setup(flags: &Flags) -> fe::Setup {
    let &[node, me, phase] = flags.fe_unbalance.as_slice() else {
        fail("--fe-unbalance takes three numbers: NODE,ME,PHASE");
    };
    if node < 0.0 || node.fract() != 0.0 {
        fail(format!(
            "--fe-unbalance: the node {node} is not a node number"
        ));
    }
    fe::Setup {
        ring_node: flags.fe_ring_node,
        gap: flags.fe_gap,
        ring_stiffness: flags.fe_ring_stiffness,
        ring_damping: flags.fe_ring_damping,
        unbalance: (node as usize, me, phase),
        modes: flags.fe_modes,
        bearings: fe_bearings(flags),
        rub_map: flags.fe_rub_map,
    }
}

fn up_and_back(flags: &Flags, scene: &Scene, dir: &Path) {
    let up = ramp(flags);
    let legs = [
        Segment::Ramp {
            to: flags.eta_to(),
            rate: flags.rate(),
        },
        Segment::Ramp {
            to: flags.eta_from(),
            rate: -flags.rate(),
        },
    ];
    let profile = SpeedProfile::piecewise(flags.eta_from(), &legs).unwrap_or_else(|e| fail(e));
    let (rotor, traj, error) = run(flags, scene, profile);
    let turn = up.ramp_time();
    let mut out = io::stdout().lock();
    for span in [(0.0, turn), (turn, f64::INFINITY)] {
        if let Err(e) = write_summary(&mut out, &rotor, &traj, span) {
            eprintln!("error: writing the output: {e}");
            std::process::exit(1);
        }
    }
    if let Some(e) = error {
        eprintln!("error: {e}");
        std::process::exit(1);
    }
    common::or_exit(std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display())));
    common::or_exit(draw_legs(flags, dir, &rotor, &traj, turn));
}

/// The pictures and tables of the two legs, split at the turn.
fn draw_legs(
    flags: &Flags,
    dir: &Path,
    rotor: &ProfiledJeffcott,
    traj: &Trajectory<U6>,
    turn: f64,
) -> Result<(), String> {
    let s = flags.samples_per_period();
    let revs = per_revolution(traj, s, |y| rotor.station(y)).map_err(|e| e.to_string())?;
    let (up, down): (Vec<Revolution>, Vec<Revolution>) =
        revs.into_iter().partition(|r| r.t_start < turn);
    let label = |a: f64, b: f64, r: f64| format!("{a} → {b} at R = {r}");
    let legs = [
        (label(flags.eta_from(), flags.eta_to(), flags.rate()), up),
        (label(flags.eta_to(), flags.eta_from(), -flags.rate()), down),
    ];
    let ring = if flags.no_ring {
        "without the ring"
    } else {
        "on the ring"
    };
    let preset = &flags.scene.preset;
    envelope::draw(dir, &format!("{preset} {ring}: envelope"), &legs)?;
    envelope::write_table(dir, &legs)?;
    if s < 8 {
        eprintln!("note: order tracking up to order 3 needs --samples-per-period >= 8; skipped");
        return Ok(());
    }
    let strobes: Vec<_> = traj.strobe.iter().map(|p| (p.t, p.y[0], p.y[1])).collect();
    let rows = orders::track(s, rotor.params().phi0, &strobes)?;
    let (up_rows, _): (Vec<_>, Vec<_>) = rows.into_iter().partition(|r| r.time < turn);
    let leg = &legs[0].0;
    orders::draw_orders(dir, &format!("{preset} {ring}, {leg}: orders"), &up_rows)?;
    orders::draw_waterfall(dir, &format!("{preset} {ring}, {leg}: waterfall"), &up_rows)
}

/// The peak radius and its speed for a run up (or down) at each of `--peak-rates`; with `--out`
/// the picture `peak_vs_rate.png` of both against the rate.
fn peak_against_rate(flags: &Flags, scene: &Scene) {
    let sign = (flags.eta_to() - flags.eta_from()).signum();
    let mut peaks = Vec::new();
    for &r in &flags.peak_rates {
        let one = Flags {
            rate: Some(sign * r),
            scene: flags.scene.clone(),
            motor: Vec::new(),
            out: None,
            peak_rates: Vec::new(),
            fe_mat: None,
            fe_unbalance: Vec::new(),
            fe_profile: None,
            fe_motor: Vec::new(),
            fe_bearing_mat: Vec::new(),
            ..*flags
        };
        let (rotor, traj, error) = run(&one, scene, ramp(&one));
        if let Some(e) = error {
            fail(format!("rate {r}: {e}"));
        }
        let peak = traj
            .strobe
            .iter()
            .map(|p| (p.y[0].hypot(p.y[1]), rotor.profile().eta(p.t)))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((radius, eta)) = peak {
            println!("rate {r}: peak radius {radius} at eta {eta}");
            peaks.push((r, radius, eta));
        }
    }
    if let Some(dir) = &flags.out {
        common::or_exit(
            std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display())),
        );
        let ring = if flags.no_ring {
            "without the ring"
        } else {
            "on the ring"
        };
        let title = format!("{} {ring}: peak against the rate", flags.scene.preset);
        let fig = common::plot::Figure::new(&title, "|R| = |dη/dτ|", "peak |r| and its η")
            .with_columns("rate", "value")
            .with_log(true, false)
            .with_markers();
        let series = [
            common::plot::Series::new("peak radius", peaks.iter().map(|p| (p.0, p.1)).collect()),
            common::plot::Series::new("η at the peak", peaks.iter().map(|p| (p.0, p.2)).collect()),
        ];
        common::or_exit(
            common::plot::lines(dir.join("peak_vs_rate.png"), &fig, &series)
                .map_err(|e| e.to_string()),
        );
    }
}
