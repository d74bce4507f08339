"""Periodic orbits and Floquet multipliers against the independent reference of the Rust
tests (tests/data/stability_reference.csv: SciPy, Newton and Richardson central differences of
the stroboscopic map, no code of the crate), with tests/suite/stability/stability_orbits.rs' bounds."""

import math
import subprocess
import sys

import numpy as np
import pytest

import jeffcott
from conftest import data_dir, interrupted_after, stamps_during


def reference(case, column=2):
    rows = [l.split(",") for l in (data_dir() / "stability_reference.csv").read_text().splitlines()
            if l.startswith(case + ",")]
    return {r[1]: float(r[column]) for r in rows}


def reference_error(case, quantity):
    """The reference's largest stated error of the four multipliers' `quantity`, plus 3e-11 of
    ours (as the Rust test: tests/suite/stability/stability_orbits.rs)."""
    err = reference(case, column=3)
    return max(err[f"mult{i}_{quantity}"] for i in range(4)) + 3e-11


# (point, multiplier modulus, argument) bounds of the Rust tests for each case.
BOUNDS = {
    "fig8a_eta2": (5e-12, reference_error("fig8a_eta2", "modulus"),
                   reference_error("fig8a_eta2", "argument")),
    "fig8b_eta2": (4e-11, 2.5e-10, 6e-11),
}


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


def test_lyapunov_spectrum_of_a_stable_orbit_is_the_log_of_its_multipliers():
    # As tests/suite/stability/stability_lyapunov.rs: Fig. 8a at eta = 2, 500 + 100 + 2000 periods;
    # the truth is ln|multiplier| of the independent reference, with that test's bounds.
    ref = reference("fig8a_eta2")
    l = jeffcott.lyapunov_exponents(jeffcott.Params.preset("fig8a"), transient=500, align=100,
                                    periods=2000, batch=100)
    assert l.exponents.shape == (4,) and l.exponents.dtype == np.float64
    assert l.stderr.shape == l.per_time.shape == l.per_time_stderr.shape == (4,)
    assert l.running.shape == (20, 4) and l.batches == 20 and l.end.shape == (6,)
    m = l.exponents
    assert abs(m[0] - math.log(ref["mult0_modulus"])) < 1e-6
    # The complex pair's two exponents split over a finite run; their mean converges.
    assert abs(0.5 * (m[1] + m[2]) - math.log(ref["mult1_modulus"])) < 1e-6
    assert abs(m[3] - math.log(ref["mult3_modulus"])) < 1e-8
    assert l.stderr[0] < 1e-6
    assert l.forcing_period == pytest.approx(math.pi)
    assert np.allclose(l.per_time, m / l.forcing_period, rtol=1e-15, atol=0)
    # The two-trajectory estimate (plain runs, no variational code) against the same truth.
    assert l.two_trajectory is not None
    assert abs(l.two_trajectory - math.log(ref["mult0_modulus"])) < 1e-6
    one = jeffcott.lyapunov_exponents(jeffcott.Params.preset("fig8a"), periods=200, batch=10,
                                      exponents=1, separation=None)
    assert one.exponents.shape == (1,) and one.two_trajectory is None


@pytest.mark.parametrize("kw", [dict(periods=10, batch=20), dict(separation=0.0),
                                dict(exponents=5), dict(state0=[0.0])])
def test_lyapunov_bad_input(kw):
    with pytest.raises(ValueError):
        jeffcott.lyapunov_exponents(jeffcott.Params(), **kw)


