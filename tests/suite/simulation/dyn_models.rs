//! Models whose size is known at run time: the paper's model run as a `Dyn` model gives
//! bitwise the same trajectory as the fixed-size one, its run allocates nothing per step, and
//! its ring position can be declared algebraic.

use jeffcott::hybrid::{
    simulate, DenseSampling, ExactSegment, Flow, GuardCrossing, ModelError, OutputPlan, RotorModel,
    SimOptions, SimStats, StrobeRange, Trajectory,
};
use jeffcott::nalgebra::{DVector, Dyn, U6};
use jeffcott::numeric::Direction;
use jeffcott::paper::{Cache, FreeSegment, Mode};
use jeffcott::params::{Params, Preset};
use jeffcott::{JeffcottModel, State};

/// The paper's model on `DVector` states of length 6: every call copies the state into a
/// fixed-size one (on the stack) and the result back.
struct DynPaper {
    inner: JeffcottModel,
    /// Whether the ring position (components 4, 5) is declared algebraic.
    algebraic_ring: bool,
}

fn fixed(y: &DVector<f64>) -> State {
    State::from_column_slice(y.as_slice())
}

/// Free flight of the paper's model, on `DVector` states.
struct DynSegment(FreeSegment);

impl ExactSegment<Dyn> for DynSegment {
    fn eval(&self, t: f64, y: &mut DVector<f64>, dy: &mut DVector<f64>) {
        let (mut a, mut b) = (State::zeros(), State::zeros());
        self.0.eval(t, &mut a, &mut b);
        y.copy_from_slice(a.as_slice());
        dy.copy_from_slice(b.as_slice());
    }
    fn next_guard(&mut self, t_from: f64, t_to: f64) -> Option<GuardCrossing> {
        self.0.next_guard(t_from, t_to)
    }
    fn evaluations(&self) -> u64 {
        ExactSegment::<U6>::evaluations(&self.0)
    }
}

impl RotorModel for DynPaper {
    type Dim = Dyn;
    type Mode = Mode;
    type Segment = DynSegment;
    type Cache = Cache;

    fn dim(&self) -> Dyn {
        Dyn(6)
    }
    fn new_cache(&self) -> Cache {
        self.inner.new_cache()
    }
    fn is_algebraic(&self, i: usize) -> bool {
        self.algebraic_ring && i >= 4
    }
    fn initial_mode(&self, t: f64, y: &DVector<f64>) -> Result<Mode, ModelError> {
        self.inner.initial_mode(t, &fixed(y))
    }
    fn flow(&self, mode: Mode) -> Flow {
        self.inner.flow(mode)
    }
    fn rhs(&self, mode: Mode, t: f64, y: &DVector<f64>, dy: &mut DVector<f64>, cache: &Cache) {
        let mut d = State::zeros();
        self.inner.rhs(mode, t, &fixed(y), &mut d, cache);
        dy.copy_from_slice(d.as_slice());
    }
    fn guard_count(&self, mode: Mode) -> usize {
        self.inner.guard_count(mode)
    }
    fn guard_direction(&self, mode: Mode, i: usize) -> Direction {
        self.inner.guard_direction(mode, i)
    }
    fn guard_value(&self, mode: Mode, i: usize, t: f64, y: &DVector<f64>, cache: &Cache) -> f64 {
        self.inner.guard_value(mode, i, t, &fixed(y), cache)
    }
    fn guard_derivative(
        &self,
        mode: Mode,
        i: usize,
        t: f64,
        y: &DVector<f64>,
        dy: &DVector<f64>,
        cache: &Cache,
    ) -> Option<f64> {
        self.inner
            .guard_derivative(mode, i, t, &fixed(y), &fixed(dy), cache)
    }
    fn guard_derivative_needs_rhs(&self) -> bool {
        self.inner.guard_derivative_needs_rhs()
    }
    fn guard_derivative_needs_rhs_of(&self, mode: Mode, i: usize) -> bool {
        self.inner.guard_derivative_needs_rhs_of(mode, i)
    }
    fn guard_label(&self, mode: Mode, i: usize) -> &'static str {
        self.inner.guard_label(mode, i)
    }
    fn transition(
        &self,
        mode: Mode,
        guard: usize,
        t: f64,
        y: &mut DVector<f64>,
    ) -> Result<Mode, ModelError> {
        let mut s = fixed(y);
        let next = self.inner.transition(mode, guard, t, &mut s);
        y.copy_from_slice(s.as_slice());
        next
    }
    fn start_segment(&self, mode: Mode, t: f64, y: &DVector<f64>) -> DynSegment {
        DynSegment(self.inner.start_segment(mode, t, &fixed(y)))
    }
    fn project(&self, mode: Mode, t: f64, y: &mut DVector<f64>, cache: &Cache) {
        let mut s = fixed(y);
        self.inner.project(mode, t, &mut s, cache);
        y.copy_from_slice(s.as_slice());
    }
    fn mode_label(&self, mode: Mode) -> u8 {
        self.inner.mode_label(mode)
    }
    fn forcing_period(&self) -> f64 {
        self.inner.forcing_period()
    }
}

fn models(p: Params) -> (JeffcottModel, DynPaper) {
    let m = JeffcottModel::new(p).unwrap();
    let d = DynPaper {
        inner: m.clone(),
        algebraic_ring: false,
    };
    (m, d)
}

