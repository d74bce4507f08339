//! Bearings whose stiffness and damping follow the speed ([`BearingTable`],
//! [`ProfiledLinearRotor::with_bearing_table`]), against truths that do not come from the
//! correction's own bookkeeping:
//!
//! * the field at many times and states against $M^{-1}$ of the equation written out here with
//!   the table's rule written out here too and $\Omega G$;
//! * a constant speed between two grid points is the constant-speed rotor built with the
//!   interpolated matrices (its free flight in closed form), on the ring;
//! * the Jacobian against central differences in free flight and the contact regimes.

use jeffcott::nalgebra::{Complex, DMatrix, DVector};
use jeffcott::rotor::{
    BearingTable, LinearRotor, LinearSystem, ProfiledLinearRotor, RotorError, SmoothRotor,
    SpeedProfile,
};

use super::fe_reduction_s1::reduction;
use super::fe_run_up::{agrees_with_the_closed_form, at_speed_with, dop853, reduced, run};
use super::fe_s1::S1;

/// S1's full lateral stiffness and damping with the bearings at nodes 4 and 31 changed by
/// `factor` (direct terms and cross terms), as a fluid-film bearing's coefficients move with
/// the speed.
fn bearings_at(s1: &S1, factor: f64) -> (DMatrix<f64>, DMatrix<f64>) {
    let lateral = s1.lateral();
    let (mut k, mut c) = (lateral.stiffness().clone(), lateral.damping().clone());
    for node in [4, 31] {
        let x = lateral.x_dof(node).unwrap();
        let y = x + 1;
        let (kxx, cxx) = (k[(x, x)], c[(x, x)]);
        k[(x, x)] += (factor - 1.0) * 0.5 * kxx;
        k[(y, y)] += (factor - 1.0) * 0.4 * kxx;
        // Cross terms of one sign: anisotropic, not circulatory (which would destabilise).
        k[(x, y)] += 0.05 * (factor - 0.5) * kxx;
        k[(y, x)] += 0.05 * (factor - 0.5) * kxx;
        c[(x, x)] += (factor - 1.0) * 0.3 * cxx;
        c[(y, y)] += (factor - 1.0) * 0.2 * cxx;
    }
    (k, c)
}

/// The grid's speeds (in units of S1's speed) and factors.
const GRID: [(f64, f64); 3] = [(0.8, 0.7), (1.1, 1.0), (1.5, 1.6)];

/// The table of [`bearings_at`] on [`GRID`], in the coordinates of the reduction `project`.
fn table(s1: &S1, speed: f64, project: impl Fn(&DMatrix<f64>) -> DMatrix<f64>) -> BearingTable {
    let (mut speeds, mut ks, mut cs) = (vec![], vec![], vec![]);
    for (at, factor) in GRID {
        let (k, c) = bearings_at(s1, factor);
        speeds.push(at * speed);
        ks.push(project(&k));
        cs.push(project(&c));
    }
    BearingTable::new(speeds, ks, cs).unwrap()
}

/// A table with a bad grid is refused, naming the field and the point.
#[test]
fn a_bad_table_is_refused_naming_the_field_and_point() {
    let m = |v: f64| DMatrix::from_diagonal_element(2, 2, v);
    let bad = |r: Result<BearingTable, RotorError>| match r {
        Err(RotorError::BearingTable { field, index, .. }) => (field, index),
        other => panic!("not refused as a bad table: {other:?}"),
    };
    assert_eq!(
        bad(BearingTable::new(vec![], vec![], vec![])),
        ("speeds", 0)
    );
    let (ks, cs) = (vec![m(1.0), m(2.0)], vec![m(0.1), m(0.1)]);
    assert_eq!(
        bad(BearingTable::new(vec![1.0, 1.0], ks.clone(), cs.clone())),
        ("speeds", 1)
    );
    assert_eq!(
        bad(BearingTable::new(
            vec![1.0, f64::NAN],
            ks.clone(),
            cs.clone()
        )),
        ("speeds", 1)
    );
    assert_eq!(
        bad(BearingTable::new(vec![1.0], ks.clone(), cs.clone())),
        ("stiffness", 0)
    );
    let wrong = vec![m(1.0), DMatrix::zeros(3, 3)];
    assert_eq!(
        bad(BearingTable::new(vec![1.0, 2.0], wrong, cs.clone())),
        ("stiffness", 1)
    );
    let nan = vec![m(0.1), m(f64::INFINITY)];
    assert_eq!(
        bad(BearingTable::new(vec![1.0, 2.0], ks.clone(), nan)),
        ("damping", 1)
    );
    // A table of another size than the system it is given to.
    let s1 = S1::load();
    let (rotor, _, g) = reduced(&s1, 8);
    let profile = SpeedProfile::constant(rotor.system().speed()).unwrap();
    let small = BearingTable::new(vec![1.0, 2.0], ks, cs).unwrap();
    let refused = rotor
        .with_speed_profile(&g, profile)
        .unwrap()
        .with_bearing_table(&small);
    assert_eq!(bad(refused.map(|_| small.clone())), ("stiffness", 0));
}

