//! `LinearSystem` and `LinearRotor`: the ring in metres is the ring in gaps (scale
//! invariance on case S1's first contacts), and clear errors for bad input.

use jeffcott::hybrid::SimOptions;
use jeffcott::nalgebra::{Complex, DMatrix, DVector};
use jeffcott::ode::Method;
use jeffcott::ring::{RingError, SnubberRing};
use jeffcott::rotor::{
    CraigBampton, DofLayout, LinearRotor, LinearSystem, ModeSelection, RotorError, RotorMatrices,
};

use crate::fe::fe_s1::{contact_events, run, sample_error, S1};

/// S1 to 0.03 s (two onsets, one loss) once in metres and once with every length in gaps
/// (the same matrices, the unbalance and the ring's lengths divided by the gap: forces in
/// N/gap). The element has no absolute length tolerance, so the two runs agree to the
/// integration's error, event by event, and each agrees with the reference.
#[test]
fn the_ring_in_metres_is_the_ring_in_gaps() {
    let (s1, t_end) = (S1::load(), 0.03);
    let opts = SimOptions::default()
        .with_method(Method::Radau5)
        .with_rtol(1e-8)
        .with_atol(1e-8);
    let metres = run(&s1, 1.0, &opts, t_end);
    let gaps = run(&s1, s1.gap, &opts, t_end);
    let (em, eg) = (contact_events(&metres), contact_events(&gaps));
    assert_eq!(em.len(), 3, "{em:?}");
    assert_eq!(
        em.iter().map(|e| &e.0).collect::<Vec<_>>(),
        eg.iter().map(|e| &e.0).collect::<Vec<_>>()
    );
    let dt = em
        .iter()
        .zip(&eg)
        .fold(0.0, |m, (a, b)| f64::max(m, (a.1 - b.1).abs()));
    let model = s1.model(1.0);
    let mut worst = 0.0f64;
    for (a, b) in metres
        .trajectory
        .samples
        .iter()
        .zip(&gaps.trajectory.samples)
    {
        let (pa, pb) = (
            model.rotor().station_displacement(&a.y),
            model.rotor().station_displacement(&b.y),
        );
        let d = ((pa[0] - pb[0] * s1.gap).powi(2) + (pa[1] - pb[1] * s1.gap).powi(2)).sqrt();
        worst = worst.max(d / s1.gap);
    }
    let (err_m, _) = sample_error(&s1, &metres, 1.0, t_end);
    let (err_g, _) = sample_error(&s1, &gaps, s1.gap, t_end);
    println!(
        "metres vs gaps: samples {worst:.2e} gap, events {dt:.1e} s; against S1: {err_m:.2e} and {err_g:.2e} gap"
    );
    assert!(worst <= 1e-7, "{worst:e}");
    assert!(dt <= 1e-9, "{dt:e}");
    assert!(err_m.max(err_g) <= 1e-7, "{err_m:e} {err_g:e}");
}

fn jeffcott(speed: f64) -> LinearSystem {
    let eye = DMatrix::<f64>::identity(2, 2);
    LinearSystem::new(&eye * 10.0, &eye * 100.0, &eye * 1e6, speed).unwrap()
}

