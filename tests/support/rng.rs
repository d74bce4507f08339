//! A small deterministic random generator for the tests' constructed cases (SplitMix64), so
//! that every run sees the same cases. Included by the test areas that draw cases.
#![allow(dead_code)] // not every area uses every draw

/// SplitMix64: a small deterministic generator, so that every run sees the same cases.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
    /// Uniform in $[-1, 1)$.
    pub fn sym(&mut self) -> f64 {
        2.0 * self.unit() - 1.0
    }
    pub fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.unit()).exp()
    }
    pub fn sign(&mut self) -> f64 {
        if self.unit() < 0.5 {
            -1.0
        } else {
            1.0
        }
    }
}

/// proptest's configuration with a **fixed seed** (proptest draws a fresh one every run): the
/// property tests see the same cases in every run of `cargo test`, so CI passes or fails by the
/// code and not by the second it starts in (three tests' tolerances were found too tight that
/// way, each failing one CI run in tens). To explore other cases by hand, set
/// `PROPTEST_RNG_SEED=<u64>` (proptest reads it; e.g. `PROPTEST_RNG_SEED=$RANDOM cargo test
/// --test suite ring::`): the failure message then names the seed's case.
pub fn proptest_defaults() -> proptest::test_runner::Config {
    use proptest::test_runner::{Config, RngSeed};
    let mut config = Config::default();
    if config.rng_seed == RngSeed::Random {
        config.rng_seed = RngSeed::Fixed(0x00F0_2210);
    }
    config
}

/// [`proptest_defaults`] with `cases` cases.
pub fn proptest_cases(cases: u32) -> proptest::test_runner::Config {
    proptest::test_runner::Config {
        cases,
        ..proptest_defaults()
    }
}
