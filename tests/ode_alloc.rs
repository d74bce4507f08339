//! No heap allocation in the hot loop, for a dimension known at run time:
//! `step`, `dense`, `find_first_event`, `truncate` and `reset` of a `Dyn`
//! system allocate nothing once the integrator and the event state exist.
//! Counted by the `allocation-counter` global allocator (this test binary
//! only; it counts the allocations of the current thread). With and without
//! the step-end screen of the event detector. Every method of `Method::ALL`, RADAU5 with
//! its Jacobians and LU decompositions included.

use jeffcott::numeric::Direction;
use jeffcott::ode::{
    find_first_event, AnyIntegrator, EventFns, EventOptions, EventState, Integrator, Method,
    Options, Tolerance,
};
use nalgebra::{DVector, Dyn};

/// A chain of `m` masses with cubic springs and fixed ends, forced at the
/// first one: $y = (x, v)$, $n = 2m$.
fn chain(t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
    let m = y.len() / 2;
    for i in 0..m {
        let left = if i > 0 { y[i - 1] } else { 0.0 };
        let right = if i + 1 < m { y[i + 1] } else { 0.0 };
        let stretch = 2.0 * y[i] - left - right;
        dy[i] = y[m + i];
        dy[m + i] = -stretch - 0.5 * stretch.powi(3) - 0.05 * y[m + i];
    }
    dy[m] += 0.3 * (1.3 * t).cos();
}

#[test]
fn thousand_steps_with_events_of_a_dyn_system_allocate_nothing() {
    let m = 6;
    let n = 2 * m;
    for method in Method::ALL {
        let opts = match method {
            Method::Rk4 => Options::fixed(0.02),
            _ => Options::default()
                .with_rtol(Tolerance::Scalar(1e-9))
                .with_atol(Tolerance::PerComponent(DVector::from_element(n, 1e-11))),
        };
        let mut integ = AnyIntegrator::with_dim(method, Dyn(n), opts).unwrap();
        // A wall at x_0 = 0.1 (impact: the velocity is reversed), with the
        // derivative (grazing detection, one rhs per sample), and a
        // non-terminal level of the last mass.
        let events = EventFns::new(
            [Direction::Rising, Direction::Either],
            move |i, _t, y: &DVector<f64>| {
                if i == 0 {
                    y[0] - 0.1
                } else {
                    y[m - 1] - 0.01
                }
            },
        )
        .with_derivative(
            move |i, _t, _y: &DVector<f64>, dy: &DVector<f64>| {
                if i == 0 {
                    dy[0]
                } else {
                    dy[m - 1]
                }
            },
        )
        .terminal([true, false]);
        let mut state = EventState::with_dim(Dyn(n));
        let ev_opts = EventOptions::default();
        let y0 = DVector::from_fn(n, |i, _| 0.05 * (i as f64 + 1.0).sin());
        let mut y = y0.clone();
        let mut mid = y0.clone();
        integ.reset(&chain, 0.0, &y0, false).unwrap();

        let (mut steps, mut impacts, mut levels) = (0, 0, 0);
        let info = allocation_counter::measure(|| {
            while steps < 1000 {
                integ.step(&chain, 1e6).unwrap();
                steps += 1;
                let tm = 0.5 * (integ.t_prev() + integ.t());
                integ.dense(&chain, tm, &mut mid);
                while let Some(hit) =
                    find_first_event(&mut integ, &chain, &events, &ev_opts, &mut state).unwrap()
                {
                    if hit.index == 1 {
                        levels += 1;
                        continue;
                    }
                    impacts += 1;
                    let t_hit = hit.t;
                    y.copy_from(&hit.y);
                    integ.truncate(&chain, t_hit).unwrap();
                    y[m] *= -0.8;
                    integ.reset(&chain, t_hit, &y, true).unwrap();
                    state.reset();
                    break;
                }
            }
        });
        println!(
            "{}: {steps} steps to t = {:.1}, {impacts} impacts, {levels} level crossings, {:?}",
            method.name(),
            integ.t(),
            info
        );
        assert!(impacts >= 5 && levels >= 5, "{impacts} {levels}");
        if method == Method::Radau5 {
            // The implicit method's linear algebra ran inside the measured loop: finite-
            // difference Jacobians (one per reset at least) and LU decompositions.
            let s = integ.stats();
            assert!(
                s.jacobians > impacts && s.lu_decompositions >= s.jacobians,
                "{s:?}"
            );
        }
        assert_eq!(
            info.count_total,
            0,
            "{}: {} allocations ({} bytes) in 1000 steps",
            method.name(),
            info.count_total,
            info.bytes_total
        );
    }
}

