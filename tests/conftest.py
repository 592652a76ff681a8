"""Shared fixtures: the paper's mechanism and small helpers."""

from __future__ import annotations

import pytest

from jointplay.io.config import load_preset
from jointplay.model.mechanism import Mechanism


@pytest.fixture(scope="session")
def paper_fourbar() -> Mechanism:
    return load_preset("paper-fourbar")


@pytest.fixture(scope="session")
def slider_crank() -> Mechanism:
    return load_preset("flores-slider-crank")


def pytest_addoption(parser: pytest.Parser, pluginmanager: pytest.PytestPluginManager) -> None:
    """Accept pyproject's ``-n auto --dist worksteal`` when pytest-xdist is absent or blocked
    (``-p no:xdist``): the tests then run serially, as with ``-n 0``."""
    if pluginmanager.has_plugin("xdist"):
        return
    group = parser.getgroup("xdist-absent", "without pytest-xdist (the tests run serially)")
    # pytest reserves lowercase short options for plugins; pytest-xdist registers its own "-n"
    # through the same private call
    group._addoption("-n", "--numprocesses", dest="numprocesses", default=None, help="ignored")
    group.addoption("--dist", dest="dist", default="no", help="ignored")
