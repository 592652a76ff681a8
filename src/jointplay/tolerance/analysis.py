"""The tolerance study of a mechanism: one call from the mechanism to the answer, and its files.

:func:`tolerance_study` picks the response model (kinematic: ideal joints, toleranced
lengths; dynamic: clearance joints, toleranced lengths and clearances), runs the method
(:mod:`jointplay.tolerance.methods`) on a backend (:mod:`jointplay.tolerance.execution`) and
returns a frozen :class:`ToleranceStudyResult`. :func:`write_study` writes

* ``samples.parquet`` — one row per evaluated point: ``sample``, ``role``, the inputs (SI),
  the responses (SI, NaN where the point failed), ``status`` (ok / failed / not run) and
  ``error``;
* ``summary.json`` — method, seed, inputs, statistics and contributions per response,
  failures with their inputs, settings, execution record and provenance (SI);
* ``tornado.png`` (contributions per response), and for Monte Carlo ``histograms.png``
  (with nominal, mean, ideal-joint value and spec limits marked) and ``scatter.png`` (the most
  influential input against each response);
* ``report.html`` — a self-contained page with the tables and the plots embedded.

Reports show lengths in mm, clearances in µm and angles in degrees; files stay SI.
"""

from __future__ import annotations

import base64
import html
import io
import math
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

import numpy as np
import pandas as pd

from jointplay.errors import ConfigError
from jointplay.model.mechanism import Mechanism
from jointplay.tolerance.execution import STATUS, Backend
from jointplay.tolerance.methods import (
    METHODS,
    Corners,
    Failure,
    MethodResult,
    ResponseSummary,
    SpecLimits,
    monte_carlo,
    rss,
    worst_case,
)
from jointplay.tolerance.responses import dynamic_model, kinematic_model
from jointplay.tolerance.sampling import SamplingMethod
from jointplay.tolerance.spec import JointTolerance, ToleranceSpec

__all__ = [
    "PAPER_IFM",
    "RESPONSE_KINDS",
    "ToleranceStudyResult",
    "build_model",
    "display_scale",
    "input_label",
    "response_units",
    "tolerance_study",
    "write_study",
]

ResponseKind = Literal["kinematic", "dynamic"]

#: Response kinds of :func:`tolerance_study`.
RESPONSE_KINDS: tuple[str, ...] = ("kinematic", "dynamic")

#: The paper's conventional IFM parameters (Table 3) in SI: k = 1e4 N/mm^1.5,
#: e = 1.5, c_max = 10 N·s/mm, d = 0.1 mm.
PAPER_IFM: Mapping[str, float] = {
    "stiffness": 1e4 * 1000.0**1.5,
    "exponent": 1.5,
    "c_max": 1e4,
    "d_max": 1e-4,
}

#: How many failures summary.json lists in full (samples.parquet has every one).
MAX_LISTED_FAILURES = 1000


