"""Where the tests' truths are: the repository's tests/data (copies of the shared reference
set, as the Rust tests read them), else the shared set beside the clone (../shared)."""

import _thread
import signal
import sys
import threading
import time
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]

# `python -m pytest` started inside python/ puts that folder (the package's source, without
# its compiled part) first on sys.path, and `import jeffcott` then failed; the tests are of
# the installed package.
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != REPO / "python"]

# The Ctrl-C tests raise it with `_thread.interrupt_main`, which does nothing where SIGINT is
# ignored, as a shell starts a background job (`nohup ... &`): there, Python installs no
# handler and the interrupted runs went on (a run of 10^8 periods: hours). Python's own
# handler, whatever the tests were started from.
signal.signal(signal.SIGINT, signal.default_int_handler)


def data_dir() -> Path:
    for d in (REPO / "tests" / "data", REPO.parent / "shared" / "reference"):
        if (d / "fig8a_eta2.0.csv").exists():
            return d
    pytest.skip("no reference data (tests/data or ../shared)")


def rotors_dir() -> Path:
    for d in (REPO / "tests" / "data" / "rotors", REPO.parent / "shared" / "rotors"):
        if (d / "S1_reference.json").exists() and (d / "rotor_example_with_damping_1200rpm.npz").exists():
            return d
    pytest.skip("no rotor data (tests/data/rotors or ../shared/rotors)")


def interrupted_after(seconds, call):
    """Raises Ctrl-C (`_thread.interrupt_main`) `seconds` into `call()`: the time until the
    `KeyboardInterrupt` came out of it."""
    timer = threading.Timer(seconds, _thread.interrupt_main)
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            call()
    finally:
        timer.cancel()
    return time.monotonic() - start


def stamps_during(call):
    """Runs `call()` in the main thread while a Python thread leaves time stamps every
    millisecond: the call's duration and the stamps left inside its window (but for a tenth
    at each end). None could be there if the call held the GIL."""
    stamps, stop = [], threading.Event()

    def spin():
        while not stop.is_set():
            stamps.append(time.monotonic())
            time.sleep(0.001)

    t = threading.Thread(target=spin)
    t.start()
    try:
        time.sleep(0.05)
        start = time.monotonic()
        call()
        end = time.monotonic()
    finally:
        stop.set()
        t.join()
    margin = 0.1 * (end - start)
    return end - start, [s for s in stamps if start + margin < s < end - margin]
