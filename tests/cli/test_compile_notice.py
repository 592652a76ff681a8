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
    arguments, target = CASES[name]
    monkeypatch.setattr(jointplay._kernels, "compiled_cache_present", lambda: cached)
    printed: list[str] = []

    def dynamics(*args: object, **kwargs: object) -> None:
        seen = capsys.readouterr()
        printed.append(seen.out + seen.err)
        raise ConfigError(STOP)

    monkeypatch.setattr(target, dynamics)
    status = run([a.replace("OUT", str(tmp_path / "out")) for a in arguments])
    rest = capsys.readouterr()
    assert status == 2 and STOP in rest.err, rest.err  # the stand-in ran: the work was reached
    before = " ".join("".join(printed).split())  # a terminal-wide console folds the line
    assert (COMPILE_NOTICE in before) is not cached, before
