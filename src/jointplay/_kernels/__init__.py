"""The compiled numerical kernels (Numba), and whether a compiled copy of them is cached.

Numba compiles each kernel on first use and keeps the machine code in an on-disk cache
(``cache=True``): the first dynamic run after an install or an upgrade spends one to two
minutes compiling (2-core machine; each lane inlines the whole lane source), later runs load
the cache in about a second.
:func:`compiled_cache_present` tells the command line which of the two is about to happen,
so that it can say so; it reads only file names (no Numba import). Each command asks about the
kernels it runs: the single engine's (:func:`single_engine`, ``simulate``, ``paper``, ...)
or the batch lanes' (:data:`BATCH_LANES`, the dynamic responses of ``tolerance`` and
``design``); a warm cache of the one says nothing about the other.

Numba judges a cached kernel fresh by its own file's time stamp and size alone, but the
kernels inline functions from other files (the lane source is compiled into the single
engine's hooks and the lanes' drivers): after an edit of ``lanes/source.py`` alone, a cached
hook of ``eom.py`` would still load, and run the old equations without a word. Importing this
package therefore compares a digest of every kernel source with the one stamped beside each
cache folder and, when they differ, deletes that folder's cached kernels
(:func:`drop_stale_caches`); an installed release never sees this (an install writes every
file anew), a working tree after an edit, a ``git checkout`` or a merge does.
"""

from __future__ import annotations

import hashlib
import os
import sys
from collections.abc import Sequence
from pathlib import Path

#: The cached kernel that says the batch engine's lanes are compiled (its index file's stem):
#: the drivers' ``_alive``, which every batch driver calls (either method, serial or on
#: threads) and nothing else does. The lanes' other kernels share their modules' names with
#: the single engine's (``source``, ``source_radau``: the traced lanes), so a cache warm for
#: ``simulate`` alone holds them too. (It named ``radau`` and ``eom``, which no batch run
#: compiles: every warm ``tolerance`` and ``design`` run said it was compiling.) A cache of
#: one method's drivers passes for the other's, which then compiles without the notice.
BATCH_LANES = ("cpu._alive",)
#: Kept for callers of the name: the batch lanes' modules.
FIRST_COMPILED = BATCH_LANES


def single_engine(*integrators: str | None) -> tuple[str, ...]:
    """The kernels one simulation of the single engine
    (:func:`jointplay.dynamics.simulate.simulate`) compiles with each of ``integrators``
    (``None``: the default, Radau), by the stems of their cache files: the equations' cold
    callers (``eom``: the diagnostics) and each integrator's traced lane
    (:data:`jointplay._kernels.lanes.cpu.traced`)."""
    chosen = [f"cpu._traced_{name or 'radau'}" for name in integrators or (None,)]
    return tuple(dict.fromkeys(("eom", *chosen)))


#: The stamp beside a cache folder's kernels: the digest of the sources they were compiled from.
SOURCES_STAMP = "jointplay-kernel-sources.txt"


def sources_digest(root: Path | None = None) -> str:
    """A digest of every ``*.py`` file under ``root`` (default: this package), names and
    bytes, in a fixed order: any edit of any kernel source changes it."""
    root = Path(__file__).parent if root is None else root
    digest = hashlib.blake2b(digest_size=16)
    for path in sorted(root.rglob("*.py")):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()


def _user_wide_cache() -> Path:
    """Numba's user-wide cache folder (its ``AppDirs("numba").user_cache_dir`` on Linux)."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "numba"


def _numba_folder(root: Path, source_folder: Path) -> Path:
    """The cache folder Numba's user-wide and user-provided locators give the sources of
    ``source_folder`` under ``root`` (``numba.core.caching``'s ``get_suitable_cache_subpath``:
    the folder's name and the SHA-1 of its absolute path)."""
    path = str(source_folder.absolute())
    return root / f"{source_folder.name}_{hashlib.sha1(path.encode()).hexdigest()}"


def drop_stale_caches(folders: Sequence[tuple[Path, bool]], digest: str) -> list[Path]:
    """Delete the cached kernels (``*.nbi``, ``*.nbc``) of every folder whose stamp
    (:data:`SOURCES_STAMP`) is not ``digest`` (or is missing: a cache of unknown sources),
    then stamp it; returns the folders cleared.

    Args:
        folders: ``(folder, first)`` pairs, ``first`` where Numba will write the kernels it
            compiles: such a folder is created if missing and stamped at once, so that what
            Numba caches there later is known to be of these sources. A missing folder that
            is not ``first`` is skipped, one that cannot be written is left as it is.
        digest: :func:`sources_digest` of the sources the process runs.
    """
    cleared = []
    for folder, first in folders:
        stamp = folder / SOURCES_STAMP
        try:
            if first:
                folder.mkdir(parents=True, exist_ok=True)
            if not folder.is_dir() or stamp.read_text() == digest:
                continue
        except OSError:
            if not folder.is_dir():
                continue  # not creatable here: Numba cannot cache in it either
        try:
            for cached in [*folder.glob("*.nbi"), *folder.glob("*.nbc")]:
                cached.unlink(missing_ok=True)
            partial = folder / f".{SOURCES_STAMP}.{os.getpid()}"
            partial.write_text(digest)
            partial.replace(stamp)
        except OSError:
            continue
        cleared.append(folder)
    return cleared


def _source_folders() -> list[Path]:
    """This package's folder and its sub-packages' (each may hold cached kernels)."""
    here = Path(__file__).parent
    return [here, *(path for path in sorted(here.iterdir()) if (path / "__init__.py").is_file())]


def kernel_cache_folders() -> list[tuple[Path, bool]]:
    """Every folder that may hold this package's cached kernels, each with whether Numba
    writes there first (:func:`drop_stale_caches`): the folders of ``NUMBA_CACHE_DIR`` when it
    is set, else ``__pycache__`` beside each source folder where that can be written, else the
    user-wide cache's folder (Numba's locators, in their order); the others are checked too,
    for kernels cached there before."""
    user_wide = _user_wide_cache()
    provided = os.environ.get("NUMBA_CACHE_DIR")
    folders = []
    for source in _source_folders():
        in_tree = not provided and os.access(source, os.W_OK)
        if provided:
            folders.append((_numba_folder(Path(provided), source), True))
        folders.append((source / "__pycache__", in_tree))
        folders.append((_numba_folder(user_wide, source), not provided and not in_tree))
    return folders


def cache_folders() -> list[Path]:
    """Where Numba keeps the kernels' cache: ``NUMBA_CACHE_DIR`` when set, else
    ``__pycache__`` beside the sources (this package's and its sub-packages'), or the user-wide
    cache where that is read-only."""
    custom = os.environ.get("NUMBA_CACHE_DIR")
    if custom:
        return [Path(custom)]
    return [*(folder / "__pycache__" for folder in _source_folders()), _user_wide_cache()]


def compiled_cache_present(modules: Sequence[str] = BATCH_LANES) -> bool:
    """Whether every kernel module of ``modules`` (:func:`single_engine`,
    :data:`BATCH_LANES`) has a cache index for this Python
    (``<module>.<function>-<line>.py<XY>.nbi``; a module may name its function too). A cache
    made from other kernel sources does not count: importing this package has dropped it
    (:func:`drop_stale_caches`)."""
    tag = f"py{sys.version_info.major}{sys.version_info.minor}"
    folders = [folder for folder in cache_folders() if folder.is_dir()]
    return all(
        any(next(folder.rglob(f"{module}[.-]*.{tag}.nbi"), None) for folder in folders)
        for module in modules
    )


drop_stale_caches(kernel_cache_folders(), sources_digest())
