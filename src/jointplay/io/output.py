"""Writing a command's results all-or-nothing, never losing a complete one.

A command prepares its output folder before it computes anything (:func:`output_dir`): a
fresh staging folder beside the target, under a short name (``.jointplay-PID-XXXXXXXX``), so
that an unwritable output folder is reported at once and a long name still fits. Every
result folder carries a marker file (:data:`MARKER`) saying whether it is complete; an
existing non-empty folder without one is not a jointplay result and is refused unless
``force``, and even then replaced only if it lies inside the working folder, the home folder
or a temp folder (:func:`_outside_own_work`). Some folders are never replaced, ``force`` or
not (:func:`_forbidden`): the root and every top-level folder, the system trees (``/usr``,
``/etc``, ...), a folder directly under a system top-level folder (:data:`SYSTEM_TOPS`:
``/var/lib``, ``/opt/x``, ``/home/bob``), a mount point, a temp folder itself, the home
folder and the folders above it and above the working folder, and any folder that holds an
input of the run.

How a run ends:

* **success** — the staging folder takes the target's place in one atomic swap
  (``renameat2(RENAME_EXCHANGE)`` on Linux; elsewhere two renames, see :func:`_swap`), the
  target's checks repeated just before it (a folder someone created at the target during the
  run is not replaced without ``force``); the old result is then removed, with a warning if
  it cannot be;
* **interrupted with finished work** — the command raises :class:`Interrupted` inside the
  ``with`` block, after writing what finished. The partial result takes the target's place
  only if the target holds nothing or a less complete partial result; beside a complete one
  (or an equally complete partial one) it is kept as ``NAME.interrupted-N``. With nothing
  finished, nothing is written;
* **failed or interrupted before any result** — the target is left as it was.

Staging folders of runs that died (SIGKILL) are swept by the next run in the same folder.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import errno
import json
import math
import os
import re
import shutil
import signal
import sys
import threading
import uuid
from collections.abc import Iterator, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

from jointplay.errors import ConfigError, Interrupted, SettingError

#: Name of the marker file that every result folder written by jointplay carries.
MARKER = ".jointplay-result.json"
#: Staging (and, on the fallback path, old-result) folders: ``.jointplay-PID-HEX.KIND``.
_STAGING = re.compile(r"^\.jointplay-(\d+)-[0-9a-f]{8}\.(partial|old)$")
#: Trees no result ever replaces (with the root and every folder directly under it).
SYSTEM_TREES = ("/bin", "/boot", "/dev", "/etc", "/lib", "/lib32", "/lib64", "/libx32", "/proc",
                "/run", "/sbin", "/sys", "/usr")  # fmt: skip
#: Top-level folders whose own children are system or other users' folders (``/var/lib``,
#: ``/opt/x``, ``/home/bob``, ``/mnt/disk``): no result replaces a folder directly under one,
#: unless it lies inside the home folder (``/root/out`` for root) or a temp folder (``/tmp/x``).
SYSTEM_TOPS = ("/home", "/media", "/mnt", "/nix", "/opt", "/private", "/root", "/snap", "/srv",
               "/tmp", "/var", "/Applications", "/Library", "/System", "/Users", "/Volumes")  # fmt: skip


def _temp_folders() -> list[Path]:
    """The temp folders: Python's (``$TMPDIR``, ...), ``/tmp`` and ``/var/tmp``, resolved."""
    import tempfile

    return [Path(folder).resolve() for folder in (tempfile.gettempdir(), "/tmp", "/var/tmp")]


