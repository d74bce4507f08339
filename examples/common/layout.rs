//! Text that fits and does not collide, for the figures of [`super::plot`]: titles broken into
//! lines to fit the picture's width, and labels (reference marks, special points, the legend)
//! placed where they cover neither each other nor the data.
//!
//! Everything here works in backend pixels. The data drawn so far is recorded on a coarse grid
//! of cells ([`Occupancy`]); a label goes to the first of its candidate places that stays inside
//! the plot and overlaps no label placed before, preferring the place that covers the fewest
//! occupied cells.

use std::ops::Range;

use plotters::coord::Shift;
use plotters::prelude::*;

/// Title font size in pixels; a title that does not fit on three lines is drawn smaller.
const TITLE_SIZE: u32 = 28;
/// Cell side of the occupancy grid in pixels.
const CELL: i32 = 6;

/// Draws `title` at the top of `area`, broken at separators ("; ", ": ", ", ", " ") into at
/// most three lines that fit the width, and returns the area below it. An empty title takes no
/// room.
pub fn fit_title<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    title: &str,
) -> Result<DrawingArea<DB, Shift>, String> {
    if title.is_empty() {
        return Ok(area.clone());
    }
    let width = i64::from(area.dim_in_pixel().0) - 24;
    let mut size = TITLE_SIZE;
    let lines = loop {
        let style: TextStyle = ("sans-serif", size).into();
        let fits = |s: &str| match area.estimate_text_size(s, &style) {
            Ok((w, _)) => i64::from(w) <= width,
            Err(_) => true,
        };
        let lines = wrap(title, &fits);
        if (lines.len() <= 3 && lines.iter().all(|l| fits(l))) || size <= 14 {
            break lines;
        }
        size -= 2;
    };
    let mut rest = area.clone();
    for line in lines {
        rest = rest
            .titled(&line, ("sans-serif", size))
            .map_err(|e| e.to_string())?;
    }
    Ok(rest)
}

/// Greedy line breaking: pieces of `text` ending in a separator, joined while `fits`.
fn wrap(text: &str, fits: &dyn Fn(&str) -> bool) -> Vec<String> {
    if fits(text) {
        return vec![text.to_string()];
    }
    // Break after "; " first, then ": ", ", ", then any space.
    for sep in ["; ", ": ", ", ", " "] {
        let pieces: Vec<&str> = text.split_inclusive(sep).collect();
        if pieces.len() < 2 {
            continue;
        }
        let mut lines: Vec<String> = Vec::new();
        let mut cur = String::new();
        for p in pieces {
            let candidate = format!("{cur}{p}");
            if !cur.is_empty() && !fits(candidate.trim_end()) {
                lines.push(cur.trim_end().to_string());
                cur = p.to_string();
            } else {
                cur = candidate;
            }
        }
        lines.push(cur.trim_end().to_string());
        if lines.iter().all(|l| fits(l)) {
            return lines;
        }
    }
    vec![text.to_string()]
}

/// A rectangle in pixels: `(left, top, right, bottom)`.
pub type Rect = (i32, i32, i32, i32);

fn overlaps(a: Rect, b: Rect) -> bool {
    a.0 < b.2 && b.0 < a.2 && a.1 < b.3 && b.1 < a.3
}

/// Which parts of the plot area hold data or labels, on a grid of `CELL`-pixel cells.
pub struct Occupancy {
    x: Range<i32>,
    y: Range<i32>,
    cols: i32,
    cells: Vec<bool>,
    labels: Vec<Rect>,
}

impl Occupancy {
    /// An empty grid over the plot area `(x pixels, y pixels)`.
    pub fn new((x, y): (Range<i32>, Range<i32>)) -> Self {
        let cols = (x.end - x.start) / CELL + 1;
        let rows = (y.end - y.start) / CELL + 1;
        Occupancy {
            x,
            y,
            cols,
            cells: vec![false; (cols.max(1) * rows.max(1)) as usize],
            labels: Vec::new(),
        }
    }

    fn index(&self, (px, py): (i32, i32)) -> Option<usize> {
        if !self.x.contains(&px) || !self.y.contains(&py) {
            return None;
        }
        let (c, r) = ((px - self.x.start) / CELL, (py - self.y.start) / CELL);
        Some((r * self.cols + c) as usize)
    }

