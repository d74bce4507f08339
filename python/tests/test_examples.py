"""The examples run (each skipped when what it imports is missing: matplotlib, ross)."""

import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def run(script, *args):
    out = subprocess.run([sys.executable, str(EXAMPLES / script), *map(str, args)],
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_ross_example_runs(tmp_path):
    pytest.importorskip("ross")
    pytest.importorskip("matplotlib")
    stdout = run("ross_snubber.py", tmp_path / "ross_snubber.png")
    assert "contact onsets" in stdout
    assert (tmp_path / "ross_snubber.png").stat().st_size > 10_000


def test_fig8_example_runs(tmp_path):
    pytest.importorskip("matplotlib")
    stdout = run("paper_fig8.py", tmp_path / "fig8b.png", 7)
    assert stdout.startswith("7 values")
    assert (tmp_path / "fig8b.png").stat().st_size > 10_000


def test_rub_run_up_example_runs(tmp_path):
    pytest.importorskip("ross", reason="ROSS is not installed (it needs Python 3.13)")
    pytest.importorskip("matplotlib")
    stdout = run("rub_run_up.py", tmp_path / "rub_run_up.png")
    ring, free = stdout.splitlines()[-2:]
    assert ring.startswith("on the ring: peak") and free.startswith("without it: peak")
    assert (tmp_path / "rub_run_up.png").stat().st_size > 10_000
