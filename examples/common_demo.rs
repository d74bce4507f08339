//! Exercises the shared example infrastructure (flags, CSV, figures) on synthetic data:
//!
//! * a logistic-map bifurcation diagram (450 000 points by default), computed with the
//!   library's deterministic parallel sweep, with the period detected at each value;
//! * a Poincaré-like scatter plot (orbits of the Chirikov standard map);
//! * a phase portrait with jumps (a bouncing ball) and a smooth spiral;
//! * a heat map (Lyapunov exponent of the logistic map forced with an AB sequence);
//! * a log-log work-precision diagram (Euler, Heun, RK4 on a scalar ODE).
//!
//! Run `cargo run --release --example common_demo -- --help` for the flags. Figures and CSV go
//! to `--out` (default `target/figures/common_demo`).

#[path = "common/mod.rs"]
mod common;

use std::f64::consts::TAU;
use std::path::PathBuf;

use clap::Parser;
use common::cli::{f64_in, fail, parse, usize_in};
use common::plot::{self, Figure, Grid, LegendPosition, Series};
use jeffcott::analysis::{detect_period_scalar, sweep, Periodicity, StderrProgress, SweepOptions};

/// Demo of the examples' shared helpers on synthetic data (logistic map, standard map,
/// bouncing ball, Lyapunov heat map, work-precision diagram).
#[derive(Parser)]
#[command(name = "common_demo")]
struct Flags {
    /// Output folder
    #[arg(long, value_name = "DIR", default_value = "target/figures/common_demo")]
    out: PathBuf,
    /// Lowest logistic parameter r [range: 0..=4]
    #[arg(long, value_name = "NUMBER", default_value = "2.8", value_parser = f64_in(0.0, 4.0))]
    r_min: f64,
    /// Highest logistic parameter r [range: 0..=4]
    #[arg(long, value_name = "NUMBER", default_value = "4", value_parser = f64_in(0.0, 4.0))]
    r_max: f64,
    /// Number of r values [range: 2..=100000]
    #[arg(long, value_name = "COUNT", default_value = "1500", value_parser = usize_in(2, 100_000))]
    values: usize,
    /// Points plotted per r value [range: 1..=100000]
    #[arg(long, value_name = "COUNT", default_value = "300", value_parser = usize_in(1, 100_000))]
    points: usize,
    /// Iterations discarded per r value
    #[arg(long, value_name = "COUNT", default_value = "1000")]
    transient: usize,
    /// State carried from value to value, or reset
    #[arg(long, default_value = "carry", value_parser = ["carry", "reset"])]
    mode: String,
    /// Contiguous chunks in carry mode [range: 1..=100000]
    #[arg(long, value_name = "COUNT", default_value = "8", value_parser = usize_in(1, 100_000))]
    chunks: usize,
    /// Worker threads, unset = all cores [range: 1..=1024]
    #[arg(long, value_name = "COUNT", value_parser = usize_in(1, 1024))]
    threads: Option<usize>,
    /// Format of the phase portrait
    #[arg(long, default_value = "png", value_parser = ["png", "svg"])]
    lines_format: String,
}