/// The table's rule written out: the grid matrices `at`, linear between the two speeds around
/// `speed`, the end's beyond the grid.
fn lerp(speeds: &[f64], at: &[DMatrix<f64>], speed: f64) -> DMatrix<f64> {
    let last = speeds.len() - 1;
    if speed <= speeds[0] {
        return at[0].clone();
    }
    if speed >= speeds[last] {
        return at[last].clone();
    }
    let i = (0..last).find(|&i| speed < speeds[i + 1]).unwrap();
    let w = (speed - speeds[i]) / (speeds[i + 1] - speeds[i]);
    &at[i] + (&at[i + 1] - &at[i]) * w
}

/// The field written out: $q^{\prime\prime} = M^{-1}\big(f - (C(\Omega) + \Omega G)q^\prime -
/// K(\Omega)q\big)$ with the out-of-balance $f = \operatorname{Re}(\hat U(\Omega^2 -
/// i\Omega^\prime)e^{i\Phi})$, $\hat U = \hat F/\Omega_r^2$.
fn field_written_out(
    system: &LinearSystem,
    g: &DMatrix<f64>,
    table: &BearingTable,
    (speed, rate, phase): (f64, f64, f64),
    y: &DVector<f64>,
) -> DVector<f64> {
    let n = system.dofs();
    let (q, v) = (y.rows(0, n), y.rows(n, n));
    let w2 = system.speed() * system.speed();
    let spin = Complex::new(speed * speed, -rate) * Complex::from_polar(1.0, phase) / w2;
    let f = system.harmonic_force().map(|u| (u * spin).re);
    let damping = lerp(table.speeds(), table.damping(), speed) + g * speed;
    let stiffness = lerp(table.speeds(), table.stiffness(), speed);
    let rhs = f - damping * v - stiffness * q;
    system.mass().clone().lu().solve(&rhs).unwrap()
}

/// On a ramp through the whole grid (below it, between its points, on them and above it), the
/// field of the profiled rotor with the table is the field written out, to rounding.
#[test]
fn the_field_follows_the_table_below_between_on_and_above_its_grid() {
    let s1 = S1::load();
    let (cb, _) = reduction(&s1, 8);
    let (rotor, _, g) = reduced(&s1, 8);
    let w = rotor.system().speed();
    let table = table(&s1, w, |a| cb.project(a).unwrap());
    let rate = 0.6 * w;
    let profile = SpeedProfile::ramp(0.5 * w, 1.7 * w, rate).unwrap();
    let system = rotor.system().clone();
    let profiled = rotor
        .with_speed_profile(&g, profile.clone())
        .unwrap()
        .with_bearing_table(&table)
        .unwrap();
    let dim = profiled.dim().0;
    let n = system.dofs();
    let mut worst = 0.0f64;
    for k in 0..=40 {
        // t on the ramp (0.5 to 1.7 of S1's speed) and just past it (held at 1.7).
        let t = 2.2 / 40.0 * k as f64;
        let y = DVector::from_fn(dim, |i, _| 1e-4 * ((i * 13 + k * 7) as f64).sin());
        let mut dy = DVector::zeros(dim);
        profiled.rhs(t, &y, &mut dy);
        let speed = profile.eta(t);
        let want = field_written_out(
            &system,
            &g,
            &table,
            (speed, profile.eta_rate(t), profile.phase(t)),
            &y,
        );
        let got = dy.rows(n, n);
        let scale = want.amax();
        worst = worst.max((got - &want).amax() / scale);
    }
    println!("field against the written-out equation: {worst:.1e} (relative to its largest entry)");
    assert!(worst < 1e-9, "{worst:e}");
}

