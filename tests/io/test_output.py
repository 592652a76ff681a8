"""The output folder: all or nothing, never stale, never a temporary folder left behind."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import pytest

from jointplay.errors import ConfigError, Interrupted
from jointplay.io import output
from jointplay.io.output import MARKER, output_dir


def _leftovers(parent: Path, keep: str) -> list[str]:
    return sorted(p.name for p in parent.iterdir() if p.name != keep)


def test_a_run_replaces_the_whole_folder(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with output_dir(target) as folder:
        (folder / "timeseries.csv").write_text("old", encoding="utf-8")
        (folder / "plot.png").write_bytes(b"png")
    with output_dir(target) as folder:
        (folder / "summary.json").write_text("{}", encoding="utf-8")
    assert sorted(p.name for p in target.iterdir()) == [MARKER, "summary.json"]
    assert json.loads((target / MARKER).read_text(encoding="utf-8"))["written_by"] == "jointplay"
    assert _leftovers(tmp_path, "out") == []


def test_a_failed_run_leaves_the_previous_result(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with output_dir(target) as folder:
        (folder / "summary.json").write_text("first", encoding="utf-8")
    with pytest.raises(RuntimeError), output_dir(target) as folder:
        (folder / "summary.json").write_text("second", encoding="utf-8")
        raise RuntimeError("boom")
    assert (target / "summary.json").read_text(encoding="utf-8") == "first"
    assert _leftovers(tmp_path, "out") == []


def test_an_interrupted_run_leaves_nothing(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with pytest.raises(KeyboardInterrupt), output_dir(target) as folder:
        (folder / "half.csv").write_text("1,2", encoding="utf-8")
        raise KeyboardInterrupt
    assert not target.exists()
    assert _leftovers(tmp_path, "out") == []


def test_the_staging_folder_exists_before_the_work(tmp_path: Path) -> None:
    with output_dir(tmp_path / "out") as folder:
        assert folder.is_dir() and folder.parent == tmp_path


def test_foreign_folders_are_refused_unless_forced(tmp_path: Path) -> None:
    target = tmp_path / "out"
    target.mkdir()
    (target / "notes.txt").write_text("mine", encoding="utf-8")
    with pytest.raises(ConfigError, match="force=True") as refused, output_dir(target):
        pass
    assert "--force" in str(refused.value.named({"force=True": "--force"}))  # as the CLI shows it
    assert (target / "notes.txt").exists()
    with output_dir(target, force=True) as folder:
        (folder / "a.txt").write_text("a", encoding="utf-8")
    assert sorted(p.name for p in target.iterdir()) == [MARKER, "a.txt"]


def test_an_empty_existing_folder_is_fine(tmp_path: Path) -> None:
    target = tmp_path / "out"
    target.mkdir()
    with output_dir(target) as folder:
        (folder / "a.txt").write_text("a", encoding="utf-8")
    assert (target / "a.txt").exists()


@pytest.mark.parametrize("name", ["", "."])
def test_the_current_folder_is_refused(name: str) -> None:
    with pytest.raises(ConfigError, match=r"^output folder"), output_dir(name):
        pass


def test_a_failed_swap_leaves_the_previous_result(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    target = tmp_path / "out"
    with output_dir(target) as folder:
        (folder / "summary.json").write_text("first", encoding="utf-8")

    def failing(source: Path, destination: Path, flags: int) -> bool:
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(output, "_renameat2", failing)
    with pytest.raises(OSError), output_dir(target) as folder:
        (folder / "summary.json").write_text("second", encoding="utf-8")
    monkeypatch.undo()
    assert (target / "summary.json").read_text(encoding="utf-8") == "first"
    assert _leftovers(tmp_path, "out") == []


@pytest.mark.parametrize("exchange", [True, False], ids=["renameat2", "two-renames"])
def test_the_swap_puts_the_new_result_in_place_and_returns_the_old(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, exchange: bool
) -> None:
    """One atomic exchange on Linux; the documented fallback (two renames) elsewhere."""
    if not exchange:
        monkeypatch.setattr(output, "_renameat2", lambda source, destination, flags: False)
    target, staging = tmp_path / "out", tmp_path / ".jointplay-1-0123abcd.partial"
    target.mkdir()
    (target / "a").write_text("old", encoding="utf-8")
    staging.mkdir()
    (staging / "a").write_text("new", encoding="utf-8")
    old = output._swap(staging, target)
    assert old is not None and (old / "a").read_text(encoding="utf-8") == "old"
    assert (target / "a").read_text(encoding="utf-8") == "new"
    assert old == staging if exchange else old.name == ".jointplay-1-0123abcd.old"


def test_linux_has_the_atomic_exchange(tmp_path: Path) -> None:
    if not sys.platform.startswith("linux"):
        pytest.skip("renameat2 is Linux's")
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    (tmp_path / "a" / "x").touch()
    assert output._renameat2(tmp_path / "a", tmp_path / "b", output._RENAME_EXCHANGE)
    assert (tmp_path / "b" / "x").exists() and not (tmp_path / "a" / "x").exists()


# --- nothing lost: partial results ------------------------------------------------------------


def _result(target: Path, text: str, **interrupted: int) -> Interrupted | None:
    """Write a result with ``summary.json`` = ``text``; interrupted after ``finished`` of
    ``total`` items when given."""
    try:
        with output_dir(target) as folder:
            (folder / "summary.json").write_text(text, encoding="utf-8")
            if interrupted:
                raise Interrupted(interrupted["finished"], interrupted["total"], "points")
    except Interrupted as stopped:
        return stopped
    return None


def test_a_partial_result_goes_where_nothing_was(tmp_path: Path) -> None:
    target = tmp_path / "out"
    stopped = _result(target, "partial", finished=5, total=40)
    assert stopped is not None and stopped.written_to == target and stopped.kept is None
    assert (target / "summary.json").read_text(encoding="utf-8") == "partial"
    assert json.loads((target / MARKER).read_text(encoding="utf-8"))["complete"] == 0.125
    assert "5 of 40 points finished; their results were written to" in stopped.line()


def test_a_partial_result_never_replaces_a_complete_one(tmp_path: Path) -> None:
    target = tmp_path / "out"
    _result(target, "complete")
    for number in (1, 2):
        stopped = _result(target, f"partial {number}", finished=390, total=400)
        assert stopped is not None and stopped.kept == target
        beside = tmp_path / f"out.interrupted-{number}"
        assert stopped.written_to == beside
        assert (beside / "summary.json").read_text(encoding="utf-8") == f"partial {number}"
        assert f"(the more complete result in {target} was kept)" in stopped.line()
    assert (target / "summary.json").read_text(encoding="utf-8") == "complete"
    assert _leftovers(tmp_path, "out") == ["out.interrupted-1", "out.interrupted-2"]


def test_a_more_complete_partial_result_replaces_a_less_complete_one(tmp_path: Path) -> None:
    target = tmp_path / "out"
    _result(target, "few", finished=5, total=40)
    stopped = _result(target, "fewer", finished=4, total=40)
    assert stopped is not None and stopped.written_to == tmp_path / "out.interrupted-1"
    stopped = _result(target, "more", finished=30, total=40)
    assert stopped is not None and stopped.written_to == target
    assert (target / "summary.json").read_text(encoding="utf-8") == "more"
    _result(target, "complete")
    assert (target / "summary.json").read_text(encoding="utf-8") == "complete"


def test_an_interrupt_with_nothing_finished_writes_nothing(tmp_path: Path) -> None:
    target = tmp_path / "out"
    _result(target, "complete")
    stopped = _result(target, "empty", finished=0, total=400)
    assert stopped is not None and stopped.written_to is None
    assert stopped.line() == (
        "0 of 400 points finished; nothing was written (the output folder is as it was)"
    )
    assert (target / "summary.json").read_text(encoding="utf-8") == "complete"
    assert _leftovers(tmp_path, "out") == []


# --- --force: guard rails -----------------------------------------------------------------------


def test_force_never_replaces_the_home_folder(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    home = tmp_path / "home" / "user"
    (home / "work").mkdir(parents=True)
    (home / "thesis.tex").write_text("years", encoding="utf-8")
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.chdir(tmp_path)
    for target in (home, home.parent):
        with pytest.raises(ConfigError, match="home folder"), output_dir(target, force=True):
            pass
    assert (home / "thesis.tex").read_text(encoding="utf-8") == "years"


@pytest.mark.parametrize("target", ["/", "/tmp", "/home", "/usr/local/share/out", "/etc/out"])
def test_force_never_replaces_a_system_folder(target: str) -> None:
    with pytest.raises(ConfigError, match=r"root|system"), output_dir(target, force=True):
        pass


#: (target, why it is never replaced, or "" for a folder the guard lets through). HOME is
#: /home/alice and the current folder is a temp folder's subfolder in this table.
GUARD_TABLE = [
    ("/var/lib", "system folder"),
    ("/var/log", "system folder"),
    ("/var", "root or a folder directly under it"),
    ("/opt/vendor", "system folder"),
    ("/srv", "root or a folder directly under it"),
    ("/srv/www", "system folder"),
    ("/mnt/disk", "system folder"),
    ("/media/usb", "system folder"),
    ("/nix/store", "system folder"),
    ("/snap/core", "system folder"),
    ("/usr/local", "system folder"),
    ("/usr/local/share/out", "system folder"),
    ("/home", "root or a folder directly under it"),
    ("/home/bob", "system folder"),
    ("/home/alice", "home folder"),
    ("/root", "root or a folder directly under it"),
    ("/tmp", "root or a folder directly under it"),
    ("/var/tmp", "temp folder itself"),
    ("/dev/shm", "system folder"),
    ("/tmp/out", ""),
    ("/var/tmp/out", ""),
    ("/home/alice/out", ""),
    ("/data/results", ""),
    ("/var/lib/app/data", ""),  # not never: --force's own-work rule refuses it (below)
]


@pytest.mark.parametrize(("target", "why"), GUARD_TABLE, ids=[row[0] for row in GUARD_TABLE])
def test_the_guard_refuses_system_and_top_two_level_folders(
    target: str, why: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("HOME", "/home/alice")
    monkeypatch.chdir(tmp_path)
    reason = output._forbidden(Path(target), [])
    assert (why in reason) if why else reason == "", reason


@pytest.mark.parametrize(
    ("target", "outside"),
    [("/var/lib/app/data", True), ("/data/results", True), ("/opt/vendor/lib", True),
     ("/home/alice/out", False), ("/tmp/out", False), ("/var/tmp/x/out", False)],
)  # fmt: skip
def test_force_replaces_only_inside_the_users_own_work(
    target: str, outside: bool, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Inside the current folder, the home folder or a temp folder, nowhere else."""
    monkeypatch.setenv("HOME", "/home/alice")
    monkeypatch.chdir(tmp_path)
    assert output._outside_own_work(Path(target)) is outside
    assert output._outside_own_work(tmp_path / "out") is False  # inside the current folder


