"""The design study's result: :class:`DesignResult` (the table of schemes, the verdicts, the
answer and its summary) and its plausibility findings over the samples
(part of :mod:`jointplay.study.design`, which re-exports them)."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from jointplay.errors import name_settings
from jointplay.model.mechanism import Mechanism
from jointplay.study.design_schemes import Callout, Scheme
from jointplay.study.requirements import Requirement
from jointplay.tolerance.analysis import (
    ConvergenceCheck,
    StudyDiagnostic,
    penetration_warning,
)
from jointplay.tolerance.definitions import response_definitions
from jointplay.tolerance.execution import OK, STATUS
from jointplay.tolerance.response_base import REGIME_CHECKS, regime_fractions
from jointplay.tolerance.responses import (
    ELASTIC_RATIO,
    PENETRATION_RATIO,
)

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class DesignDiagnostic(StudyDiagnostic):
    """A plausibility finding over the samples of every finished scheme.

    The fields of :class:`~jointplay.tolerance.analysis.StudyDiagnostic` count over all
    schemes together (``count`` samples concerned of ``out_of`` successful ones;
    ``worst_sample`` is the ``sample`` column of ``samples.parquet`` *within*
    ``worst_scheme``; ``worst_inputs`` SI); in addition:

    Attributes:
        schemes: finished schemes with at least one sample concerned.
        out_of_schemes: finished schemes.
        worst_scheme: label of the scheme of the worst sample.
        best: the recommended scheme (:attr:`DesignResult.best`), or ``None``.
        best_count: samples of the recommended scheme concerned (0 when none is, or when
            there is no recommended scheme).
        best_out_of: successful samples of the recommended scheme (0 without one).
    """

    schemes: int
    out_of_schemes: int
    worst_scheme: str
    best: str | None
    best_count: int
    best_out_of: int

    @property
    def best_concerned(self) -> bool:
        """The recommended scheme has samples concerned."""
        return self.best_count > 0

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: :meth:`StudyDiagnostic.as_dict` plus ``schemes``, ``out_of_schemes``,
        ``worst_scheme``, ``best``, ``best_concerned``, ``best_count`` and ``best_out_of``."""
        return {
            **super().as_dict(),
            "schemes": self.schemes,
            "out_of_schemes": self.out_of_schemes,
            "worst_scheme": self.worst_scheme,
            "best": self.best,
            "best_concerned": self.best_concerned,
            "best_count": self.best_count,
            "best_out_of": self.best_out_of,
        }


def _penetration_columns(check_names: Sequence[str]) -> dict[str, str]:
    """Joint → its penetration-ratio check (``penetration_ratio_<joint>``) among ``check_names``."""
    return {
        name.removeprefix(PENETRATION_RATIO): name
        for name in check_names
        if name.startswith(PENETRATION_RATIO)
    }


def _scheme_penetration(
    check_names: Sequence[str], checks: FloatArray, ok: NDArray[np.bool_]
) -> dict[str, Any]:
    """A scheme's row entries of the penetration checks, per clearance joint:
    ``penetration_exceeds_<joint>`` (successful samples whose ratio passes 1) and
    ``penetration_ratio_max_<joint>`` (the largest ratio of its successful samples,
    dimensionless; NaN when none succeeded).

    Args:
        check_names: the model's checks.
        checks: (n, c) their values per sample (NaN where a sample failed).
        ok: (n,) which samples succeeded.
    """
    row: dict[str, Any] = {}
    for joint, name in _penetration_columns(check_names).items():
        ratio = checks[ok, list(check_names).index(name)]
        ratio = ratio[np.isfinite(ratio)]
        row[f"penetration_exceeds_{joint}"] = int(np.sum(ratio > 1.0))
        row[f"penetration_ratio_max_{joint}"] = float(ratio.max()) if len(ratio) else math.nan
    return row


