"""The shared ids, slots, statuses and counters have one home, :mod:`jointplay._kernels.ids`:
no kernel module assigns one of its names itself (each imports it), so the dialects cannot
drift apart. Read from the modules' syntax trees (issue 38: "no copies")."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

import jointplay._kernels
from jointplay._kernels import ids

KERNELS = Path(jointplay._kernels.__file__).parent


def _assigned_names(path: Path) -> set[str]:
    """Upper-case names a module assigns at its top level."""
    names: set[str] = set()
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        targets = node.targets if isinstance(node, ast.Assign) else (
            [node.target] if isinstance(node, ast.AnnAssign) else []
        )  # fmt: skip
        for target in targets:
            for leaf in ast.walk(target):
                if isinstance(leaf, ast.Name) and leaf.id.isupper():
                    names.add(leaf.id)
    return names


SHARED = _assigned_names(Path(ids.__file__))


def test_the_home_holds_the_shared_names() -> None:
    assert {"LAW_IMPACT", "G_FILM", "G_CAPTURE", "S_ONSET_TOL", "STATUS_INTERRUPTED",
            "K_STEPS", "NUM_JAC_MAX_FACTOR", "LAW_STEP"} <= SHARED  # fmt: skip


@pytest.mark.parametrize(
    "path",
    sorted(p for p in KERNELS.rglob("*.py") if p.name != "ids.py"),
    ids=lambda p: str(p.relative_to(KERNELS)),
)
def test_no_kernel_module_copies_a_shared_name(path: Path) -> None:
    copies = _assigned_names(path) & SHARED
    assert not copies, f"{path.name} defines {sorted(copies)}: import them from _kernels.ids"
