"""The paper's Fig. 8b: the bifurcation diagram of the preloaded ring (D = 0.1) over the
frequency ratio eta in [2, 5], each value from rest, 300 periods discarded and 150 recorded
(x of the stroboscopic points, in gaps). ``python paper_fig8.py [out.png] [values]``
(default fig8b.png, 601 values; the crate's threads on every core)."""

import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import jeffcott

out = sys.argv[1] if len(sys.argv) > 1 else "fig8b.png"
values = np.linspace(2.0, 5.0, int(sys.argv[2]) if len(sys.argv) > 2 else 601)
d = jeffcott.bifurcation(jeffcott.Params.preset("fig8b"), values, transient=300, record=150)
print(f"{len(values)} values, periods found: {sorted(set(d.periods.tolist()))}")

fig, ax = plt.subplots(figsize=(8, 5))
eta = np.repeat(d.values, d.points.shape[1])
ax.plot(eta, d.points[:, :, 0].ravel(), ",k")
ax.set(xlabel="frequency ratio η", ylabel="x at the stroboscopic times (gaps)",
       title="Fig. 8b: preload D = 0.1, from rest, 300 periods discarded, 150 recorded")
fig.tight_layout()
fig.savefig(out, dpi=150)
