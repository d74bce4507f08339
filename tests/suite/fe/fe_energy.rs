//! Energy balance of finite-element rotors on the ring, with contact: a truth that does not
//! come from the integrator's own error estimate.
//!
//! With $q$ the coordinates, $v = q^\prime$, $s$ the ring's centre and $f$ the ring's force
//! (the rotor feels $-f$ at the station, whose velocity is $r^\prime$),
//!
//! $$E = \tfrac12 v^{\mathsf T} M v + \tfrac12 q^{\mathsf T} K_s q + E_\text{ring}(s),$$
//!
//! and along a run, with $K_a = \tfrac12(K - K^{\mathsf T})$, $D_s = \tfrac12(D + D^{\mathsf T})$
//! (the gyroscopic $\Omega G$ is skew and drops out), $C(s)$ the ring's damping ($4\nu_2$ on
//! an inner branch, $2\nu_2$ beyond the preload) and $g = \nabla E_\text{ring}$:
//!
//! * the rotor: $\frac{d}{dt}E_\text{rot} = v\cdot F(t) - v^{\mathsf T}D_s v -
//!   v^{\mathsf T}K_a q - f\cdot r^\prime$;
//! * the ring in contact: $f\cdot r^\prime = g\cdot s^\prime + s^{\prime\mathsf T}C
//!   s^\prime + f\cdot(r^\prime - s^\prime)$. The last term, the *slip* work, is the paper's
//!   model: the massless ring sits at the minimum of its elastic energy, so $g$ is along the
//!   normal, but its dampers' force $C s^\prime$ is not, and its tangential part acts on the
//!   rotor like a viscous friction against the tangential slip $r^\prime - s^\prime$ (the
//!   normal parts of $r^\prime$ and $s^\prime$ are equal: $|r - s| = \gamma$ holds). It is
//!   40 % of the dampers' own dissipation to more than all of it here: the rotor's work on
//!   the ring is *not* the change of the ring's elastic energy plus its dampers'
//!   dissipation alone;
//! * the ring in free flight: $f = 0$ and $g\cdot s^\prime = -s^{\prime\mathsf T}Cs^\prime$;
//! * at a touch the ring may jump to the minimiser of its energy (a ring not yet relaxed):
//!   $E_\text{ring}$ drops there, instantly.
//!
//! So $E(T) - E(0) = W_\text{in} - W_\text{visc} - W_\text{skew} - W_\text{damper} -
//! W_\text{slip} + \sum \Delta E_\text{ring, events}$. Every integrand is computed here from the
//! sampled states with the model's formulas written out again (not the crate's force), and
//! integrated by a local degree-5 interpolation (3-point Gauss on each interval between
//! samples), piecewise between the events of the driver's log (the integrands have kinks
//! and jumps there; their one-sided values come from the event's states). The free ring's
//! dissipation is integrated from its closed-form relaxation on panels of a quarter of its
//! time constant (it relaxes within $10^{-8}$ s on S1, far below any sample spacing).

use jeffcott::hybrid::{
    simulate, DenseSampling, EventRecord, HybridObserver, OutputPlan, RotorModel, Sample,
    SimOptions, SimStats,
};
use jeffcott::nalgebra::{Complex, DMatrix, DVector, Dyn, Vector2};
use jeffcott::ode::Method;
use jeffcott::ring::{Branches, Relaxation, RingCache, RingMode, SnubberRing};

use crate::energy::{axis_law, contact_branches, free_ring_dissipation, integrate_piece};
use jeffcott::rotor::{LinearRotor, MotorTorque, RingedRotor, SmoothRotor};

use super::fe_reduction_s1::reduced_model;
use super::fe_s1::S1;

/// The integrands (W): $v\cdot F$, $v^{\mathsf T}D_s v$, $v^{\mathsf T}K_a q$, $f\cdot
/// r^\prime$, $s^{\prime\mathsf T}Cs^\prime$, $g\cdot s^\prime$, $f\cdot(r^\prime - s^\prime)$.
const POWERS: usize = 7;
pub const INPUT: usize = 0;
const VISCOUS: usize = 1;
const SKEW: usize = 2;
const CONTACT: usize = 3;
pub const DAMPER: usize = 4;
const ELASTIC: usize = 5;
pub const SLIP: usize = 6;

