//! Craig-Bampton reduction of the ROSS rotors with the ring's node kept physical.
//!
//! Truths: an invertible change of coordinates changes no solution (all modes kept); a static
//! solution lying in the basis is reproduced exactly by the Galerkin projection (the
//! constraint modes span the static response to boundary forces); ROSS's own unbalance
//! responses (the sidecars' `linear_check`); the generalized eigenvalues of the interior
//! computed another way ($M^{-1/2} K M^{-1/2}$ by the eigenvectors of $M$, not its Cholesky
//! factor).

use jeffcott::nalgebra::{Complex, DMatrix, DVector, SymmetricEigen};
use jeffcott::rotor::{CraigBampton, LinearSystem, ModeSelection, RotorError, RotorMatrices};

/// One of the shared rotors with its unbalance case (the sidecar's `linear_check`) and the
/// ring's node.
pub struct Case {
    pub file: &'static str,
    pub ring_node: usize,
    pub unbalance_node: usize,
    pub me: f64,
    pub phase: f64,
    pub speed: f64,
}

pub const CASES: [Case; 2] = [
    Case {
        file: "rotor_example_with_damping_1200rpm",
        ring_node: 12,
        unbalance_node: 12,
        me: 2e-3,
        phase: -std::f64::consts::FRAC_PI_2,
        speed: 125.66370614359172,
    },
    Case {
        file: "rotor_example_1500rpm",
        ring_node: 4,
        unbalance_node: 2,
        me: 1e-4,
        phase: 0.0,
        speed: 157.07963267948966,
    },
];

fn data(name: &str) -> String {
    format!("{}/tests/data/rotors/{name}", env!("CARGO_MANIFEST_DIR"))
}

impl Case {
    /// The lateral rotor.
    pub fn rotor(&self) -> RotorMatrices {
        RotorMatrices::from_ross_mat(data(&format!("{}.mat", self.file)))
            .unwrap()
            .lateral()
            .unwrap()
    }

    /// $\hat F$: $F_x = m e\thinspace\Omega^2 e^{i\varphi}$, $F_y = -i F_x$ at the unbalance
    /// node (shared README's convention, lateral layout).
    pub fn force(&self, dofs: usize) -> DVector<Complex<f64>> {
        let fx = Complex::from_polar(self.me * self.speed * self.speed, self.phase);
        let mut f = DVector::zeros(dofs);
        f[4 * self.unbalance_node] = fx;
        f[4 * self.unbalance_node + 1] = -Complex::<f64>::i() * fx;
        f
    }

    /// ROSS's response at the ring node (the sidecar's `all_nodes_x_y`), `[X_x, X_y]`.
    fn ross_response(&self) -> [Complex<f64>; 2] {
        let text = std::fs::read_to_string(data(&format!("{}.json", self.file))).unwrap();
        let json: serde_json::Value = serde_json::from_str(&text).unwrap();
        let node = &json["linear_check"]["all_nodes_x_y"][self.ring_node];
        let c =
            |v: &serde_json::Value| Complex::new(v[0].as_f64().unwrap(), v[1].as_f64().unwrap());
        [c(&node[0]), c(&node[1])]
    }
}

/// The full system at speed `w` under the harmonic force `f` (no constant force).
pub fn system(rotor: &RotorMatrices, f: &DVector<Complex<f64>>, w: f64) -> LinearSystem {
    let n = rotor.dofs();
    let (m, k) = (rotor.mass().clone(), rotor.stiffness().clone());
    LinearSystem::from_parts(m, damping(rotor, w), k, w, f.clone(), DVector::zeros(n)).unwrap()
}

/// $D = C + \Omega G$.
pub fn damping(rotor: &RotorMatrices, speed: f64) -> DMatrix<f64> {
    rotor.damping() + rotor.gyroscopic() * speed
}

