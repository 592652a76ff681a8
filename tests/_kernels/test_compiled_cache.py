"""Whether the compiled kernels are cached: what the command line says before compiling."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from jointplay._kernels import FIRST_COMPILED, compiled_cache_present

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