#[test]
fn bad_input_is_a_clear_error() {
    let station = LinearRotor::new(jeffcott(300.0), [0, 2], [0.0; 2]).unwrap_err();
    assert_eq!(
        station,
        RotorError::DofOutOfRange {
            field: "station y",
            index: 2,
            dofs: 2
        }
    );
    assert!(
        station.to_string().contains("coordinates 0 to 1"),
        "{station}"
    );
    // No coordinate at all: an error, not nalgebra's panic on an empty solve.
    let empty = DMatrix::<f64>::zeros(0, 0);
    let none = LinearSystem::new(empty.clone(), empty.clone(), empty, 300.0).unwrap_err();
    assert_eq!(
        none,
        RotorError::DofCount {
            dofs: 0,
            per_node: 1
        }
    );
    let twice = LinearRotor::new(jeffcott(300.0), [1, 1], [0.0; 2]).unwrap_err();
    assert_eq!(twice, RotorError::StationCoincident { index: 1 });
    let offset = LinearRotor::new(jeffcott(300.0), [0, 1], [f64::NAN, 0.0]).unwrap_err();
    assert!(matches!(
        offset,
        RotorError::Parameter {
            field: "ring offset x",
            ..
        }
    ));
    let eye = DMatrix::<f64>::identity(2, 2);
    let shape = LinearSystem::new(eye.clone(), DMatrix::zeros(3, 3), eye.clone(), 1.0).unwrap_err();
    assert_eq!(
        shape,
        RotorError::MatrixShape {
            matrix: "D",
            rows: 3,
            cols: 3,
            expected: 2
        }
    );
    let speed = LinearSystem::new(eye.clone(), eye.clone(), eye.clone(), 0.0).unwrap_err();
    assert_eq!(speed, RotorError::Speed { value: 0.0 });
    let length = LinearSystem::from_parts(
        eye.clone(),
        eye.clone(),
        eye.clone(),
        1.0,
        DVector::from_element(3, Complex::new(1.0, 0.0)),
        DVector::zeros(2),
    )
    .unwrap_err();
    assert_eq!(
        length,
        RotorError::VectorLength {
            vector: "F_hat",
            len: 3,
            expected: 2
        }
    );
    // Two coordinates are not whole nodes of a 4-DOF layout; a node beyond the rotor.
    let layout = jeffcott(1.0)
        .with_unbalance(DofLayout::Lateral4, 0, 1e-3, 0.0)
        .unwrap_err();
    assert_eq!(
        layout,
        RotorError::DofCount {
            dofs: 2,
            per_node: 4
        }
    );
    let four = DMatrix::<f64>::identity(4, 4);
    let node = LinearSystem::new(four.clone(), four.clone(), four.clone(), 1.0)
        .unwrap()
        .with_unbalance(DofLayout::Lateral4, 1, 1e-3, 0.0)
        .unwrap_err();
    assert_eq!(node, RotorError::NodeOutOfRange { node: 1, nodes: 1 });
    // A zero mass: refused at the door (not positive definite), not later by the LU of M.
    assert!(matches!(
        LinearSystem::new(DMatrix::zeros(2, 2), eye.clone(), eye.clone(), 1.0),
        Err(RotorError::MassNotPositiveDefinite { .. })
    ));
    let ring = SnubberRing::from_units(1e6, -1.0, [0.0; 2], 1e-4).unwrap_err();
    assert_eq!(
        ring,
        RingError::Negative {
            field: "unit_damping",
            value: -1.0
        }
    );
}

/// The unbalance is ROSS's: F_x = me W^2 cos(W t + phase), F_y = me W^2 sin(W t + phase) at
/// the node's x and y (README of the shared rotors), so at rest the rotor's acceleration is
/// F / m at t = 0 and a quarter period later.
#[test]
fn unbalance_and_gravity_are_the_forces_they_say() {
    let (w, me, phase) = (300.0, 2e-3, 0.4);
    let system = jeffcott(w)
        .with_unbalance(DofLayout::Lateral4, 0, me, phase)
        .map(|_| ())
        .unwrap_err();
    assert_eq!(
        system,
        RotorError::DofCount {
            dofs: 2,
            per_node: 4
        }
    );
    let four = DMatrix::<f64>::identity(4, 4);
    let system = LinearSystem::new(&four * 10.0, &four * 100.0, &four * 1e6, w)
        .unwrap()
        .with_unbalance(DofLayout::Lateral4, 0, me, phase)
        .unwrap()
        .with_gravity(DofLayout::Lateral4, [0.0, -9.81])
        .unwrap();
    let rotor = LinearRotor::new(system, [0, 1], [0.0; 2]).unwrap();
    let y = rotor.rest_state();
    let mut dy = y.clone();
    use jeffcott::rotor::SmoothRotor;
    for t in [0.0, 0.25 * std::f64::consts::TAU / w] {
        rotor.rhs(t, &y, &mut dy);
        let f = me * w * w;
        let want = [
            (w * t + phase).cos() * f / 10.0,
            (w * t + phase).sin() * f / 10.0 - 9.81,
        ];
        assert!(
            (dy[4] - want[0]).abs() <= 1e-12 * f,
            "{} {}",
            dy[4],
            want[0]
        );
        assert!(
            (dy[5] - want[1]).abs() <= 1e-12 * f,
            "{} {}",
            dy[5],
            want[1]
        );
    }
    // The static part: K^{-1} (M g) = -9.81e-5 m at y.
    let q0 = rotor.system().static_deflection().unwrap();
    assert!((q0[1] + 9.81 * 10.0 / 1e6).abs() < 1e-18);
}

