"""ROSS rotors as they are: a ``ross.Rotor`` on the snubber ring without a file.

``from_rotor(rotor, speed)`` reads the rotor's matrices at one speed (the bearings' and the
frequency-dependent elements' coefficients at that speed) and its shaft's outer radius at each
node; the ``FeRotor`` it returns runs ``fe_transient`` and ``fe_run_up`` on them, the run-up
with the bearings' ``K`` and ``C`` read again on a grid of the run's speeds. ROSS is not
imported here: any object with ROSS's ``M``, ``K``, ``C``, ``G`` and ``shaft_elements`` works.
"""

from dataclasses import dataclass, field

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
    #: The ``ross.Rotor`` the matrices came from (``None``: given as matrices only), read
    #: again by ``run_up`` for the bearings at other speeds.
    rotor: object = field(default=None, repr=False, compare=False)

    def transient(self, **kw) -> FeRun:
        """``fe_transient`` of this rotor at ``speed``; ``kw`` as ``fe_transient``'s."""
        return fe_transient(self.M, self.K, self.C, self.G, self.speed, **kw)

    def run_up(self, times=None, speeds=None, *, bearing_points: int = 33, **kw) -> FeRun:
        """``fe_run_up`` of this rotor through the speed table (``times``, ``speeds``), or on
        a drive (``motor``, ``inertia``, ``speed0`` in ``kw``); ``kw`` as ``fe_run_up``'s.

        With the ROSS rotor known (``from_rotor``) and ``bearing_points`` > 1, ``K`` and ``C``
        follow the speed: ``rotor.K(w, w)`` and ``rotor.C(w, w)`` read at ``bearing_points``
        speeds equally spaced over the table's range (a drive's: from ``speed0`` to the
        motor's no-load speed; ``fe_run_up``'s ``bearing_speeds``, ``bearing_K``,
        ``bearing_C``; linear between them, held beyond). Otherwise ``K`` and ``C`` are those
        at ``speed`` for every speed."""
        if self.rotor is not None and bearing_points > 1 and "bearing_speeds" not in kw:
            if speeds is None and kw.get("motor") is not None and kw.get("speed0") is not None:
                w = np.array([kw["speed0"], kw["motor"].no_load_speed], dtype=np.float64)
            else:
                w = np.asarray(speeds, dtype=np.float64)
            grid = np.linspace(w.min(), w.max(), bearing_points)
            if grid[-1] > grid[0]:
                kw["bearing_speeds"] = grid
                kw["bearing_K"] = np.array([self.rotor.K(s, s) for s in grid], dtype=np.float64)
                kw["bearing_C"] = np.array([self.rotor.C(s, s) for s in grid], dtype=np.float64)
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
    return FeRotor(M, K, C, G, speed, shaft_radius(rotor), rotor)