@dataclass(frozen=True)
class ToleranceStudyResult:
    """A finished (or interrupted) tolerance study.

    Attributes:
        mechanism: the nominal mechanism.
        responses: ``"kinematic"``, ``"dynamic"`` or ``"custom"``.
        spec: the toleranced inputs actually varied.
        model: description of the response model and its settings.
        result: the method's points, responses, summaries and failures.
        ideal: dynamic studies: each response of the nominal mechanism with ideal joints.
    """

    mechanism: Mechanism
    responses: str
    spec: ToleranceSpec
    model: Mapping[str, Any]
    result: MethodResult
    ideal: Mapping[str, float] | None = None

    @property
    def method(self) -> str:
        return self.result.method

    @property
    def summaries(self) -> Mapping[str, ResponseSummary]:
        return self.result.summaries

    @property
    def failures(self) -> tuple[Failure, ...]:
        return self.result.failures

    @property
    def interrupted(self) -> bool:
        return self.result.interrupted

    @property
    def seed(self) -> int | None:
        seed = self.result.settings.get("seed")
        return None if seed is None else int(seed)

    def to_dataframe(self) -> pd.DataFrame:
        """One row per evaluated point (the content of ``samples.parquet``)."""
        r = self.result
        columns: dict[str, Any] = {
            "sample": np.arange(len(r.x), dtype=np.int64),
            "role": list(r.roles),
        }
        for i, name in enumerate(r.input_names):
            columns[name] = r.x[:, i]
        for j, name in enumerate(r.response_names):
            columns[name] = r.run.values[:, j]
        columns["status"] = [STATUS[int(s)] for s in r.run.status]
        columns["error"] = list(r.run.errors)
        return pd.DataFrame(columns)

    def summary(self) -> dict[str, Any]:
        """The ``summary.json`` content without provenance (SI)."""
        from jointplay.model.summary import mechanism_summary

        r = self.result
        responses = {}
        for name, item in r.summaries.items():
            entry = item.describe()
            if self.ideal is not None and name in self.ideal:
                entry["ideal_joints"] = self.ideal[name]
            responses[name] = entry
        status = r.run.status
        return {
            "mechanism": self.mechanism.name,
            "method": r.method,
            "responses_kind": self.responses,
            "seed": self.seed,
            "settings": dict(r.settings),
            "model": dict(self.model),
            "inputs": self.spec.describe(),
            "counts": {
                "points": len(status),
                "ok": int(np.sum(status == 0)),
                "failed": int(np.sum(status == 1)),
                "not_run": int(np.sum(status == 2)),
            },
            "interrupted": r.interrupted,
            "responses": responses,
            "most_influential": {name: s.most_influential for name, s in r.summaries.items()},
            "failures": [
                {"sample": f.index, "role": f.role, "inputs": dict(f.inputs), "error": f.error}
                for f in r.failures[:MAX_LISTED_FAILURES]
            ],
            "configuration": mechanism_summary(self.mechanism),
            "execution": r.run.describe(),
        }


def tolerance_study(
    mechanism: Mechanism,
    spec: ToleranceSpec | None = None,
    *,
    method: str = "monte-carlo",
    responses: ResponseKind = "kinematic",
    samples: int = 1000,
    seed: int = 0,
    sampling: SamplingMethod = "random",
    limits: Mapping[str, SpecLimits] | None = None,
    contact: Any = None,
    friction: Any = None,
    start: str = "rest",
    revolutions: float = 1.0,
    solver: Any = None,
    corners: Corners = "auto",
    fd_step: float = 0.5,
    sensitivity: Literal["finite-difference", "analytic"] = "finite-difference",
    backend: Backend | None = None,
    progress: bool = False,
    model: Any = None,
) -> ToleranceStudyResult:
    """Run a tolerance study of ``mechanism``.

    Args:
        mechanism: the nominal mechanism.
        spec: the toleranced inputs (default: :meth:`ToleranceSpec.from_mechanism`). Kinematic
            studies use its length inputs, dynamic studies lengths and clearances.
        method: ``"monte-carlo"``, ``"worst-case"`` or ``"rss"``.
        responses: ``"kinematic"`` (ideal joints) or ``"dynamic"`` (clearance joints).
        samples, seed, sampling: Monte Carlo settings (``sampling``: random or lhs).
        limits: specification limits per response name (SI).
        contact: dynamic: a contact law instance or name (default: the paper's conventional
            IFM, :data:`PAPER_IFM`).
        friction: dynamic: a friction law, or ``None``.
        start: dynamic: ``"rest"`` (the paper's) or ``"steady"``.
        revolutions: dynamic: simulated crank revolutions.
        solver: dynamic: :class:`~jointplay.dynamics.simulate.SolverOptions`.
        corners, fd_step, sensitivity: worst-case and RSS settings (see
            :mod:`jointplay.tolerance.methods`).
        backend: where the points run (default: local processes).
        progress: show a progress bar on stderr.
        model: a custom response model (overrides ``responses``); its inputs must be ``spec``'s.
    """
    if method not in METHODS:
        raise ConfigError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
    spec = spec if spec is not None else ToleranceSpec.from_mechanism(mechanism)
    ideal: dict[str, float] | None = None
    if model is not None:
        kind = "custom"
    else:
        kind = responses
        model, spec = build_model(
            mechanism,
            spec,
            responses,
            contact=contact,
            friction=friction,
            start=start,
            revolutions=revolutions,
            solver=solver,
        )
        if kind == "dynamic":
            ideal = _ideal_peaks(mechanism, model.peak_keys)
    if method == "monte-carlo":
        outcome = monte_carlo(
            model,
            spec,
            samples,
            seed,
            sampling=sampling,
            limits=limits,
            backend=backend,
            progress=progress,
        )
    elif method == "rss":
        outcome = rss(
            model,
            spec,
            fd_step=fd_step,
            sensitivity=sensitivity,
            limits=limits,
            backend=backend,
            progress=progress,
        )
    else:
        outcome = worst_case(
            model,
            spec,
            corners=corners,
            fd_step=fd_step,
            limits=limits,
            backend=backend,
            progress=progress,
        )
    return ToleranceStudyResult(mechanism, kind, spec, model.describe(), outcome, ideal)


