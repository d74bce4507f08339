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

class ContactEpisodes:
    start: npt.NDArray[np.float64]  # (E,) s: onset, or the run's start
    end: npt.NDArray[np.float64]  # (E,) s: loss; NaN if open at the run's end
    duration: npt.NDArray[np.float64]  # (E,) s
    peak_force: npt.NDArray[np.float64]  # (E,) N: samples, onset and loss
    impulse: npt.NDArray[np.float64]  # (E,) N s: trapezoid on samples, onset and loss

class Revolutions:
    start: npt.NDArray[np.float64]  # (R,) s
    end: npt.NDArray[np.float64]  # (R,) s
    speed: npt.NDArray[np.float64]  # (R,) rad/s, 2 pi / (end - start)
    peak_radius: npt.NDArray[np.float64]  # (R,) m from the ring's rest centre, located
    contact_time: npt.NDArray[np.float64]  # (R,) s
    amplitude_1x: npt.NDArray[np.float64]  # (R,) m, the forward 1x whirl's radius
    phase_1x: npt.NDArray[np.float64]  # (R,) rad, against FeRun.phase

class FeRun:
    t: npt.NDArray[np.float64]  # (N,) s
    speed: npt.NDArray[np.float64]  # (N,) rad/s
    phase: npt.NDArray[np.float64]  # (N,) rad, the integral of the speed
    x: npt.NDArray[np.float64]  # (N,) m, the ring node
    y: npt.NDArray[np.float64]  # (N,) m
    vx: npt.NDArray[np.float64]  # (N,) m/s
    vy: npt.NDArray[np.float64]  # (N,) m/s
    ring_x: npt.NDArray[np.float64]  # (N,) m, the ring's centre from its rest
    ring_y: npt.NDArray[np.float64]  # (N,) m
    force_x: npt.NDArray[np.float64]  # (N,) N, the ring's force on the rotor
    force_y: npt.NDArray[np.float64]  # (N,) N
    normal_force: npt.NDArray[np.float64]  # (N,) N, >= 0
    friction_force: npt.NDArray[np.float64]  # (N,) N, along the tangent (counter-clockwise)
    whirl_rate: npt.NDArray[np.float64]  # (N,) rad/s, > 0 forward, < 0 backward
    slip_velocity: npt.NDArray[np.float64]  # (N,) m/s; 0 rolling, NaN free or frictionless
    rub_torque: npt.NDArray[np.float64]  # (N,) N m on the shaft, shaft_radius * friction_force
    friction_power: npt.NDArray[np.float64]  # (N,) W dissipated by friction, >= 0
    friction_energy: float  # J, the power's trapezoidal integral over the samples
    probe_nodes: npt.NDArray[np.uint64]  # (P,)
    probe_x: npt.NDArray[np.float64]  # (N, P) m
    probe_y: npt.NDArray[np.float64]  # (N, P) m
    probe_vx: npt.NDArray[np.float64]  # (N, P) m/s
    probe_vy: npt.NDArray[np.float64]  # (N, P) m/s
    regimes: npt.NDArray[np.uint8]  # (N,)
    onsets: npt.NDArray[np.float64]  # s
    losses: npt.NDArray[np.float64]  # s
    contacts: ContactEpisodes
    revolutions: Revolutions
    dofs: int
    modes: int  # Craig-Bampton modes kept, 0: the full model
    mode_error: float  # the reduction's steady-response error over the run's speeds
    least_damping_ratio: float  # min -Re(lambda)/|lambda|; NaN if not computed
    linearly_unstable: bool  # a mode grows beyond rounding (a RuntimeWarning too)
    method: str  # the integration method that ran: asked for, or the default picked
    stats: dict[str, int]

FeTransient = FeRun

class WhirlSpectrum:
    frequency: npt.NDArray[np.float64]  # (B,) per unit of t
    forward: npt.NDArray[np.float64]  # (B,)
    backward: npt.NDArray[np.float64]  # (B,)

class OrderTrack:
    orders: npt.NDArray[np.float64]  # (K,)
    time: npt.NDArray[np.float64]  # (W,) window centres
    speed: npt.NDArray[np.float64]  # (W,) rad per unit of t
    forward: npt.NDArray[np.float64]  # (W, K)
    backward: npt.NDArray[np.float64]  # (W, K)
    waterfall_orders: npt.NDArray[np.float64]  # (B,)
    waterfall_forward: npt.NDArray[np.float64]  # (W, B)
    waterfall_backward: npt.NDArray[np.float64]  # (W, B)

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

class Lyapunov:
    exponents: npt.NDArray[np.float64]  # (p,) per forcing period, largest first
    stderr: npt.NDArray[np.float64]  # (p,)
    per_time: npt.NDArray[np.float64]  # (p,) per unit tau
    per_time_stderr: npt.NDArray[np.float64]  # (p,)
    running: npt.NDArray[np.float64]  # (batches, p)
    batches: int
    forcing_period: float
    two_trajectory: float | None
    two_trajectory_stderr: float | None
    grazing_events: int
    min_margin: float
    open_sections: int
    end: npt.NDArray[np.float64]  # (6,)