/// A constant speed at 1.3 of S1's (between the grid's points at 1.1 and 1.5: weight 1/2) with
/// the table is the rotor built at that speed from the interpolated matrices (its free flight
/// in closed form), on the ring for 0.15 s.
#[test]
fn a_constant_speed_between_grid_points_is_the_rotor_built_with_its_matrices() {
    let (s1, modes) = (S1::load(), 8);
    let (cb, _) = reduction(&s1, modes);
    let (rotor, ring, g) = reduced(&s1, modes);
    let w = rotor.system().speed();
    let speed = 1.3 * w;
    let table = table(&s1, w, |a| cb.project(a).unwrap());
    let profiled = rotor
        .with_speed_profile(&g, SpeedProfile::constant(speed).unwrap())
        .unwrap()
        .with_bearing_table(&table)
        .unwrap()
        .ringed(ring)
        .unwrap();
    // The full matrices interpolated here, by hand, then reduced: the truth's own route.
    let (k0, c0) = bearings_at(&s1, GRID[1].1);
    let (k1, c1) = bearings_at(&s1, GRID[2].1);
    let (k, c) = ((k0 + k1) * 0.5, (c0 + c1) * 0.5);
    let exact = at_speed_with(&s1, modes, speed, (&k, &c))
        .ringed(ring)
        .unwrap();
    let a = agrees_with_the_closed_form(&exact, &profiled, s1.gap);
    // And the table changes the run: the rotor without it is elsewhere.
    let plain = at_speed_with(
        &s1,
        modes,
        speed,
        (s1.lateral().stiffness(), s1.lateral().damping()),
    );
    let y0 = exact.rotor().rest_state();
    let c = run(
        &plain.ringed(ring).unwrap(),
        &y0,
        (0.15, 5e-4),
        &dop853(1e-10),
    );
    let apart = a.samples.iter().zip(&c.samples).fold(0.0f64, |m, (p, q)| {
        let [x, y] = exact.rotor().station_displacement(&p.y);
        let [u, v] = exact.rotor().station_displacement(&q.y);
        m.max((x - u).hypot(y - v) / s1.gap)
    });
    assert!(
        apart > 1e-3,
        "the table must matter: {apart:e} of the gap apart"
    );
}

/// A table that is the system's at every grid point (its `C` plus $\Omega_r G$ is the
/// system's $D$, computed as `LinearSystem::from_matrices` computes it) changes nothing: the
/// field with it is the field without it, bit for bit.
#[test]
fn a_table_equal_to_the_system_changes_nothing() {
    let n = 6;
    let m = DMatrix::from_fn(n, n, |i, j| if i == j { 2.0 } else { 0.1 });
    let k = DMatrix::from_fn(n, n, |i, j| if i == j { 50.0 } else { -2.0 });
    let c = k.scale(1e-2);
    let g = DMatrix::from_fn(n, n, |i, j| ((i as f64) - (j as f64)) * 0.01);
    let system = LinearSystem::new(m, &c + &g * 5.0, k.clone(), 5.0)
        .unwrap()
        .with_harmonic_force(2, Complex::new(1.0, -0.5))
        .unwrap();
    let profile = SpeedProfile::ramp(3.0, 8.0, 5.0).unwrap();
    let plain = LinearRotor::new(system, [2, 3], [0.0, 0.0])
        .unwrap()
        .with_speed_profile(&g, profile)
        .unwrap();
    let table = BearingTable::new(vec![4.0, 7.0], vec![k.clone(), k], vec![c.clone(), c]).unwrap();
    let tabled = plain.clone().with_bearing_table(&table).unwrap();
    let dim = plain.dim().0;
    for t in [0.0, 0.2, 0.5, 0.9] {
        let y = DVector::from_fn(dim, |i, _| 0.3 * ((i * 5) as f64 + t).sin());
        let (mut a, mut b) = (DVector::zeros(dim), DVector::zeros(dim));
        plain.rhs(t, &y, &mut a);
        tabled.rhs(t, &y, &mut b);
        assert_eq!(a, b, "at t = {t}");
    }
}

