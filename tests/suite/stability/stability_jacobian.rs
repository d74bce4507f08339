//! The analytic Jacobian of the stroboscopic map (variational equations through every event)
//! against central finite differences of the map itself, on periodic, preloaded (regimes
//! II..V, preload crossings, a section in contact) and chaotic orbits of the paper's model.
//!
//! The differences are Richardson-extrapolated central differences, $(4D_{h/2} - D_h)/3$,
//! with the map integrated at rtol 1e-13 (its noise is a few 1e-15): truncation $O(h^4)$ and
//! rounding $\approx 10^{-15}/h$, both near 1e-11 at $h = 10^{-3}$ (the contact stiffness makes
//! plain central differences at that step wrong by 1e-5). Near a grazing contact the map is
//! smooth only within the distance to grazing, and the step is reduced there (`h` per case).

use jeffcott::hybrid::SimOptions;
use jeffcott::paper::{JeffcottModel, State};
use jeffcott::params::{Params, Preset};
use jeffcott::stability::StroboscopicMap;
use nalgebra::{DMatrix, DVector};

fn tight() -> SimOptions {
    SimOptions::default().with_rtol(1e-13).with_atol(1e-15)
}

/// Richardson central differences of the map on z at the state `y`.
fn fd_jacobian(map: &StroboscopicMap<'_, JeffcottModel>, y: &State, h: f64) -> DMatrix<f64> {
    let z = map.reduce(y);
    let p = |z: &DVector<f64>| map.reduce(&map.advance(&map.state(y, z)).unwrap().y);
    let mut jac = DMatrix::zeros(z.len(), z.len());
    for j in 0..z.len() {
        let central = |h: f64| {
            let (mut a, mut b) = (z.clone(), z.clone());
            a[j] += h;
            b[j] -= h;
            (p(&a) - p(&b)) / (2.0 * h)
        };
        jac.set_column(j, &((central(0.5 * h) * 4.0 - central(h)) / 3.0));
    }
    jac
}

/// A state on the attractor from rest after `transient` periods.
fn attractor(model: &JeffcottModel, transient: u64) -> State {
    let map = StroboscopicMap::new(model, transient, SimOptions::default()).unwrap();
    map.advance(&State::zeros()).unwrap().y
}

/// Worst |DP - DP_fd| over `count` consecutive applications of P^n from `y`, with the event
/// kinds seen, and the smallest event margin.
fn compare(
    params: Params,
    y: State,
    periods: u64,
    count: usize,
    h: f64,
) -> (f64, Vec<&'static str>, f64) {
    let model = JeffcottModel::new(params).unwrap();
    let map = StroboscopicMap::new(&model, periods, tight()).unwrap();
    let (mut worst, mut kinds, mut margin) = (0.0f64, Vec::new(), 1.0f64);
    let mut y = y;
    for _ in 0..count {
        let lin = map.linearize(&y).unwrap();
        assert_eq!(lin.openness, [0.0, 0.0], "sections must close the map on z");
        let fd = fd_jacobian(&map, &y, h);
        worst = worst.max((&lin.jacobian - fd).abs().max());
        for e in &lin.events {
            if !kinds.contains(&e.kind) {
                kinds.push(e.kind);
            }
            margin = margin.min(e.margin);
        }
        y = lin.y;
    }
    (worst, kinds, margin)
}

#[test]
fn period_one_orbits_at_eta_2_regimes_v_and_ii() {
    let check = [0.5781094858, -0.0232587983, 0.0944197873, -0.3099208533];
    for (preset, bound) in [(Preset::Fig8a, 3e-10), (Preset::Fig8b, 5e-10)] {
        let model = JeffcottModel::new(preset.params()).unwrap();
        let y = model
            .state_at([check[0], check[1]], [check[2], check[3]])
            .unwrap();
        let (worst, kinds, _) = compare(preset.params(), y, 1, 2, 1e-3);
        eprintln!("{preset}: |DP - FD| = {worst:e}, events {kinds:?}");
        assert_eq!(kinds, ["contact onset", "contact loss"]);
        // Measured: 9.9e-11 (8a), 1.7e-10 (8b).
        assert!(worst < bound, "{preset}: {worst:e}");
    }
}