/// The integrands and energies (kinetic, elastic of the rotor, of the ring) at one instant.
#[derive(Debug, Clone, Copy)]
struct Point {
    t: f64,
    label: u8,
    power: [f64; POWERS],
    energy: [f64; 3],
    ring: Vector2<f64>,
}

impl Point {
    fn total(&self) -> f64 {
        self.energy.iter().sum()
    }
}

/// A driven rotor's terms ([`jeffcott::rotor::DrivenLinearRotor`], `fe_drive`): the input is
/// the motor's power $T(\Omega)\Omega$ instead of $v\cdot F$, and the kinetic energy has the
/// spin's $\tfrac12 J\Omega^2$ and the out-of-balance's $\Omega\thinspace v\cdot b(\varphi)$,
/// $b = -\operatorname{Im}(\hat U e^{i\varphi})$, $\hat U = \hat F/\Omega_r^2$.
pub struct Drive {
    pub motor: MotorTorque,
    pub inertia: f64,
    /// The state's indices of $\Omega$ and $\varphi$.
    pub slots: [usize; 2],
    /// The symmetric part of $G$ (its damping at $\Omega - \Omega_r$; zero for a skew $G$).
    pub g_sym: DMatrix<f64>,
}

/// What the balance needs of a model: its matrices split into symmetric and skew parts.
pub struct Terms<'a, R> {
    model: &'a RingedRotor<R>,
    linear: &'a LinearRotor,
    drive: Option<Drive>,
    mass: DMatrix<f64>,
    k_sym: DMatrix<f64>,
    k_skew: DMatrix<f64>,
    d_sym: DMatrix<f64>,
}

impl<'a> Terms<'a, LinearRotor> {
    fn of(model: &'a RingedRotor<LinearRotor>) -> Self {
        Self::new(model, model.rotor(), None)
    }
}

impl<'a, R: SmoothRotor<Dim = Dyn>> Terms<'a, R> {
    /// The terms of `model`, whose linear part is `linear` (and drive `drive`).
    pub fn new(model: &'a RingedRotor<R>, linear: &'a LinearRotor, drive: Option<Drive>) -> Self {
        let s = linear.system();
        let sym = |a: &DMatrix<f64>| (a + a.transpose()) * 0.5;
        // The kinetic energy's rate is v^T M v' only for a symmetric M.
        assert!(asymmetry(s.mass()) <= 1e-14, "M is not symmetric");
        Self {
            model,
            linear,
            drive,
            mass: sym(s.mass()),
            k_sym: sym(s.stiffness()),
            k_skew: (s.stiffness() - s.stiffness().transpose()) * 0.5,
            d_sym: sym(s.damping()),
        }
    }

    /// $F(t) = \operatorname{Re}(\hat F e^{i\Omega t}) + f_0$.
    fn force(&self, t: f64) -> DVector<f64> {
        let s = self.linear.system();
        let e = Complex::from_polar(1.0, s.speed() * t);
        s.harmonic_force().map(|f| (f * e).re) + s.constant_force()
    }

    /// The integrands and energies at `(t, y)` with the state's derivative `dy` (the ring's
    /// velocity is its slots' derivative) in the mode labelled `label`.
    fn point(&self, t: f64, y: &DVector<f64>, dy: &DVector<f64>, label: u8) -> Point {
        let n = self.mass.nrows();
        let ring = self.model.ring();
        let (q, v) = (y.rows(0, n), y.rows(n, n));
        let [ix, iy] = self.linear.station_dofs();
        let r_dot = Vector2::new(v[ix], v[iy]);
        let s = Vector2::new(y[2 * n], y[2 * n + 1]);
        let s_dot = Vector2::new(dy[2 * n], dy[2 * n + 1]);
        let branches = contact_branches(ring, label, &s).unwrap_or(Branches::of(ring, &s));
        let (gx, cx, ex) = axis_law(&ring.x, ring.damping, branches.x, s.x);
        let (gy, cy, ey) = axis_law(&ring.y, ring.damping, branches.y, s.y);
        let (g, c) = (Vector2::new(gx, gy), Vector2::new(cx, cy));
        let f = if label == 1 {
            Vector2::zeros()
        } else {
            g + c.component_mul(&s_dot)
        };
        let (input, viscous, kinetic) = match &self.drive {
            None => (v.dot(&self.force(t)), v.dot(&(&self.d_sym * v)), 0.0),
            Some(d) => {
                let (w, phase) = (y[d.slots[0]], y[d.slots[1]]);
                let s = self.linear.system();
                let e = Complex::from_polar(1.0 / (s.speed() * s.speed()), phase);
                let b = s.harmonic_force().map(|u| -(u * e).im);
                let damping = &self.d_sym + &d.g_sym * (w - s.speed());
                let kinetic = 0.5 * d.inertia * w * w + w * v.dot(&b);
                (d.motor.torque(w) * w, v.dot(&(damping * v)), kinetic)
            }
        };
        let power = [
            input,
            viscous,
            v.dot(&(&self.k_skew * q)),
            f.dot(&r_dot),
            s_dot.dot(&c.component_mul(&s_dot)),
            g.dot(&s_dot),
            f.dot(&(r_dot - s_dot)),
        ];
        let energy = [
            0.5 * v.dot(&(&self.mass * v)) + kinetic,
            0.5 * q.dot(&(&self.k_sym * q)),
            ex + ey,
        ];
        Point {
            t,
            label,
            power,
            energy,
            ring: s,
        }
    }

