//! The steady unbalance response of both shared ROSS rotors against ROSS's own
//! (`run_unbalance_response`, in each sidecar's `linear_check`) at the check node, and against
//! the sidecar's direct solve at every node. Truth: ROSS 3.1.0 (and numpy's solve of the
//! exported matrices, which agrees with ROSS to 3e-12).

use jeffcott::nalgebra::{Complex, DVector};
use jeffcott::rotor::{LinearSystem, RotorMatrices};
use serde_json::Value;

fn data(name: &str) -> String {
    format!("{}/tests/data/rotors/{name}", env!("CARGO_MANIFEST_DIR"))
}

fn complex(v: &Value) -> Complex<f64> {
    Complex::new(v[0].as_f64().unwrap(), v[1].as_f64().unwrap())
}

/// The sidecar, the lateral system with the sidecar's unbalances, and its steady response.
fn solve(stem: &str) -> (Value, RotorMatrices, DVector<Complex<f64>>) {
    let text = std::fs::read_to_string(data(&format!("{stem}.json"))).unwrap();
    let json: Value = serde_json::from_str(&text).unwrap();
    let speed = json["speed_rad_s"].as_f64().unwrap();
    let lateral = RotorMatrices::from_ross_mat(data(&format!("{stem}.mat")))
        .unwrap()
        .lateral()
        .unwrap();
    let mut system = LinearSystem::from_matrices(&lateral, speed).unwrap();
    for u in json["linear_check"]["unbalance"].as_array().unwrap() {
        system = system
            .with_unbalance(
                lateral.layout(),
                u["node"].as_u64().unwrap() as usize,
                u["magnitude_kg_m"].as_f64().unwrap(),
                u["phase_rad"].as_f64().unwrap(),
            )
            .unwrap();
    }
    let x = system.steady_response().unwrap();
    (json, lateral, x)
}

fn check(stem: &str) {
    let (json, lateral, x) = solve(stem);
    let check = &json["linear_check"];
    let node = check["check_node"].as_u64().unwrap() as usize;
    let i = lateral.x_dof(node).unwrap();
    let ross = &check["X_node_ross_unbalance_response"];
    let (rx, ry) = (complex(&ross["x"]), complex(&ross["y"]));
    let scale = rx.norm().max(ry.norm());
    let at_node = (x[i] - rx).norm().max((x[i + 1] - ry).norm()) / scale;
    println!("{stem}: node {node} against ROSS: {at_node:.2e} relative");
    assert!(at_node <= 1e-10, "{stem}: {at_node:e}");
    // Every node, against the sidecar's direct solve (relative to its largest amplitude).
    let nodes = check["all_nodes_x_y"].as_array().unwrap();
    assert_eq!(nodes.len(), lateral.nodes());
    let reference: Vec<[Complex<f64>; 2]> = nodes
        .iter()
        .map(|n| [complex(&n[0]), complex(&n[1])])
        .collect();
    let largest = reference
        .iter()
        .flat_map(|r| r.iter().map(|c| c.norm()))
        .fold(0.0, f64::max);
    let mut worst = 0.0f64;
    for (k, r) in reference.iter().enumerate() {
        let j = lateral.x_dof(k).unwrap();
        worst = worst.max((x[j] - r[0]).norm().max((x[j + 1] - r[1]).norm()));
    }
    println!("{stem}: every node: {:.2e} relative", worst / largest);
    assert!(worst <= 1e-10 * largest, "{stem}: {:e}", worst / largest);
}

#[test]
fn steady_unbalance_response_of_the_42_dof_rotor_is_ross_s() {
    check("rotor_example_1500rpm");
}

#[test]
fn steady_unbalance_response_of_the_204_dof_rotor_is_ross_s() {
    check("rotor_example_with_damping_1200rpm");
}

/// The conventions matter: a backward-whirling force (F_y = +i me W^2) or G with the other
/// sign gives an answer far outside the tolerance (the sidecar's sensitivity: 200 % and 3 %).
#[test]
fn a_wrong_whirl_or_gyroscopic_sign_is_caught() {
    let stem = "rotor_example_with_damping_1200rpm";
    let (json, lateral, x) = solve(stem);
    let speed = json["speed_rad_s"].as_f64().unwrap();
    let flipped = RotorMatrices::new(
        lateral.mass().clone(),
        lateral.damping().clone(),
        -lateral.gyroscopic(),
        lateral.stiffness().clone(),
        lateral.layout(),
    )
    .unwrap();
    let g_flipped = LinearSystem::from_matrices(&flipped, speed)
        .unwrap()
        .with_unbalance(lateral.layout(), 12, 2e-3, -std::f64::consts::FRAC_PI_2)
        .unwrap()
        .steady_response()
        .unwrap();
    let change = (&g_flipped - &x).norm() / x.norm();
    assert!(change > 1e-2, "{change}");
}