fn plan(p: &Params, periods: u64, dense: bool) -> OutputPlan {
    let period = p.forcing_period();
    OutputPlan {
        t_end: period * periods as f64,
        strobe: Some(StrobeRange {
            first: 0,
            last: periods,
        }),
        dense: dense.then_some(DenseSampling {
            t_start: period * (periods - 3) as f64,
            dt: period / 200.0,
        }),
        events: true,
    }
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

#[test]
fn the_paper_model_as_a_dyn_model_gives_bitwise_the_same_run() {
    // Chaotic (Fig. 9d), period 1 with preload crossings (Fig. 10b), and DOPRI5 / RK4.
    let cases = [
        (Preset::Fig9d.params(), SimOptions::default()),
        (Preset::Fig10b.params(), SimOptions::default()),
        (
            Preset::Fig8b.params().with_eta(3.0),
            SimOptions::default().with_method(jeffcott::ode::Method::Dopri5),
        ),
        (
            Preset::Fig8b.params().with_eta(3.0),
            SimOptions::default().with_method(jeffcott::ode::Method::Rk4),
        ),
    ];
    for (p, opts) in cases {
        let (m, d) = models(p);
        let plan = plan(&p, 60, true);
        let mut a = Trajectory::default();
        let sa = simulate(&m, 0.0, &State::zeros(), &plan, &opts, &mut a).unwrap();
        let mut b = Trajectory::default();
        let sb = simulate(&d, 0.0, &DVector::zeros(6), &plan, &opts, &mut b).unwrap();
        assert_eq!(sa, sb, "{:?}", opts.method);
        assert!(sa.transitions >= 30, "{sa:?}");
        assert_eq!(a.strobe.len(), b.strobe.len());
        for (x, y) in a.strobe.iter().zip(&b.strobe) {
            assert_eq!((x.k, x.t.to_bits(), x.label), (y.k, y.t.to_bits(), y.label));
            assert_eq!(bits(x.y.as_slice()), bits(y.y.as_slice()), "k = {}", x.k);
        }
        assert_eq!(a.samples.len(), b.samples.len());
        assert!(!a.samples.is_empty());
        for (x, y) in a.samples.iter().zip(&b.samples) {
            assert_eq!(x.t.to_bits(), y.t.to_bits());
            assert_eq!(bits(x.y.as_slice()), bits(y.y.as_slice()));
            assert_eq!(bits(x.dy.as_slice()), bits(y.dy.as_slice()));
        }
        assert_eq!(a.events.len(), b.events.len());
        for (x, y) in a.events.iter().zip(&b.events) {
            assert_eq!((x.t.to_bits(), x.kind, x.to), (y.t.to_bits(), y.kind, y.to));
            assert_eq!(bits(x.after.as_slice()), bits(y.after.as_slice()));
        }
    }
}

/// Allocations made by a run of `periods` forcing periods with an observer that stores
/// nothing.
fn allocations(d: &DynPaper, p: &Params, periods: u64) -> (u64, SimStats) {
    let plan = plan(p, periods, true);
    let y0 = DVector::zeros(6);
    let mut stats = SimStats::default();
    let info = allocation_counter::measure(|| {
        stats = simulate(d, 0.0, &y0, &plan, &SimOptions::default(), &mut ()).unwrap();
    });
    (info.count_total, stats)
}

#[test]
fn a_dyn_run_allocates_only_when_it_starts() {
    // Free flight, contact, preload crossings, strobes, dense samples and events: the number of
    // allocations does not grow with the length of the run.
    let p = Preset::Fig10b.params();
    let (_, d) = models(p);
    let (short, s_short) = allocations(&d, &p, 5);
    let (long, s_long) = allocations(&d, &p, 100);
    assert!(
        s_long.steps > 20 * s_short.steps.max(1) / 2,
        "{s_short:?} {s_long:?}"
    );
    assert!(s_long.transitions > 100, "{s_long:?}");
    assert_eq!(
        short, long,
        "allocations grow with the run: {short} vs {long}"
    );
    eprintln!(
        "{long} allocations for {} steps, {} transitions",
        s_long.steps, s_long.transitions
    );
    // A handful at the start (integrator, event state, scratch, caches), not thousands.
    assert!(long < 64, "{long} allocations");
}

#[test]
fn an_algebraic_ring_is_left_out_of_the_error_control() {
    // Declaring the ring position algebraic (it is set by `project`, its integrated value only
    // follows the ring's velocity) changes the step-size control, not the solution beyond the
    // tolerance.
    let p = Preset::Fig8b.params().with_eta(2.0);
    let (m, mut d) = models(p);
    d.algebraic_ring = true;
    let plan = plan(&p, 200, false);
    let opts = SimOptions::default();
    let mut a = Trajectory::default();
    let sa = simulate(&m, 0.0, &State::zeros(), &plan, &opts, &mut a).unwrap();
    let mut b = Trajectory::default();
    let sb = simulate(&d, 0.0, &DVector::zeros(6), &plan, &opts, &mut b).unwrap();
    assert!(sb.transitions > 100, "{sb:?}");
    let worst = a
        .strobe
        .iter()
        .zip(&b.strobe)
        .map(|(x, y)| {
            x.y.iter()
                .zip(y.y.iter())
                .map(|(u, v)| (u - v).abs())
                .fold(0.0, f64::max)
        })
        .fold(0.0, f64::max);
    // Both runs are accurate to ~1e-9 here (docs/accuracy.md: rtol 1e-10 gives ~1e-9 on the
    // period-1 orbit of Fig. 8b).
    assert!(worst < 1e-7, "{worst:e}");
    assert_ne!(sa.steps, 0);
    eprintln!(
        "ring error-controlled: {} steps, {} rhs; algebraic: {} steps, {} rhs; max diff {worst:e}",
        sa.steps, sa.rhs_evals, sb.steps, sb.rhs_evals
    );
}