def _forbidden(resolved: Path, inputs: Sequence[Path]) -> str:
    """Why ``resolved`` may never be replaced, ``force`` or not, or ``""``."""
    home = Path.home().resolve()
    here = Path.cwd().resolve()
    temps = _temp_folders()
    if len(resolved.parts) <= 2:
        return "is the root or a folder directly under it"
    if any(resolved == Path(tree) or Path(tree) in resolved.parents for tree in SYSTEM_TREES):
        return "is a system folder"
    if os.path.ismount(resolved):
        return "is a mount point (the top folder of a file system)"
    if resolved in temps:
        return "is a temp folder itself"
    if resolved == home or resolved in home.parents:
        return "is the home folder or one above it"
    if resolved == here or resolved in here.parents:
        return "is the current folder or one above it"
    if (
        len(resolved.parts) == 3
        and str(resolved.parent) in SYSTEM_TOPS
        and not any(folder in resolved.parents for folder in (home, *temps))
    ):
        return f"is a system folder or another user's (directly under {resolved.parent})"
    for item in inputs:
        if resolved in item.parents:
            return f"holds {item.name!r}, an input of this run"
    return ""


def _outside_own_work(resolved: Path) -> bool:
    """Whether ``resolved`` lies outside the user's own work: not inside the current folder,
    the home folder or a temp folder. ``force`` replaces a folder jointplay did not write
    only inside one of them."""
    own = (Path.cwd().resolve(), Path.home().resolve(), *_temp_folders())
    return not any(folder in resolved.parents for folder in own)


def file_refusal(target: Path) -> str:
    """Why ``--force`` may not replace the existing file ``target`` (the file outputs, such as
    ``animate --out``), or ``""``: the folders' rule (docs/cli.md) for the file's folder — never
    in a system folder, and only inside the current, home or a temp folder."""
    resolved = target.resolve()
    if any(resolved == Path(tree) or Path(tree) in resolved.parents for tree in SYSTEM_TREES):
        return "is in a system folder"
    if _outside_own_work(resolved):
        return (
            "is outside your own work: --force replaces an existing file only inside the "
            "current folder, the home folder or a temp folder"
        )
    return ""


def _check_target(target: Path | str, force: bool, inputs: Sequence[Path | str] = ()) -> Path:
    """``target`` as a path that may be replaced, or a ConfigError saying why not."""
    text = str(target)
    if text.strip() in ("", "."):
        raise SettingError(
            "{output folder} {got!r} names the current folder; give a folder to write into",
            got=text,
        )
    path = Path(text)
    try:
        resolved = path.resolve()
        why = _forbidden(resolved, [Path(item).resolve() for item in inputs])
    except (OSError, RuntimeError) as exc:
        raise SettingError(
            "{output folder} {got!r} cannot be resolved: {why}", got=text, why=exc
        ) from None
    if why:
        raise SettingError(
            "{output folder} {got!r} {why}; give a new folder to write into", got=text, why=why
        )
    if path.is_symlink():
        raise SettingError(
            "{output folder} {got!r} is a symbolic link (to {to!r}), which is never replaced; "
            "give the folder itself ({real!r}) or a new folder",
            got=text,
            to=os.readlink(path),
            real=str(resolved),
        )
    if path.exists() and not path.is_dir():
        raise SettingError(
            "{output folder} {got!r} is a file, not a folder; give a new folder to write the "
            "results into (e.g. {example!r})",
            got=text,
            example=f"{path.with_suffix('')}-results",
        )
    blocker = _file_above(path)
    if blocker is not None:
        raise SettingError(
            "cannot write the output folder {got!r}: {blocker!r} is a file, not a folder; "
            "move that file, or give an {output folder} that is not inside it",
            got=text,
            blocker=str(blocker),
        )
    if path.is_dir() and _foreign(path):
        if not force:
            raise SettingError(
                "{output folder} {got!r} is a non-empty folder that jointplay did not write; "
                "give a new folder, or {force=True} to replace it",
                got=text,
            )
        if _outside_own_work(resolved):
            raise SettingError(
                "{output folder} {got!r} is a non-empty folder that jointplay did not write, "
                "outside the current folder, the home folder and the temp folders; "
                "{force=True} replaces such a folder only inside one of them: give a new "
                "folder, or empty this one by hand",
                got=text,
            )
    return path


