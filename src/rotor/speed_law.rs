//! A user's speed law $\eta(t)$ with its phase integrated by Gauss-Legendre quadrature on a
//! table of panels ([`SpeedProfile::from_fn`](super::SpeedProfile::from_fn) states the
//! accuracy).

use super::RotorError;
use crate::numeric::{illinois, RootOptions};

type Curve = Box<dyn Fn(f64) -> f64 + Send + Sync>;

/// The 5-point Gauss-Legendre nodes on $[-1, 1]$ and their weights.
const NODES: [f64; 5] = [
    -0.906_179_845_938_664,
    -0.538_469_310_105_683,
    0.0,
    0.538_469_310_105_683,
    0.906_179_845_938_664,
];
const WEIGHTS: [f64; 5] = [
    0.236_926_885_056_189_1,
    0.478_628_670_499_366_5,
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_5,
    0.236_926_885_056_189_1,
];

/// The panels per unit time (the panel width is at most its inverse).
const PANELS_PER_UNIT: f64 = 8.0;

/// The law and the phase at the panels' ends.
pub(super) struct Law {
    eta: Curve,
    eta_rate: Curve,
    width: f64,
    /// $\Phi$ at $k h$, $k = 0..=n$.
    table: Vec<f64>,
    eta_max: f64,
}

impl Law {
    pub(super) fn new(end: f64, eta: Curve, eta_rate: Curve) -> Result<Self, RotorError> {
        let bad = |field, value, reason| {
            Err(RotorError::SpeedProfile {
                field,
                value,
                reason,
            })
        };
        if !(end.is_finite() && end > 0.0) {
            return bad("end", end, "a law's interval must be finite and > 0");
        }
        let panels = (end * PANELS_PER_UNIT).ceil().max(1.0) as usize;
        let width = end / panels as f64;
        let mut law = Self {
            eta,
            eta_rate,
            width,
            table: Vec::with_capacity(panels + 1),
            eta_max: 0.0,
        };
        law.table.push(0.0);
        for k in 0..panels {
            let (a, b) = (k as f64 * width, (k + 1) as f64 * width);
            for t in NODES
                .map(|x| a + 0.5 * (b - a) * (1.0 + x))
                .into_iter()
                .chain([a, b])
            {
                let v = (law.eta)(t);
                if !(v.is_finite() && v >= 0.0) {
                    return bad("eta", v, "a law's speed must be finite and >= 0");
                }
                law.eta_max = law.eta_max.max(v);
            }
            let next = law.table[k] + law.integral(a, b);
            law.table.push(next);
        }
        if law.eta_max <= 0.0 {
            return bad(
                "eta",
                0.0,
                "the rotor must turn: the speed must be > 0 somewhere",
            );
        }
        Ok(law)
    }

    /// $\int_a^b \eta$ by the 5-point rule.
    fn integral(&self, a: f64, b: f64) -> f64 {
        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
        let sum: f64 = NODES
            .iter()
            .zip(WEIGHTS)
            .map(|(x, w)| w * (self.eta)(mid + half * x))
            .sum();
        half * sum
    }

    pub(super) fn eta(&self, t: f64) -> f64 {
        (self.eta)(t)
    }

    pub(super) fn eta_rate(&self, t: f64) -> f64 {
        (self.eta_rate)(t)
    }

    pub(super) fn eta_max(&self) -> f64 {
        self.eta_max
    }

    fn end(&self) -> f64 {
        self.width * (self.table.len() - 1) as f64
    }

    /// $\Phi(t)$ for $0 \le t \le T$.
    pub(super) fn phase(&self, t: f64) -> f64 {
        let last = self.table.len() - 1;
        let k = ((t / self.width).floor() as usize).min(last);
        let start = k as f64 * self.width;
        if k == last || t <= start {
            return self.table[k];
        }
        self.table[k] + self.integral(start, t)
    }

    /// The first $t \in [0, T]$ with $\Phi(t) = $ `phase`, for $0 <$ `phase` $\le \Phi(T)$.
    pub(super) fn time_of_phase(&self, phase: f64) -> f64 {
        // The first panel whose end reaches the phase.
        let k = self
            .table
            .partition_point(|&p| p < phase)
            .clamp(1, self.table.len() - 1);
        let (a, b) = (
            (k - 1) as f64 * self.width,
            (k as f64 * self.width).min(self.end()),
        );
        let g = |t: f64| self.phase(t) - phase;
        let (ga, gb) = (g(a), g(b));
        if gb == 0.0 {
            return b;
        }
        let tol = 4.0 * f64::EPSILON * b.max(1.0);
        let opts = RootOptions::default()
            .with_tol(tol)
            .with_max_evaluations(200);
        // A bracket with a sign change by the choice of k; a NaN speed is refused at build.
        illinois((a, ga), (b, gb), &opts, g).map_or(b, |r| r.hi)
    }
}
