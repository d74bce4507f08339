"""The finite-element rotor on the ring: case S1 against the shared reference (an
independent SciPy implementation, tests/data/rotors/README of the shared set), as
tests/suite/fe/fe_s1.rs checks it."""

import json
import warnings
import numpy as np
import pytest

import jeffcott
from conftest import rotors_dir


def s1_inputs():
    d = rotors_dir()
    params = json.loads((d / "S1_reference.json").read_text())["parameters"]
    m = np.load(d / params["rotor_file"])
    return params, m


def s1_run(t_end, **kw):
    p, m = s1_inputs()
    unb = [(u["node"], u["magnitude_kg_m"], u["phase_rad"]) for u in p["unbalance"]]
    samples = round(t_end / p["sample_spacing_s"])
    return jeffcott.fe_transient(
        m["M"], m["K"], m["C"], m["G"], p["speed_rad_s"], ring_node=p["ring_node"],
        gap=p["gamma_m"], ring_stiffness=p["k_s_N_per_m"], ring_damping=p["c_s_N_s_per_m"],
        preload=(p["Delta_x_m"], p["Delta_y_m"]), ring_offset=tuple(p["ring_offset_m"]),
        unbalance=unb, t_end=t_end, samples=samples, **kw), p


def reference(t_end):
    ref = np.loadtxt(rotors_dir() / "S1_reference.csv", delimiter=",", skiprows=1)
    return ref[ref[:, 0] <= t_end * (1 + 1e-12)]


def events(t_end):
    rows = [l.split(",") for l in (rotors_dir() / "S1_events.csv").read_text().splitlines()[1:]]
    pick = lambda kind: np.array([float(r[1]) for r in rows if r[0] == kind and float(r[1]) <= t_end])
    return pick("onset"), pick("loss")


def test_s1_full_model_radau5():
    # tests/suite/fe/fe_s1.rs: all 1001 samples within 1e-6 of the gap, 7 onsets and 6 losses at
    # the reference's times (within 1e-9 s).
    run, p = s1_run(0.5, rtol=1e-8, form="physical")
    assert run.method == "radau5"
    ref = reference(0.5)
    assert run.t.shape == run.x.shape == run.y.shape == (1001,)
    assert run.x.dtype == np.float64 and run.regimes.dtype == np.uint8
    assert run.dofs == 136  # 34 nodes x 4 lateral DOFs
    assert not run.linearly_unstable and run.least_damping_ratio > 0
    assert np.max(np.abs(run.t - ref[:, 0])) <= 1e-12
    err = np.max(np.hypot(run.x - ref[:, 1], run.y - ref[:, 2])) / p["gamma_m"]
    assert err <= 1e-6, f"{err:e} gap"
    onsets, losses = events(0.5)
    assert run.onsets.shape == (7,) and run.losses.shape == (6,)
    assert np.max(np.abs(run.onsets - onsets)) <= 1e-9
    assert np.max(np.abs(run.losses - losses)) <= 1e-9


def test_s1_craig_bampton_reduction_follows_the_reference():
    # A reduction to 16 modes is an approximation: the first contact at the reference's time
    # within 1e-5 s and the orbit within a few percent of the gap until then.
    run, p = s1_run(0.01, modes=16)
    onsets, _ = events(0.01)
    assert run.onsets.shape == onsets.shape == (1,)
    assert abs(run.onsets[0] - onsets[0]) < 1e-5
    ref = reference(0.01)
    err = np.max(np.hypot(run.x - ref[:, 1], run.y - ref[:, 2])) / p["gamma_m"]
    assert err < 0.05


@pytest.mark.parametrize("change", [
    {"ring_node": 99},
    {"gap": -1.0},
    {"ring_stiffness": 0.0},
    {"unbalance": [(99, 1e-3, 0.0)]},
    {"layout": "ross5"},
    {"method": "euler"},
    {"samples": 0},
    {"modes": 10**6},
])
def test_fe_bad_input_raises_value_error(change):
    p, m = s1_inputs()
    kw = dict(ring_node=12, gap=7.95e-5, ring_stiffness=1.1e6, ring_damping=0.01,
              unbalance=[(12, 2e-3, 0.0)], t_end=1e-3, samples=2)
    kw.update(change)
    with pytest.raises(ValueError):
        jeffcott.fe_transient(m["M"], m["K"], m["C"], m["G"], 125.0, **kw)


def test_fe_non_square_matrix_raises_value_error():
    _, m = s1_inputs()
    with pytest.raises(ValueError, match="square"):
        jeffcott.fe_transient(m["M"][:, :-1], m["K"], m["C"], m["G"], 125.0, ring_node=12,
                              gap=7.95e-5, ring_stiffness=1.1e6, ring_damping=0.01,
                              unbalance=[], t_end=1e-3, samples=2)


def test_fe_matrices_as_any_array_like():
    # What numpy users pass: nested lists, float32, Fortran order (the stubs say ArrayLike).
    # Each gives bit for bit the run on the same values as C-ordered float64; float32 values
    # are those of the float32 matrices widened, so that run is the truth for them.
    p, m = s1_inputs()
    short = dict(ring_node=p["ring_node"], gap=p["gamma_m"], ring_stiffness=p["k_s_N_per_m"],
                 ring_damping=p["c_s_N_s_per_m"], preload=(p["Delta_x_m"], p["Delta_y_m"]),
                 unbalance=[(u["node"], u["magnitude_kg_m"], u["phase_rad"])
                            for u in p["unbalance"]], t_end=0.01, samples=20, modes=8)
    names = ("M", "K", "C", "G")

    def run(convert):
        r = jeffcott.fe_transient(*(convert(m[n]) for n in names), p["speed_rad_s"], **short)
        return np.concatenate([r.x, r.y, r.onsets, r.losses])

    base = run(np.ascontiguousarray)
    assert np.array_equal(run(lambda a: a.tolist()), base)
    assert np.array_equal(run(np.asfortranarray), base)
    widened = run(lambda a: a.astype(np.float32).astype(np.float64))
    assert np.array_equal(run(lambda a: a.astype(np.float32)), widened)
    with pytest.raises((ValueError, TypeError)):
        jeffcott.fe_transient([["a"]], m["K"], m["C"], m["G"], 125.0, **short)


