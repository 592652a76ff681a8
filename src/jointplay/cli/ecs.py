"""``jointplay ecs``: the paper's Equivalent Contact Stiffness method (eqs. 9–13).

Prints the conventions, the contact load of every joint, K, δ and D per joint and overall with
their intermediate values (E*, R, a or b), the paper's published values (Tables 4 and 5) with
the ratio ours/paper, the IMPACT and Restitution-Method parameters that follow, and optionally
a crank-speed sweep with the hysteresis comparison. Human output is in N, mm, N/mm and N·s/mm
(the paper's units); ``--json`` gives SI and paper units. See :mod:`jointplay.study.ecs` and
docs/ecs.md.

The heavy modules (NumPy, pandas, the nominal analysis) are imported inside the functions, so
``jointplay --help`` does not load them through this module.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from jointplay.cli._app import app
from jointplay.cli._common import (
    ConfigOption,
    FigureFormatOption,
    ForceOption,
    PresetOption,
    RpmOption,
    check_figure_format,
    choice,
    maybe_output_dir,
    provenance,
    whole_headers,
)
from jointplay.errors import ConfigError
from jointplay.settings.mechanism import mechanism_from_options, quantity_option
from jointplay.units import parse_quantity

if TYPE_CHECKING:
    import pandas as pd

    from jointplay.contact.ecs import EcsEstimate
    from jointplay.model.mechanism import Mechanism
    from jointplay.study.ecs import EcsParameters, EcsResult, EcsSweep

console = Console(highlight=False, soft_wrap=True)
#: Width of the tables when the output is not a terminal (files, pipes, tests), characters.
PIPE_WIDTH = 150

#: Default crank-speed sweep with --out.
DEFAULT_SWEEP = "50:500:50 rpm"
#: Largest number of speeds a sweep may have.
MAX_SWEEP_POINTS = 500
#: 1 N/m = 1e-3 N/mm; 1 m = 1e3 mm.
_MM = 1e-3


def _parse_number(text: str, option: str, requirement: str, ok: Any) -> float:
    """``text`` as a float that is finite and satisfies ``ok``, else a ConfigError."""
    try:
        value = float(text)
    except ValueError:
        raise ConfigError(f"{option} must be {requirement}, got {text!r}") from None
    if not (math.isfinite(value) and ok(value)):
        raise ConfigError(f"{option} must be {requirement}, got {text!r}")
    return value


def _contacts(text: str) -> tuple[str, ...]:
    from jointplay.contact.ecs import CONTACT_TYPES

    value = choice(text, "--contact", (*CONTACT_TYPES, "both"))
    return CONTACT_TYPES if value == "both" else (value,)


def parse_sweep(text: str) -> list[float]:
    """Crank speeds in rev/min from ``"START:STOP:STEP UNIT"`` (inclusive) or a list
    ``"100,200,300 UNIT"``; the unit (``rpm``, ``rad/s``, ...) is written once, at the end.

    Raises:
        ConfigError: malformed text, no unit (a bare list is refused, as every quantity
            without a unit), a speed not positive, or more than :data:`MAX_SWEEP_POINTS`
            speeds.
    """
    form = (
        "START:STOP:STEP UNIT such as '50:500:50 rpm', or a list such as '100,200,300 rpm' "
        "(speeds > 0)"
    )
    numbers, unit = _split_unit(text)
    if not unit:
        raise ConfigError(f"--sweep: {text!r} has no unit; write it with one, e.g. '{numbers} rpm'")
    try:
        per_unit = parse_quantity(f"1 {unit}", "rad/s", field="--sweep")
    except ConfigError:
        raise ConfigError(
            f"--sweep: {unit!r} is not a unit of crank speed (e.g. rpm, rad/s), got {text!r}"
        ) from None
    # rev/min per unit, to 12 digits: 1 rpm is 1.0 rpm, not 2π/60 · 30/π = 1.0000000000000002
    rpm_per_unit = float(f"{per_unit * 30.0 / math.pi:.12g}")
    try:
        if ":" in numbers:
            start, stop, step = (float(part) for part in numbers.split(":"))
            if not (
                math.isfinite(start + stop + step) and start > 0 and step > 0 and stop >= start
            ):
                raise ValueError
            count = math.floor((stop - start) / step + 1e-9) + 1
            if count > MAX_SWEEP_POINTS:
                raise ConfigError(
                    f"--sweep {text!r} has {count} speeds; at most {MAX_SWEEP_POINTS}"
                )
            values = [start + i * step for i in range(count)]
        else:
            values = [float(part) for part in numbers.split(",")]
    except ValueError:
        raise ConfigError(f"--sweep must read {form}, got {text!r}") from None
    speeds = [value * rpm_per_unit for value in values]
    if not speeds or not all(math.isfinite(s) and s > 0 for s in speeds):
        raise ConfigError(f"--sweep must read {form}, got {text!r}")
    if len(speeds) > MAX_SWEEP_POINTS:
        raise ConfigError(f"--sweep {text!r} has {len(speeds)} speeds; at most {MAX_SWEEP_POINTS}")
    return speeds


def _split_unit(text: str) -> tuple[str, str]:
    """``"50:500:50 rpm"`` → ``("50:500:50", "rpm")``: the numbers, and the unit that
    follows them (from the first letter on; empty without one)."""
    value = text.strip()
    for index, char in enumerate(value):
        if char.isalpha() and char not in "eE":
            return value[:index].strip(), value[index:].strip()
        if char in "eE" and not (index and value[index - 1].isdigit()):
            return value[:index].strip(), value[index:].strip()
    return value, ""


def _length(text: str) -> str | float:
    from jointplay.contact.ecs import LENGTH_CONVENTIONS

    value = text.strip().lower()
    if value in LENGTH_CONVENTIONS:
        return value
    length = parse_quantity(text, "m", field="--length")
    if not length > 0:
        raise ConfigError(f"--length must be positive, got {text!r}")
    return length


@app.command("ecs")
def ecs_command(
    preset: PresetOption = None,
    config: ConfigOption = None,
    rpm: RpmOption = None,
    contact: Annotated[
        str, typer.Option("--contact", help="spherical (eqs. 9–10), cylindrical (11–12) or both.")
    ] = "both",
    load: Annotated[
        str,
        typer.Option(
            "--load",
            help="eq13: max |α r m| (paper); reaction: max ideal-joint reaction force.",
        ),
    ] = "eq13",
    damping_ratio: Annotated[
        str,
        typer.Option(
            "--damping-ratio", help="D/K, a time, e.g. '0.01 s' (the paper's D = 0.01 K)."
        ),
    ] = "0.01 s",
    radius: Annotated[
        str, typer.Option("--radius", help="Equivalent radius: conformal, pin or sum.")
    ] = "conformal",
    modulus: Annotated[
        str, typer.Option("--modulus", help="E*: johnson, rigid-bearing or no-poisson.")
    ] = "johnson",
    length: Annotated[
        str,
        typer.Option(
            "--length", help="l of eqs. 11–12: link-thickness, pin-length or a length ('12 mm')."
        ),
    ] = "link-thickness",
    a0: Annotated[
        str, typer.Option("--a0", help="a₀ of eq. 10 with a unit, e.g. '0.01 mm'.")
    ] = "0 mm",
    eq11_log: Annotated[
        str, typer.Option("--eq11-log", help="Eq. 11 logarithm of: half-width (b) or length (l).")
    ] = "half-width",
    alpha_link: Annotated[
        str, typer.Option("--alpha-link", help="Whose α enters eq. 13: max, pin or bearing.")
    ] = "max",
    ifm_stiffness: Annotated[
        str,
        typer.Option(
            "--ifm-stiffness", help="K → IMPACT k: paper (N/mm read as N/mm^1.5), linear, matched."
        ),
    ] = "paper",
    restitution: Annotated[
        str,
        typer.Option("--restitution", help="e of the compared damping models (LN, HC, ...)."),
    ] = "0.8",
    sweep: Annotated[
        str | None,
        typer.Option(
            "--sweep",
            help="Crank speeds START:STOP:STEP or a list, the unit once at the end, e.g. "
            f"'100,200,300 rpm' (with --out: '{DEFAULT_SWEEP}').",
        ),
    ] = None,
    as_json: Annotated[
        bool, typer.Option("--json", help="Print JSON (SI and paper units).")
    ] = False,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out", "-o", help="Write ecs.json, ecs_sweep.csv, ecs_sweep.png, ecs_damping.png."
        ),
    ] = None,
    force: ForceOption = False,
    figure_format: FigureFormatOption = "png",
) -> None:
    """Equivalent Contact Stiffness (paper eqs. 9–13): K, δ and D of the clearance joints.

    The load is the largest eq. 13 force |α r m| of the nominal cycle (or the largest ideal
    reaction with --load reaction); Hertz theory turns it into K and δ, and D = ratio × K.
    Every convention the paper leaves open is an option and is printed with the results.
    """
    from jointplay.contact.ecs import (
        ALPHA_LINKS,
        EQ11_LOG_ARGUMENTS,
        IFM_STIFFNESS_CONVENTIONS,
        LOAD_SOURCES,
        MODULUS_CONVENTIONS,
        RADIUS_CONVENTIONS,
        EcsConventions,
    )
    from jointplay.io.output import json_text, write_csv, write_json
    from jointplay.model.summary import mechanism_summary
    from jointplay.study.ecs import ecs_analysis, ecs_sweep

    if not console.is_terminal:
        console.width = PIPE_WIDTH
    figure_format = check_figure_format(figure_format)
    with maybe_output_dir(out, force, inputs=(config,)) as folder:
        contacts = _contacts(contact)
        ratio = quantity_option(damping_ratio, "s", "--damping-ratio", example="s")
        if not ratio >= 0:
            raise ConfigError(
                f"--damping-ratio must be >= 0 (the paper's D = 0.01 K is '0.01 s'), got "
                f"{damping_ratio!r}"
            )
        e = _parse_number(restitution, "--restitution", "a number in (0, 1]", lambda v: 0 < v <= 1)
        conventions = EcsConventions(
            radius=choice(radius, "--radius", RADIUS_CONVENTIONS),
            modulus=choice(modulus, "--modulus", MODULUS_CONVENTIONS),
            initial_contact_radius=_a0(a0),
            contact_length=_length(length),
            eq11_log_argument=choice(eq11_log, "--eq11-log", EQ11_LOG_ARGUMENTS),
            alpha_link=choice(alpha_link, "--alpha-link", ALPHA_LINKS),
            load=choice(load, "--load", LOAD_SOURCES),
            damping_ratio=ratio,
            ifm_stiffness=choice(ifm_stiffness, "--ifm-stiffness", IFM_STIFFNESS_CONVENTIONS),
        )
        speeds = parse_sweep(sweep) if sweep is not None else None
        if speeds is None and out is not None:
            speeds = parse_sweep(DEFAULT_SWEEP)
        mechanism = mechanism_from_options(preset, config, rpm)
        result = ecs_analysis(mechanism, conventions)
        swept = (
            ecs_sweep(mechanism, speeds, conventions, restitution=e) if speeds is not None else None
        )
        document = _document(mechanism, result, contacts, e, swept)
        if folder is not None:
            write_json(
                folder / "ecs.json",
                {**document, "provenance": provenance(mechanism_summary(mechanism))},
            )
            if swept is not None:
                write_csv(_sweep_csv(swept), folder / "ecs_sweep.csv")
                from jointplay.report.plots import ecs_sweep_plots

                ecs_sweep_plots(swept, contacts, folder, figure_format=figure_format)
    if as_json:
        print(json_text(document))
        return
    _print_report(mechanism, result, contacts, e, swept)
    if out is not None:
        console.print(f"results written to {out}")


def _sweep_csv(swept: EcsSweep) -> pd.DataFrame:
    """The sweep in the paper's units, followed by the dimensional columns again in SI."""
    si = swept.table
    dimensional = [
        c
        for c in si.columns
        if c.endswith(("_N_per_m", "_N_s_per_m")) or (c.startswith("delta_") and c.endswith("_m"))
    ]
    return swept.paper_units_table().join(si[dimensional])