/// `max_rate` bounds the rates of the motion: at least the largest |eigenvalue| of the lateral
/// state matrix that each sidecar gives (numpy's eig of the exported matrices).
#[test]
fn max_rate_bounds_the_largest_eigenvalue() {
    use jeffcott::rotor::{RotorMatrices, SmoothRotor};
    for stem in [
        "rotor_example_1500rpm",
        "rotor_example_with_damping_1200rpm",
    ] {
        let path = |ext: &str| {
            format!(
                "{}/tests/data/rotors/{stem}.{ext}",
                env!("CARGO_MANIFEST_DIR")
            )
        };
        let json: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(path("json")).unwrap()).unwrap();
        let speed = json["speed_rad_s"].as_f64().unwrap();
        let largest = json["largest_eigenvalue_modulus_lateral_rad_s"]
            .as_f64()
            .unwrap();
        let lateral = RotorMatrices::from_ross_mat(path("mat"))
            .unwrap()
            .lateral()
            .unwrap();
        let system = LinearSystem::from_matrices(&lateral, speed).unwrap();
        let x = lateral.x_dof(2).unwrap();
        let rotor = LinearRotor::new(system, [x, x + 1], [0.0; 2]).unwrap();
        let y = rotor.rest_state();
        let free = rotor.max_rate(0.0, &y, 0.0, 0.0).unwrap();
        let contact = rotor.max_rate(0.0, &y, 2.2e6, 0.02).unwrap();
        println!("{stem}: largest |eigenvalue| {largest:.3e}, max_rate {free:.3e} (contact {contact:.3e})");
        assert!(free >= largest, "{free} < {largest}");
        assert!(contact >= free);
    }
}

/// `write_jacobian` is the derivative of `rhs`: against central differences of the vector
/// field (exact for a linear field up to rounding).
#[test]
fn the_linear_jacobian_is_the_derivative_of_rhs() {
    use jeffcott::rotor::SmoothRotor;
    let n = 4;
    let m = DMatrix::from_fn(n, n, |i, j| if i == j { 3.0 } else { 0.2 });
    let k = DMatrix::from_fn(
        n,
        n,
        |i, j| if i == j { 5e3 } else { -30.0 * (i + j) as f64 },
    );
    let d = DMatrix::from_fn(n, n, |i, j| {
        0.5 * (i as f64 - j as f64) + if i == j { 2.0 } else { 0.0 }
    });
    let system = LinearSystem::new(m, d, k, 20.0)
        .unwrap()
        .with_harmonic_force(1, Complex::new(2.0, 1.0))
        .unwrap();
    let rotor = LinearRotor::new(system, [0, 1], [0.0; 2]).unwrap();
    let dim = 2 * n + 2;
    let mut storage = DMatrix::from_element(dim, dim, f64::NAN);
    assert!(rotor.write_jacobian(&mut storage.view_mut((0, 0), (dim, dim))));
    let y = DVector::from_fn(dim, |i, _| 1e-3 * (1.0 + i as f64).sin());
    let (mut plus, mut minus) = (y.clone(), y.clone());
    for j in 0..dim {
        let h = 1e-6;
        plus[j] += h;
        minus[j] -= h;
        let (mut fp, mut fm) = (y.clone(), y.clone());
        rotor.rhs(0.3, &plus, &mut fp);
        rotor.rhs(0.3, &minus, &mut fm);
        plus[j] = y[j];
        minus[j] = y[j];
        for i in 0..2 * n {
            let fd = (fp[i] - fm[i]) / (2.0 * h);
            let scale = storage[(i, j)].abs().max(1.0);
            assert!(
                (fd - storage[(i, j)]).abs() <= 1e-6 * scale,
                "({i}, {j}): {fd} {}",
                storage[(i, j)]
            );
        }
    }
    assert!(storage.rows(2 * n, 2).iter().all(|&v| v == 0.0));
    let mut wrong = DMatrix::zeros(3, 3);
    assert!(!rotor.write_jacobian(&mut wrong.view_mut((0, 0), (3, 3))));
}

