"""Whether the compiled kernels are cached: what the command line says before compiling."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import pytest

from jointplay._kernels import (
    FIRST_COMPILED,
    SOURCES_STAMP,
    compiled_cache_present,
    drop_stale_caches,
    sources_digest,
)

TAG = f"py{sys.version_info.major}{sys.version_info.minor}"


def test_an_empty_cache_means_the_kernels_are_compiled_now(tmp_path, monkeypatch) -> None:
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    assert not compiled_cache_present()


def test_index_files_of_every_first_kernel_mean_a_cached_copy(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path))
    folder = tmp_path / "some" / "source" / "path"  # Numba mirrors the source's path
    folder.mkdir(parents=True)
    for module in FIRST_COMPILED[:-1]:
        (folder / f"{module}._kernel-12.{TAG}.nbi").touch()
    assert not compiled_cache_present()  # one module still missing
    (folder / f"{FIRST_COMPILED[-1]}._kernel-40.{TAG}.nbi").touch()
    assert compiled_cache_present()
    (folder / f"{FIRST_COMPILED[-1]}._kernel-40.{TAG}.nbi").rename(
        folder / f"{FIRST_COMPILED[-1]}._kernel-40.py27.nbi"
    )
    assert not compiled_cache_present()  # another Python's cache is not this one's


# --- stale caches: Numba judges a kernel by its own file only; the kernels inline other files'


def _cached(folder: Path, stamp: str | None) -> list[Path]:
    folder.mkdir(parents=True, exist_ok=True)
    files = [folder / f"eom.rhs-293.{TAG}.nbi", folder / f"eom.rhs-293.{TAG}.1.nbc"]
    for path in files:
        path.write_bytes(b"machine code")
    if stamp is not None:
        (folder / SOURCES_STAMP).write_text(stamp)
    return files


def test_caches_of_other_sources_are_dropped_and_those_of_these_kept(tmp_path: Path) -> None:
    stale = _cached(tmp_path / "stale", "an older digest")
    fresh = _cached(tmp_path / "fresh", "now")
    unknown = _cached(tmp_path / "unstamped", None)
    cleared = drop_stale_caches(
        [(tmp_path / "stale", False), (tmp_path / "fresh", False), (tmp_path / "unstamped", True)],
        "now",
    )
    assert cleared == [tmp_path / "stale", tmp_path / "unstamped"]
    assert not any(path.exists() for path in stale + unknown)
    assert all(path.exists() for path in fresh)
    for name in ("stale", "fresh", "unstamped"):
        assert (tmp_path / name / SOURCES_STAMP).read_text() == "now"
    assert drop_stale_caches([(tmp_path / "stale", False)], "now") == []  # stamped: kept now


def test_the_folder_numba_writes_first_is_stamped_before_it_caches(tmp_path: Path) -> None:
    """A fresh tree: the kernels Numba caches after this import must not count as unknown
    (and be dropped) at the next one."""
    first, other = tmp_path / "first" / "__pycache__", tmp_path / "other"
    assert drop_stale_caches([(first, True), (other, False)], "now") == [first]
    assert (first / SOURCES_STAMP).read_text() == "now" and not other.exists()
    compiled = _cached(first, None)  # Numba compiles and caches
    assert drop_stale_caches([(first, True), (other, False)], "now") == []
    assert all(path.exists() for path in compiled)


def test_any_edit_of_any_kernel_source_changes_the_digest(tmp_path: Path) -> None:
    (tmp_path / "lanes").mkdir()
    (tmp_path / "eom.py").write_text("def rhs(): return 1\n")
    (tmp_path / "lanes" / "source.py").write_text("def force(): return 2.0\n")
    before = sources_digest(tmp_path)
    assert sources_digest(tmp_path) == before
    (tmp_path / "lanes" / "source.py").write_text("def force(): return 2.5\n")
    edited = sources_digest(tmp_path)
    assert edited != before
    (tmp_path / "lanes" / "source.py").rename(tmp_path / "lanes" / "other.py")
    assert sources_digest(tmp_path) != edited


def test_importing_the_kernels_drops_a_cache_of_older_sources(tmp_path: Path) -> None:
    """The scenario that ran old equations silently: an edit of the lane source alone left
    the single engine's cached hooks (``eom.py``'s, which inline it) loading as fresh."""
    import subprocess

    import jointplay._kernels as kernels

    here = Path(kernels.__file__).parent
    folder = kernels._numba_folder(tmp_path, here)
    stale = _cached(folder, "the digest before lanes/source.py was edited")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)}
    subprocess.run([sys.executable, "-c", "import jointplay._kernels"], env=env, check=True)
    assert not any(path.exists() for path in stale)
    assert (folder / SOURCES_STAMP).read_text() == sources_digest()
