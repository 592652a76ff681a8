"""The paper study's report: one self-contained HTML page, results.json and the figures.

Only consumes a :class:`~jointplay.study.paper.PaperStudy`; no physics here. The first screen
answers: how many of the paper's claims hold and which, which do not and why, and the running
mechanism's numbers (rocker speed, joint forces, penetration flagged where it goes beyond the
clearance, error against the measurements) in one small table, then the measured and simulated
rocker speed. The peaks from rest, the paper's setting, come further down as what they are:
start-up impacts. Supporting tables and figures are folded (``<details>``) so the page stays
short; every figure is a palette PNG, so the page stays small. The page has a table of
contents; every table has headers in words with units and numbers
in the one format of :mod:`jointplay.report.format`; every response is defined where it is
reported; every figure is a PNG embedded in the page (and SVG or PDF beside it on request).

The page is assembled here (:func:`write_paper_report`) from its parts:
:mod:`~jointplay.report.paper_results` (``results.json`` and the claims' verdicts, as data),
:mod:`~jointplay.report.paper_summary` (the first screen and the claims),
:mod:`~jointplay.report.paper_sections` (the mechanism, ECS, the six methods),
:mod:`~jointplay.report.paper_checks` (nominal vs actual, the experiment, the solver) and
:mod:`~jointplay.report.paper_figures`; ``jointplay.report.paper`` stays their import path.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

from jointplay.io.output import write_json
from jointplay.report.figures import check_format
from jointplay.report.html import HtmlReport
from jointplay.report.paper_checks import (
    _experiment_section,
    _solver_section,
    _tolerance_section,
)
from jointplay.report.paper_results import (
    AGREEMENT_PCT,
    INCREASE_DEFINITION,
    LABELS,
    PAPER,
    PEAK_DEFINITION,
    claim_counts,
    claim_verdict,
    results_document,
)
from jointplay.report.paper_sections import (
    _ecs_section,
    _mechanism_section,
    _methods_section,
)
from jointplay.report.paper_summary import (
    _claims_section,
    _Page,
    _summary_section,
)
from jointplay.study.claims import paper_claims
from jointplay.study.paper import PaperStudy

__all__ = [
    "AGREEMENT_PCT",
    "INCREASE_DEFINITION",
    "LABELS",
    "PAPER",
    "PEAK_DEFINITION",
    "claim_counts",
    "claim_verdict",
    "results_document",
    "write_paper_report",
]


def write_paper_report(
    study: PaperStudy,
    folder: Path,
    provenance: dict[str, Any],
    *,
    figure_format: str = "png",
) -> dict[str, Any]:
    """Write ``report.html``, ``results.json`` and ``figures/*.png`` into ``folder``.

    Args:
        study: the study to report.
        folder: the output folder (exists).
        provenance: version, command line and settings, written into both files.
        figure_format: ``"png"`` (embedded), or ``"svg"``/``"pdf"``: every figure also
            written in that format beside its PNG and linked from the page.

    Returns:
        The ``results.json`` document.
    """
    check_format(figure_format)
    wall = time.perf_counter()
    figures = folder / "figures"
    figures.mkdir(exist_ok=True)
    claims = paper_claims(study)
    results = results_document(study, claims, provenance)
    write_json(folder / "results.json", results)
    page = _Page(
        HtmlReport(
            "jointplay: the four-bar with tolerance stack of Akhadkar et al., reproduced",
            contents_before="claims",  # the summary fills the first screen
        ),
        folder,
        figure_format,
    )
    _summary_section(page, study, claims)
    _claims_section(page, claims)
    _mechanism_section(page, study)
    _ecs_section(page, study)
    _methods_section(page, study)
    _tolerance_section(page, study)
    _experiment_section(page, study)
    _solver_section(page, study, provenance, time.perf_counter() - wall)
    page.report.write(folder / "report.html")
    return results
