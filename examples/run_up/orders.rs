//! Order analysis of a sweep (`analysis::order_track`): the whirl amplitudes of the orders
//! 1/2, 1, 3/2, 2 and 3 against the speed, and a waterfall of the windows' full spectra.

use std::path::Path;

use jeffcott::analysis::{order_track, AngleSamples, OrderRow, OrderTrackOptions};

use crate::common::plot::{self, Figure, Series};

/// The order-tracking rows of the strobes `(t, x, y)`, `per_revolution` a revolution from the
/// phase `phase0`.
pub fn track(
    per_revolution: usize,
    phase0: f64,
    strobes: &[(f64, f64, f64)],
) -> Result<Vec<OrderRow>, String> {
    let times = strobes.iter().map(|s| s.0).collect();
    let x = strobes.iter().map(|s| s.1).collect();
    let y = strobes.iter().map(|s| s.2).collect();
    let samples =
        AngleSamples::new(per_revolution, phase0, times, x, y).map_err(|e| e.to_string())?;
    order_track(&samples, &OrderTrackOptions::default()).map_err(|e| e.to_string())
}

/// Draws `orders.png` in `out`: the forward whirl of each tracked order against the speed, and
/// the backward whirl of order 1.
pub fn draw_orders(out: &Path, title: &str, rows: &[OrderRow]) -> Result<(), String> {
    let orders = OrderTrackOptions::default().orders;
    let mut series: Vec<Series> = orders
        .iter()
        .enumerate()
        .map(|(i, o)| {
            let points = rows.iter().map(|r| (r.speed, r.forward[i])).collect();
            Series::new(&format!("{o}× forward"), points)
        })
        .collect();
    let backward = rows.iter().map(|r| (r.speed, r.backward[1])).collect();
    series.push(Series::new("1× backward", backward));
    let fig = Figure::new(title, "η", "whirl radius").with_columns("eta", "radius");
    plot::lines(out.join("orders.png"), &fig, &series).map_err(|e| e.to_string())
}

/// Draws `waterfall.png` in `out`: the full spectrum up to order 4 (backward whirl at negative
/// orders) of at most 50 windows evenly picked, each lifted to its speed; the radii scaled so
/// that the largest spans four rows.
pub fn draw_waterfall(out: &Path, title: &str, rows: &[OrderRow]) -> Result<(), String> {
    let rows: Vec<&OrderRow> = rows
        .iter()
        .step_by(rows.len().div_ceil(50).max(1))
        .collect();
    let Some(first) = rows.first() else {
        return Ok(());
    };
    let bins = first
        .spectrum
        .frequency
        .iter()
        .take_while(|&&f| f <= 4.0)
        .count();
    let largest = rows
        .iter()
        .flat_map(|r| {
            r.spectrum.forward[1..bins]
                .iter()
                .chain(&r.spectrum.backward[1..bins])
        })
        .fold(0.0f64, |a, &b| a.max(b));
    let (lo, hi) = rows
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), r| {
            (a.min(r.speed), b.max(r.speed))
        });
    let scale = 4.0 * (hi - lo) / rows.len() as f64 / largest.max(f64::MIN_POSITIVE);
    let series: Vec<Series> = rows
        .iter()
        .map(|r| {
            let s = &r.spectrum;
            let r = *r;
            let back = (1..bins)
                .rev()
                .map(|k| (-s.frequency[k], r.speed + scale * s.backward[k]));
            let fwd = (1..bins).map(|k| (s.frequency[k], r.speed + scale * s.forward[k]));
            Series::new("", back.chain(fwd).collect())
        })
        .collect();
    let fig = Figure::new(
        title,
        "order (< 0: backward whirl)",
        "η (+ scaled whirl radius)",
    )
    .with_columns("order", "eta_plus_radius");
    plot::lines(out.join("waterfall.png"), &fig, &series).map_err(|e| e.to_string())
}
