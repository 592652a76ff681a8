"""The paper study's answers as data: ``results.json`` and the claims' verdicts.

No HTML here: :func:`results_document` is the JSON document written beside the page,
:func:`claim_verdict` and :func:`claim_counts` say which of the paper's claims hold (within
:data:`AGREEMENT_PCT`), and the start-up-versus-running comparison says, per method, why the
peaks from rest differ from those of the running mechanism. The page
(:mod:`jointplay.report.paper`) reports the same numbers; ``jointplay.report.paper`` stays the
import path.
"""

from __future__ import annotations

import json
import math
from collections.abc import Sequence
from typing import Any

import pandas as pd

from jointplay.report.format import number, percent
from jointplay.report.paper_figures import (
    QUANTITIES,
    axis_label,
)
from jointplay.study.claims import Claim
from jointplay.study.paper import (
    PEAK_KEYS,
    PaperStudy,
    geometry_figures,
    worst_corners,
)

PAPER = (
    'C. A. Akhadkar, A. B. Deoghare, A. M. Vaidya, "Simulation and experimental response of '
    'four-bar mechanism with tolerance stack"'
)


#: A claim "holds" when our value lies within this relative difference of the paper's, %.
AGREEMENT_PCT = 10.0


#: Column headers of the peak quantities (symbol and unit).
LABELS = {key: axis_label(key) for key in QUANTITIES}


PEAK_DEFINITION = (
    "Peak: the largest |value| over the analysed crank revolution(s), located on the continuous "
    "solution between integrator steps (not on an output grid)."
)


INCREASE_DEFINITION = (
    "Increase: (peak − nominal peak) / nominal peak × 100, where the nominal peak is that of "
    "the ideal-joint mechanism with the same crank speed, running steadily."
)


def _records(table: pd.DataFrame) -> list[dict[str, Any]]:
    return json.loads(table.to_json(orient="records"))


def _rows(table: pd.DataFrame) -> list[Any]:
    """The rows of ``table`` as objects with one attribute per column."""
    from types import SimpleNamespace

    return [
        SimpleNamespace(**{str(k): v for k, v in row.items()})
        for row in table.to_dict(orient="records")
    ]


def results_document(
    study: PaperStudy, claims: list[Claim], provenance: dict[str, Any]
) -> dict[str, Any]:
    """Every number of the report's tables, JSON-ready."""
    methods = {}
    for key, outcome in study.outcomes.items():
        summary = outcome.summary or {}
        methods[key] = {
            "method": outcome.task.method,
            "ecs_source": outcome.task.ecs_source,
            "description": outcome.task.label,
            "lengths_m": dict(outcome.task.lengths),
            "error": outcome.error,
            "peaks": summary.get("peaks") if outcome.ok else None,
            "increase_percent": summary.get("increase_percent") if outcome.ok else None,
            "start": outcome.task.start,
            "settle_revolutions": outcome.task.settle,
            "startup_peaks": outcome.startup_peaks,
            "sampled_peaks": outcome.sampled_peaks,
            "solver": summary.get("solver") if outcome.ok else None,
            "clearance_joints": summary.get("clearance_joints") if outcome.ok else None,
            "diagnostics": summary.get("diagnostics") if outcome.ok else None,
            "wall_s": outcome.wall_s,
        }
    return {
        "paper": PAPER,
        "definitions": {
            "peak": PEAK_DEFINITION,
            "increase_percent": INCREASE_DEFINITION,
            "startup_peaks": f"largest |value| in the first {study.options.startup_deg:g}° of "
            "crank after the start from rest",
            "sampled_peaks": "the same run's peak seen every 0.5° of crank (an output grid, as "
            "a post-processor's curve shows it)",
            "ecs_source": "paper: K, δ, D as printed in the paper's Tables 4 and 5; computed: "
            "our estimate from eqs. 9-13 with the conventions in ecs.conventions",
        },
        "start_up_vs_running": _start_up_vs_running(study),
        "options": {k: getattr(study.options, k) for k in study.options.__dataclass_fields__},
        "mechanism": geometry_figures(study.mechanism),
        "nominal_peaks": study.nominal_peaks,
        "ecs": study.ecs,
        "ecs_sweep": _records(study.ecs_sweep.paper_units_table()),
        "simulations": methods,
        "length_cases": _records(study.length_cases),
        "worst_corners": _records(
            worst_corners(study.length_cases, study.options.tolerance_method)
        ),
        "sensitivities": _records(study.sensitivities),
        "experiment": None if study.experiment is None else study.experiment.as_dict(),
        "table7_explained": study.extra.get("table7_explained"),
        "claims": [{**c.as_dict(), "verdict": claim_verdict(c)} for c in claims],
        "wall_s": study.wall_s,
        "provenance": provenance,
    }