fn main() {
    let Flags {
        out,
        r_min,
        r_max,
        values,
        points,
        transient,
        mode,
        chunks,
        threads,
        lines_format: format,
    } = parse();
    if r_min >= r_max {
        fail(format!("--r-min ({r_min}) must be below --r-max ({r_max})"));
    }

    // 1. Bifurcation diagram through the library's sweep.
    let rs: Vec<f64> = (0..values)
        .map(|i| r_min + (r_max - r_min) * i as f64 / (values - 1) as f64)
        .collect();
    let mut config = match mode.as_str() {
        "carry" => SweepOptions::carry_over(chunks),
        _ => SweepOptions::reset(),
    };
    if let Some(n) = threads {
        config = config.with_threads(n);
    }
    let runner = |r: &f64, state: Option<f64>| -> Result<(Vec<f64>, f64), String> {
        let mut x = state.unwrap_or(0.5);
        for _ in 0..transient {
            x = r * x * (1.0 - x);
        }
        let mut orbit = Vec::with_capacity(points);
        for _ in 0..points {
            x = r * x * (1.0 - x);
            orbit.push(x);
        }
        if x.is_finite() {
            Ok((orbit, x))
        } else {
            Err(format!("orbit diverged at r = {r}"))
        }
    };
    let progress = StderrProgress::new("logistic sweep");
    let result = common::or_exit(sweep(&rs, &config, runner, Some(&progress)));
    let mut pts = Vec::with_capacity(values * points);
    let mut periods = [0usize; 9]; // 1..=8, then "none"
    for (r, res) in rs.iter().zip(&result.results) {
        match res {
            Ok(orbit) => {
                pts.extend(orbit.iter().map(|&x| (*r, x)));
                let max_p = 8.min(orbit.len() / 2).max(1);
                match detect_period_scalar(orbit, max_p, 1e-6) {
                    Ok(Periodicity::Period(p)) if p <= 8 => periods[p - 1] += 1,
                    _ => periods[8] += 1,
                }
            }
            Err(e) => eprintln!("warning: {e}"),
        }
    }
    eprintln!(
        "periods 1,2,4,8: {} {} {} {}; period 3: {}; other: {}",
        periods[0], periods[1], periods[3], periods[7], periods[2], periods[8]
    );
    let fig = Figure::new(
        &format!(
            "Logistic map x ↦ r x (1 − x): {points} iterates per r after {transient}, {values} values of r, mode {mode}"
        ),
        "r",
        "x_n",
    )
    .with_columns("r", "x")
    .with_size(1600, 1000)
    .with_dots(0, 0.6)
    .with_mark(3.0, "r = 3")
    .with_mark(1.0 + 6f64.sqrt(), "1 + √6")
    .with_mark(1.0 + 8f64.sqrt(), "1 + √8");
    common::or_exit(plot::bifurcation(out.join("bifurcation.png"), &fig, &pts));

    // 2. Scatter: standard map p' = p + K sin θ, θ' = θ + p' (mod 2π).
    let k = 0.971635;
    let series: Vec<Series> = [0.3, 0.9, 1.5, 2.0, 2.6, 3.1, 3.6, 4.4]
        .iter()
        .map(|&p0| {
            let (mut th, mut p) = (0.5, p0);
            let pts = (0..2000)
                .map(|_| {
                    p = (p + k * f64::sin(th)).rem_euclid(TAU);
                    th = (th + p).rem_euclid(TAU);
                    (th, p)
                })
                .collect();
            Series::new(&format!("p₀ = {p0}"), pts)
        })
        .collect();
    let fig = Figure::new(
        &format!("Standard map, K = {k}: 2000 iterates of 8 orbits from θ₀ = 0.5"),
        "θ",
        "p",
    )
    .with_columns("theta", "p")
    .with_size(1200, 1000)
    .with_x_range(0.0, TAU)
    .with_y_range(0.0, TAU);
    common::or_exit(plot::scatter(out.join("scatter.png"), &fig, &series));

    // 3. Phase portrait with jumps: a ball bouncing on x = 0 (restitution 0.8, gravity 1),
    //    and a damped oscillator spiral.
    let mut ball = Vec::new();
    let (mut x, mut v, dt, e) = (1.0f64, 0.0f64, 1e-3, 0.8);
    for _ in 0..12_000 {
        v -= dt;
        x += v * dt;
        if x < 0.0 {
            x = -x;
            v *= -e;
        }
        ball.push((x, v));
    }
    let spiral: Vec<(f64, f64)> = (0..4000)
        .map(|i| {
            let t = i as f64 * 0.01;
            let a = (-0.05 * t).exp();
            (0.5 + 0.4 * a * (2.0 * t).cos(), -0.8 * a * (2.0 * t).sin())
        })
        .collect();
    let fig = Figure::new(
        "Phase portraits: bouncing ball (restitution 0.8; velocity jumps at impact) and a damped oscillator",
        "x",
        "x′ = dx/dτ",
    )
    .with_columns("x", "v")
    .with_max_jump(0.05)
    .with_legend(LegendPosition::LowerRight);
    let curves = [
        Series::new("bouncing ball (broken at jumps)", ball),
        Series::new("damped oscillator", spiral),
    ];
    common::or_exit(plot::lines(
        out.join(format!("phase.{format}")),
        &fig,
        &curves,
    ));

    // 4. Heat map: Lyapunov exponent of x ↦ r_n x (1 − x), r_n alternating a, b (AB sequence).
    let n = 240;
    let axis: Vec<f64> = (0..n)
        .map(|i| 2.5 + 1.5 * (i as f64 + 0.5) / n as f64)
        .collect();
    let mut values = Vec::with_capacity(n * n);
    for &b in &axis {
        for &a in &axis {
            let (mut x, mut sum) = (0.5f64, 0.0);
            for i in 0..600 {
                let r = if i % 2 == 0 { a } else { b };
                x = r * x * (1.0 - x);
                if i >= 200 {
                    sum += (r * (1.0 - 2.0 * x)).abs().max(1e-300).ln();
                }
            }
            values.push((sum / 400.0).max(-2.0));
        }
    }
    let grid = Grid {
        xs: axis.clone(),
        ys: axis,
        values,
        z_range: Some((-2.0, 0.7)),
    };
    let fig = Figure::new(
        "Lyapunov exponent of the logistic map with r alternating a, b (400 iterates after 200)",
        "a",
        "b",
    )
    .with_columns("a", "b")
    .with_size(1150, 1000);
    common::or_exit(plot::heatmap(
        out.join("heatmap.png"),
        &fig,
        &grid,
        "λ (clamped at −2)",
    ));

    // 5. Work-precision: y' = -y + sin t, y(0) = 1, on [0, 10].
    let exact = |t: f64| 1.5 * (-t).exp() + 0.5 * (t.sin() - t.cos());
    let f = |t: f64, y: f64| -y + t.sin();
    let mut curves = vec![Series::default(); 3];
    let names = [
        "explicit Euler (order 1)",
        "Heun (order 2)",
        "classical RK4 (order 4)",
    ];
    for (m, c) in curves.iter_mut().enumerate() {
        c.label = names[m].to_string();
        for steps in [10usize, 20, 40, 80, 160, 320, 640, 1280, 2560] {
            let h = 10.0 / steps as f64;
            let (mut t, mut y) = (0.0, 1.0);
            for _ in 0..steps {
                y += match m {
                    0 => h * f(t, y),
                    1 => {
                        let k1 = f(t, y);
                        let k2 = f(t + h, y + h * k1);
                        0.5 * h * (k1 + k2)
                    }
                    _ => {
                        let k1 = f(t, y);
                        let k2 = f(t + 0.5 * h, y + 0.5 * h * k1);
                        let k3 = f(t + 0.5 * h, y + 0.5 * h * k2);
                        let k4 = f(t + h, y + h * k3);
                        h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
                    }
                };
                t += h;
            }
            let evals = (steps * [1, 2, 4][m]) as f64;
            c.points.push((evals, (y - exact(10.0)).abs()));
        }
    }
    let fig = Figure::new(
        "Work-precision on y′ = −y + sin t, y(0) = 1, t ∈ [0, 10]",
        "right-hand-side evaluations",
        "error at t = 10",
    )
    .with_columns("evaluations", "error")
    .with_log(true, true)
    .with_markers()
    .with_legend(LegendPosition::LowerLeft);
    common::or_exit(plot::lines(out.join("work_precision.png"), &fig, &curves));
    eprintln!("figures and CSV written to {}", out.display());
}