/// Solves $(K - \Omega^2 M + i\Omega D) X = F$ (complex LU).
pub fn steady(
    m: &DMatrix<f64>,
    d: &DMatrix<f64>,
    k: &DMatrix<f64>,
    f: &DVector<Complex<f64>>,
    w: f64,
) -> DVector<Complex<f64>> {
    let a = DMatrix::from_fn(m.nrows(), m.ncols(), |r, c| {
        Complex::new(k[(r, c)] - w * w * m[(r, c)], w * d[(r, c)])
    });
    a.lu().solve(f).unwrap()
}

fn rel(a: &DVector<Complex<f64>>, b: &DVector<Complex<f64>>) -> f64 {
    (a - b).norm() / b.norm()
}

/// The interior DOFs' count of a node-boundary reduction.
fn interior(rotor: &RotorMatrices) -> usize {
    rotor.dofs() - 2
}

/// "Equal up to rounding" for the 204-DOF rotor: its dynamic stiffness at speed has the
/// condition number 2.3e7 (1.3e7 at rest; SVD, measured), so each solve alone may be off by
/// kappa eps = 5e-9; measured 1.0e-11 (all modes, all DOFs) and 1.3e-12 (static), against
/// 4.9e-8 with one mode of 134 short. The 42-DOF rotor (kappa 2.3e3) stays below 2e-14.
const EXACT: f64 = 1e-10;

/// With every fixed-interface mode kept, $T$ is square and invertible: the reduced steady
/// response is the full one in other coordinates, at every DOF.
fn assert_all_modes_exact(rotor: &RotorMatrices, node: usize, f: &DVector<Complex<f64>>, w: f64) {
    let n = rotor.dofs();
    let d = damping(rotor, w);
    let full = steady(rotor.mass(), &d, rotor.stiffness(), f, w);
    let x = 4 * node;
    for modes in [
        ModeSelection::Count(interior(rotor)),
        ModeSelection::Below(f64::INFINITY),
    ] {
        let cb = CraigBampton::at_node(rotor, node, modes).unwrap();
        assert_eq!(cb.reduced_dofs(), n, "node {node}: T is square");
        assert_eq!(cb.boundary(), &[x, x + 1]);
        assert_eq!(
            (cb.boundary_index(x), cb.boundary_index(x + 1)),
            (Some(0), Some(1))
        );
        let [mr, dr, kr] = [rotor.mass(), &d, rotor.stiffness()].map(|a| cb.project(a).unwrap());
        let q = steady(&mr, &dr, &kr, &cb.project_force(f).unwrap(), w);
        let e = rel(&cb.expand(&q).unwrap(), &full);
        assert!(e < EXACT, "node {node}: all DOFs off by {e:e}");
        let err = cb.response_error(&system(rotor, f, w)).unwrap();
        assert!(err.relative < EXACT, "node {node}: {err:?}");
        let amplitude = (full[x].norm_sqr() + full[x + 1].norm_sqr()).sqrt();
        assert!(
            (err.amplitude - amplitude).abs() <= EXACT * amplitude,
            "{err:?} {amplitude}"
        );
    }
}

#[test]
fn all_modes_kept_reproduce_the_full_response_and_ross() {
    for case in &CASES {
        let rotor = case.rotor();
        let f = case.force(rotor.dofs());
        let d = damping(&rotor, case.speed);
        let full = steady(rotor.mass(), &d, rotor.stiffness(), &f, case.speed);
        // The direct solve is ROSS's answer (shared README: 3e-13 at node 12, 2e-15 at node 4).
        let x = 4 * case.ring_node;
        let at_node = DVector::from_vec(vec![full[x], full[x + 1]]);
        let ross = DVector::from_vec(case.ross_response().to_vec());
        assert!(rel(&at_node, &ross) < 1e-10, "{}", case.file);
        // This test's F_hat is LinearSystem's unbalance (the shared README's convention).
        let unbalance = LinearSystem::from_matrices(&rotor, case.speed)
            .unwrap()
            .with_unbalance(rotor.layout(), case.unbalance_node, case.me, case.phase)
            .unwrap();
        assert!(rel(unbalance.harmonic_force(), &f) < 1e-15);
        assert_all_modes_exact(&rotor, case.ring_node, &f, case.speed);
    }
    // A non-symmetric K: the basis comes from its symmetric part, the projection from K.
    let case = &CASES[0];
    let rotor = cross_coupled(&case.rotor());
    assert_all_modes_exact(
        &rotor,
        case.ring_node,
        &case.force(rotor.dofs()),
        case.speed,
    );
}

