//! A finite-element rotor exported by ROSS on the snubber ring: the transient from rest,
//! event-located, in SI units, with the full model or a Craig-Bampton reduction.
//!
//! Reads `rotor.save_mat(file, speed)`'s MAT file (ROSS's layout, six DOFs a node; the axial
//! and torsional DOFs are dropped after checking that they are uncoupled), puts the ring at
//! `--ring-node` and the unbalances where `--unbalance NODE:KGM:PHASE` says, and runs from rest
//! (q = q' = 0, the ring at its centre, as ROSS's Newmark starts) to `--t-end`.
//!
//! Prints the CSV `t,x,y` on stdout: the ring node's displacement (m, from its undeflected
//! position) at `--samples` + 1 equally spaced times from 0 to `--t-end`; one summary line on
//! stderr (contacts, steps, seconds); draws in `--out` the orbit at the ring node with the gap
//! circle (`orbit.png`) and x(t), y(t) (`displacement.png`).
//!
//! With `--friction MU` (> 0) Coulomb friction acts between the ring and a shaft of radius
//! `--shaft-radius A` (m, the shaft's outer radius at the ring node; required then: ROSS's
//! export holds the matrices only) spinning counter-clockwise (`rotor::RubbingRotor`,
//! docs/friction.md); the summary line counts the slip stops and the ends of rolling.
//!
//! Without `--method` the fastest path measured to the requested accuracy runs
//! (docs/fe-rotors.md, "The fastest accurate path"): the full model in its modal coordinates
//! with ETD4, a reduced one with DOP853; the summary line names it, "(default)".
//!
//! ```text
//! cargo run --release --example ross_rotor -- --mat ../shared/rotors/rotor_example_with_damping_1200rpm.mat \
//!     --speed-rpm 1200 --ring-node 12 --gap 7.95e-5 --ring-stiffness 1.1e6 --ring-damping 0.01 \
//!     --unbalance 12:2e-3:-1.5707963267948966 --t-end 0.5 --samples 1000 > s1.csv
//! ```

#[path = "../common/mod.rs"]
mod common;

use std::path::PathBuf;
use std::time::Instant;

use clap::Parser;
use common::cli::{f64_in, fail, parse, usize_in};
use common::plot::{self, Figure, Series};
use common::scene::MethodFlag;
use jeffcott::hybrid::RotorModel;
use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, SimOptions, Trajectory};
use jeffcott::nalgebra::{DVector, Dyn};
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{
    CraigBampton, LinearClosedForm, LinearRotor, LinearSystem, ModalRotor, ModeSelection,
    RingedRotor, RotorError, RotorMatrices, RubbingRotor, SmoothRotor,
};

/// One out-of-balance: node, magnitude (kg m), phase (rad).
#[derive(Clone, Copy, Debug)]
struct Unbalance {
    node: usize,
    me: f64,
    phase: f64,
}

fn unbalance(s: &str) -> Result<Unbalance, String> {
    let parts: Vec<&str> = s.split(':').collect();
    let [node, me, phase] = parts[..] else {
        return Err("expected NODE:KGM:PHASE, e.g. 12:2e-3:-1.5708".into());
    };
    let node = node
        .trim()
        .parse()
        .map_err(|_| format!("node '{node}' is not a whole number"))?;
    let num = |v: &str, what: &str| match v.trim().parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("{what} '{v}' is not a finite number")),
    };
    Ok(Unbalance {
        node,
        me: num(me, "magnitude")?,
        phase: num(phase, "phase")?,
    })
}

