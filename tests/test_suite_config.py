"""The test command's configuration: parallel by default, and serial runs still work."""

from __future__ import annotations

import os
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

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


def test_the_long_modules_are_there() -> None:
    """Each module the workers run first exists (a renamed one would quietly go back to its
    place in the collection), once; the two that share the session's reduced paper run stay
    side by side, so that one worker starts both."""
    from conftest import LONG_MODULES

    assert [m for m in LONG_MODULES if not (ROOT / m).is_file()] == []
    assert len(set(LONG_MODULES)) == len(LONG_MODULES)
    paper = LONG_MODULES.index("tests/study/test_paper.py")
    assert LONG_MODULES[paper + 1] == "tests/report/test_browser.py"


def test_the_workers_run_the_long_modules_first() -> None:
    """Under pytest-xdist (a worker's config has ``workerinput``) the long modules' tests come
    first, in :data:`LONG_MODULES`' order, each module's tests and the rest in the collection's
    order; a serial run keeps the collection as it is."""
    from types import SimpleNamespace

    from conftest import pytest_collection_modifyitems

    collected = [
        "tests/_kernels/test_driver.py::test_a",
        "tests/report/test_browser.py::test_b",
        "tests/study/test_paper.py::test_c",
        "tests/study/test_paper.py::test_d",
        "tests/test_docs_examples.py::test_e[1]",
        "tests/test_readme.py::test_f",
        "tests/test_docs_examples.py::test_e[2]",
        "tests/tolerance/test_x.py::test_g",
    ]
    items: list[Any] = [SimpleNamespace(nodeid=n) for n in collected]
    serial = list(items)
    pytest_collection_modifyitems(SimpleNamespace(), serial)  # type: ignore[arg-type]
    assert serial == items
    worker = list(items)
    pytest_collection_modifyitems(SimpleNamespace(workerinput={}), worker)  # type: ignore[arg-type]
    order = [i.nodeid for i in worker]
    assert order == [
        "tests/test_readme.py::test_f",
        "tests/test_docs_examples.py::test_e[1]",
        "tests/test_docs_examples.py::test_e[2]",
        "tests/study/test_paper.py::test_c",
        "tests/study/test_paper.py::test_d",
        "tests/report/test_browser.py::test_b",
        "tests/_kernels/test_driver.py::test_a",
        "tests/tolerance/test_x.py::test_g",
    ]


def test_the_readme_command_leaves_out_the_slow_tier_and_ci_runs_it() -> None:
    """``pytest`` alone deselects the slow tier (the README's command within its time); CI
    runs the README's command and then the slow tier, so every test runs there."""
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    addopts = config["tool"]["pytest"]["ini_options"]["addopts"]
    assert "-m 'not slow'" in addopts
    ci = [line.strip() for line in (ROOT / ".ci" / "run").read_text().splitlines()]
    readme = ci.index('pip install --quiet ".[test]" && pytest')
    assert "pytest -m slow" in ci[readme + 1 :]


def test_the_slow_tier_is_not_empty_and_not_the_suite() -> None:
    """``-m slow`` (a later ``-m`` than addopts') selects the slow tier alone."""
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-n", "0", "-p", "no:cacheprovider", "--collect-only",
         "-q", "-m", "slow", "tests/test_readme.py", "tests/test_suite_config.py"],
        cwd=ROOT, capture_output=True, text=True, check=False, timeout=300,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
    )  # fmt: skip
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    selected = [line for line in done.stdout.splitlines() if "::" in line]
    assert selected and all(line.startswith("tests/test_readme.py") for line in selected)
