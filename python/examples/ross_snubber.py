"""A ROSS rotor on the snubber ring: ``ross.rotor_example()`` (42 DOF) at 1500 rpm, out of
balance at its first disk, the ring at the second disk (node 4), the transient from rest.
Draws the orbit at the ring node with the gap circle, and x(t): ``python ross_snubber.py
[out.png]``. Needs ``pip install ross-rotordynamics matplotlib`` beside ``pip install ./python``."""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import ross

import jeffcott

rotor = ross.rotor_example()
speed = 1500 * np.pi / 30  # rad/s, between the first and second criticals
M, K, C, G = rotor.M(speed, speed), rotor.K(speed, speed), rotor.C(speed, speed), rotor.G()
gap = 1.5e-6  # m: the free steady orbit at node 4 has a radius of about 2.3e-6 m
run = jeffcott.fe_transient(
    M, K, C, G, speed, ring_node=4, gap=gap, ring_stiffness=1e7, ring_damping=10.0,
    unbalance=[(2, 1e-4, 0.0)], t_end=0.2, samples=4000,
)
print(f"{run.onsets.size} contact onsets, {run.losses.size} losses, "
      f"max |r| = {np.hypot(run.x, run.y).max() / gap:.3f} gap, {run.stats['steps']} steps")

fig, (orbit, time) = plt.subplots(1, 2, figsize=(10, 4.5))
circle = np.linspace(0, 2 * np.pi, 200)
orbit.plot(run.x * 1e6, run.y * 1e6, lw=0.6)
orbit.plot(gap * 1e6 * np.cos(circle), gap * 1e6 * np.sin(circle), "k--", lw=1, label="gap")
orbit.set(xlabel="x (µm)", ylabel="y (µm)", aspect="equal", title="orbit at the ring node")
orbit.legend()
time.plot(run.t, run.x * 1e6, lw=0.6)
time.set(xlabel="t (s)", ylabel="x (µm)", title="x at the ring node")
fig.tight_layout()
fig.savefig(sys.argv[1] if len(sys.argv) > 1 else "ross_snubber.png", dpi=120)
