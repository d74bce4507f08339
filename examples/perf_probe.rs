//! Temporary timing probe.
use jeffcott::hybrid::SimOptions;
use jeffcott::jeffcott::{JeffcottModel, State};
use jeffcott::params::Preset;
fn main() {
    for preset in [Preset::Fig8a, Preset::Fig8b] {
        let t = std::time::Instant::now();
        let mut tot = jeffcott::hybrid::SimStats::default();
        let n: usize = std::env::var("N").ok().and_then(|s| s.parse().ok()).unwrap_or(60);
        for i in 0..n {
            let eta = 2.0 + 3.0 * i as f64 / (n - 1) as f64;
            let m = JeffcottModel::new(preset.params().with_eta(eta)).unwrap();
            let opts = SimOptions { rtol: 1e-9, atol: 1e-12, ..SimOptions::default() };
            let (_tr, s) = m.stroboscopic(&State::zeros(), 300, 450, &opts).unwrap();
            tot.steps += s.steps; tot.rhs_evals += s.rhs_evals; tot.exact_evals += s.exact_evals; tot.transitions += s.transitions; tot.rejected += s.rejected;
        }
        let el = t.elapsed().as_secs_f64();
        println!("{preset}: {:.3} s for {n} x 450 periods = {:.2} us/period; {:?}", el, el / (n as f64 * 450.0) * 1e6, tot);
    }
}
