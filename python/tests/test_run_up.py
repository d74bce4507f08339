"""The run-up against the truth of tests/suite/simulation/run_up.rs: the linear rotor (ring out of
reach) through its resonance at constant acceleration equals the Duhamel integral of the
out-of-balance force with its tangential term, evaluated here by composite 5-point
Gauss-Legendre quadrature (numpy's nodes; no code of the crate)."""

import math

import numpy as np
import pytest

import jeffcott
from conftest import interrupted_after

NODES, WEIGHTS = np.polynomial.legendre.leggauss(5)


def ramp_force(beta, phi0, eta0, rate, s, tangential=True):
    eta = eta0 + rate * s
    phase = phi0 + eta0 * s + 0.5 * rate * s * s
    a, b = beta * eta * eta, (beta * rate if tangential else 0.0)
    return np.stack([a * np.cos(phase) + b * np.sin(phase), a * np.sin(phase) - b * np.cos(phase)])


def duhamel(nu, beta, phi0, eta0, rate, tau, panels, tangential=True):
    """(x, y) at tau of u'' + 2 nu u' + u = F from rest: int_0^tau h(tau - s) F(s) ds."""
    wd = math.sqrt(1.0 - nu * nu)
    h = (tau / panels)
    mids = (np.arange(panels) + 0.5) * h
    s = (mids[:, None] + 0.5 * h * NODES[None, :]).ravel()
    w = np.tile(0.5 * h * WEIGHTS, panels)
    kernel = np.exp(-nu * (tau - s)) * np.sin(wd * (tau - s)) / wd
    return ramp_force(beta, phi0, eta0, rate, s, tangential) @ (w * kernel)


def test_linear_run_up_matches_the_duhamel_integral():
    # tests/suite/simulation/run_up.rs' case: Fig. 8a with nu1 = 0.05, rest at the ring's centre,
    # phi0 = 0.3, eta 0.3 -> 2.0 at 0.02, rtol 1e-12; that test's bound 1e-9 of the peak.
    p = jeffcott.Params.preset("fig8a")
    p.nu1, p.ex, p.ey, p.phi0 = 0.05, 0.0, 0.0, 0.3
    eta0, eta1, rate = 0.3, 2.0, 0.02
    r = jeffcott.run_up(p, eta0, eta1, rate, ring=False, dt=0.05, rtol=1e-12, atol=1e-13)
    n = len(r.tau)
    assert r.ramp_time == pytest.approx((eta1 - eta0) / rate, rel=1e-14)
    assert n == math.floor(r.ramp_time / 0.05 * (1 + 1e-12)) + 1
    for a in (r.tau, r.eta, r.x, r.y):
        assert a.shape == (n,) and a.dtype == np.float64
    assert r.states.shape == (n, 6) and r.regimes.dtype == np.uint8
    assert len(r.event_t) == 0 and r.event_kind == [] and (r.regimes == 1).all()
    assert np.allclose(r.eta, eta0 + rate * r.tau, rtol=1e-14, atol=1e-14)
    assert np.array_equal(r.x, r.states[:, 0]) and np.array_equal(r.y, r.states[:, 1])
    radius = np.hypot(r.x, r.y)
    peak = int(np.argmax(radius))
    amplitude = radius[peak]
    worst = without_tangential = 0.0
    for i in (peak - 400, peak - 100, peak, peak + 100, peak + 400):
        tau = r.tau[i]
        panels = math.ceil(tau * 100)
        q = duhamel(p.nu1, p.beta, p.phi0, eta0, rate, tau, panels)
        q2 = duhamel(p.nu1, p.beta, p.phi0, eta0, rate, tau, 2 * panels)
        assert np.max(np.abs(q - q2)) < 1e-13 * amplitude  # the quadrature has converged
        worst = max(worst, np.max(np.abs(r.states[i, :2] - q2)))
        q0 = duhamel(p.nu1, p.beta, p.phi0, eta0, rate, tau, panels, tangential=False)
        without_tangential = max(without_tangential, np.max(np.abs(r.states[i, :2] - q0)))
    assert worst <= 1e-9 * amplitude, worst
    # The check tells the tangential (eta') terms apart.
    assert without_tangential > 1e-4 * amplitude


