"""The result of a population life (:mod:`jointplay.study.life`): each mechanism's functional
life, and what the population shows — the empirical B1, B10 and B50 with their exact
intervals, the Weibull fit with right-censoring and its likelihood-ratio intervals
(:mod:`jointplay.study.weibull`), the failing criteria's shares, and the first-screen answer.
Times are SI (s) inside; hours in the summary's ``*_h`` fields and the text.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from jointplay.study.weibull import (
    INTERVAL_LEVEL,
    EmpiricalQuantile,
    WeibullFit,
    empirical_quantile,
    fit_weibull,
)

__all__ = ["QUANTILES", "SIMULATION_FAILED", "LifeResult", "Lives", "hours_text", "quantile_text"]

FloatArray = NDArray[np.float64]

#: The failing criterion of a mechanism whose simulation failed (at its worn clearances).
SIMULATION_FAILED = "simulation failed"
#: The quantiles reported, by name.
QUANTILES: Mapping[str, float] = {"B1": 0.01, "B10": 0.10, "B50": 0.50}
HOUR = 3600.0


def hours_text(seconds: float) -> str:
    """``1 240 h`` (thin-space thousands, 3–4 significant digits), ``> 600 h`` never here."""
    if not math.isfinite(seconds):
        return "∞ h"
    value = seconds / HOUR
    if value >= 100:
        return f"{value:,.0f}".replace(",", " ") + " h"
    return f"{value:.3g} h"


@dataclass(frozen=True)
class Lives:
    """Each mechanism's functional life.

    Attributes:
        joints: the clearance joints, in the histories' order.
        life: (n,) the life, s (the censoring time where censored).
        censored: (n,) the mechanism met every criterion to the end.
        failing: (n,) the criterion that failed first (``""`` where censored).
        resimulations: (n,) simulations run for this mechanism (the first included).
        history: per mechanism, ``(time s, clearances m per joint)`` at each accepted step
            (and at the failure).
        hours: the time simulated, s.
        floor_steps: (n,) steps accepted at the smallest step with an estimate above the
            tolerance.
        worst_error: (n,) the largest local-error estimate accepted, as a share of its
            step's clearance growth.
    """

    joints: tuple[str, ...]
    life: FloatArray
    censored: NDArray[np.bool_]
    failing: tuple[str, ...]
    resimulations: NDArray[np.int64]
    history: tuple[tuple[tuple[float, tuple[float, ...]], ...], ...] = field(repr=False)
    hours: float
    floor_steps: NDArray[np.int64] | None = None
    worst_error: FloatArray | None = None

    @property
    def n(self) -> int:
        return len(self.life)

    @classmethod
    def concatenate(cls, parts: Sequence[Lives]) -> Lives:
        first = parts[0]
        return cls(
            first.joints,
            np.concatenate([p.life for p in parts]),
            np.concatenate([p.censored for p in parts]),
            tuple(f for p in parts for f in p.failing),
            np.concatenate([p.resimulations for p in parts]),
            tuple(h for p in parts for h in p.history),
            first.hours,
            np.concatenate([_or_zeros(p.floor_steps, p.n) for p in parts]).astype(np.int64),
            np.concatenate([_or_zeros(p.worst_error, p.n) for p in parts]),
        )


@dataclass(frozen=True)
class LifeResult:
    """A population life.

    Attributes:
        mechanism_name: the mechanism's name.
        criteria: every criterion's label, in order.
        input_names: the model's inputs (``clearance_<J>``, ``length_<link>``).
        feature_names: the features as made (``hole_<J>``, ``pin_<J>``, lengths).
        features, inputs: (n, ·) their values per mechanism, SI.
        lives: the lives.
        settings: how it was run (JSON-ready), the update rule stated.
    """

    mechanism_name: str
    criteria: tuple[str, ...]
    input_names: tuple[str, ...]
    feature_names: tuple[str, ...]
    features: FloatArray = field(repr=False)
    inputs: FloatArray = field(repr=False)
    lives: Lives = field(repr=False)
    settings: Mapping[str, Any] = field(default_factory=dict)

    @property
    def n(self) -> int:
        return self.lives.n

    @property
    def failures(self) -> int:
        return int((~self.lives.censored).sum())

    @property
    def at_start(self) -> int:
        """Mechanisms failing as made (life 0)."""
        return int(((self.lives.life <= 0) & ~self.lives.censored).sum())

    @cached_property
    def weibull(self) -> WeibullFit | None:
        """The Weibull fit of the positive lives (``None`` with fewer than two failures)."""
        positive = self.lives.life > 0
        return fit_weibull(self.lives.life[positive], self.lives.censored[positive])

    @cached_property
    def quantiles(self) -> dict[str, EmpiricalQuantile]:
        return {
            name: empirical_quantile(self.lives.life, self.lives.censored, p)
            for name, p in QUANTILES.items()
        }

    @cached_property
    def b10_interval(self) -> tuple[float, float] | None:
        fit = self.weibull
        return None if fit is None else fit.quantile_interval(0.10)

    @property
    def shares(self) -> dict[str, float]:
        """Each failing criterion's share of the failures (by count, largest first)."""
        counts = Counter(
            f for f, c in zip(self.lives.failing, self.lives.censored, strict=True) if not c
        )
        total = sum(counts.values())
        return {k: v / total for k, v in counts.most_common()} if total else {}

    @property
    def zero_failure_confidence(self) -> float:
        """With no failure: the confidence that B10 lies beyond the hours, ``1 − 0.9ⁿ`` (the
        chance that n mechanisms would all outlive it were B10 shorter)."""
        return 1.0 - 0.9**self.n

    def representative(self, p: float) -> int:
        """The index of the mechanism at the ``p`` quantile of the lives (order statistic
        ``⌈np⌉``; censored lives last)."""
        order = np.lexsort((self.lives.life, self.lives.censored))
        return int(order[max(math.ceil(self.n * p - 1e-12), 1) - 1])

    def headline(self) -> str:
        """The first-screen answer, one line."""
        hours = hours_text(self.lives.hours)
        fit = self.weibull
        level = f"{100 * INTERVAL_LEVEL:g} %"
        if self.failures == 0:
            return (
                f"no mechanism of {self.n} failed within {hours}: no Weibull fit from zero "
                f"failures; B10 > {hours} at {100 * self.zero_failure_confidence:.4g} % "
                "confidence (1 − 0.9^n)"
            )
        shares = self.shares
        top, share = next(iter(shares.items()))
        tail = f"{top} fails first in {100 * share:.0f} % of the {self.failures} failures"
        if fit is None:
            b10 = self.quantiles["B10"]
            return (
                f"B10 {quantile_text(b10, self.lives.hours)} (order statistic, too few failures for a "
                f"Weibull fit); {tail}"
            )
        low, high = self.b10_interval or (math.nan, math.nan)
        high_text = hours_text(high) if math.isfinite(high) else "∞ h"
        return (
            f"B10 = {hours_text(fit.quantile(0.10))} [{hours_text(low).removesuffix(' h')}–"
            f"{high_text}] at {level}; {tail}"
        )

    def lines(self) -> list[str]:
        """The terminal's lines after the headline: the fit, the empirical quantiles, the
        shares, the censoring and the cost."""
        out = []
        fit = self.weibull
        if fit is not None:
            s_low, s_high = fit.shape_interval
            e_low, e_high = fit.scale_interval
            out.append(
                f"Weibull (censored MLE, {100 * fit.level:g} % likelihood-ratio intervals): "
                f"shape {fit.shape:.3g} [{s_low:.3g}–{s_high:.3g}], scale "
                f"{hours_text(fit.scale)} [{hours_text(e_low).removesuffix(' h')}–"
                f"{hours_text(e_high)}]"
                + (f" ({self.at_start} lives of 0 h left out)" if self.at_start else "")
            )
        parts = [
            f"{name} {quantile_text(q, self.lives.hours)}" for name, q in self.quantiles.items()
        ]
        out.append(
            f"empirical ({100 * INTERVAL_LEVEL:g} % order-statistic intervals): " + "; ".join(parts)
        )
        if self.shares:
            out.append(
                "failing first: "
                + ", ".join(f"{k} {100 * v:.0f} %" for k, v in self.shares.items())
            )
        out.append(
            f"{self.n} mechanisms, {self.failures} failed and {self.n - self.failures} censored "
            f"at {hours_text(self.lives.hours)}; "
            f"{float(np.mean(self.lives.resimulations)):.1f} simulations per life"
        )
        floor = self.floor_note()
        if floor:
            out.append(floor)
        return out

    def floor_note(self) -> str:
        """One line when steps were accepted at the smallest step above the tolerance."""
        floor = _or_zeros(self.lives.floor_steps, self.n)
        if not floor.sum():
            return ""
        worst = float(np.max(_or_zeros(self.lives.worst_error, self.n)))
        return (
            f"{int((floor > 0).sum())} of {self.n} lives took {int(floor.sum())} steps at the "
            f"smallest step with a local-error estimate above the tolerance (largest "
            f"{100 * worst:.3g} % of a step's growth): the wear rate varies between "
            "re-simulations more than the tolerance; shorter --update-hours follow it closer"
        )

    def table(self) -> pd.DataFrame:
        """lives.csv: per mechanism the features as made, the model's inputs, the life (h),
        censored, the failing criterion and the simulations it took."""
        frame = pd.DataFrame(self.features, columns=list(self.feature_names))
        for c, name in enumerate(self.input_names):
            if name not in frame:
                frame[name] = self.inputs[:, c]
        frame.insert(0, "mechanism", np.arange(self.n))
        frame["life_h"] = self.lives.life / HOUR
        frame["censored"] = self.lives.censored
        frame["failing"] = list(self.lives.failing)
        frame["simulations"] = self.lives.resimulations
        frame["steps_at_smallest"] = _or_zeros(self.lives.floor_steps, self.n).astype(int)
        frame["largest_step_error"] = _or_zeros(self.lives.worst_error, self.n)
        return frame

    def histories(self, indices: Sequence[int] | None = None) -> pd.DataFrame:
        """The clearance histories (long form): mechanism, hours, ``clearance_<J>_um``."""
        rows = []
        chosen = range(self.n) if indices is None else indices
        for i in chosen:
            for time, values in self.lives.history[i]:
                rows.append(
                    {
                        "mechanism": i,
                        "hours": time / HOUR,
                        **{
                            f"clearance_{j}_um": v * 1e6
                            for j, v in zip(self.lives.joints, values, strict=True)
                        },
                    }
                )
        return pd.DataFrame(rows)

    def summary(self) -> dict[str, Any]:
        """summary.json: the headline, the fit, the quantiles, the shares, the settings."""
        fit = self.weibull
        return {
            "headline": self.headline(),
            "mechanisms": self.n,
            "failures": self.failures,
            "censored": self.n - self.failures,
            "failing_as_made": self.at_start,
            "hours_h": self.lives.hours / HOUR,
            "weibull": None if fit is None else fit.describe(HOUR, "_h"),
            "weibull_note": (
                None
                if fit is not None
                else "no Weibull fit: fewer than two failures"
                + (
                    f"; B10 > the hours at {100 * self.zero_failure_confidence:.4g} % confidence"
                    if self.failures == 0
                    else ""
                )
            ),
            "empirical_h": {
                name: {
                    **q.describe(),
                    **{
                        k: (None if v is None else v / HOUR)
                        for k, v in q.describe().items()
                        if k in ("value", "low", "high")
                    },
                }
                for name, q in self.quantiles.items()
            },
            "failing_share": self.shares,
            "simulations_per_life": float(np.mean(self.lives.resimulations)),
            "steps_at_smallest_step": int(_or_zeros(self.lives.floor_steps, self.n).sum()),
            "largest_accepted_step_error": float(
                np.max(_or_zeros(self.lives.worst_error, self.n), initial=0.0)
            ),
            "criteria": list(self.criteria),
            "settings": dict(self.settings),
        }


def _or_zeros(values: Any, n: int) -> Any:
    return np.zeros(n) if values is None else np.asarray(values)


def quantile_text(q: EmpiricalQuantile, hours: float) -> str:
    """A quantile's words after its name: ``"= 4.2 h [3.1–5.0 h]"``; one that the lives
    censored at ``hours`` (s) leave beyond them, ``"> 6 h [5.1–∞ h]"``; an interval the
    samples cannot bound at all says so rather than print ``[0–∞ h]``."""

    def end(v: float) -> str:
        return hours_text(v).removesuffix(" h") if math.isfinite(v) else "∞"

    value = f"= {hours_text(q.value)}" if math.isfinite(q.value) else f"> {hours_text(hours)}"
    if q.low <= 0.0 and not math.isfinite(q.high):
        return f"{value} [not bounded by {100 * q.level:g} % order statistics from these samples]"
    return f"{value} [{end(q.low)}–{end(q.high)} h]"
