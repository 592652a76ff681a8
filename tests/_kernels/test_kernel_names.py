"""Each kernel function's name says which one it is (issue 38): a top-level function name is
defined in one kernel file only, JAX aside, but for the batch backends' shared entry point."""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

import jointplay._kernels

KERNELS = Path(jointplay._kernels.__file__).parent
#: The batch backends' contract: ``dynamics.batch`` calls every backend by this name.
CONTRACT = {"run_batch"}


def _defined_in() -> dict[str, list[str]]:
    files: dict[str, list[str]] = defaultdict(list)
    for path in sorted(KERNELS.rglob("*.py")):
        relative = path.relative_to(KERNELS)
        if "jax" in relative.parts or path.name == "jax_batch.py":
            continue
        for node in ast.parse(path.read_text(encoding="utf-8")).body:
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                files[node.name].append(relative.as_posix())
    return files


def test_no_kernel_function_name_is_defined_twice() -> None:
    shared = {name: where for name, where in _defined_in().items() if len(where) > 1}
    assert set(shared) <= CONTRACT, shared