def build_model(
    mechanism: Mechanism,
    spec: ToleranceSpec,
    responses: ResponseKind,
    *,
    contact: Any = None,
    friction: Any = None,
    start: str = "rest",
    revolutions: float = 1.0,
    solver: Any = None,
) -> tuple[Any, ToleranceSpec]:
    """The response model of a study and the part of ``spec`` it varies.

    Kinematic studies vary the length inputs; dynamic studies lengths and clearances (see
    :func:`tolerance_study` for the arguments).
    """
    if responses == "kinematic":
        spec = spec.only("length")
        if len(spec) == 0:
            raise ConfigError(
                f"mechanism {mechanism.name!r} has no length tolerances to study; add "
                "[tolerances.lengths.<name>] tables (or a general class) to its configuration"
            )
        return kinematic_model(mechanism, spec.names), spec
    if responses != "dynamic":
        raise ConfigError(f"responses must be kinematic or dynamic, got {responses!r}")
    from jointplay.contact.laws import get_law
    from jointplay.dynamics.simulate import Start

    spec = spec.only("length", "clearance")
    if len(spec) == 0:
        raise ConfigError(
            f"mechanism {mechanism.name!r} has no length or clearance tolerances to study"
        )
    law = get_law("impact", **PAPER_IFM) if contact is None else get_law(contact)
    radius = {
        item.joint: item.journal_radius for item in spec.inputs if isinstance(item, JointTolerance)
    }
    model = dynamic_model(
        mechanism,
        spec.names,
        law,
        journal_radius=radius,
        start=Start(start) if isinstance(start, str) else start,  # type: ignore[arg-type]
        revolutions=revolutions,
        solver=solver,
        friction=friction,
    )
    if not model.clearance_joints:
        raise ConfigError(
            "a dynamic study needs clearance joints: give joints an ISO 286 fit "
            "([joints.<name>] fit and diameter) or a clearance"
        )
    return model, spec


def response_units(
    mechanism: Mechanism, spec: ToleranceSpec, responses: ResponseKind, **options: Any
) -> dict[str, str]:
    """SI unit of every response of a study (e.g. to read spec limits given with units)."""
    model, _ = build_model(mechanism, spec, responses, **options)
    return dict(model.units)


def _ideal_peaks(mechanism: Mechanism, keys: tuple[str, ...]) -> dict[str, float]:
    """Largest |value| of each quantity for the nominal mechanism with ideal joints (0.1° steps)."""
    from jointplay.dynamics.nominal import nominal_analysis

    table = nominal_analysis(mechanism, step_deg=0.1).table
    return {f"{key}_peak": float(table[key].abs().max()) for key in keys if key in table}


