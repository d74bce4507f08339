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
    ContactEpisodes,
    DenseRun,
    Diagram,
    FeRun,
    Lyapunov,
    Orbit,
    Params,
    Revolutions,
    RunUp,
    Section,
    SimulationError,
    SpecialPoint,
    StrobeRun,
    __version__,
    basins,
    bifurcation,
    continue_orbit,
    fe_run_up,
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

#: The name of ``fe_transient``'s result before it became ``FeRun`` (kept for old code).
FeTransient = FeRun

__all__ = [
    "BasinAttractor",
    "Basins",
    "Branch",
    "ContactEpisodes",
    "DenseRun",
    "Diagram",
    "FeRun",
    "FeTransient",
    "Lyapunov",
    "Orbit",
    "Params",
    "Revolutions",
    "RunUp",
    "Section",
    "SimulationError",
    "SpecialPoint",
    "StrobeRun",
    "__version__",
    "basins",
    "bifurcation",
    "continue_orbit",
    "fe_run_up",
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
