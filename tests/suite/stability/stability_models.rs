//! The linearisation through the `Variational` trait for other models than the paper's
//! analytic one: a user's rotor on the ring (`rotor::RingedRotor`, integrated free flight, its
//! own field differenced), the same with a dimension known at run time (`Dyn`), the paper's
//! model with every finite-difference default of the trait, and a slow ring that has not
//! relaxed when the rotor meets it again (its sensitivity carried in closed form).

use crate::rotor;

use jeffcott::hybrid::{ModelError, RotorModel, SimOptions, Variational, VariationalAlloc};
use jeffcott::nalgebra::DefaultAllocator;
use jeffcott::nalgebra::{DMatrix, DVector, Dyn, OVector, SVector, Vector2, U6};
use jeffcott::numeric::Direction;
use jeffcott::paper::{Cache, FreeSegment, JeffcottModel, Mode, State};
use jeffcott::params::Preset;
use jeffcott::ring::Kinematics;
use jeffcott::rotor::{RingedRotor, SmoothRotor};
use jeffcott::stability::{multipliers, periodic_orbit, OrbitOptions, StroboscopicMap};

const CHECK: [f64; 4] = [0.5781094858, -0.0232587983, 0.0944197873, -0.3099208533];

fn tight() -> SimOptions {
    SimOptions::default().with_rtol(1e-13).with_atol(1e-15)
}

/// Richardson central differences of P^n on z at `y`.
pub(super) fn fd_jacobian<M>(
    map: &StroboscopicMap<'_, M>,
    y: &OVector<f64, M::Dim>,
    h: f64,
) -> DMatrix<f64>
where
    M: Variational,
    DefaultAllocator: VariationalAlloc<M::Dim>,
{
    let z = map.reduce(y);
    let p = |z: &DVector<f64>| map.reduce(&map.advance(&map.state(y, z)).unwrap().y);
    let mut jac = DMatrix::zeros(z.len(), z.len());
    for j in 0..z.len() {
        let central = |h: f64| {
            let (mut a, mut b) = (z.clone(), z.clone());
            a[j] += h;
            b[j] -= h;
            (p(&a) - p(&b)) / (2.0 * h)
        };
        jac.set_column(j, &((central(0.5 * h) * 4.0 - central(h)) / 3.0));
    }
    jac
}

fn check_state<M: RotorModel<Dim = U6>>(_: &M) -> SVector<f64, 6> {
    SVector::from([CHECK[0], CHECK[1], CHECK[2], CHECK[3], 0.0, 0.0])
}

#[test]
fn a_user_rotor_on_the_ring_has_the_paper_models_multipliers() {
    // Without cross-coupling and cubic term the user's rotor is the paper's model with an
    // integrated free flight.
    let p = Preset::Fig8a.params().with_eta(2.0);
    let model = rotor::on_ring(p, 0.0, 0.0).unwrap();
    let opts = OrbitOptions::default().with_sim(tight());
    let orbit = periodic_orbit(&model, &check_state(&model), 1, &opts).unwrap();
    // tests/data/stability_reference.csv (independent; its error 7e-11).
    let want = [
        0.7311493467511,
        0.6746058590190,
        0.6746058590190,
        0.6235630127494,
    ];
    let off = orbit
        .multipliers
        .iter()
        .zip(want)
        .fold(0.0f64, |a, (m, w)| a.max((m.modulus() - w).abs()));
    eprintln!("user rotor on the ring: multipliers {off:.1e} from the reference's");
    // Measured: 5.1e-11 (the integrated free flight).
    assert!(off < 2e-10, "{off:e}");
    for (a, b) in orbit.point.iter().zip(CHECK) {
        assert!((a - b).abs() < 2e-10);
    }
}

#[test]
fn a_nonlinear_user_rotor_jacobian_matches_differences() {
    // Cross-coupled stiffness and a cubic bearing: the rotor's own field by differences.
    let p = Preset::Fig8b.params().with_eta(2.0);
    let model = rotor::on_ring(p, 0.08, 0.5).unwrap();
    let y = StroboscopicMap::new(&model, 200, SimOptions::default())
        .unwrap()
        .advance(&SVector::zeros())
        .unwrap()
        .y;
    let map = StroboscopicMap::new(&model, 1, tight()).unwrap();
    let (mut worst, mut events) = (0.0f64, 0);
    let mut y = y;
    for _ in 0..4 {
        let lin = map.linearize(&y).unwrap();
        events += lin.events.len();
        worst = worst.max((&lin.jacobian - fd_jacobian(&map, &y, 1e-4)).abs().max());
        y = lin.y;
    }
    eprintln!("cross-coupled cubic rotor: |DP - FD| = {worst:e}, {events} events");
    assert!(events >= 4);
    // Measured: 6.2e-10 (the field's differences at h = 1e-5 are good to ~1e-9 relative).
    assert!(worst < 2e-9, "{worst:e}");
}