#[test]
fn event_bookkeeping_grows_once_for_a_larger_set() {
    let osc = |_t: f64, y: &DVector<f64>, dy: &mut DVector<f64>| {
        dy[0] = y[1];
        dy[1] = -y[0];
    };
    let mut integ = AnyIntegrator::with_dim(Method::Dop853, Dyn(2), Options::fixed(0.5)).unwrap();
    integ
        .reset(&osc, 0.0, &DVector::from_vec(vec![1.0, 0.0]), false)
        .unwrap();
    integ.step(&osc, 10.0).unwrap();
    // 40 levels of x: more than the state has room for at first.
    let many = EventFns::new(vec![Direction::Either; 40], |i, _t, y: &DVector<f64>| {
        y[0] - 1.0 + 0.001 * i as f64
    });
    let mut state = EventState::with_dim(Dyn(2));
    let opts = EventOptions::default();
    let first = allocation_counter::measure(|| {
        find_first_event(&mut integ, &osc, &many, &opts, &mut state).unwrap();
    });
    // Exactly one: the per-event bookkeeping grows from its initial room
    // (this also shows that the counter counts).
    assert_eq!(first.count_total, 1, "{first:?}");
    for _ in 0..3 {
        integ.step(&osc, 10.0).unwrap();
        let again = allocation_counter::measure(|| {
            state.reset();
            find_first_event(&mut integ, &osc, &many, &opts, &mut state).unwrap();
        });
        assert_eq!(again.count_total, 0, "{again:?}");
    }
}

/// `rotor::LinearRotor` (a finite-element rotor's vector field): its right-hand side and the
/// ring's force at its station allocate nothing (one matrix-vector product into views).
#[test]
fn linear_rotor_rhs_allocates_nothing() {
    use jeffcott::nalgebra::{Complex, DMatrix, Vector2};
    use jeffcott::rotor::{LinearRotor, LinearSystem, SmoothRotor};
    let n = 8;
    let m = DMatrix::from_fn(n, n, |i, j| if i == j { 2.0 } else { 0.1 });
    let k = DMatrix::from_fn(n, n, |i, j| if i == j { 1e4 } else { -10.0 });
    let system = LinearSystem::new(m, k.scale(1e-4), k, 50.0)
        .unwrap()
        .with_harmonic_force(2, Complex::new(1.0, -0.5))
        .unwrap()
        .with_constant_force(3, -9.81)
        .unwrap();
    let rotor = LinearRotor::new(system, [2, 3], [1e-5, 0.0]).unwrap();
    let y = DVector::from_fn(2 * n + 2, |i, _| 1e-4 * (i as f64).cos());
    let mut dy = rotor.rest_state();
    let force = Vector2::new(3.0, -1.0);
    let info = allocation_counter::measure(|| {
        for step in 0..100 {
            rotor.rhs(step as f64 * 1e-3, &y, &mut dy);
            rotor.add_station_force(&y, &force, &mut dy);
            std::hint::black_box(rotor.station(&y));
        }
    });
    assert_eq!(info.count_total, 0, "{info:?}");
}

