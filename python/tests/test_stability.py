"""Periodic orbits and Floquet multipliers against the independent reference of the Rust
tests (tests/data/stability_reference.csv: SciPy, Newton and Richardson central differences of
the stroboscopic map, no code of the crate), with tests/stability/stability_orbits.rs' bounds."""

import math

import numpy as np
import pytest

import jeffcott
from conftest import data_dir


def reference(case):
    rows = [l.split(",") for l in (data_dir() / "stability_reference.csv").read_text().splitlines()
            if l.startswith(case + ",")]
    return {r[1]: float(r[2]) for r in rows}


# (point, multiplier modulus, argument) bounds of the Rust tests for each case.
BOUNDS = {"fig8a_eta2": (5e-12, 2e-11, 3e-11), "fig8b_eta2": (4e-11, 2.5e-10, 6e-11)}


@pytest.mark.parametrize("preset,case", [("fig8a", "fig8a_eta2"), ("fig8b", "fig8b_eta2")])
def test_period_one_orbit_and_multipliers(preset, case):
    point_tol, mod_tol, arg_tol = BOUNDS[case]
    ref = reference(case)
    orbit = jeffcott.periodic_orbit(jeffcott.Params.preset(preset), 1)
    assert orbit.point.shape == (4,) and orbit.state.shape == (6,)
    assert orbit.multipliers.shape == (4,) and orbit.multipliers.dtype == np.complex128
    want = np.array([ref[k] for k in ("x", "y", "vx", "vy")])
    assert np.max(np.abs(orbit.point - want)) < point_tol
    assert orbit.residual <= 1e-11 and orbit.minimal_period == 1 and not orbit.grazing
    for i, m in enumerate(orbit.multipliers):
        assert abs(abs(m) - ref[f"mult{i}_modulus"]) < mod_tol
        assert abs(abs(np.angle(m)) - ref[f"mult{i}_argument"]) < arg_tol
    assert orbit.spectral_radius == pytest.approx(ref["mult0_modulus"], abs=mod_tol)


def test_periodic_orbit_bad_input():
    with pytest.raises(ValueError):
        jeffcott.periodic_orbit(jeffcott.Params(), 1, state0=[1.0])
