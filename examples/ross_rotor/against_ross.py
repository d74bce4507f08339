"""Case S1 side by side: ROSS's own rub model against the crate's ross_rotor, on one machine.

ROSS (its `Rubbing` fault: a penalty spring switched inside a fixed-step Newmark, the contact
force lagged one step) and the crate's example (`ross_rotor`: event-located contact) run the
same case, S1 of ../shared/rotors/README.md: ROSS's `rotor_example_with_damping()` at 1200 rpm,
the ring at node 12 (gap 7.95e-5 m, k_s = 1.1e6 N/m), 2e-3 kg m of unbalance at node 12,
phase -pi/2, from rest, 0 to 0.5 s. Both are compared with the shared reference transient
(S1_reference.csv, an independent implementation at rtol 1e-12) at its 1001 sample times, and
timed (wall clock, ROSS's `run` call; the crate's whole process, build excluded).

With `--friction MU` both run S1 with Coulomb friction at the ring: ROSS's `friction_coeff` (its
per-axis rule: the friction force's components are MU times the absolute values of the contact
force's, with signs fixed per axis by the sign of a velocity component) and the crate's
`--friction MU --shaft-radius A` with A the shaft's outer radius at the node in ROSS's model
(its `odl / 2`, the radius ROSS's rule uses). There is no shared reference with friction: the
crate's run is compared with itself at a tolerance 100 times tighter (its convergence), ROSS's
with the crate's, and with `--ross-refine` ROSS at dt / 10 too (ROSS's own convergence).

Needs ROSS (`pip install ross-rotordynamics`, Python 3.13) and cargo. Run from the repository:

    python examples/ross_rotor/against_ross.py [--dt 1e-4] [--modes 0] [--rtol 1e-8] [--shared ../shared]
    python examples/ross_rotor/against_ross.py --friction 0.3 [--ross-refine]

Not run by CI (ROSS takes minutes to install).
"""

import argparse
import csv
import io
import subprocess
import time

import numpy as np

GAP = 7.95e-5
SPEED = 125.66370614359172
NODE = 12


def reference(shared):
    data = np.loadtxt(f"{shared}/rotors/S1_reference.csv", delimiter=",", skiprows=1)
    return data[:, 0], data[:, 1:3]


def episodes(xy):
    """Contact episodes seen at the samples (|r| beyond the gap)."""
    inside = np.hypot(xy[:, 0], xy[:, 1]) > GAP
    return int(np.sum(inside[1:] & ~inside[:-1]) + inside[0])


def shaft_radius():
    """The shaft's outer radius at the ring's element in ROSS's model (m)."""
    import ross

    rotor = ross.rotor_example_with_damping()
    return next(e.odl for e in rotor.shaft_elements if e.n == NODE) / 2


def run_ross(t_ref, dt, friction=0.0):
    import ross
    from ross import Rubbing

    rotor = ross.rotor_example_with_damping()
    rub = Rubbing(rotor, n=NODE, distance=GAP, contact_stiffness=1.1e6,
                  contact_damping=0.0, friction_coeff=friction)
    t = np.arange(0.0, 0.5 + dt / 2, dt)
    clock = time.perf_counter()
    res = rub.run(node=[NODE], unb_magnitude=[2e-3], unb_phase=[-np.pi / 2], speed=SPEED, t=t)
    seconds = time.perf_counter() - clock
    y = np.asarray(res.yout)
    if y.shape[0] != len(t):
        y = y.T
    xy = np.column_stack([np.interp(t_ref, t, y[:, 6 * NODE + d]) for d in (0, 1)])
    return xy, seconds


