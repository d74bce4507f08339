//! Temporary.
use jeffcott::hybrid::{OutputPlan, SimOptions};
use jeffcott::jeffcott::{JeffcottModel, State};
use jeffcott::params::Preset;
fn main() {
    let which = std::env::var("P").unwrap_or("fig8b".into());
    let p = which.parse::<Preset>().unwrap().params();
    let m = JeffcottModel::new(p).unwrap();
    let plan = OutputPlan {
        t_end: 400.0 * p.forcing_period(),
        strobe: None,
        dense: None,
        events: false,
    };
    let o = SimOptions {
        rtol: 1e-9,
        atol: 1e-12,
        ..SimOptions::default()
    };
    let (_tr, st) = m.run(0.0, &State::zeros(), &plan, &o).unwrap();
    println!("{which} {st:?}");
}
