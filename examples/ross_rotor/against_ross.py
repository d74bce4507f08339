"""Case S1 side by side: ROSS's own rub model against the crate's ross_rotor, on one machine.

ROSS (its `Rubbing` fault: a penalty spring switched inside a fixed-step Newmark, the contact
force lagged one step) and the crate's example (`ross_rotor`: event-located contact) run the
same case, S1 of ../shared/rotors/README.md: ROSS's `rotor_example_with_damping()` at 1200 rpm,
the ring at node 12 (gap 7.95e-5 m, k_s = 1.1e6 N/m), 2e-3 kg m of unbalance at node 12,
phase -pi/2, from rest, 0 to 0.5 s. Both are compared with the shared reference transient
(S1_reference.csv, an independent implementation at rtol 1e-12) at its 1001 sample times, and
timed (wall clock, ROSS's `run` call; the crate's whole process, build excluded).

Needs ROSS (`pip install ross-rotordynamics`, Python 3.13) and cargo. Run from the repository:

    python examples/ross_rotor/against_ross.py [--dt 1e-4] [--modes 0] [--rtol 1e-8] [--shared ../shared]

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


def run_ross(t_ref, dt):
    import ross
    from ross import Rubbing

    rotor = ross.rotor_example_with_damping()
    rub = Rubbing(rotor, n=NODE, distance=GAP, contact_stiffness=1.1e6,
                  contact_damping=0.0, friction_coeff=0.0)
    t = np.arange(0.0, 0.5 + dt / 2, dt)
    clock = time.perf_counter()
    res = rub.run(node=[NODE], unb_magnitude=[2e-3], unb_phase=[-np.pi / 2], speed=SPEED, t=t)
    seconds = time.perf_counter() - clock
    y = np.asarray(res.yout)
    if y.shape[0] != len(t):
        y = y.T
    xy = np.column_stack([np.interp(t_ref, t, y[:, 6 * NODE + d]) for d in (0, 1)])
    return xy, seconds


def run_crate(shared, modes, rtol, method):
    mat = f"{shared}/rotors/rotor_example_with_damping_1200rpm.mat"
    args = ["--mat", mat, "--speed-rpm", "1200", "--ring-node", str(NODE), "--gap", str(GAP),
            "--ring-stiffness", "1.1e6", "--ring-damping", "0.01",
            "--unbalance", f"{NODE}:2e-3:{-np.pi / 2!r}", "--t-end", "0.5", "--samples", "1000",
            "--modes", str(modes), "--rtol", str(rtol)] + (["--method", method] if method else [])
    subprocess.run(["cargo", "build", "--release", "--example", "ross_rotor"], check=True)
    clock = time.perf_counter()
    out = subprocess.run(["target/release/examples/ross_rotor", *args], check=True,
                         capture_output=True, text=True)
    seconds = time.perf_counter() - clock
    rows = list(csv.reader(io.StringIO(out.stdout)))
    xy = np.array([[float(r[1]), float(r[2])] for r in rows[1:]])
    return xy, seconds, out.stderr.strip()


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dt", type=float, default=1e-4, help="ROSS's Newmark step (s)")
    ap.add_argument("--modes", type=int, default=0, help="crate: modes kept (0: full model)")
    ap.add_argument("--rtol", type=float, default=1e-8, help="crate: relative tolerance")
    ap.add_argument("--method", default=None,
                    help="crate: integration method (default: the example's, radau5 for the full model, dop853 for a reduced one)")
    ap.add_argument("--shared", default="../shared", help="the shared data folder")
    a = ap.parse_args()
    t_ref, xy_ref = reference(a.shared)
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
