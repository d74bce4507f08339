"""Coulomb friction at the ring for a finite-element rotor (fe_transient's friction and
shaft_radius): the law at every sample, computed here from the run's own forces, and the
frictionless run unchanged."""

import numpy as np
import pytest

import jeffcott

# One node (layout lateral4: x, y, alpha, beta) with unit mass and stiffness, damping ratio
# 0.05: the paper's rotor in its own units, on a ring of unit stiffness 30 and gap 1.
NU1, K = 0.05, 30.0
M, KK, C, G = np.eye(4), np.eye(4), 2 * NU1 * np.eye(4), np.zeros((4, 4))


def run(beta, eta, ring_damping=0.0, **kw):
    return jeffcott.fe_transient(
        M, KK, C, G, eta, ring_node=0, gap=1.0, ring_stiffness=K,
        ring_damping=ring_damping, unbalance=[(0, beta, 0.3)], t_end=60.0, samples=6000,
        layout="lateral4", rtol=1e-10, **kw)


@pytest.mark.parametrize("beta, eta, mu, a, preload", [
    (0.5, 1.2, 0.2, 5.0, (0.0, 0.0)),   # slips forward only
    (0.5, 1.2, 0.3, 0.05, (0.0, 0.0)),  # slips and rolls
    (0.3, 1.1, 0.5, 0.2, (0.0, 0.0)),   # slips both ways and rolls
    (0.5, 1.2, 0.3, 0.05, (0.05, 0.02)),  # a preloaded ring: crossings while slipping, rolling
])
def test_fe_transient_friction_obeys_coulombs_law_at_every_sample(beta, eta, mu, a, preload):
    # Without ring dampers the ring's force is its springs' alone, so the law is exact: slipping
    # forward (regime 6) the friction on the rotor is -mu N, backward (7) +mu N, rolling (8)
    # at most mu N in size.
    r = run(beta, eta, friction=mu, shaft_radius=a, preload=preload)
    f, n = r.friction_force, r.normal_force
    seen = set(np.unique(r.regimes))
    assert seen <= {1, 6, 7, 8} and 6 in seen
    for regime, sign in [(6, -1.0), (7, 1.0)]:
        m = r.regimes == regime
        assert np.all(n[m] > 0)
        assert np.all(np.abs(f[m] - sign * mu * n[m]) <= 1e-12 * n[m])
    m = r.regimes == 8
    assert np.all(np.abs(f[m]) <= mu * n[m] * (1 + 1e-12))
    out = r.regimes == 1
    assert np.all(f[out] == 0) and np.all(n[out] == 0)
    # The contact episodes run from onsets to losses, whatever the friction's modes between.
    assert len(r.onsets) == len(r.contacts.start) and np.all(r.losses > 0)


def test_fe_transient_friction_modes_are_all_met():
    r = run(0.3, 1.1, friction=0.5, shaft_radius=0.2)
    assert set(np.unique(r.regimes)) == {1, 6, 7, 8}


def test_fe_transient_without_friction_is_the_frictionless_run():
    plain = run(0.5, 1.2, ring_damping=0.004)
    zero = run(0.5, 1.2, ring_damping=0.004, friction=0.0, shaft_radius=0.1)
    assert np.array_equal(plain.x, zero.x) and np.array_equal(plain.y, zero.y)
    assert np.array_equal(plain.regimes, zero.regimes)
    # Without friction and dampers the ring's force is normal.
    springs = run(0.5, 1.2)
    assert np.all(np.abs(springs.friction_force) <= 1e-12 * np.max(springs.normal_force))


@pytest.mark.parametrize("kw, message", [
    (dict(friction=0.2), "shaft_radius"),
    (dict(friction=-0.1, shaft_radius=0.1), "friction"),
    (dict(friction=3.0, shaft_radius=0.1, preload=(0.1, 0.0)), "friction"),
    (dict(friction=0.2, shaft_radius=-1.0), "shaft_radius"),
])
def test_fe_transient_bad_friction_raises_value_error(kw, message):
    with pytest.raises(ValueError, match=message):
        run(0.5, 1.2, **kw)


def test_fe_transient_losses_are_the_ends_of_contact_only():
    # A preloaded ring: contacts change regime (II to V) without ending. The losses are the
    # ends of the contact episodes, never a change of regime (they were, before this was fixed).
    r = run(0.5, 1.2, ring_damping=0.004, preload=(0.05, 0.05))
    assert len(set(np.unique(r.regimes)) - {1, 2}) > 0, "no regime beyond II met"
    ends = r.contacts.end[~np.isnan(r.contacts.end)]
    assert len(r.losses) > 0 and np.array_equal(r.losses, ends)
    assert len(r.onsets) == len(r.contacts.start)


