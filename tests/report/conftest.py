"""A fixture that checks every figure a report saves for overlapping text."""

from __future__ import annotations

from collections.abc import Iterator
from typing import Any

import pytest

from _figures import record_text_overlaps


@pytest.fixture
def text_overlaps(monkeypatch: pytest.MonkeyPatch) -> Iterator[dict[str, list[Any]]]:
    """Every figure saved while the test runs, by file name (stem), with the pairs of its
    texts that overlap (:func:`jointplay.report.figures.overlapping_text`)."""
    yield record_text_overlaps(monkeypatch)
