"""The compiled numerical kernels (Numba), and whether a compiled copy of them is cached.

Numba compiles each kernel on first use and keeps the machine code in an on-disk cache
(``cache=True``): the first dynamic run after an install or an upgrade spends one to two
minutes compiling (2-core machine; the single engine inlines the lane source into each of its
hooks), later runs load the cache in about a second.
:func:`compiled_cache_present` tells the command line which of the two is about to happen,
so that it can say so; it reads only file names (no Numba import). Each command asks about the
kernels it runs: the single engine's (:func:`single_engine`, ``simulate``, ``paper``, ...)
or the batch lanes' (:data:`BATCH_LANES`, the dynamic responses of ``tolerance`` and
``design``); a warm cache of the one says nothing about the other.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Sequence
from pathlib import Path

from jointplay._kernels.integrators import INTEGRATORS

#: The kernel modules the batch engine's lanes compile first (their index files name them):
#: ``lanes/source.py`` with the equations of motion and Radau's step control.
BATCH_LANES = ("radau", "eom", "source")
#: Kept for callers of the name: the batch lanes' modules.
FIRST_COMPILED = BATCH_LANES
#: The module of each integrator of the single engine (:mod:`jointplay.dynamics.integrate`).
INTEGRATOR_MODULES = {
    name: integrator.module for name, integrator in INTEGRATORS.items() if integrator.module
}


def single_engine(*integrators: str | None) -> tuple[str, ...]:
    """The kernel modules one simulation of the single engine
    (:func:`jointplay.dynamics.simulate.simulate`) compiles with each of ``integrators``
    (``None``: the default, Radau): the equations of motion, Radau's module (its step
    callbacks serve every integrator) and each integrator's own."""
    chosen = [INTEGRATOR_MODULES.get(name or "radau", "radau") for name in integrators or (None,)]
    return tuple(dict.fromkeys(("eom", "radau", *chosen)))


def cache_folders() -> list[Path]:
    """Where Numba keeps the kernels' cache: ``NUMBA_CACHE_DIR`` when set, else
    ``__pycache__`` beside the sources (this package's and ``lanes``'), or the user-wide cache
    where that is read-only."""
    custom = os.environ.get("NUMBA_CACHE_DIR")
    if custom:
        return [Path(custom)]
    here = Path(__file__).parent
    return [here / "__pycache__", here / "lanes" / "__pycache__", Path.home() / ".cache" / "numba"]


def compiled_cache_present(modules: Sequence[str] = BATCH_LANES) -> bool:
    """Whether every kernel module of ``modules`` (:func:`single_engine`,
    :data:`BATCH_LANES`) has a cache index for this Python
    (``<module>.<function>-<line>.py<XY>.nbi``). A cache made before the kernels were
    edited still counts: Numba then recompiles what changed, which this cannot see."""
    tag = f"py{sys.version_info.major}{sys.version_info.minor}"
    folders = [folder for folder in cache_folders() if folder.is_dir()]
    return all(
        any(next(folder.rglob(f"{module}.*.{tag}.nbi"), None) for folder in folders)
        for module in modules
    )