/// The cross-coupling a fluid-film bearing adds ($k_{xy} = -k_{yx}$), at the 204-DOF rotor's
/// first bearing (node 4): $K$ is then not symmetric.
fn cross_coupled(rotor: &RotorMatrices) -> RotorMatrices {
    let mut k = rotor.stiffness().clone();
    k[(16, 17)] += 4e5;
    k[(17, 16)] -= 4e5;
    RotorMatrices::new(
        rotor.mass().clone(),
        rotor.damping().clone(),
        rotor.gyroscopic().clone(),
        k,
        rotor.layout(),
    )
    .unwrap()
}

#[test]
fn a_static_boundary_force_is_reproduced_exactly_at_any_mode_count() {
    let base = CASES[0].rotor();
    let rotors = [CASES[0].rotor(), CASES[1].rotor(), cross_coupled(&base)];
    for (rotor, node) in rotors.iter().zip([12, 4, 12]) {
        let x = 4 * node;
        let mut f = DVector::<f64>::zeros(rotor.dofs());
        f[x] = 1.3e3;
        f[x + 1] = -2.1e3;
        let k = rotor.stiffness();
        let full = k.clone().lu().solve(&f).unwrap();
        for count in [0, 8] {
            let cb = CraigBampton::at_node(rotor, node, ModeSelection::Count(count)).unwrap();
            let kr = cb.project(k).unwrap();
            let q = kr.lu().solve(&cb.project_force(&f).unwrap()).unwrap();
            let e = (cb.expand(&q).unwrap() - &full).norm() / full.norm();
            assert!(e < EXACT, "node {node}, {count} modes: {e:e}");
            // The same through the reduced LinearSystem's static deflection.
            let zero = DVector::zeros(rotor.dofs());
            let full_system = system(rotor, &zero, 1.0);
            let loaded = LinearSystem::from_parts(
                full_system.mass().clone(),
                full_system.damping().clone(),
                k.clone(),
                1.0,
                zero,
                f.clone(),
            )
            .unwrap();
            let q = cb.reduce(&loaded).unwrap().static_deflection().unwrap();
            let e = (cb.expand(&q).unwrap() - &full).norm() / full.norm();
            assert!(
                e < EXACT,
                "node {node}, {count} modes, reduced system: {e:e}"
            );
        }
    }
}

/// Relative errors at the ring node for these mode counts.
pub const COUNTS: [usize; 8] = [0, 4, 8, 12, 16, 24, 32, 48];

#[test]
fn the_error_falls_as_modes_are_added() {
    for case in &CASES {
        let rotor = case.rotor();
        let f = case.force(rotor.dofs());
        let counts: Vec<usize> = COUNTS
            .into_iter()
            .filter(|&c| c <= interior(&rotor))
            .collect();
        let errors: Vec<f64> = counts
            .iter()
            .map(|&c| {
                let cb =
                    CraigBampton::at_node(&rotor, case.ring_node, ModeSelection::Count(c)).unwrap();
                cb.response_error(&system(&rotor, &f, case.speed))
                    .unwrap()
                    .relative
            })
            .collect();
        println!("{}: {counts:?} modes: {errors:?}", case.file);
        // Guyan alone misses the dynamics of the running speed by a visible amount.
        assert!(errors[0] > 1e-3, "{}: {errors:?}", case.file);
        // Not monotone mode by mode (a Galerkin projection of the indefinite K - W^2 M + i W D
        // is not a best approximation: the 42-DOF rotor's error rises from 8 to 12 modes), but
        // doubling the modes always helps, and the last count is far below Guyan.
        for (i, &c) in counts.iter().enumerate().skip(1) {
            if let Some(j) = counts.iter().position(|&d| d == 2 * c) {
                assert!(
                    errors[j] < errors[i],
                    "{}: {counts:?}: {errors:?}",
                    case.file
                );
            }
        }
        assert!(
            *errors.last().unwrap() < 1e-6 * errors[0],
            "{}: {errors:?}",
            case.file
        );
    }
}

