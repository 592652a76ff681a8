"""Every figure a report saves, checked for overlapping text: shared by
``tests/report/conftest.py``'s ``text_overlaps`` fixture and the session's reduced paper run
(``tests/conftest.py``)."""

from __future__ import annotations

import importlib
from typing import Any

import pytest

#: The report modules that save figures, with the name they call the saver by.
SAVERS = {
    "jointplay.report.calibration": "save",
    "jointplay.report.overlays": "save",
    "jointplay.report.paper_figures": "save",
    "jointplay.report.plots": "save",
    "jointplay.report.running": "save",
    "jointplay.report.design": "encode",
    "jointplay.report.tolerance_plots": "encode",
}


def record_text_overlaps(monkeypatch: pytest.MonkeyPatch) -> dict[str, list[Any]]:
    """Until ``monkeypatch`` is undone: every figure saved, by file name (stem), with the
    pairs of its texts that overlap (:func:`jointplay.report.figures.overlapping_text`)."""
    from jointplay.report import figures

    seen: dict[str, list[Any]] = {}
    for module_name, attribute in SAVERS.items():
        module = importlib.import_module(module_name)
        original = getattr(figures, attribute)

        def checked(fig: Any, path: Any, *args: Any, _original: Any = original, **kw: Any) -> Any:
            seen[str(getattr(path, "stem", path))] = figures.overlapping_text(fig)
            return _original(fig, path, *args, **kw)

        monkeypatch.setattr(module, attribute, checked)
    return seen