def test_run_up_on_the_ring_touches_it():
    r = jeffcott.run_up(jeffcott.Params.preset("fig8a"), 0.5, 2.5, 0.05)
    assert len(r.event_t) > 0 and "onset" in " ".join(r.event_kind)
    assert r.regimes.max() > 1 and r.tau[-1] == pytest.approx(40.0)
    assert r.stats["steps"] > 0


@pytest.mark.parametrize("args,kw", [((0.3, 2.0, -0.02), {}), ((0.3, 2.0, 0.0), {}),
                                     ((-1.0, 2.0, 0.02), {}), ((0.3, 2.0, 0.02), dict(dt=0.0)),
                                     ((0.3, 2.0, 0.02), dict(state0=[1.0]))])
def test_run_up_bad_input(args, kw):
    with pytest.raises(ValueError):
        jeffcott.run_up(jeffcott.Params(), *args, **kw)


def test_ctrl_c_stops_a_long_run_up():
    p = jeffcott.Params.preset("fig9c")
    elapsed = interrupted_after(0.5, lambda: jeffcott.run_up(p, 0.5, 3.0, 1e-7))
    assert elapsed < 5.0, f"KeyboardInterrupt after {elapsed:.2f} s"


# The paper's rotor on a drive (``run_up(..., motor=, inertia=)``, rotor::DrivenJeffcott).

def driven_field(z, p, j, torque):
    """z = [x, y, x', y', eta, phi]; the equations of MODEL.md's units written out: the
    rotor's two and j eta' = t(eta) + beta (x'' sin phi - y'' cos phi), solved together."""
    x, y, vx, vy, eta, phi = z
    s, c = math.sin(phi), math.cos(phi)
    b = p.beta
    A = np.array([[1.0, 0.0, -b * s], [0.0, 1.0, b * c], [-b * s, b * c, j]])
    rhs = np.array([b * eta * eta * c - 2 * p.nu1 * vx - (x - p.ex),
                    b * eta * eta * s - 2 * p.nu1 * vy - (y - p.ey), torque(eta)])
    ax, ay, deta = np.linalg.solve(A, rhs)
    return np.array([vx, vy, ax, ay, deta, eta])


def test_driven_run_up_off_the_ring_follows_an_independent_solve():
    # Off the ring, a DC motor t = 0.05 (1 - eta / 3) through j = 2 from eta = 0.3, at rest at
    # the origin: against RK4 on the equations written out here (h = dt / 8). (With a stall
    # torque of 0.2 the same rotor passes the resonance and nears eta = 2.9 by tau = 150.)
    p = jeffcott.Params.preset("fig8a")
    p.nu1, p.phi0 = 0.05, 0.3
    stall, no_load, j, dt, t_end = 0.05, 3.0, 2.0, 0.05, 150.0
    torque = lambda eta: stall * (1.0 - eta / no_load)
    r = jeffcott.run_up(p, 0.3, motor=jeffcott.Motor.linear(stall, no_load), inertia=j,
                        t_end=t_end, dt=dt, ring=False, rtol=1e-12, atol=1e-13)
    z, h = np.array([0.0, 0.0, 0.0, 0.0, 0.3, p.phi0]), dt / 8
    truth = [z.copy()]
    for _ in range(round(t_end / h)):
        k1 = driven_field(z, p, j, torque)
        k2 = driven_field(z + h / 2 * k1, p, j, torque)
        k3 = driven_field(z + h / 2 * k2, p, j, torque)
        k4 = driven_field(z + h * k3, p, j, torque)
        z = z + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        truth.append(z.copy())
    truth = np.array(truth[::8])
    assert r.tau.shape == (len(truth),) and math.isnan(r.ramp_time)
    scale = np.max(np.hypot(truth[:, 0], truth[:, 1]))
    assert np.max(np.hypot(r.x - truth[:, 0], r.y - truth[:, 1])) <= 1e-8 * scale
    assert np.max(np.abs(r.eta - truth[:, 4])) <= 1e-9
    assert np.max(np.abs(r.phase - truth[:, 5])) <= 1e-8 * truth[-1, 5]
    # The Sommerfeld effect: this motor cannot pass the resonance (eta near 1) off the ring;
    # the speed hangs below it, as in the finite-element drive of test_fe_drive.py.
    late = r.tau > t_end / 2
    assert 0.85 < np.min(r.eta[late]) and np.max(r.eta[late]) < 1.0