/// Issue 31, finding 4: matrices checked at the door, naming the entry. A non-symmetric or
/// indefinite mass (a negative mass on a reduction's boundary DOF) and a gyroscopic matrix
/// that is not skew-symmetric are refused; cross-coupled (non-symmetric) stiffness and damping
/// are accepted.
#[test]
fn bad_matrices_are_refused_naming_the_entry() {
    let n = 4;
    let eye = DMatrix::<f64>::identity(n, n);
    let mut k = DMatrix::<f64>::from_fn(n, n, |i, j| match i.abs_diff(j) {
        0 => 2e6,
        1 => -1e6,
        _ => 0.0,
    });
    // A cross-coupled bearing: K and C not symmetric, accepted.
    k[(0, 1)] += 3e5;
    k[(1, 0)] -= 3e5;
    let mut c = &eye * 10.0;
    c[(2, 3)] = 4.0;
    assert!(LinearSystem::new(eye.clone(), c.clone(), k.clone(), 100.0).is_ok());
    // M not symmetric: the first pair named, (row, col) below the diagonal.
    let mut m = eye.clone();
    m[(2, 1)] = 0.1;
    let err = LinearSystem::new(m.clone(), c.clone(), k.clone(), 100.0).unwrap_err();
    assert_eq!(
        err,
        RotorError::NotSymmetric {
            matrix: "M",
            row: 2,
            col: 1,
            value: 0.1,
            transposed: 0.0
        }
    );
    assert!(err.to_string().contains("(2, 1)"), "{err}");
    // Rounding-level asymmetry (an assembled matrix) is accepted.
    let mut m = eye.clone();
    m[(2, 1)] = 1e-14;
    m[(1, 2)] = 1e-14 * (1.0 + 1e-12);
    assert!(LinearSystem::new(m, c.clone(), k.clone(), 100.0).is_ok());
    // A negative mass at DOF 3: not positive definite, the DOF named.
    let mut m = eye.clone();
    m[(3, 3)] = -0.5;
    let err = LinearSystem::new(m.clone(), c.clone(), k.clone(), 100.0).unwrap_err();
    assert!(
        matches!(err, RotorError::MassNotPositiveDefinite { eigenvalue, dof: 3 } if eigenvalue == -0.5),
        "{err}"
    );
    // The same on a reduction's boundary DOF (before: accepted, only M_ii was checked).
    let err = CraigBampton::new(&m, &k, &[3], ModeSelection::Count(1)).unwrap_err();
    assert!(
        matches!(err, RotorError::MassNotPositiveDefinite { dof: 3, .. }),
        "{err}"
    );
    let mut skewed = eye.clone();
    skewed[(0, 3)] = 0.2;
    assert!(matches!(
        CraigBampton::new(&skewed, &k, &[0, 1], ModeSelection::Count(1)),
        Err(RotorError::NotSymmetric { row: 3, col: 0, .. })
    ));
    // G must be skew-symmetric (gyroscopic moments do no work).
    let mut g = DMatrix::<f64>::zeros(n, n);
    g[(2, 3)] = 0.7;
    g[(3, 2)] = -0.7;
    let ok = RotorMatrices::new(
        eye.clone(),
        c.clone(),
        g.clone(),
        k.clone(),
        DofLayout::Lateral4,
    );
    assert!(ok.is_ok(), "{ok:?}");
    g[(3, 2)] = 0.7;
    let err = RotorMatrices::new(eye.clone(), c, g, k, DofLayout::Lateral4).unwrap_err();
    assert_eq!(
        err,
        RotorError::NotSkewSymmetric {
            row: 3,
            col: 2,
            value: 0.7,
            transposed: 0.7
        }
    );
}
