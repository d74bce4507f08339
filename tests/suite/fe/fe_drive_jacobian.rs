//! The analytic Jacobian of a finite-element rotor on a non-ideal drive on a preloaded ring
//! (`RotorModel::jacobian` of `RingedRotor<DrivenLinearRotor>`, which Radau5 uses) against
//! central differences of the model's own right-hand side (an independent check: the field
//! only), at random states, speeds and phases, in free flight and in contact; with bearings
//! that follow the speed, also the field against the rotor built at the state's speed.
//!
//! Tolerance: entry $(i, j)$ within $10^{-7}\max|J| + 10^{-6}|J_{ij}|$. The differences'
//! step is $h_j = 10^{-6}(1 + |y_j|)$: their rounding error is about
//! $\varepsilon|f|/h \approx 2\cdot 10^{-10}$ of the field's scale and their truncation error
//! $h^2|f^{\prime\prime\prime}|/6 \approx 10^{-12}$ of it, so $10^{-7}$ of the largest entry
//! leaves a margin of hundreds, while every term of the Jacobian (checked by dropping each)
//! is far above it.

use jeffcott::hybrid::RotorModel;
use jeffcott::nalgebra::{Complex, DMatrix, DVector};
use jeffcott::ring::{RingAxis, SnubberRing};
use jeffcott::rotor::{
    BearingTable, DrivenLinearRotor, LinearRotor, LinearSystem, MotorTorque, RingedRotor,
    SmoothRotor,
};

use crate::rng::Rng;

const N: usize = 8;
const DIM: usize = 2 * N + 4;
const SLOTS: [usize; 2] = [2 * N, 2 * N + 1];

/// The test rotor's mass, stiffness, total damping at 5 rad/s and gyroscopic matrices.
fn matrices() -> [DMatrix<f64>; 4] {
    let m = DMatrix::from_fn(N, N, |i, j| if i == j { 2.0 } else { 0.1 });
    let k = DMatrix::from_fn(N, N, |i, j| if i == j { 50.0 } else { -2.0 });
    let g = DMatrix::from_fn(N, N, |i, j| (i as f64 - j as f64) * 0.3);
    [m, k.scale(1e-2), k, g]
}

/// The test rotor's system at `speed` with its stiffness and total damping `(k, d)`: the
/// out-of-balance (given at 5 rad/s) scaled to `speed`.
fn system(speed: f64, (k, d): (DMatrix<f64>, DMatrix<f64>)) -> LinearSystem {
    let [m, ..] = matrices();
    let s = (speed / 5.0).powi(2);
    LinearSystem::new(m, d, k, speed)
        .unwrap()
        .with_harmonic_force(2, Complex::new(20.0, -10.0) * s)
        .unwrap()
        .with_harmonic_force(5, Complex::new(-6.0, 8.0) * s)
        .unwrap()
}

/// The test rotor's bearings at the speed factor `s`: stiffer, cross-coupled and more damped
/// at DOFs 0, 1 ($C$ without the gyroscopic part: $D - 5G$ at rest).
fn bearing(s: f64) -> (DMatrix<f64>, DMatrix<f64>) {
    let [_, d, k, g] = matrices();
    let (mut kk, mut cc) = (k, &d - &g * 5.0);
    kk[(0, 0)] += 10.0 * s;
    kk[(1, 1)] += 6.0 * s;
    kk[(0, 1)] += 2.0 * s;
    kk[(1, 0)] += 2.0 * s;
    cc[(0, 0)] += 0.2 * s;
    (kk, cc)
}

/// The grid of [`table`]: speeds (rad/s) and [`bearing`]'s factors.
const GRID: [(f64, f64); 3] = [(3.0, 0.5), (5.0, 1.0), (7.5, 2.5)];

/// A bearing table on the test rotor: [`bearing`] on [`GRID`].
fn table() -> BearingTable {
    let (ks, cs): (Vec<_>, Vec<_>) = GRID.iter().map(|&(_, f)| bearing(f)).unzip();
    BearingTable::new(GRID.iter().map(|&(s, _)| s).collect(), ks, cs).unwrap()
}

/// An 8-DOF rotor (reference speed 5 rad/s) with a large out-of-balance at DOFs 2, 3 (the
/// station), a skew gyroscopic matrix, the polar inertia 1 (its coupling $b\cdot M^{-1}b$
/// up to about 0.3 of it) and the motor `motor`, on an anisotropic preloaded ring (gap 1);
/// with [`table`]'s bearings if `bearings`.
fn model(motor: MotorTorque, bearings: bool) -> RingedRotor<DrivenLinearRotor> {
    let [_, d, k, g] = matrices();
    let rotor = LinearRotor::new(system(5.0, (k, d)), [2, 3], [0.0, 0.0]).unwrap();
    let mut driven = rotor.with_drive(&g, 1.0, motor).unwrap();
    if bearings {
        driven = driven.with_bearing_table(&table()).unwrap();
    }
    let ring = SnubberRing::new(
        RingAxis::new(30.0, 0.15),
        RingAxis::new(60.0, 0.05),
        0.05,
        1.0,
    )
    .unwrap();
    driven.ringed(ring).unwrap()
}

