//! The analytic Jacobian of a linear rotor on a preloaded ring (`RotorModel::jacobian` of
//! `RingedRotor<LinearRotor>` and of `RingedRotor<ModalRotor>`, which Radau5 uses) against
//! central differences of the model's own right-hand side, in free flight and in every contact
//! regime the states below reach.

use jeffcott::hybrid::{RotorModel, Variational, Workspace};
use jeffcott::nalgebra::{Complex, DMatrix, DVector, Dyn};
use jeffcott::ring::{RingAxis, RingMode, SnubberRing};
use jeffcott::rotor::{LinearRotor, LinearSystem, ModalRotor, RingedRotor, SmoothRotor};

/// An 8-DOF rotor with the station at DOFs 2, 3 (gap 1).
fn rotor() -> LinearRotor {
    let n = 8;
    let m = DMatrix::from_fn(n, n, |i, j| if i == j { 2.0 } else { 0.1 });
    let k = DMatrix::from_fn(n, n, |i, j| if i == j { 50.0 } else { -2.0 });
    let system = LinearSystem::new(m, k.scale(1e-2), k, 5.0)
        .unwrap()
        .with_harmonic_force(2, Complex::new(1.0, -0.5))
        .unwrap();
    LinearRotor::new(system, [2, 3], [0.0, 0.0]).unwrap()
}

/// The anisotropic preloaded ring of the tests.
pub(super) fn ring() -> SnubberRing {
    SnubberRing::new(
        RingAxis::new(30.0, 0.15),
        RingAxis::new(60.0, 0.05),
        0.05,
        1.0,
    )
    .unwrap()
}

/// [`rotor`] on [`ring`].
fn model() -> RingedRotor<LinearRotor> {
    rotor().ringed(ring()).unwrap()
}

/// A state with the station at `r` and the rest of the state of order one.
fn state(r: [f64; 2], seed: usize) -> DVector<f64> {
    let mut y = DVector::from_fn(18, |i, _| 0.3 * ((i * 7 + seed * 3) as f64).sin());
    y[2] = r[0];
    y[3] = r[1];
    y
}

/// Checks `model`'s Jacobian against central differences of its right-hand side at the
/// states `state(r, seed)` (physical, `[q, q', s]`) carried to the model's coordinates by
/// `coordinates`, over depths and angles of the station that reach free flight and the
/// contact regimes; returns the regimes checked.
pub(super) fn check_jacobian<R: SmoothRotor<Dim = Dyn>>(
    model: &RingedRotor<R>,
    coordinates: impl Fn(DVector<f64>) -> DVector<f64>,
) -> Vec<u8> {
    let cache = model.new_cache();
    let dim = model.dim().0;
    let slots = model.rotor().ring_slots();
    let t = 0.37;
    let mut regimes = Vec::new();
    let mut checked = 0;
    for (seed, depth) in [0.5, 1.01, 1.05, 1.15, 1.3, 1.6].into_iter().enumerate() {
        for a in 0..16 {
            let angle = 0.1 + a as f64 * std::f64::consts::TAU / 16.0;
            let mut y = coordinates(state([depth * angle.cos(), depth * angle.sin()], seed + a));
            model.make_consistent(&mut y).unwrap();
            let Ok(mode) = model.initial_mode(t, &y) else {
                continue;
            };
            let mut jac = DMatrix::<f64>::zeros(dim, dim);
            let mut view = jac.view_mut((0, 0), (dim, dim));
            assert!(model.jacobian(mode, t, &y, &mut view, &cache));
            let (mut plus, mut minus) = (y.clone(), y.clone());
            let (mut fp, mut fm) = (y.clone(), y.clone());
            let mut fd = DMatrix::<f64>::zeros(dim, dim);
            for j in 0..dim {
                let h = 1e-6 * (1.0 + y[j].abs());
                plus[j] += h;
                minus[j] -= h;
                model.rhs(mode, t, &plus, &mut fp, &cache);
                model.rhs(mode, t, &minus, &mut fm, &cache);
                plus[j] = y[j];
                minus[j] = y[j];
                fd.set_column(j, &((&fp - &fm) / (2.0 * h)));
            }
            let big = fd.amax();
            for i in (0..dim).filter(|i| !slots.contains(i)) {
                for j in 0..dim {
                    let (got, want) = (jac[(i, j)], fd[(i, j)]);
                    assert!(
                        (got - want).abs() <= 1e-7 * big + 1e-6 * want.abs(),
                        "mode {mode:?}, r at depth {depth}, angle {angle}: J[{i}, {j}] = {got}, differences {want}"
                    );
                }
            }
            check_product(model, (mode, t, &y), &jac, seed + a);
            regimes.push(model.mode_label(mode));
            checked += 1;
        }
    }
    regimes.sort_unstable();
    regimes.dedup();
    assert!(checked > 60, "states checked: {checked}");
    // Free flight (1) and the contact regimes of a preloaded anisotropic ring.
    assert!(regimes.len() >= 4, "regimes reached: {regimes:?}");
    println!("regimes checked: {regimes:?} in {checked} states");
    regimes
}