/// The user's rotor with a dimension known at run time.
struct DynRotor(rotor::CrossCoupledRotor);

impl SmoothRotor for DynRotor {
    type Dim = Dyn;
    fn dim(&self) -> Dyn {
        Dyn(6)
    }
    fn rhs(&self, t: f64, y: &DVector<f64>, dy: &mut DVector<f64>) {
        let ys = SVector::<f64, 6>::from_column_slice(y.as_slice());
        let mut d = SVector::<f64, 6>::zeros();
        self.0.rhs(t, &ys, &mut d);
        dy.copy_from_slice(d.as_slice());
    }
    fn station(&self, y: &DVector<f64>) -> Kinematics {
        Kinematics::new([y[0], y[1]], [y[2], y[3]])
    }
    fn add_station_force(&self, _y: &DVector<f64>, f: &Vector2<f64>, dy: &mut DVector<f64>) {
        dy[2] += f.x;
        dy[3] += f.y;
    }
    fn ring_slots(&self) -> [usize; 2] {
        [4, 5]
    }
    fn forcing_period(&self) -> f64 {
        self.0.forcing_period()
    }
}

#[test]
fn a_dynamic_dimension_gives_the_same_linearisation() {
    let p = Preset::Fig8b.params().with_eta(2.0);
    let fixed = rotor::on_ring(p, 0.08, 0.5).unwrap();
    let dynamic = RingedRotor::new(DynRotor(fixed.rotor().clone()), *fixed.ring()).unwrap();
    let y = check_state(&fixed);
    let lf = StroboscopicMap::new(&fixed, 1, SimOptions::default())
        .unwrap()
        .linearize(&y)
        .unwrap();
    let yd = DVector::from_column_slice(y.as_slice());
    let ld = StroboscopicMap::new(&dynamic, 1, SimOptions::default())
        .unwrap()
        .linearize(&yd)
        .unwrap();
    assert_eq!(lf.value, ld.value);
    assert_eq!(lf.jacobian, ld.jacobian);
}

/// The paper's model through every finite-difference default of `Variational` (only the ring's
/// slots declared algebraic).
struct Differenced(JeffcottModel);

impl RotorModel for Differenced {
    type Dim = U6;
    type Mode = Mode;
    type Segment = FreeSegment;
    type Cache = Cache;
    fn dim(&self) -> U6 {
        U6
    }
    fn new_cache(&self) -> Cache {
        self.0.new_cache()
    }
    fn initial_mode(&self, t: f64, y: &State) -> Result<Mode, ModelError> {
        self.0.initial_mode(t, y)
    }
    fn flow(&self, mode: Mode) -> jeffcott::hybrid::Flow {
        self.0.flow(mode)
    }
    fn rhs(&self, mode: Mode, t: f64, y: &State, dy: &mut State, cache: &Cache) {
        self.0.rhs(mode, t, y, dy, cache)
    }
    fn guard_count(&self, mode: Mode) -> usize {
        self.0.guard_count(mode)
    }
    fn guard_direction(&self, mode: Mode, i: usize) -> Direction {
        self.0.guard_direction(mode, i)
    }
    fn guard_value(&self, mode: Mode, i: usize, t: f64, y: &State, cache: &Cache) -> f64 {
        self.0.guard_value(mode, i, t, y, cache)
    }
    fn guard_label(&self, mode: Mode, i: usize) -> &'static str {
        self.0.guard_label(mode, i)
    }
    fn transition(
        &self,
        mode: Mode,
        guard: usize,
        t: f64,
        y: &mut State,
    ) -> Result<Mode, ModelError> {
        self.0.transition(mode, guard, t, y)
    }
    fn start_segment(&self, mode: Mode, t: f64, y: &State) -> FreeSegment {
        self.0.start_segment(mode, t, y)
    }
    fn project(&self, mode: Mode, t: f64, y: &mut State, cache: &Cache) {
        self.0.project(mode, t, y, cache)
    }
    fn mode_label(&self, mode: Mode) -> u8 {
        self.0.mode_label(mode)
    }
    fn forcing_period(&self) -> f64 {
        self.0.forcing_period()
    }
}