/// A random state with the station at `r`, the speed in [2, 9] rad/s and any phase.
fn state(rng: &mut Rng, r: [f64; 2]) -> DVector<f64> {
    let mut y = DVector::from_fn(DIM, |_, _| 0.5 * rng.sym());
    y[2] = r[0];
    y[3] = r[1];
    y[DIM - 2] = rng.uniform(2.0, 9.0);
    y[DIM - 1] = rng.uniform(-10.0, 10.0);
    y
}

/// Central differences of the model's field in `mode` at `y`.
fn differences(
    model: &RingedRotor<DrivenLinearRotor>,
    mode: <RingedRotor<DrivenLinearRotor> as RotorModel>::Mode,
    y: &DVector<f64>,
) -> DMatrix<f64> {
    let cache = model.new_cache();
    let (mut plus, mut minus) = (y.clone(), y.clone());
    let (mut fp, mut fm) = (y.clone(), y.clone());
    let mut fd = DMatrix::<f64>::zeros(DIM, DIM);
    for j in 0..DIM {
        let h = 1e-6 * (1.0 + y[j].abs());
        plus[j] += h;
        minus[j] -= h;
        model.rhs(mode, 0.37, &plus, &mut fp, &cache);
        model.rhs(mode, 0.37, &minus, &mut fm, &cache);
        plus[j] = y[j];
        minus[j] = y[j];
        fd.set_column(j, &((&fp - &fm) / (2.0 * h)));
    }
    fd
}

/// The analytic Jacobian against [`differences`] over random states in free flight and
/// contact; returns the regimes reached.
fn check(motor: MotorTorque, seed: u64, bearings: bool) -> Vec<u8> {
    let model = model(motor, bearings);
    let cache = model.new_cache();
    let mut rng = Rng(seed);
    let (mut regimes, mut checked) = (Vec::new(), 0);
    for depth in [0.5, 1.01, 1.05, 1.15, 1.3, 1.6] {
        for a in 0..12 {
            let angle = 0.1 + a as f64 * std::f64::consts::TAU / 12.0;
            let mut y = state(&mut rng, [depth * angle.cos(), depth * angle.sin()]);
            model.make_consistent(&mut y).unwrap();
            let Ok(mode) = model.initial_mode(0.37, &y) else {
                continue;
            };
            let mut jac = DMatrix::from_element(DIM, DIM, f64::NAN);
            let mut view = jac.view_mut((0, 0), (DIM, DIM));
            assert!(model.jacobian(mode, 0.37, &y, &mut view, &cache));
            let fd = differences(&model, mode, &y);
            let big = fd.amax();
            for i in (0..DIM).filter(|i| !SLOTS.contains(i)) {
                for j in 0..DIM {
                    let (got, want) = (jac[(i, j)], fd[(i, j)]);
                    assert!(
                        (got - want).abs() <= 1e-7 * big + 1e-6 * want.abs(),
                        "mode {mode:?}, depth {depth}, angle {angle}, speed {}, phase {}: \
                         J[{i}, {j}] = {got}, differences {want} (largest entry {big})",
                        y[DIM - 2],
                        y[DIM - 1]
                    );
                }
            }
            regimes.push(model.mode_label(mode));
            checked += 1;
        }
    }
    assert!(checked > 50, "states checked: {checked}");
    regimes.sort_unstable();
    regimes.dedup();
    regimes
}

/// A linear DC motor (its slope exact) and a user's nonlinear characteristic (its slope a
/// central difference of $T$ alone): free flight and at least three contact regimes.
#[test]
fn driven_fe_rotor_jacobian_matches_differences_in_every_regime() {
    let linear = check(MotorTorque::linear(3.0, 8.0).unwrap(), 1, false);
    let user = check(
        MotorTorque::user(|w| 3.0 * (1.0 - w / 8.0) + 2.0 * (0.7 * w).sin()),
        2,
        false,
    );
    println!("regimes checked: linear motor {linear:?}, user's motor {user:?}");
    for regimes in [linear, user] {
        assert!(regimes.len() >= 4, "regimes reached: {regimes:?}");
    }
}

/// With bearings that follow the speed ([`table`]; the speeds 2 to 9 rad/s reach below,
/// between and above its grid): the Jacobian, the speed's column with the table's slope
/// included, against differences in free flight and contact.
#[test]
fn driven_fe_rotor_with_a_bearing_table_jacobian_matches_differences() {
    let regimes = check(MotorTorque::linear(3.0, 8.0).unwrap(), 3, true);
    assert!(regimes.len() >= 4, "regimes reached: {regimes:?}");
}