/// The generalized eigenvalues of $(K_{ii}, M_{ii})$ (symmetric parts), increasing, by
/// $M^{-1/2} K M^{-1/2}$ with $M^{-1/2}$ from $M$'s eigenvectors.
fn interior_eigenvalues(rotor: &RotorMatrices, boundary: &[usize]) -> Vec<f64> {
    let keep: Vec<usize> = (0..rotor.dofs())
        .filter(|i| !boundary.contains(i))
        .collect();
    let pick = |a: &DMatrix<f64>| {
        let s = (a + a.transpose()) * 0.5;
        DMatrix::from_fn(keep.len(), keep.len(), |r, c| s[(keep[r], keep[c])])
    };
    let m = SymmetricEigen::new(pick(rotor.mass()));
    let inv_sqrt = &m.eigenvectors
        * DMatrix::from_diagonal(&m.eigenvalues.map(|v| 1.0 / v.sqrt()))
        * m.eigenvectors.transpose();
    let a = &inv_sqrt * pick(rotor.stiffness()) * &inv_sqrt;
    let mut v: Vec<f64> = SymmetricEigen::new((&a + a.transpose()) * 0.5)
        .eigenvalues
        .iter()
        .copied()
        .collect();
    v.sort_by(f64::total_cmp);
    v
}

#[test]
fn the_kept_frequencies_are_the_fixed_interface_eigenvalues() {
    let base = CASES[0].rotor();
    let rotors = [CASES[0].rotor(), CASES[1].rotor(), cross_coupled(&base)];
    for (rotor, node) in rotors.iter().zip([12, 4, 12]) {
        let all =
            CraigBampton::at_node(rotor, node, ModeSelection::Count(interior(rotor))).unwrap();
        let want = interior_eigenvalues(rotor, all.boundary());
        let top = want.last().unwrap();
        for (k, (w, l)) in all.frequencies().iter().zip(&want).enumerate() {
            let tol = 1e-8 * l + 1e-12 * top;
            assert!(
                (w * w - l).abs() <= tol,
                "node {node}, mode {k}: {} vs {l}",
                w * w
            );
        }
        // Each mode solves K_ii phi = omega^2 M_ii phi (symmetric parts) on the interior rows, to
        // the rounding of a symmetric eigensolver, eps (omega_max / omega)^2: 3e-10 for the
        // 204-DOF rotor's first mode (measured 4.9e-11).
        let inner: Vec<usize> = (0..rotor.dofs())
            .filter(|i| !all.boundary().contains(i))
            .collect();
        let sym = |a: &DMatrix<f64>| {
            let s = (a + a.transpose()) * 0.5;
            DMatrix::from_fn(inner.len(), inner.len(), |r, c| s[(inner[r], inner[c])])
        };
        let (k_ii, m_ii) = (sym(rotor.stiffness()), sym(rotor.mass()));
        for (k, w) in all.frequencies().iter().enumerate() {
            let col = all.basis().column(2 + k);
            let phi = DVector::from_fn(inner.len(), |r, _| col[inner[r]]);
            let (kp, mp) = (&k_ii * &phi, &m_ii * &phi * (w * w));
            let res = (&kp - &mp).norm() / kp.norm();
            assert!(res < 1e-9, "node {node}, mode {k}: residual {res:e}");
        }
        // Mass-normalised and M-orthogonal: the modal block of T^T M T is the identity.
        let mr = all.project(rotor.mass()).unwrap();
        let modal = mr.view((2, 2), (all.modes(), all.modes()));
        let off = (modal - DMatrix::<f64>::identity(all.modes(), all.modes())).amax();
        assert!(off < 1e-10, "node {node}: Phi^T M Phi off I by {off:e}");
        // A cut-off keeps exactly the modes below it.
        let cut = 0.5 * (all.frequencies()[9] + all.frequencies()[10]);
        let below = CraigBampton::at_node(rotor, node, ModeSelection::Below(cut)).unwrap();
        assert_eq!(below.modes(), 10);
        assert_eq!(below.frequencies(), &all.frequencies()[..10]);
        assert_eq!(below.basis(), &all.basis().columns(0, 12).into_owned());
    }
}

