//! The energy balance of the non-ideal drive ([`DrivenJeffcott`]) with contact: a truth that
//! does not come from the integrator's own error estimate nor from the crate's force.
//!
//! With $t_\varphi = (-\sin\varphi, \cos\varphi)$ and the ring's energy $E_\text{ring}(s)$,
//!
//! $$E = \tfrac12|r^\prime|^2 + \tfrac12 j\eta^2 + \beta\eta\,r^\prime\cdot t_\varphi +
//! \tfrac12|r - e|^2 + E_\text{ring}(s)$$
//!
//! (the out-of-balance mass's kinetic energy is the cross term; this is the Lagrangian's
//! energy, written here from the physical picture, not the crate's). Along a run (as in
//! `tests/suite/fe/fe_energy.rs`, whose helpers `tests/support/energy.rs` are shared)
//!
//! $$E(T) - E(0) = \int t(\eta)\eta - \int 2\nu_1|r^\prime|^2 - \int_\text{contact}
//! s^{\prime\mathsf T}Cs^\prime - \int_\text{free} s^{\prime\mathsf T}Cs^\prime -
//! \int_\text{contact} f\cdot(r^\prime - s^\prime) + \sum\Delta E_\text{ring, touches}:$$
//!
//! the motor's work goes into the kinetic energy (translation, spin, out-of-balance), the
//! rotor's and the ring's elastic energies, the rotor's damping and the ring's dampers
//! (their force's tangential part acting on the slip, `fe_energy`'s docs say why).

use jeffcott::hybrid::{
    simulate, DenseSampling, EventRecord, HybridObserver, OutputPlan, RotorModel, Sample,
    SimOptions,
};
use jeffcott::nalgebra::{SVector, Vector2, U8};
use jeffcott::params::{Params, Preset};
use jeffcott::ring::{Branches, Relaxation, RingCache, RingMode};
use jeffcott::rotor::{DrivenJeffcott, MotorTorque, RingedRotor, ETA, PHASE};

use crate::energy::{axis_law, contact_branches, free_ring_dissipation, integrate_piece};

/// The integrands: the motor's power, the rotor's damping, the ring's dampers, $g\cdot
/// s^\prime$, the slip $f\cdot(r^\prime - s^\prime)$.
const N: usize = 5;
const MOTOR: usize = 0;
const VISCOUS: usize = 1;
const DAMPER: usize = 2;
const SLIP: usize = 4;

#[derive(Debug, Clone, Copy)]
struct Point {
    t: f64,
    label: u8,
    power: [f64; N],
    /// The rotor's (kinetic, spin, out-of-balance, elastic) and the ring's energy.
    energy: [f64; 2],
    ring: Vector2<f64>,
    eta: f64,
}

struct Terms<'a> {
    model: &'a RingedRotor<DrivenJeffcott>,
    p: Params,
    j: f64,
    motor: MotorTorque,
}

impl Terms<'_> {
    fn point(&self, t: f64, y: &SVector<f64, 8>, dy: &SVector<f64, 8>, label: u8) -> Point {
        let (p, ring) = (&self.p, self.model.ring());
        let (r, v) = (Vector2::new(y[0], y[1]), Vector2::new(y[2], y[3]));
        let (s, s_dot) = (Vector2::new(y[4], y[5]), Vector2::new(dy[4], dy[5]));
        let (eta, phase) = (y[ETA], y[PHASE]);
        let branches = contact_branches(ring, label, &s).unwrap_or(Branches::of(ring, &s));
        let (gx, cx, ex) = axis_law(&ring.x, ring.damping, branches.x, s.x);
        let (gy, cy, ey) = axis_law(&ring.y, ring.damping, branches.y, s.y);
        let (g, c) = (Vector2::new(gx, gy), Vector2::new(cx, cy));
        let f = if label == 1 {
            Vector2::zeros()
        } else {
            g + c.component_mul(&s_dot)
        };
        let tangent = Vector2::new(-phase.sin(), phase.cos());
        let u = r - Vector2::new(p.ex, p.ey);
        let rotor = 0.5 * (v.norm_squared() + self.j * eta * eta + u.norm_squared())
            + p.beta * eta * v.dot(&tangent);
        Point {
            t,
            label,
            power: [
                self.motor.torque(eta) * eta,
                2.0 * p.nu1 * v.norm_squared(),
                s_dot.dot(&c.component_mul(&s_dot)),
                g.dot(&s_dot),
                f.dot(&(v - s_dot)),
            ],
            energy: [rotor, ex + ey],
            ring: s,
            eta,
        }
    }

    /// The one-sided point at an event's state in the mode labelled `label`.
    fn event_point(&self, t: f64, y: &SVector<f64, 8>, label: u8) -> Point {
        let ring = self.model.ring();
        let s = Vector2::new(y[4], y[5]);
        let mode = match contact_branches(ring, label, &s) {
            Some(b) => RingMode::Contact(b),
            None => RingMode::free(Relaxation { t0: t, s0: s }),
        };
        let mut dy = SVector::<f64, 8>::zeros();
        self.model.rhs(mode, t, y, &mut dy, &RingCache::default());
        self.point(t, y, &dy, label)
    }
}

