"""The package as a Python user meets it: its version, and help() on every function."""

import inspect
import re

import jeffcott
from conftest import REPO


def test_version_is_the_crates():
    # The truth: the crate's own manifest (the bindings are released with it).
    manifest = (REPO / "Cargo.toml").read_text()
    version = re.search(r'^\[package\][^\[]*?^version = "([^"]+)"', manifest, re.M | re.S)
    assert version, "no [package] version in Cargo.toml"
    assert jeffcott.__version__ == version.group(1)


def test_every_signature_shows_its_defaults():
    # help() and inspect show each default as Python would write it, never `...` (Ellipsis:
    # what pyo3 shows for a default it cannot print, e.g. a tuple).
    shown = {}
    for name in jeffcott.__all__:
        f = getattr(jeffcott, name)
        if inspect.isbuiltin(f) or inspect.isfunction(f):
            shown[name] = str(inspect.signature(f))
    assert {"fe_transient", "fe_run_up", "lyapunov_exponents"} <= shown.keys()
    assert not [n for n, s in shown.items() if "Ellipsis" in s or "..." in s], shown
    assert "preload=(0.0, 0.0)" in shown["fe_transient"]
    assert "ring_offset=(0.0, 0.0)" in shown["fe_run_up"]
    assert "separation=1e-08" in shown["lyapunov_exponents"]


def test_python_m_pytest_inside_the_package_folder_tests_the_installed_package(tmp_path):
    # `python -m pytest` started in python/ puts the source folder (no compiled part) first on
    # sys.path; conftest.py takes it off, so the tests import the installed package. A test
    # file of this one check, run so from python/ in a fresh interpreter.
    import subprocess
    import sys

    check = REPO / "python" / "tests" / f"_tmp_{tmp_path.name}_test_installed.py"
    check.write_text("import jeffcott\n\ndef test_compiled():\n    assert jeffcott.fe_run_up\n")
    try:
        run = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                              str(check.relative_to(REPO / "python"))],
                             cwd=REPO / "python", capture_output=True, text=True, timeout=120)
    finally:
        check.unlink()
    assert run.returncode == 0, run.stdout + run.stderr