def _a0(text: str) -> float:
    value = parse_quantity(text, "m", field="--a0")
    if not value >= 0:
        raise ConfigError(f"--a0 must be >= 0, got {text!r}")
    return value


# --- the JSON document ------------------------------------------------------------------------


def _parameters(
    mechanism: Mechanism, result: EcsResult, contacts: tuple[str, ...]
) -> dict[str, dict[str, EcsParameters | str]]:
    """IMPACT/RM parameters per contact and source, or the reason they are unavailable."""
    from jointplay.study.ecs import ecs_parameters

    out: dict[str, dict[str, EcsParameters | str]] = {}
    for c in contacts:
        out[c] = {}
        for source in ("computed", "paper"):
            try:
                out[c][source] = ecs_parameters(
                    mechanism, c, source, result.conventions, result=result
                )
            except ConfigError as exc:
                out[c][source] = str(exc)
    return out


def _ratio(ours: float, paper: float) -> float:
    return ours / paper if paper else math.nan


def _document(
    mechanism: Mechanism,
    result: EcsResult,
    contacts: tuple[str, ...],
    restitution: float,
    swept: EcsSweep | None,
) -> dict[str, Any]:
    from jointplay.contact.ecs import CONTACT_TYPES, comparison_factors, spherical_load_lower_bound
    from jointplay.study.ecs import EcsParameters
    from jointplay.study.published import PAPER_PUBLISHED

    record = result.as_dict()
    record["overall"] = {c: record["overall"][c] for c in contacts}
    for joint in record["joints"]:
        for other in CONTACT_TYPES:
            if other not in contacts:
                del joint[other]
    paper: dict[str, Any] = {}
    parameters: dict[str, Any] = {}
    for c in contacts:
        published = PAPER_PUBLISHED[c]
        ours = result.estimate(c)
        entry = published.as_dict()
        entry["ours_over_paper"] = {
            "stiffness": _ratio(ours.stiffness, published.stiffness),
            "penetration": _ratio(ours.penetration, published.penetration),
            "damping": _ratio(ours.damping, published.damping),
        }
        if c == "spherical":
            entry["implied_load_lower_bound_N"] = spherical_load_lower_bound(
                published.stiffness, published.penetration
            )
        paper[c] = entry
        parameters[c] = {
            source: p.as_dict() if isinstance(p, EcsParameters) else {"error": p}
            for source, p in _parameters(mechanism, result, (c,))[c].items()
        }
    document: dict[str, Any] = {
        "method": "Equivalent Contact Stiffness, Akhadkar et al. eqs. 9-13",
        "contacts": list(contacts),
        "ecs": record,
        "paper": paper,
        "simulator_parameters": parameters,
        "hysteresis": {
            **record.pop("hysteresis"),
            "restitution": restitution,
            "chi_models": comparison_factors(restitution),
            "definition": "chi_ecs = (D/K) v0 / delta (see docs/ecs.md)",
        },
    }
    if swept is not None:
        document["sweep"] = swept.table.to_dict(orient="records")
    return document


