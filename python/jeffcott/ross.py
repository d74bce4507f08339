"""ROSS rotors as they are: a ``ross.Rotor`` on the snubber ring without a file.

``from_rotor(rotor, speed)`` reads the rotor's matrices at one speed (the bearings' and the
frequency-dependent elements' coefficients at that speed) and its shaft's outer radius at each
node; the ``FeRotor`` it returns runs ``fe_transient`` and ``fe_run_up`` on them. ROSS is not
imported here: any object with ROSS's ``M``, ``K``, ``C``, ``G`` and ``shaft_elements`` works.
"""

from dataclasses import dataclass

import numpy as np

from ._jeffcott import FeRun, fe_run_up, fe_transient


@dataclass(frozen=True)
class FeRotor:
    """A finite-element rotor's matrices in ROSS's layout (6 DOFs a node: x, y, z, alpha,
    beta, theta), SI units."""

    #: Mass matrix (kg, kg m^2), shape (6 n, 6 n).
    M: np.ndarray
    #: Stiffness (N/m, N m/rad), the bearings' at ``speed``.
    K: np.ndarray
    #: Damping (N s/m, ...), the bearings' at ``speed``; without the gyroscopic part.
    C: np.ndarray
    #: Gyroscopic matrix per unit speed (kg m^2).
    G: np.ndarray
    #: The speed (rad/s) at which ``K`` and ``C`` were evaluated.
    speed: float
    #: The shaft's outer radius at each node (m), shape (n,): the largest of the shaft
    #: elements that end there; NaN at a node no shaft element ends at.
    shaft_radius: np.ndarray

    def transient(self, **kw) -> FeRun:
        """``fe_transient`` of this rotor at ``speed``; ``kw`` as ``fe_transient``'s."""
        return fe_transient(self.M, self.K, self.C, self.G, self.speed, **kw)

    def run_up(self, times, speeds, **kw) -> FeRun:
        """``fe_run_up`` of this rotor through the speed table (``times``, ``speeds``), with
        ``K`` and ``C`` as evaluated at ``speed`` for every speed; ``kw`` as ``fe_run_up``'s."""
        return fe_run_up(self.M, self.K, self.C, self.G, times, speeds, **kw)


def shaft_radius(rotor) -> np.ndarray:
    """The outer radius (m) of ``rotor``'s shaft at each node: the largest outer diameter, over
    the shaft elements that end at the node (``odl`` at their left node ``n_l``, ``odr`` at
    their right node ``n_r``), halved; NaN where none ends."""
    nodes = len(rotor.nodes)
    radius = np.full(nodes, np.nan)
    for e in rotor.shaft_elements:
        for node, diameter in ((e.n_l, e.odl), (e.n_r, e.odr)):
            radius[node] = np.fmax(radius[node], diameter / 2)
    return radius


def from_rotor(rotor, speed: float) -> FeRotor:
    """The matrices of the ``ross.Rotor`` ``rotor`` at ``speed`` (rad/s) as ROSS gives them
    (``rotor.M(speed, speed)``, ``rotor.K(speed, speed)``, ``rotor.C(speed, speed)``,
    ``rotor.G()``, float64) and its shaft's outer radius at each node."""
    speed = float(speed)
    matrices = (rotor.M(speed, speed), rotor.K(speed, speed), rotor.C(speed, speed), rotor.G())
    M, K, C, G = (np.array(a, dtype=np.float64) for a in matrices)
    return FeRotor(M, K, C, G, speed, shaft_radius(rotor))
