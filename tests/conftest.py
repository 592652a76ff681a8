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