# --- human output -----------------------------------------------------------------------------


def _g(value: float, digits: int = 4) -> str:
    if not math.isfinite(value):
        return "—"
    return f"{value:.{digits}g}"


def _print_report(
    mechanism: Mechanism,
    result: EcsResult,
    contacts: tuple[str, ...],
    restitution: float,
    swept: EcsSweep | None,
) -> None:
    from jointplay.contact.ecs import comparison_factors
    from jointplay.study.ecs import EcsParameters

    conv = result.conventions
    console.print(
        f"[bold]Equivalent Contact Stiffness[/bold] (Akhadkar et al. eqs. 9–13) — "
        f"{result.mechanism} at {result.crank_speed_rpm:.6g} RPM"
    )
    table = Table("convention", "value", "meaning", box=None, title="Conventions")
    record = conv.as_dict()
    descriptions = record.pop("descriptions")
    for name, value in record.items():
        text = "estimated" if value is None else str(value)
        if name == "initial_contact_radius" or (
            name == "contact_length" and not isinstance(value, str)
        ):
            text = f"{float(value) / _MM:g} mm"
        elif name == "damping_ratio":
            text = f"{value:g} s"
        table.add_row(name, text, descriptions.get(name, ""))
    console.print(whole_headers(table))

    loads = Table(
        "joint", "α from", "|α|max (rad/s²)", "at crank (deg)", "r (mm)", "m (g)", "c (mm)",
        "l (mm)", "F (N)", box=None, title=f"Contact load per joint ({conv.load})",
    )  # fmt: skip
    for entry in result.joints:
        ld = entry.load
        loads.add_row(
            ld.joint + (" *" if ld.joint == result.overall_joint else ""),
            ld.alpha_link or "—",
            _g(ld.alpha_max),
            f"{ld.crank_deg:.0f}",
            _g(ld.pin_radius / _MM),
            _g(ld.pin_mass * 1e3),
            _g(ld.clearance / _MM),
            _g(ld.length / _MM),
            _g(ld.load),
        )
    console.print(whole_headers(loads))
    console.print("* the joint with the largest load: its values are the mechanism's ECS values")

    for c in contacts:
        _print_contact(result, c)

    params = Table(
        "contact", "source", "IMPACT k", "e", "c_max (N·s/mm)", "d_max (mm)", "RM penalty (N/mm)",
        box=None, title=f"Simulator parameters (IMPACT k: {conv.ifm_stiffness})",
    )  # fmt: skip
    for c, by_source in _parameters(mechanism, result, contacts).items():
        for source, p in by_source.items():
            if not isinstance(p, EcsParameters):
                params.add_row(c, source, p, "", "", "", "")
                continue
            params.add_row(
                c,
                source,
                f"{_g(p.stiffness * _MM**p.exponent, 6)} N/mm^{p.exponent:g}",
                f"{p.exponent:g}",
                _g(p.c_max * _MM),
                _g(p.d_max / _MM),
                _g(p.penalty * _MM, 6),
            )
    console.print(whole_headers(params))
    if not math.isclose(result.crank_speed_rpm, 200.0, rel_tol=1e-6):
        console.print("note: the paper's values are for 200 RPM")

    chi_models = comparison_factors(restitution)
    hyst = ", ".join(f"χ_ECS {c} = {_g(result.hysteresis_factor(c))}" for c in contacts)
    console.print(
        f"Hysteresis (χ_ECS = (D/K) v0/δ, v0 = {_g(result.impact_velocity / _MM)} mm/s "
        f"{result.impact_velocity_source}): {hyst}; at e = {restitution:g}: "
        + ", ".join(f"{name} {chi:.3g}" for name, chi in chi_models.items())
    )
    if swept is not None:
        _print_sweep(swept, contacts)