@pytest.mark.parametrize("preset,case", [("fig8a", "fig8a_flip"), ("fig8b", "fig8b_flip")])
def test_continuation_finds_the_fig8_flip(preset, case):
    # The period-1 orbit from eta = 2 to 2.3 (tests/suite/global/global_continuation.rs): one flip,
    # at the independent reference's eta* (stability_reference.csv) within that test's 3e-8.
    flip_ref = reference(case)["flip_eta"]
    b = jeffcott.continue_orbit(jeffcott.Params.preset(preset), 2.0, 2.3)
    n = len(b.parameters)
    assert b.end == "reached" and b.period == 1 and b.parameter_name == "eta"
    assert b.points.shape == (n, 4) and b.states.shape == (n, 6)
    assert b.multipliers.shape == (n, 4) and b.multipliers.dtype == np.complex128
    assert b.stable.dtype == np.bool_ and b.contacts.dtype == np.int64
    assert b.arclength.shape == (n,)
    flips = [s for s in b.specials if s.kind == "flip"]
    assert len(flips) == 1
    f = flips[0]
    assert f.converged and abs(f.parameter - flip_ref) < 3e-8, f.parameter
    assert abs(f.multipliers[0].real + 1.0) < 1e-5 and abs(f.multipliers[0].imag) < 1e-9
    assert f.bracket[0] <= f.parameter <= f.bracket[1] or f.bracket[1] <= f.parameter <= f.bracket[0]
    # Stable before the flip, unstable after.
    assert np.array_equal(b.stable, b.parameters < f.parameter)


@pytest.mark.parametrize("args,kw", [((2.0, 2.0), {}), ((2.0, 2.3), dict(parameter="zeta")),
                                     ((2.0, 2.3), dict(ds=-1.0)), ((2.0, 2.3), dict(period=0))])
def test_continuation_bad_input(args, kw):
    with pytest.raises(ValueError):
        jeffcott.continue_orbit(jeffcott.Params.preset("fig8a"), *args, transient=0, **kw)


def test_lyapunov_releases_the_gil():
    # As test_paper's check: a Python thread leaves time stamps inside the call's window.
    p = jeffcott.Params.preset("fig9c")
    duration, inside = stamps_during(
        lambda: jeffcott.lyapunov_exponents(p, transient=0, periods=1500))
    assert duration > 0.1, "the run is too short to tell"
    assert len(inside) >= 10, f"{len(inside)} stamps in a {duration:.3f} s run"


# The reference period-1 point of Fig. 8a at eta = 2 (tests/suite/global/global_continuation.rs),
# the ring at rest inside the gap: a start with no transient.
FIG8A_POINT = [0.5781094858, -0.0232587983, 0.0944197873, -0.3099208533, 0.0, 0.0]


def test_ctrl_c_stops_lyapunov_exponents_between_periods():
    # No transient: the periods of the library call itself (uninterrupted: 10 to 30 s, far
    # past the bound).
    p = jeffcott.Params.preset("fig9c")
    elapsed = interrupted_after(
        0.5, lambda: jeffcott.lyapunov_exponents(p, transient=0, periods=50_000))
    assert elapsed < 5.0, f"KeyboardInterrupt after {elapsed:.2f} s"


def test_ctrl_c_stops_a_continuation_between_steps():
    # No transient: the continuation itself, in small steps (uninterrupted: about 30 s).
    p = jeffcott.Params.preset("fig8a")
    elapsed = interrupted_after(0.5, lambda: jeffcott.continue_orbit(
        p, 2.0, 2.2, transient=0, state0=FIG8A_POINT, ds=1e-6, ds_max=1e-6,
        max_points=10**6))
    assert elapsed < 5.0, f"KeyboardInterrupt after {elapsed:.2f} s"


def test_a_ctrl_c_pending_at_the_first_array_is_a_keyboard_interrupt(tmp_path):
    # A fresh interpreter whose first numpy array from the extension comes after a Ctrl-C
    # pressed during a call that does not look for it (Newton on P^2000 of the stable orbit of
    # Fig. 8a, seconds long): the KeyboardInterrupt comes when the call returns, and numpy's
    # C API, loaded by the extension's import, is not loaded under it (that was a panic).
    code = (
        "import _thread, threading, jeffcott\n"
        "threading.Timer(0.3, _thread.interrupt_main).start()\n"
        "try:\n"
        "    jeffcott.periodic_orbit(jeffcott.Params.preset('fig8a'), 2000, transient=0,\n"
        f"                            state0={FIG8A_POINT})\n"
        "except KeyboardInterrupt:\n"
        "    print('KeyboardInterrupt')\n"
    )
    # Run from an empty folder: `-c` puts the working directory first on sys.path, and from
    # python/ that is the package's sources without the compiled extension.
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         timeout=120, cwd=tmp_path)
    assert out.returncode == 0 and out.stdout.strip() == "KeyboardInterrupt", out.stderr[-2000:]