/// A ROSS rotor on the snubber ring: the transient from rest at the ring node.
#[derive(Parser)]
#[command(name = "ross_rotor")]
struct Flags {
    /// ROSS's export, rotor.save_mat(FILE, speed) (MATLAB v5: M, K, C, G)
    #[arg(long, value_name = "FILE")]
    mat: PathBuf,
    /// Spin speed in rpm (the speed the file was exported at: its bearing coefficients are
    /// those of that speed) [range: 0..=1e6]
    #[arg(long, allow_hyphen_values = true, value_name = "R", value_parser = f64_in(0.0, 1e6))]
    speed_rpm: f64,
    /// Node of the ring (0-based, ROSS's numbering)
    #[arg(long, value_name = "N")]
    ring_node: usize,
    /// Radial gap (m) [range: 1e-12..=1]
    #[arg(long, allow_hyphen_values = true, value_name = "G", value_parser = f64_in(1e-12, 1.0))]
    gap: f64,
    /// Unit stiffness k_s of the ring's spring units (N/m) [range: 1e-6..=1e15]
    #[arg(long, allow_hyphen_values = true, value_name = "KS", value_parser = f64_in(1e-6, 1e15))]
    ring_stiffness: f64,
    /// Unit damping c_s of the ring's units (N s/m) [range: 0..=1e12]
    #[arg(long, allow_hyphen_values = true, value_name = "CS", value_parser = f64_in(0.0, 1e12))]
    ring_damping: f64,
    /// Preload of the x units, Delta_x (m) [range: 0..=1]
    #[arg(long, allow_hyphen_values = true, value_name = "DX", default_value = "0", value_parser = f64_in(0.0, 1.0))]
    preload_x: f64,
    /// Preload of the y units, Delta_y (m) [range: 0..=1]
    #[arg(long, allow_hyphen_values = true, value_name = "DY", default_value = "0", value_parser = f64_in(0.0, 1.0))]
    preload_y: f64,
    /// The ring's rest centre from the undeflected node, x (m) [range: -1..=1]
    #[arg(long, allow_hyphen_values = true, value_name = "OX", default_value = "0", value_parser = f64_in(-1.0, 1.0))]
    ring_offset_x: f64,
    /// The ring's rest centre from the undeflected node, y (m) [range: -1..=1]
    #[arg(long, allow_hyphen_values = true, value_name = "OY", default_value = "0", value_parser = f64_in(-1.0, 1.0))]
    ring_offset_y: f64,
    /// An out-of-balance NODE:KGM:PHASE (node, m e in kg m, phase in rad); repeat for more
    #[arg(long, value_name = "NODE:KGM:PHASE", value_parser = unbalance, required = true)]
    unbalance: Vec<Unbalance>,
    /// End time (s) [range: 0..=1e4]
    #[arg(long, allow_hyphen_values = true, value_name = "T", value_parser = f64_in(0.0, 1e4))]
    t_end: f64,
    /// Output intervals: S + 1 samples from 0 to T [range: 1..=10000000]
    #[arg(long, value_name = "S", value_parser = usize_in(1, 10_000_000))]
    samples: usize,
    /// Fixed-interface modes kept by a Craig-Bampton reduction (the ring node's x, y stay
    /// physical); 0 or absent: the full model [range: 0..=100000]
    #[arg(long, value_name = "M", default_value = "0", value_parser = usize_in(0, 100_000))]
    modes: usize,
    /// Relative tolerance [range: 1e-14..=1e-2]
    #[arg(long, allow_hyphen_values = true, value_name = "R", default_value = "1e-8", value_parser = f64_in(1e-14, 1e-2))]
    rtol: f64,
    /// Integration method of contact phases; default: the fastest measured to the requested
    /// accuracy (docs/fe-rotors.md): etd4 for the full model (radau5 where its modal form
    /// cannot be built: the summary says why), dop853 for a reduced one (accuracy sets the
    /// step); etd4 runs the rotor in its modal coordinates (free flight exact, contact
    /// integrated with the modes propagated exactly: cost linear in the modes)
    #[arg(long, value_enum)]
    method: Option<MethodFlag>,
    /// Folder of the pictures
    #[arg(long, value_name = "DIR", default_value = "target/figures/ross_rotor")]
    out: PathBuf,
    /// Coulomb friction coefficient between ring and shaft (0: frictionless) [range: 0..=100]
    #[arg(long, allow_hyphen_values = true, value_name = "MU", default_value = "0", value_parser = f64_in(0.0, 100.0))]
    friction: f64,
    /// The shaft's outer radius at the ring node (m; required with --friction > 0) [range: 1e-9..=100]
    #[arg(long, allow_hyphen_values = true, value_name = "A", value_parser = f64_in(1e-9, 100.0))]
    shaft_radius: Option<f64>,
}

/// A bad input: `error: ...` on stderr, status 2.
fn check<T, E: std::fmt::Display>(r: Result<T, E>, what: &str) -> T {
    r.unwrap_or_else(|e| fail(format!("{what}: {e}")))
}

fn main() {
    let mut f: Flags = parse();
    let (rotor, ring, kept) = model(&f);
    let dofs = rotor.system().dofs();
    let asked = f.method.is_some();
    f.method = Some(method(&f));
    let mut picked = if asked { "" } else { " (default)" }.to_string();
    let modal = match f.method {
        Some(MethodFlag::Etd4) => match ModalRotor::new(&rotor) {
            Ok(modal) => Some(modal),
            Err(e) if !asked => {
                // The default's fallback: the stiff physical form, and why.
                f.method = Some(MethodFlag::Radau5);
                picked = format!(" (default; no modal form: {e})");
                None
            }
            Err(e) => fail(format!("modal form: {e}")),
        },
        _ => None,
    };
    // Each form on the ring with its own decomposition (the physical one is not built for the
    // modal run: one eigen-decomposition, not two).
    let (run, free_flight) = if let Some(modal) = modal {
        let modal = check(modal.ringed(ring), "ring");
        let free_flight = format!("{} (modal coordinates)", free_flight(modal.closed_form()));
        (
            on_ring(modal, &f, ModalRotor::station_displacement),
            free_flight,
        )
    } else {
        let model = check(rotor.ringed(ring), "ring");
        let free_flight = free_flight(model.closed_form());
        (
            on_ring(model, &f, LinearRotor::station_displacement),
            free_flight,
        )
    };
    write_csv(&run.samples);
    eprintln!("{}", summary(&f, dofs, kept, &picked, &free_flight, &run));
    draw(&f, &run.samples);
}

