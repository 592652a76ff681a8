"""Ctrl-C and SIGTERM stop a run cleanly: exit 130, one line, no temporary folder left.

The runs go through the compiled integrator on the serial path (one worker), where an
interrupt used to escape through Numba as a SystemError. They take several seconds each.
"""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow


def _interrupt(arguments: list[str], out: Path, wait: float, sig: int) -> tuple[int, str]:
    """Run ``jointplay ARGUMENTS --out OUT``, send ``sig`` ``wait`` s after it starts computing."""
    process = subprocess.Popen(
        [sys.executable, "-m", "jointplay", *arguments, "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    deadline = time.monotonic() + 60
    while not any(p.name.startswith(f".{out.name}.partial-") for p in out.parent.iterdir()):
        assert process.poll() is None, process.communicate()
        assert time.monotonic() < deadline
        time.sleep(0.05)
    time.sleep(wait)  # into the integration
    assert process.poll() is None, "finished before the interrupt; make the run longer"
    process.send_signal(sig)
    _, err = process.communicate(timeout=60)
    return process.returncode, err


def _leftovers(out: Path) -> list[str]:
    return sorted(p.name for p in out.parent.iterdir() if p.name != out.name)


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_interrupted_simulation_writes_nothing(tmp_path: Path, sig: int) -> None:
    out = tmp_path / "sim"
    status, err = _interrupt(
        ["simulate", "--revolutions", "500", "--no-plots"], out, wait=4.0, sig=sig
    )
    assert status == 130, err
    lines = err.strip().splitlines()
    assert lines == ["jointplay: interrupted; nothing was written (the output folder is as it was)"]
    assert not out.exists()
    assert _leftovers(out) == []


def test_interrupted_serial_tolerance_study_keeps_finished_samples(tmp_path: Path) -> None:
    import pandas as pd

    out = tmp_path / "tol"
    arguments = ["tolerance", "--responses", "dynamic", "--samples", "40000", "--workers", "1"]
    arguments += ["--revolutions", "1", "--settle", "0", "--no-progress", "--no-plots"]
    status, err = _interrupt(arguments, out, wait=25.0, sig=signal.SIGINT)
    assert status == 130, err
    # the finished samples' findings (penetration warnings) may come first; then one line
    # saying what was kept
    lines = [line for line in err.strip().splitlines() if "warning:" not in line]
    assert len(lines) == 1 and "points finished" in lines[0], err
    samples = pd.read_parquet(out / "samples.parquet")
    finished = int((samples["status"] == "ok").sum()) if "status" in samples else len(samples)
    assert 0 < finished < 40000, err
    assert _leftovers(out) == []
