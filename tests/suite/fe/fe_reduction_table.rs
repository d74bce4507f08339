//! The reduction's report (not a check): the relative error of the unbalance response at the
//! ring node against the number of fixed-interface modes, the highest kept frequency, the worst
//! error over a speed sweep, and how stiff the reduced model is (the largest and smallest
//! |eigenvalue| of its first-order state matrix). Run with
//! `cargo test --test suite fe::fe_reduction_table -- --ignored --nocapture`.

use jeffcott::nalgebra::DMatrix;
use jeffcott::rotor::{CraigBampton, ModeSelection};

use super::fe_reduction::{damping, system, CASES, COUNTS};

/// Smallest and largest |eigenvalue| of $[0, I; -M^{-1} K, -M^{-1} D]$.
fn state_span(m: &DMatrix<f64>, d: &DMatrix<f64>, k: &DMatrix<f64>) -> (f64, f64) {
    let n = m.nrows();
    let lu = m.clone().lu();
    let (mk, md) = (lu.solve(k).unwrap(), lu.solve(d).unwrap());
    let mut a = DMatrix::zeros(2 * n, 2 * n);
    a.view_mut((0, n), (n, n)).fill_with_identity();
    a.view_mut((n, 0), (n, n)).copy_from(&(-mk));
    a.view_mut((n, n), (n, n)).copy_from(&(-md));
    let moduli: Vec<f64> = a.complex_eigenvalues().iter().map(|l| l.norm()).collect();
    let lo = moduli.iter().copied().fold(f64::INFINITY, f64::min);
    let hi = moduli.iter().copied().fold(0.0, f64::max);
    (lo, hi)
}

#[test]
#[ignore = "a report: run with --ignored --nocapture"]
fn fe_reduction_table() {
    for case in &CASES {
        let rotor = case.rotor();
        let w = case.speed;
        let (f, d) = (case.force(rotor.dofs()), damping(&rotor, w));
        let (lo, hi) = state_span(rotor.mass(), &d, rotor.stiffness());
        println!(
            "\n{} (ring node {}, W = {w} rad/s)",
            case.file, case.ring_node
        );
        println!(
            "full: {} DOF, state |eig| {lo:.3e} .. {hi:.3e} rad/s",
            rotor.dofs()
        );
        println!("modes | rel. error at W | worst rel. error 0.1 W..2 W (39 speeds) | highest kept (rad/s) | reduced state |eig| max (rad/s)");
        let speeds: Vec<f64> = (2..=40).map(|i| 0.05 * i as f64 * w).collect();
        let available = rotor.dofs() - 2;
        for count in COUNTS
            .into_iter()
            .filter(|&c| c <= available)
            .chain([available])
        {
            let cb =
                CraigBampton::at_node(&rotor, case.ring_node, ModeSelection::Count(count)).unwrap();
            let e = cb.response_error(&system(&rotor, &f, w)).unwrap();
            let sweep = cb.response_error_sweep(&rotor, &f, &speeds).unwrap();
            let [mr, dr, kr] =
                [rotor.mass(), &d, rotor.stiffness()].map(|a| cb.project(a).unwrap());
            let (_, hi) = state_span(&mr, &dr, &kr);
            let top = cb
                .frequencies()
                .last()
                .map_or("-".into(), |v| format!("{v:.4e}"));
            println!(
                "{count:>5} | {:.2e} | {:.2e} at {:.1} | {top} | {hi:.3e}",
                e.relative, sweep.relative, sweep.speed
            );
        }
        let x = 4 * case.ring_node;
        for tolerance in [1e-2, 1e-3, 1e-4, 1e-6] {
            let fewest = |speeds: &[f64]| {
                CraigBampton::fewest_modes(&rotor, &[x, x + 1], &f, speeds, tolerance)
                    .map_or("-".into(), |(cb, _)| cb.modes().to_string())
            };
            println!(
                "fewest modes for {tolerance:e}: at W {}, over the sweep {}",
                fewest(&[w]),
                fewest(&speeds)
            );
        }
    }
}