def run_crate(shared, modes, rtol, method, friction=None):
    """The crate's run; `friction` = (MU, shaft radius in m) or None."""
    mat = f"{shared}/rotors/rotor_example_with_damping_1200rpm.mat"
    args = ["--mat", mat, "--speed-rpm", "1200", "--ring-node", str(NODE), "--gap", str(GAP),
            "--ring-stiffness", "1.1e6", "--ring-damping", "0.01",
            "--unbalance", f"{NODE}:2e-3:{-np.pi / 2!r}", "--t-end", "0.5", "--samples", "1000",
            "--modes", str(modes), "--rtol", str(rtol)] + (["--method", method] if method else [])
    if friction:
        args += ["--friction", str(friction[0]), "--shaft-radius", repr(friction[1])]
    subprocess.run(["cargo", "build", "--release", "--example", "ross_rotor"], check=True)
    clock = time.perf_counter()
    out = subprocess.run(["target/release/examples/ross_rotor", *args], check=True,
                         capture_output=True, text=True)
    seconds = time.perf_counter() - clock
    rows = list(csv.reader(io.StringIO(out.stdout)))
    xy = np.array([[float(r[1]), float(r[2])] for r in rows[1:]])
    return xy, seconds, out.stderr.strip()


def with_friction(a, t_ref):
    """S1 with friction: the crate against itself at a tighter tolerance, ROSS against the crate."""
    friction = (a.friction, shaft_radius())
    crate_xy, crate_s, summary = run_crate(a.shared, a.modes, a.rtol, a.method, friction)
    tight_xy, tight_s, tight_summary = run_crate(a.shared, a.modes, a.rtol * 1e-2, a.method, friction)
    runs = [(f"crate modes={a.modes} rtol={a.rtol:g}", crate_xy, crate_s),
            (f"crate rtol={a.rtol * 1e-2:g}", tight_xy, tight_s)]
    for dt in [a.dt] + ([a.dt / 10] if a.ross_refine else []):
        xy, seconds = run_ross(t_ref, dt, a.friction)
        runs.append((f"ROSS Newmark dt={dt:g}", xy, seconds))
    print(f"S1 with friction {a.friction} (shaft radius {friction[1]:g} m, ROSS's odl/2 at node "
          f"{NODE}); the largest distance over the 1001 samples from the crate's tighter run:")
    print(f"{'':28}{'distance (m)':>14}{'/ gap':>10}{'episodes':>10}{'peak |r|/gap':>14}{'seconds':>10}")
    for name, xy, seconds in runs:
        d = np.max(np.hypot(*(xy - tight_xy).T))
        peak = np.max(np.hypot(*xy.T)) / GAP
        print(f"{name:28}{d:14.3e}{d / GAP:10.2e}{episodes(xy):10d}{peak:14.4f}{seconds:10.3f}")
    print(f"crate's summary: {summary}")
    print(f"crate's summary (tighter): {tight_summary}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dt", type=float, default=1e-4, help="ROSS's Newmark step (s)")
    ap.add_argument("--modes", type=int, default=0, help="crate: modes kept (0: full model)")
    ap.add_argument("--rtol", type=float, default=1e-8, help="crate: relative tolerance")
    ap.add_argument("--method", default=None,
                    help="crate: integration method (default: the example's, etd4 in modal form for the full model, dop853 for a reduced one)")
    ap.add_argument("--shared", default="../shared", help="the shared data folder")
    ap.add_argument("--friction", type=float, default=0.0,
                    help="Coulomb friction at the ring, both codes (0: frictionless, against the reference)")
    ap.add_argument("--ross-refine", action="store_true",
                    help="with --friction: ROSS at dt / 10 too")
    a = ap.parse_args()
    t_ref, xy_ref = reference(a.shared)
    if a.friction > 0:
        with_friction(a, t_ref)
        return
    crate_xy, crate_s, summary = run_crate(a.shared, a.modes, a.rtol, a.method)
    ross_xy, ross_s = run_ross(t_ref, a.dt)
    print("S1 (reference: 7 contact episodes), errors max over the 1001 samples, episodes seen at them:")
    print(f"{'':28}{'error (m)':>12}{'/ gap':>10}{'episodes':>10}{'seconds':>10}")
    for name, xy, s in [(f"ROSS Newmark dt={a.dt:g}", ross_xy, ross_s),
                        (f"crate modes={a.modes} rtol={a.rtol:g}", crate_xy, crate_s)]:
        err = np.max(np.hypot(*(xy - xy_ref).T))
        print(f"{name:28}{err:12.3e}{err / GAP:10.2e}{episodes(xy):10d}{s:10.3f}")
    print(f"crate's summary: {summary}")
    print(f"time ratio ROSS / crate: {ross_s / crate_s:.1f}")


if __name__ == "__main__":
    main()