def _file_above(path: Path) -> Path | None:
    """The first of ``path``'s parents that exists and is not a folder, or ``None``."""
    for parent in reversed(path.absolute().parents):
        if parent.exists() and not parent.is_dir():
            return parent
        if not parent.exists():
            return None
    return None


def _foreign(path: Path) -> bool:
    """Whether ``path`` is a non-empty folder without jointplay's marker."""
    try:
        entries = [entry.name for entry in path.iterdir()]
    except OSError as exc:
        raise SettingError(
            "{output folder} {got!r} cannot be read: {why}", got=str(path), why=exc.strerror
        ) from None
    return bool(entries) and MARKER not in entries


def _completeness(path: Path) -> float | None:
    """How complete the jointplay result at ``path`` is (1: complete), ``None`` if none."""
    from jointplay.io.config import read_text_file  # the one bounded reader

    try:  # a FIFO or device in its place is refused, never read (it would hang)
        record = json.loads(read_text_file(path / MARKER, "result marker"))
    except (OSError, ValueError):  # ConfigError is a ValueError
        return None if not path.is_dir() or _foreign(path) else 0.0
    share = record.get("complete", 1.0) if isinstance(record, dict) else 1.0
    return float(share) if isinstance(share, int | float) else 1.0


@contextmanager
def output_dir(
    target: Path | str, *, force: bool = False, inputs: Sequence[Path | str | None] = ()
) -> Iterator[Path]:
    """Yield a fresh staging folder beside ``target``; on normal exit it replaces ``target``.

    Enter it before computing: the checks (a usable ``target``, a writable parent) come
    first, so bad output paths are reported before any work. On :class:`Interrupted` the
    partial result is kept by the module's rules; on any other exception (including
    KeyboardInterrupt) the staging folder is removed and ``target`` is left as it was.

    Args:
        target: the output folder.
        force: replace an existing non-empty folder even if jointplay did not write it.
        inputs: the files the run reads (``None`` entries ignored): a folder holding one is
            never replaced.

    Raises:
        ConfigError: ``target`` cannot be used or its parent is not writable.
    """
    given = [Path(item) for item in inputs if item is not None]
    path = _check_target(target, force, given)
    parent = path.absolute().parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        _sweep(parent)
        staging = parent / f".jointplay-{os.getpid()}-{uuid.uuid4().hex[:8]}.partial"
        staging.mkdir()
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise ConfigError(f"cannot write the output folder {str(target)!r}: {reason}") from None
    try:
        try:
            yield staging
        except Interrupted as stopped:
            if stopped.finished > 0:
                _write_marker(staging, stopped.complete_share)
                with signals_held():
                    stopped.written_to, stopped.kept = _keep_partial(
                        staging, path, stopped.complete_share
                    )
            raise
        _write_marker(staging, 1.0)
        with signals_held():
            if path.is_dir() and not force and _foreign(path):  # made during the run
                beside = _free_name(path)
                _swap(staging, beside)
                raise SettingError(
                    "{output folder} {got!r} became a folder that jointplay did not write "
                    "during the run and is not replaced without {force=True}; the results "
                    "were written to {beside}",
                    got=str(target),
                    beside=beside,
                )
            _check_target(path, force, given)  # again, just before the swap
            _publish(staging, path)
    finally:
        with signals_held():  # also ends a hold_signals() that no writing took over
            shutil.rmtree(staging, ignore_errors=True)


def _write_marker(folder: Path, complete: float) -> None:
    record = {"written_by": "jointplay", "complete": round(complete, 6)}
    (folder / MARKER).write_text(json.dumps(record) + "\n", encoding="utf-8")


def _keep_partial(staging: Path, target: Path, share: float) -> tuple[Path, Path | None]:
    """Publish the partial result ``staging`` (completeness ``share``) at ``target`` if that
    holds nothing or a less complete result, else beside it; (where it went, what was kept)."""
    old = _completeness(target) if target.exists() else -1.0
    if old is not None and old < share:
        _publish(staging, target)
        return target, None
    beside = _free_name(target)
    _swap(staging, beside)
    return beside, target