/// How free flight runs: exact (closed form and certified onset search) or integrated, and why.
fn free_flight(closed_form: Option<Result<&LinearClosedForm, &RotorError>>) -> String {
    match closed_form {
        Some(Ok(_)) => "exact".to_string(),
        Some(Err(e)) => format!("integrated ({e})"),
        None => "integrated".to_string(),
    }
}

/// The rotor of the flags, full or reduced, its ring, and the highest kept mode's frequency
/// (rad/s) of a reduction. Bad input exits with status 2.
fn model(f: &Flags) -> (LinearRotor, SnubberRing, Option<f64>) {
    let matrices = check(
        RotorMatrices::from_ross_mat(&f.mat),
        &f.mat.display().to_string(),
    );
    let lateral = check(matrices.lateral(), "--mat");
    let speed = f.speed_rpm * std::f64::consts::PI / 30.0;
    let mut system = check(LinearSystem::from_matrices(&lateral, speed), "--speed-rpm");
    for u in &f.unbalance {
        system = check(
            system.with_unbalance(lateral.layout(), u.node, u.me, u.phase),
            "--unbalance",
        );
    }
    let ring_x = check(lateral.x_dof(f.ring_node), "--ring-node");
    let preload = [f.preload_x, f.preload_y];
    let units = SnubberRing::from_units(f.ring_stiffness, f.ring_damping, preload, f.gap);
    let ring = check(units, "ring");
    let offset = [f.ring_offset_x, f.ring_offset_y];
    let (rotor, kept) = if f.modes == 0 {
        let full = LinearRotor::new(system, [ring_x, ring_x + 1], offset);
        (check(full, "rotor"), None)
    } else {
        let modes = ModeSelection::Count(f.modes);
        let cb = check(
            CraigBampton::at_node(&lateral, f.ring_node, modes),
            "--modes",
        );
        let reduced = check(cb.reduce(&system), "--modes");
        // The reduced coordinates 0 and 1 are the ring node's x and y.
        let rotor = check(LinearRotor::new(reduced, [0, 1], offset), "rotor");
        (rotor, cb.frequencies().last().copied())
    };
    (rotor, ring, kept)
}

/// The summary line: the model, the method (`picked`: whether it is the default), how free
/// flight runs, the counts and the time.
fn summary(
    f: &Flags,
    dofs: usize,
    kept: Option<f64>,
    picked: &str,
    free_flight: &str,
    run: &Run,
) -> String {
    let reduction = kept.map_or(String::new(), |w| {
        format!(" ({} modes, highest {w:.4e} rad/s)", f.modes)
    });
    let friction = if f.friction > 0.0 {
        format!(
            ", friction {} ({} slip stops, {} ends of rolling)",
            f.friction, run.stops, run.slides
        )
    } else {
        String::new()
    };
    format!(
        "ross_rotor: {} DOFs{reduction}, {:?}{picked}, free flight {free_flight}, {} contacts{friction}, {} steps ({} rejected), {} events, {:.3} s",
        dofs,
        method(f).method(),
        run.contacts,
        run.steps,
        run.rejected,
        run.events,
        run.seconds
    )
}

/// What a run gives the outputs.
struct Run {
    samples: Vec<[f64; 3]>,
    contacts: usize,
    /// With friction: slip stops (into rolling) and ends of rolling.
    stops: usize,
    slides: usize,
    events: usize,
    steps: u64,
    rejected: u64,
    seconds: f64,
}

/// The transient of `model` on the ring, with friction if the flags ask for it; `at` reads the
/// ring node's displacement from the rotor and a state.
fn on_ring<R: SmoothRotor<Dim = Dyn>>(
    model: RingedRotor<R>,
    f: &Flags,
    at: fn(&R, &DVector<f64>) -> [f64; 2],
) -> Run {
    let mut y0 = DVector::zeros(model.rotor().dim().0); // q = q' = 0, s = 0
    check(model.make_consistent(&mut y0), "initial state");
    if f.friction == 0.0 {
        return transient(&model, &y0, f, |y| at(model.rotor(), y));
    }
    let radius = f.shaft_radius.unwrap_or_else(|| {
        fail("--friction needs --shaft-radius (the shaft's outer radius at the ring node, m)")
    });
    let rub = check(RubbingRotor::new(model, f.friction, radius), "--friction");
    transient(&rub, &y0, f, |y| at(rub.ringed().rotor(), y))
}

