"""The exit statuses are the documented ones whatever the terminal: an encoding that lacks a
character, a full or closed stderr, an unwritable stdout (README, "Exit codes")."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

needs_dev_full = pytest.mark.skipif(not Path("/dev/full").exists(), reason="needs /dev/full")

#: A quick command whose table has a µ (stdout), and one whose error line has a °.
TABLE = ["fit", "H7/g6", "--size", "10 mm"]
BAD_UNIT = ["fit", "H7/g6", "--size", "10 °"]


def _jointplay(arguments: list[str], **options: Any) -> subprocess.CompletedProcess[bytes]:
    env = {**os.environ, **options.pop("env", {})}
    return subprocess.run(
        [sys.executable, "-m", "jointplay", *arguments], env=env, check=False, **options
    )


def test_an_ascii_terminal_gets_escapes_not_an_internal_error() -> None:
    """``PYTHONIOENCODING=ascii``: the µ of a table was a UnicodeEncodeError, exit 3."""
    done = _jointplay(TABLE, capture_output=True, env={"PYTHONIOENCODING": "ascii:strict"})
    assert done.returncode == 0, done.stderr
    assert b"\\xb5m" in done.stdout and done.stderr == b""


@needs_dev_full
@pytest.mark.parametrize(
    ("arguments", "status"),
    [(TABLE, 0), (BAD_UNIT, 2), (["no-such-command"], 2)],
    ids=["success", "bad-value", "usage-error"],
)
def test_an_unwritable_stderr_keeps_the_exit_status(arguments: list[str], status: int) -> None:
    """``2>/dev/full``: the error line cannot be written, and used to turn every failure
    into exit 1."""
    with open("/dev/full", "wb") as full:
        done = _jointplay(arguments, stdout=subprocess.DEVNULL, stderr=full)
    assert done.returncode == status


def test_a_closed_stderr_keeps_the_exit_status_and_stdout_clean() -> None:
    """``2>&-``: Python has no stderr at all; the error line must not go to stdout."""
    # closed by a shell, not by preexec_fn: a fork in a test process that has imported JAX
    # (multithreaded) warns, and the warning fails the test under filterwarnings = error
    done = subprocess.run(
        ["sh", "-c", 'exec "$0" "$@" 2>&-', sys.executable, "-m", "jointplay", *BAD_UNIT],
        stdout=subprocess.PIPE, check=False,
    )  # fmt: skip
    assert done.returncode == 2
    assert done.stdout == b""


@needs_dev_full
def test_an_unwritable_stdout_is_an_error_said_on_stderr() -> None:
    """The result cannot reach its reader: exit 2 with one line, not 0 nor a traceback
    (stdout is not made unfailing as stderr is: its writes are the command's result)."""
    with open("/dev/full", "wb") as full:
        done = _jointplay(TABLE, stdout=full, stderr=subprocess.PIPE)
    assert done.returncode == 2
    lines = done.stderr.decode().strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("jointplay: error: "), lines
    assert "No space left on device" in lines[0]


# --- the progress bar: on a terminal, or where asked for -------------------------------------------

#: A quick study with a progress bar (kinematic Monte Carlo, ~2 s).
STUDY = ["tolerance", "--samples", "50", "--no-plots", "--force"]
BAR = b"Monte Carlo samples"


def _stderr_on_a_terminal(arguments: list[str]) -> bytes:
    """What ``jointplay ARGS`` writes to stderr when stderr is a terminal (a pseudo-terminal)."""
    import pty

    master, slave = pty.openpty()
    try:
        process = subprocess.Popen(
            [sys.executable, "-m", "jointplay", *arguments],
            stdout=subprocess.DEVNULL,
            stderr=slave,
        )
        os.close(slave)
        said = b""
        while True:
            try:
                chunk = os.read(master, 65536)
            except OSError:  # EIO: the terminal's other end closed
                break
            if not chunk:
                break
            said += chunk
        assert process.wait(timeout=120) == 0, said
        return said
    finally:
        os.close(master)


def test_no_bar_on_a_stderr_that_is_not_a_terminal(tmp_path: Path) -> None:
    """A log file or a pipe got the bar's last frame, a line of box characters."""
    done = _jointplay([*STUDY, "--out", str(tmp_path / "r")], capture_output=True)
    assert done.returncode == 0, done.stderr
    assert BAR not in done.stderr and "━".encode() not in done.stderr


def test_progress_forces_the_bar_on_any_stderr(tmp_path: Path) -> None:
    done = _jointplay([*STUDY, "--progress", "--out", str(tmp_path / "r")], capture_output=True)
    assert done.returncode == 0, done.stderr
    assert BAR in done.stderr and b"50/50" in done.stderr


@pytest.mark.skipif(not hasattr(os, "openpty"), reason="needs a pseudo-terminal")
def test_a_terminal_gets_the_bar_unless_no_progress(tmp_path: Path) -> None:
    assert b"50/50" in _stderr_on_a_terminal([*STUDY, "--out", str(tmp_path / "a")])
    hidden = _stderr_on_a_terminal([*STUDY, "--no-progress", "--out", str(tmp_path / "b")])
    assert BAR not in hidden
