"""Ctrl-C and SIGTERM stop a run cleanly: exit 130, one line, nothing lost, no staging left.

Each run is a subprocess of ``jointplay`` started through a small launcher that announces
readiness (a file appears) when the work the test wants to interrupt has begun: the compiled
integration, or the first finished samples. The signal goes then, never after a fixed sleep.
The property test interrupts tolerance and design studies at random moments after that and
checks that the previous result is intact, or that a strictly more complete one replaced it.
"""

from __future__ import annotations

import json
import os
import random
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from jointplay.cli import run
from jointplay.cli._common import COMPILE_NOTICE
from jointplay.io.output import MARKER

pytestmark = pytest.mark.slow

#: How the line after a first run's compiled work begins (``compiling_kernels``).
COMPILED_LINE = "jointplay: kernels compiled and cached;"

#: Runs ``jointplay ARGS`` with a readiness file (``$JOINTPLAY_TEST_READY``) that appears
#: when the compiled integration starts (``integration``), when the first block of samples
#: (more than the nominal point) has finished and been kept (``samples``: the executor's
#: progress callback), or when the figures are being drawn (``figures``). With
#: ``$JOINTPLAY_TEST_COLD_CACHE`` set, the kernels' cache looks cold to the command (it prints
#: the compile notice of a first run after an install; what is cached still loads).
_LAUNCHER = """
import os
import sys
from contextlib import contextmanager
from pathlib import Path


def announcing(original, when):
    @contextmanager
    def wrapped(*args, **kwargs):
        with original(*args, **kwargs) as value:
            if when == "integration":
                Path(os.environ["JOINTPLAY_TEST_READY"]).touch()
                yield value
                return

            def advance(count):
                value(count)
                if count > 1:  # samples, not the nominal point alone
                    Path(os.environ["JOINTPLAY_TEST_READY"]).touch()

            yield advance

    return wrapped


if __name__ == "__main__":
    if os.environ.get("JOINTPLAY_TEST_COLD_CACHE"):  # the first run after an install
        import jointplay._kernels

        jointplay._kernels.compiled_cache_present = lambda *args, **kwargs: False
    from jointplay.dynamics import integrate
    from jointplay.execution import progress

    if sys.argv[1] == "integration":
        integrate._interrupts_watched = announcing(integrate._interrupts_watched, "integration")
    elif sys.argv[1] == "figures":  # announce, then draw for as long as it takes the signal
        import time

        from jointplay.report import design, tolerance

        def drawing(*args, **kwargs):
            Path(os.environ["JOINTPLAY_TEST_READY"]).touch()
            time.sleep(120)

        tolerance.study_plots = design.design_plots = drawing
    else:  # a block of samples is stored (the executor's progress, after it keeps them)
        progress.bar = announcing(progress.bar, "samples")
    from jointplay.cli import main

    sys.argv = ["jointplay", *sys.argv[2:]]
    main()
"""


def _start(
    tmp_path: Path, when: str, arguments: list[str], env: dict[str, str] | None = None
) -> tuple[subprocess.Popen[str], Path]:
    launcher = tmp_path / "launch.py"
    launcher.write_text(_LAUNCHER, encoding="utf-8")
    ready = tmp_path / f"ready-{time.monotonic_ns()}"
    process = subprocess.Popen(
        [sys.executable, str(launcher), when, *arguments],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env={**os.environ, **(env or {}), "JOINTPLAY_TEST_READY": str(ready)},
        start_new_session=True,  # its own process group: a failed test kills the pool too
    )
    return process, ready


def _wait_for(process: subprocess.Popen[str], ready: Path, timeout: float = 240.0) -> bool:
    """Whether ``ready`` appeared while the process still ran (False: it had finished)."""
    deadline = time.monotonic() + timeout
    while not ready.exists():
        if process.poll() is not None:
            return False
        if time.monotonic() > deadline:  # stop the run (and its pool) before failing
            os.killpg(process.pid, signal.SIGKILL)
            process.communicate()
            raise AssertionError("no readiness signal")
        time.sleep(0.02)
    return True


