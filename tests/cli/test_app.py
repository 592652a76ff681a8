"""The command line's edges: --version, python -m jointplay, and light start-up.

Start-up *time* is a benchmark (benchmarks/bench_cli_startup.py); what the tests pin down is
its cause: the quick commands must not import the numerical stack at all.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from jointplay import __version__
from jointplay.cli import run

HEAVY = ("numba", "scipy", "pandas", "dask", "distributed", "matplotlib", "pint")


def test_version(capsys) -> None:
    assert run(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"jointplay {__version__}"


def test_python_dash_m_runs_the_command_line() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "jointplay", "--version"], capture_output=True, text=True
    )
    assert done.returncode == 0
    assert done.stdout.strip() == f"jointplay {__version__}"


@pytest.mark.parametrize(
    "arguments",
    [
        ["--help"],
        ["simulate", "--help"],
        ["fit", "H8/g7", "--size", "10mm"],
        ["general-tolerance", "c", "--size", "270.5mm"],
        ["presets"],
        ["show", "paper-fourbar"],
    ],
    ids=" ".join,
)
def test_quick_commands_do_not_import_the_numerical_stack(arguments: list[str]) -> None:
    code = (
        "import sys\n"
        "from jointplay.cli import run\n"
        f"status = run({arguments!r})\n"
        f"print(status, ','.join(m for m in {HEAVY!r} if m in sys.modules))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    status, _, loaded = done.stdout.strip().splitlines()[-1].partition(" ")
    assert status == "0", done.stderr
    assert loaded == "", f"{' '.join(arguments)} imported {loaded}"
