//! Dimensions known at run time (`Dyn`) against fixed ones (`Const<N>`): the
//! same problems give bitwise identical trajectories, events and counters;
//! dimension errors are typed.

use jeffcott::numeric::Direction;
use jeffcott::ode::{
    find_first_event, solve, AnyIntegrator, Dop853, Dopri5, EventFns, EventOptions, EventSet,
    EventState, Integrator, Method, OdeError, OdeSystem, Options, Recorder, Rk4, Stats, Tolerance,
};
use nalgebra::allocator::Allocator;
use nalgebra::{Const, DVector, DefaultAllocator, Dim, DimName, Dyn, OVector, SVector, U1};

/// A chain of `M` masses with cubic springs, fixed ends, forced at the first
/// mass: $y = (x_0..x_{M-1}, v_0..v_{M-1})$, written once for any dimension.
struct Chain;

impl<D: Dim> OdeSystem<D> for Chain
where
    DefaultAllocator: Allocator<D>,
{
    fn rhs(&self, t: f64, y: &OVector<f64, D>, dy: &mut OVector<f64, D>) {
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
}

/// Zero crossings of the first position (with derivative, for grazing
/// detection) and of the last velocity (without), not terminal.
struct Crossings;

impl<D: Dim> EventSet<D> for Crossings
where
    DefaultAllocator: Allocator<D>,
{
    fn len(&self) -> usize {
        2
    }
    fn direction(&self, _i: usize) -> Direction {
        Direction::Either
    }
    fn terminal(&self, _i: usize) -> bool {
        false
    }
    fn value(&self, i: usize, _t: f64, y: &OVector<f64, D>) -> f64 {
        if i == 0 {
            y[0]
        } else {
            y[y.len() - 1]
        }
    }
    fn derivative(
        &self,
        i: usize,
        _t: f64,
        _y: &OVector<f64, D>,
        dy: &OVector<f64, D>,
    ) -> Option<f64> {
        (i == 0).then_some(dy[0])
    }
}

/// Bit patterns of everything a run produced.
#[derive(Debug, PartialEq)]
struct Fingerprint {
    points: Vec<u64>,
    events: Vec<(usize, u64, Direction)>,
    stats: Stats,
}

fn bits<D: Dim>(t: f64, y: &OVector<f64, D>, out: &mut Vec<u64>)
where
    DefaultAllocator: Allocator<D>,
{
    out.push(t.to_bits());
    out.extend(y.iter().map(|v| v.to_bits()));
}

fn initial<D: Dim>(dim: D) -> OVector<f64, D>
where
    DefaultAllocator: Allocator<D>,
{
    let n = dim.value();
    OVector::from_iterator_generic(dim, U1, (0..n).map(|i| 0.1 * (i as f64 + 1.0).sin()))
}

fn options<D: Dim>(method: Method, dim: D) -> Options<D>
where
    DefaultAllocator: Allocator<D>,
{
    match method {
        Method::Rk4 => Options::fixed(0.01),
        _ => {
            // Per-component tolerances, one component excluded from control.
            let n = dim.value();
            let atol = OVector::from_iterator_generic(
                dim,
                U1,
                (0..n).map(|i| if i == 1 { f64::INFINITY } else { 1e-11 }),
            );
            Options::default()
                .with_rtol(Tolerance::Scalar(1e-9))
                .with_atol(Tolerance::PerComponent(atol))
        }
    }
}

/// `solve` with outputs on a grid, every step and the events recorded.
fn run_solve<D: Dim>(method: Method, dim: D) -> Fingerprint
where
    DefaultAllocator: Allocator<D>,
{
    let mut integ = AnyIntegrator::with_dim(method, dim, options(method, dim)).unwrap();
    let mut rec = Recorder::with_grid((0..=120).map(|i| i as f64 * 0.25).collect());
    rec.record_steps = true;
    let rep = solve(
        &mut integ,
        &Chain,
        0.0,
        &initial(dim),
        30.0,
        &Crossings,
        &mut rec,
    )
    .unwrap();
    let mut points = Vec::new();
    for (t, y) in rec.outputs.iter().chain(rec.steps.iter()) {
        bits(*t, y, &mut points);
    }
    bits(rep.t, &rep.y, &mut points);
    let mut events = Vec::new();
    for h in &rec.events {
        events.push((h.index, h.t.to_bits(), h.direction));
        bits(h.t, &h.y, &mut points);
    }
    Fingerprint {
        points,
        events,
        stats: rep.stats,
    }
}

/// The hybrid loop by hand: step, detect, truncate, reset map, restart
/// keeping the step; dense output in the middle of every step.
fn run_hybrid<D: Dim>(method: Method, dim: D) -> Fingerprint
where
    DefaultAllocator: Allocator<D>,
{
    let mut integ = AnyIntegrator::with_dim(method, dim, options(method, dim)).unwrap();
    // A wall at x_0 = 0.12: impact reverses the first velocity.
    let m = dim.value() / 2;
    let wall = EventFns::new([Direction::Rising], |_i, _t, y: &OVector<f64, D>| {
        y[0] - 0.12
    })
    .with_derivative(move |_i, _t, y: &OVector<f64, D>, _dy: &OVector<f64, D>| y[m]);
    let mut state = EventState::new();
    let opts = EventOptions::default();
    integ.reset(&Chain, 0.0, &initial(dim), false).unwrap();
    let (mut points, mut events) = (Vec::new(), Vec::new());
    let mut mid = initial(dim);
    let mut y = initial(dim);
    while integ.t() < 30.0 {
        integ.step(&Chain, 30.0).unwrap();
        let tm = 0.5 * (integ.t_prev() + integ.t());
        integ.dense(&Chain, tm, &mut mid);
        bits(tm, &mid, &mut points);
        if let Some(hit) = find_first_event(&mut integ, &Chain, &wall, &opts, &mut state).unwrap() {
            events.push((hit.index, hit.t.to_bits(), hit.direction));
            let t_hit = hit.t;
            y.copy_from(&hit.y);
            integ.truncate(&Chain, t_hit).unwrap();
            y[m] *= -0.9;
            integ.reset(&Chain, t_hit, &y, true).unwrap();
            state.reset();
        }
        bits(integ.t(), integ.y(), &mut points);
    }
    Fingerprint {
        points,
        events,
        stats: *integ.stats(),
    }
}

fn compare<const N: usize>() {
    for method in Method::ALL {
        let fixed = run_solve(method, Const::<N>);
        let dynamic = run_solve(method, Dyn(N));
        assert!(fixed.events.len() > 10, "{}", method.name());
        assert_eq!(fixed, dynamic, "solve, {}, N = {N}", method.name());
        let fixed = run_hybrid(method, Const::<N>);
        let dynamic = run_hybrid(method, Dyn(N));
        assert!(!fixed.events.is_empty(), "{}", method.name());
        assert_eq!(fixed, dynamic, "hybrid loop, {}, N = {N}", method.name());
        println!(
            "N = {N}, {}: {} events, {:?}",
            method.name(),
            fixed.events.len(),
            fixed.stats
        );
    }
}

#[test]
fn dyn_and_fixed_dimensions_are_bitwise_identical() {
    compare::<2>();
    compare::<6>();
    compare::<20>();
}

#[test]
fn constructors_for_fixed_and_run_time_dimensions() {
    // new() for fixed sizes, with_dim() for any.
    let a = Dop853::<Const<3>>::new(Options::default()).unwrap();
    let b = Dop853::with_dim(Dyn(3), Options::default()).unwrap();
    assert_eq!(a.dim(), Const::<3>);
    assert_eq!(b.dim(), Dyn(3));
    assert!(Dopri5::with_dim(Dyn(3), Options::default()).is_ok());
    assert!(Rk4::with_dim(Dyn(3), Options::fixed(0.1)).is_ok());
    assert_eq!(
        AnyIntegrator::with_dim(Method::Dopri5, Dyn(5), Options::default())
            .unwrap()
            .dim(),
        Dyn(5)
    );
    assert_eq!(Const::<3>::name(), a.dim());
    // Closures with DVector arguments are systems.
    let osc = |_t: f64, y: &DVector<f64>, dy: &mut DVector<f64>| {
        dy[0] = y[1];
        dy[1] = -y[0];
    };
    let mut integ = Dop853::with_dim(Dyn(2), Options::with_tol(1e-12, 1e-12)).unwrap();
    let rep = solve(
        &mut integ,
        &osc,
        0.0,
        &DVector::from_vec(vec![1.0, 0.0]),
        1.0,
        &jeffcott::ode::NoEvents,
        &mut (),
    )
    .unwrap();
    assert!((rep.y[0] - 1f64.cos()).abs() < 1e-11);
    // ... and SVector closures still are, through new().
    let osc2 = |_t: f64, y: &SVector<f64, 2>, dy: &mut SVector<f64, 2>| {
        dy[0] = y[1];
        dy[1] = -y[0];
    };
    let mut integ = Dop853::new(Options::with_tol(1e-12, 1e-12)).unwrap();
    integ
        .reset(&osc2, 0.0, &SVector::<f64, 2>::new(1.0, 0.0), false)
        .unwrap();
    integ.step(&osc2, 1.0).unwrap();
}

#[test]
fn wrong_lengths_are_typed_errors() {
    let osc = |_t: f64, y: &DVector<f64>, dy: &mut DVector<f64>| {
        dy[0] = y[1];
        dy[1] = -y[0];
    };
    let per = |n: usize| Tolerance::PerComponent(DVector::from_element(n, 1e-9));
    let e = Dop853::with_dim(Dyn(2), Options::default().with_atol(per(3))).unwrap_err();
    assert_eq!(
        e,
        OdeError::DimensionMismatch {
            field: "atol",
            expected: 2,
            found: 3
        }
    );
    let e = Dopri5::with_dim(Dyn(2), Options::default().with_rtol(per(1))).unwrap_err();
    assert!(matches!(
        e,
        OdeError::DimensionMismatch { field: "rtol", .. }
    ));
    assert!(e.to_string().contains("with_dim"), "{e}");

    let mut integ = Dop853::with_dim(Dyn(2), Options::default()).unwrap();
    let e = integ
        .reset(&osc, 0.0, &DVector::from_vec(vec![1.0, 0.0, 0.0]), false)
        .unwrap_err();
    assert_eq!(
        e,
        OdeError::DimensionMismatch {
            field: "y0",
            expected: 2,
            found: 3
        }
    );
    // solve reports it with the given initial point.
    let e = solve(
        &mut integ,
        &osc,
        0.0,
        &DVector::from_vec(vec![1.0]),
        1.0,
        &jeffcott::ode::NoEvents,
        &mut (),
    )
    .unwrap_err();
    assert!(matches!(
        e.error,
        OdeError::DimensionMismatch { found: 1, .. }
    ));
    // dense() into a vector of the wrong length: replaced, no panic.
    integ
        .reset(&osc, 0.0, &DVector::from_vec(vec![1.0, 0.0]), false)
        .unwrap();
    integ.step(&osc, 1.0).unwrap();
    let mut out = DVector::zeros(0);
    integ.dense(&osc, 0.5 * integ.t(), &mut out);
    assert_eq!(out.len(), 2);
    assert!((out[0] - (0.5 * integ.t()).cos()).abs() < 1e-8);
}

#[test]
fn event_state_follows_the_dimension() {
    // One EventState used with integrators of two sizes: its scratch is
    // resized on first use with each.
    let mut state = EventState::<Dyn>::new();
    let g = EventFns::new([Direction::Falling], |_i, _t, y: &DVector<f64>| y[0]);
    for n in [2, 5] {
        let osc = |_t: f64, y: &DVector<f64>, dy: &mut DVector<f64>| {
            dy.fill(0.0);
            dy[0] = y[1];
            dy[1] = -y[0];
        };
        let mut integ = Dop853::with_dim(Dyn(n), Options::with_tol(1e-12, 1e-12)).unwrap();
        let mut y0 = DVector::zeros(n);
        y0[0] = 1.0;
        integ.reset(&osc, 0.0, &y0, false).unwrap();
        state.reset();
        let t_hit = loop {
            integ.step(&osc, 3.0).unwrap();
            if let Some(hit) =
                find_first_event(&mut integ, &osc, &g, &EventOptions::default(), &mut state)
                    .unwrap()
            {
                assert_eq!(hit.y.len(), n);
                break hit.t;
            }
        };
        assert!(
            (t_hit - std::f64::consts::FRAC_PI_2).abs() < 1e-10,
            "{t_hit}"
        );
    }
}
