"""The test command's configuration: parallel by default, and serial runs still work."""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_pytest_alone_runs_on_every_core() -> None:
    """The README's ``pytest`` takes pyproject's addopts: xdist, one worker per core."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    addopts = config["tool"]["pytest"]["ini_options"]["addopts"].split()
    assert addopts[addopts.index("-n") + 1] == "auto"
    assert addopts[addopts.index("--dist") + 1] == "worksteal"


@pytest.mark.parametrize("serial", [["-n", "0"], ["-p", "no:xdist"]], ids=["n0", "no-xdist"])
def test_serial_runs_still_work(serial: list[str]) -> None:
    """``-n 0``, and xdist blocked (tests/conftest.py then accepts ``-n auto --dist``). One
    quick test is run so: what is checked is the command line, not the tests (the 50 of
    tests/test_units.py took ~4 s more each time)."""
    done = subprocess.run(
        [sys.executable, "-m", "pytest", *serial, "-p", "no:cacheprovider", "-q",
         "tests/test_suite_config.py::test_pytest_alone_runs_on_every_core"],
        cwd=ROOT, capture_output=True, text=True, check=False, timeout=300,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
    )  # fmt: skip
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert " passed" in done.stdout and "created: " not in done.stdout  # no xdist workers