class SpecialPoint:
    kind: str  # "fold", "flip", "neimark-sacker", "grazing"
    parameter: float
    bracket: tuple[float, float]
    converged: bool
    unconverged: str | None
    point: npt.NDArray[np.float64]  # (4,)
    multipliers: npt.NDArray[np.complex128]  # (4,)
    contacts: tuple[int, int]
    after_point: int

class Branch:
    parameter_name: str
    period: int
    parameters: npt.NDArray[np.float64]  # (N,)
    points: npt.NDArray[np.float64]  # (N, 4)
    states: npt.NDArray[np.float64]  # (N, 6)
    multipliers: npt.NDArray[np.complex128]  # (N, 4)
    stable: npt.NDArray[np.bool_]  # (N,)
    grazing: npt.NDArray[np.bool_]  # (N,)
    contacts: npt.NDArray[np.int64]  # (N,)
    arclength: npt.NDArray[np.float64]  # (N,)
    specials: list[SpecialPoint]
    end: str  # "reached", "max-points", "stalled"
    end_reason: tuple[float, str] | None

class BasinAttractor:
    period: int  # 0: not periodic
    cycle: npt.NDArray[np.float64]  # (period, 6)
    count: int
    first: int
    contacts_per_period: float
    contact_fraction: float
    description: str

class Basins:
    x: npt.NDArray[np.float64]  # (nx,)
    y: npt.NDArray[np.float64]  # (ny,)
    names: tuple[str, str]
    labels: npt.NDArray[np.int64]  # (ny, nx), -1: failed
    attractors: list[BasinAttractor]
    failures: list[tuple[int, str]]

class RunUp:
    tau: npt.NDArray[np.float64]  # (N,) 1/omega_n
    eta: npt.NDArray[np.float64]  # (N,)
    phase: npt.NDArray[np.float64]  # (N,) rad
    x: npt.NDArray[np.float64]  # (N,) gaps
    y: npt.NDArray[np.float64]  # (N,) gaps
    states: npt.NDArray[np.float64]  # (N, 6)
    regimes: npt.NDArray[np.uint8]  # (N,)
    event_t: npt.NDArray[np.float64]  # (E,)
    event_kind: list[str]
    ramp_time: float
    stats: dict[str, int]

def presets() -> list[str]: ...
def lyapunov_exponents(
    params: Params,
    *,
    transient: int = 300,
    align: int = 100,
    periods: int = 2000,
    batch: int = 100,
    separation: float | None = 1e-8,
    exponents: int | None = None,
    state0: Sequence[float] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
) -> Lyapunov: ...
def continue_orbit(
    params: Params,
    start: float,
    stop: float,
    *,
    parameter: str = "eta",
    period: int = 1,
    transient: int = 300,
    state0: Sequence[float] | None = None,
    ds: float | None = None,
    ds_max: float | None = None,
    max_points: int | None = None,
    bracket_width: float | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
) -> Branch: ...
def basins(
    params: Params,
    x: Sequence[float],
    y: Sequence[float],
    *,
    plane: str = "x-vx",
    transient: int = 500,
    record: int = 64,
    max_transient: int = 4000,
    match_state: float = 1e-3,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
    threads: int | None = None,
) -> Basins: ...
def run_up(
    params: Params,
    eta_from: float,
    eta_to: float | None = None,
    rate: float | None = None,
    *,
    motor: Motor | None = None,
    inertia: float | None = None,
    t_end: float | None = None,
    dt: float = 0.05,
    ring: bool = True,
    state0: Sequence[float] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
    friction: float = 0.0,
    shaft_radius: float | None = None,
) -> RunUp: ...
def poincare(
    params: Params,
    *,
    transient: int = 300,
    record: int = 150,
    state0: Sequence[float] | None = None,
    rtol: float | None = None,
    atol: float | None = None,
    method: str | None = None,
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
    friction: float = 0.0,
    shaft_radius: float | None = None,
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
    friction: float = 0.0,
    shaft_radius: float | None = None,
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
class RubSpecialPoint:
    kind: str  # "fold", "flip", "neimark-sacker", "grazing"
    speed: float  # rad/s
    bracket: tuple[float, float]
    converged: bool
    unconverged: str | None
    spectral_radius: float
    contacts: tuple[int, int]

class RubMap:
    speed: npt.NDArray[np.float64]  # (N,) rad/s
    amplitude: npt.NDArray[np.float64]  # (N,) m
    contact_fraction: npt.NDArray[np.float64]  # (N,)
    peak_force: npt.NDArray[np.float64]  # (N,) N
    stable: npt.NDArray[np.bool_]  # (N,)
    spectral_radius: npt.NDArray[np.float64]  # (N,)
    contacts: npt.NDArray[np.int64]  # (N,)
    specials: list[RubSpecialPoint]
    end: str  # "reached", "max-points", "stalled", "stopped"
    end_reason: tuple[float, str] | None
    failures: list[tuple[int, str]]
    modes: int
    mode_error: float

def fe_rub_map(
    M: npt.ArrayLike,
    K: npt.ArrayLike,
    C: npt.ArrayLike,
    G: npt.ArrayLike,
    speed_from: float,
    speed_to: float,
    *,
    ring_node: int,
    gap: float,
    ring_stiffness: float,
    ring_damping: float,
    unbalance: Sequence[tuple[int, float, float]],
    preload: tuple[float, float] = (0.0, 0.0),
    ring_offset: tuple[float, float] = (0.0, 0.0),
    modes: int | str = 0,
    mode_tolerance: float = 1e-3,
    bearing_speeds: npt.ArrayLike | None = None,
    bearing_K: npt.ArrayLike | None = None,
    bearing_C: npt.ArrayLike | None = None,
    transient: int = 0,
    ds: float | None = None,
    ds_max: float = 0.2,
    max_points: int = 2000,
    bracket_width: float | None = None,
    samples: int = 256,
    rtol: float = 1e-9,
    atol: float | None = None,
    method: str | None = None,
    layout: str = "ross6",
) -> RubMap: ...
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
    modes: int | str = 0,
    mode_tolerance: float = 1e-3,
    probe_nodes: Sequence[int] = [],
    form: str | None = None,
    friction: float = 0.0,
    shaft_radius: float | None = None,
    rtol: float = 1e-8,
    atol: float | None = None,
    method: str | None = None,
    layout: str = "ross6",
) -> FeRun: ...
class Motor:
    @staticmethod
    def linear(stall_torque: float, no_load_speed: float) -> Motor: ...
    @staticmethod
    def table(speeds: npt.ArrayLike, torques: npt.ArrayLike) -> Motor: ...
    def torque(self, speed: float) -> float: ...
    @property
    def no_load_speed(self) -> float: ...