def _answer(process: subprocess.Popen[str], timeout: float = 120.0) -> str:
    """The stderr of ``process`` once it has ended. One still running after ``timeout`` s
    (an interrupt it did not answer) is killed with its pool before the test fails: left
    running, a 40 000-sample study kept a core busy for minutes after its test."""
    try:
        return process.communicate(timeout=timeout)[1]
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        _, err = process.communicate()
        raise AssertionError(f"still running {timeout} s after the signal: {err}") from None


def _interrupt(
    tmp_path: Path,
    when: str,
    arguments: list[str],
    sig: int = signal.SIGINT,
    env: dict[str, str] | None = None,
) -> tuple[int, str]:
    process, ready = _start(tmp_path, when, arguments, env)
    assert _wait_for(process, ready), process.communicate()
    process.send_signal(sig)
    err = _answer(process)
    return process.returncode, err


def _lines(err: str) -> list[str]:
    """The lines of ``err`` without the compile notice, which a first run after an install
    (Numba's cache cold, as in a fresh clone's first test run) prints before its work and,
    when the work ends normally, after it (``compiling_kernels``)."""
    return [
        line
        for line in err.strip().splitlines()
        if line != COMPILE_NOTICE and not line.startswith(COMPILED_LINE)
    ]


def _leftovers(out: Path) -> list[str]:
    return sorted(p.name for p in out.parent.iterdir() if p.name.startswith(".jointplay-"))


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_interrupted_simulation_writes_nothing(tmp_path: Path, sig: int) -> None:
    out = tmp_path / "sim"
    arguments = ["simulate", "--revolutions", "500", "--no-plots", "--out", str(out)]
    status, err = _interrupt(tmp_path, "integration", arguments, sig)
    assert status == 130, err
    lines = _lines(err)
    assert lines == ["jointplay: interrupted; nothing was written (the output folder is as it was)"]
    assert not out.exists()
    assert _leftovers(out) == []


def _finished(out: Path) -> int:
    import pandas as pd

    samples = pd.read_parquet(out / "samples.parquet")
    return int((samples["status"] != "not run").sum())


@pytest.mark.parametrize("backend", ["local", "processes"])
def test_an_interrupted_tolerance_study_keeps_the_finished_samples(
    tmp_path: Path, backend: str
) -> None:
    """The batch engine returns the samples it finished (it used to keep none of them).

    Run as the first run after an install (the launcher makes the kernels' cache look cold,
    compiling nothing more): the compile notice that a fresh clone's first test run printed
    here comes first and is not one of the lines checked."""
    out = tmp_path / "tol"
    arguments = ["tolerance", "--responses", "dynamic", "--samples", "40000", "--backend"]
    arguments += [backend, "--revolutions", "1", "--settle", "0"]
    arguments += ["--workers", "2"] if backend == "processes" else []
    arguments += ["--no-progress", "--no-plots", "--out", str(out)]
    cold = {"JOINTPLAY_TEST_COLD_CACHE": "1"}
    status, err = _interrupt(tmp_path, "samples", arguments, env=cold)
    assert status == 130, err
    assert err.strip().splitlines()[0] == COMPILE_NOTICE, err
    # the finished samples' findings (penetration warnings) may come first; then one line
    # saying what was kept
    lines = [line for line in _lines(err) if "warning:" not in line]
    assert len(lines) == 1 and "points finished; their results were written to" in lines[0], err
    assert 0 < _finished(out) < 40000, err
    assert json.loads((out / MARKER).read_text(encoding="utf-8"))["complete"] < 1
    assert _leftovers(out) == []


