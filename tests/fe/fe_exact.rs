//! Closed-form free flight of the ROSS rotors: the decomposition's conditioning.

use jeffcott::nalgebra::{Complex, DVector, Vector2};
use jeffcott::rotor::{LinearFreeFlight, RotorMatrices};

fn data(name: &str) -> String {
    format!("{}/tests/data/rotors/{name}", env!("CARGO_MANIFEST_DIR"))
}

/// The S1 rotor's free flight (ROSS's 204-DOF example at 1200 rpm, lateral DOFs, ring at node
/// 12, the unbalance 0.002 kg m at phase -pi/2 at node 12).
pub fn s1_free_flight() -> LinearFreeFlight {
    let full =
        RotorMatrices::from_ross_mat(data("rotor_example_with_damping_1200rpm.mat")).unwrap();
    let lat = full.lateral().unwrap();
    let w = 1200.0 * std::f64::consts::TAU / 60.0;
    let n = lat.dofs();
    let ix = lat.x_dof(12).unwrap();
    let d = lat.damping() + lat.gyroscopic() * w;
    let mut f = DVector::from_element(n, Complex::new(0.0, 0.0));
    let me = 0.002 * w * w;
    let ph = Complex::from_polar(me, -std::f64::consts::FRAC_PI_2);
    f[ix] = ph;
    f[ix + 1] = ph * Complex::new(0.0, -1.0);
    LinearFreeFlight::new(
        lat.mass().clone(),
        d,
        lat.stiffness().clone(),
        w,
        f,
        DVector::zeros(n),
        [ix, ix + 1],
        Vector2::zeros(),
    )
}

#[test]
fn ross_rotor_closed_form_diagnostics() {
    let lf = s1_free_flight();
    let t = std::time::Instant::now();
    let form = lf.prepare();
    let el = t.elapsed();
    match &form {
        Ok(f) => {
            let ev = f.eigenvalues();
            let maxre = ev.iter().map(|l| l.re).fold(f64::NEG_INFINITY, f64::max);
            let maxabs = ev.iter().map(|l| l.norm()).fold(0.0, f64::max);
            let minabs = ev.iter().map(|l| l.norm()).fold(f64::INFINITY, f64::min);
            eprintln!(
                "n {} cond {:e} residual {:e} max Re {maxre:e} |lambda| {minabs:e}..{maxabs:e} in {el:?}",
                f.dofs(),
                f.condition(),
                f.residual()
            );
        }
        Err(e) => eprintln!("refused: {e} in {el:?}"),
    }
}
