"""Jeffcott rotor on a preloaded snubber ring, and finite-element rotors on the ring.

The Rust crate ``jeffcott`` from Python: numpy arrays in, numpy arrays out, the loops
compiled. The paper's model works in non-dimensional units (time in 1/omega_n, lengths in
gaps); the finite-element rotor in SI units. Long runs release the GIL and stop on Ctrl-C
(``KeyboardInterrupt``). Bad input raises ``ValueError``; a failed run raises
``SimulationError`` (a ``RuntimeError``) whose ``partial`` attribute holds what was computed.
"""

from ._jeffcott import (
    BasinAttractor,
    Basins,
    Branch,
    DenseRun,
    Diagram,
    FeTransient,
    Lyapunov,
    Orbit,
    Params,
    RunUp,
    Section,
    SimulationError,
    SpecialPoint,
    StrobeRun,
    __version__,
    basins,
    bifurcation,
    continue_orbit,
    fe_transient,
    lyapunov_exponents,
    periodic_orbit,
    poincare,
    presets,
    regime,
    ring_position,
    run_up,
    simulate,
    simulate_dense,
)

__all__ = [
    "BasinAttractor",
    "Basins",
    "Branch",
    "DenseRun",
    "Diagram",
    "FeTransient",
    "Lyapunov",
    "Orbit",
    "Params",
    "RunUp",
    "Section",
    "SimulationError",
    "SpecialPoint",
    "StrobeRun",
    "__version__",
    "basins",
    "bifurcation",
    "continue_orbit",
    "fe_transient",
    "lyapunov_exponents",
    "periodic_orbit",
    "poincare",
    "presets",
    "regime",
    "ring_position",
    "run_up",
    "simulate",
    "simulate_dense",
]
