//! The envelope of a sweep: the largest radius from the ring's centre in each revolution of the
//! out-of-balance, against the speed, drawn for the sweep and its reverse.

use std::path::Path;

use jeffcott::hybrid::Trajectory;
use jeffcott::nalgebra::U6;
use jeffcott::rotor::SpeedProfile;

use crate::common::plot::{self, Figure, Series};

/// `(eta, largest |r|)` per revolution: `samples` strobes a revolution, the speed at the
/// revolution's largest radius.
pub fn per_revolution(
    traj: &Trajectory<U6>,
    profile: &SpeedProfile,
    samples: usize,
) -> Vec<(f64, f64)> {
    traj.strobe
        .chunks(samples)
        .filter_map(|rev| {
            rev.iter()
                .map(|p| (profile.eta(p.t), p.y[0].hypot(p.y[1])))
                .max_by(|a, b| a.1.total_cmp(&b.1))
        })
        .collect()
}

/// Draws `envelope.png` (and its `envelope.csv`) in `out`: the sweeps `(label, points)`.
pub fn draw(out: &Path, title: &str, sweeps: Vec<(String, Vec<(f64, f64)>)>) -> Result<(), String> {
    let fig = Figure::new(title, "η", "largest |r| per revolution").with_columns("eta", "radius");
    let series: Vec<Series> = sweeps
        .into_iter()
        .map(|(label, points)| Series::new(&label, points))
        .collect();
    plot::lines(out.join("envelope.png"), &fig, &series).map_err(|e| e.to_string())
}