def _free_name(target: Path) -> Path:
    """``NAME.interrupted-N`` beside ``target``, the first N that is free."""
    number = 1
    while True:
        candidate = target.with_name(f"{target.name}.interrupted-{number}")
        if not candidate.exists() and not candidate.is_symlink():
            return candidate
        number += 1


def _sweep(parent: Path) -> None:
    """Remove the staging folders in ``parent`` of jointplay runs that are no longer alive
    (a run killed with SIGKILL cannot clean up after itself)."""
    for entry in parent.iterdir():
        match = _STAGING.match(entry.name)
        if match is None or match[2] != "partial" or _alive(int(match[1])):
            continue
        shutil.rmtree(entry, ignore_errors=True)


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # another user's process: alive
        return True
    return True


@contextmanager
def signals_held() -> Iterator[None]:
    """Hold SIGINT and SIGTERM back (delivered on exit), so that the renames, the clean-up and
    the writing of a result's data files are never cut in half.

    In the main thread the two signals' handlers are replaced by one that only records them,
    and the first one recorded is raised again on exit. Blocking them with
    ``pthread_sigmask`` alone is not enough: it holds them for the calling thread only, and a
    signal sent to the process is then delivered through another thread (pyarrow's writers,
    Numba's workers), whose Python handler still interrupts the main thread at once (seen: an
    interrupted design's partial result without its samples file). Elsewhere, where Python
    handlers cannot be set, the calling thread blocks them.
    """
    if threading.current_thread() is not threading.main_thread():
        if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - not POSIX
            yield
            return
        previous_mask = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
        try:
            yield
        finally:
            signal.pthread_sigmask(signal.SIG_SETMASK, previous_mask)
        return
    global _held_over
    pending: list[int] = []

    def record(signum: int, frame: object) -> None:
        pending.append(signum)

    # a handler set outside Python (None) could not be put back: such a signal is not held
    previous: dict[signal.Signals, Any] = {
        number: signal.signal(number, record)
        for number in (signal.SIGINT, signal.SIGTERM)
        if signal.getsignal(number) is not None
    }
    if _held_over is not None:  # take over what hold_signals() held: delivered at our end
        held, _held_over = _held_over, None
        previous = {**previous, **held[0]}
        pending[:0] = held[1]
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)
        if pending:
            signal.raise_signal(pending[0])


#: What :func:`hold_signals` holds: the handlers it replaced and the signals it noted.
_held_over: tuple[dict[signal.Signals, Any], list[int]] | None = None


def hold_signals() -> None:
    """Hold SIGINT and SIGTERM back from now until a result's data have been written: the
    next :func:`signals_held` (the writing of the data files) takes them over and delivers
    them when it ends, or :func:`release_signals` does. For the stretch between a study's
    end and the writing of its results, where an interrupt would lose every finished sample.
    In the main thread only (elsewhere nothing is held)."""
    global _held_over
    if _held_over is not None or threading.current_thread() is not threading.main_thread():
        return
    pending: list[int] = []

    def record(signum: int, frame: object) -> None:
        pending.append(signum)

    previous = {
        number: signal.signal(number, record)
        for number in (signal.SIGINT, signal.SIGTERM)
        if signal.getsignal(number) is not None
    }
    _held_over = (previous, pending)


def release_signals() -> None:
    """End :func:`hold_signals`'s hold if no :func:`signals_held` took it over: the handlers
    are put back and the first signal held is delivered."""
    global _held_over
    if _held_over is None or threading.current_thread() is not threading.main_thread():
        return
    (previous, pending), _held_over = _held_over, None
    for number, handler in previous.items():
        signal.signal(number, handler)
    if pending:
        signal.raise_signal(pending[0])