# --- files ----------------------------------------------------------------------------------------


def display_scale(unit: str, kind: str = "") -> tuple[str, float]:
    """(label, factor) that turns an SI value into report units: mm, µm (clearances), deg."""
    if unit == "m":
        return ("µm", 1e6) if kind == "clearance" else ("mm", 1e3)
    if unit == "rad":
        return "deg", 180.0 / math.pi
    return unit.replace("^2", "²").replace("*", "·"), 1.0


def write_study(
    study: ToleranceStudyResult,
    folder: Path,
    *,
    plots: bool = True,
    provenance: Mapping[str, Any] | None = None,
) -> list[Path]:
    """Write ``samples.parquet``, ``summary.json``, the PNG plots and ``report.html`` into ``folder``."""
    from jointplay.io.output import write_json

    folder = Path(folder)
    written = [folder / "samples.parquet", folder / "summary.json"]
    study.to_dataframe().to_parquet(written[0], index=False)
    summary = study.summary()
    if provenance is not None:
        summary["provenance"] = dict(provenance)
    write_json(written[1], summary)
    images: dict[str, bytes] = {}
    if plots:
        images = _plots(study)
        for name, data in images.items():
            path = folder / name
            path.write_bytes(data)
            written.append(path)
    report = folder / "report.html"
    report.write_text(_html(study, summary, images), encoding="utf-8")
    written.append(report)
    return written


def _input_scale(study: ToleranceStudyResult, name: str) -> tuple[str, float]:
    item = study.spec[name]
    return display_scale(item.unit, item.kind)


def _pyplot() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _grid(plt: Any, count: int, *, left: float = 0.07) -> tuple[Any, list[Any]]:
    columns = min(3, max(1, count))
    rows = math.ceil(count / columns)
    height = 3.0 * rows + 0.6
    fig, axes = plt.subplots(rows, columns, figsize=(4.8 * columns, height), dpi=100, squeeze=False)
    # Fixed margins: tight_layout doubles the drawing time of these many-panel figures.
    fig.subplots_adjust(
        left=left / columns * 3 if columns < 3 else left,
        right=0.98,
        bottom=0.55 / height,
        top=1.0 - 0.9 / height,
        hspace=0.65,
        wspace=0.25 + 2.5 * left,
    )
    flat = list(axes.ravel())
    for ax in flat[count:]:
        ax.set_visible(False)
    return fig, flat[:count]


def _png(plt: Any, fig: Any) -> bytes:
    buffer = io.BytesIO()
    fig.savefig(buffer, format="png")
    plt.close(fig)
    return buffer.getvalue()


def input_label(name: str) -> str:
    """Short label of an input for plots and tables: ``crank`` for ``length_crank``."""
    return name.replace("length_", "").replace("clearance_", "clearance ").replace("_", " ")