    /// The one-sided point at an event's state `y` in the mode labelled `label` (the mode
    /// before or after the event): the derivative from the model's own vector field in that
    /// mode (contact on the label's branches, or the ring relaxing from where it is).
    fn event_point(&self, t: f64, y: &DVector<f64>, label: u8) -> Point {
        let n = self.mass.nrows();
        let ring = self.model.ring();
        let s = Vector2::new(y[2 * n], y[2 * n + 1]);
        let mode = match contact_branches(ring, label, &s) {
            Some(b) => RingMode::Contact(b),
            None => RingMode::free(Relaxation { t0: t, s0: s }),
        };
        let mut dy = DVector::zeros(y.len());
        self.model.rhs(mode, t, y, &mut dy, &RingCache::default());
        self.point(t, y, &dy, label)
    }
}

/// Records the points of a run's samples and events.
struct Recorder<'a, R> {
    terms: &'a Terms<'a, R>,
    samples: Vec<Point>,
    /// `(kind, before, after)`.
    events: Vec<(&'static str, Point, Point)>,
}

impl<R: SmoothRotor<Dim = Dyn>> HybridObserver<Dyn> for Recorder<'_, R> {
    fn on_sample(&mut self, s: &Sample<Dyn>) {
        self.samples
            .push(self.terms.point(s.t, &s.y, &s.dy, s.label));
    }
    fn on_event(&mut self, e: &EventRecord<Dyn>) {
        let before = self.terms.event_point(e.t, &e.before, e.from);
        let after = self.terms.event_point(e.t, &e.after, e.to);
        self.events.push((e.kind, before, after));
    }
}

/// The balance of a run: each term's integral (J) and the energies.
#[derive(Debug, Default)]
pub struct Balance {
    pub work: [f64; POWERS],
    /// $\int s^{\prime\mathsf T}Cs^\prime$ over free flight (the relaxing ring).
    pub free_damper: f64,
    /// $\int |v\cdot F|$.
    input_abs: f64,
    /// $\sum$ over events of $E_\text{ring}$ after minus before.
    ring_jumps: f64,
    /// $E(0)$, $E(T)$ by part (kinetic, rotor elastic, ring), and $\max_t E$.
    start: [f64; 3],
    end: [f64; 3],
    max_energy: f64,
    pieces: usize,
    pub contact_pieces: usize,
}

impl Balance {
    /// The samples strictly inside `(a, b)`, farther than a quarter spacing `h` from either
    /// end (a node closer to an end would make the interpolation amplify the data's noise).
    fn piece_nodes(
        samples: &[Point],
        start: &Point,
        end: &Point,
        h: f64,
    ) -> Vec<(f64, [f64; POWERS])> {
        let inside = samples
            .iter()
            .filter(|p| p.t > start.t + 0.25 * h && p.t < end.t - 0.25 * h);
        let mut nodes = vec![(start.t, start.power)];
        for p in inside {
            assert_eq!(p.label, start.label, "a sample at {} in another mode", p.t);
            nodes.push((p.t, p.power));
        }
        nodes.push((end.t, end.power));
        nodes
    }

