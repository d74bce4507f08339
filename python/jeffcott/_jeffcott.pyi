"""Type stubs of the compiled module (shapes and units in the docstrings)."""

from collections.abc import Sequence
from typing import Any

import numpy as np
import numpy.typing as npt

__version__: str

class SimulationError(RuntimeError):
    """A failed run; ``partial`` is the result computed before the failure."""

    partial: Any

class Params:
    """The paper's non-dimensional parameters (time in 1/omega_n, lengths in gaps)."""

    eta: float
    nu1: float
    nu2: float
    kx: float
    ky: float
    beta: float
    dx: float
    dy: float
    ex: float
    ey: float
    phi0: float
    def __init__(self, **fields: float) -> None: ...
    @staticmethod
    def preset(name: str) -> Params: ...
    def to_dict(self) -> dict[str, float]: ...
    @staticmethod
    def from_dict(d: dict[str, float]) -> Params: ...
    def validate(self) -> None: ...
    def with_stiffness(self, k: float) -> Params: ...
    def with_preload(self, d: float) -> Params: ...
    @property
    def forcing_period(self) -> float: ...

class StrobeRun:
    k: npt.NDArray[np.int64]  # (N+1,)
    t: npt.NDArray[np.float64]  # (N+1,)
    states: npt.NDArray[np.float64]  # (N+1, 6): x, y, x', y', x_s, y_s
    regimes: npt.NDArray[np.uint8]  # (N+1,), 1..5
    stats: dict[str, int]

class DenseRun:
    t: npt.NDArray[np.float64]  # (N,)
    states: npt.NDArray[np.float64]  # (N, 6)
    derivatives: npt.NDArray[np.float64]  # (N, 6)
    regimes: npt.NDArray[np.uint8]  # (N,)
    event_t: npt.NDArray[np.float64]  # (E,)
    event_kind: list[str]
    event_regime: npt.NDArray[np.uint8]  # (E,)
    stats: dict[str, int]

class Diagram:
    values: npt.NDArray[np.float64]  # (V,)
    points: npt.NDArray[np.float64]  # (V, record, 6)
    periods: npt.NDArray[np.int64]  # (V,), -1: none
    errors: list[str | None]

class FeTransient:
    t: npt.NDArray[np.float64]  # (N+1,) s
    x: npt.NDArray[np.float64]  # (N+1,) m
    y: npt.NDArray[np.float64]  # (N+1,) m
    regimes: npt.NDArray[np.uint8]  # (N+1,)
    onsets: npt.NDArray[np.float64]  # s
    losses: npt.NDArray[np.float64]  # s
    dofs: int
    stats: dict[str, int]

class Orbit:
    period: int
    state: npt.NDArray[np.float64]  # (6,)
    point: npt.NDArray[np.float64]  # (4,)
    multipliers: npt.NDArray[np.complex128]  # (4,), largest modulus first
    spectral_radius: float
    residual: float
    iterations: int
    minimal_period: int
    grazing: bool

class Section:
    k: npt.NDArray[np.int64]  # (record,)
    points: npt.NDArray[np.float64]  # (record, 6)
    regimes: npt.NDArray[np.uint8]  # (record,)
    period: int  # -1: none

def presets() -> list[str]: ...
def poincare(
    params: Params,
    *,
    transient: int = 300,
    record: int = 150,
    state0: Sequence[float] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
    chunk: int = 100,
) -> Section: ...
def periodic_orbit(
    params: Params,
    period: int = 1,
    *,
    transient: int = 300,
    state0: Sequence[float] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
) -> Orbit: ...
def simulate(
    params: Params,
    periods: int,
    *,
    state0: Sequence[float] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
    max_steps: int | None = None,
    chunk: int = 100,
) -> StrobeRun: ...
def simulate_dense(
    params: Params,
    t_end: float,
    dt: float,
    *,
    state0: Sequence[float] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
    max_steps: int | None = None,
    chunk: int = 100,
) -> DenseRun: ...
def bifurcation(
    params: Params,
    values: Sequence[float],
    *,
    parameter: str = "eta",
    transient: int = 300,
    record: int = 150,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
    threads: int | None = None,
) -> Diagram: ...
def ring_position(params: Params, x: float, y: float) -> tuple[float, float]: ...
def regime(params: Params, x: float, y: float) -> int: ...
def fe_transient(
    M: npt.ArrayLike,
    K: npt.ArrayLike,
    C: npt.ArrayLike,
    G: npt.ArrayLike,
    speed: float,
    *,
    ring_node: int,
    gap: float,
    ring_stiffness: float,
    ring_damping: float,
    unbalance: Sequence[tuple[int, float, float]],
    t_end: float,
    samples: int,
    preload: tuple[float, float] = (0.0, 0.0),
    ring_offset: tuple[float, float] = (0.0, 0.0),
    modes: int = 0,
    rtol: float = 1e-8,
    atol: float | None = None,
    method: str | None = None,
    layout: str = "ross6",
    chunk: int = 50,
) -> FeTransient: ...
