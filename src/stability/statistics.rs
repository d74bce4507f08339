use nalgebra::{DMatrix, DVector};

/// Batch-means accumulator of a vector-valued series (one sample per iteration).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct BatchMeans {
    batch_length: usize,
    dim: usize,
    /// Sum over the current (incomplete) batch.
    current: Vec<f64>,
    in_current: usize,
    /// Means of the complete batches.
    batches: Vec<Vec<f64>>,
    /// Sum over every sample.
    total: Vec<f64>,
    count: usize,
}

/// A batch-means estimate of a time average and its standard error (see [batch means](crate::stability#batch-means)).
#[derive(Debug, Clone, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct BatchEstimate {
    /// The mean over every sample, per component.
    pub mean: Vec<f64>,
    /// Its standard error by batch means, per component (NaN with fewer than two batches).
    pub stderr: Vec<f64>,
    /// Samples used.
    pub samples: usize,
    /// The batch length $b$.
    pub batch_length: usize,
    /// Complete batches $m$.
    pub batches: usize,
    /// The running estimate: the mean of all samples up to the end of each complete batch.
    pub running: Vec<Vec<f64>>,
}

impl BatchMeans {
    /// An accumulator of `dim`-component samples with batches of `batch_length` (at least 1).
    pub fn new(dim: usize, batch_length: usize) -> Self {
        Self {
            batch_length: batch_length.max(1),
            dim,
            current: vec![0.0; dim],
            in_current: 0,
            batches: Vec::new(),
            total: vec![0.0; dim],
            count: 0,
        }
    }

    /// Adds one sample (its first `dim` components).
    pub fn push(&mut self, sample: &[f64]) {
        for i in 0..self.dim {
            self.current[i] += sample[i];
            self.total[i] += sample[i];
        }
        self.in_current += 1;
        self.count += 1;
        if self.in_current == self.batch_length {
            let b = self.batch_length as f64;
            self.batches
                .push(self.current.iter().map(|s| s / b).collect::<Vec<f64>>());
            self.current.iter_mut().for_each(|s| *s = 0.0);
            self.in_current = 0;
        }
    }

    /// The current estimate.
    pub fn estimate(&self) -> BatchEstimate {
        let n = self.count.max(1) as f64;
        let mean: Vec<f64> = self.total.iter().map(|s| s / n).collect();
        let m = self.batches.len();
        let stderr = (0..self.dim)
            .map(|i| {
                if m < 2 {
                    return f64::NAN;
                }
                let bm = self.batches.iter().map(|b| b[i]).sum::<f64>() / m as f64;
                let var = self
                    .batches
                    .iter()
                    .map(|b| (b[i] - bm) * (b[i] - bm))
                    .sum::<f64>()
                    / (m - 1) as f64;
                (var / m as f64).sqrt()
            })
            .collect();
        let mut running = Vec::with_capacity(m);
        let mut acc = vec![0.0; self.dim];
        for (j, b) in self.batches.iter().enumerate() {
            for i in 0..self.dim {
                acc[i] += b[i];
            }
            running.push(acc.iter().map(|a| a / (j + 1) as f64).collect());
        }
        BatchEstimate {
            mean,
            stderr,
            samples: self.count,
            batch_length: self.batch_length,
            batches: m,
            running,
        }
    }
}

/// One QR step of the Benettin method: `y` $= DP\thinspace Q$ ($d\times p$, $p \le d$) is
/// factored as $Q^\prime R$ with $R_{ii} > 0$; returns $Q^\prime$ and $\ln R_{ii}$. A zero or
/// non-finite diagonal (a direction collapsed to rounding, or a non-finite Jacobian) gives
/// $-\infty$ or NaN in that slot, for the caller to report.
pub(crate) fn qr_step(y: DMatrix<f64>) -> (DMatrix<f64>, DVector<f64>) {
    let p = y.ncols();
    let qr = y.qr();
    let (mut q, r) = (qr.q(), qr.r());
    let mut logs = DVector::zeros(p);
    for i in 0..p {
        let rii = r[(i, i)];
        if rii < 0.0 {
            q.column_mut(i).neg_mut();
        }
        logs[i] = rii.abs().ln();
    }
    (q, logs)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn batch_means_of_independent_samples_give_the_textbook_error() {
        // A deterministic pseudo-random sequence (xorshift) uniform in [0, 1): variance 1/12.
        let mut state = 0x9E37_79B9_7F4A_7C15u64;
        let mut next = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut bm = BatchMeans::new(1, 100);
        let n = 200_000;
        for _ in 0..n {
            bm.push(&[next()]);
        }
        let e = bm.estimate();
        let expected = (1.0 / 12.0 / n as f64).sqrt();
        assert_eq!(e.batches, 2000);
        assert!((e.mean[0] - 0.5).abs() < 4.0 * expected, "{}", e.mean[0]);
        // The standard error of a standard error from m = 2000 batches is 1/sqrt(2(m-1)) = 1.6 %.
        assert!(
            (e.stderr[0] / expected - 1.0).abs() < 0.08,
            "{} vs {expected}",
            e.stderr[0]
        );
        assert_eq!(e.running.len(), 2000);
        assert!((e.running.last().unwrap()[0] - e.mean[0]).abs() < 1e-12);
    }

    #[test]
    fn qr_steps_of_a_constant_matrix_give_the_logs_of_its_eigenvalue_moduli() {
        let a = DMatrix::from_row_slice(3, 3, &[2.0, 1.0, 0.0, 0.0, -0.5, 0.3, 0.0, 0.0, 0.1]);
        let mut q = DMatrix::identity(3, 3);
        let mut sums = DVector::zeros(3);
        let n = 400;
        for _ in 0..n {
            let (qn, logs) = qr_step(&a * &q);
            q = qn;
            sums += logs;
        }
        let exps = sums / n as f64;
        let expect = [2.0f64.ln(), 0.5f64.ln(), 0.1f64.ln()];
        for i in 0..3 {
            assert!(
                (exps[i] - expect[i]).abs() < 5e-3,
                "{i}: {} vs {}",
                exps[i],
                expect[i]
            );
        }
        // The identity of the factorisation: ln|det| per step.
        assert!((exps.sum() - (2.0f64 * 0.5 * 0.1).ln()).abs() < 1e-12);
    }
}
