//! Paper Fig. 7: the restoring force on the rotor for Dx = 1.5, Dy = 1.1, K = 30, ex = ey = 0:
//! heat maps of F_rx, F_ry and |F_r| over (x_r, y_r), and (d) cuts F_rx(R) along rays.
//!
//! `F_r = r - e + g(s*(r))` in contact (`|r| > 1`) and `r - e` out of contact, with the elastic
//! force `g` of Table 1 (the paper's eq. 29 drops the preload term; see MODEL.md errata).
//!
//! The paper's Fig. 7d text says the middle cut is at `phi = arctan(Dy/Dx) = 66 deg`; but
//! `arctan(1.1/1.5) = 36.25 deg` (and `arctan(Dx/Dy) = 53.7 deg`), and only the ray at 36.25 deg
//! passes through the corner where II meets V directly, which is what the text describes. We plot
//! 27, 36.25 and 85 deg, plus the paper's literal 66 deg for comparison.
//!
//! Usage: `cargo run --example fig7_restoring_force [OUT_DIR]` (default `target/figures/fig7`). Writes
//! `fig7_restoring_force.png`, `fig7_force_grid.csv` (x_r, y_r, regime, F_rx, F_ry, |F_r|) and
//! `fig7_cuts.csv` (phi_deg, R, F_rx, regime).

#[path = "common/mod.rs"]
mod common;

use std::error::Error;
use std::fs;
use std::io::Write;
use std::path::PathBuf;

use clap::Parser;
use common::cli::parse;
use jeffcott::ring::boundaries::{Boundary, RegionBoundaries};
use jeffcott::ring::{Regime, RingAxis, SnubberRing};
use nalgebra::Vector2;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

const HALF: f64 = 3.0;
const N: usize = 241;
const K: f64 = 30.0;
const DX: f64 = 1.5;
const DY: f64 = 1.1;

/// Restoring force and regime at rotor position `r` (eccentricity 0).
fn restoring(
    ring: &SnubberRing,
    r: &Vector2<f64>,
) -> Result<(Vector2<f64>, Regime), Box<dyn Error>> {
    Ok(match ring.regime(r)? {
        Regime::I => (*r, Regime::I),
        _ => {
            let c = ring.locate(r)?;
            (r + ring.elastic_force(&c.s), c.regime())
        }
    })
}

fn lerp(a: (f64, f64, f64), b: (f64, f64, f64), t: f64) -> RGBColor {
    let f = |x: f64, y: f64| (x + (y - x) * t).round().clamp(0.0, 255.0) as u8;
    RGBColor(f(a.0, b.0), f(a.1, b.1), f(a.2, b.2))
}

/// Viridis-like sequential map on `[0, 1]`.
fn sequential(t: f64) -> RGBColor {
    const C: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = t.clamp(0.0, 1.0) * 4.0;
    let i = (t.floor() as usize).min(3);
    lerp(C[i], C[i + 1], t - i as f64)
}

/// Blue-white-red diverging map on `[0, 1]` (0.5 is white).
fn diverging(t: f64) -> RGBColor {
    let t = t.clamp(0.0, 1.0);
    if t < 0.5 {
        lerp((33.0, 102.0, 172.0), (247.0, 247.0, 247.0), t / 0.5)
    } else {
        lerp((247.0, 247.0, 247.0), (178.0, 24.0, 43.0), (t - 0.5) / 0.5)
    }
}

struct Map<'a> {
    title: &'a str,
    values: &'a [f64],
    lo: f64,
    hi: f64,
    cmap: fn(f64) -> RGBColor,
}