def _print_contact(result: EcsResult, contact: str) -> None:
    from jointplay.contact.ecs import spherical_load_lower_bound
    from jointplay.study.published import PAPER_PUBLISHED

    spherical = contact == "spherical"
    size = "a (mm)" if spherical else "b (mm)"
    extra = () if spherical else ("l (mm)", "Σln(4dᵢ/b)")
    eqs = "eqs. 9–10" if spherical else "eqs. 11–12"
    table = Table(
        "joint", "F (N)", "E* (N/mm²)", "R (mm)", size, *extra, "K (N/mm)", "δ (mm)",
        "D (N·s/mm)", "status", box=None, title=f"{contact.capitalize()} contact ({eqs})",
    )  # fmt: skip

    def row(label: str, est: EcsEstimate) -> list[str]:
        cells = [
            label,
            _g(est.load),
            _g(est.modulus * _MM**2, 6),
            _g(est.radius / _MM, 6),
            _g(est.contact_size / _MM),
        ]
        if not spherical:
            cells += [_g(est.length / _MM), _g(est.log_term)]
        cells += [
            _g(est.stiffness * _MM, 6),
            _g(est.penetration / _MM),
            _g(est.damping * _MM, 5),
            est.status,
        ]
        return cells

    for entry in result.joints:
        table.add_row(*row(entry.load.joint, entry.estimate(contact)))
    ours = result.estimate(contact)
    table.add_row(*row(f"overall ({result.overall_joint})", ours))
    published = PAPER_PUBLISHED[contact]
    blanks = [""] * (4 + len(extra))
    table.add_row(
        f"paper {published.table}",
        *blanks,
        _g(published.stiffness_n_per_mm, 6),
        _g(published.penetration_mm),
        _g(published.damping_n_s_per_mm, 5),
        "",
    )
    table.add_row(
        "ours / paper",
        *blanks,
        _g(_ratio(ours.stiffness, published.stiffness)),
        _g(_ratio(ours.penetration, published.penetration)),
        _g(_ratio(ours.damping, published.damping)),
        "",
    )
    console.print(whole_headers(table))
    if spherical:
        bound = spherical_load_lower_bound(published.stiffness, published.penetration)
        console.print(
            f"Table 5's K and δ need a load of at least (4/3) K δ = {bound:.4g} N under eqs. 9–10 "
            f"with any E*, R and a₀ ≥ 0 (our load: {ours.load:.4g} N)."
        )


def _print_sweep(swept: EcsSweep, contacts: tuple[str, ...]) -> None:
    data = swept.paper_units_table()
    columns = ["rpm", "load_N"]
    headers = ["rpm", "F (N)"]
    for c in contacts:
        short = "sph" if c == "spherical" else "cyl"
        columns += [f"K_{c}_N_per_mm", f"delta_{c}_mm", f"D_{c}_N_s_per_mm", f"chi_ecs_{c}"]
        headers += [f"K {short} (N/mm)", f"δ {short} (mm)", f"D {short} (N·s/mm)", f"χ_ECS {short}"]
    table = Table(*headers, box=None, title="Crank-speed sweep (overall joint)")
    for _, record in data.iterrows():
        table.add_row(*(_g(float(record[col]), 5) for col in columns))
    console.print(whole_headers(table))
