//! `LinearClosedForm::least_damping_ratio` against the eigenvalues in closed form: one node
//! with cross-coupled stiffness $q$ (a bearing's), $M = I$, $C = cI$, $K = [[k, q], [-q, k]]$.
//! In $u = x + iy$ the modes solve $\lambda^2 + c\lambda + k \mp iq = 0$, so
//! $\lambda = (-c \pm \sqrt{c^2 - 4(k \mp iq)})/2$; the forward mode grows once $q > c\sqrt{k}$
//! (to first order in $c$ and $q$).

use jeffcott::nalgebra::{Complex, DMatrix, Vector2};
use jeffcott::rotor::{LinearFreeFlight, LinearSystem};

fn least_damping_ratio(c: f64, k: f64, q: f64) -> f64 {
    let system = LinearSystem::new(
        DMatrix::identity(2, 2),
        DMatrix::identity(2, 2) * c,
        DMatrix::from_row_slice(2, 2, &[k, q, -q, k]),
        1.0,
    )
    .unwrap();
    LinearFreeFlight::new(system, [0, 1], Vector2::zeros())
        .prepare()
        .unwrap()
        .least_damping_ratio()
}

/// The truth: the four roots of the two quadratics, written out.
fn closed_form(c: f64, k: f64, q: f64) -> f64 {
    let mut zeta = f64::INFINITY;
    for sign in [1.0, -1.0] {
        let root = (Complex::new(c * c - 4.0 * k, 4.0 * sign * q)).sqrt();
        for l in [(-c + root) / 2.0, (-c - root) / 2.0] {
            zeta = zeta.min(-l.re / l.norm());
        }
    }
    zeta
}

#[test]
fn cross_coupling_past_its_threshold_is_a_negative_damping_ratio() {
    // Threshold q = c sqrt(k) = 0.02: below, at 0.01, stable; above, at 0.05, the forward mode
    // grows; without cross-coupling the ratio is c / (2 sqrt(k)) = 0.01.
    for (q, stable) in [(0.0, true), (0.01, true), (0.05, false)] {
        let (got, truth) = (least_damping_ratio(0.02, 1.0, q), closed_form(0.02, 1.0, q));
        println!("q = {q}: least damping ratio {got:.9} (closed form {truth:.9})");
        assert!((got - truth).abs() <= 1e-12, "{got} {truth}");
        assert_eq!(got >= 0.0, stable);
    }
    assert!((least_damping_ratio(0.02, 1.0, 0.0) - 0.01).abs() <= 1e-12);
}

#[test]
fn a_rigid_body_mode_has_no_damping_ratio() {
    // k = 0: eigenvalues 0 (twice) and -c (twice); the zero ones are left out, -c is
    // overdamped (ratio 1).
    assert!((least_damping_ratio(0.3, 0.0, 0.0) - 1.0).abs() <= 1e-12);
}

#[test]
fn an_undamped_rotor_is_neutral_not_unstable() {
    // ROSS's rotor_example (42 DOF, bearings without damping, 1500 rpm; the ring's damping
    // acts only in contact): every eigenvalue of its free flight is on the imaginary axis in
    // exact arithmetic; computed, some real parts come out a hair positive. They lie within
    // the rounding level, so the rotor is not called unstable. Truth: an undamped, gyroscopic
    // system (M, K symmetric, G skew) is conservative.
    let model = super::fe_eccentric::rotor_42(5e6, 50.0, [0.0; 2], 1.5e-6, [0.0; 2]);
    let form = model.closed_form().unwrap().unwrap();
    let largest_re = form
        .eigenvalues()
        .iter()
        .map(|l| l.re.abs())
        .fold(0.0, f64::max);
    println!(
        "least damping ratio {:e}, largest |Re| {largest_re:e}, threshold {:e}",
        form.least_damping_ratio(),
        form.growth_threshold()
    );
    assert!(largest_re <= form.growth_threshold());
    assert!(!form.is_linearly_unstable());
}
