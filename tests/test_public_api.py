"""The public API at the top of the package: every advertised name resolves, lazily."""

from __future__ import annotations

import subprocess
import sys

import pytest

import jointplay


@pytest.mark.parametrize("name", jointplay.__all__)
def test_every_public_name_resolves(name: str) -> None:
    assert getattr(jointplay, name) is not None
    assert name in dir(jointplay)


def test_unknown_name_is_an_attribute_error() -> None:
    with pytest.raises(AttributeError, match="no attribute 'no_such_thing'"):
        _ = jointplay.no_such_thing  # type: ignore[attr-defined]


def test_top_level_names_are_the_defining_objects() -> None:
    from jointplay.dynamics.simulate import simulate
    from jointplay.io.config import load_preset

    assert jointplay.simulate is simulate
    assert jointplay.load_preset is load_preset


def test_importing_the_package_loads_no_heavy_library() -> None:
    code = (
        "import sys, jointplay; "
        "print(','.join(m for m in ('numpy', 'scipy', 'numba', 'pandas', 'dask', 'matplotlib')"
        " if m in sys.modules))"
    )
    loaded = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout.strip()
    assert loaded == ""


def test_all_lists_exactly_the_lazy_names_and_the_errors() -> None:
    errors = {"AssemblyError", "ConfigError", "IntegrationError", "JointplayError"}
    expected = {*jointplay._LAZY, *errors, "StandardsError", "__version__"}
    assert set(jointplay.__all__) == expected
