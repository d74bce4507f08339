"""fe_rub_map: the rub map of a finite-element rotor (one lateral4 node with its tilts and
gyroscopic coupling, as test_fe_run_up builds it) continued in speed. Truths computed here with
numpy, not by the crate: the linear unbalance response (the complex dynamic stiffness solved at
each speed), the speed where its orbit at the ring node first reaches the gap (bisection), and
the orbit's largest radius below it (the ellipse's semi-major axis)."""

import numpy as np
import pytest

import jeffcott
from conftest import interrupted_after
from test_fe_run_up import GAP, KS, ME, PHASE, matrices


def anisotropic():
    """The test rotor with its y support 30 % stiffer: an elliptical orbit, which first
    touches the ring at two points a revolution."""
    M, K, C, G = matrices()
    K = K.copy()
    K[1, 1] *= 1.3
    return M, K, C, G


def free_radius(mats, w):
    """The largest radius of the linear steady orbit at the node, from numpy's solve of
    (K - w^2 M + i w (C + w G)) X = F: Re(Z e^{i theta}) for Z = (X_x, X_y) is an ellipse of
    semi-major axis sqrt((|Z|^2 + |Z.Z|)/2)."""
    M, K, C, G = mats
    f = ME * w * w * np.exp(1j * PHASE)
    F = np.array([f, -1j * f, 0.0, 0.0])
    X = np.linalg.solve(K - w * w * M + 1j * w * (C + w * G), F)
    z = X[:2]
    return np.sqrt((np.vdot(z, z).real + abs(z @ z)) / 2.0)


def first_contact(mats, lo, hi):
    assert free_radius(mats, lo) < GAP < free_radius(mats, hi)
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if free_radius(mats, mid) < GAP else (lo, mid)
    return 0.5 * (lo + hi)


def rub_map(mats, lo, hi, **kw):
    M, K, C, G = mats
    return jeffcott.fe_rub_map(M, K, C, G, lo, hi, ring_node=0, gap=GAP, ring_stiffness=KS,
                               ring_damping=0.5, unbalance=[(0, ME, PHASE)], layout="lateral4",
                               rtol=1e-11, method="dop853", **kw)


@pytest.mark.parametrize("mats, kind", [(matrices(), "isotropic"), (anisotropic(), "anisotropic")])
def test_the_first_contact_is_where_numpys_linear_response_reaches_the_gap(mats, kind):
    graze = first_contact(mats, 6.0, 9.9)
    m = rub_map(mats, 6.0, 9.9, max_points=80)
    first = m.specials[0]
    assert first.kind == "grazing" and first.converged, (first.kind, first.unconverged)
    assert abs(first.speed - graze) <= 1e-8, (first.speed, graze)
    # Off the ring: the amplitudes are numpy's, nothing touches.
    free = m.speed < graze
    assert free.sum() >= 3
    expected = np.array([free_radius(mats, w) for w in m.speed[free]])
    assert np.max(np.abs(m.amplitude[free] - expected)) <= 1e-8 * GAP
    assert np.all(m.contact_fraction[free] == 0.0) and np.all(m.peak_force[free] == 0.0)
    # Past it: in contact, pressed on the ring; an isotropic rotor's rub is a full annular rub
    # (in contact all the period, no onset), an anisotropic one's touches twice a revolution.
    past = m.speed > graze + 1e-6
    assert past.sum() >= 3
    assert np.all(m.amplitude[past] > GAP) and np.all(m.peak_force[past] > 0.0)
    if kind == "isotropic":
        assert np.all(m.contact_fraction[past] == 1.0) and np.all(m.contacts[past] == 0)
    else:
        assert m.contacts[past][0] == 2 and 0.0 < m.contact_fraction[past][0] < 1.0
    assert m.failures == [] and m.modes == 0 and m.mode_error == 0.0


def test_bearings_that_follow_the_speed_move_the_first_contact_as_numpy_says():
    # The supports 20 % stiffer at 10 rad/s than at 6, linear between (as BearingTable
    # interpolates): numpy's response with K(w) at each speed is the truth.
    M, K, C, G = anisotropic()
    K10 = K.copy()
    K10[:2, :2] *= 1.2

    def k_at(w):
        return K + (w - 6.0) / 4.0 * (K10 - K)

    def radius(w):
        return free_radius((M, k_at(w), C, G), w)

    lo, hi = 6.0, 9.99
    assert radius(lo) < GAP < radius(hi)
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if radius(mid) < GAP else (lo, mid)
    graze = 0.5 * (lo + hi)
    m = rub_map((M, K, C, G), 6.0, 9.99, max_points=80, bearing_speeds=[6.0, 10.0],
                bearing_K=[K, K10], bearing_C=[C, C])
    first = m.specials[0]
    assert first.kind == "grazing" and first.converged, first.unconverged
    assert abs(first.speed - graze) <= 1e-8, (first.speed, graze)
    # Without the table the contact comes elsewhere: the bearings were followed.
    assert abs(graze - first_contact(anisotropic(), 6.0, 9.9)) > 1e-3


def test_bad_input_is_a_value_error():
    M, K, C, G = matrices()
    with pytest.raises(ValueError, match="speed"):
        jeffcott.fe_rub_map(M, K, C, G, -1.0, 9.0, ring_node=0, gap=GAP, ring_stiffness=KS,
                            ring_damping=0.5, unbalance=[(0, ME, PHASE)], layout="lateral4")
    with pytest.raises(ValueError, match="ring_node|node"):
        jeffcott.fe_rub_map(M, K, C, G, 6.0, 9.0, ring_node=3, gap=GAP, ring_stiffness=KS,
                            ring_damping=0.5, unbalance=[(0, ME, PHASE)], layout="lateral4")
    with pytest.raises(ValueError, match="samples"):
        rub_map(matrices(), 6.0, 9.0, samples=2)


def test_ctrl_c_stops_it():
    # A map of 10^5 tiny steps (minutes), stopped 0.3 s in: within a step.
    took = interrupted_after(0.3, lambda: rub_map(matrices(), 6.0, 30.0, ds=1e-4, ds_max=1e-4,
                                                  max_points=100000))
    assert took < 5.0
