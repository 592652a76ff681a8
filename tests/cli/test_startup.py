"""A fast command line (issue 41): the options of ``simulate`` are read and checked before
the numerical stack is imported, so a mistyped option is one error line without waiting for
SciPy, pandas and Numba (seconds on a loaded machine). No timing here: the speed is measured
by ``benchmarks/bench_cli_startup.py``; these tests check what is imported."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

#: What a command that only reads its options must not import.
HEAVY = ("numba", "scipy", "pandas", "matplotlib", "dask", "pint")

CHECK = """
import sys
from jointplay.cli import run
status = run(sys.argv[1:])
print("STATUS", status)
print("HEAVY", ",".join(m for m in {heavy!r} if m in sys.modules))
"""


def _run(arguments: list[str]) -> tuple[int, list[str], str]:
    """(exit status, heavy modules imported, stderr) of ``jointplay ARGUMENTS`` in a fresh
    interpreter."""
    done = subprocess.run(
        [sys.executable, "-c", CHECK.format(heavy=HEAVY), *arguments],
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    )
    lines = dict(line.split(" ", 1) for line in done.stdout.splitlines() if " " in line)
    heavy = [name for name in lines.get("HEAVY", "").strip().split(",") if name]
    return int(lines["STATUS"]), heavy, done.stderr


@pytest.mark.parametrize(
    ("options", "named"),
    [
        (["--rpm", "200 rmp"], "'rmp' is not defined"),
        (["--clearance", "0.021 mmm"], "--clearance"),
        (["--format", "xls"], "--format"),
        (["--revolutions", "-1"], "--revolutions"),
        (["--sample-deg", "500 deg"], "--sample-deg"),
        (["--max-step", "1 mss"], "--max-step"),
    ],
)
def test_a_bad_option_is_one_line_before_the_numerical_stack_loads(
    options: list[str], named: str, tmp_path: Path
) -> None:
    out = tmp_path / "out"
    status, heavy, err = _run(["simulate", *options, "--out", str(out)])
    assert status == 2 and named in err and len(err.strip().splitlines()) == 1, err
    assert heavy == [], f"imported {heavy} before refusing {options}"
    assert not out.exists()