    /// Adds the piece from `start` to `end` (one mode) given at `nodes`.
    fn add_piece(
        &mut self,
        ring: &SnubberRing,
        start: &Point,
        end: &Point,
        nodes: &[(f64, [f64; POWERS])],
    ) {
        let free = start.label == 1;
        for (p, w) in integrate_piece(nodes).into_iter().enumerate() {
            // The free ring's terms are integrated from its closed form below.
            if !(free && (p == DAMPER || p == ELASTIC)) {
                self.work[p] += w;
            }
        }
        if free {
            self.free_damper += free_ring_dissipation(ring, start.ring, start.t, end.t);
        } else {
            self.contact_pieces += 1;
        }
        self.pieces += 1;
        let abs: Vec<_> = nodes
            .iter()
            .map(|&(t, p)| (t, [p[INPUT].abs(), 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]))
            .collect();
        self.input_abs += integrate_piece(&abs)[INPUT];
    }

    /// The balance of a recorded run, sampled every `h`.
    fn of<R: SmoothRotor<Dim = Dyn>>(rec: &Recorder<R>, h: f64) -> Self {
        let (samples, ring) = (&rec.samples, rec.terms.model.ring());
        let (first, last) = (samples[0], samples[samples.len() - 1]);
        let mut b = Balance {
            start: first.energy,
            end: last.energy,
            max_energy: samples.iter().map(Point::total).fold(0.0, f64::max),
            ..Default::default()
        };
        let mut start = first;
        let ends = rec.events.iter().map(|e| (e.1, Some(e.2)));
        for (end, next) in ends.chain(std::iter::once((last, None))) {
            if end.t > start.t {
                b.add_piece(
                    ring,
                    &start,
                    &end,
                    &Self::piece_nodes(samples, &start, &end, h),
                );
            }
            if let Some(after) = next {
                b.ring_jumps += after.energy[2] - end.energy[2];
                start = after;
            }
        }
        b
    }

    /// The scale the residuals are measured against: the largest energy or the input's
    /// total work, whichever is larger.
    fn scale(&self) -> f64 {
        self.max_energy.max(self.input_abs)
    }

    /// $\Delta E_\text{rot} - (W_\text{in} - W_\text{visc} - W_\text{skew} - W_\text{contact})$.
    fn rotor_residual(&self) -> f64 {
        let de = self.end[0] + self.end[1] - self.start[0] - self.start[1];
        let w = &self.work;
        de - (w[INPUT] - w[VISCOUS] - w[SKEW] - w[CONTACT])
    }

    /// $\Delta E_\text{ring} - (\int_\text{contact} g\cdot s^\prime - \int_\text{free}
    /// s^{\prime\mathsf T}Cs^\prime + \text{jumps})$.
    fn ring_residual(&self) -> f64 {
        let de = self.end[2] - self.start[2];
        de - (self.work[ELASTIC] - self.free_damper + self.ring_jumps)
    }

    /// $\Delta E - (W_\text{in} - W_\text{visc} - W_\text{skew} - W_\text{damper} -
    /// W_\text{slip} + \text{jumps})$.
    pub fn system_residual(&self) -> f64 {
        let de: f64 = self.end.iter().sum::<f64>() - self.start.iter().sum::<f64>();
        let w = &self.work;
        let damper = w[DAMPER] + self.free_damper;
        de - (w[INPUT] - w[VISCOUS] - w[SKEW] - damper - w[SLIP] + self.ring_jumps)
    }

    pub fn report(&self, name: &str, stats: &SimStats) {
        let w = &self.work;
        println!(
            "{name}: {} steps, {} transitions, {} pieces ({} in contact)\n  \
             E(0) = {:.6e}, E(T) = {:.6e}, max E = {:.6e}, int |v.F| = {:.6e} J\n  \
             W_in {:.6e}, W_visc {:.6e}, W_skew {:.3e}, W_contact {:.6e}\n  \
             W_damper contact {:.6e} free {:.6e}, W_slip {:.6e}, ring jumps {:.3e}, \
             int g.s' (contact) {:.6e}\n  \
             residual / scale: rotor {:.2e}, ring {:.2e}, system {:.2e}",
            stats.steps,
            stats.transitions,
            self.pieces,
            self.contact_pieces,
            self.start.iter().sum::<f64>(),
            self.end.iter().sum::<f64>(),
            self.max_energy,
            self.input_abs,
            w[INPUT],
            w[VISCOUS],
            w[SKEW],
            w[CONTACT],
            w[DAMPER],
            self.free_damper,
            w[SLIP],
            self.ring_jumps,
            w[ELASTIC],
            self.rotor_residual() / self.scale(),
            self.ring_residual() / self.scale(),
            self.system_residual() / self.scale(),
        );
    }
}