def claim_verdict(claim: Claim) -> str:
    """``"holds"`` (within :data:`AGREEMENT_PCT` of the paper's value), ``"differs"``, or
    ``"no paper value"``."""
    difference = claim.difference_pct
    if not math.isfinite(difference):
        return "no paper value" if not math.isfinite(claim.paper) else "not computed"
    return "holds" if abs(difference) <= AGREEMENT_PCT else "differs"


def _difference(claim: Claim) -> str:
    """Ours against the paper's: in points for a claim in %, else in % of the paper's value."""
    if claim.unit == "%":
        if not (math.isfinite(claim.paper) and math.isfinite(claim.ours)):
            return "—"
        return f"{number(claim.ours - claim.paper, 3, signed=True)} points"
    return percent(claim.difference_pct)


def claim_counts(claims: Sequence[Claim]) -> dict[str, list[Claim]]:
    """The claims by verdict (:func:`claim_verdict`), in the order holds, differs, no paper
    value, not computed; every claim is in exactly one list."""
    counts: dict[str, list[Claim]] = {
        v: [] for v in ("holds", "differs", "no paper value", "not computed")
    }
    for claim in claims:
        counts[claim_verdict(claim)].append(claim)
    return counts


def _start_up_vs_running(study: PaperStudy) -> dict[str, Any]:
    """Per method: peaks from rest (the paper's setting) and running steadily, with the
    nominal ones, and the sentence that says why they differ; JSON-ready."""
    out: dict[str, Any] = {}
    for key, running in study.outcomes.items():
        if not key.startswith("steady/"):
            continue
        _, method, source = key.split("/")
        start_up = study.outcomes.get(f"method/{method}/{source}")
        out[f"{method}/{source}"] = {
            quantity: {
                "from_rest": None
                if start_up is None or not start_up.ok
                else start_up.peak(quantity),
                "running": None if not running.ok else running.peak(quantity),
                "nominal": study.nominal_peaks[quantity],
            }
            for quantity in PEAK_KEYS
        }
    return {"why": _why(study, out), "methods": out}


def _why(study: PaperStudy, methods: dict[str, Any]) -> str:
    """One sentence on why the paper's start-up peaks and the running ones differ, with the
    ranges this study found (rocker speed above the ideal joints', largest joint force as a
    multiple of the ideal one)."""

    def spread(setting: str) -> tuple[float, float, float, float]:
        speed, force = [], []
        for values in methods.values():
            if values["omega4"][setting] is None:
                continue
            speed.append(100 * (values["omega4"][setting] / values["omega4"]["nominal"] - 1))
            force.append(
                max(
                    values[q][setting] / values[q]["nominal"]
                    for q in PEAK_KEYS
                    if q.startswith("F_")
                )
            )
        if not speed:
            return (math.nan,) * 4
        return min(speed), max(speed), min(force), max(force)

    rest, running = spread("from_rest"), spread("running")
    return (
        "The paper starts every simulation from rest with the pins centred, so the crank is "
        "jerked to full speed at t = 0 and the pins strike their bearings: its first-revolution "
        f"peaks are that start-up impact (rocker speed {rest[0]:.0f}–{rest[1]:.0f} % above the "
        f"ideal joints', joint forces {rest[2]:,.0f}–{rest[3]:,.0f} times theirs). Started on "
        f"the nominal motion and left {_settle(study)} revolutions to settle, the same methods "
        f"run with the rocker speed {running[0]:.1f}–{running[1]:.1f} % above the ideal and "
        f"joint forces {running[2]:.3g}–{running[3]:,.0f} times the ideal ones: what the "
        "contact law does to the running mechanism, the stiffest ECS contacts still rattling."
    )


def _settle(study: PaperStudy) -> int:
    return next((o.task.settle for k, o in study.outcomes.items() if k.startswith("steady/")), 0)
