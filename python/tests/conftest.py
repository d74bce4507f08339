"""Where the tests' truths are: the repository's tests/data (copies of the shared reference
set, as the Rust tests read them), else the shared set beside the clone (../shared)."""

from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


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
