//! Paper Fig. 6: the regions I..V of the rotor plane (first quadrant) for a preloaded ring,
//! shaded by the classifier `SnubberRing::regime` on a grid, with the analytic boundary curves
//! (eqs. 23-27) overlaid.
//!
//! Usage: `cargo run --example fig6_regions [OUT_DIR] [DX] [DY]` (default `target/figures/fig6`, Dx = 1.5,
//! Dy = 1.1 as in the paper's Fig. 7). Writes `fig6_regions.png`,
//! `fig6_regions_grid.csv` (x_r, y_r, regime) and `fig6_boundaries.csv` (boundary, x_r, y_r).

#[path = "common/mod.rs"]
mod common;

use std::error::Error;
use std::fs;
use std::io::Write;
use std::path::{Path, PathBuf};

use clap::Parser;
use common::cli::{finite, parse};
use jeffcott::ring::boundaries::{Boundary, RegionBoundaries};
use jeffcott::ring::{Regime, RingAxis, SnubberRing};
use nalgebra::Vector2;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{register_font, FontStyle};

const LIMIT: f64 = 3.2;
const CELLS: usize = 320;

fn region_colour(r: Regime) -> RGBColor {
    match r {
        Regime::I => RGBColor(245, 245, 245),
        Regime::II => RGBColor(166, 206, 227),
        Regime::III => RGBColor(178, 223, 138),
        Regime::IV => RGBColor(253, 191, 111),
        Regime::V => RGBColor(202, 178, 214),
    }
}

fn boundary_colour(b: Boundary) -> RGBColor {
    match b {
        Boundary::IContact => RGBColor(0, 0, 0),
        Boundary::IiIii => RGBColor(31, 120, 180),
        Boundary::IiIv => RGBColor(227, 26, 28),
        Boundary::IiiV => RGBColor(51, 160, 44),
        Boundary::IvV => RGBColor(255, 127, 0),
    }
}

fn equation(b: Boundary) -> &'static str {
    match b {
        Boundary::IContact => "eq. 23",
        Boundary::IiIii => "eq. 24",
        Boundary::IiIv => "eq. 25",
        Boundary::IiiV => "eq. 26",
        Boundary::IvV => "eq. 27",
    }
}

type Grid = Vec<(f64, f64, Regime)>;

fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    ring: &SnubberRing,
    grid: &Grid,
    curves: &[(Boundary, Vec<Vector2<f64>>)],
) -> Result<(), Box<dyn Error>>
where
    DB::ErrorType: 'static,
{
    root.fill(&WHITE)?;
    let title = format!(
        "Fig. 6: regions (shading: classifier; lines: eqs. 23-27), Dx = {}, Dy = {}, gap = {}",
        ring.x.preload, ring.y.preload, ring.gap
    );
    let mut chart = ChartBuilder::on(root)
        .caption(title, ("sans-serif", 24))
        .margin(15)
        .x_label_area_size(50)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..LIMIT, 0.0..LIMIT)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("x (rotor, units of the gap γ)")
        .y_desc("y (rotor, units of the gap γ)")
        .axis_desc_style(("sans-serif", 20))
        .label_style(("sans-serif", 16))
        .draw()?;
    let h = LIMIT / CELLS as f64;
    chart.draw_series(grid.iter().map(|&(x, y, reg)| {
        Rectangle::new(
            [(x - 0.5 * h, y - 0.5 * h), (x + 0.5 * h, y + 0.5 * h)],
            region_colour(reg).filled(),
        )
    }))?;
    for (b, pts) in curves {
        let c = boundary_colour(*b);
        chart
            .draw_series(LineSeries::new(
                pts.iter().map(|p| (p.x, p.y)),
                c.stroke_width(3),
            ))?
            .label(format!("{} ({})", b.label(), equation(*b)))
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], c.stroke_width(3)));
    }
    // Region names near each region's centroid (the nearest cell of that region to it).
    for reg in [Regime::I, Regime::II, Regime::III, Regime::IV, Regime::V] {
        let cells: Vec<(f64, f64)> = grid
            .iter()
            .filter(|c| c.2 == reg)
            .map(|c| (c.0, c.1))
            .collect();
        if cells.len() < 200 {
            continue;
        }
        let n = cells.len() as f64;
        let (cx, cy) = cells
            .iter()
            .fold((0.0, 0.0), |a, c| (a.0 + c.0 / n, a.1 + c.1 / n));
        let &(x, y) = cells
            .iter()
            .min_by(|a, b| {
                let da = (a.0 - cx).hypot(a.1 - cy);
                let db = (b.0 - cx).hypot(b.1 - cy);
                da.total_cmp(&db)
            })
            .unwrap_or(&(cx, cy));
        chart.draw_series(std::iter::once(Text::new(
            reg.to_string(),
            (x, y),
            ("sans-serif", 28).into_font().color(&BLACK),
        )))?;
    }
    let bounds = RegionBoundaries::from_ring(ring)?;
    if let Some(c) = bounds.corner() {
        chart.draw_series(std::iter::once(Circle::new((c.x, c.y), 5, BLACK.filled())))?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font(("sans-serif", 15))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()?;
    root.present()?;
    Ok(())
}