/// A linear rotor of `n` DOFs with a skew gyroscopic matrix, and a two-point table that
/// changes the station's neighbours, on a ramp across it.
fn small_profiled() -> ProfiledLinearRotor {
    let n = 8;
    let m = DMatrix::from_fn(n, n, |i, j| if i == j { 2.0 } else { 0.1 });
    let k = DMatrix::from_fn(n, n, |i, j| if i == j { 50.0 } else { -2.0 });
    let g = DMatrix::from_fn(n, n, |i, j| ((i as f64) - (j as f64)) * 0.01);
    let system = LinearSystem::new(m, k.scale(1e-2), k.clone(), 5.0)
        .unwrap()
        .with_harmonic_force(2, Complex::new(1.0, -0.5))
        .unwrap();
    let rotor = LinearRotor::new(system, [2, 3], [0.0, 0.0]).unwrap();
    let bump = |s: f64| {
        let mut kk = k.clone();
        kk[(0, 0)] += 20.0 * s;
        kk[(0, 1)] += 5.0 * s;
        let mut cc = k.scale(1e-2);
        cc[(1, 1)] += 0.3 * s;
        (kk, cc)
    };
    let (ka, ca) = bump(0.5);
    let (kb, cb) = bump(2.0);
    let table = BearingTable::new(vec![4.0, 7.0], vec![ka, kb], vec![ca, cb]).unwrap();
    rotor
        .with_speed_profile(&g, SpeedProfile::ramp(3.0, 8.0, 5.0).unwrap())
        .unwrap()
        .with_bearing_table(&table)
        .unwrap()
}

/// The Jacobian with the table (Radau5's) against central differences of the field, in free
/// flight and the contact regimes, at a time between the grid's points.
#[test]
fn the_jacobian_with_a_table_matches_differences_in_every_regime() {
    let model = small_profiled().ringed(super::fe_jacobian::ring()).unwrap();
    let regimes = super::fe_jacobian::check_jacobian(&model, |y| y);
    assert!(regimes.len() >= 4, "{regimes:?}");
}

/// `CraigBampton::project_table`: the reduced table is the projected one at every speed
/// (between, on and beyond the grid's points), against the full table's matrices interpolated
/// by the rule written out here and projected here ($T^{\mathsf T} A T$ with the basis).
#[test]
fn a_projected_table_is_the_projection_at_every_speed() {
    let s1 = S1::load();
    let (cb, model) = reduction(&s1, 8);
    let speed = model.rotor().system().speed();
    let full = table(&s1, speed, |a| a.clone());
    let reduced = cb.project_table(&full).unwrap();
    let t = cb.basis();
    for w in [0.5, 0.8, 0.9, 1.1, 1.3, 1.5, 2.0].map(|f| f * speed) {
        let (lo, hi) = (GRID[0].0 * speed, GRID[2].0 * speed);
        // The rule: linear between the two points around w, held beyond the ends.
        let entry = |pick: usize| -> DMatrix<f64> {
            let at = |i: usize| {
                let (k, c) = bearings_at(&s1, GRID[i].1);
                if pick == 0 {
                    k
                } else {
                    c
                }
            };
            if w <= lo {
                return at(0);
            }
            if w >= hi {
                return at(2);
            }
            let i = if w <= GRID[1].0 * speed { 0 } else { 1 };
            let (a, b) = (GRID[i].0 * speed, GRID[i + 1].0 * speed);
            let s = (w - a) / (b - a);
            at(i) * (1.0 - s) + at(i + 1) * s
        };
        for (pick, got) in [(0, reduced.stiffness_at(w)), (1, reduced.damping_at(w))] {
            let want = t.transpose() * entry(pick) * t;
            let err = (&got - &want).amax() / want.amax();
            assert!(err < 1e-12, "speed {w}: {err:e}");
        }
    }
}