#[test]
fn the_sweep_reports_the_worst_speed() {
    let case = &CASES[0];
    let rotor = case.rotor();
    let f = case.force(rotor.dofs());
    let cb = CraigBampton::at_node(&rotor, case.ring_node, ModeSelection::Count(8)).unwrap();
    let speeds = [50.0, case.speed, 180.0, 400.0];
    let each: Vec<f64> = speeds
        .iter()
        .map(|&w| cb.response_error(&system(&rotor, &f, w)).unwrap().relative)
        .collect();
    let worst = cb.response_error_sweep(&rotor, &f, &speeds).unwrap();
    let (i, max) = each.iter().enumerate().fold(
        (0, 0.0),
        |(j, m), (i, &e)| if e > m { (i, e) } else { (j, m) },
    );
    assert_eq!(worst.speed, speeds[i]);
    // The worst is at 180 rad/s, by the first critical (181.5 rad/s): there the dynamic
    // stiffness's condition number is 2.1e8 (SVD, measured), so a response is known to
    // kappa eps = 5e-8 of itself, and so is an error measured against it (measured
    // differences below: up to 1.8e-10).
    let rounding = 1e-8;
    // The sweep projects C and G apart, not C + W G: the same up to rounding.
    assert!(
        (worst.relative - max).abs() <= rounding,
        "{worst:?} vs {max}"
    );
    // The relative error does not depend on the force's scale (an unbalance's W^2).
    let scaled = cb
        .response_error_sweep(&rotor, &(&f * Complex::new(3.0, 0.0)), &speeds)
        .unwrap();
    assert!(
        (scaled.relative - worst.relative).abs() <= rounding,
        "{scaled:?} {worst:?}"
    );
}