/// Paper Fig. 6: the regions I..V of the rotor plane (first quadrant) for a preloaded ring,
/// shaded by the classifier on a grid, with the analytic boundary curves (eqs. 23-27).
/// Writes fig6_regions.png, fig6_regions_grid.csv and fig6_boundaries.csv into OUT_DIR.
#[derive(Parser)]
#[command(name = "fig6_regions")]
struct Flags {
    /// Output folder
    #[arg(value_name = "OUT_DIR", default_value = "target/figures/fig6")]
    out: PathBuf,
    /// Preload D_x of the ring (stiffness 30 on both axes)
    #[arg(value_name = "DX", default_value = "1.5", value_parser = finite)]
    dx: f64,
    /// Preload D_y of the ring
    #[arg(value_name = "DY", default_value = "1.1", value_parser = finite)]
    dy: f64,
}

fn main() -> Result<(), Box<dyn Error>> {
    let Flags { out, dx, dy } = parse();
    fs::create_dir_all(&out)?;
    register_font(
        "sans-serif",
        FontStyle::Normal,
        include_bytes!("common/assets/DejaVuSans.ttf"),
    )
    .map_err(|_| "cannot register the bundled font")?;

    let ring = SnubberRing::new(RingAxis::new(30.0, dx), RingAxis::new(30.0, dy), 0.002, 1.0)?;
    let h = LIMIT / CELLS as f64;
    let mut grid: Grid = Vec::with_capacity(CELLS * CELLS);
    for i in 0..CELLS {
        for j in 0..CELLS {
            let (x, y) = ((i as f64 + 0.5) * h, (j as f64 + 0.5) * h);
            grid.push((x, y, ring.regime(&Vector2::new(x, y))?));
        }
    }
    let bounds = RegionBoundaries::from_ring(&ring)?;
    let curves: Vec<(Boundary, Vec<Vector2<f64>>)> = Boundary::ALL
        .iter()
        .map(|&b| (b, bounds.polyline(b, 1500, LIMIT)))
        .filter(|(_, p)| !p.is_empty())
        .collect();

    let grid_csv = out.join("fig6_regions_grid.csv");
    let mut f = fs::File::create(&grid_csv)?;
    writeln!(f, "x_r,y_r,regime")?;
    for (x, y, r) in &grid {
        writeln!(f, "{x},{y},{}", r.number())?;
    }
    let curves_csv = out.join("fig6_boundaries.csv");
    let mut f = fs::File::create(&curves_csv)?;
    writeln!(f, "boundary,equation,x_r,y_r")?;
    for (b, pts) in &curves {
        for p in pts {
            writeln!(f, "{},{},{},{}", b.label(), equation(*b), p.x, p.y)?;
        }
    }

    let png = out.join("fig6_regions.png");
    draw(
        &BitMapBackend::new(&png, (1000, 950)).into_drawing_area(),
        &ring,
        &grid,
        &curves,
    )?;
    for p in [&png, &grid_csv, &curves_csv] {
        println!("wrote {}", display(p));
    }
    Ok(())
}

fn display(p: &Path) -> String {
    p.display().to_string()
}