/// Runs `model` from `y0` (made consistent) to `t_end`, sampled every `h`, and balances it.
fn run(
    model: &RingedRotor<LinearRotor>,
    y0: DVector<f64>,
    t_end: f64,
    h: f64,
    opts: &SimOptions,
) -> (Balance, SimStats, Vec<u8>) {
    run_terms(&Terms::of(model), y0, t_end, h, opts)
}

/// [`run`] for any rotor's terms.
pub fn run_terms<R: SmoothRotor<Dim = Dyn>>(
    terms: &Terms<R>,
    mut y0: DVector<f64>,
    t_end: f64,
    h: f64,
    opts: &SimOptions,
) -> (Balance, SimStats, Vec<u8>) {
    let model = terms.model;
    model.make_consistent(&mut y0).unwrap();
    let mut rec = Recorder {
        terms,
        samples: Vec::new(),
        events: Vec::new(),
    };
    let plan = OutputPlan {
        t_end,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: h,
        }),
        events: true,
    };
    let stats = simulate(model, 0.0, &y0, &plan, opts, &mut rec).unwrap();
    let last = rec.samples.last().unwrap().t;
    assert!(rec.samples[0].t == 0.0 && (last - t_end).abs() <= 1e-9 * t_end);
    let mut labels: Vec<u8> = rec.samples.iter().map(|p| p.label).collect();
    labels.extend(rec.events.iter().flat_map(|e| [e.1.label, e.2.label]));
    labels.sort_unstable();
    labels.dedup();
    (Balance::of(&rec, h), stats, labels)
}

pub fn options(method: Method, rtol: f64) -> SimOptions {
    SimOptions::default()
        .with_method(method)
        .with_rtol(rtol)
        .with_atol(rtol)
}

fn asymmetry(a: &DMatrix<f64>) -> f64 {
    (a - a.transpose()).amax() / a.amax().max(f64::MIN_POSITIVE)
}

/// The relative tolerance of every balance: measured 4e-14 to 9e-13 (see the report below).
const TOL: f64 = 1e-10;

/// Asserts the rotor's, the ring's and the whole system's balance within [`TOL`] of the
/// scale, and that the ring's terms are large enough for the balance to see them missing.
pub fn check(name: &str, b: &Balance, stats: &SimStats) {
    b.report(name, stats);
    let scale = b.scale();
    for (what, r) in [
        ("rotor", b.rotor_residual()),
        ("ring", b.ring_residual()),
        ("whole system", b.system_residual()),
    ] {
        assert!(
            (r / scale).abs() <= TOL,
            "{name}: the {what}'s energy balance is off by {r:.3e} J, {:.2e} of the scale \
             {scale:.3e} J",
            r / scale
        );
    }
    for (what, w) in [("damper", b.work[DAMPER]), ("slip", b.work[SLIP])] {
        assert!(
            w / scale > 1e3 * TOL,
            "{name}: the ring's {what} work {w:e} J is too small to test"
        );
    }
}

/// The preloaded ring of `fe_eccentric` with its centre beyond the gap (2 µm off, gap 1.5 µm:
/// the rotor starts in contact) on the undamped 42-DOF rotor, 0.2 s (5 revolutions): every
/// contact regime, two losses and two onsets.
fn case_42(method: Method) {
    let model = super::fe_eccentric::rotor_42(5e6, 50.0, [2e-7, 1e-7], 1.5e-6, [2e-6, 0.0]);
    let (b, stats, labels) = run(
        &model,
        model.rotor().rest_state(),
        0.2,
        2e-6,
        &options(method, 1e-10),
    );
    assert_eq!(
        labels,
        [1, 2, 3, 4, 5],
        "free flight and the regimes II to V"
    );
    assert!(
        b.pieces - b.contact_pieces >= 2,
        "{} free pieces",
        b.pieces - b.contact_pieces
    );
    assert_eq!(b.work[VISCOUS], 0.0, "C = 0 and G skew: no viscous work");
    assert!(b.free_damper / b.scale() > 1e3 * TOL, "{:e}", b.free_damper);
    check(&format!("42 DOF, {method:?} rtol 1e-10"), &b, &stats);
}

