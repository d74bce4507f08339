"""The bindings' overhead: 1000 forcing periods from rest from Python, against the same run
from Rust (the criterion bench `python_baseline/*` of benches/simulation.rs).

    python python/benches/overhead.py
    cargo bench --bench simulation -- python_baseline

Prints the median and minimum wall time of `jeffcott.simulate(p, 1000)` (default options,
all 1001 states recorded, as in the bench), with the default chunks of 100 periods and in
one chunk. A measurement, not a test: run it on a quiet machine.
"""

import statistics
import time

import jeffcott


def timed(p, repeats, **kw):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        jeffcott.simulate(p, 1000, **kw)
        times.append(time.perf_counter() - start)
    return statistics.median(times), min(times)


for name in ("fig8b", "fig9c"):
    p = jeffcott.Params.preset(name)
    jeffcott.simulate(p, 1000)  # warm-up
    for label, kw in (("chunks of 100", {}), ("one chunk", {"chunk": 1000})):
        med, best = timed(p, 30, **kw)
        print(f"{name} 1000 periods, {label}: median {med * 1e3:.3f} ms, min {best * 1e3:.3f} ms")
