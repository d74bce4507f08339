//! Reading ROSS's exports: sizes, the lateral DOFs, and clear errors for what is not one.

use jeffcott::rotor::{DofLayout, RotorError, RotorMatrices};

fn data(name: &str) -> String {
    format!("{}/tests/data/rotors/{name}", env!("CARGO_MANIFEST_DIR"))
}

#[test]
fn reads_both_ross_exports_and_keeps_the_lateral_dofs() {
    // Sizes from the shared sidecars (ndof 42 and 204, 6 DOF a node).
    for (file, dofs) in [
        ("rotor_example_1500rpm.mat", 42),
        ("rotor_example_with_damping_1200rpm.mat", 204),
    ] {
        let full = RotorMatrices::from_ross_mat(data(file)).unwrap();
        assert_eq!(full.dofs(), dofs);
        assert_eq!(full.layout(), DofLayout::Ross6);
        let lat = full.lateral().unwrap();
        assert_eq!(lat.dofs(), dofs / 6 * 4);
        assert_eq!(lat.layout(), DofLayout::Lateral4);
        // Node 12's x of the 204-DOF rotor is DOF 72 there and 48 here; M's entry agrees.
        let node = full.nodes() / 3;
        let (fx, lx) = (full.x_dof(node).unwrap(), lat.x_dof(node).unwrap());
        assert_eq!(full.mass()[(fx + 1, fx + 1)], lat.mass()[(lx + 1, lx + 1)]);
        assert_eq!(
            full.stiffness()[(fx, fx + 4)],
            lat.stiffness()[(lx, lx + 3)]
        );
    }
}

#[test]
fn what_is_not_a_ross_export_is_a_clear_error() {
    let csv = RotorMatrices::from_ross_mat(data("S1_reference.csv")).unwrap_err();
    assert_eq!(csv, RotorError::NotMatFile);
    let none = RotorMatrices::from_ross_mat(data("no_such_file.mat")).unwrap_err();
    assert_eq!(none, RotorError::Io(std::io::ErrorKind::NotFound));
    let full = RotorMatrices::from_ross_mat(data("rotor_example_1500rpm.mat")).unwrap();
    let out = full.x_dof(7).unwrap_err();
    assert_eq!(out, RotorError::NodeOutOfRange { node: 7, nodes: 7 });
    // A coupling between a lateral and an axial DOF forbids dropping the axial ones.
    let mut k = full.stiffness().clone();
    k[(0, 2)] = 1.0;
    let coupled = RotorMatrices::new(
        full.mass().clone(),
        full.damping().clone(),
        full.gyroscopic().clone(),
        k,
        DofLayout::Ross6,
    )
    .unwrap();
    assert!(matches!(
        coupled.lateral(),
        Err(RotorError::LateralCoupling {
            matrix: "K",
            row: 0,
            col: 2,
            ..
        })
    ));
    let bad = RotorMatrices::new(
        full.mass().clone(),
        full.damping().clone(),
        full.gyroscopic().clone(),
        full.stiffness().clone().remove_row(0),
        DofLayout::Ross6,
    );
    assert!(matches!(
        bad,
        Err(RotorError::MatrixShape { matrix: "K", .. })
    ));
}