fn heat_map<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    map: &Map,
    xs: &[f64],
    curves: &[Vec<(f64, f64)>],
) -> Result<(), Box<dyn Error>>
where
    DB::ErrorType: 'static,
{
    let (w, _) = area.dim_in_pixel();
    let (main, bar) = area.split_horizontally(w as i32 - 110);
    let mut chart = ChartBuilder::on(&main)
        .caption(map.title, ("sans-serif", 22))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(50)
        .build_cartesian_2d(-HALF..HALF, -HALF..HALF)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x (rotor, units of the gap γ)")
        .y_desc("y (rotor, units of the gap γ)")
        .axis_desc_style(("sans-serif", 18))
        .label_style(("sans-serif", 14))
        .draw()?;
    let h = xs[1] - xs[0];
    let span = map.hi - map.lo;
    chart.draw_series(xs.iter().enumerate().flat_map(|(i, &x)| {
        xs.iter().enumerate().map(move |(j, &y)| {
            let v = map.values[i * N + j];
            Rectangle::new(
                [(x - 0.5 * h, y - 0.5 * h), (x + 0.5 * h, y + 0.5 * h)],
                (map.cmap)((v - map.lo) / span).filled(),
            )
        })
    }))?;
    for c in curves {
        chart.draw_series(LineSeries::new(
            c.iter().copied(),
            BLACK.mix(0.7).stroke_width(1),
        ))?;
    }
    // Colour bar.
    let mut cb = ChartBuilder::on(&bar)
        .margin_top(40)
        .margin_bottom(50)
        .margin_right(10)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..1.0, map.lo..map.hi)?;
    cb.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .label_style(("sans-serif", 14))
        .draw()?;
    let steps = 200;
    cb.draw_series((0..steps).map(|k| {
        let a = map.lo + span * k as f64 / steps as f64;
        let b = map.lo + span * (k + 1) as f64 / steps as f64;
        Rectangle::new(
            [(0.0, a), (1.0, b)],
            (map.cmap)((k as f64 + 0.5) / steps as f64).filled(),
        )
    }))?;
    Ok(())
}

/// Paper Fig. 7: the restoring force on the rotor for Dx = 1.5, Dy = 1.1, K = 30,
/// ex = ey = 0: heat maps of F_rx, F_ry and |F_r|, and cuts F_rx(R) along rays. Writes
/// fig7_restoring_force.png, fig7_force_grid.csv and fig7_cuts.csv into OUT_DIR.
#[derive(Parser)]
#[command(name = "fig7_restoring_force")]
struct Flags {
    /// Output folder
    #[arg(value_name = "OUT_DIR", default_value = "target/figures/fig7")]
    out: PathBuf,
}

