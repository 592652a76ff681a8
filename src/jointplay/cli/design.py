"""``jointplay design``: the cheapest fit and length class that meet the requirements.

Import-light: NumPy, pandas, Numba and the study load when the command runs.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer
from rich.console import Console

from jointplay.cli._app import Interrupted, app
from jointplay.cli._common import (
    ConfigOption,
    FigureFormatOption,
    ForceOption,
    GravityOption,
    HardnessOption,
    OutOption,
    PresetOption,
    RpmOption,
    SettleOption,
    WearCoefficientOption,
    check_figure_format,
    choice,
    mechanism_from_options,
    provenance,
)
from jointplay.cli._simulation import (
    CmaxOption,
    ContactOption,
    DampingOption,
    DepthOption,
    EcsSourceOption,
    ExponentOption,
    FrictionLawOption,
    FrictionOption,
    MethodOption,
    RestitutionOption,
    RtolOption,
    StiffnessLawOption,
    StiffnessOption,
    contact_from_options,
)
from jointplay.cli.tolerance import (
    BackendOption,
    backend_from_options,
    solver_options,
)
from jointplay.errors import ConfigError
from jointplay.units import parse_quantity

if TYPE_CHECKING:
    from jointplay.study.design import DesignResult

console = Console(highlight=False, soft_wrap=True)

DEFAULT_FITS = "H7/h6,H7/g6,H8/f7,H8/g7,H9/d9,H11/c11"


def read_table(path: Path | None, config: Path | None = None) -> dict[str, Any]:
    """The ``[wear]`` and ``[cost]`` tables: those of the mechanism's configuration file
    (``--config``), each table replaced by the one of ``--table`` where that file has it."""
    from jointplay.io.config import design_table_keys, design_tables

    tables = design_tables(config)
    if path is None:
        return tables
    import tomllib

    try:
        with open(path, "rb") as handle:
            data = tomllib.load(handle)
    except OSError as exc:
        raise ConfigError(f"--table {path}: cannot read it ({exc.strerror})") from None
    except tomllib.TOMLDecodeError as exc:
        raise ConfigError(f"--table {path}: not valid TOML ({exc})") from None
    return {**tables, **design_table_keys(data, f"--table {path}")}


def wear_settings(table: dict[str, Any], coefficient: float | None, hardness: str | None) -> Any:
    """Archard settings from a ``[wear]`` table and the command-line overrides."""
    from jointplay.dynamics.wear import WearSettings
    from jointplay.io.config import design_table_keys

    wear = design_table_keys({"wear": table.get("wear", {})}, "wear table")["wear"]
    options: dict[str, Any] = {}
    if "coefficient" in wear:
        options["coefficient"] = _coefficient(wear["coefficient"], "[wear] coefficient")
    if "hardness" in wear:
        options["hardness"] = parse_quantity(
            wear["hardness"], "Pa", field="[wear] hardness", example="GPa"
        )
    joints: dict[str, dict[str, float]] = {}
    for joint, values in dict(wear.get("joints", {})).items():
        entry: dict[str, float] = {}
        for key, value in dict(values).items():
            where = f"[wear.joints.{joint}] {key}"
            if key == "hardness":
                entry[key] = parse_quantity(value, "Pa", field=where, example="GPa")
            else:
                entry[key] = _coefficient(value, where)
        joints[joint] = entry
    options["joints"] = joints
    if coefficient is not None:
        options["coefficient"] = coefficient
    if hardness is not None:
        options["hardness"] = parse_quantity(hardness, "Pa", field="--hardness")
    return WearSettings(**options)


def _coefficient(value: Any, where: str) -> float:
    """An Archard wear coefficient (a dimensionless number) from a ``[wear]`` table."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ConfigError(f"{where} must be a number (Archard's k is dimensionless), got {value!r}")
    return float(value)


def parse_clearance_limit(text: str | None) -> tuple[float | None, float | None]:
    """``--clearance-limit``: ``"80 um"`` (absolute radial clearance) or ``"+20 um"`` (the
    fit's largest radial clearance plus an allowance) → (limit, allowance), m."""
    if text is None:
        return None, None
    value = text.strip()
    if value.startswith("+"):
        return None, parse_quantity(value[1:].strip(), "m", field="--clearance-limit")
    return parse_quantity(value, "m", field="--clearance-limit"), None


def parse_joint_fits(texts: list[str]) -> dict[str, str]:
    """``--fit JOINT=FIT`` options."""
    out: dict[str, str] = {}
    for text in texts:
        joint, sep, fit = text.partition("=")
        if not sep or not joint.strip() or not fit.strip():
            raise ConfigError(f"--fit {text!r}: expected JOINT=FIT, e.g. 'O2=H7/g6'")
        out[joint.strip()] = fit.strip()
    return out


@app.command("design")
def design_command(
    out: OutOption,
    require: Annotated[
        list[str],
        typer.Option(
            "--require",
            "-r",
            help="A requirement: RESPONSE <=|<|>=|> VALUE [UNIT] [@CONFIDENCE], e.g. "
            "'rocker_speed_error <= 1 %' or 'joint_force <= 150 N @99.73'. Repeatable.",
        ),
    ],
    preset: PresetOption = None,
    config: ConfigOption = None,
    fits: Annotated[
        str,
        typer.Option("--fits", help="Candidate ISO 286 fits for every pin joint, comma-separated."),
    ] = DEFAULT_FITS,
    fit: Annotated[
        list[str] | None,
        typer.Option("--fit", help="Fix one joint's fit, JOINT=FIT (e.g. O2=H7/g6). Repeatable."),
    ] = None,
    classes: Annotated[
        str, typer.Option("--classes", help="Candidate ISO 2768-1 classes, comma-separated.")
    ] = "f,m,c,v",
    confidence: Annotated[
        float,
        typer.Option("--confidence", help="Share of samples that must meet a requirement, %."),
    ] = 99.73,
    samples: Annotated[
        int, typer.Option("--samples", "-n", help="Samples per scheme.", min=1)
    ] = 200,
    seed: Annotated[
        int, typer.Option("--seed", help="Seed (the same for every scheme).", min=0)
    ] = 0,
    truncate: Annotated[
        bool,
        typer.Option(
            "--truncate/--no-truncate",
            help="Draw each normal input (σ = a sixth of its tolerance band) from the normal "
            "truncated at its limits, as parts outside them are rejected (default); "
            "--no-truncate keeps the 0.27 % of samples beyond ±3σ.",
        ),
    ] = True,
    responses: Annotated[
        str,
        typer.Option(
            "--responses", help="auto (kinematic when every requirement is), kinematic or dynamic."
        ),
    ] = "auto",
    clearance_limit: Annotated[
        str | None,
        typer.Option(
            "--clearance-limit",
            help="Radial clearance that ends a joint's life: '80 um', or '+20 um' = the fit's "
            "largest radial clearance plus 20 µm (needed by a 'life' requirement).",
        ),
    ] = None,
    table: Annotated[
        Path | None,
        typer.Option(
            "--table",
            help="TOML file with [wear] (coefficient, hardness, joints.<J>) and [cost] (model, "
            "a, b, k, reference, it, iso2768) tables; the same tables may sit in the --config "
            "file, and a table here replaces the config's.",
        ),
    ] = None,
    wear_coefficient: WearCoefficientOption = None,
    hardness: HardnessOption = None,
    method: MethodOption = None,
    ecs_source: EcsSourceOption = None,
    contact: ContactOption = None,
    k: StiffnessOption = None,
    exponent: ExponentOption = None,
    cmax: CmaxOption = None,
    depth: DepthOption = None,
    restitution: RestitutionOption = None,
    damping: DampingOption = None,
    stiffness_law: StiffnessLawOption = None,
    friction: FrictionOption = None,
    friction_law: FrictionLawOption = None,
    rtol: RtolOption = None,
    model_check: Annotated[
        bool,
        typer.Option(
            "--model-sensitivity/--no-model-sensitivity",
            help="Dynamic: re-evaluate the chosen scheme at the ends of the contact model's "
            "ranges (restitution 0.6-0.95, friction 0.01-0.2, the other stiffness law; "
            "docs/contact.md) and say whether the choice holds.",
        ),
    ] = True,
    settle: SettleOption = 2,
    revolutions: Annotated[
        float, typer.Option("--revolutions", help="Analysed revolutions.")
    ] = 1.0,
    rpm: RpmOption = None,
    gravity: GravityOption = None,
    backend: BackendOption = "processes",
    workers: Annotated[
        int | None,
        typer.Option("--workers", help="Local worker processes (default: one per CPU).", min=1),
    ] = None,
    dask_scheduler: Annotated[
        str | None, typer.Option("--dask-scheduler", help="Run on the Dask cluster at ADDRESS.")
    ] = None,
    plots: Annotated[bool, typer.Option("--plots/--no-plots", help="Write PNG plots.")] = True,
    progress: Annotated[
        bool, typer.Option("--progress/--no-progress", help="Progress bar.")
    ] = True,
    force: ForceOption = False,
    figure_format: FigureFormatOption = "png",
) -> None:
    """Design study: every fit × length class through the dynamics; the cheapest that meets
    the requirements, its yield and relative cost.

    Link lengths and radial clearances are sampled from normal distributions centred in
    their limits, ±3σ at the limits, truncated at the limits (see --truncate).

    Writes DIR/design.parquet and DIR/design.csv (one row per scheme; dynamic:
    penetration_exceeds_<joint> and penetration_ratio_max_<joint>), DIR/samples.parquet
    (dynamic: penetration_ratio_<joint>), DIR/summary.json (with diagnostics), PNG plots and
    DIR/report.html. Samples whose pins sink deeper than the radial clearance (not physical)
    get one warning line per joint on stderr.
    """
    from jointplay.io.output import output_dir
    from jointplay.report.design import write_design
    from jointplay.study.design import design_study, design_units, resolve_responses
    from jointplay.study.sensitivity import model_sensitivity
    from jointplay.tolerance.cost import CostModel

    mechanism = mechanism_from_options(preset, config, rpm=rpm, gravity=gravity)
    kind = choice(responses, "--responses", ("auto", "kinematic", "dynamic"))
    contact_options = {
        "method": method, "ecs_source": ecs_source, "contact": contact, "k": k,
        "exponent": exponent, "cmax": cmax, "depth": depth, "restitution": restitution,
        "damping": damping, "stiffness_law": stiffness_law, "friction": friction,
        "friction_law": friction_law,
    }  # fmt: skip
    given = [f"--{key.replace('_', '-')}" for key, v in contact_options.items() if v is not None]
    if given and resolve_responses(mechanism, require, kind) != "dynamic":  # type: ignore[arg-type]
        raise ConfigError(
            f"{', '.join(given)}: contact options apply to dynamic designs only, and every "
            "requirement here is kinematic; add --responses dynamic or drop them"
        )
    contact_used = contact_from_options(config, mechanism, "--method", **contact_options)
    if not (math.isfinite(confidence) and 0 < confidence < 100):
        raise ConfigError(f"--confidence must lie between 0 and 100 %, got {confidence}")
    fit_list = [f.strip() for f in fits.split(",") if f.strip()]
    fixed = parse_joint_fits(fit or [])
    candidates: list[Any] = (
        [{**dict.fromkeys(_fit_joints(mechanism), f), **fixed} for f in fit_list]
        if fixed
        else fit_list
    )
    class_list = [c.strip() for c in classes.split(",") if c.strip()]
    limit, allowance = parse_clearance_limit(clearance_limit)
    data = read_table(table, config)
    cost = CostModel.from_table(data.get("cost", {}))
    wear = wear_settings(data, wear_coefficient, hardness)
    where = backend_from_options(backend, workers, dask_scheduler)
    figure_format = check_figure_format(figure_format)
    with output_dir(out, force=force) as folder:  # checked before the study runs
        options: dict[str, Any] = {
            "samples": samples, "seed": seed, "truncate": truncate, "cost": cost,
            "clearance_limit": limit, "clearance_allowance": allowance, "wear": wear,
            "settle": settle, "revolutions": revolutions, "solver": solver_options(rtol),
            "backend": where, "progress": progress,
        }  # fmt: skip
        result = design_study(
            mechanism,
            candidates,
            class_list,
            require,
            confidence=confidence / 100.0,
            responses=kind,  # type: ignore[arg-type]
            contact=contact_used,
            **options,
        )
        sensitivity = (
            model_sensitivity(mechanism, result, contact_used, **options)
            if model_check and not result.interrupted
            else None
        )
        units = design_units(mechanism, result.responses)  # type: ignore[arg-type]
        summary = result.summary()
        write_design(
            result,
            folder,
            units,
            plots=plots,
            provenance=provenance(summary["settings"]),
            figure_format=figure_format,
            sensitivity=sensitivity,
        )
    _print(result, units)
    if result.settings.get("model", {}).get("contact"):
        console.print(f"contact: {result.settings['model']['contact']}")
    if sensitivity is not None:
        console.print(f"model sensitivity: {sensitivity.verdict}")
    if result.interrupted:
        raise Interrupted(
            f"{len(result.table)} scheme(s) finished; their results were written to {out}"
        )
    console.print(f"results written to {out}")


def _fit_joints(mechanism: Any) -> list[str]:
    return [j.name for j in mechanism.revolute_joints if j.fit is not None]


def _print(result: DesignResult, units: dict[str, str]) -> None:
    from rich.table import Table

    from jointplay.report.design import display

    table = result.table
    grid = Table(box=None)
    headers = ["scheme", "cost", "yield %", "DPM"]
    required = list(dict.fromkeys(r.response for r in result.requirements))
    for name in required:
        unit, _ = display(units.get(name, ""))
        headers.append(f"{name} @{100 * result.confidence:g}% ({unit})")
    headers.append("meets all")
    for header in headers:
        grid.add_column(header, justify="left" if header == "scheme" else "right")
    if len(table):
        for _, row in table.sort_values("cost").iterrows():
            cells = [
                str(row["scheme"]),
                f"{row['cost']:.3g}",
                f"{row['yield']:.2f}",
                f"{row['dpm']:,.0f}",
            ]
            for name in required:
                _, scale = display(units.get(name, ""))
                cells.append(f"{row[f'{name}_at_confidence'] * scale:.4g}")
            cells.append("yes" if row["feasible"] else "no")
            grid.add_row(*cells)
    console.print(grid)
    best = result.best_row
    if best is not None:
        line = (
            f"choose {result.best}: relative cost {best['cost']:.3g}, yield {best['yield']:.2f} %"
        )
        life = best.get("life_at_confidence")
        if life is not None and math.isfinite(life):
            line += f", life {life / 3600.0:,.0f} h at {100 * result.confidence:g} %"
        console.print(line)
    elif result.binding is not None:
        console.print(f"no scheme meets every requirement; binding: {result.binding}")
    for finding in result.diagnostics:  # one line each, on stderr, as `jointplay tolerance`
        print(f"jointplay: {finding.line()}", file=sys.stderr)
