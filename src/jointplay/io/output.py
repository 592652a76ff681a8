"""Writing a command's results all-or-nothing.

A command prepares its output folder before it computes anything (:func:`output_dir`): a
fresh temporary folder beside the target, so that an unwritable ``--out`` is reported at
once. Everything is written there; only when the command succeeds does the temporary folder
replace the target, by renames (old → trash, staging → target, trash removed). A failed or
interrupted run leaves the target as it was: the previous complete result, or nothing. Every
result folder carries a marker file (:data:`MARKER`); an existing non-empty folder without
one is not a jointplay result and is refused unless ``force``.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import tempfile
import uuid
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from jointplay.errors import ConfigError

#: Name of the marker file that every result folder written by jointplay carries.
MARKER = ".jointplay-result.json"


def _check_target(target: Path | str, force: bool) -> Path:
    """``target`` as a path that may be replaced, or a ConfigError saying why not."""
    text = str(target)
    if text.strip() in ("", "."):
        raise ConfigError(f"--out {text!r} names the current folder; give a folder to write into")
    path = Path(text)
    try:
        resolved = path.resolve()
        here = Path.cwd().resolve()
    except (OSError, RuntimeError) as exc:
        raise ConfigError(f"--out {text!r} cannot be resolved: {exc}") from None
    if resolved == here or resolved in here.parents or resolved.parent == resolved:
        raise ConfigError(
            f"--out {text!r} is the current folder or one above it; give a folder to write into"
        )
    if path.is_symlink() or (path.exists() and not path.is_dir()):
        raise ConfigError(f"--out {text!r} exists and is not a folder")
    if path.is_dir() and not force:
        try:
            entries = [entry.name for entry in path.iterdir()]
        except OSError as exc:
            raise ConfigError(f"--out {text!r} cannot be read: {exc.strerror}") from None
        if entries and MARKER not in entries:
            raise ConfigError(
                f"--out {text!r} is a non-empty folder that jointplay did not write; "
                "give a new folder, or --force to replace it"
            )
    return path


@contextmanager
def output_dir(target: Path | str, *, force: bool = False) -> Iterator[Path]:
    """Yield a fresh temporary folder beside ``target``; on normal exit it replaces ``target``.

    Enter it before computing: the checks (a usable ``target``, a writable parent) come
    first, so bad output paths are reported before any work. On an exception (including
    KeyboardInterrupt) the temporary folder is removed and ``target`` is left as it was.

    Args:
        target: the output folder (``--out``).
        force: replace an existing non-empty folder even if jointplay did not write it.

    Raises:
        ConfigError: ``target`` cannot be used or its parent is not writable.
    """
    path = _check_target(target, force)
    parent = path.absolute().parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=f".{path.name}.partial-", dir=parent))
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise ConfigError(f"cannot write the output folder {str(target)!r}: {reason}") from None
    try:
        yield staging
        (staging / MARKER).write_text(
            json.dumps({"written_by": "jointplay"}) + "\n", encoding="utf-8"
        )
        with _signals_held():
            _publish(staging, path)
    finally:
        with _signals_held():
            shutil.rmtree(staging, ignore_errors=True)


@contextmanager
def _signals_held() -> Iterator[None]:
    """Hold SIGINT and SIGTERM back (delivered on exit), so that the renames and the clean-up
    are never cut in half."""
    if not hasattr(signal, "pthread_sigmask"):  # pragma: no cover - not POSIX
        yield
        return
    previous = signal.pthread_sigmask(signal.SIG_BLOCK, {signal.SIGINT, signal.SIGTERM})
    try:
        yield
    finally:
        signal.pthread_sigmask(signal.SIG_SETMASK, previous)


def _publish(staging: Path, target: Path) -> None:
    """Put ``staging`` in the place of ``target`` by renames (all or nothing)."""
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(staging, 0o777 & ~umask)
    if not target.exists():
        staging.rename(target)
        return
    trash = target.absolute().parent / f".{target.name}.old-{uuid.uuid4().hex[:8]}"
    target.rename(trash)
    try:
        staging.rename(target)
    except BaseException:
        trash.rename(target)
        raise
    shutil.rmtree(trash, ignore_errors=True)


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

    The one JSON sanitiser of the package: every JSON file and ``--json`` document goes
    through it.
    """
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [jsonable(v) for v in value]
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