fn main() -> Result<(), Box<dyn Error>> {
    let Flags { out } = parse();
    fs::create_dir_all(&out)?;
    register_font(
        "sans-serif",
        FontStyle::Normal,
        include_bytes!("common/assets/DejaVuSans.ttf"),
    )
    .map_err(|_| "cannot register the bundled font")?;
    let ring = SnubberRing::new(RingAxis::new(K, DX), RingAxis::new(K, DY), 0.002, 1.0)?;

    // Grid.
    let xs: Vec<f64> = (0..N)
        .map(|i| -HALF + 2.0 * HALF * i as f64 / (N - 1) as f64)
        .collect();
    let (mut fx, mut fy, mut fa) = (vec![0.0; N * N], vec![0.0; N * N], vec![0.0; N * N]);
    let grid_csv = out.join("fig7_force_grid.csv");
    let mut f = fs::File::create(&grid_csv)?;
    writeln!(f, "x_r,y_r,regime,F_rx,F_ry,F_r")?;
    for (i, &x) in xs.iter().enumerate() {
        for (j, &y) in xs.iter().enumerate() {
            let (force, reg) = restoring(&ring, &Vector2::new(x, y))?;
            fx[i * N + j] = force.x;
            fy[i * N + j] = force.y;
            fa[i * N + j] = force.norm();
            writeln!(
                f,
                "{x},{y},{},{},{},{}",
                reg.number(),
                force.x,
                force.y,
                force.norm()
            )?;
        }
    }
    let max_abs = |v: &[f64]| v.iter().fold(0.0f64, |m, &a| m.max(a.abs()));

    // Boundary curves mirrored into the four quadrants.
    let bounds = RegionBoundaries::from_ring(&ring)?;
    let mut curves = Vec::new();
    for b in Boundary::ALL {
        let pts = bounds.polyline(b, 1500, HALF);
        for (sx, sy) in [(1.0, 1.0), (-1.0, 1.0), (1.0, -1.0), (-1.0, -1.0)] {
            curves.push(pts.iter().map(|p| (sx * p.x, sy * p.y)).collect::<Vec<_>>());
        }
    }

    // Cuts along rays.
    let diag = (DY / DX).atan().to_degrees();
    let cuts: Vec<(f64, &str, RGBColor)> = vec![
        (
            27.0,
            "phi = 27 deg (< arctan(Dy/Dx))",
            RGBColor(31, 120, 180),
        ),
        (diag, "phi = arctan(Dy/Dx) = 36.25 deg", RGBColor(0, 0, 0)),
        (
            66.0,
            "phi = 66 deg (paper's stated value)",
            RGBColor(150, 150, 150),
        ),
        (
            85.0,
            "phi = 85 deg (> arctan(Dy/Dx))",
            RGBColor(227, 26, 28),
        ),
    ];
    let cuts_csv = out.join("fig7_cuts.csv");
    let mut f = fs::File::create(&cuts_csv)?;
    writeln!(f, "phi_deg,R,F_rx,regime")?;
    let mut cut_lines = Vec::new();
    for &(deg, _, _) in &cuts {
        let dir = Vector2::new(deg.to_radians().cos(), deg.to_radians().sin());
        let mut line = Vec::new();
        for k in 0..=1400 {
            let rad = 3.5 * k as f64 / 1400.0;
            let (force, reg) = restoring(&ring, &(dir * rad))?;
            writeln!(f, "{deg},{rad},{},{}", force.x, reg.number())?;
            line.push((rad, force.x));
        }
        cut_lines.push(line);
    }

    let png = out.join("fig7_restoring_force.png");
    {
        let root = BitMapBackend::new(&png, (1600, 1400)).into_drawing_area();
        root.fill(&WHITE)?;
        let root = root.titled(
            "Restoring force (Fig. 7): Dx = 1.5, Dy = 1.1, K = 30, ex = ey = 0",
            ("sans-serif", 28),
        )?;
        let panels = root.split_evenly((2, 2));
        let mx = max_abs(&fx);
        let my = max_abs(&fy);
        heat_map(
            &panels[0],
            &Map {
                title: "(a) F_rx",
                values: &fx,
                lo: -mx,
                hi: mx,
                cmap: diverging,
            },
            &xs,
            &curves,
        )?;
        heat_map(
            &panels[1],
            &Map {
                title: "(b) F_ry",
                values: &fy,
                lo: -my,
                hi: my,
                cmap: diverging,
            },
            &xs,
            &curves,
        )?;
        heat_map(
            &panels[2],
            &Map {
                title: "(c) |F_r|",
                values: &fa,
                lo: 0.0,
                hi: max_abs(&fa),
                cmap: sequential,
            },
            &xs,
            &curves,
        )?;
        let ymax = cut_lines.iter().flatten().fold(0.0f64, |m, p| m.max(p.1)) * 1.05;
        let mut chart = ChartBuilder::on(&panels[3])
            .caption(
                "(d) F_rx along rays phi = arctan(y_r/x_r)",
                ("sans-serif", 22),
            )
            .margin(15)
            .x_label_area_size(40)
            .y_label_area_size(55)
            .build_cartesian_2d(0.0..3.5, 0.0..ymax)?;
        chart
            .configure_mesh()
            .x_desc("R = |r|")
            .y_desc("F_rx")
            .axis_desc_style(("sans-serif", 18))
            .label_style(("sans-serif", 14))
            .draw()?;
        for (line, &(_, label, colour)) in cut_lines.iter().zip(&cuts) {
            chart
                .draw_series(LineSeries::new(
                    line.iter().copied(),
                    colour.stroke_width(2),
                ))?
                .label(label)
                .legend(move |(x, y)| {
                    PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
                });
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .label_font(("sans-serif", 15))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .draw()?;
        root.present()?;
    }
    for p in [&png, &grid_csv, &cuts_csv] {
        println!("wrote {}", p.display());
    }
    Ok(())
}