#: Seconds from the signal to the end of an interrupted run, writing the kept samples
#: included (measured: 0.2-0.6 s on a 2-core machine, loaded or not; the samples in flight
#: stop within one step of their integration). Generous: the suite shares its machine.
ANSWERED_WITHIN_S = 20.0


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize(
    ("backend", "threads"),
    [("processes", "1"), ("processes", "2"), ("local", "1")],
    ids=["one-worker", "two-workers", "local-one-thread"],
)
def test_the_implicit_lanes_answer_an_interrupt_on_every_worker_count(
    tmp_path: Path, sig: int, backend: str, threads: str
) -> None:
    """The lubricated paper four-bar runs the implicit (Radau) lanes. With one worker (or one
    thread) they ran one after the other, and the loop left the lanes after the interrupted
    one unmarked: the block failed ("1 is not a valid IntegrationStatus"), the study went on
    to its next block and Ctrl-C or SIGTERM was ignored. Now every count stops promptly and
    keeps the finished samples."""
    out = tmp_path / "tol"
    arguments = ["tolerance", "--preset", "paper-fourbar", "--responses", "dynamic"]
    arguments += ["--samples", "4000", "--revolutions", "1", "--settle", "0", "--seed", "2"]
    arguments += ["--backend", backend]
    arguments += ["--workers", threads] if backend == "processes" else []
    arguments += ["--no-progress", "--no-plots", "--out", str(out)]
    env = {"NUMBA_NUM_THREADS": threads} if backend == "local" else {}
    process, ready = _start(tmp_path, "samples", arguments, env)
    assert _wait_for(process, ready), process.communicate()
    process.send_signal(sig)
    sent = time.monotonic()
    try:
        _, err = process.communicate(timeout=ANSWERED_WITHIN_S)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        _, err = process.communicate()
        raise AssertionError(
            f"still running {ANSWERED_WITHIN_S} s after the signal: {err}"
        ) from None
    assert process.returncode == 130, err
    assert time.monotonic() - sent < ANSWERED_WITHIN_S
    assert "points finished; their results were written to" in _lines(err)[-1], err
    assert 0 < _finished(out) < 4000, err
    assert json.loads((out / MARKER).read_text(encoding="utf-8"))["complete"] < 1
    assert _leftovers(out) == []


def _state(out: Path) -> tuple[float, bytes] | None:
    """(completeness, samples file) of the result at ``out``, or None."""
    if not out.exists():
        return None
    record = json.loads((out / MARKER).read_text(encoding="utf-8"))
    return float(record.get("complete", 1.0)), (out / "samples.parquet").read_bytes()


@pytest.mark.parametrize("backend", ["local", "processes"])
def test_interrupts_at_random_moments_never_lose_a_result(
    tmp_path: Path, backend: str, capsys: pytest.CaptureFixture[str]
) -> None:
    """Property: whenever a tolerance or design run into a folder holding a result is
    interrupted, that result is intact, or a strictly more complete one replaced it; what was
    not kept there is beside it, named, or nowhere."""
    rng = random.Random(24)
    runs = {
        "tolerance": ["tolerance", "--responses", "dynamic", "--revolutions", "1"],
        "design": ["design", "--fits", "H7/g6,H8/f7,H11/c11", "--classes", "m", "--require"],
    }
    # dynamic: the 4000-sample runs are still going when the signal comes, in the batch
    # engine's blocks (an interrupted block of the design's peak model lost its derived
    # responses and made the run fail before)
    runs["design"] += ["omega4_peak <= 30 rad/s", "--responses", "dynamic", "--revolutions", "1"]
    common = ["--settle", "0", "--no-progress", "--no-plots", "--backend", backend]
    common += ["--workers", "2"] if backend == "processes" else []
    for command, arguments in runs.items():
        out = tmp_path / command
        small = "40" if command == "tolerance" else "10"
        # the complete results run in this process (the same command without a second
        # interpreter's start-up); only the runs to interrupt need their own process
        assert run([*arguments, *common, "--samples", small, "--out", str(out)]) == 0, (
            capsys.readouterr().err
        )
        for attempt in range(2):
            before = _state(out)
            assert before is not None and before[0] == 1.0
            process, ready = _start(
                tmp_path, "samples", [*arguments, *common, "--samples", "4000", "--out", str(out)]
            )
            if _wait_for(process, ready):
                time.sleep(rng.uniform(0.0, 3.0))  # a random moment after the first samples
                process.send_signal(signal.SIGINT)
            err = _answer(process)
            after = _state(out)
            if process.returncode == 0:  # finished first: a complete result replaced it
                assert after is not None and after[0] == 1.0, err
                continue
            assert process.returncode == 130, err
            assert after == before, (command, attempt, err)  # a complete result stays
            beside = sorted(tmp_path.glob(f"{command}.interrupted-*"))
            if "nothing was written" not in err:
                assert beside, err
                assert _state(beside[-1]) is not None
                assert _state(beside[-1])[0] < 1.0  # type: ignore[index]
            assert _leftovers(out) == []
        # an interrupted result where there was none; a later, more complete one replaces it
        target = tmp_path / f"{command}-fresh"
        process, ready = _start(
            tmp_path, "samples", [*arguments, *common, "--samples", "4000", "--out", str(target)]
        )
        assert _wait_for(process, ready)
        process.send_signal(signal.SIGINT)
        err = _answer(process)
        first = _state(target)
        # a quick (kinematic) design can finish every scheme between the readiness and the
        # signal: then the result is written whole, and the run says that all finished
        whole = re.search(r"\b(\d+) of \1 \w+ finished", err)
        assert first is None or first[0] < 1.0 or (first[0] == 1.0 and whole), err
        assert run([*arguments, *common, "--samples", small, "--out", str(target)]) == 0, (
            capsys.readouterr().err
        )
        assert _state(target)[0] == 1.0  # type: ignore[index]