def test_fe_run_up_with_friction_obeys_coulombs_law():
    # Through the rotor's critical speed (1) on a ring without dampers: the surface speed
    # follows the profile; the law at every sample in contact.
    mu = 0.3
    r = jeffcott.fe_run_up(
        M, KK, C, G, [0.0, 60.0], [0.6, 1.6], ring_node=0, gap=1.0, ring_stiffness=K,
        ring_damping=0.0, unbalance=[(0, 0.3, 0.0)], layout="lateral4", rtol=1e-10,
        friction=mu, shaft_radius=0.2)
    f, n = r.friction_force, r.normal_force
    assert 6 in set(np.unique(r.regimes))
    for regime, sign in [(6, -1.0), (7, 1.0)]:
        m = r.regimes == regime
        assert np.all(np.abs(f[m] - sign * mu * n[m]) <= 1e-12 * n[m])
    m = r.regimes == 8
    assert np.all(np.abs(f[m]) <= mu * n[m] * (1 + 1e-12))
    with pytest.raises(ValueError, match="shaft_radius"):
        jeffcott.fe_run_up(
            M, KK, C, G, [0.0, 60.0], [0.6, 1.6], ring_node=0, gap=1.0, ring_stiffness=K,
            ring_damping=0.0, unbalance=[(0, 0.3, 0.0)], layout="lateral4", friction=mu)


def paper_contact(p, state):
    """The paper's rotor in contact at `state` [x, y, x', y', x_s, y_s] (gap 1, no preload):
    the ring on the circle (asserted), the tangent t and the ring's elastic normal force and
    friction force, g = K s."""
    n = state[:2] - state[4:]
    assert abs(np.hypot(*n) - 1) < 1e-12
    t = np.array([-n[1], n[0]])
    g = np.array([p.kx * state[4], p.ky * state[5]])
    return t, n @ g, t @ g


def test_paper_simulate_with_friction_obeys_coulombs_law():
    # The paper's rotor (Fig. 8a at eta 2.5) with friction from Python: at every dense sample in
    # contact, slipping forward F_t = mu N with v > 0, rolling v = 0 and |F_t| <= mu N, from the
    # sample's own states and derivatives and the ring's force law (no preload: g = K s).
    mu, a = 0.3, 0.05
    p = jeffcott.Params.preset("fig8a")
    p.eta = 2.5
    period = 2 * np.pi / p.eta
    r = jeffcott.simulate_dense(p, 40 * period, period / 64, friction=mu, shaft_radius=a)
    y, dy, reg = r.states, r.derivatives, r.regimes
    assert {6, 8} <= set(np.unique(reg)) <= {1, 6, 7, 8}
    for i in np.flatnonzero(reg >= 6):
        t, normal, tangential = paper_contact(p, y[i])
        v = (y[i, 2:4] - dy[i, 4:]) @ t + p.eta * a
        if reg[i] == 6:
            assert v >= -1e-9 and abs(tangential - mu * normal) <= 1e-9 * normal
        elif reg[i] == 8:
            assert abs(v) <= 1e-9 and abs(tangential) <= mu * normal * (1 + 1e-12)
    # The stroboscopic run is the dense run's states at the forcing periods.
    s = jeffcott.simulate(p, 40, friction=mu, shaft_radius=a)
    assert np.allclose(s.states[-1], y[-1], rtol=0, atol=1e-9)
    # Without friction, the paper's model as before; bad friction input is a ValueError.
    plain = jeffcott.simulate(p, 10)
    assert np.array_equal(plain.states, jeffcott.simulate(p, 10, friction=0.0).states)
    with pytest.raises(ValueError, match="shaft_radius"):
        jeffcott.simulate(p, 10, friction=0.3)
    with pytest.raises(ValueError, match="friction"):
        jeffcott.simulate(p, 10, friction=-0.3, shaft_radius=1.0)


def test_paper_run_up_with_friction_obeys_coulombs_law():
    # The paper's rotor (Fig. 8a) run up from eta 2.3 to 2.7 with friction: at every sample in
    # contact the ring is on the circle and its elastic force (no preload, no dampers' part:
    # g = K s) obeys the law of the sample's regime, slipping forward F_t = mu N, backward
    # -mu N, rolling |F_t| <= mu N, from the positions alone. The shaft's surface speed is
    # the ramp's eta(tau) a, so slips stop and rolls end along the way.
    mu, a = 0.3, 0.05
    p = jeffcott.Params.preset("fig8a")
    r = jeffcott.run_up(p, 2.3, 2.7, 0.004, dt=0.02, friction=mu, shaft_radius=a)
    y, reg = r.states, r.regimes
    assert {6, 8} <= set(np.unique(reg)) <= {1, 6, 7, 8}
    assert {"slip velocity zero", "friction cone's edge"} <= set(r.event_kind)
    for i in np.flatnonzero(reg >= 6):
        _, normal, tangential = paper_contact(p, y[i])
        assert normal > 0
        if reg[i] == 8:
            assert abs(tangential) <= mu * normal * (1 + 1e-12)
        else:
            sign = 1.0 if reg[i] == 6 else -1.0
            assert abs(tangential - sign * mu * normal) <= 1e-9 * normal
    # Without friction, the run-up as before; friction without a radius is a ValueError.
    plain = jeffcott.run_up(p, 2.3, 2.7, 0.004, dt=0.02)
    zero = jeffcott.run_up(p, 2.3, 2.7, 0.004, dt=0.02, friction=0.0, shaft_radius=a)
    assert np.array_equal(plain.states, zero.states)
    assert not np.array_equal(plain.states, r.states)
    with pytest.raises(ValueError, match="shaft_radius"):
        jeffcott.run_up(p, 2.3, 2.7, 0.004, friction=mu)
