"""Basins of attraction against the truths of tests/suite/global/global_scan.rs: at eta = 2.2 the
Fig. 8a model has a period-1 and a period-3 attractor on the grid (-1..1) x (-1.5..1.5) of
(x0, x0'), and the run from rest reaches period 3 (the paper's 2.165: period 1 ends below 2.2)."""


import numpy as np
import pytest

import jeffcott
from conftest import interrupted_after

# That test's settings: 1000 periods of transient, up to 2000; 32 recorded.
SETTINGS = dict(transient=1000, record=32, max_transient=2000)


def same_cycle(a, b, tol=1e-3):
    return a.shape == b.shape and any(np.max(np.abs(np.roll(a, s, axis=0) - b)) < tol
                                      for s in range(len(a)))


def test_basins_at_eta_2_2_hold_period_1_and_period_3():
    p = jeffcott.Params.preset("fig8a")
    p.eta = 2.2
    x, y = np.linspace(-1.0, 1.0, 5), np.linspace(-1.5, 1.5, 4)
    b = jeffcott.basins(p, x, y, threads=2, **SETTINGS)
    assert b.labels.shape == (4, 5) and b.labels.dtype == np.int64
    assert b.x.shape == (5,) and b.y.shape == (4,) and b.names == ("x0", "vx0")
    assert sorted(a.period for a in b.attractors) == [1, 3]
    assert b.failures == [] and (b.labels >= 0).all()
    assert sum(a.count for a in b.attractors) == 20
    for k, a in enumerate(b.attractors):
        assert a.cycle.shape == (a.period, 6) and a.cycle.dtype == np.float64
        assert (b.labels == k).sum() == a.count and b.labels.flat[a.first] == k
    # From rest: period 3, one of the grid's attractors.
    rest = jeffcott.basins(p, [0.0], [0.0], **SETTINGS)
    assert rest.labels.shape == (1, 1) and rest.attractors[0].period == 3
    assert any(same_cycle(rest.attractors[0].cycle, a.cycle) for a in b.attractors)


@pytest.mark.parametrize("kw", [dict(plane="x-z"), dict(record=1), dict(threads=0),
                                dict(match_state=0.0)])
def test_basins_bad_input(kw):
    with pytest.raises(ValueError):
        jeffcott.basins(jeffcott.Params(), [0.0], [0.0], **kw)
    with pytest.raises(ValueError):
        jeffcott.basins(jeffcott.Params(), [], [0.0])


def test_ctrl_c_stops_a_basin_scan_between_rows():
    p = jeffcott.Params.preset("fig8a")
    p.eta = 2.2
    elapsed = interrupted_after(0.5, lambda: jeffcott.basins(
        p, np.linspace(-1, 1, 8), np.linspace(-1.5, 1.5, 10000), threads=2))
    assert elapsed < 5.0, f"KeyboardInterrupt after {elapsed:.2f} s"
