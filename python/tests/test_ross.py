"""ROSS rotors as they are (``jeffcott.ross``): skipped unless ``ross`` imports (ROSS needs
Python 3.13; CI's interpreter may be older). The truth is the shared export of the same rotor
(tests/data/rotors, made by an independent script with ROSS 3.1.0)."""

import warnings

import numpy as np
import pytest

import jeffcott
from conftest import rotors_dir
from jeffcott.ross import FeRotor, from_rotor, shaft_radius

ross = pytest.importorskip("ross", reason="ROSS is not installed (it needs Python 3.13)")


def test_from_rotor_reads_the_matrices_of_the_export():
    export = np.load(rotors_dir() / "rotor_example_1500rpm.npz")
    speed = 1500 * np.pi / 30
    fe = from_rotor(ross.rotor_example(), speed)
    assert isinstance(fe, FeRotor) and fe.speed == speed
    for name in "MKCG":
        assert np.allclose(getattr(fe, name), export[name], rtol=1e-13, atol=0), name
    # rotor_example's shaft: six elements of outer diameter 0.05 m.
    assert np.array_equal(fe.shaft_radius, np.full(7, 0.025))
    # The same run as from the exported matrices.
    kw = dict(ring_node=4, gap=1.5e-6, ring_stiffness=1e7, ring_damping=10.0,
              unbalance=[(2, 1e-4, 0.0)], t_end=0.02, samples=100)
    with warnings.catch_warnings():
        # Undamped (rotor_example's bearings have none): neutral, not linearly unstable.
        warnings.simplefilter("error")
        mine = fe.transient(**kw)
    assert not mine.linearly_unstable and abs(mine.least_damping_ratio) < 1e-12
    theirs = jeffcott.fe_transient(export["M"], export["K"], export["C"], export["G"], speed, **kw)
    assert np.allclose(mine.x, theirs.x, rtol=0, atol=1e-9 * 1.5e-6)
    assert np.array_equal(mine.regimes, theirs.regimes)


def test_shaft_radius_follows_a_stepped_shaft():
    steel = ross.Material(name="Steel", rho=7810, E=211e9, G_s=81.2e9)
    diameters = [(0.04, 0.04), (0.06, 0.05), (0.05, 0.05)]
    shaft = [ross.ShaftElement(L=0.2, idl=0.0, odl=l, odr=r, material=steel)
             for l, r in diameters]
    bearings = [ross.BearingElement(n=n, kxx=1e6, cxx=0.0) for n in (0, 3)]
    rotor = ross.Rotor(shaft, [], bearings)
    # Node 1 is where a 0.04 and a 0.06 m section meet: the larger is the shaft's surface.
    assert np.allclose(shaft_radius(rotor), [0.02, 0.03, 0.025, 0.025])