#[test]
fn preload_crossings_and_a_section_in_contact() {
    // Fig. 10d (eta = 3, D = 0.03): a period-2 orbit whose section is in regime III every other
    // period, crossing x_s = D both ways.
    let p = Preset::Fig10d.params();
    let model = JeffcottModel::new(p).unwrap();
    let y = attractor(&model, 300);
    let two = StroboscopicMap::new(&model, 1, tight()).unwrap();
    let labels = [
        two.advance(&y).unwrap().label,
        two.advance(&two.advance(&y).unwrap().y).unwrap().label,
    ];
    assert!(
        labels.contains(&3) && labels.contains(&1),
        "sections in III and I: {labels:?}"
    );
    let (worst, kinds, _) = compare(p, y, 1, 4, 1e-3);
    eprintln!("Fig. 10d: |DP - FD| = {worst:e}, events {kinds:?}");
    for k in [
        "contact onset",
        "x_s beyond preload",
        "x_s within preload",
        "contact loss",
    ] {
        assert!(kinds.contains(&k), "{k} missing from {kinds:?}");
    }
    // Measured: 5.1e-10.
    assert!(worst < 2e-9, "{worst:e}");
    // The Fig. 8 values with D = 0.003 at eta = 3: regimes II, III, V, both axes crossing.
    let p = Preset::Fig8a.params().with_eta(3.0).with_preload(0.003);
    let y = attractor(&JeffcottModel::new(p).unwrap(), 300);
    let (worst, kinds, _) = compare(p, y, 1, 4, 1e-3);
    eprintln!("D = 0.003: |DP - FD| = {worst:e}, events {kinds:?}");
    for k in [
        "y_s beyond preload",
        "y_s within preload",
        "x_s beyond preload",
    ] {
        assert!(kinds.contains(&k), "{k} missing from {kinds:?}");
    }
    // Measured: 1.4e-10.
    assert!(worst < 5e-10, "{worst:e}");
}

#[test]
fn chaotic_orbits_at_eta_2_442() {
    for preset in [Preset::Fig8a, Preset::Fig8b] {
        let p = preset.params().with_eta(2.442);
        let y = attractor(&JeffcottModel::new(p).unwrap(), 300);
        // Near-grazing contacts occur on these attractors (onset margins down to 0.07): the
        // map is smooth only within the distance to grazing, so the step is smaller. Which
        // periods are sampled depends on the rounding of the 300-period transient (a chaotic
        // orbit), so the step is taken small enough for the closest grazings seen.
        // (Measured with h = 1e-3, 3e-4, 1e-4, 3e-5: 3.8e-6, 3.1e-8, 4.2e-10, 1.8e-10 for 8a on
        // one sample, and 5.1e-9 at h = 1e-4 on a sample with margin 0.067: the differences
        // converge to the analytic Jacobian as the step shrinks.)
        let (worst, kinds, margin) = compare(p, y, 1, 10, 3e-5);
        eprintln!("{preset} chaotic: |DP - FD| = {worst:e}, events {kinds:?}, min margin {margin}");
        // Measured: 2.0e-10 (8a), 2.9e-10 (8b) at h = 3e-5; entries of DP up to 3.
        assert!(worst < 1e-9, "{preset}: {worst:e}");
    }
}

#[test]
fn a_jacobian_vector_product_is_the_jacobian_times_the_vector() {
    let p = Preset::Fig8b.params().with_eta(2.442);
    let model = JeffcottModel::new(p).unwrap();
    let y = attractor(&model, 300);
    let map = StroboscopicMap::new(&model, 2, SimOptions::default()).unwrap();
    let full = map.linearize(&y).unwrap();
    let v = DMatrix::from_column_slice(4, 1, &[0.3, -0.1, 0.5, 0.2]);
    let jvp = map.linearize_along(&y, &v).unwrap();
    // Same trajectory bitwise (the variational components are out of the error control).
    assert_eq!(full.y, jvp.y);
    assert!((&full.jacobian * &v - &jvp.jacobian).abs().max() < 1e-13);
    // And the plain map gives the same state bitwise.
    assert_eq!(map.advance(&y).unwrap().y, full.y);
}
