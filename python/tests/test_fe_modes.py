"""How many modes: the Craig-Bampton reduction's error on the steady unbalance response at the
ring node (``response_error``), the fewest modes that meet a tolerance (``fewest_modes``) and
``modes="auto"``, against a reduction and steady solves written here in numpy."""

import numpy as np
import pytest

import jeffcott
from test_fe import s1_inputs

LATERAL = [0, 1, 3, 4]  # x, y, alpha, beta of ROSS's six DOFs a node


def lateral(a):
    n = a.shape[0] // 6
    keep = [6 * i + d for i in range(n) for d in LATERAL]
    return a[np.ix_(keep, keep)]


def numpy_response_error(M, K, C, G, force, ring, modes, speed):
    """The truth: T = [[I, 0], [Psi, Phi]] (boundary b = the ring node's x, y first; Psi the
    static constraint modes, Phi the lowest fixed-interface modes of K_ii, M_ii), the reduced
    and the full steady responses to ``force`` at ``speed``, compared at b."""
    n = M.shape[0]
    b = [4 * ring, 4 * ring + 1]
    i = [k for k in range(n) if k not in b]
    L = np.linalg.cholesky(M[np.ix_(i, i)])
    Li = np.linalg.inv(L)
    w2, U = np.linalg.eigh(Li @ K[np.ix_(i, i)] @ Li.T)
    Phi = Li.T @ U[:, :modes]
    Psi = -np.linalg.solve(K[np.ix_(i, i)], K[np.ix_(i, b)])
    order = b + i
    T = np.zeros((n, 2 + modes))
    T[order, :] = np.block([[np.eye(2), np.zeros((2, modes))], [Psi, Phi]])
    dyn = lambda m, k, c, g: k - speed**2 * m + 1j * speed * (c + speed * g)
    full = np.linalg.solve(dyn(M, K, C, G), force)[b]
    red = T.T @ force
    red = np.linalg.solve(dyn(*(T.T @ a @ T for a in (M, K, C, G))), red)[:2]
    return np.linalg.norm(red - full) / np.linalg.norm(full)


def s1_lateral():
    p, m = s1_inputs()
    M, K, C, G = (lateral(m[k]) for k in "MKCG")
    ring = p["ring_node"]
    unb = [(u["node"], u["magnitude_kg_m"], u["phase_rad"]) for u in p["unbalance"]]
    force = np.zeros(M.shape[0], complex)
    for node, me, phase in unb:  # m e e^{i phase} (1, -i) at the node's x, y (any speed's)
        force[4 * node] += me * np.exp(1j * phase)
        force[4 * node + 1] += -1j * me * np.exp(1j * phase)
    return (M, K, C, G), force, ring, unb


@pytest.mark.parametrize("modes", [2, 8, 16])
def test_response_error_against_numpy(modes):
    mats, force, ring, unb = s1_lateral()
    speeds = [80.0, 182.0, 300.0]
    error, speed = jeffcott.response_error(*mats, speeds, ring_node=ring, unbalance=unb,
                                           modes=modes, layout="lateral4")
    truth = [numpy_response_error(*mats, force, ring, modes, w) for w in speeds]
    assert speed == speeds[int(np.argmax(truth))]
    # To 1e-9 (measured: 5e-11): the error is a difference of two responses, each rounded
    # at the critical (182 rad/s) where the dynamic stiffness is nearly singular.
    assert error == pytest.approx(max(truth), rel=1e-6, abs=1e-9)


def test_fewest_modes_is_the_fewest_and_auto_uses_it():
    mats, force, ring, unb = s1_lateral()
    speed, tol = 182.0, 1e-4
    modes, error = jeffcott.fewest_modes(*mats, [speed], ring_node=ring, unbalance=unb,
                                         tolerance=tol, layout="lateral4")
    assert error <= tol and modes > 0
    below = jeffcott.response_error(*mats, [speed], ring_node=ring, unbalance=unb,
                                    modes=modes - 1, layout="lateral4")[0]
    assert below > tol
    kw = dict(ring_node=ring, gap=7.95e-5, ring_stiffness=1.1e6, ring_damping=0.01,
              unbalance=unb, t_end=0.05, samples=100, layout="lateral4")
    auto = jeffcott.fe_transient(*mats, speed, modes="auto", mode_tolerance=tol, **kw)
    assert (auto.modes, auto.mode_error) == (modes, error)
    assert auto.dofs == modes + 2
    fixed = jeffcott.fe_transient(*mats, speed, modes=modes, **kw)
    assert fixed.mode_error == error and fixed.modes == modes
    full = jeffcott.fe_transient(*mats, speed, **kw)
    assert (full.modes, full.mode_error) == (0, 0.0)
    with pytest.raises(ValueError, match="auto"):
        jeffcott.fe_transient(*mats, speed, modes="all", **kw)
    with pytest.raises(ValueError):
        jeffcott.fewest_modes(*mats, [speed], ring_node=ring, unbalance=unb, tolerance=0.0,
                              layout="lateral4")


def test_probe_nodes_through_the_reduction():
    # Nodes other than the ring's: the reduced model's (24 modes, through its basis) against
    # the full model's (its own coordinates) within 1e-4 of the largest displacement
    # (measured: 2.6e-5); the ring node's probe is its x, y; the velocities are the
    # displacements' derivatives (central differences: 2.8e-3 off, their O(dt^2) error).
    mats, force, ring, unb = s1_lateral()
    kw = dict(ring_node=ring, gap=7.95e-5, ring_stiffness=1.1e6, ring_damping=0.01,
              unbalance=unb, t_end=0.05, samples=500, layout="lateral4",
              probe_nodes=[5, ring, 20])
    full = jeffcott.fe_transient(*mats, 182.0, **kw)
    reduced = jeffcott.fe_transient(*mats, 182.0, modes=24, **kw)
    assert full.probe_x.shape == (501, 3) and np.array_equal(full.probe_nodes, [5, ring, 20])
    for run in (full, reduced):
        assert np.array_equal(run.probe_x[:, 1], run.x) and np.array_equal(run.probe_vy[:, 1], run.vy)
    scale = np.max(np.abs(full.probe_x))
    assert np.max(np.abs(reduced.probe_x - full.probe_x)) <= 1e-4 * scale
    assert np.max(np.abs(reduced.probe_y - full.probe_y)) <= 1e-4 * scale
    dt = full.t[1] - full.t[0]
    fd = (full.probe_y[2:, 0] - full.probe_y[:-2, 0]) / (2 * dt)
    assert np.max(np.abs(fd - full.probe_vy[1:-1, 0])) <= 5e-3 * np.max(np.abs(full.probe_vy[:, 0]))
    with pytest.raises(ValueError):
        jeffcott.fe_transient(*mats, 182.0, **{**kw, "probe_nodes": [999]})