/// The exponential integrator ETD4 (a system with a diagonal linear part: the chain's
/// velocity damping; without and with its forcing declared), with events, truncations and
/// resets, and `rotor::ModalRotor`'s field, station and force: nothing allocated.
#[test]
fn etd4_steps_and_the_modal_rotor_allocate_nothing() {
    use jeffcott::nalgebra::{Complex, DMatrix, Vector2};
    use jeffcott::ode::{BlockForcing, DiagonalLinearPart, OdeSystem};
    use jeffcott::rotor::{LinearRotor, LinearSystem, ModalRotor, SmoothRotor};
    struct Split(DiagonalLinearPart);
    impl OdeSystem<Dyn> for Split {
        fn rhs(&self, t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
            chain(t, y, dy)
        }
        fn linear_part(&self) -> Option<&DiagonalLinearPart> {
            Some(&self.0)
        }
    }
    let m = 6;
    let n = 2 * m;
    let damping: Vec<(usize, f64)> = (m..n).map(|i| (i, -0.05)).collect();
    let plain = DiagonalLinearPart::new(n, &damping, &[]).unwrap();
    // The chain's forcing 0.3 cos 1.3t at the first mass's velocity, declared: the forced
    // stepping path (its increments and the dense output's response).
    let drive = BlockForcing {
        cos: Complex::new(0.3, 0.0),
        ..BlockForcing::default()
    };
    let forced = plain.clone().with_forcing(1.3, &[(m, drive)]).unwrap();
    for (lp, label) in [(plain, "ETD4"), (forced, "ETD4 with a declared forcing")] {
        let sys = Split(lp);
        let opts = Options::default().with_rtol(1e-9).with_atol(1e-11);
        let mut integ = AnyIntegrator::with_dim(Method::Etd4, Dyn(n), opts).unwrap();
        let events = EventFns::new([Direction::Rising], |_i, _t, y: &DVector<f64>| y[0] - 0.1)
            .with_derivative(|_i, _t, _y: &DVector<f64>, dy: &DVector<f64>| dy[0]);
        let mut state = EventState::with_dim(Dyn(n));
        let ev_opts = EventOptions::default();
        let y0 = DVector::from_fn(n, |i, _| 0.05 * (i as f64 + 1.0).sin());
        let (mut y, mut mid) = (y0.clone(), y0.clone());
        integ.reset(&sys, 0.0, &y0, false).unwrap();
        let mut impacts = 0;
        let info = allocation_counter::measure(|| {
            for _ in 0..1000 {
                integ.step(&sys, 1e6).unwrap();
                let tm = 0.5 * (integ.t_prev() + integ.t());
                integ.dense(&sys, tm, &mut mid);
                if let Some(hit) =
                    find_first_event(&mut integ, &sys, &events, &ev_opts, &mut state).unwrap()
                {
                    impacts += 1;
                    y.copy_from(&hit.y);
                    integ.truncate(&sys, hit.t).unwrap();
                    y[m] *= -0.8;
                    integ.reset(&sys, hit.t, &y, true).unwrap();
                    state.reset();
                }
            }
        });
        assert!(impacts >= 5, "{label}: {impacts}");
        assert_eq!(info.count_total, 0, "{label}: {info:?}");
    }

    let k = DMatrix::from_fn(8, 8, |i, j| if i == j { 1e4 } else { -10.0 });
    let system = LinearSystem::new(DMatrix::identity(8, 8) * 2.0, k.scale(1e-4), k, 50.0)
        .unwrap()
        .with_harmonic_force(2, Complex::new(1.0, -0.5))
        .unwrap();
    let rotor = ModalRotor::new(&LinearRotor::new(system, [2, 3], [1e-5, 0.0]).unwrap()).unwrap();
    let y = DVector::from_fn(rotor.rest_state().len(), |i, _| 1e-4 * (i as f64).cos());
    let mut dy = rotor.rest_state();
    let force = Vector2::new(3.0, -1.0);
    let info = allocation_counter::measure(|| {
        for step in 0..100 {
            rotor.rhs(step as f64 * 1e-3, &y, &mut dy);
            rotor.add_station_force(&y, &force, &mut dy);
            std::hint::black_box(rotor.station(&y));
        }
    });
    assert_eq!(info.count_total, 0, "ModalRotor: {info:?}");
}