def test_force_refuses_a_foreign_folder_outside_the_users_own_work(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """A real folder elsewhere (as /var/lib/app would be): refused with ``force``, kept whole;
    the same folder inside the current folder is replaced."""
    home, work, elsewhere = tmp_path / "home", tmp_path / "work", tmp_path / "srv" / "app"
    for folder in (home, work, elsewhere):
        folder.mkdir(parents=True)
    (elsewhere / "db.sqlite").write_text("data", encoding="utf-8")
    monkeypatch.setenv("HOME", str(home))
    monkeypatch.chdir(work)
    monkeypatch.setattr(output, "_temp_folders", lambda: [tmp_path / "tmp"])
    with (
        pytest.raises(ConfigError, match="only inside one of them") as refused,
        output_dir(elsewhere, force=True),
    ):
        pass
    assert "--force" in str(refused.value.named({"force=True": "--force"}))
    assert (elsewhere / "db.sqlite").read_text(encoding="utf-8") == "data"
    monkeypatch.chdir(tmp_path / "srv")
    with output_dir(elsewhere, force=True) as folder:
        (folder / "a.txt").write_text("a", encoding="utf-8")
    assert sorted(p.name for p in elsewhere.iterdir()) == [MARKER, "a.txt"]


def test_force_never_replaces_a_mount_point(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    disk = tmp_path / "disk"
    disk.mkdir()
    (disk / "photos").mkdir()
    real_ismount = os.path.ismount
    monkeypatch.setattr(os.path, "ismount", lambda p: Path(p) == disk or real_ismount(p))
    with pytest.raises(ConfigError, match="mount point"), output_dir(disk, force=True):
        pass
    assert (disk / "photos").is_dir()


def test_out_under_a_file_says_the_file_is_in_the_way(tmp_path: Path) -> None:
    blocker = tmp_path / "good.csv"
    blocker.write_text("a,b\n", encoding="utf-8")
    for target in (blocker / "sub", blocker / "a" / "b"):
        with (
            pytest.raises(ConfigError, match=r"good\.csv' is a file, not a folder; move"),
            output_dir(target),
        ):
            pass
    with (
        pytest.raises(ConfigError, match=r"is a file, not a folder; give a new folder"),
        output_dir(blocker, force=True),
    ):
        pass
    assert blocker.read_text(encoding="utf-8") == "a,b\n"


def test_out_a_symbolic_link_says_so_and_names_the_folder(tmp_path: Path) -> None:
    real = tmp_path / "real"
    real.mkdir()
    link = tmp_path / "link"
    link.symlink_to(real)
    with (
        pytest.raises(ConfigError, match=r"is a symbolic link .*give the folder itself") as error,
        output_dir(link, force=True),
    ):
        pass
    assert str(real) in str(error.value)
    assert link.is_symlink() and real.is_dir()


def test_force_never_replaces_a_folder_holding_an_input(tmp_path: Path) -> None:
    project = tmp_path / "proj"
    project.mkdir()
    config = project / "my.toml"
    config.write_text("[mechanism]\n", encoding="utf-8")
    with (
        pytest.raises(ConfigError, match=r"holds 'my.toml', an input of this run"),
        output_dir(project, force=True, inputs=(None, config)),
    ):
        pass
    (project / MARKER).write_text("{}", encoding="utf-8")  # even one that looks like a result
    with pytest.raises(ConfigError, match="input"), output_dir(project, inputs=(config,)):
        pass
    assert config.exists()


# --- one swap, checked again; long names; stale folders swept ------------------------------------


def test_a_folder_made_at_out_during_the_run_is_not_replaced(tmp_path: Path) -> None:
    target = tmp_path / "out"
    with (
        pytest.raises(ConfigError, match=r"out\.interrupted-1") as error,
        output_dir(target) as folder,
    ):
        (folder / "summary.json").write_text("new", encoding="utf-8")
        target.mkdir()
        (target / "mine.txt").write_text("mine", encoding="utf-8")
    assert "did not write during the run" in str(error.value)
    assert (target / "mine.txt").read_text(encoding="utf-8") == "mine"
    assert (tmp_path / "out.interrupted-1" / "summary.json").read_text(encoding="utf-8") == "new"


def test_a_name_of_255_characters_is_staged_under_a_short_one(tmp_path: Path) -> None:
    target = tmp_path / ("r" * 255)
    for text in ("first", "second"):
        with output_dir(target) as folder:
            assert len(folder.name) < 40
            (folder / "summary.json").write_text(text, encoding="utf-8")
    assert (target / "summary.json").read_text(encoding="utf-8") == "second"


def test_an_old_result_that_cannot_be_removed_gives_a_warning(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    target = tmp_path / "out"
    _result(target, "first")

    def stuck(path: Path, onerror: Any = None, **_: Any) -> None:
        if onerror is None:
            return
        onerror(os.rmdir, str(path), (OSError, OSError(16, "Device or resource busy"), None))

    monkeypatch.setattr(output.shutil, "rmtree", stuck)
    _result(target, "second")
    monkeypatch.undo()
    warning = capsys.readouterr().err
    assert warning.startswith("jointplay: warning: the old result, moved to ")
    assert "could not be fully removed (Device or resource busy); remove it by hand" in warning
    assert (target / "summary.json").read_text(encoding="utf-8") == "second"


def test_staging_folders_of_dead_runs_are_swept(tmp_path: Path) -> None:
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True)  # fmt: skip
    stale = tmp_path / f".jointplay-{int(dead.stdout)}-0123abcd.partial"
    alive = tmp_path / f".jointplay-{os.getppid()}-0123abcd.partial"
    old = tmp_path / f".jointplay-{int(dead.stdout)}-0123abcd.old"  # a fallback's old result
    for folder in (stale, alive, old):
        folder.mkdir()
    _result(tmp_path / "out", "result")
    assert not stale.exists() and alive.exists() and old.exists()


_KILLED_AT = """
import os, signal, sys
from pathlib import Path
from jointplay.io import output

real = output._renameat2
def renameat2(source, destination, flags):
    if sys.argv[2] == "before":
        os.kill(os.getpid(), signal.SIGKILL)
    done = real(source, destination, flags)
    os.kill(os.getpid(), signal.SIGKILL)
output._renameat2 = renameat2
with output.output_dir(sys.argv[1]) as folder:
    (folder / "summary.json").write_text("second", encoding="utf-8")
"""


@pytest.mark.parametrize("moment", ["before", "after"])
def test_a_sigkill_at_the_swap_leaves_one_whole_result(tmp_path: Path, moment: str) -> None:
    """Fault injection: the process is killed just before, or just after, the swap (where two
    renames used to leave no --out at all): --out holds the old or the new result, whole, and
    the next run sweeps what the dead one left."""
    if not sys.platform.startswith("linux"):
        pytest.skip("renameat2 is Linux's")
    target = tmp_path / "out"
    _result(target, "first")
    script = tmp_path / "killed.py"
    script.write_text(_KILLED_AT, encoding="utf-8")
    run = subprocess.run([sys.executable, str(script), str(target), moment], check=False)
    assert run.returncode == -signal.SIGKILL
    expected = "first" if moment == "before" else "second"
    assert (target / "summary.json").read_text(encoding="utf-8") == expected
    assert len(_leftovers(tmp_path, "out")) == 2  # the script and the dead run's folder
    _result(tmp_path / "other", "third")
    assert _leftovers(tmp_path, "out") == ["killed.py", "other"]


# --- JSON numbers: rounded to what they mean --------------------------------------------------


def test_json_numbers_are_rounded_to_twelve_significant_digits() -> None:
    """Round-off of unit conversions disappears; every meaningful digit stays."""
    import math

    import numpy as np

    from jointplay.io.output import JSON_DIGITS, json_text, jsonable, round_significant
    from jointplay.units import parse_quantity

    rpm = parse_quantity("200 rpm", "rad/s", field="x") * 30 / math.pi
    assert rpm == 199.99999999999997  # the noise the sanitiser removes
    assert jsonable(math.degrees(math.radians(30))) == 30.0
    assert JSON_DIGITS == 12
    assert jsonable({"rpm": rpm, "sum": 0.1 + 0.2}) == {"rpm": 200.0, "sum": 0.3}
    assert '"rpm": 200.0' in json_text({"rpm": np.float64(rpm)})
    third = jsonable(1.0 / 3.0)
    assert third == 0.333333333333 and abs(third - 1.0 / 3.0) < 5e-13
    for exact in (0.1, 21e-6, 1.5e-300, -2.5e12, 12345678901.5, 0.0):
        assert jsonable(exact) == exact  # 12 digits or fewer: unchanged
    assert jsonable(7) == 7 and jsonable(True) is True  # integers and booleans as they are
    assert jsonable(math.nan) is None and jsonable(-math.inf) is None
    rng = np.random.default_rng(0)
    values = rng.normal(size=1000) * 10.0 ** rng.integers(-300, 300, size=1000)
    once = [round_significant(float(v)) for v in values]
    assert once == [round_significant(v) for v in once]  # idempotent
    assert all(
        abs(a - float(v)) <= 5e-12 * abs(float(v)) for a, v in zip(once, values, strict=True)
    )


def test_csv_cells_that_would_start_a_formula_are_quoted(tmp_path: Path) -> None:
    """A point named '=HYPERLINK(...)' reached CSV headers verbatim: a spreadsheet formula."""
    import pandas as pd

    from jointplay.io.output import write_csv

    table = pd.DataFrame(
        {
            "x_=HYPERLINK(1)": [-1.5, 2.0],
            "label": ["+SUM(A1)", "plain"],
            "@cmd": ["-2", "tab\tin the middle"],
        }
    )
    path = tmp_path / "t.csv"
    write_csv(table, path)
    back = pd.read_csv(path)
    assert list(back.columns) == ["x_=HYPERLINK(1)", "label", "'@cmd"]
    assert back["x_=HYPERLINK(1)"].tolist() == [-1.5, 2.0]  # numbers as they are
    assert back["label"].tolist() == ["'+SUM(A1)", "plain"]
    assert back["'@cmd"].tolist() == ["'-2", "tab\tin the middle"]
    write_csv(table.rename(columns={"x_=HYPERLINK(1)": "=HYPERLINK(1)"}), path)
    assert pd.read_csv(path).columns[0] == "'=HYPERLINK(1)"


def test_an_interrupt_sent_through_another_thread_waits_for_the_held_block() -> None:
    """A SIGINT sent to the process while a result's files are written arrives after them,
    whichever thread the kernel delivers it through (a thread that does not block it, as
    pyarrow's writers do not, is the one sending it here)."""
    steps: list[str] = []
    with pytest.raises(KeyboardInterrupt):
        with output.signals_held():
            sender = threading.Thread(target=os.kill, args=(os.getpid(), signal.SIGINT))
            sender.start()
            sender.join()
            time.sleep(0.05)  # time for the signal to be delivered and its handler to run
            steps.append("the files are whole")
        steps.append("not reached")
    assert steps == ["the files are whole"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # put back


def test_a_held_interrupt_is_delivered_after_the_next_data_write_or_on_release() -> None:
    """hold_signals() (from a study's end) notes Ctrl-C; the writing of the data files
    (signals_held) takes it over and delivers it when they are whole; without a writing,
    release_signals() delivers it; the handlers are put back either way."""
    import os
    import signal

    from jointplay.io.output import hold_signals, release_signals, signals_held

    written = []
    hold_signals()
    os.kill(os.getpid(), signal.SIGINT)  # noted, not raised
    with pytest.raises(KeyboardInterrupt), signals_held():
        written.append("data")
    assert written == ["data"]
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    release_signals()  # taken over already: nothing left to deliver

    hold_signals()
    os.kill(os.getpid(), signal.SIGINT)
    with pytest.raises(KeyboardInterrupt):
        release_signals()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler
    hold_signals()
    release_signals()  # nothing came: nothing raised


def test_a_marker_that_is_a_fifo_is_not_read(tmp_path: Path) -> None:
    """The marker of an old result goes through the bounded reader: a FIFO in its place (a
    read would block for ever) counts as no marker, and the partial result goes beside it."""
    import os

    from jointplay.errors import Interrupted

    out = tmp_path / "out"
    out.mkdir()
    os.mkfifo(out / MARKER)
    with pytest.raises(Interrupted) as stopped, output_dir(out) as staging:
        (staging / "a.txt").write_text("x")
        raise Interrupted(1, 2, "points")
    assert stopped.value.written_to is not None
    assert (stopped.value.written_to / "a.txt").read_text() == "x"


@pytest.mark.parametrize(
    ("target", "why"),
    [("/etc/hosts", "system folder"), ("/usr/bin/python3", "system folder"),
     ("/var/lib/app/mechanism.gif", "outside your own work"), ("/home/alice/m.gif", ""),
     ("/tmp/m.gif", "")],
)  # fmt: skip
def test_force_replaces_a_file_only_where_it_would_replace_a_folder(
    target: str, why: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The file outputs (``animate --out FILE``) follow the folders' rule: as root, ``--out
    /etc/hosts --force`` once replaced the file."""
    monkeypatch.setenv("HOME", "/home/alice")
    monkeypatch.chdir(tmp_path)
    reason = output.file_refusal(Path(target))
    assert (why in reason) if why else reason == "", reason
    assert output.file_refusal(tmp_path / "mechanism.gif") == ""


def test_a_table_of_floats_is_written_as_pandas_writes_it(tmp_path: Path) -> None:
    """write_csv's own writer of all-float tables (simulate's time series) gives pandas'
    bytes: the same numbers, names, quoting and line ends; other tables go to pandas."""
    import numpy as np
    import pandas as pd

    from jointplay.io.output import _write_floats, write_csv

    generator = np.random.default_rng(41)
    values = generator.normal(size=(300, 5)) * 10.0 ** generator.integers(-12, 12, size=(300, 5))
    values[0] = [0.0, -0.0, 1e300, -1e-300, 123456789.123456789]
    table = pd.DataFrame(
        values, columns=["t", "crank_deg", "name, with comma", 'quote "q"', "=formula"]
    )
    for float_format in ("%.10g", "%.6e", "%.3f"):
        mine, theirs = tmp_path / "mine.csv", tmp_path / "theirs.csv"
        write_csv(table, mine, float_format=float_format)
        safe = table.rename(columns=lambda name: "'" + name if name.startswith("=") else name)
        safe.to_csv(theirs, index=False, float_format=float_format)
        assert mine.read_bytes() == theirs.read_bytes()
        counted = table.assign(contact=generator.integers(0, 2, size=300), n=-np.arange(300))
        write_csv(counted, mine, float_format=float_format)
        counted.rename(columns={"=formula": "'=formula"}).to_csv(
            theirs, index=False, float_format=float_format
        )
        assert mine.read_bytes() == theirs.read_bytes()
    # simulate's contact flags are 8-bit integers: every integer width takes the fast path
    widths = table.assign(
        **{
            f"{kind}": generator.integers(0, 100, size=300).astype(kind)
            for kind in ("int8", "int16", "int32", "uint8", "uint16", "uint32", "uint64")
        },
        negative=-generator.integers(0, 100, size=300).astype("int8"),
    )
    mine, theirs = tmp_path / "mine.csv", tmp_path / "theirs.csv"
    assert _write_floats(widths, mine, "%.10g")
    widths.to_csv(theirs, index=False, float_format="%.10g")
    assert mine.read_bytes() == theirs.read_bytes()
    with_nan = table.assign(t=np.nan)
    mixed = table.assign(label="a")
    flags = table.assign(flag=True)
    for other in (with_nan, mixed, flags):
        assert not _write_floats(other, tmp_path / "x.csv", "%.10g")
    assert not (tmp_path / "x.csv").exists()