def one_node(q, c=0.02, k=1.0):
    # One node (layout lateral4: x, y, alpha, beta), cross-coupled stiffness q in x-y.
    M = np.eye(4)
    K = np.diag([k, k, 1.0, 1.0])
    K[0, 1], K[1, 0] = q, -q
    return M, K, c * np.eye(4), np.zeros((4, 4))


def numpy_least_damping_ratio(M, K, C):
    # The truth, independent of the crate: numpy's eigenvalues of the first-order form.
    n = len(M)
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ C]])
    lam = np.linalg.eigvals(A)
    return np.min(-lam.real / np.abs(lam))


@pytest.mark.parametrize("q, unstable", [(0.01, False), (0.05, True)])
def test_fe_linearly_unstable_rotor_is_flagged(q, unstable):
    # Cross-coupling q against the threshold c sqrt(k) = 0.02: below it stable, above it a
    # forward mode grows (the ring out of reach: the free response alone).
    M, K, C, G = one_node(q)
    kw = dict(ring_node=0, gap=1e6, ring_stiffness=1.0, ring_damping=0.0,
              unbalance=[(0, 1e-3, 0.0)], t_end=1.0, samples=10, layout="lateral4")
    truth = numpy_least_damping_ratio(M, K, C)
    assert (truth < 0) == unstable
    if unstable:
        with pytest.warns(RuntimeWarning, match="linearly unstable"):
            run = jeffcott.fe_transient(M, K, C, G, 1.0, **kw)
    else:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            run = jeffcott.fe_transient(M, K, C, G, 1.0, **kw)
    assert run.linearly_unstable == unstable
    assert abs(run.least_damping_ratio - truth) <= 1e-12


def test_s1_full_model_default_is_modal_etd4():
    # The default path for the full model (the fastest measured, docs/fe-rotors.md): the modal
    # form with ETD4, within 1e-6 of the gap of the shared reference (4.97e-9 measured at rtol
    # 1e-8) with its onsets and losses.
    run, p = s1_run(0.5, rtol=1e-8)
    assert run.method == "etd4" and run.dofs == 136
    ref = reference(0.5)
    err = np.max(np.hypot(run.x - ref[:, 1], run.y - ref[:, 2])) / p["gamma_m"]
    assert err <= 1e-6, f"{err:e} gap"
    onsets, losses = events(0.5)
    assert np.max(np.abs(run.onsets - onsets)) <= 1e-6
    assert np.max(np.abs(run.losses - losses)) <= 1e-6


def test_fe_transient_default_falls_back_to_radau5_without_a_modal_form():
    # A free-free rotor (K = 0 on x, y: the rigid modes at lambda = 0 are defective) has no
    # modal form: asked for, a ValueError says why; by default the physical form with radau5
    # runs, and `method` says so.
    M, K, C, G = np.eye(4), np.diag([0.0, 0.0, 1.0, 1.0]), np.zeros((4, 4)), np.zeros((4, 4))
    kw = dict(ring_node=0, gap=1.0, ring_stiffness=1.0, ring_damping=0.0,
              unbalance=[(0, 1e-3, 0.0)], t_end=1.0, samples=10, layout="lateral4")
    with pytest.raises(ValueError, match="condition number"):
        jeffcott.fe_transient(M, K, C, G, 1.0, form="modal", **kw)
    run = jeffcott.fe_transient(M, K, C, G, 1.0, **kw)
    assert run.method == "radau5" and run.t.shape == (11,)


@pytest.mark.parametrize("kw, allowed", [(dict(), 1e-6), (dict(method="dop853", modes=24), 1e-4)])
def test_s1_modal_form(kw, allowed):
    # The modal form (free flight exact; in contact ETD4, its default, or DOP853) against the
    # shared reference as the physical form is: the full rotor within 1e-6 of the gap
    # (measured 3.7e-9), 24 Craig-Bampton modes within 1e-4 (4.7e-5, as in physical form); the
    # same onsets and losses.
    run, p = s1_run(0.5, rtol=1e-8, form="modal", **kw)
    ref = reference(0.5)
    err = np.max(np.hypot(run.x - ref[:, 1], run.y - ref[:, 2])) / p["gamma_m"]
    assert err <= allowed, f"{err:e} gap"
    onsets, losses = events(0.5)
    assert np.max(np.abs(run.onsets - onsets)) <= 1e-6
    assert np.max(np.abs(run.losses - losses)) <= 1e-6
    assert run.dofs == (136 if "modes" not in kw else 26) and run.stats["steps"] > 0


@pytest.mark.parametrize("kw", [dict(method="etd4", form="physical"),
                                dict(form="modal", probe_nodes=[3]), dict(form="spectral")])
def test_fe_form_and_method_must_agree(kw):
    with pytest.raises(ValueError):
        s1_run(0.01, **kw)