#[test]
fn bad_input_is_a_clear_error() {
    let rotor = CASES[1].rotor();
    let n = rotor.dofs();
    let new = |b: &[usize], m| CraigBampton::from_rotor(&rotor, b, m).map(|_| ());
    let c0 = ModeSelection::Count(0);
    assert_eq!(
        new(&[0, n], c0),
        Err(RotorError::DofOutOfRange {
            field: "boundary DOF",
            index: n,
            dofs: n
        })
    );
    assert_eq!(
        new(&[3, 3], c0),
        Err(RotorError::DuplicateBoundaryDof { dof: 3 })
    );
    let many = ModeSelection::Count(n - 1);
    assert_eq!(
        new(&[0, 1], many),
        Err(RotorError::ModeCount {
            requested: n - 1,
            available: n - 2
        })
    );
    assert!(matches!(
        new(&[0], ModeSelection::Below(f64::NAN)),
        Err(RotorError::ModeCutoff { cutoff }) if cutoff.is_nan()
    ));
    assert_eq!(
        new(&[0], ModeSelection::Below(-1.0)),
        Err(RotorError::ModeCutoff { cutoff: -1.0 })
    );
    assert_eq!(
        CraigBampton::at_node(&rotor, 7, c0),
        Err(RotorError::NodeOutOfRange { node: 7, nodes: 7 })
    );
    // ROSS's 6-DOF export: the axial and torsional DOFs have no stiffness to ground.
    let full = RotorMatrices::from_ross_mat(data("rotor_example_1500rpm.mat")).unwrap();
    match CraigBampton::at_node(&full, 4, c0) {
        Err(RotorError::InteriorStiffness { eigenvalue }) => assert!(eigenvalue.abs() < 1e-3),
        other => panic!("{other:?}"),
    }
    // A massless interior DOF: the mass as a whole is refused, naming the DOF.
    let mut m = rotor.mass().clone();
    m.row_mut(5).fill(0.0);
    m.column_mut(5).fill(0.0);
    assert!(matches!(
        CraigBampton::new(&m, rotor.stiffness(), &[0, 1], c0),
        Err(RotorError::MassNotPositiveDefinite { dof: 5, .. })
    ));
    // Finite entries whose products overflow.
    let huge = rotor.stiffness() * 1e300;
    assert!(matches!(
        CraigBampton::new(rotor.mass(), &huge, &[0, 1], c0),
        Err(RotorError::InteriorStiffness { eigenvalue }) if eigenvalue.is_nan()
    ));
    let mut k = rotor.stiffness().clone();
    k[(2, 3)] = f64::NAN;
    assert!(matches!(
        CraigBampton::new(rotor.mass(), &k, &[0, 1], c0),
        Err(RotorError::MatrixEntry {
            matrix: "K",
            row: 2,
            col: 3,
            ..
        })
    ));
    let cb = CraigBampton::at_node(&rotor, 4, ModeSelection::Count(4)).unwrap();
    assert!(matches!(
        cb.project(&DMatrix::zeros(n, n - 1)),
        Err(RotorError::MatrixShape {
            rows: 28,
            cols: 27,
            expected: 28,
            ..
        })
    ));
    assert_eq!(
        cb.project_force(&DVector::<f64>::zeros(n + 1)),
        Err(RotorError::VectorLength {
            vector: "f",
            len: n + 1,
            expected: n
        })
    );
    assert_eq!(
        cb.expand(&DVector::<f64>::zeros(n)),
        Err(RotorError::VectorLength {
            vector: "q",
            len: n,
            expected: 6
        })
    );
    let f = CASES[1].force(n);
    let other = CASES[0].rotor();
    assert!(matches!(
        cb.response_error(&system(&other, &CASES[0].force(other.dofs()), 100.0)),
        Err(RotorError::MatrixShape {
            matrix: "projected",
            rows: 136,
            ..
        })
    ));
    assert_eq!(
        cb.response_error_sweep(&rotor, &f, &[100.0, 0.0]),
        Err(RotorError::Speed { value: 0.0 })
    );
    assert!(matches!(
        cb.response_error_sweep(&rotor, &f, &[]),
        Err(RotorError::Speed { value }) if value.is_nan()
    ));
    // An undamped two-mass system at its (fixed-interface and full) natural frequency 1.
    let toy = CraigBampton::new(
        &DMatrix::identity(2, 2),
        &DMatrix::from_diagonal(&DVector::from_vec(vec![4.0, 1.0])),
        &[0],
        ModeSelection::Count(1),
    )
    .unwrap();
    let f2 = DVector::from_element(2, Complex::new(1.0, 0.0));
    let k2 = DMatrix::from_diagonal(&DVector::from_vec(vec![4.0, 1.0]));
    let undamped = LinearSystem::from_parts(
        DMatrix::identity(2, 2),
        DMatrix::zeros(2, 2),
        k2,
        1.0,
        f2,
        DVector::zeros(2),
    )
    .unwrap();
    let at_resonance = toy.response_error(&undamped);
    assert!(matches!(
        at_resonance,
        Err(RotorError::Singular {
            matrix: "K - W^2 M + i W D",
            ..
        })
    ));
}

