"""Shared fixtures: the paper's mechanism, the reduced paper run, and small helpers."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any, TypeVar

import pytest

from jointplay.io.config import load_preset
from jointplay.model.mechanism import Mechanism

T = TypeVar("T")


@pytest.fixture(scope="session")
def paper_fourbar() -> Mechanism:
    return load_preset("paper-fourbar")


@pytest.fixture(scope="session")
def slider_crank() -> Mechanism:
    return load_preset("flores-slider-crank")


@dataclass(frozen=True)
class ReducedPaperRun:
    """One ``jointplay paper`` run on the reduced setting (:data:`REDUCED_PAPER`).

    Attributes:
        out: Its output folder (``results.json``, ``report.html``); read it, never write.
        progress: Each ``(label, done, total)`` the study reported to the command's progress.
        text_overlaps: Every figure the report saved, by file name (stem), with the pairs of
            its texts that overlap.
    """

    out: Path
    progress: tuple[tuple[str, int, int], ...]
    text_overlaps: dict[str, list[Any]]


#: The reduced paper study: 0.03 revolutions from rest, no length corners, the paper's ECS
#: values, one steady revolution for Table 7 (the experiment), one process.
REDUCED_PAPER = [
    "paper", "--revolutions", "0.03", "--no-corners", "--ecs-source", "paper",
    "--experiment-revolutions", "1", "--workers", "1",
]  # fmt: skip


@pytest.fixture(scope="session")
def reduced_paper(tmp_path_factory: pytest.TempPathFactory) -> ReducedPaperRun:
    """``jointplay paper`` on the reduced setting, run once per session (per xdist worker):
    ``tests/study/test_paper.py`` checks its results and report, ``tests/report/
    test_browser.py`` lays its page out in Chromium (each ran its own reduced study before).
    The study's progress reports and the report's figures are recorded on the way."""
    from _figures import record_text_overlaps
    from jointplay.cli import run
    from jointplay.study import paper

    out = tmp_path_factory.mktemp("paper") / "paper"
    calls: list[tuple[str, int, int]] = []
    original = paper.run_paper_study

    def recording(*args: Any, progress: Any = None, **kwargs: Any) -> Any:
        def both(label: str, done: int, total: int) -> None:
            calls.append((label, done, total))
            if progress is not None:
                progress(label, done, total)

        return original(*args, progress=both, **kwargs)

    with pytest.MonkeyPatch.context() as patch:
        overlaps = record_text_overlaps(patch)
        patch.setattr(paper, "run_paper_study", recording)
        assert run([*REDUCED_PAPER, "--out", str(out)]) == 0
    return ReducedPaperRun(out, tuple(calls), overlaps)


def pytest_configure(config: pytest.Config) -> None:
    """Ctrl-C as at a terminal, however pytest was started. A shell starts a background job
    (``pytest &``, ``nohup``, a script's ``cmd &``) with SIGINT ignored, which every process
    it starts inherits; the command line then rightly leaves SIGINT alone (it watches only
    signals with a handler), and every test that interrupts a run with SIGINT, in this process
    or in a child, failed so (11 of tests/cli alone). A handler here is not inherited across
    ``exec``: the children start with SIGINT's default, as from a terminal."""
    import signal

    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


#: Test modules that pytest-xdist's workers run before the others, in this order: the dearest
#: of the suite (CPU-s of their tests, warm cache, measured in docs/performance.md, "Tests").
#: ``--dist worksteal`` hands each worker a contiguous part of the collection and lets a worker
#: that runs out take the far end of the other's queue; with these long tests at the end of the
#: collection (``tests/test_docs_examples.py`` and ``tests/test_readme.py`` sit between
#: ``study/`` and ``tolerance/``), one of them could start last and leave the other core idle
#: for minutes. Whole modules move, their own order kept, so module fixtures are built once;
#: ``study/test_paper.py`` and ``report/test_browser.py`` share the session's reduced paper run
#: and stay side by side.
LONG_MODULES = (
    "tests/test_readme.py",
    "tests/test_docs_examples.py",
    "tests/cli/test_interrupts.py",
    "tests/cli/test_life_cli.py",
    "tests/dynamics/test_irregular_contract.py",
    "tests/study/test_paper.py",
    "tests/report/test_browser.py",
)


def long_modules_first(items: list[T], module: Callable[[T], str]) -> list[T]:
    """``items`` with those of :data:`LONG_MODULES` first, in its order; the rest, and each
    module's own items, in their order. ``module(item)``: its file, relative to the root."""
    rank = {name: i for i, name in enumerate(LONG_MODULES)}
    return sorted(items, key=lambda item: rank.get(module(item), len(rank)))


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """On pytest-xdist's workers (each collects, all alike): :data:`LONG_MODULES` first. A
    serial run (``-n 0``) keeps the collection's order."""
    if hasattr(config, "workerinput"):
        items[:] = long_modules_first(items, lambda item: item.nodeid.split("::")[0])


def pytest_addoption(parser: pytest.Parser, pluginmanager: pytest.PytestPluginManager) -> None:
    """Accept pyproject's ``-n auto --dist worksteal`` when pytest-xdist is absent or blocked
    (``-p no:xdist``): the tests then run serially, as with ``-n 0``."""
    if pluginmanager.has_plugin("xdist"):
        return
    group = parser.getgroup("xdist-absent", "without pytest-xdist (the tests run serially)")
    # pytest reserves lowercase short options for plugins; pytest-xdist registers its own "-n"
    # through the same private call
    group._addoption("-n", "--numprocesses", dest="numprocesses", default=None, help="ignored")
    group.addoption("--dist", dest="dist", default="no", help="ignored")


#: Seconds the controller waits for the kernels' first compilation before it lets the workers
#: start anyway (they then compile what is missing, as without this step). Measured: 61-90 s
#: wall for the longer group at load 2-4 on the 2-core machine.
PRECOMPILE_TIMEOUT_S = 900.0


def _cold_kernel_groups() -> list[tuple[str, ...]]:
    """The groups of ``tests/_precompile.py`` with a kernel that Numba's cache lacks (no index
    file of it for this Python in any cache folder that :mod:`jointplay._kernels` names)."""
    import sys

    from _precompile import GROUPS, KERNELS
    from jointplay._kernels import cache_folders

    tag = f"py{sys.version_info.major}{sys.version_info.minor}"
    folders = [folder for folder in cache_folders() if folder.is_dir()]

    def cached(name: str) -> bool:
        return any(next(f.rglob(f"{KERNELS[name]}-*.{tag}.nbi"), None) for f in folders)

    return [group for group in GROUPS if not all(cached(name) for name in group)]


def _precompile(groups: list[tuple[str, ...]], timeout: float) -> list[int | None]:
    """Run ``tests/_precompile.py`` on each group at once, in its own process, and wait (at
    most ``timeout`` s, then kill what still runs). The exit status of each (None: killed);
    never raises for the children's sake."""
    import os
    import subprocess
    import sys
    import time
    from pathlib import Path

    import jointplay

    script = Path(__file__).with_name("_precompile.py")
    source = str(Path(jointplay.__file__).resolve().parents[1])  # the jointplay pytest imports
    path = os.pathsep.join(p for p in (source, os.environ.get("PYTHONPATH", "")) if p)
    env = {**os.environ, "PYTHONPATH": path}
    children = [
        subprocess.Popen(
            [sys.executable, str(script), ",".join(group)],
            env=env,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        for group in groups
    ]
    deadline = time.monotonic() + timeout
    codes: list[int | None] = []
    for child in children:
        try:
            codes.append(child.wait(timeout=max(0.0, deadline - time.monotonic())))
        except subprocess.TimeoutExpired:
            child.kill()
            child.wait()
            codes.append(None)
    return codes


def pytest_sessionstart(session: pytest.Session) -> None:
    """On pytest-xdist's controller, with two workers or more and a cold Numba cache: compile
    the kernels a test run compiles first (``tests/_precompile.py``: what importing ``eom``
    compiles, and the single engine's traced lanes) once, split between two processes, before
    the workers start (pytest-xdist starts them in its own, later ``pytest_sessionstart``),
    instead of every worker compiling all of them (docs/performance.md, "# Tests").
    Nothing with ``-n 0``, on a worker, or with a warm cache; whatever goes wrong here, the
    workers compile as before."""
    config = session.config
    if hasattr(config, "workerinput") or not config.pluginmanager.has_plugin("dsession"):
        return
    if len(getattr(config.option, "tx", None) or []) < 2:
        return
    try:
        groups = _cold_kernel_groups()
        if not groups:
            return
        reporter = config.pluginmanager.get_plugin("terminalreporter")
        if reporter is not None:
            reporter.write_line(
                "Numba's cache is cold: compiling the kernels once, in two processes, "
                "before the workers start (a minute or two)"
            )
        _precompile(groups, PRECOMPILE_TIMEOUT_S)
    except Exception:  # an optimisation only: the workers compile as before
        return
