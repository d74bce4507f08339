//! The envelope of a sweep up and back: the largest radius from the ring's centre in each
//! revolution of the out-of-balance against the speed (`analysis::per_revolution`), drawn for
//! the two legs, and the per-revolution table.

use std::io::Write;
use std::path::Path;

use jeffcott::analysis::Revolution;

use crate::common::plot::{self, Figure, Series};

/// Draws `envelope.png` (and its `envelope.csv`) in `out`: `(label, revolutions)` per leg,
/// the largest radius against the revolution's mean speed.
pub fn draw(out: &Path, title: &str, legs: &[(String, Vec<Revolution>)]) -> Result<(), String> {
    let fig = Figure::new(title, "η", "largest |r| per revolution").with_columns("eta", "radius");
    let series: Vec<Series> = legs
        .iter()
        .map(|(label, revs)| {
            Series::new(
                label,
                revs.iter().map(|r| (r.speed, r.max_radius)).collect(),
            )
        })
        .collect();
    plot::lines(out.join("envelope.png"), &fig, &series).map_err(|e| e.to_string())
}

/// Writes `revolutions.csv` in `out`: per leg and revolution, its start, mean speed, largest
/// radius, time in contact and the fraction of time in each regime I..V (the friction's
/// modes, never met by the frictionless run-up, are left out).
pub fn write_table(out: &Path, legs: &[(String, Vec<Revolution>)]) -> Result<(), String> {
    let path = out.join("revolutions.csv");
    let mut text =
        String::from("leg,t_start,eta,max_radius,contact_time,occ_I,occ_II,occ_III,occ_IV,occ_V\n");
    for (leg, (_, revs)) in legs.iter().enumerate() {
        for r in revs {
            let occ: Vec<String> = r.occupancy[..5].iter().map(f64::to_string).collect();
            text += &format!(
                "{leg},{},{},{},{},{}\n",
                r.t_start,
                r.speed,
                r.max_radius,
                r.contact_time,
                occ.join(",")
            );
        }
    }
    std::fs::File::create(&path)
        .and_then(|mut f| f.write_all(text.as_bytes()))
        .map_err(|e| format!("{}: {e}", path.display()))
}