def fe_run_up(
    M: npt.ArrayLike,
    K: npt.ArrayLike,
    C: npt.ArrayLike,
    G: npt.ArrayLike,
    times: npt.ArrayLike | None = None,
    speeds: npt.ArrayLike | None = None,
    *,
    ring_node: int,
    gap: float,
    ring_stiffness: float,
    ring_damping: float,
    unbalance: Sequence[tuple[int, float, float]],
    motor: Motor | None = None,
    inertia: float | None = None,
    speed0: float | None = None,
    ring: bool = True,
    t_end: float | None = None,
    dt: float | None = None,
    preload: tuple[float, float] = (0.0, 0.0),
    ring_offset: tuple[float, float] = (0.0, 0.0),
    modes: int | str = 0,
    mode_tolerance: float = 1e-3,
    probe_nodes: Sequence[int] = [],
    bearing_speeds: npt.ArrayLike | None = None,
    bearing_K: npt.ArrayLike | None = None,
    bearing_C: npt.ArrayLike | None = None,
    friction: float = 0.0,
    shaft_radius: float | None = None,
    rtol: float = 1e-8,
    atol: float | None = None,
    method: str | None = None,
    layout: str = "ross6",
) -> FeRun: ...
def full_spectrum(
    t: npt.ArrayLike, x: npt.ArrayLike, y: npt.ArrayLike, *, window: str = "hann"
) -> WhirlSpectrum: ...
def amplitude_spectrum(
    t: npt.ArrayLike, x: npt.ArrayLike, *, window: str = "hann"
) -> tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
def order_track(
    t: npt.ArrayLike,
    phase: npt.ArrayLike,
    x: npt.ArrayLike,
    y: npt.ArrayLike,
    *,
    orders: Sequence[float] = [0.5, 1.0, 1.5, 2.0, 3.0],
    per_revolution: int = 32,
    revolutions_per_window: int = 8,
    hop_revolutions: int = 2,
    window: str = "hann",
    max_interpolation_error: float = 0.01,
) -> OrderTrack: ...
def fewest_modes(
    M: npt.ArrayLike,
    K: npt.ArrayLike,
    C: npt.ArrayLike,
    G: npt.ArrayLike,
    speeds: Sequence[float],
    *,
    ring_node: int,
    unbalance: Sequence[tuple[int, float, float]],
    tolerance: float = 1e-3,
    layout: str = "ross6",
) -> tuple[int, float]: ...
def response_error(
    M: npt.ArrayLike,
    K: npt.ArrayLike,
    C: npt.ArrayLike,
    G: npt.ArrayLike,
    speeds: Sequence[float],
    *,
    ring_node: int,
    unbalance: Sequence[tuple[int, float, float]],
    modes: int,
    layout: str = "ross6",
) -> tuple[float, float]: ...