def test_driven_run_up_of_huge_inertia_is_the_constant_speed_model():
    # A motor holding eta = 2 through j = 1e10 (its speed moves by about 1e-8): Fig. 8a's rotor
    # from (0.9, 0) on the ring, against simulate_dense at eta = 2 (the paper's model).
    p = jeffcott.Params.preset("fig8a")
    p.eta = 2.0
    start = [0.9, 0.0, 0.0, 0.0, 0.0, 0.0]
    t_end = 20 * math.pi
    r = jeffcott.run_up(p, 2.0, motor=jeffcott.Motor.linear(1e8, 2.0), inertia=1e10,
                        t_end=t_end, dt=0.1, state0=start, rtol=1e-11, atol=1e-12)
    d = jeffcott.simulate_dense(p, t_end, 0.1, state0=start, rtol=1e-11, atol=1e-12)
    assert len(r.event_t) >= 4 and len(r.event_t) == len(d.event_t)
    assert np.max(np.abs(r.states - d.states)) <= 1e-6
    assert np.max(np.abs(r.eta - 2.0)) <= 1e-7
    assert np.allclose(r.phase, p.phi0 + 2.0 * r.tau, rtol=1e-7)


@pytest.mark.parametrize("kw, message", [
    (dict(eta_to=2.0, rate=0.1, inertia=2.0), "not both"),
    (dict(eta_to=2.0), "go together"),
    (dict(inertia=2.0), "motor and inertia"),
    (dict(inertia=2.0, motor="m"), "t_end"),
    (dict(inertia=1e-9, motor="m", t_end=1.0), "inertia"),
])
def test_driven_run_up_bad_input(kw, message):
    p = jeffcott.Params.preset("fig8a")
    if kw.get("motor") == "m":
        kw["motor"] = jeffcott.Motor.linear(0.05, 3.0)
    if "inertia" in kw and "motor" not in kw and "rate" in kw:
        kw["motor"] = jeffcott.Motor.linear(0.05, 3.0)
    with pytest.raises(ValueError, match=message):
        jeffcott.run_up(p, 0.3, **kw)


def test_driven_run_up_with_friction_is_braked():
    # Fig. 8a's rotor on a drive (t = 0.2 (1 - eta / 3), j = 2, from eta = 0.5) on the ring,
    # with Coulomb friction mu = 0.2 at a shaft of radius 5 gaps: it slips (regime 6) and rolls
    # (8) on the ring, and the rub torque holds the speed down (about 1.2 against 1.6 without
    # friction over the second half). A check of the plumbing: the torque itself is checked
    # in Rust (tests/suite/ring/rub_drive.rs) and on the finite-element rotor here
    # (test_fe_drive.py).
    p = jeffcott.Params.preset("fig8a")
    kw = dict(motor=jeffcott.Motor.linear(0.2, 3.0), inertia=2.0, t_end=100.0, dt=0.05,
              rtol=1e-9)
    free = jeffcott.run_up(p, 0.5, **kw)
    rub = jeffcott.run_up(p, 0.5, friction=0.2, shaft_radius=5.0, **kw)
    assert {6, 8} <= set(np.unique(rub.regimes)) and set(np.unique(free.regimes)) <= {1, 2, 3, 4, 5}
    late = free.tau > 50.0
    assert np.mean(rub.eta[late]) < np.mean(free.eta[late]) - 0.2
