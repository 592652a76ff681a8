"""``jointplay explore`` as a process: when the server is stopped (SIGTERM, or Ctrl-C sent
to it alone), the ``jointplay simulate`` of a download in progress ends with it rather than
running on under pid 1, and a view in progress costs at most the 5 s grace, without a
traceback. Linux only (it reads /proc); only 127.0.0.1 is contacted."""

from __future__ import annotations

import contextlib
import os
import signal
import subprocess
import sys
import threading
import time
import urllib.request
from pathlib import Path

import pytest

pytest.importorskip("uvicorn", reason="jointplay[explore] is not installed")
pytestmark = [
    pytest.mark.slow,  # ~15 s each: a server, and a simulate process to stop
    pytest.mark.skipif(not Path("/proc/self/stat").exists(), reason="reads /proc (Linux)"),
]

#: A download whose simulate runs for minutes (stopped long before it ends; before the
#: fix it ran on, orphaned, after the server had stopped).
LONG = "rpm=1&start=rest&settle=10&contact=ifm-ecs-cylindrical"


def _children(pid: int) -> list[int]:
    """Processes whose parent is ``pid`` and whose command line runs ``simulate``."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
            command = (entry / "cmdline").read_bytes().split(b"\0")
        except OSError:
            continue
        parent = int(stat[stat.rindex(")") + 2 :].split()[1])
        if parent == pid and b"simulate" in command:
            found.append(int(entry.name))
    return found


def _alive(pid: int) -> bool:
    """Whether ``pid`` still runs (a zombie, ended but not yet reaped, does not)."""
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat[stat.rindex(")") + 2] != "Z"


@pytest.mark.parametrize("stop", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_stopping_the_server_ends_its_simulate_children(stop) -> None:
    server = subprocess.Popen(
        [sys.executable, "-m", "jointplay", "explore", "--no-browser", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    children: list[int] = []
    try:
        assert server.stdout is not None
        line = server.stdout.readline()  # once the server answers
        assert "http://127.0.0.1:" in line, line
        url = line[line.index("http://") :].split()[0]

        def download() -> None:
            with contextlib.suppress(OSError):  # the server stopped: no answer
                urllib.request.urlopen(f"{url}api/download?{LONG}", timeout=60).read()

        threading.Thread(target=download, daemon=True).start()
        deadline = time.monotonic() + 30
        while not children and time.monotonic() < deadline:
            time.sleep(0.05)
            children = _children(server.pid)
        assert children, "the download started no jointplay simulate"
        server.send_signal(stop)  # to the server alone, as `kill` does
        server.communicate(timeout=30)
        deadline = time.monotonic() + 10
        while any(map(_alive, children)) and time.monotonic() < deadline:
            time.sleep(0.05)
        assert not any(map(_alive, children)), "jointplay simulate outlived the server"
        assert server.returncode == 0
    finally:
        for pid in [server.pid, *children]:
            with contextlib.suppress(ProcessLookupError, PermissionError):
                os.kill(pid, signal.SIGKILL)
        server.wait(timeout=10)


def test_stopping_the_server_during_a_view_prints_no_traceback() -> None:
    """SIGTERM while a view computes (it cannot be interrupted; it runs to its step budget):
    the server stops once its 5 s grace has passed, with its one line and no traceback."""
    server = subprocess.Popen(
        [sys.executable, "-m", "jointplay", "explore", "--no-browser", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    try:
        assert server.stdout is not None
        line = server.stdout.readline()
        assert "http://127.0.0.1:" in line, line
        url = line[line.index("http://") :].split()[0]

        def view() -> None:
            with contextlib.suppress(OSError):
                urllib.request.urlopen(f"{url}api/view?{LONG}", timeout=60).read()

        threading.Thread(target=view, daemon=True).start()
        time.sleep(1.0)  # the view is under way (it takes 5-12 s to its budget)
        started = time.monotonic()
        server.send_signal(signal.SIGTERM)
        _, stderr = server.communicate(timeout=30)
        assert time.monotonic() - started < 15
        assert server.returncode == 0
        assert "Traceback" not in stderr and "jointplay explore: stopped" in stderr, stderr
    finally:
        server.kill()
        server.wait(timeout=10)
