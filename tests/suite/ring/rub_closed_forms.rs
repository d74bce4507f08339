//! The closed forms of rub with friction (`paper::rub`: synchronous full annular rub, dry whip)
//! against the equation of motion written here, with the ring's force from the crate's ring
//! with friction (`ring::FrictionRing`), and against a scan for completeness.

use jeffcott::nalgebra::Vector2;
use jeffcott::paper::rub::{dry_whip, synchronous_rub};
use jeffcott::params::{ParamError, Params};
use jeffcott::ring::{FrictionRing, Slip, SnubberRing};

/// The paper's rotor centred in an isotropic ring without preload.
fn centred(eta: f64, nu1: f64, nu2: f64, k: f64, beta: f64) -> Params {
    Params {
        eta,
        nu1,
        nu2,
        kx: k,
        ky: k,
        beta,
        dx: 0.0,
        dy: 0.0,
        ex: 0.0,
        ey: 0.0,
        phi0: 0.3,
    }
}

/// The residual of `r'' + 2 nu1 r' + r + f = beta eta^2 (cos th, sin th)` at a state on a
/// circular orbit turning at `rate` (so `r'' = -rate^2 r`), with `f` the force of the ring
/// slipping forward located by the crate at `r`; and that ring's distance from `s`.
fn residual(
    p: &Params,
    mu: f64,
    (r, r_dot): (Vector2<f64>, Vector2<f64>),
    rate: f64,
    tau: f64,
    s: Vector2<f64>,
) -> (f64, f64) {
    let ring = SnubberRing::isotropic(p.kx, 0.0, p.nu2).unwrap();
    let c = FrictionRing::new(ring, mu)
        .unwrap()
        .locate_slipping(&r, Slip::Forward)
        .unwrap();
    let th = p.phi0 + p.eta * tau;
    let forcing = Vector2::new(th.cos(), th.sin()) * (p.beta * p.eta * p.eta);
    let r_ddot = -r * (rate * rate);
    let res = r_ddot + r_dot * (2.0 * p.nu1) + r + c.force(&r_dot) - forcing;
    (res.norm(), (c.s - s).norm())
}

/// Each synchronous rub solves the equation of motion with the ring's force, at every phase;
/// its ring turns rigidly with it; the count of branches shows the jump (two rub branches
/// beside a free orbit inside the gap) at some speeds.
#[test]
fn synchronous_rubs_solve_the_equation_of_motion() {
    let mut coexisting = 0;
    for (nu1, nu2, k, beta, mu) in [
        (0.05, 0.002, 30.0, 0.5, 0.2),
        (0.125, 0.002, 30.0, 0.119, 0.1),
        (0.02, 0.01, 5.0, 0.3, 0.6),
    ] {
        for i in 0..60 {
            let eta = 0.5 + 0.05 * i as f64;
            let p = centred(eta, nu1, nu2, k, beta);
            let rubs = synchronous_rub(&p, mu).unwrap();
            let free = beta * eta * eta / ((1.0 - eta * eta).hypot(2.0 * nu1 * eta));
            if rubs.len() == 2 && free < 1.0 {
                coexisting += 1;
            }
            for rub in &rubs {
                assert!(rub.radius > 1.0 && rub.contact_force > 0.0);
                for tau in [0.0, 0.7, 2.9] {
                    let state = rub.rotor(tau);
                    let scale = p.kx * rub.radius;
                    let (res, off) = residual(&p, mu, state, eta, tau, rub.ring(tau));
                    assert!(res <= 1e-12 * scale, "eta {eta}: residual {res:e}");
                    assert!(off <= 1e-13 * rub.radius, "eta {eta}: ring {off:e} off");
                    // The ring turns with the rotor: s' = i eta s.
                    let ring = SnubberRing::isotropic(p.kx, 0.0, p.nu2).unwrap();
                    let c = FrictionRing::new(ring, mu)
                        .unwrap()
                        .locate_slipping(&state.0, Slip::Forward)
                        .unwrap();
                    let s = rub.ring(tau);
                    let turning = Vector2::new(-s.y, s.x) * eta;
                    assert!(
                        (c.ring_velocity(&state.1) - turning).norm() <= 1e-12 * eta * rub.radius
                    );
                }
            }
        }
    }
    assert!(
        coexisting > 0,
        "no speed with two rub branches beside a free orbit in the gap"
    );
}