struct Recorder<'a> {
    terms: &'a Terms<'a>,
    samples: Vec<Point>,
    events: Vec<(Point, Point)>,
}

impl HybridObserver<U8> for Recorder<'_> {
    fn on_sample(&mut self, s: &Sample<U8>) {
        self.samples
            .push(self.terms.point(s.t, &s.y, &s.dy, s.label));
    }
    fn on_event(&mut self, e: &EventRecord<U8>) {
        let before = self.terms.event_point(e.t, &e.before, e.from);
        let after = self.terms.event_point(e.t, &e.after, e.to);
        self.events.push((before, after));
    }
}

/// Fig. 8a's ring with the preload 0.1 (every regime), the rotor from rest at $(0.9, 0)$
/// and $\eta = 0.5$, run up by the DC motor $0.5(1 - \eta/3)$ with $j = 5$ for 150 time
/// units (through the critical speed and into contact), sampled every 0.005, `rtol`
/// $10^{-12}$. Measured: see the printed line.
#[test]
fn energy_balance_of_a_driven_run_up_with_contact() {
    let p = Preset::Fig8b.params();
    let (j, motor) = (5.0, MotorTorque::linear(0.5, 3.0).unwrap());
    let model = DrivenJeffcott::new(p, j, motor.clone())
        .unwrap()
        .on_ring()
        .unwrap();
    let terms = Terms {
        model: &model,
        p,
        j,
        motor,
    };
    let mut y0 = model.rotor().state_at([p.ex, p.ey], [0.0, 0.0], 0.5);
    model.make_consistent(&mut y0).unwrap();
    let (t_end, h) = (150.0, 0.005);
    let plan = OutputPlan {
        t_end,
        strobe: None,
        dense: Some(DenseSampling {
            t_start: 0.0,
            dt: h,
        }),
        events: true,
    };
    let mut rec = Recorder {
        terms: &terms,
        samples: Vec::new(),
        events: Vec::new(),
    };
    let opts = SimOptions::default().with_rtol(1e-12).with_atol(1e-12);
    let stats = simulate(&model, 0.0, &y0, &plan, &opts, &mut rec).unwrap();

    let (first, last) = (rec.samples[0], *rec.samples.last().unwrap());
    let (mut work, mut free_damper, mut jumps, mut contact_pieces) = ([0.0; N], 0.0, 0.0, 0);
    let mut start = first;
    let ends = rec.events.iter().map(|e| (e.0, Some(e.1)));
    for (end, next) in ends.chain(std::iter::once((last, None))) {
        if end.t > start.t {
            let mut nodes = vec![(start.t, start.power)];
            nodes.extend(
                rec.samples
                    .iter()
                    .filter(|q| q.t > start.t + 0.25 * h && q.t < end.t - 0.25 * h)
                    .map(|q| (q.t, q.power)),
            );
            nodes.push((end.t, end.power));
            let free = start.label == 1;
            for (k, w) in integrate_piece(&nodes).into_iter().enumerate() {
                if !(free && k >= DAMPER) {
                    work[k] += w;
                }
            }
            if free {
                free_damper += free_ring_dissipation(model.ring(), start.ring, start.t, end.t);
            } else {
                contact_pieces += 1;
            }
        }
        if let Some(after) = next {
            jumps += after.energy[1] - end.energy[1];
            start = after;
        }
    }
    let de: f64 = last.energy.iter().sum::<f64>() - first.energy.iter().sum::<f64>();
    let losses = work[VISCOUS] + work[DAMPER] + free_damper + work[SLIP];
    let residual = de - (work[MOTOR] - losses + jumps);
    let scale = work[MOTOR].abs().max(last.energy.iter().sum::<f64>());
    println!(
        "driven run-up: {} transitions, {contact_pieces} contact pieces, eta {:.3} -> {:.3}\n  \
         W_motor {:.6e}, dE {:.6e}, rotor damping {:.6e}, ring dampers {:.6e} (+ free \
         {:.3e}), slip {:.6e}, jumps {:.2e}\n  residual {residual:.2e}, {:.2e} of W_motor",
        stats.transitions,
        first.eta,
        last.eta,
        work[MOTOR],
        de,
        work[VISCOUS],
        work[DAMPER],
        free_damper,
        work[SLIP],
        jumps,
        residual / scale,
    );
    assert!(contact_pieces >= 5, "{contact_pieces} contact pieces");
    assert!(
        work[DAMPER] / scale > 1e-6,
        "the ring's dampers are too weak to test"
    );
    assert!(
        (residual / scale).abs() < 1e-9,
        "the energy balance is off by {residual:e}, {:e} of the motor's work",
        residual / scale
    );
}
