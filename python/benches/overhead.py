"""The bindings' overhead (issue 22: a 1000-period simulation from Python costs at most 5 %
more than the same run from Rust), measured with the two interleaved.

    python python/benches/overhead.py [--repeats 100] [--periods 1000]

It starts the Rust side, `cargo bench --bench python_overhead` (benches/python_overhead.rs:
the same run, `JeffcottModel::strobe_range` from rest with default options, timed in Rust),
and talks to it over a pipe: each repetition times, for each scene (Fig. 8b, one contact a
period; Fig. 9c, chaotic), one Rust run and one `jeffcott.simulate(p, periods)`, in an order
that alternates from one repetition to the next.

Two clocks: wall time, and the CPU time of the thread that runs the simulation (Python's
`time.thread_time`, the same `clock_gettime` clock as the Rust side's; the Python call runs
in the calling thread with the GIL released). On a machine shared with other work the wall
time counts the waits for a core; the CPU time counts only the run's own work (cache and
memory contention still show in it). For each clock: the median and the minimum of each
column, and three ratios Python / Rust: of the medians, of the minima, and the median of the
ratios within a repetition (runs under the same load). The integrator steps of each column
show the work is the same (the Python run is one run of the same driver, never restarted). A
measurement, not a test.
"""

import argparse
import statistics
import subprocess
import time
from pathlib import Path

import jeffcott

REPO = Path(__file__).resolve().parents[2]
SCENES = ("fig8b", "fig9c")


class RustTimer:
    """The Rust side: one timed run per request, `WALL CPU STEPS` back."""

    def __init__(self):
        self.proc = subprocess.Popen(
            ["cargo", "bench", "--quiet", "--bench", "python_overhead"],
            cwd=REPO,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )

    def run(self, scene, periods):
        self.proc.stdin.write(f"{scene} {periods}\n")
        self.proc.stdin.flush()
        reply = self.proc.stdout.readline().split()
        if len(reply) != 3 or reply[0] == "error":
            raise RuntimeError(f"Rust side: {' '.join(reply) or 'no reply'}")
        return float(reply[0]), float(reply[1]), int(reply[2])

    def close(self):
        self.proc.stdin.close()
        self.proc.wait()


def python_run(params, periods):
    wall, cpu = time.perf_counter(), time.thread_time()
    run = jeffcott.simulate(params, periods)
    return time.perf_counter() - wall, time.thread_time() - cpu, run.stats["steps"]


def report(label, times, names, steps):
    print(f"{label} (ms); ratios Python / Rust: of the medians, of the minima, paired median")
    for s in SCENES:
        base = times[(s, names[0])]
        base_med, base_min = statistics.median(base), min(base)
        for c in names:
            t = times[(s, c)]
            med, best = statistics.median(t), min(t)
            paired = statistics.median(x / y for x, y in zip(t, base))
            print(f"  {s:6} {c:22} median {med * 1e3:8.3f}  min {best * 1e3:8.3f}  "
                  f"ratios {med / base_med:6.4f} {best / base_min:6.4f} {paired:6.4f}  "
                  f"steps {steps[(s, c)]}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=100)
    ap.add_argument("--periods", type=int, default=1000)
    args = ap.parse_args()
    rust = RustTimer()
    columns = {
        "rust": lambda s, p: rust.run(s, args.periods),
        "python": lambda s, p: python_run(p, args.periods),
    }
    names = list(columns)
    wall = {(s, c): [] for s in SCENES for c in names}
    cpu = {(s, c): [] for s in SCENES for c in names}
    steps = {}
    params = {s: jeffcott.Params.preset(s) for s in SCENES}
    for s in SCENES:  # warm-up: code and caches, not timed
        for c in names:
            columns[c](s, params[s])
    for r in range(args.repeats):
        for s in SCENES:
            order = names[r % len(names):] + names[: r % len(names)]
            for c in order:
                w, t, n = columns[c](s, params[s])
                wall[(s, c)].append(w)
                cpu[(s, c)].append(t)
                steps[(s, c)] = n
    rust.close()
    print(f"{args.periods} forcing periods from rest, default options, {args.repeats} "
          f"interleaved repetitions")
    report("wall time", wall, names, steps)
    report("thread CPU time", cpu, names, steps)


if __name__ == "__main__":
    main()