/// Each dry whip solves the unforced equation of motion with the ring slipping forward (the
/// surface speed above the whirl), and a scan of the whirl frequency for a real positive `q`
/// finds no other.
#[test]
fn dry_whips_solve_the_equation_of_motion_and_none_is_missed() {
    for (nu1, nu2, k, mu) in [
        (0.01, 0.002, 30.0, 0.3),
        (0.125, 0.002, 30.0, 0.3),
        (0.05, 0.05, 4.0, 0.8),
        (0.3, 0.0, 10.0, 0.1),
    ] {
        let p = centred(2.0, nu1, nu2, k, 0.0);
        let whips = dry_whip(&p, mu).unwrap();
        for whip in &whips {
            let w = whip.frequency;
            for tau in [0.0, 0.4, 1.3] {
                let (r, r_dot) = whip.rotor(tau);
                let (res, off) = residual(&p, mu, (r, r_dot), w, tau, whip.ring(tau));
                assert!(res <= 1e-11 * p.kx * whip.radius, "w {w}: residual {res:e}");
                assert!(off <= 1e-13 * whip.radius);
                let ring = SnubberRing::isotropic(p.kx, 0.0, p.nu2).unwrap();
                let c = FrictionRing::new(ring, mu)
                    .unwrap()
                    .locate_slipping(&r, Slip::Forward)
                    .unwrap();
                // Backward whirl: the contact point runs at -w; a surface speed above w slips
                // forward.
                assert!((c.whirl_speed(&r_dot) + w).abs() <= 1e-12 * w);
                assert!(c.slip_velocity(&r_dot, 1.01 * w) > 0.0);
            }
        }
        // The scan: q(w) = -A/((1 + i mu)(A + B)) real and positive.
        let q_of = |w: f64| {
            let a = jeffcott::nalgebra::Complex::new(1.0 - w * w, -2.0 * nu1 * w);
            let b = jeffcott::nalgebra::Complex::new(k, -2.0 * nu2 * w);
            -a / (jeffcott::nalgebra::Complex::new(1.0, mu) * (a + b))
        };
        let (mut found, mut prev) = (0, q_of(1e-6));
        for i in 1..=200_000 {
            let cur = q_of(1e-6 + 20.0 * i as f64 / 200_000.0);
            if (prev.im < 0.0) != (cur.im < 0.0) && cur.re > 0.0 && prev.re > 0.0 {
                found += 1;
            }
            prev = cur;
        }
        assert_eq!(whips.len(), found, "nu1 {nu1} nu2 {nu2} K {k} mu {mu}");
    }
    assert!(dry_whip(&centred(2.0, 0.01, 0.002, 30.0, 0.0), 0.0)
        .unwrap()
        .is_empty());
}

/// Parameters outside the closed forms are named.
#[test]
fn parameters_outside_the_closed_forms_are_refused() {
    let p = centred(1.5, 0.05, 0.002, 30.0, 0.2);
    let outside = |q: Params, f: f64| match synchronous_rub(&q, f) {
        Err(ParamError::OutsideClosedForm { field, .. }) => field,
        other => panic!("{other:?}"),
    };
    assert_eq!(outside(Params { ky: 20.0, ..p }, 0.1), "ky");
    assert_eq!(outside(Params { dy: 0.1, ..p }, 0.1), "dy");
    assert_eq!(outside(Params { ex: 0.1, ..p }, 0.1), "ex");
    assert!(matches!(
        synchronous_rub(&p, -0.1),
        Err(ParamError::Negative {
            field: "friction",
            ..
        })
    ));
    assert!(matches!(
        dry_whip(&p, 0.1),
        Err(ParamError::OutsideClosedForm { field: "beta", .. })
    ));
}