/// A heavily damped ring (c_s = 2e4 N s/m: it relaxes with the time constant c_s/k_s = 4 ms)
/// on the same rotor: the rotor touches it again before it has relaxed, and the touch places
/// it at the minimum of its energy over the disk $|r - s| \le \gamma$, a drop of its
/// elastic energy at the event (never a rise). Measured: the drops sum to -4.0e-9 J, 1.3e-5
/// of the scale; the slip work (1.6e-4 J) exceeds the dampers' (1.1e-4 J); the balance
/// closes to 7e-14 of the scale.
#[test]
fn energy_balance_42_dof_ring_not_relaxed_at_a_touch() {
    let model = super::fe_eccentric::rotor_42(5e6, 2e4, [2e-7, 1e-7], 1.5e-6, [2e-6, 0.0]);
    let opts = options(Method::Dop853, 1e-10);
    let (b, stats, labels) = run(&model, model.rotor().rest_state(), 0.2, 2e-6, &opts);
    assert_eq!(
        labels,
        [1, 2, 3, 4, 5],
        "free flight and the regimes II to V"
    );
    assert!(
        b.ring_jumps <= 0.0,
        "a touch raised the ring's energy by {:e} J",
        b.ring_jumps
    );
    assert!(
        -b.ring_jumps / b.scale() > 1e3 * TOL,
        "{:e} J",
        b.ring_jumps
    );
    check("42 DOF, damped ring, Dop853 rtol 1e-10", &b, &stats);
}

/// Measured: DOP853 4.4e-14 of the scale (0.7 s), with C = 0 every loss of energy is the
/// ring's: its dampers 2.7e-6 J in contact and 3.3e-10 J relaxing, the slip 1.0e-6 J.
#[test]
fn energy_balance_42_dof_preloaded_ring_dop853() {
    case_42(Method::Dop853);
}

/// Measured: Radau5 (its collocation polynomial as dense output) 6e-13 of the scale
/// (5 s: 1.5e5 steps, the undamped rotor's contact phases at rtol 1e-10).
#[test]
fn energy_balance_42_dof_preloaded_ring_radau5() {
    case_42(Method::Radau5);
}

/// S1 on 24 Craig-Bampton modes, 0.1 s (5 onsets, 4 losses), with DOP853 and Radau5:
/// measured 4e-15 and 7e-14 of the scale.
#[test]
fn energy_balance_s1_on_24_modes() {
    let model = reduced_model(&S1::load(), 24);
    for method in [Method::Dop853, Method::Radau5] {
        let (b, stats, labels) = run(
            &model,
            model.rotor().rest_state(),
            0.1,
            2e-6,
            &options(method, 1e-10),
        );
        assert_eq!(labels, [1, 5], "S1's ring has no preload");
        check(
            &format!("S1 on 24 modes, {method:?} rtol 1e-10"),
            &b,
            &stats,
        );
    }
}

/// The limits: each balance's residual against the sample spacing (quadrature) and the
/// tolerance (integration), DOP853.
#[test]
#[ignore = "a report, about 10 s: run with --ignored --nocapture"]
fn energy_balance_report() {
    let cases = [
        (
            "42 DOF",
            super::fe_eccentric::rotor_42(5e6, 50.0, [2e-7, 1e-7], 1.5e-6, [2e-6, 0.0]),
            0.2,
        ),
        ("S1, 24 modes", reduced_model(&S1::load(), 24), 0.1),
    ];
    println!("case | h (s) | rtol | rotor | ring | system (residual / scale)");
    for (name, model, t_end) in &cases {
        let runs = [2e-5, 1e-5, 4e-6, 2e-6]
            .map(|h| (h, 1e-10))
            .into_iter()
            .chain([1e-6, 1e-8, 1e-12].map(|rtol| (2e-6, rtol)));
        for (h, rtol) in runs {
            let opts = options(Method::Dop853, rtol);
            let (b, _, _) = run(model, model.rotor().rest_state(), *t_end, h, &opts);
            let scale = b.scale();
            println!(
                "{name} | {h:.0e} | {rtol:.0e} | {:.1e} | {:.1e} | {:.1e}",
                b.rotor_residual() / scale,
                b.ring_residual() / scale,
                b.system_residual() / scale
            );
        }
    }
}
