//! Exploration (scratch, not committed).
use jeffcott::hybrid::SimOptions;
use jeffcott::paper::JeffcottModel;
use jeffcott::params::Preset;
use jeffcott::stability::{multipliers, StroboscopicMap};
use nalgebra::DVector;

#[test]
fn explore() {
    let model = JeffcottModel::new(Preset::Fig8a.params().with_eta(2.0)).unwrap();
    let map = StroboscopicMap::new(&model, 1, SimOptions::default()).unwrap();
    let z = DVector::from_vec(vec![
        0.5781094858,
        -0.0232587983,
        0.0944197873,
        -0.3099208533,
    ]);
    let y = model.state_at([z[0], z[1]], [z[2], z[3]]).unwrap();
    let lin = map.linearize(&y).unwrap();
    println!("P(z) - z = {}", (&lin.value - &z).transpose());
    println!("DP = {}", lin.jacobian);
    for m in multipliers(&lin.jacobian).unwrap() {
        println!("{} @ {}", m.modulus(), m.argument());
    }
    println!("events {:?}", lin.events);
    let adv = map.advance(&y).unwrap();
    println!("advance - lin: {:e}", (adv.y - lin.y).norm());
    // FD of P
    let h = 1e-3;
    let p = |z: &DVector<f64>| {
        let y = map.state(&y, z);
        map.reduce(&map.advance(&y).unwrap().y)
    };
    let mut fd = nalgebra::DMatrix::zeros(4, 4);
    for j in 0..4 {
        let d = |h: f64| {
            let mut a = z.clone();
            a[j] += h;
            let mut b = z.clone();
            b[j] -= h;
            (p(&a) - p(&b)) / (2.0 * h)
        };
        let c = (d(h / 2.0) * 4.0 - d(h)) / 3.0;
        fd.set_column(j, &c);
    }
    println!("FD - DP: {:e}", (&fd - &lin.jacobian).abs().max());
}
