"""The population life's files and report (:mod:`jointplay.study.life`): lives.csv,
histories.csv, summary.json, the Weibull probability plot, the wear profiles of the median
and the B10 mechanism, and report.html whose first screen is the answer ("B10 = … h [… h] at
90 %; … fails first in … %").

The probability plot is drawn on Weibull paper: x = ln t, y = ln(−ln(1 − F)), where a
Weibull is a straight line of slope β. The points are the failures at their median ranks
(Benard, :func:`jointplay.study.weibull.median_ranks`; exact since every censoring time is
the same and follows every failure), the lives censored at the hours one grey ▷ on the
censoring line with their count (right-censored: no rank of their own), the line the
censored maximum-likelihood fit, the band its pointwise 90 % likelihood-ratio interval of
the quantiles.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from jointplay.io.output import write_csv, write_json
from jointplay.report._mpl import pyplot
from jointplay.report.figures import encode
from jointplay.report.html import HtmlReport
from jointplay.study.life_result import HOUR, QUANTILES, LifeResult, hours_text
from jointplay.study.weibull import median_ranks

__all__ = ["life_plots", "life_section", "probability_figure", "profiles_figure", "write_life"]

#: Probabilities at which the plot's band is drawn.
BAND_P = (0.001, 0.003, 0.01, 0.03, 0.1, 0.2, 0.3, 0.5, 0.7, 0.9, 0.99)
#: The probability axis's labelled ticks, %.
TICKS = (0.1, 1, 5, 10, 20, 50, 63.2, 90, 99)


def _weibull_y(p: Any) -> Any:
    return np.log(-np.log1p(-np.asarray(p, dtype=float)))


def probability_figure(result: LifeResult) -> Any:
    """The lives on Weibull probability paper (module docstring); ``None`` without a
    failure."""
    failures, positions = median_ranks(result.lives.life, result.lives.censored)
    keep = failures > 0
    failures, positions = failures[keep], positions[keep]
    if not len(failures):
        return None
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 5))
    fit = result.weibull
    hours = result.lives.hours / HOUR
    if fit is not None:
        p = np.array(BAND_P)
        ends = np.array([fit.quantile_interval(q) for q in p]) / HOUR
        centre = np.array([fit.quantile(q) for q in p]) / HOUR
        ax.plot(np.log(centre), _weibull_y(p), c="tab:blue", label=_fit_label(result))
        low, high = ends[:, 0], ends[:, 1]
        finite = np.isfinite(high) & (low > 0)
        ax.fill_betweenx(
            _weibull_y(p)[finite],
            np.log(low[finite]),
            np.log(high[finite]),
            color="tab:blue",
            alpha=0.15,
            label="90 % likelihood-ratio band",
        )
    ax.plot(
        np.log(failures / HOUR),
        _weibull_y(positions),
        "o",
        ms=4,
        c="k",
        label=f"failures at median ranks ({len(failures)} of {result.n})",
    )
    censored = int(np.sum(result.lives.censored))
    if censored:  # right-censored: no rank of their own, they shift the failures' ranks
        ax.plot(
            [math.log(hours)],
            [_weibull_y(positions.max())],
            ">",
            ms=7,
            c="grey",
            label=f"{censored} right-censored at {hours_text(result.lives.hours)}",
        )
    ax.axvline(math.log(hours), c="grey", ls=":", lw=1)
    ax.text(math.log(hours), _weibull_y(0.002), " censored here", color="grey", fontsize=8)
    ticks = [t for t in TICKS]
    ax.set_yticks(_weibull_y(np.array(ticks) / 100.0))
    ax.set_yticklabels([f"{t:g}" for t in ticks])
    ax.set_ylim(_weibull_y(0.001), _weibull_y(0.995))
    xt = _hour_ticks(float(failures.min()) / HOUR, hours)
    ax.set_xticks(np.log(xt))
    ax.set_xticklabels([f"{t:g}" for t in xt])
    ax.set_xlabel("life (h, log scale)")
    ax.set_ylabel("share failed (%, Weibull scale)")
    ax.grid(True, lw=0.3)
    ax.legend(fontsize=8, loc="upper left")
    ax.set_title("population life on Weibull paper")
    return fig


def _fit_label(result: LifeResult) -> str:
    fit = result.weibull
    assert fit is not None
    return f"Weibull fit: β {fit.shape:.3g}, η {hours_text(fit.scale)}"


def _hour_ticks(low: float, high: float) -> list[float]:
    out = []
    for decade in range(math.floor(math.log10(max(low, 1e-3))) - 1, math.ceil(math.log10(high))):
        for m in (1, 2, 5):
            value = m * 10.0**decade
            if low / 3 <= value <= high * 1.5:
                out.append(value)
    return out or [low, high]


def profiles_figure(result: LifeResult) -> Any:
    """Each joint's radial clearance over the hours of the median (B50) and the B10
    mechanism, one panel per joint."""
    plt = pyplot()
    joints = result.lives.joints
    fig, axes = plt.subplots(1, len(joints), figsize=(3.4 * len(joints), 3.4), sharey=False)
    chosen = {"B10 mechanism": result.representative(0.10), "median mechanism": 0}
    chosen["median mechanism"] = result.representative(0.50)
    for ax, (j, joint) in zip(np.atleast_1d(axes), enumerate(joints), strict=True):
        for (label, index), style in zip(chosen.items(), ("-o", "--s"), strict=True):
            history = result.lives.history[index]
            t = [h[0] / HOUR for h in history]
            c = [h[1][j] * 1e6 for h in history]
            ax.plot(t, c, style, ms=3, label=f"{label} (#{index})")
        limit = result.settings.get("clearance_limit_m", {}).get(joint)
        if limit is not None:
            ax.axhline(limit * 1e6, c="grey", ls=":", lw=1)
        ax.set_title(f"joint {joint}", fontsize=9)
        ax.set_xlabel("hours")
    np.atleast_1d(axes)[0].set_ylabel("radial clearance (µm)")
    np.atleast_1d(axes)[0].legend(fontsize=7)
    fig.tight_layout()
    return fig


def life_plots(result: LifeResult, figure_format: str = "png") -> dict[str, bytes]:
    """The plots by file name."""
    images: dict[str, bytes] = {}
    figure = probability_figure(result)
    if figure is not None:
        images.update(encode(figure, "life_probability", figure_format, dpi=110))
    if result.n:
        images.update(encode(profiles_figure(result), "life_profiles", figure_format, dpi=110))
    return images


def life_section(report: HtmlReport, result: LifeResult, images: Mapping[str, bytes]) -> None:
    """The population life's sections: the answer first, then the evidence."""
    report.heading("Answer", anchor="answer")
    report.paragraph(result.headline())
    for line in result.lines():
        report.paragraph(line)
    if "life_probability.png" in images:
        report.figure(
            images["life_probability.png"],
            "The lives on Weibull paper: failures at their median ranks (Benard; exact with "
            "every censoring at the same hours), the censored maximum-likelihood Weibull "
            "fit and its pointwise 90 % likelihood-ratio band (Meeker & Escobar §8.3).",
        )
    report.heading("Quantiles", anchor="quantiles")
    rows = []
    fit = result.weibull
    for name, q in result.quantiles.items():
        p = QUANTILES[name]
        weibull = fit.quantile(p) / HOUR if fit is not None else math.nan
        low, high = fit.quantile_interval(p) if fit is not None else (math.nan, math.nan)
        rows.append(
            (name, q.value / HOUR, q.low / HOUR, q.high / HOUR, weibull, low / HOUR, high / HOUR)
        )
    report.table(
        rows,
        headers=[
            "quantile",
            "empirical (h)",
            "90 % low (h)",
            "90 % high (h)",
            "Weibull (h)",
            "90 % low (h)",
            "90 % high (h)",
        ],
        note="Empirical: the order statistic with its exact binomial interval (∞: beyond the "
        "hours simulated). Weibull: the censored fit with likelihood-ratio intervals.",
    )
    if "life_profiles.png" in images:
        report.heading("Wear profiles", anchor="profiles")
        report.figure(
            images["life_profiles.png"],
            "Each joint's radial clearance over the hours of the B10 and the median mechanism "
            "(dotted: the clearance limit).",
        )
    report.heading("How it was computed", anchor="method")
    settings = result.settings
    report.definitions(
        {
            "scheme": str(settings.get("scheme", "")),
            "criteria": "; ".join(result.criteria),
            "update rule": str(settings.get("update_rule", "")),
            "samples": f"{result.n} ({settings.get('stopped_by', '')})",
        }
    )


def write_life(
    result: LifeResult,
    folder: Path,
    *,
    plots: bool = True,
    provenance: Mapping[str, Any] | None = None,
    figure_format: str = "png",
) -> list[Path]:
    """Write the population life's files into ``folder`` (existing); returns them."""
    folder = Path(folder)
    written = [folder / "lives.csv", folder / "histories.csv", folder / "summary.json"]
    write_csv(result.table(), written[0], float_format=None)
    write_csv(result.histories(), written[1], float_format=None)
    summary = result.summary()
    if provenance is not None:
        summary["provenance"] = dict(provenance)
    write_json(written[2], summary)
    images = life_plots(result, figure_format) if plots else {}
    for name, data in images.items():
        (folder / name).write_bytes(data)
        written.append(folder / name)
    report = HtmlReport(
        f"jointplay life — {result.settings.get('scheme', '')}", contents_before="quantiles"
    )
    life_section(report, result, images)
    written.append(report.write(folder / "report.html"))
    return written
