#!/usr/bin/env python3
"""Independent reference for the stability tests (tests/suite/stability/stability_orbits.rs,
stability_lyapunov.rs).

Computes, for the paper's model (shared/MODEL.md) with the Fig. 8 values, WITHOUT the crate:

* the period-1 orbit at eta = 2 (Fig. 8a: no preload; Fig. 8b: Dx = Dy = 0.1), found by Newton
  on P(z) - z with a finite-difference Jacobian, from the state reached from rest after 300
  forcing periods;
* its monodromy matrix DP by Richardson-extrapolated central differences of the stroboscopic map
  P, and the Floquet multipliers (its eigenvalues);
* the parameter eta* at which the real negative multiplier of that orbit reaches -1 (the flip),
  followed by natural continuation in eta and located by Brent's method, with the multipliers
  there and their slopes in eta;
* the largest Lyapunov exponent of the chaotic attractor at eta = 2.442 without preload, by the
  two-trajectory method (3000 periods after 500 from rest), with its batch-means error.

Nothing here uses the crate's variational equations, saltation matrices, Newton or continuation:
the map is brute-force simulation (SciPy DOP853 with terminal events) and every derivative is a
finite difference of it.

Model pieces used (MODEL.md): on these orbits the ring stays isotropic during contact: with
no preload only regime V exists and each axis' force is K s + 2 nu2 s'; with D = 0.1 the
contacts stay in regime II (|x_s|, |y_s| < D, asserted at every step) with 2 K s + 4 nu2 s'. For
an isotropic ring the contact position is s*(r) = r (R - 1)/R (R = |r|), its velocity J v with
J = (1 - 1/R) I + r r^T / R^3, and the normal force n . f = k (R - 1) + c R'. Free flight: the
ring relaxes as s(t) = s_L exp(-(t - t_L) K/(2 nu2)) (inside the preload). Contact onset:
|r - s(t)| = 1 rising; loss: n . f = 0 falling (or R = 1 falling).

Usage: python3 stability_reference.py > stability_reference.csv   (about 4 minutes of CPU; the
estimates of each value's error go to stderr as comments; the argument `lyapunov` runs only
the last item)
Needs numpy and scipy (tested with numpy 2.4.6, scipy 1.17.1, Python 3.11).
"""

import sys

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

FIG8 = dict(nu1=0.125, nu2=0.002, K=30.0, ex=0.9, ey=0.0, beta=0.119, phi0=0.0)
RTOL, ATOL = 1e-13, 1e-15
H = 5e-4  # finite-difference step of the monodromy matrix (Richardson with H and H/2)