@pytest.mark.parametrize("command", ["tolerance", "design"])
def test_an_interrupt_while_the_figures_are_drawn_keeps_the_samples(
    tmp_path: Path, command: str
) -> None:
    """Every sample had finished: the data files are kept (beside a complete result)."""
    arguments = {
        "tolerance": ["tolerance", "--samples", "40"],
        "design": [
            "design",
            "--fits",
            "H7/g6,H8/f7",
            "--classes",
            "m",
            "-r",
            "rocker_swing >= 50 deg",
        ],
    }[command]
    out = tmp_path / "out"
    status, err = _interrupt(tmp_path, "figures", [*arguments, "--out", str(out)])
    assert status == 130, err
    unit = "points" if command == "tolerance" else "schemes"
    total = 40 if command == "tolerance" else 2
    assert _lines(err)[-1] == (
        f"jointplay: interrupted; {total} of {total} {unit} finished (the figures and report "
        f"missing); their results were written to {out}"
    )
    assert (out / "summary.json").is_file() and (out / "samples.parquet").is_file()
    assert not (out / "report.html").exists()
    assert _leftovers(out) == []


def _children(pid: int) -> set[int]:
    """The process ids of ``pid``'s children (Linux: /proc)."""
    found: set[int] = set()
    for task in Path(f"/proc/{pid}/task").glob("*"):
        try:
            found |= {int(c) for c in (task / "children").read_text().split()}
        except OSError:
            continue
    return found


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


@pytest.mark.skipif(not Path("/proc/self/task").exists(), reason="needs Linux /proc")
def test_the_worker_pool_dies_with_its_parent(tmp_path: Path) -> None:
    """SIGKILL of the command (no clean-up runs) used to leave its workers for minutes."""
    out = tmp_path / "tol"
    arguments = ["tolerance", "--responses", "dynamic", "--samples", "40000", "--backend"]
    arguments += ["processes", "--workers", "2", "--revolutions", "1", "--settle", "0"]
    arguments += ["--no-progress", "--no-plots", "--out", str(out)]
    process, ready = _start(tmp_path, "samples", arguments)
    assert _wait_for(process, ready), process.communicate()
    workers = _children(process.pid)
    assert len(workers) >= 2
    process.kill()
    process.communicate(timeout=60)
    deadline = time.monotonic() + 10  # each worker looks at its parent every 0.5 s
    while any(_alive(pid) for pid in workers):
        assert time.monotonic() < deadline, [pid for pid in workers if _alive(pid)]
        time.sleep(0.1)