def _plots(study: ToleranceStudyResult) -> dict[str, bytes]:
    plt = _pyplot()
    r = study.result
    names = list(r.response_names)
    images = {}
    fig, axes = _grid(plt, len(names), left=0.1)
    what = "share of the worst-case stack" if r.method == "worst-case" else "share of variance"
    for ax, name in zip(axes, names, strict=True):
        shares = r.summaries[name].contributions
        order = sorted(shares, key=lambda k: shares[k])
        ax.barh([input_label(k) for k in order], [100.0 * shares[k] for k in order], color="C0")
        ax.set_xlim(0, 100)
        ax.set_title(name, fontsize=9)
        ax.set_xlabel(f"{what} (%)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, axis="x", alpha=0.3)
    fig.suptitle(f"{study.mechanism.name}: contributions ({r.method})", fontsize=10)
    images["tornado.png"] = _png(plt, fig)
    if r.method != "monte-carlo":
        return images
    ok = r.run.status == 0
    fig, axes = _grid(plt, len(names))
    for j, (ax, name) in enumerate(zip(axes, names, strict=True)):
        unit, scale = display_scale(r.units[name])
        values = r.run.values[ok, j] * scale
        summary = r.summaries[name]
        if len(values):
            ax.hist(values, bins=min(60, max(10, int(math.sqrt(len(values))))), color="0.75")
        ax.axvline(summary.nominal * scale, color="k", linewidth=1.2, label="nominal")
        if summary.mean is not None:
            ax.axvline(summary.mean * scale, color="C0", linestyle="--", linewidth=1, label="mean")
        if study.ideal is not None and name in study.ideal:
            ax.axvline(
                study.ideal[name] * scale,
                color="C2",
                linestyle="-.",
                linewidth=1,
                label="ideal joints",
            )
        if summary.limits is not None:
            for value in (summary.limits.lower, summary.limits.upper):
                if value is not None:
                    ax.axvline(
                        value * scale, color="C3", linestyle=":", linewidth=1.5, label="spec limit"
                    )
        ax.set_title(name, fontsize=9)
        ax.set_xlabel(unit, fontsize=8)
        ax.tick_params(labelsize=7)
        handles, labels = ax.get_legend_handles_labels()
        unique = dict(zip(labels, handles, strict=True))
        ax.legend(unique.values(), unique.keys(), fontsize=6)
    fig.suptitle(f"{study.mechanism.name}: Monte Carlo, {int(ok.sum())} samples", fontsize=10)
    images["histograms.png"] = _png(plt, fig)
    fig, axes = _grid(plt, len(names))
    shown = np.flatnonzero(ok)[:5000]
    for j, (ax, name) in enumerate(zip(axes, names, strict=True)):
        summary = r.summaries[name]
        driver = summary.most_influential or r.input_names[0]
        i = r.input_names.index(driver)
        x_unit, x_scale = _input_scale(study, driver)
        y_unit, y_scale = display_scale(r.units[name])
        ax.scatter(r.x[shown, i] * x_scale, r.run.values[shown, j] * y_scale, s=3, alpha=0.4)
        nominal_x = study.spec.nominal[i] * x_scale
        ax.plot([nominal_x], [summary.nominal * y_scale], "k+", markersize=10, label="nominal")
        share = 100.0 * summary.contributions.get(driver, 0.0)
        ax.set_title(f"{name} ({share:.0f} % from {input_label(driver)})", fontsize=9)
        ax.set_xlabel(f"{input_label(driver)} ({x_unit})", fontsize=8)
        ax.set_ylabel(y_unit, fontsize=8)
        ax.tick_params(labelsize=7)
    fig.suptitle(f"{study.mechanism.name}: most influential input per response", fontsize=10)
    images["scatter.png"] = _png(plt, fig)
    return images


def _fmt(value: Any, scale: float = 1.0) -> str:
    if value is None:
        return "–"
    value = float(value) * scale
    return f"{value:.5g}" if math.isfinite(value) else "–"


def _html(
    study: ToleranceStudyResult, summary: Mapping[str, Any], images: Mapping[str, bytes]
) -> str:
    r = study.result
    esc = html.escape
    parts = [
        "<!DOCTYPE html><html lang='en'><head><meta charset='utf-8'>",
        f"<title>{esc(study.mechanism.name)} tolerance study</title>",
        "<style>body{font-family:sans-serif;margin:2em;max-width:1400px}"
        "table{border-collapse:collapse;margin:1em 0;font-size:90%}"
        "td,th{border:1px solid #ccc;padding:3px 8px;text-align:right}"
        "th{background:#eee}td:first-child,th:first-child{text-align:left}"
        "img{max-width:100%;border:1px solid #ddd;margin:1em 0}</style></head><body>",
        f"<h1>Tolerance study of {esc(study.mechanism.name)}</h1>",
        f"<p>Method <b>{esc(r.method)}</b>, {esc(study.responses)} responses; settings: "
        f"{esc(', '.join(f'{k} = {v}' for k, v in r.settings.items()))}. "
        f"Points: {summary['counts']['points']}, ok {summary['counts']['ok']}, "
        f"failed {summary['counts']['failed']}, not run {summary['counts']['not_run']}"
        f"{' (interrupted)' if r.interrupted else ''}.</p>",
        "<h2>Inputs</h2><table><tr><th>input</th><th>unit</th><th>nominal</th><th>lower</th>"
        "<th>upper</th><th>distribution</th><th>mean</th><th>std</th><th>source</th></tr>",
    ]
    for item in study.spec.inputs:
        unit, scale = display_scale(item.unit, item.kind)
        t = item.tolerance
        parts.append(
            f"<tr><td>{esc(item.name)}</td><td>{esc(unit)}</td><td>{_fmt(item.nominal, scale)}</td>"
            f"<td>{_fmt(t.lower, scale)}</td><td>{_fmt(t.upper, scale)}</td>"
            f"<td>{esc(t.distribution)}</td><td>{_fmt(t.mean, scale)}</td>"
            f"<td>{_fmt(t.std, scale)}</td><td>{esc(item.source)}</td></tr>"
        )
    parts.append("</table><h2>Responses</h2><table><tr><th>response</th><th>unit</th>")
    columns = ["nominal", "mean", "std", "minimum", "maximum", "half_range"]
    extra = ["out_of_spec_percent", "cp", "cpk"]
    parts.append("".join(f"<th>{c.replace('_', ' ')}</th>" for c in columns))
    if study.ideal is not None:
        parts.append("<th>ideal joints</th>")
    parts.append("".join(f"<th>{c.replace('_', ' ')}</th>" for c in extra))
    parts.append("<th>most influential</th></tr>")
    for name, response in r.summaries.items():
        unit, scale = display_scale(response.unit)
        cells = [_fmt(getattr(response, c), scale) for c in columns]
        if study.ideal is not None:
            cells.append(_fmt(study.ideal.get(name), scale))
        cells += [_fmt(getattr(response, c)) for c in extra]
        top = response.most_influential
        influence = (
            f"{esc(input_label(top))} ({100 * response.contributions[top]:.0f} %)" if top else "–"
        )
        parts.append(
            f"<tr><td>{esc(name)}</td><td>{esc(unit)}</td>"
            + "".join(f"<td>{c}</td>" for c in cells)
            + f"<td>{influence}</td></tr>"
        )
    parts.append("</table>")
    failures = r.failures
    parts.append(f"<h2>Failures ({len(failures)})</h2>")
    if failures:
        parts.append("<table><tr><th>sample</th><th>role</th>")
        parts.append("".join(f"<th>{esc(n)}</th>" for n in r.input_names))
        parts.append("<th>error</th></tr>")
        for f in failures[:100]:
            values = "".join(
                f"<td>{_fmt(f.inputs[n], _input_scale(study, n)[1])}</td>" for n in r.input_names
            )
            parts.append(
                f"<tr><td>{f.index}</td><td>{esc(f.role)}</td>{values}"
                f"<td style='text-align:left'>{esc(f.error)}</td></tr>"
            )
        parts.append("</table>")
        if len(failures) > 100:
            parts.append(f"<p>… and {len(failures) - 100} more (see samples.parquet).</p>")
    else:
        parts.append("<p>None.</p>")
    for name, data in images.items():
        encoded = base64.b64encode(data).decode("ascii")
        parts.append(f"<h2>{esc(name.removesuffix('.png'))}</h2>")
        parts.append(f"<img alt='{esc(name)}' src='data:image/png;base64,{encoded}'>")
    parts.append("</body></html>\n")
    return "".join(parts)