class Model:
    def __init__(self, eta, D, rtol=RTOL, atol=ATOL):
        p = FIG8
        self.nu1, self.nu2, self.K = p["nu1"], p["nu2"], p["K"]
        self.ex, self.ey, self.beta, self.phi0 = p["ex"], p["ey"], p["beta"], p["phi0"]
        self.eta, self.D = eta, D
        # Isotropic contact: regime V without preload, regime II with it.
        self.k, self.c = (self.K, 2 * self.nu2) if D == 0 else (2 * self.K, 4 * self.nu2)
        self.T = 2 * self.nu2 / self.K  # ring relaxation time (inside the preload)
        self.period = 2 * np.pi / eta
        self.rtol, self.atol = rtol, atol
        self.max_depth = 0.0

    def forcing(self, t):
        a = self.beta * self.eta**2
        ph = self.phi0 + self.eta * t
        return a * np.cos(ph), a * np.sin(ph)

    def free(self, t, z):
        x, y, vx, vy = z
        fx, fy = self.forcing(t)
        return [vx, vy, fx - 2 * self.nu1 * vx - (x - self.ex), fy - 2 * self.nu1 * vy - (y - self.ey)]

    def ring(self, r):
        R = np.hypot(r[0], r[1])
        return r * (R - 1) / R

    def contact(self, t, z):
        x, y, vx, vy = z
        r, v = np.array([x, y]), np.array([vx, vy])
        R = np.hypot(x, y)
        s = r * (R - 1) / R
        jv = (1 - 1 / R) * v + r * (r @ v) / R**3
        f = self.k * s + self.c * jv
        fx, fy = self.forcing(t)
        return [vx, vy, fx - 2 * self.nu1 * vx - (x - self.ex) - f[0],
                fy - 2 * self.nu1 * vy - (y - self.ey) - f[1]]

    def normal_force(self, t, z):
        R = np.hypot(z[0], z[1])
        return self.k * (R - 1) + self.c * (z[0] * z[2] + z[1] * z[3]) / R

    def advance(self, z0, t0=0.0, t1=None):
        """State z = (x, y, x', y') at t1 from z0 at t0 (t0 a section: ring relaxed to 0)."""
        t1 = t0 + self.period if t1 is None else t1
        assert np.hypot(z0[0], z0[1]) < 1, "sections must be in free flight"
        z, contact, _, _ = self.flow((np.array(z0, float), False, np.zeros(2), t0), t0, t1)
        assert not contact, "sections must be in free flight"
        return z

    def flow(self, state, t, t1):
        """The hybrid state (z, in contact, released ring position, release time) from t to
        t1."""
        z, contact, s_l, t_l = state
        z = np.array(z, float)
        while t < t1:
            if not contact:
                def onset(tt, zz, s_l=s_l, t_l=t_l):
                    s = s_l * np.exp(-(tt - t_l) / self.T)
                    return (zz[0] - s[0]) ** 2 + (zz[1] - s[1]) ** 2 - 1

                onset.terminal, onset.direction = True, 1
                sol = solve_ivp(self.free, (t, t1), z, method="DOP853", rtol=self.rtol,
                                atol=self.atol, events=onset)
            else:
                def loss(tt, zz):
                    return self.normal_force(tt, zz)

                def gap(tt, zz):
                    return np.hypot(zz[0], zz[1]) - 1

                def peak(tt, zz):  # R' = 0 falling: the deepest point of the contact
                    return zz[0] * zz[2] + zz[1] * zz[3]

                loss.terminal, loss.direction = True, -1
                gap.terminal, gap.direction = True, -1
                peak.direction = -1
                sol = solve_ivp(self.contact, (t, t1), z, method="DOP853", rtol=self.rtol,
                                atol=self.atol, events=[loss, gap, peak])
                for zp in sol.y_events[2]:
                    self.max_depth = max(self.max_depth, float(np.hypot(zp[0], zp[1]) - 1))
                sol.t_events, sol.y_events = sol.t_events[:2], sol.y_events[:2]
                R = np.hypot(sol.y[0], sol.y[1])
                if self.D > 0:
                    s = sol.y[:2] * (R - 1) / R
                    assert np.abs(s).max() < self.D, "the contact left regime II"
            assert sol.status >= 0, sol.message
            if sol.status == 1:  # an event ended the piece
                hit = [e for e in sol.t_events if len(e)]
                t = float(hit[0][0])
                z = np.array([e for e in sol.y_events if len(e)][0][0])
                if contact:
                    s_l, t_l = self.ring(z[:2]), t
                else:
                    assert np.hypot(z[0], z[1]) >= 1 - 1e-9, "onset inside the gap circle"
                contact = not contact
            else:
                t, z = float(sol.t[-1]), sol.y[:, -1].copy()
        return z, contact, s_l, t_l


def jacobian(m, z, h):
    """Central differences of P with steps h and h/2, Richardson-combined (error O(h^4))."""
    def central(hh):
        J = np.empty((4, 4))
        for j in range(4):
            e = np.zeros(4)
            e[j] = hh
            J[:, j] = (m.advance(z + e) - m.advance(z - e)) / (2 * hh)
        return J

    return (4 * central(h / 2) - central(h)) / 3


def fixed_point(m, z, tol=1e-12, h=1e-5):
    """Newton on P(z) - z with the finite-difference Jacobian; returns z and |P(z) - z|."""
    for _ in range(30):
        F = m.advance(z) - z
        if np.abs(F).max() < tol:
            return z, np.abs(F).max()
        z = z - np.linalg.solve(jacobian(m, z, h) - np.eye(4), F)
    raise RuntimeError("Newton did not converge")


def multipliers(J):
    w = np.linalg.eigvals(J)
    return w[np.argsort(-np.abs(w), kind="stable")]




def out(case, name, value, err):
    print(f"{case},{name},{value:.13f},{err:.1e}")
    sys.stdout.flush()


def orbit_case(case, D):
    m = Model(2.0, D)
    z = np.zeros(4)
    for _ in range(300):
        z = m.advance(z)
    z, res = fixed_point(m, z)
    m.max_depth = 0.0
    m.advance(z)
    depth = m.max_depth  # at the located maximum of R (R' = 0)
    # Error estimates: the same fixed point at rtol 1e-12 (integration error), and Richardson
    # Jacobians with steps H and 2 H (truncation and the integration noise over h).
    m12 = Model(2.0, D, rtol=1e-12, atol=1e-14)
    J1 = jacobian(m, z, H)
    z12 = z - np.linalg.solve(J1 - np.eye(4), m12.advance(z) - z)  # one Newton step on rtol 1e-12
    err_z = max(np.abs(z12 - z).max(), res)
    w1, w2 = multipliers(J1), multipliers(jacobian(m, z, 2 * H))
    w12 = multipliers(jacobian(m12, z12, H))
    err_w = max(np.abs(w1 - w2).max(), np.abs(w1 - w12).max())
    print(f"# {case}: residual {res:.1e}, fixed point rtol 1e-12 vs 1e-13 {np.abs(z12 - z).max():.1e}, "
          f"multipliers h vs 2 h {np.abs(w1 - w2).max():.1e}, rtol 1e-12 vs 1e-13 "
          f"{np.abs(w1 - w12).max():.1e}", file=sys.stderr)
    for name, v in zip(["x", "y", "vx", "vy"], z):
        out(case, name, v, err_z)
    for i, w in enumerate(w1):
        out(case, f"mult{i}_modulus", abs(w), err_w)
        out(case, f"mult{i}_argument", abs(np.angle(w)), err_w / abs(w))
    m12.max_depth = 0.0
    m12.advance(z12)
    out(case, "depth", depth, max(abs(m12.max_depth - depth), 1e-12))
    return z


