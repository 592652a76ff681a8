"""Writing a command's results all-or-nothing.

A command writes into a fresh temporary folder beside the target; only when everything has
been written are the files moved into the target folder. A failure leaves the target as it
was, so no partial result is ever left behind.
"""

from __future__ import annotations

import json
import math
import shutil
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import numpy as np

from jointplay.errors import ConfigError


@contextmanager
def output_dir(target: Path | str) -> Iterator[Path]:
    """Yield a temporary folder; on normal exit move its contents into ``target``."""
    target = Path(target)
    if target.exists() and not target.is_dir():
        raise ConfigError(f"output folder {str(target)!r} exists and is not a folder")
    parent = target.absolute().parent
    try:
        parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ConfigError(f"cannot create output folder {str(target)!r}: {exc.strerror}") from None
    staging = Path(tempfile.mkdtemp(prefix=f".{target.name}.partial-", dir=parent))
    try:
        yield staging
        target.mkdir(exist_ok=True)
        for item in staging.iterdir():
            destination = target / item.name
            if destination.is_dir():
                shutil.rmtree(destination)
            item.replace(destination)
    finally:
        shutil.rmtree(staging, ignore_errors=True)


def jsonable(value: Any) -> Any:
    """``value`` as plain JSON data: NumPy scalars and arrays become Python numbers and lists,
    tuples become lists, paths strings, and NaN or inf become ``None`` (JSON null).

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
        return value if math.isfinite(value) else None
    if isinstance(value, Path):
        return str(value)
    return value


def json_text(data: Any) -> str:
    """``data`` as indented JSON text (through :func:`jsonable`, so never NaN or inf)."""
    return json.dumps(jsonable(data), indent=2, ensure_ascii=False, allow_nan=False)


def write_json(path: Path, data: Any) -> None:
    """Write ``data`` as indented JSON (NumPy scalars converted, NaN/inf written as null)."""
    path.write_text(json_text(data) + "\n", encoding="utf-8")