/// The variational equations' product $JV$ (`Variational::rhs_jacobian_product`: the linear
/// rotor's own, without forming $J$; the modal rotor's the dense default) against the
/// Jacobian `jac` times $V$, outside the ring's slots (whose rows are algebraic).
fn check_product<R: SmoothRotor<Dim = Dyn>>(
    model: &RingedRotor<R>,
    (mode, t, y): (RingMode, f64, &DVector<f64>),
    jac: &DMatrix<f64>,
    seed: usize,
) {
    let dim = y.len();
    let v = DMatrix::from_fn(dim, 3, |i, c| ((i * 5 + c * 11 + seed) as f64).cos());
    let (mut out, mut scratch) = (DMatrix::zeros(dim, 3), DMatrix::zeros(dim, dim));
    let mut work = Workspace::new(model);
    let cache = model.new_cache();
    model.rhs_jacobian_product(mode, t, y, &v, &mut out, &mut scratch, (&cache, &mut work));
    let dense = jac * &v;
    let size = jac.amax() * v.amax() * dim as f64;
    let slots = model.rotor().ring_slots();
    for i in (0..dim).filter(|i| !slots.contains(i)) {
        for c in 0..3 {
            let (got, want) = (out[(i, c)], dense[(i, c)]);
            assert!(
                (got - want).abs() <= 1e-14 * size,
                "mode {mode:?}: (JV)[{i}, {c}] = {got}, J times V {want}"
            );
        }
    }
}

#[test]
fn ringed_linear_rotor_jacobian_matches_differences_in_every_regime() {
    check_jacobian(&model(), |y| y);
    // The product checked there is the linear rotor's own (not the dense fallback).
    let (rotor, y) = (rotor(), state([0.2, 0.1], 1));
    let v = DMatrix::from_fn(18, 2, |i, c| (i + 3 * c) as f64);
    let mut out = DMatrix::zeros(18, 2);
    assert!(rotor.jacobian_product(0.0, &y, None, v.as_slice(), out.as_mut_slice()));
}

/// The modal form's Jacobian (issue 31, L3): without its own, Radau5 took forward differences,
/// which lose every column once the modal coordinates span more than $1/\varepsilon$ (a
/// growing mode at $10^{22}$ beside decayed ones at $10^{-2}$, seed `0x00F02210` case 6772's
/// first contact: each column exactly 0, and the simplified Newton diverged at every step size).
#[test]
fn ringed_modal_rotor_jacobian_matches_differences_in_every_regime() {
    let modal = ModalRotor::new(&rotor()).unwrap();
    let to_modal = modal.clone();
    let model = modal.ringed(ring()).unwrap();
    check_jacobian(&model, |y| to_modal.modal_state(&y).unwrap());
}