def _scheme_regimes(
    check_names: Sequence[str], checks: FloatArray, ok: NDArray[np.bool_]
) -> dict[str, Any]:
    """A scheme's row entries of its lubricated joints' regimes (dynamic studies with a
    film), per joint: ``full_film_mean_<joint>``, ``mixed_mean_<joint>``,
    ``boundary_mean_<joint>`` (the mean fractions of the analysed time in each regime over
    its successful samples) and ``left_full_film_<joint>`` (how many of them ever left full
    film; :func:`~jointplay.tolerance.response_base.regime_fractions`)."""
    row: dict[str, Any] = {}
    for joint, entry in regime_fractions(check_names, checks, ok).items():
        for regime in REGIME_CHECKS:
            mean = entry[f"{regime}_mean"]
            row[f"{regime}_mean_{joint}"] = math.nan if mean is None else mean
        row[f"left_full_film_{joint}"] = entry["left_full_film"]
    return row


def regime_rows(row: Mapping[str, Any]) -> list[list[Any]]:
    """The regime table of one scheme's row (:func:`_scheme_regimes`): per lubricated
    joint, its mean fractions in full film, mixed and boundary lubrication (%) and the
    samples that ever left full film (of the successful ones)."""
    joints = [
        str(k).removeprefix("left_full_film_") for k in row if str(k).startswith("left_full_film_")
    ]
    return [
        [
            joint,
            *(100.0 * row[f"{regime}_mean_{joint}"] for regime in REGIME_CHECKS),
            f"{int(row[f'left_full_film_{joint}'])} of {int(row['ok'])}",
        ]
        for joint in joints
    ]


def penetration_diagnostics(
    samples: pd.DataFrame,
    check_names: Sequence[str],
    input_names: Sequence[str],
    best: str | None,
) -> tuple[DesignDiagnostic, ...]:
    """One ``penetration-exceeds-clearance`` warning per clearance joint whose pin, in some
    successful samples of some scheme, sinks deeper into its bearing than the radial
    clearance (``penetration_ratio_<joint>`` > 1), and one ``penetration-exceeds-elastic``
    per joint whose pin sinks deeper than ``ELASTIC_FACTOR`` times its Hertz approach
    (``elastic_ratio_<joint>``, :mod:`jointplay.dynamics.diagnostics`).

    The tolerance study's :func:`~jointplay.tolerance.analysis.penetration_findings` judges
    the samples of one study; this counts them over the schemes, names the worst sample's
    scheme and says whether the recommended one is concerned.

    Args:
        samples: one row per sample (:attr:`DesignResult.samples`): ``scheme``, ``sample``,
            the inputs, the checks, ``status``.
        check_names: the model's checks (none: no warning).
        input_names: the inputs, SI.
        best: the recommended scheme, or ``None``.
    """
    from jointplay.dynamics.diagnostics import ELASTIC_FACTOR, Diagnostic

    kinds = [(joint, name, 1.0) for joint, name in _penetration_columns(check_names).items()] + [
        (name.removeprefix(ELASTIC_RATIO), name, ELASTIC_FACTOR)
        for name in check_names
        if name.startswith(ELASTIC_RATIO)
    ]
    if not kinds or not len(samples):
        return ()
    ok = (samples["status"] == STATUS[OK]).to_numpy()
    scheme = samples["scheme"].to_numpy()
    labels = list(dict.fromkeys(scheme))
    out_of = int(ok.sum())
    findings = []
    for joint, name, limit in kinds:
        ratio = np.where(ok, samples[name].to_numpy(dtype=float), np.nan)
        exceeds = ratio > limit  # NaN compares False
        count = int(exceeds.sum())
        if count == 0:
            continue
        per_scheme = {label: int(exceeds[scheme == label].sum()) for label in labels}
        concerned = sum(1 for n in per_scheme.values() if n)
        worst = int(np.argmax(np.where(exceeds, ratio, -np.inf)))
        worst_scheme = str(scheme[worst])
        worst_sample = int(samples["sample"].iloc[worst])
        best_count = per_scheme.get(best, 0) if best is not None else 0
        best_out_of = int(ok[scheme == best].sum()) if best is not None else 0
        if best is None:
            verdict = ""
        elif best_count:
            verdict = (
                f"; the recommended scheme {best} is concerned ({best_count} of its "
                f"{best_out_of} samples): its yield cannot be trusted"
            )
        else:
            verdict = (
                f"; the recommended scheme {best} is not concerned, but the schemes it was "
                "chosen over were judged on these samples"
            )
        what = (
            "the radial clearance"
            if limit == 1.0
            else "the elastic approach of the joint's own Hertz law at its peak force"
        )
        per_scheme_column = (
            f", penetration_exceeds_{joint} per scheme in design.parquet" if limit == 1.0 else ""
        )
        message = (
            f"{count} of {out_of} samples ({100.0 * count / out_of:.3g} %) in {concerned} of "
            f"{len(labels)} schemes: the pin of {joint} penetrates its bearing by up to "
            f"{ratio[worst]:.3g} times {what} (scheme {worst_scheme}, sample "
            f"{worst_sample}; {name} in samples.parquet{per_scheme_column}); those samples' "
            f"responses are not physical{verdict}; the contact stiffness is far too low for "
            "the load: use a stiffness from the joints' geometry (the default contact, or "
            "a stiffness law)"
        )
        diagnostic = (
            penetration_warning(joint, float(ratio[worst]), message)
            if limit == 1.0
            else Diagnostic(
                "warning", "penetration-exceeds-elastic", joint, float(ratio[worst]), limit,
                message,
            )
        )  # fmt: skip
        findings.append(
            DesignDiagnostic(
                diagnostic,
                count=count,
                out_of=out_of,
                worst_sample=worst_sample,
                worst_inputs={n: float(samples[n].iloc[worst]) for n in input_names},
                schemes=concerned,
                out_of_schemes=len(labels),
                worst_scheme=worst_scheme,
                best=best,
                best_count=best_count,
                best_out_of=best_out_of,
            )
        )
    return tuple(findings)