def _publish(staging: Path, target: Path) -> None:
    """Put ``staging`` in the place of ``target`` in one swap; then remove the old result,
    warning if it cannot be (fully) removed."""
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(staging, 0o777 & ~umask)
    if not target.exists():
        _swap(staging, target)
        return
    old = _swap(staging, target)
    if old is None:
        return
    failures: list[str] = []
    shutil.rmtree(
        old, onerror=lambda f, name, info: failures.append(getattr(info[1], "strerror", "") or "")
    )
    if failures or old.exists():
        print(
            f"jointplay: warning: the old result, moved to {old}, could not be fully removed "
            f"({failures[0] or 'an error' if failures else 'it is still there'}); remove it by hand",
            file=sys.stderr,
        )


_RENAME_NOREPLACE, _RENAME_EXCHANGE, _AT_FDCWD = 1, 2, -100


def _renameat2(source: Path, destination: Path, flags: int) -> bool:
    """``renameat2(source, destination, flags)``; False where the platform lacks it."""
    if not sys.platform.startswith("linux"):
        return False
    libc = ctypes.CDLL(ctypes.util.find_library("c") or None, use_errno=True)
    function = getattr(libc, "renameat2", None)
    if function is None:  # glibc < 2.28
        return False
    function.argtypes = [ctypes.c_int, ctypes.c_char_p, ctypes.c_int, ctypes.c_char_p,
                         ctypes.c_uint]  # fmt: skip
    result = function(_AT_FDCWD, os.fsencode(source), _AT_FDCWD, os.fsencode(destination), flags)
    if result == 0:
        return True
    code = ctypes.get_errno()
    if code in (errno.EINVAL, errno.ENOSYS, errno.EOPNOTSUPP):  # kernel or file system lacks it
        return False
    raise OSError(code, os.strerror(code), str(destination))


def _swap(staging: Path, target: Path) -> Path | None:
    """Move ``staging`` to ``target``; if ``target`` exists, the two change places in one
    atomic ``renameat2(RENAME_EXCHANGE)`` (Linux >= 3.15) and the old result is returned, now
    at ``staging``'s name.

    Fallback where the platform has no exchange: two renames (old → ``.jointplay-PID-HEX.old``
    beside it, staging → target); a kill between them leaves no ``target`` and the old result
    in that folder, which no run removes (restore it by renaming it back).
    """
    if not target.exists() and not target.is_symlink():
        if not _renameat2(staging, target, _RENAME_NOREPLACE):
            staging.rename(target)
        return None
    if _renameat2(staging, target, _RENAME_EXCHANGE):
        return staging
    trash = staging.with_name(staging.name.removesuffix(".partial") + ".old")
    target.rename(trash)
    try:
        staging.rename(target)
    except BaseException:
        trash.rename(target)
        raise
    return trash


#: The first characters that make a spreadsheet read a CSV cell as a formula (OWASP, "CSV
#: Injection"): such text cells and column names are written behind a single quote.
FORMULA_STARTS = ("=", "+", "-", "@", "\t", "\r")


def csv_safe(text: object) -> object:
    """``text`` behind a ``'`` if it is a string a spreadsheet would read as a formula."""
    if isinstance(text, str) and text.startswith(FORMULA_STARTS):
        return "'" + text
    return text


def write_csv(table: Any, path: Path, float_format: str | None = "%.10g") -> None:
    """Write the pandas ``table`` as CSV without its index, every column name and text cell
    that would start a spreadsheet formula quoted (:func:`csv_safe`); numbers are as they are.
    The one CSV writer of the package."""
    safe = table.rename(columns=csv_safe)
    if _write_floats(safe, path, float_format):
        return
    text = [name for name, kind in safe.dtypes.items() if getattr(kind, "kind", "") == "O"]
    if text:
        safe = safe.assign(**{str(name): safe[name].map(csv_safe) for name in text})
    safe.to_csv(path, index=False, float_format=float_format)