/// RADAU5 on a second-order system that declares its diagonal springs
/// (`OdeSystem::diagonal_springs`; 12 oscillators coupled by a cubic spring through one
/// "station", rank 1, with an analytic Jacobian): its Woodbury decompositions and solves, with
/// truncations and resets, allocate nothing.
#[test]
fn radau5_woodbury_solves_allocate_nothing() {
    use jeffcott::ode::{DiagonalSprings, JacobianMut, OdeSystem};
    struct Modes {
        k: Vec<f64>,
        d: Vec<f64>,
        phi: Vec<f64>,
    }
    impl Modes {
        fn station(&self, y: &DVector<f64>) -> f64 {
            self.phi.iter().zip(y.iter()).map(|(p, x)| p * x).sum()
        }
    }
    impl OdeSystem<Dyn> for Modes {
        fn rhs(&self, t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
            let p = self.k.len();
            let s = self.station(y);
            for i in 0..p {
                dy[i] = y[p + i];
                dy[p + i] =
                    -self.k[i] * y[i] - self.d[i] * y[p + i] - self.phi[i] * 50.0 * s.powi(3)
                        + self.phi[i] * (1.3 * t).cos();
            }
        }
        fn jacobian(&self, _t: f64, y: &DVector<f64>, jac: &mut JacobianMut<'_, Dyn>) -> bool {
            let p = self.k.len();
            let g = 150.0 * self.station(y).powi(2);
            jac.fill(0.0);
            for i in 0..p {
                jac[(i, p + i)] = 1.0;
                jac[(p + i, i)] = -self.k[i];
                jac[(p + i, p + i)] = -self.d[i];
                for j in 0..p {
                    jac[(p + i, j)] -= self.phi[i] * g * self.phi[j];
                }
            }
            true
        }
        fn second_order(&self) -> Option<usize> {
            Some(self.k.len())
        }
        fn diagonal_springs(&self) -> Option<DiagonalSprings<'_>> {
            Some(DiagonalSprings {
                stiffness: &self.k,
                damping: &self.d,
            })
        }
    }
    let p = 12;
    let sys = Modes {
        k: (1..=p).map(|j| (j * j * j * j) as f64).collect(),
        d: (1..=p).map(|j| 0.02 * (j * j) as f64).collect(),
        phi: (1..=p).map(|j| (j as f64 * 1.1).sin()).collect(),
    };
    let n = 2 * p;
    let opts = Options::default().with_rtol(1e-8).with_atol(1e-10);
    let mut integ = AnyIntegrator::with_dim(Method::Radau5, Dyn(n), opts).unwrap();
    let y0 = DVector::from_fn(n, |i, _| if i < p { 0.1 / (i + 1) as f64 } else { 0.0 });
    let mut mid = y0.clone();
    integ.reset(&sys, 0.0, &y0, false).unwrap();
    let info = allocation_counter::measure(|| {
        for step in 1..=1000 {
            integ.step(&sys, 1e6).unwrap();
            let tm = 0.5 * (integ.t_prev() + integ.t());
            integ.dense(&sys, tm, &mut mid);
            if step % 100 == 0 {
                integ.truncate(&sys, tm).unwrap();
                mid.copy_from(integ.y());
                integ.reset(&sys, tm, &mid, true).unwrap();
            }
        }
    });
    let s = integ.stats();
    println!("{s:?}, {info:?}");
    assert!(
        s.woodbury_decompositions > 10 && s.woodbury_decompositions == s.lu_decompositions,
        "{s:?}"
    );
    assert_eq!(info.count_total, 0, "RADAU5 Woodbury: {info:?}");
}