# --- the study -------------------------------------------------------------------------------


@dataclass(frozen=True)
class DesignResult:
    """A finished (or interrupted) design study.

    Attributes:
        mechanism: the nominal mechanism.
        responses: ``"kinematic"`` or ``"dynamic"``.
        requirements: the requirements.
        confidence: the study's confidence level (fraction).
        table: one row per finished scheme (:meth:`to_dataframe`); dynamic studies add
            ``penetration_exceeds_<joint>`` and ``penetration_ratio_max_<joint>`` per
            clearance joint.
        samples: one row per sample of the finished schemes: scheme, the features as made
            (``hole_<joint>``, ``pin_<joint>`` diameters), the model's inputs (lengths,
            clearances), responses, dynamic studies' ``penetration_ratio_<joint>``
            (dimensionless; above 1: not physical), status.
        best: label of the cheapest scheme shown to meet every requirement (verdict
            ``meets``: the lower bound of each yield's exact 95 % interval at or above the
            confidence level), or ``None`` (always for an interrupted study: a choice among
            some of the schemes is no choice).
        binding: when none is: the requirement whose best observed yield is lowest
            (``None`` for an interrupted study).
        interrupted: Ctrl-C stopped the run; only finished schemes are in ``table``.
        settings: samples, seed, model description, cost model, clearance limits.
        diagnostics: plausibility warnings over the samples of the finished schemes
            (:func:`penetration_diagnostics`, then the ``peaks-not-converged`` warning of
            :attr:`convergence`); empty when every sample is physical and converged, and for
            kinematic studies.
        convergence: dynamic studies: the integrator's share of the responses' scatter
            (:func:`~jointplay.tolerance.analysis.convergence_finding`, over the first
            round's samples; ``None`` when not checked).
        candidates: every scheme of the study (finished or not).
    """

    mechanism: Mechanism
    responses: str
    requirements: tuple[Requirement, ...]
    confidence: float
    table: pd.DataFrame = field(repr=False)
    samples: pd.DataFrame = field(repr=False)
    best: str | None
    binding: str | None
    interrupted: bool
    settings: Mapping[str, Any] = field(default_factory=dict)
    diagnostics: tuple[StudyDiagnostic, ...] = ()
    convergence: ConvergenceCheck | None = None
    candidates: tuple[Scheme, ...] = ()

    def to_dataframe(self) -> pd.DataFrame:
        """One row per scheme (the content of ``design.parquet``)."""
        return self.table.copy()

    @property
    def best_row(self) -> Mapping[str, Any] | None:
        if self.best is None:
            return None
        row = self.table[self.table["scheme"] == self.best].iloc[0]
        return {str(k): _plain(v) for k, v in row.items()}

    @property
    def drawing(self) -> tuple[Callout, ...]:
        """The drawing callouts of the answer (none without one)."""
        for scheme in self.candidates:
            if scheme.label == self.best:
                return scheme.callouts(self.mechanism)
        return ()

    @property
    def undecided(self) -> pd.DataFrame:
        """The undecided schemes cheaper than the answer (all of them without one), by cost."""
        if not len(self.table):
            return self.table
        rows = self.table[self.table["verdict"] == "undecided"]
        if self.best is not None:
            rows = rows[rows["cost"] < self.best_row["cost"]]  # type: ignore[index]
        return rows.sort_values("cost")

    @property
    def to_decide(self) -> str | None:
        """What would decide the undecided schemes that could change the answer, or ``None``."""
        return self.what_decides()

    def what_decides(self, names: Mapping[str, str] | None = None) -> str | None:
        """:attr:`to_decide`, the settings it advises on called by ``names`` (setting →
        name, :func:`~jointplay.errors.name_settings`; the command line its options')."""
        rows = self.undecided
        if not len(rows):
            return None
        row = rows.iloc[0]
        m = row["samples_to_decide"]
        text = f"undecided: {row['scheme']} after {row['samples']:,} samples (" + (
            name_settings(
                f"about {int(m):,} would decide it at its observed defect rate: "
                f"{{max_samples}} {int(m)})",
                names,
            )
            if not pd.isna(m)
            else "its observed defect rate sits at the level: more samples may not decide it)"
        )
        if len(rows) > 1:
            text += f", and {len(rows) - 1} dearer undecided scheme(s)"
        return text

    @property
    def time_note(self) -> str | None:
        """What would decide the schemes a time budget stopped, or ``None``."""
        return self.what_times()

    def what_times(self, names: Mapping[str, str] | None = None) -> str | None:
        """:attr:`time_note`, the settings it advises on called by ``names`` (setting →
        name; the command line its options')."""
        settings = self.settings
        if not settings.get("stopped_at_max_time") or "stopped" not in self.table:
            return None
        budget = float(settings["max_time_s"])
        waiting = sum(1 for r in settings.get("not_run") or () if r.get("stopped") == "time")
        still = int((self.table["stopped"] == "time").sum()) + waiting
        text = f"stopped at the time budget ({duration(budget)}): {still} scheme(s) undecided"
        if waiting:
            text += f" ({waiting} not run yet)"
        rate = settings.get("samples_per_s")
        if still and rate:
            again = 2.0 * budget
            text += name_settings(
                "; {resume} with {max_time} {again} would allow ~{more:,.0f} more samples, "
                "the cheapest open scheme first (at the measured {rate:.3g} samples/s)",
                names,
                again=duration(again),
                more=rate * again,
                rate=rate,
            )
        return text

    @property
    def lubrication(self) -> str:
        """The joints' lubrication in words, as the dynamic model ran them (``lubricated,
        0.05 Pa*s oil``, ``dry``; empty for a kinematic design)."""
        model = self.settings.get("model", {})
        return str(model.get("lubrication_text", "")) if isinstance(model, Mapping) else ""

    @property
    def verdict(self) -> str:
        """The answer in one sentence; a dynamic design's says the joints' lubrication
        (``— lubricated, 0.05 Pa*s oil``, ``— dry``: :attr:`lubrication`)."""
        if self.interrupted:
            return (
                f"interrupted: {len(self.table)} of {self.settings.get('schemes', '?')} schemes "
                "with finished blocks; no recommendation from some of the schemes (resume the "
                "study: its samples are kept)"
            )
        regime = f" — {self.lubrication}" if self.lubrication else ""
        if self.best is not None:
            text = f"cheapest scheme shown to meet every requirement: {self.best}{regime}"
        elif not len(self.table):
            return "no finished scheme"
        elif (self.table["verdict"] == "fails").all():
            text = f"every scheme fails{regime}"
            if self.binding is not None:
                text += f"; binding requirement: {self.binding}"
            return text
        else:
            text = f"no scheme is shown to meet every requirement{regime}"
            if self.binding is not None:
                text += f"; binding requirement: {self.binding}"
        if self.to_decide is not None:
            text += f"; {'cheaper, ' if self.best is not None else ''}{self.to_decide}"
        return text

    def summary(self) -> dict[str, Any]:
        """The ``summary.json`` content (SI; yields and their intervals as fractions in
        ``schemes[].requirements[]``, as % in the flat scheme columns)."""
        return {
            "mechanism": self.mechanism.name,
            "responses_kind": self.responses,
            "confidence": self.confidence,
            "requirements": [r.describe() for r in self.requirements],
            "verdict": self.verdict,
            "best": self.best,
            "best_scheme": self.best_row,
            "drawing": [c.as_dict() for c in self.drawing],
            "binding": self.binding,
            "to_decide": self.to_decide,
            "time_note": self.time_note,
            "interrupted": self.interrupted,
            "settings": dict(self.settings),
            "response_definitions": response_definitions(self.reported_responses),
            "schemes": [self._record(row) for row in self.table.to_dict(orient="records")],
            "diagnostics": [finding.as_dict() for finding in self.diagnostics],
            "convergence_check": None if self.convergence is None else self.convergence.as_dict(),
        }

    def _record(self, row: Mapping[Any, Any]) -> dict[str, Any]:
        """A scheme's summary: its flat columns, the per-requirement ones gathered in
        ``requirements`` (fractions)."""
        own = {f"_{r.text}" for r in self.requirements}
        record = {
            str(k): _plain(v) for k, v in row.items() if not any(str(k).endswith(o) for o in own)
        }
        record["requirements"] = [
            {
                "requirement": r.text,
                "confidence": r.confidence if r.confidence is not None else self.confidence,
                "failures": _plain(row[f"failures_{r.text}"]),
                "samples": _plain(row["samples"]),
                "yield": row[f"yield_{r.text}"] / 100.0,
                "yield_ci95": [
                    row[f"yield_low_{r.text}"] / 100.0,
                    row[f"yield_high_{r.text}"] / 100.0,
                ],
                "dpm": row[f"dpm_{r.text}"],
                "dpm_ci95": [row[f"dpm_low_{r.text}"], row[f"dpm_high_{r.text}"]],
                "verdict": row[f"verdict_{r.text}"],
                # the interval the verdict was decided on (settings.verdict_interval)
                "verdict_interval": [
                    _fraction(row.get(f"verdict_low_{r.text}")),
                    _fraction(row.get(f"verdict_high_{r.text}")),
                ],
                "samples_to_decide": _plain(row[f"samples_to_decide_{r.text}"]),
            }
            for r in self.requirements
        ]
        return record

    @property
    def reported_responses(self) -> tuple[str, ...]:
        """The responses the scheme table reports: those the requirements name, in order."""
        names = [r.response for r in self.requirements]
        return tuple(dict.fromkeys(names))


def _fraction(percent: Any) -> float | None:
    """A table's percentage as a fraction (``None`` where missing)."""
    value = _plain(percent)
    return None if value is None else float(value) / 100.0


def duration(seconds: float) -> str:
    """A duration as a quantity the command line reads back: ``45 s``, ``20 min``, ``2 h``."""
    if seconds < 60.0:
        return f"{seconds:.3g} s"
    if seconds < 3600.0:
        return f"{seconds / 60.0:.3g} min"
    return f"{seconds / 3600.0:.3g} h"


def _plain(value: Any) -> Any:
    """A table cell as plain JSON-ready Python (missing → ``None``)."""
    if value is None or (not isinstance(value, str | bool) and pd.isna(value)):
        return None
    return value.item() if hasattr(value, "item") else value