#: The NumPy integer kinds :func:`_write_floats` writes with ``%d``, as pandas writes them.
_INTEGER_KINDS = frozenset(f"{sign}int{bits}" for sign in ("", "u") for bits in (8, 16, 32, 64))


def _write_floats(table: Any, path: Path, float_format: str | None) -> bool:
    """Write ``table`` as pandas' ``to_csv(path, index=False, float_format=float_format)``
    writes it, byte for byte, when its columns hold finite 64-bit floats and integers of any
    width only (the time series of ``simulate``, whose contact flags are 8-bit: a fifth of
    its run without plots went to pandas formatting each value in Python); one ``%`` per row
    here. Returns False, writing nothing, for any other table."""
    import csv
    import io

    import numpy as np

    columns = list(table.columns)
    kinds = [str(kind) for kind in table.dtypes]
    if (
        float_format is None
        or not columns
        or getattr(table.columns, "nlevels", 1) != 1
        or any(kind != "float64" and kind not in _INTEGER_KINDS for kind in kinds)
    ):
        return False
    values = [table.iloc[:, k].to_numpy() for k in range(len(columns))]
    if not all(np.isfinite(column).all() for column in values):
        return False
    header = io.StringIO()
    csv.writer(header, lineterminator=os.linesep).writerow(columns)
    row = ",".join(float_format if kind == "float64" else "%d" for kind in kinds) + os.linesep
    with open(path, "w", encoding="utf-8", newline="") as stream:
        stream.write(header.getvalue())
        stream.writelines(row % line for line in zip(*(c.tolist() for c in values), strict=True))
    return True


#: Significant digits of every number in a JSON document. Twelve keep far more than any
#: computed quantity means (the integrator's tolerance is 1e-6 relative, measurements carry
#: 3–4 digits) while a value such as 200 rpm → rad/s → rpm, computed as
#: 199.99999999999997, is written as 200.0. Doubles carry 15–17 digits; the last 3–5 are
#: round-off from unit conversions and sums.
JSON_DIGITS = 12


def round_significant(value: float, digits: int = JSON_DIGITS) -> float:
    """``value`` rounded to ``digits`` significant digits (finite values; others unchanged).

    Exact for every value that has at most ``digits`` significant digits (0.1, 200.0, 1e-6
    stay what they are), and idempotent.
    """
    if value == 0.0 or not math.isfinite(value):
        return value
    return float(f"{value:.{digits}g}")


def jsonable(value: Any) -> Any:
    """``value`` as plain JSON data: NumPy scalars and arrays become Python numbers and lists,
    tuples become lists, paths strings, NaN or inf become ``None`` (JSON null), and floats
    are rounded to :data:`JSON_DIGITS` significant digits (:func:`round_significant`).

    The one JSON sanitiser of the package: every JSON file and JSON document goes
    through it.
    """
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
    np = sys.modules.get("numpy")  # no NumPy value exists before NumPy is imported
    if np is None:
        if isinstance(value, bool):
            return value
        if isinstance(value, float):
            return round_significant(value) if math.isfinite(value) else None
        return str(value) if isinstance(value, Path) else value
    if isinstance(value, np.ndarray):
        return [jsonable(v) for v in value.tolist()]
    if isinstance(value, bool | np.bool_):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, float | np.floating):
        value = float(value)
        return round_significant(value) if math.isfinite(value) else None
    if isinstance(value, Path):
        return str(value)
    return value


def json_text(data: Any) -> str:
    """``data`` as indented JSON text (through :func:`jsonable`, so never NaN or inf)."""
    return json.dumps(jsonable(data), indent=2, ensure_ascii=False, allow_nan=False)


def write_json(path: Path, data: Any) -> None:
    """Write ``data`` as indented JSON (NumPy scalars converted, NaN/inf written as null)."""
    path.write_text(json_text(data) + "\n", encoding="utf-8")