impl Variational for Differenced {
    fn is_algebraic_variation(&self, i: usize) -> bool {
        i >= 4
    }
    fn section_state(&self, t: f64, template: &State, z: &[f64]) -> State {
        self.0.section_state(t, template, z)
    }
}

#[test]
fn the_finite_difference_defaults_reproduce_the_analytic_linearisation() {
    // Differences of the field, the guards, the transitions, the free flight's closed form and
    // the projection. The ring has relaxed at every onset here, so the guards'
    // differences (blind to the ring's slots) lose nothing.
    for (preset, eta) in [(Preset::Fig8a, 2.0), (Preset::Fig10d, 3.0)] {
        let p = preset.params().with_eta(eta);
        let analytic = JeffcottModel::new(p).unwrap();
        let differenced = Differenced(JeffcottModel::new(p).unwrap());
        let y = if eta == 2.0 {
            analytic
                .state_at([CHECK[0], CHECK[1]], [CHECK[2], CHECK[3]])
                .unwrap()
        } else {
            StroboscopicMap::new(&analytic, 300, SimOptions::default())
                .unwrap()
                .advance(&State::zeros())
                .unwrap()
                .y
        };
        let a = StroboscopicMap::new(&analytic, 2, SimOptions::default())
            .unwrap()
            .linearize(&y)
            .unwrap();
        let d = StroboscopicMap::new(&differenced, 2, SimOptions::default())
            .unwrap()
            .linearize(&y)
            .unwrap();
        // The differences of the field share the model's cache (warm starts of the ring's
        // multiplier in regime III): the trajectories agree to rounding.
        assert!((a.y - d.y).amax() < 1e-12);
        let diff = (&a.jacobian - &d.jacobian).abs().max();
        let kinds: Vec<_> = a.events.iter().map(|e| e.kind).collect();
        eprintln!("{preset} eta {eta}: |analytic - differenced| = {diff:e}, events {kinds:?}");
        // Measured: 5.9e-10 and 2.9e-10.
        assert!(diff < 2e-9, "{diff:e}");
    }
}

#[test]
fn a_slow_ring_carries_its_sensitivity_to_the_next_onset() {
    // nu2 = 10: the ring's time constant 2 nu2/K = 0.67 is a fifth of a forcing period, so the
    // ring has not relaxed when the rotor meets it again, and the onset depends on where it was
    // released. Over two periods a loss and the next onset fall inside the map: the ring's
    // closed-form sensitivity carries the first to the second.
    let mut p = Preset::Fig8a.params().with_eta(2.0);
    p.nu2 = 10.0;
    let model = JeffcottModel::new(p).unwrap();
    let y = StroboscopicMap::new(&model, 200, SimOptions::default())
        .unwrap()
        .advance(&State::zeros())
        .unwrap()
        .y;
    let map = StroboscopicMap::new(&model, 2, tight()).unwrap();
    let lin = map.linearize(&y).unwrap();
    let fd = fd_jacobian(&map, &y, 1e-4);
    let diff = (&lin.jacobian - &fd).abs().max();
    // The differencing defaults do not see the ring through the onset guard (it reads the
    // relaxation, not the state) nor its decay: they must be wrong here.
    let blind = Differenced(JeffcottModel::new(p).unwrap());
    let lb = StroboscopicMap::new(&blind, 2, tight())
        .unwrap()
        .linearize(&y)
        .unwrap();
    let wrong = (&lb.jacobian - &fd).abs().max();
    eprintln!(
        "nu2 = 10: |DP - FD| = {diff:e}, without the ring's sensitivity {wrong:e}, |DP| = {:.3}, \
         events {:?}",
        lin.jacobian.abs().max(),
        lin.events.iter().map(|e| (e.kind, e.t)).collect::<Vec<_>>()
    );
    // Measured: 2.1e-11, and 1.9e-4 without the ring's sensitivity.
    assert!(diff < 1e-10, "{diff:e}");
    assert!(wrong > 1e3 * diff.max(1e-9), "{wrong:e}");
    let _ = multipliers(&lin.jacobian).unwrap();
}
