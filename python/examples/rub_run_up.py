"""A ROSS rotor through its first critical speed on a snubber ring.

The rotor is built here with ROSS (a 1.5 m steel shaft, two disks, damped bearings; first
critical 96 rad/s), put on a ring at midspan (gap 40 µm, 2e6 N/m) and run up from 60 to
200 rad/s in 6 s, with and without the ring (the fewest Craig-Bampton modes within 1e-3 of
the full model's unbalance response over the run's speeds). It prints each run's peak and
writes a figure: the largest radius per revolution against the speed, and the
waterfall of the run on the ring (the forward whirl's orders).

    python python/examples/rub_run_up.py [out.png]
"""

import sys
import time

import numpy as np
import ross

import jeffcott
from jeffcott.ross import from_rotor

steel = ross.Material(name="Steel", rho=7810, E=211e9, G_s=81.2e9)
shaft = [ross.ShaftElement(L=0.25, idl=0.0, odl=0.05, material=steel) for _ in range(6)]
disks = [ross.DiskElement.from_geometry(n=n, material=steel, width=0.07, i_d=0.05, o_d=0.28)
         for n in (2, 4)]
bearings = [ross.BearingElement(n=n, kxx=1e6, cxx=300.0) for n in (0, 6)]
rotor = from_rotor(ross.Rotor(shaft, disks, bearings), speed=0.0)

gap = 4e-5
ring = dict(ring_node=3, gap=gap, ring_stiffness=2e6, ring_damping=50.0,
            unbalance=[(2, 2e-4, 0.0)], modes="auto")
runs = {}
for on_ring in (True, False):
    start = time.perf_counter()
    runs[on_ring] = run = rotor.run_up([0.0, 6.0], [60.0, 200.0], ring=on_ring, **ring)
    rev = run.revolutions
    peak = np.argmax(rev.peak_radius)
    print(f"{'on the ring' if on_ring else 'without it'}: peak {rev.peak_radius[peak] * 1e6:.1f} µm "
          f"at {rev.speed[peak]:.1f} rad/s, {len(run.onsets)} contact onsets, {run.modes} modes "
          f"({run.mode_error:.1e}), {time.perf_counter() - start:.2f} s")
run = runs[True]
track = jeffcott.order_track(run.t, run.phase, run.x, run.y, orders=[1.0, 2.0],
                             per_revolution=64)

# The figure (matplotlib, if installed).
try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit(0)
fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.5))
for on_ring, label in ((False, "without the ring"), (True, "on the ring")):
    rev = runs[on_ring].revolutions
    a.plot(rev.speed, rev.peak_radius * 1e6, label=label)
a.axhline(gap * 1e6, color="grey", ls=":", label="gap")
a.set(xlabel="speed (rad/s)", ylabel="largest radius per revolution (µm)",
      title="ROSS rotor through its first critical")
a.legend()
level = np.log10(np.maximum(track.waterfall_forward * 1e6, 1e-3))
image = b.pcolormesh(track.waterfall_orders, track.speed, level, shading="nearest")
b.set(xlabel="order (forward whirl)", ylabel="speed (rad/s)", xlim=(0, 4),
      title="waterfall on the ring: log10 radius (µm)")
fig.colorbar(image, ax=b)
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "rub_run_up.png", dpi=120)