/// The transient of `model` from `y0` at rest; `at` reads the ring node's displacement from a
/// state.
fn transient<M: RotorModel<Dim = Dyn>>(
    model: &M,
    y0: &DVector<f64>,
    f: &Flags,
    at: impl Fn(&DVector<f64>) -> [f64; 2],
) -> Run {
    let dt = f.t_end / f.samples as f64;
    let plan = OutputPlan {
        t_end: f.t_end,
        strobe: None,
        dense: Some(DenseSampling { t_start: 0.0, dt }),
        events: true,
    };
    let opts = SimOptions::default()
        .with_method(method(f).method())
        .with_rtol(f.rtol)
        .with_atol(f.rtol)
        .with_max_events_per_period(u32::MAX);
    let mut rec = Trajectory::<Dyn>::default();
    let clock = Instant::now();
    let stats = common::or_exit(simulate(model, 0.0, y0, &plan, &opts, &mut rec));
    let seconds = clock.elapsed().as_secs_f64();
    let mut samples: Vec<[f64; 3]> = rec
        .samples
        .iter()
        .take(f.samples + 1)
        .map(|s| {
            let [x, y] = at(&s.y);
            [s.t, x, y]
        })
        .collect();
    // The last sample falls on T up to the rounding of samples * dt: read it from the end.
    while samples.len() < f.samples + 1 {
        let last = rec
            .samples
            .last()
            .map(|s| at(&s.y))
            .unwrap_or([f64::NAN; 2]);
        samples.push([f.t_end, last[0], last[1]]);
    }
    for (i, s) in samples.iter_mut().enumerate() {
        s[0] = i as f64 * dt;
    }
    let count = |kind: &str| rec.events.iter().filter(|e| e.kind == kind).count();
    Run {
        samples,
        contacts: count("contact onset"),
        stops: count("slip velocity zero"),
        slides: count("friction cone's edge"),
        events: rec.events.len(),
        steps: stats.steps,
        rejected: stats.rejected,
        seconds,
    }
}

/// The method asked for, or the fastest measured to the requested accuracy (docs/fe-rotors.md,
/// "The fastest accurate path"): ETD4 in modal coordinates for the full model (the steps
/// follow the contact, not the fastest mode), DOP853 for a reduced one (its highest kept
/// mode does not bound the step).
fn method(f: &Flags) -> MethodFlag {
    f.method.unwrap_or(if f.modes == 0 {
        MethodFlag::Etd4
    } else {
        MethodFlag::Dop853
    })
}

fn write_csv(samples: &[[f64; 3]]) {
    use std::io::Write;
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    let mut line = |s: String| common::or_exit(writeln!(out, "{s}"));
    line("t,x,y".into());
    for [t, x, y] in samples {
        line(format!("{t:?},{x:?},{y:?}"));
    }
}

fn draw(f: &Flags, samples: &[[f64; 3]]) {
    let um = |v: f64| v * 1e6;
    let circle: Vec<(f64, f64)> = (0..=360)
        .map(|k| {
            let a = (k as f64).to_radians();
            (
                um(f.ring_offset_x + f.gap * a.cos()),
                um(f.ring_offset_y + f.gap * a.sin()),
            )
        })
        .collect();
    let orbit: Vec<(f64, f64)> = samples.iter().map(|s| (um(s[1]), um(s[2]))).collect();
    let title = format!(
        "{} at {} rpm, ring at node {}",
        f.mat.file_name().unwrap_or_default().to_string_lossy(),
        f.speed_rpm,
        f.ring_node
    );
    // Equal scales on both axes, so that the gap circle is a circle.
    let reach = orbit
        .iter()
        .chain(&circle)
        .fold(0.0_f64, |m, (x, y)| m.max(x.abs()).max(y.abs()));
    let fig = Figure::new(&title, "x (µm)", "y (µm)")
        .with_size(900, 900)
        .with_x_range(-1.05 * reach, 1.05 * reach)
        .with_y_range(-1.05 * reach, 1.05 * reach);
    common::or_exit(plot::lines(
        f.out.join("orbit.png"),
        &fig,
        &[Series::new("ring node", orbit), Series::new("gap", circle)],
    ));
    let fig = Figure::new(&title, "t (s)", "displacement (µm)").with_columns("t", "displacement");
    let xt = samples.iter().map(|s| (s[0], um(s[1]))).collect();
    let yt = samples.iter().map(|s| (s[0], um(s[2]))).collect();
    common::or_exit(plot::lines(
        f.out.join("displacement.png"),
        &fig,
        &[Series::new("x", xt), Series::new("y", yt)],
    ));
}
