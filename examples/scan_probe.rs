//! Temporary.
use jeffcott::hybrid::{OutputPlan, SimOptions};
use jeffcott::jeffcott::{JeffcottModel, State};
use jeffcott::params::Preset;
fn main() {
    for samples in [1, 2, 4, 8] {
        let p = Preset::Fig8a.params();
        let m = JeffcottModel::new(p).unwrap();
        let plan = OutputPlan {
            t_end: 300.0 * p.forcing_period(),
            strobe: None,
            dense: None,
            events: false,
        };
        let o = SimOptions {
            event_samples: samples,
            rtol: 1e-9,
            ..SimOptions::default()
        };
        let (_tr, st) = m.run(0.0, &State::zeros(), &plan, &o).unwrap();
        println!(
            "samples {samples}: {st:?} rhs/step {:.1}",
            st.rhs_evals as f64 / st.steps as f64
        );
    }
}