#[test]
fn fewest_modes_is_the_first_count_within_the_tolerance() {
    for case in &CASES {
        let rotor = case.rotor();
        let f = case.force(rotor.dofs());
        let x = 4 * case.ring_node;
        let speeds = [0.5 * case.speed, case.speed];
        for tolerance in [1e-3, 1e-6] {
            let (cb, worst) =
                CraigBampton::fewest_modes(&rotor, &[x, x + 1], &f, &speeds, tolerance).unwrap();
            assert!(worst.relative <= tolerance);
            // Checked through the public single-count path, built anew for every count.
            let sweep = |count| {
                CraigBampton::at_node(&rotor, case.ring_node, ModeSelection::Count(count))
                    .unwrap()
                    .response_error_sweep(&rotor, &f, &speeds)
                    .unwrap()
            };
            // The same up to rounding: the worst error is projected with all modes and cut to a
            // leading block there, with the kept ones here (another summation order); the
            // response's rounding, about 1e-11 of it (all modes kept), bounds the difference.
            let again = sweep(cb.modes());
            assert!(
                (again.relative - worst.relative).abs() <= EXACT,
                "{again:?} {worst:?}"
            );
            for fewer in 0..cb.modes() {
                assert!(sweep(fewer).relative > tolerance, "{}: {fewer}", case.file);
            }
            println!("{}: {tolerance:e} needs {} modes", case.file, cb.modes());
        }
    }
    // The truncation of a reduction is the reduction with fewer modes.
    let rotor = CASES[0].rotor();
    let all = CraigBampton::at_node(&rotor, 12, ModeSelection::Count(20)).unwrap();
    let eight = CraigBampton::at_node(&rotor, 12, ModeSelection::Count(8)).unwrap();
    assert_eq!(all.truncated(8).unwrap(), eight);
    assert_eq!(
        all.truncated(21),
        Err(RotorError::ModeCount {
            requested: 21,
            available: 20
        })
    );
    // Nothing beats rounding.
    let f = CASES[0].force(rotor.dofs());
    let none = CraigBampton::fewest_modes(&rotor, &[48, 49], &f, &[CASES[0].speed], 0.0);
    match none {
        Err(RotorError::ModeTolerance { tolerance, best }) => {
            assert_eq!(tolerance, 0.0);
            assert!(best > 0.0 && best < EXACT, "{best}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn every_dof_or_none_on_the_boundary() {
    // Three unit masses between walls (springs 1): all on the boundary is the identity basis;
    // none is a modal basis, and with all modes the steady response is the full one.
    let m = DMatrix::<f64>::identity(3, 3);
    let k = DMatrix::from_row_slice(3, 3, &[2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0]);
    let all = CraigBampton::new(&m, &k, &[2, 0, 1], ModeSelection::Below(f64::INFINITY)).unwrap();
    assert_eq!(all.modes(), 0);
    assert_eq!(all.basis()[(2, 0)], 1.0);
    assert_eq!(all.basis().abs().sum(), 3.0);
    let none = CraigBampton::new(&m, &k, &[], ModeSelection::Count(3)).unwrap();
    // The chain's frequencies: 2 sin(j pi / 8), j = 1, 2, 3.
    for (j, w) in none.frequencies().iter().enumerate() {
        let want = 2.0 * ((j + 1) as f64 * std::f64::consts::PI / 8.0).sin();
        assert!((w - want).abs() < 1e-14, "{w} vs {want}");
    }
    let f = DVector::from_vec(vec![
        Complex::new(1.0, 0.0),
        Complex::new(0.0, -1.0),
        Complex::new(0.5, 0.0),
    ]);
    let d = DMatrix::identity(3, 3) * 0.1;
    let full = steady(&m, &d, &k, &f, 1.3);
    let [mr, dr, kr] = [&m, &d, &k].map(|a| none.project(a).unwrap());
    let q = steady(&mr, &dr, &kr, &none.project_force(&f).unwrap(), 1.3);
    assert!(rel(&none.expand(&q).unwrap(), &full) < 1e-14);
    // Nothing kept at all: a clear error, not an empty system (nalgebra panics on those).
    let empty = CraigBampton::new(&m, &k, &[], ModeSelection::Count(0));
    assert_eq!(empty.unwrap_err(), RotorError::EmptyReduction);
}
