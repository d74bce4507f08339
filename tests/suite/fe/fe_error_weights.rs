//! The error weights of `LinearRotor` (`SmoothRotor::error_scale`): each coordinate's
//! frequency $\omega_i = \sqrt{M_{ii}/(MK_s^{-1}M)_{ii}}$ against closed forms, and the weight
//! it gives the velocities.

use jeffcott::hybrid::RotorModel;
use jeffcott::nalgebra::{DMatrix, DVector};
use jeffcott::ring::SnubberRing;
use jeffcott::rotor::{LinearRotor, LinearSystem, SmoothRotor};

fn system(mass: DMatrix<f64>, stiffness: DMatrix<f64>, speed: f64) -> LinearSystem {
    let n = mass.nrows();
    LinearSystem::new(mass, DMatrix::zeros(n, n), stiffness, speed).unwrap()
}

/// Modal coordinates ($M = I$, $K = \operatorname{diag}(\omega_k^2)$): each coordinate's
/// frequency is its mode's, exactly.
#[test]
fn a_modal_coordinate_has_its_natural_frequency() {
    let w = [3.0, 40.0, 700.0];
    let s = system(
        DMatrix::identity(3, 3),
        DMatrix::from_diagonal(&DVector::from_iterator(3, w.iter().map(|x| x * x))),
        10.0,
    );
    let f = s.coordinate_frequencies();
    for (got, want) in f.iter().zip(w) {
        assert!((got - want).abs() <= 1e-14 * want, "{got} against {want}");
    }
}

/// Two unit masses between three unit springs, $K = \begin{pmatrix}2 & -1\\\\ -1 &
/// 2\end{pmatrix}$: $K^{-1} = \tfrac13\begin{pmatrix}2 & 1\\\\ 1 & 2\end{pmatrix}$ by hand, so
/// $\omega_i = \sqrt{3/2}$, between the modes' 1 and $\sqrt3$; a mass of 4 on the first
/// ($M = \operatorname{diag}(4, 1)$): $(MK^{-1}M)_{11} = 16\cdot2/3$, $\omega_1 =
/// \sqrt{4\cdot3/32}$, $(MK^{-1}M)_{22} = 2/3$, $\omega_2 = \sqrt{3/2}$. A non-symmetric
/// part of $K$ (a cross-coupled bearing) is left out.
#[test]
fn a_physical_coordinate_takes_part_in_the_low_modes() {
    let k = DMatrix::from_row_slice(2, 2, &[2.0, -1.0, -1.0, 2.0]);
    let f = system(DMatrix::identity(2, 2), k.clone(), 1.0).coordinate_frequencies();
    assert!((f[0] - 1.5f64.sqrt()).abs() < 1e-14, "{f}");
    assert!((f[1] - 1.5f64.sqrt()).abs() < 1e-14, "{f}");
    let m = DMatrix::from_diagonal(&DVector::from_vec(vec![4.0, 1.0]));
    let skew = DMatrix::from_row_slice(2, 2, &[0.0, 0.3, -0.3, 0.0]);
    let f = system(m, k + skew, 1.0).coordinate_frequencies();
    assert!((f[0] - (12.0f64 / 32.0).sqrt()).abs() < 1e-14, "{f}");
    assert!((f[1] - 1.5f64.sqrt()).abs() < 1e-14, "{f}");
}

/// A singular stiffness (a free rotor) has no such frequency: every coordinate gets the speed.
#[test]
fn a_free_rotor_falls_back_to_the_speed() {
    let f = system(DMatrix::identity(2, 2), DMatrix::zeros(2, 2), 7.0).coordinate_frequencies();
    assert_eq!(f.as_slice(), &[7.0, 7.0]);
}

/// The weights reach the composed model: velocities of coordinates faster than the speed are
/// weighed by $\omega_i$ instead of $\Omega$, the slow ones, the positions and the ring's
/// slots keep the state's scale; `with_frequency_weights(false)` gives no weights (the
/// state's scale).
#[test]
fn the_velocity_weights_reach_the_ringed_model() {
    let speed = 10.0;
    let w = [3.0, 40.0, 700.0];
    let s = system(
        DMatrix::identity(3, 3),
        DMatrix::from_diagonal(&DVector::from_iterator(3, w.iter().map(|x| x * x))),
        speed,
    );
    let ring = SnubberRing::from_units(1e6, 0.0, [0.0, 0.0], 1e-3).unwrap();
    let rotor = LinearRotor::new(s, [0, 1], [0.0, 0.0]).unwrap();
    let model = rotor.clone().ringed(ring).unwrap();
    let (state, error) = (model.state_scale(), model.error_scale().unwrap());
    for i in 0..3 {
        assert_eq!(error[i], state[i], "position {i}");
        let want = state[3 + i] * w[i].max(speed) / speed;
        assert!((error[3 + i] - want).abs() <= 1e-14 * want, "velocity {i}");
    }
    assert_eq!(error[6], state[6]);
    assert_eq!(error[7], state[7]);
    let plain = rotor.with_frequency_weights(false);
    assert!(plain.error_scale().is_none());
}