def continued(D, z, eta, h):
    """The period-1 orbit at eta by Newton from z, and its multipliers (step h)."""
    m = Model(eta, D)
    zz, _ = fixed_point(m, z)
    return zz, multipliers(jacobian(m, zz, h))


def flip_case(case, D, z):
    """Continue the orbit from eta = 2 in steps of 0.02 and locate the flip; multipliers there."""
    eta = 2.0
    while True:
        zn, w = continued(D, z, eta + 0.02, H)
        if abs(w[0]) > 1:
            break
        eta, z = eta + 0.02, zn
    lo, hi = eta, eta + 0.02
    star = {}
    for h in (H, 2 * H):  # the second estimates the error
        star[h] = brentq(lambda e: abs(continued(D, z, e, h)[1][0]) - 1, lo, hi,
                         xtol=1e-12, rtol=1e-14)
    _, w = continued(D, z, star[H], H)
    _, w2 = continued(D, z, star[H], 2 * H)
    assert abs(w[0].imag) < 1e-9 and w[0].real < 0, "the flip's critical multiplier is -1"
    err = max(abs(star[H] - star[2 * H]), 1e-11)
    print(f"# {case}: flip {star[H]:.12f}, with 2 h {star[2 * H]:.12f}", file=sys.stderr)
    out(case, "flip_eta", star[H], err)
    # Their slopes d(multiplier)/d(eta) there (central differences over +-1e-6; the multipliers
    # move fast near the flip), for comparisons at a nearby eta.
    slope = (continued(D, z, star[H] + 1e-6, H)[1] - continued(D, z, star[H] - 1e-6, H)[1]) / 2e-6
    # Error of the multipliers: the step (h vs 2 h) and eta*'s error times their slope.
    err_w = np.abs(w - w2).max() + np.abs(slope).max() * err
    for i, x in enumerate(w):
        out(case, f"mult{i}_re", x.real, err_w)
        out(case, f"mult{i}_im", x.imag, err_w)
        out(case, f"mult{i}_slope", slope[i].real, 1e-3 * abs(slope[i]))


def lyapunov_case(case, eta, D, transient=500, periods=3000, batch=150, d0=1e-8):
    """Largest Lyapunov exponent per forcing period by the two-trajectory method (a neighbour
    d0 away, renormalised every period along the separation), from rest, with its batch-means
    standard error (20 batches)."""
    m = Model(eta, D)
    state = (np.zeros(4), False, np.zeros(2), 0.0)
    t = 0.0
    for _ in range(transient):
        state = m.flow(state, t, t + m.period)
        t += m.period
    u = np.ones(4) / 2.0
    logs = []
    for _ in range(periods):
        z, contact, s_l, t_l = state
        other = (z + d0 * u, contact, s_l, t_l)
        state = m.flow(state, t, t + m.period)
        other = m.flow(other, t, t + m.period)
        t += m.period
        diff = other[0] - state[0]
        dist = np.linalg.norm(diff)
        logs.append(np.log(dist / d0))
        u = diff / dist
    means = np.array(logs).reshape(-1, batch).mean(axis=1)
    lam, se = float(np.mean(logs)), float(means.std(ddof=1) / np.sqrt(len(means)))
    print(f"# {case}: lambda_1 {lam:.5f} +- {se:.5f} ({len(means)} batches of {batch})",
          file=sys.stderr)
    out(case, "lambda1", lam, se)


def main():
    print("# Independent reference of tests/stability_*.rs: tests/data/stability_reference.py")
    print("# (SciPy DOP853 rtol 1e-13 atol 1e-15 with terminal events; Newton and multipliers from")
    print("# Richardson central differences of the stroboscopic map; no code of the crate).")
    print("# error: the estimated error of the value (rtol 1e-12 vs 1e-13, step h vs 2h); see README.md")
    print("case,quantity,value,error")
    if sys.argv[1:] != ["lyapunov"]:
        for case, D in [("fig8a_eta2", 0.0), ("fig8b_eta2", 0.1)]:
            z = orbit_case(case, D)
            flip_case(case.replace("eta2", "flip"), D, z)
    # The chaotic attractor of Fig. 9c (no preload: the contacts stay in regime V, where the
    # isotropic ring above is exact; with D = 0.1 they reach regimes III-V).
    lyapunov_case("fig8a_eta2.442", 2.442, 0.0)


if __name__ == "__main__":
    main()
