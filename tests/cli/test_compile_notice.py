"""Every command that runs the compiled kernels says so before its first run after an install
(when no compiled kernels are cached), as ``paper`` and ``simulate`` did first (issue 25).

The dynamic work itself is replaced by a stand-in that records what the command had printed
by then and stops the command (a ConfigError, exit status 2): the notice must come before the
work, and nothing is compiled or simulated here.
"""

from __future__ import annotations

from pathlib import Path

import pytest

import jointplay._kernels
from jointplay.cli import run
from jointplay.cli._common import COMPILE_NOTICE
from jointplay.errors import ConfigError

#: command line (``OUT``: a fresh path) and the function that runs its dynamics
CASES = {
    "animate": (["animate", "--out", "OUT/a.gif"], "jointplay.dynamics.simulate.simulate"),
    "compare": (["compare", "--method", "physical"], "jointplay.study.comparison.steady_cycle"),
    "calibrate": (["calibrate", "--fit", "clearance"], "jointplay.study.calibration.calibrate"),
    "simulate": (["simulate", "--out", "OUT"], "jointplay.dynamics.simulate.simulate"),
    "wear": (
        ["wear", "--hours", "10 h", "--clearance-limit", "+20 um", "--out", "OUT"],
        "jointplay.dynamics.wear.wear_life",
    ),
    "tolerance": (
        ["tolerance", "--responses", "dynamic", "-n", "2", "--backend", "local", "--out", "OUT"],
        "jointplay.tolerance.analysis.tolerance_study",
    ),
    "design": (
        ["design", "-r", "joint_force <= 150 N", "-n", "2", "--backend", "local", "--out", "OUT"],
        "jointplay.study.design.design_study",
    ),
    "paper": (["paper", "--out", "OUT"], "jointplay.study.paper.run_paper_study"),
}
STOP = "stopped by the test where the dynamics would run"


@pytest.mark.parametrize("cached", [False, True])
@pytest.mark.parametrize("name", sorted(CASES))
def test_a_first_dynamic_run_says_it_compiles_the_kernels_first(
    name: str,
    cached: bool,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    monkeypatch.setattr(jointplay._kernels, "compiled_cache_present", lambda *_: cached)
    before = _printed_before_the_work(name, tmp_path, capsys, monkeypatch)
    assert (COMPILE_NOTICE in before) is not cached, before


def _printed_before_the_work(
    name: str, tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> str:
    """What command ``name`` printed before its dynamics, which a stand-in replaces (it
    stops the command with a ConfigError once the work is reached)."""
    arguments, target = CASES[name]
    printed: list[str] = []

    def dynamics(*args: object, **kwargs: object) -> None:
        seen = capsys.readouterr()
        printed.append(seen.out + seen.err)
        raise ConfigError(STOP)

    monkeypatch.setattr(target, dynamics)
    status = run([a.replace("OUT", str(tmp_path / "out")) for a in arguments])
    rest = capsys.readouterr()
    assert status == 2 and STOP in rest.err, rest.err  # the stand-in ran: the work was reached
    return " ".join("".join(printed).split())  # a terminal-wide console folds the line


def _cached_modules(folder: Path, modules: tuple[str, ...]) -> None:
    """Numba's cache index files of ``modules`` in ``folder``, as a warm cache holds them."""
    import sys

    tag = f"py{sys.version_info.major}{sys.version_info.minor}"
    for module in modules:
        (folder / f"{module}.kernel-10.{tag}.nbi").touch()


#: Commands and the kernel modules of a cache warm for the single engine only (Radau, RODAS4
#: and DOPRI5, as ``simulate`` and ``paper`` fill it: the stems of such a cache, read from one
#: on 2026-11-30), and whether each must say it compiles.
ENGINE_ONLY = ("constraints", "eom", "projection", "source", "source_radau", "source_rodas",
               "sustained", "cpu._work", "cpu._traced_radau", "cpu._traced_rodas4",
               "cpu._traced_dopri5")  # fmt: skip


@pytest.mark.parametrize(
    ("name", "notice"),
    [("simulate", False), ("paper", False), ("animate", False), ("tolerance", True)],
)
def test_the_notice_asks_about_the_kernels_the_command_runs(
    name: str,
    notice: bool,
    tmp_path: Path,
    capsys: pytest.CaptureFixture[str],
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    """A cache warm for the single engine (every ``simulate`` and ``paper`` leaves one) but
    without the batch lanes' kernels, which neither of them runs: ``simulate`` and ``paper``
    say nothing about compiling; ``tolerance``'s dynamic responses run the lanes, and say
    it. (The check looked for the lanes' cache on every command: a warm ``simulate`` said
    "compiling ... about 40 s" every time.)"""
    cache = tmp_path / "cache"
    cache.mkdir()
    _cached_modules(cache, ENGINE_ONLY)
    monkeypatch.setattr(jointplay._kernels, "cache_folders", lambda: [cache])
    before = _printed_before_the_work(name, tmp_path, capsys, monkeypatch)
    assert (COMPILE_NOTICE in before) is notice, before


def test_a_cache_without_the_integrator_run_is_not_warm(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """``simulate --integrator dopri5`` compiles DOPRI5's traced lane: a cache of Radau's
    only is not enough."""
    from jointplay._kernels import compiled_cache_present, single_engine

    monkeypatch.setattr(jointplay._kernels, "cache_folders", lambda: [tmp_path])
    _cached_modules(tmp_path, ("eom", "cpu._traced_radau"))
    assert compiled_cache_present(single_engine())
    assert compiled_cache_present(single_engine("radau"))
    assert not compiled_cache_present(single_engine("dopri5"))
    assert not compiled_cache_present(single_engine("radau", "rodas4"))
    _cached_modules(tmp_path, ("cpu._traced_dopri5",))
    assert compiled_cache_present(single_engine("dopri5"))


def test_the_batch_lanes_stem_is_a_kernel_only_the_batch_drivers_compile() -> None:
    """``BATCH_LANES`` names a function the batch drivers call and the single engine's traced
    lanes do not (so a cache warm for ``simulate`` alone does not pass for the lanes')."""
    from jointplay._kernels import BATCH_LANES
    from jointplay._kernels.lanes import cpu

    for stem in BATCH_LANES:
        module, function = stem.split(".")
        assert module == "cpu" and hasattr(cpu, function), stem
        assert function in cpu._one.__code__.co_names  # every batch driver runs _one
        assert function not in cpu._traced.__code__.co_names


@pytest.mark.slow
def test_a_warm_batch_run_says_nothing_about_compiling(tmp_path: Path) -> None:
    """End to end, on an empty cache of its own: the first dynamic ``tolerance`` run says it
    compiles the kernels, the second says nothing (it said so every time when the check
    looked for kernels no batch run compiles)."""
    import os
    import subprocess
    import sys

    environment = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path / "cache")}
    said = []
    for run_number in range(2):
        command = [sys.executable, "-m", "jointplay", "tolerance", "--responses", "dynamic",
                   "-n", "4", "--backend", "local", "--no-progress",
                   "--out", str(tmp_path / f"out{run_number}")]  # fmt: skip
        done = subprocess.run(command, env=environment, capture_output=True, text=True,
                              timeout=900, check=False)  # fmt: skip
        assert done.returncode == 0, done.stderr[-2000:]
        said.append(COMPILE_NOTICE in " ".join(done.stderr.split()))
    assert said == [True, False]
