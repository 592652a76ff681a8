"""``tests/_precompile.py``, which ``tests/conftest.py`` runs on pytest-xdist's controller when
Numba's cache is cold: its two groups must hold every kernel that importing ``eom`` compiles
and every traced lane (one left out is compiled by every worker again), each once."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from _precompile import GROUPS, KERNELS

SCRIPT = Path(__file__).with_name("_precompile.py")


def test_the_groups_are_disjoint_and_hold_every_first_compiled_kernel(tmp_path: Path) -> None:
    held = subprocess.run(
        [sys.executable, str(SCRIPT), "--list"],
        env={**os.environ, "NUMBA_CACHE_DIR": str(tmp_path)},
        capture_output=True, text=True, check=True, timeout=120,
    ).stdout.split()  # fmt: skip
    names = [name for group in GROUPS for name in group]
    assert len(GROUPS) == 2 and all(GROUPS)
    assert len(names) == len(set(names))  # disjoint
    assert sorted(names) == sorted(held) == sorted(KERNELS)
    assert not list(tmp_path.rglob("*.nbi"))  # listing compiled nothing
