"""The compiled numerical kernels (Numba), and whether a compiled copy of them is cached.

Numba compiles each kernel on first use and keeps the machine code in an on-disk cache
(``cache=True``): the first dynamic run after an install or an upgrade spends about 40 s
compiling (2-core machine, load 0.5-1), later runs load the cache in about a second.
:func:`compiled_cache_present` tells the command line which of the two is about to happen,
so that it can say so; it reads only file names (no Numba import).
"""

from __future__ import annotations

import os
import sys
from pathlib import Path

#: The kernel modules a dynamic run compiles first (their index files name them): the
#: batch engine's lanes (``lanes/source.py``) among them.
FIRST_COMPILED = ("radau", "eom", "source")


def cache_folders() -> list[Path]:
    """Where Numba keeps the kernels' cache: ``NUMBA_CACHE_DIR`` when set, else
    ``__pycache__`` beside the sources (this package's and ``lanes``'), or the user-wide cache
    where that is read-only."""
    custom = os.environ.get("NUMBA_CACHE_DIR")
    if custom:
        return [Path(custom)]
    here = Path(__file__).parent
    return [here / "__pycache__", here / "lanes" / "__pycache__", Path.home() / ".cache" / "numba"]


def compiled_cache_present() -> bool:
    """Whether every module of :data:`FIRST_COMPILED` has a cache index for this Python
    (``<module>.<function>-<line>.py<XY>.nbi``). A cache made before the kernels were
    edited still counts: Numba then recompiles what changed, which this cannot see."""
    tag = f"py{sys.version_info.major}{sys.version_info.minor}"
    folders = [folder for folder in cache_folders() if folder.is_dir()]
    return all(
        any(next(folder.rglob(f"{module}.*.{tag}.nbi"), None) for folder in folders)
        for module in FIRST_COMPILED
    )
