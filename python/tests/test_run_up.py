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