/// With [`table`]'s bearings, the field at a state of speed $\Omega_s$ is that of the driven
/// rotor without a table built at $\Omega_s$ from the matrices $K(\Omega_s)$ and
/// $C(\Omega_s) + \Omega_s G$ interpolated here by hand (its reference speed $\Omega_s$: no
/// correction at all), to rounding; at speeds below, between and above the grid.
#[test]
fn driven_fe_rotor_with_a_bearing_table_is_the_rotor_built_at_its_speed() {
    let motor = || MotorTorque::linear(3.0, 8.0).unwrap();
    let tabled = model(motor(), true);
    let [.., g] = matrices();
    let mut worst = 0.0f64;
    for (i, speed) in [2.0, 3.5, 4.2, 5.0, 6.1, 7.4, 9.0].into_iter().enumerate() {
        // The table's factor at `speed`, by hand: linear between the grid's, held beyond.
        let factor = match GRID.iter().position(|&(s, _)| speed < s) {
            Some(0) => GRID[0].1,
            None => GRID[2].1,
            Some(j) => {
                let ((s0, f0), (s1, f1)) = (GRID[j - 1], GRID[j]);
                f0 + (f1 - f0) * (speed - s0) / (s1 - s0)
            }
        };
        let (kk, cc) = bearing(factor);
        let built = LinearRotor::new(system(speed, (kk, cc + &g * speed)), [2, 3], [0.0, 0.0])
            .unwrap()
            .with_drive(&g, 1.0, motor())
            .unwrap();
        let mut rng = Rng(40 + i as u64);
        let mut y = state(&mut rng, [0.3, 0.2]);
        y[DIM - 2] = speed;
        let (mut a, mut b) = (DVector::zeros(DIM), DVector::zeros(DIM));
        tabled.rotor().rhs(0.37, &y, &mut a);
        built.rhs(0.37, &y, &mut b);
        worst = worst.max((&a - &b).amax() / b.amax());
    }
    println!("the field against the rotor built at its speed: {worst:.1e}");
    assert!(worst < 1e-12, "{worst:e}");
}

/// A report (Radau5's cost with the analytic Jacobian): case S1 reduced to node 12 and 8 or
/// 24 Craig-Bampton modes, on its ring, driven from 100 rad/s by the DC motor
/// $T = 1000(1 - \Omega/400)$ N m through $J = 0.5$ kg m² for 0.3 s (`fe_drive`'s run-up
/// through the first critical speed, in contact on the way), Radau5 at `rtol` = `atol` =
/// $10^{-8}$: steps, rhs evaluations, Jacobians, LU decompositions, wall time, and the
/// final state (the station in gaps, the speed) to compare with a run that differences $f$.
#[test]
#[ignore = "a report: run with --release --ignored --nocapture"]
fn radau5_driven_run_up_report() {
    use jeffcott::hybrid::{simulate, DenseSampling, OutputPlan, Trajectory};
    use jeffcott::nalgebra::Dyn;
    use jeffcott::ode::Method;

    use super::fe_reduction_s1::reduction;
    use super::fe_s1::S1;

    let s1 = S1::load();
    for modes in [8, 24] {
        let (cb, model) = reduction(&s1, modes);
        let g = cb.project(s1.lateral().gyroscopic()).unwrap();
        let motor = MotorTorque::linear(1000.0, 400.0).unwrap();
        let driven = model
            .rotor()
            .clone()
            .with_exact_free_flight(false)
            .with_drive(&g, 0.5, motor)
            .unwrap()
            .ringed(*model.ring())
            .unwrap();
        let plan = OutputPlan {
            t_end: 0.3,
            strobe: None,
            dense: Some(DenseSampling {
                t_start: 0.0,
                dt: 0.05,
            }),
            events: true,
        };
        let opts = super::fe_energy::options(Method::Radau5, 1e-8);
        let y0 = driven.rotor().rest_state(100.0);
        let mut traj = Trajectory::<Dyn>::default();
        let start = std::time::Instant::now();
        let stats = simulate(&driven, 0.0, &y0, &plan, &opts, &mut traj).unwrap();
        let seconds = start.elapsed().as_secs_f64();
        let last = &traj.samples.last().unwrap().y;
        println!(
            "{modes} modes (N = {}): {} steps ({} rejected), {} rhs, {} Jacobians, {} LU, \
             {} transitions, {seconds:.3} s; at t = 0.3 s the station at ({:.9}, {:.9}) gaps, \
             the speed {:.9} rad/s",
            last.len(),
            stats.steps,
            stats.rejected,
            stats.rhs_evals,
            stats.jacobians,
            stats.lu_decompositions,
            stats.transitions,
            last[0] / s1.gap,
            last[1] / s1.gap,
            last[driven.rotor().speed_index()]
        );
    }
}