    /// Marks the cell of a point.
    pub fn point(&mut self, p: (i32, i32)) {
        if let Some(i) = self.index(p) {
            self.cells[i] = true;
        }
    }

    /// Marks the cells along a segment.
    pub fn segment(&mut self, a: (i32, i32), b: (i32, i32)) {
        let len = (a.0 - b.0).abs().max((a.1 - b.1).abs());
        let steps = (len / (CELL / 2).max(1)).clamp(1, 10_000);
        for k in 0..=steps {
            let t = f64::from(k) / f64::from(steps);
            let lerp = |u: i32, v: i32| (f64::from(u) + t * f64::from(v - u)).round() as i32;
            self.point((lerp(a.0, b.0), lerp(a.1, b.1)));
        }
    }

    /// Marks a rectangle as a label's.
    pub fn label(&mut self, r: Rect) {
        self.labels.push(r);
    }

    /// Occupied cells under `r`.
    fn covered(&self, r: Rect) -> usize {
        let mut n = 0;
        let mut py = r.1;
        while py < r.3 {
            let mut px = r.0;
            while px < r.2 {
                if self.index((px, py)).is_some_and(|i| self.cells[i]) {
                    n += 1;
                }
                px += CELL;
            }
            py += CELL;
        }
        n
    }

    /// Whether `r` lies inside the plot area (with `pad` pixels to spare).
    fn inside(&self, r: Rect, pad: i32) -> bool {
        r.0 >= self.x.start + pad
            && r.2 <= self.x.end - pad
            && r.1 >= self.y.start + pad
            && r.3 <= self.y.end - pad
    }

    /// The best of `candidates` (rectangles): inside the plot, overlapping no label, covering
    /// the fewest occupied cells (the first on ties); failing that, the first inside the plot,
    /// failing that, the first. Records the choice as a label and returns its index.
    pub fn place(&mut self, candidates: &[Rect]) -> usize {
        let free = |r: &Rect| self.inside(*r, 2) && !self.labels.iter().any(|l| overlaps(*l, *r));
        let best = candidates
            .iter()
            .enumerate()
            .filter(|(_, r)| free(r))
            .min_by_key(|(i, r)| (self.covered(**r), *i))
            .map(|(i, _)| i)
            .or_else(|| candidates.iter().position(|r| self.inside(*r, 0)))
            .unwrap_or(0);
        if let Some(&r) = candidates.get(best) {
            self.label(r);
        }
        best
    }

    /// The corner for a legend box of `size` pixels (`margin` from the plot's edges): the one of
    /// upper right, upper left, lower right, lower left, covering the fewest occupied cells.
    pub fn legend_corner(
        &mut self,
        size: (i32, i32),
        margin: i32,
    ) -> plotters::chart::SeriesLabelPosition {
        use plotters::chart::SeriesLabelPosition as P;
        let (w, h) = size;
        let (l, r) = (self.x.start + margin, self.x.end - margin);
        let (t, b) = (self.y.start + margin, self.y.end - margin);
        let corners = [
            (P::UpperRight, (r - w, t, r, t + h)),
            (P::UpperLeft, (l, t, l + w, t + h)),
            (P::LowerRight, (r - w, b - h, r, b)),
            (P::LowerLeft, (l, b - h, l + w, b)),
        ];
        let rects: Vec<Rect> = corners.iter().map(|c| c.1).collect();
        let k = self.place(&rects);
        corners[k].0.clone()
    }
}

/// Candidate rectangles for a label of `size` pixels next to a point `at`, `gap` pixels away:
/// upper right, lower right, upper left, lower left, then the same a row further out, then
/// centred above and below.
pub fn around(at: (i32, i32), size: (u32, u32), gap: i32) -> Vec<Rect> {
    let (w, h) = (size.0 as i32, size.1 as i32);
    let (x, y) = at;
    let mut out = Vec::new();
    for row in [0, h + 2] {
        for (dx, up) in [
            (gap, true),
            (gap, false),
            (-gap - w, true),
            (-gap - w, false),
        ] {
            let top = if up { y - gap - h - row } else { y + gap + row };
            out.push((x + dx, top, x + dx + w, top + h));
        }
    }
    out.push((x - w / 2, y - 2 * gap - h, x - w / 2 + w, y - 2 * gap));
    out.push((x - w / 2, y + 2 * gap, x - w / 2 + w, y + 2 * gap + h));
    out
}
