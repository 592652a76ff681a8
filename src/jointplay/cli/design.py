"""``jointplay design``: the cheapest fit and length class that meet the requirements.

Import-light: NumPy, pandas, Numba and the study load when the command runs.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any, Literal

import typer
from rich.console import Console

from jointplay._kernels import BATCH_LANES
from jointplay.cli._app import app
from jointplay.cli._common import (
    MAX_SAMPLES,
    ConfigOption,
    DaskSchedulerOption,
    FigureFormatOption,
    ForceOption,
    GravityOption,
    HardnessOption,
    OutOption,
    PlotsOption,
    PresetOption,
    ProgressOption,
    RpmOption,
    SettleOption,
    WearCoefficientOption,
    WorkersOption,
    check_figure_format,
    choice,
    compiling_kernels,
    provenance,
    run_study,
    study_kept,
    whole_headers,
    writing_study,
)
from jointplay.cli._panels import (
    REQUIREMENTS_PANEL,
    RUN_PANEL,
    SAMPLING_PANEL,
    WEAR_PANEL,
)
from jointplay.cli._simulation import (
    NO_CONTACT_OPTIONS,
    SETTING_OPTIONS,
    ContactValues,
    RtolOption,
    run_settings,
    with_contact_options,
)
from jointplay.cli.tolerance import (
    BackendOption,
    backend_from_options,
)
from jointplay.dynamics.declared import setting
from jointplay.errors import ConfigError, JointplayError
from jointplay.settings.mechanism import mechanism_from_options, quantity_option
from jointplay.settings.simulation import check_revolutions, contact_from_options
from jointplay.units import parse_quantity

if TYPE_CHECKING:
    from jointplay.study.design import DesignResult

console = Console(highlight=False, soft_wrap=True)

#: The fits tried when none are named: clearance fits with room for the pin at their lower
#: limit. H7/h6, whose minimum clearance is zero, is tried only when named (with a note).
DEFAULT_FITS = "H7/g6,H8/f7,H8/g7,H9/d9,H11/c11"


def read_table(path: Path | None, config: Path | None = None) -> dict[str, Any]:
    """The ``[wear]`` and ``[cost]`` tables: those of the mechanism's configuration file
    (``--config``), each table replaced by the one of ``--table`` where that file has it."""
    from jointplay.io.config import design_table_keys, design_tables

    tables = design_tables(config)
    if path is None:
        return tables
    from jointplay.io.config import read_toml

    data = read_toml(path, "--table file")
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
    allowance = value.startswith("+")
    number = parse_quantity(value.removeprefix("+").strip(), "m", field="--clearance-limit")
    if not (number >= 0 if allowance else number > 0):
        raise ConfigError(
            f"--clearance-limit {text!r}: a radial clearance is > 0 and an allowance >= 0; "
            "write an absolute limit such as '80 um', or '+20 um' (the fit's largest radial "
            "clearance plus 20 µm)"
        )
    return (None, number) if allowance else (number, None)


def parse_samples(text: str) -> int | Literal["auto"]:
    """``--samples``: ``auto`` or a positive whole number (at most
    :data:`~jointplay.cli._common.MAX_SAMPLES`)."""
    value = text.strip().lower()
    if value == "auto":
        return "auto"
    if not value.isdigit() or not 1 <= int(value) <= MAX_SAMPLES:
        raise ConfigError(
            f"--samples: expected 'auto' or a whole number from 1 to {MAX_SAMPLES:,}, "
            f"got {text[:40]!r}"
        )
    return int(value)


def parse_process(sampling: str, distribution: str, cpk: list[str]) -> Any:
    """``--sampling``, ``--distribution`` and ``--cpk FEATURE=CPK`` → a
    :class:`~jointplay.tolerance.parts.Process`."""
    from jointplay.tolerance.parts import FEATURES, SAMPLINGS, Process

    capability: dict[str, float] = {}
    for text in cpk:
        feature, sep, value = text.partition("=")
        feature = feature.strip()
        try:
            number = float(value)
        except ValueError:
            number = math.nan
        if not sep or feature not in FEATURES or not (math.isfinite(number) and number > 0):
            raise ConfigError(
                f"--cpk {text[:40]!r}: expected FEATURE=CPK with FEATURE one of "
                f"{', '.join(FEATURES)} and CPK > 0, e.g. 'hole=1.33'"
            )
        capability[feature] = number
    return Process(
        choice(sampling, "--sampling", SAMPLINGS),  # type: ignore[arg-type]
        choice(distribution, "--distribution", ("normal", "uniform")),  # type: ignore[arg-type]
        capability,
    )


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
@with_contact_options()
def design_command(
    out: OutOption,
    require: Annotated[
        list[str],
        typer.Option(
            "--require",
            "-r",
            help="RESPONSE <=|<|>=|> VALUE [UNIT] [@CONFIDENCE], e.g. 'joint_force <= 150 N "
            "@99.73'. Repeatable.",
        ),
    ],
    preset: PresetOption = None,
    config: ConfigOption = None,
    fits: Annotated[
        str,
        typer.Option("--fits", help="Candidate ISO 286 fits, comma-separated."),
    ] = DEFAULT_FITS,
    fit: Annotated[
        list[str] | None,
        typer.Option("--fit", help="Fix a joint's fit, e.g. O2=H7/g6. Repeatable."),
    ] = None,
    classes: Annotated[
        str, typer.Option("--classes", help="Candidate ISO 2768-1 classes, comma-separated.")
    ] = "f,m,c,v",
    confidence: Annotated[
        str,
        typer.Option(
            "--confidence",
            help="Share of parts meeting a requirement (%).",
            rich_help_panel=REQUIREMENTS_PANEL,
        ),
    ] = "99.73 %",
    samples: Annotated[
        str,
        typer.Option(
            "--samples",
            "-n",
            help="Per scheme: N, or auto (blocks of 100).",
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = "auto",
    max_samples: Annotated[
        int,
        typer.Option(
            "--max-samples",
            help="--samples auto: the most per scheme.",
            min=1,
            max=MAX_SAMPLES,
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = 4000,
    sampling: Annotated[
        str,
        typer.Option(
            "--sampling",
            help="parts (each part in its ISO 286 zone) or band (over the fit's worst-case range).",
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = "parts",
    distribution: Annotated[
        str,
        typer.Option(
            "--distribution",
            help="normal (±3σ at the limits) or uniform.",
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = "normal",
    rare_defects: Annotated[
        bool,
        typer.Option(
            "--rare-defects/--no-rare-defects",
            help="Importance sampling for the schemes left undecided (to ~1 DPM).",
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = False,
    cpk: Annotated[
        list[str] | None,
        typer.Option(
            "--cpk",
            help="e.g. hole=1.33 (or pin, length); repeat.",
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = None,
    seed: Annotated[
        int,
        typer.Option(
            "--seed",
            help="Seed (the same for every scheme).",
            min=0,
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = 0,
    truncate: Annotated[
        bool,
        typer.Option(
            "--truncate/--no-truncate",
            help="Normal inputs truncated at their limits.",
            rich_help_panel=SAMPLING_PANEL,
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
            help="Radial clearance that ends a life: '80 um', or '+20 um' over the fit's largest.",
            rich_help_panel=WEAR_PANEL,
        ),
    ] = None,
    update_hours: Annotated[
        str | None,
        typer.Option(
            "--update-hours",
            help="B_p: first wear step, e.g. '200 h'.",
            rich_help_panel=WEAR_PANEL,
        ),
    ] = None,
    table: Annotated[
        Path | None,
        typer.Option(
            "--table",
            help="TOML file with [wear] and [cost] tables (replacing the --config file's).",
            rich_help_panel=WEAR_PANEL,
        ),
    ] = None,
    wear_coefficient: WearCoefficientOption = None,
    hardness: HardnessOption = None,
    contact_options: ContactValues = NO_CONTACT_OPTIONS,
    rtol: RtolOption = None,
    model_check: Annotated[
        bool,
        typer.Option(
            "--model-sensitivity/--no-model-sensitivity",
            help="Re-check the chosen scheme's first 200 samples at the model's range ends.",
        ),
    ] = True,
    settle: SettleOption = 2,
    revolutions: Annotated[
        float,
        typer.Option("--revolutions", help="Analysed revolutions.", rich_help_panel=RUN_PANEL),
    ] = 1.0,
    rpm: RpmOption = None,
    gravity: GravityOption = None,
    backend: BackendOption = "processes",
    workers: WorkersOption = None,
    dask_scheduler: DaskSchedulerOption = None,
    plots: PlotsOption = True,
    progress: ProgressOption = True,
    force: ForceOption = False,
    figure_format: FigureFormatOption = "png",
    max_time: Annotated[
        str | None,
        typer.Option(
            "--max-time",
            help="Time budget, e.g. '10 min'.",
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = None,
    resume: Annotated[
        bool,
        typer.Option(
            "--resume",
            help="Go on from the result in --out.",
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = False,
) -> None:
    """Design study: every fit × length class through the dynamics; the cheapest shown to
    meet the requirements, with its evidence and its drawing callouts.

    A scheme meets a requirement when its yield's 95 % interval lies above --confidence.
    The files written to --out: docs/cli.md.
    """
    from jointplay.io.output import output_dir
    from jointplay.report.design import life_quantile_lines, write_design
    from jointplay.study.design import (
        RareDefects,
        design_study,
        design_units,
        life_settings,
        parse_requirements,
        resolve_responses,
    )
    from jointplay.study.requirements import FUNCTIONAL_LIFE, parse_confidence
    from jointplay.study.sensitivity import model_sensitivity
    from jointplay.tolerance.cost import CostModel

    mechanism = mechanism_from_options(preset, config, rpm=rpm, gravity=gravity)
    kind = choice(responses, "--responses", ("auto", "kinematic", "dynamic"))
    requirements = parse_requirements(mechanism, require)  # once, into typed objects
    level = parse_confidence(confidence, "--confidence")
    count = parse_samples(samples)
    process = parse_process(sampling, distribution, cpk or [])
    given = [setting(key).option for key, v in contact_options.items() if v is not None]
    dynamic = resolve_responses(mechanism, requirements, kind) == "dynamic"  # type: ignore[arg-type]
    if given and not dynamic:
        raise ConfigError(
            f"{', '.join(given)}: contact options apply to dynamic designs only, and every "
            "requirement here is kinematic; add --responses dynamic or drop them"
        )
    contact_used = contact_from_options(
        config, mechanism, "--method", preset=preset, **contact_options
    )
    fit_list = [f.strip() for f in fits.split(",") if f.strip()]
    fixed = parse_joint_fits(fit or [])
    candidates: list[Any] = (
        [{**dict.fromkeys(_fit_joints(mechanism), f), **fixed} for f in fit_list]
        if fixed
        else fit_list
    )
    _note_zero_clearance(mechanism, [*fit_list, *fixed.values()])
    class_list = [c.strip() for c in classes.split(",") if c.strip()]
    limit, allowance = parse_clearance_limit(clearance_limit)
    life_step = _update_hours(update_hours, requirements)
    life_settings(  # a B_p design that cannot run is refused before the folder is touched
        [r for r in requirements if r.quantile is not None], requirements, limit, allowance,
        life_step, RareDefects() if rare_defects else None,
    )  # fmt: skip
    check_revolutions(revolutions, settle)
    data = read_table(table, config)
    cost = CostModel.from_table(data.get("cost", {}))
    wear = wear_settings(data, wear_coefficient, hardness)
    where = backend_from_options(backend, workers, dask_scheduler)
    if where.on_device and not dynamic:
        raise ConfigError(
            f"--backend {where.kind} runs the dynamics: use it with --responses dynamic"
        )
    figure_format = check_figure_format(figure_format)
    budget = parse_max_time(max_time)
    earlier = read_earlier(out) if resume else None
    # the output folder is checked before the study runs
    with output_dir(out, force=force, inputs=(config, table)) as folder:
        options: dict[str, Any] = {
            "samples": count, "max_samples": max_samples, "seed": seed, "process": process,
            "truncate": truncate, "cost": cost, "clearance_limit": limit,
            "clearance_allowance": allowance, "wear": wear, "backend": where,
            "progress": progress,
        }  # fmt: skip
        if life_step is not None:
            options["life_step"] = life_step
        if dynamic:  # the run settings, built once (kinematic designs run no dynamics)
            from jointplay.dynamics.setup import regime_line

            fitted = [j.name for j in mechanism.revolute_joints if j.fit is not None]
            print(regime_line(contact_used, mechanism, fitted))
            options["run_settings"] = run_settings(
                contact_used, settle=settle, revolutions=revolutions, rtol=rtol
            )
        sensitivity = None

        def compute() -> DesignResult:
            nonlocal sensitivity
            with compiling_kernels(needed=dynamic, kernels=BATCH_LANES):
                result = design_study(
                    mechanism,
                    candidates,
                    class_list,
                    requirements,
                    rare=RareDefects() if rare_defects else None,
                    confidence=level,
                    responses=kind,  # type: ignore[arg-type]
                    resume=earlier,
                    max_time=budget,
                    **options,
                )
                sensitivity = (
                    model_sensitivity(mechanism, result, contact_used, **options)
                    if model_check and not result.interrupted
                    else None
                )
            return result

        result, missing = run_study(compute)
        # a dynamic study's samples carry the kinematic responses too (mixed requirements)
        units = {
            **design_units(mechanism, "kinematic"),
            **design_units(mechanism, result.responses),  # type: ignore[arg-type]
            FUNCTIONAL_LIFE: "s",
        }
        summary = result.summary()
        finished = _finished(result, summary["settings"])
        with writing_study(finished, missing):
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
        for line in life_quantile_lines(result):  # B_p: the population's life, under the table
            console.print(f"life: {line}")
        if earlier is not None:
            console.print(runs_line(result.settings))
        if result.settings.get("model", {}).get("contact"):
            console.print(f"contact: {result.settings['model']['contact']}")
        if sensitivity is not None:
            console.print(f"model sensitivity: {sensitivity.verdict}")
        study_kept(result.interrupted, finished, missing)
    console.print(f"results written to {out}")


#: How the design's own advice names its settings on the command line.
DESIGN_OPTIONS = {**SETTING_OPTIONS, "max_time": "--max-time", "resume": "--resume"}


def _update_hours(text: str | None, requirements: Any) -> float | None:
    """``--update-hours``: the first step of each sample's functional life, s; refused
    without a B_p requirement (nothing would use it)."""
    if text is None:
        return None
    if not any(r.quantile is not None for r in requirements):
        raise ConfigError(
            "--update-hours steps the functional life of a B_p requirement (e.g. --require "
            "'B10 >= 2000 h'); drop it or add one"
        )
    return quantity_option(text, "s", "--update-hours", example="h", positive=True)


def parse_max_time(text: str | None) -> float | None:
    """``--max-time``: a duration with its unit (``'10 min'``, ``'1.5 h'``), s."""
    if text is None:
        return None
    seconds = parse_quantity(text, "s", field="--max-time", example="min")
    if not (math.isfinite(seconds) and seconds > 0):
        raise ConfigError(f"--max-time {text!r}: a time budget is > 0, e.g. '10 min'")
    return seconds


def _finished(result: DesignResult, settings: Any) -> tuple[int, int, str]:
    """What a study finished, for an interrupt's message and the folder's completeness: the
    schemes; an interrupted study (every scheme has a row after its first block) its samples
    of the most its schemes could take, so that it never reads as complete and a later
    interrupted run with more samples reads as more complete."""
    schemes = int(settings["schemes"])
    if not result.interrupted or not len(result.table):
        # a finished study has every scheme judged or not needed (the cost-ordered schedule
        # leaves dearer schemes unrun once a cheaper one is shown to meet)
        done = schemes if not result.interrupted else len(result.table)
        return done, schemes, "schemes"
    done = int(result.table["samples"].sum())
    return done, max(done + 1, schemes * int(settings["max_samples"])), "samples"


def read_earlier(out: Path) -> Any:
    """``--resume``: the design result in ``out`` (its ``summary.json`` settings and
    ``samples.parquet``) as a :class:`~jointplay.study.design.Earlier`, or one ConfigError
    line saying why it cannot be resumed."""
    import json

    import pandas as pd

    from jointplay.study.design import Earlier

    summary, samples = Path(out) / "summary.json", Path(out) / "samples.parquet"
    if not summary.is_file() or not samples.is_file():
        raise ConfigError(
            f"--resume: {str(out)!r} holds no design result (summary.json and samples.parquet); "
            "run the study without --resume first"
        )
    try:
        settings = json.loads(summary.read_text(encoding="utf-8")).get("settings", {})
        frame = pd.read_parquet(samples)
    except (OSError, ValueError, AttributeError) as exc:
        raise ConfigError(f"--resume: cannot read the result in {str(out)!r}: {exc}") from None
    if not isinstance(settings, dict) or "scheme" not in frame:
        raise ConfigError(f"--resume: {str(out)!r} holds no design result; run without --resume")
    return Earlier(str(out), settings, frame)


def runs_line(settings: Any) -> str:
    """What a resumed study merged, e.g. ``resumed: 2 runs merged (run 1: 3,200 samples; run
    2: 1,600 computed, 3,200 kept)``."""
    runs = list(settings.get("runs") or [])
    parts = [
        f"run {r['run']}: {int(r['samples_computed']):,} computed"
        + (" (interrupted)" if r.get("interrupted") else "")
        for r in runs
    ]
    kept = int(runs[-1]["samples_kept"]) if runs else 0
    return f"resumed: {len(runs)} runs merged, {kept:,} samples kept ({'; '.join(parts)})"


def _note_zero_clearance(mechanism: Any, fits: list[str]) -> None:
    """A note on stderr for each named fit whose smallest radial clearance is zero (H7/h6)."""
    from jointplay.tolerance import iso286

    diameters = sorted({j.fit.diameter for j in mechanism.revolute_joints if j.fit is not None})
    for name in dict.fromkeys(fits):
        for diameter in diameters:
            try:
                result = iso286.fit(name, diameter)
            except JointplayError:
                continue  # reported by the study, with the joint
            if result.radial_clearance_min <= 0 < result.radial_clearance_max:
                print(
                    f"jointplay: note: {result.designation} has a zero minimum radial clearance at "
                    f"Ø{diameter * 1e3:g} mm (0 … {result.radial_clearance_max * 1e6:.3g} µm): its "
                    "samples near the lower limit leave the pin almost no room, where the "
                    "clearance-joint model is least reliable",
                    file=sys.stderr,
                )
                break


def _fit_joints(mechanism: Any) -> list[str]:
    return [j.name for j in mechanism.revolute_joints if j.fit is not None]


#: The longest scheme label a terminal table prints as it is; longer ones (a fit per joint)
#: are printed as S1, S2, ... with a key under the table.
SHORT_LABEL = 12


def scheme_labels(schemes: list[str]) -> dict[str, str]:
    """Each scheme's label in the terminal tables: itself where at most
    :data:`SHORT_LABEL` characters, else ``S<n>`` (numbered in the tables' order)."""
    labels: dict[str, str] = {}
    long = 0
    for scheme in schemes:
        if len(scheme) <= SHORT_LABEL:
            labels[scheme] = scheme
        else:
            long += 1
            labels[scheme] = f"S{long}"
    return labels


def _one_line(table: Any, *columns: int) -> Any:
    """``table`` with the given columns never wrapped: each as wide as its widest cell."""
    for i in columns:
        column = table.columns[i]
        cells = [str(getattr(cell, "plain", cell)) for cell in column.cells]
        column.min_width = max([column.min_width or 0, *map(len, cells)])
    return table


def _print(result: DesignResult, units: dict[str, str]) -> None:
    """The schemes in two tables that read at 80 columns: the yields (all requirements, with
    their exact 95 % interval on one line) and the requirements' responses at the level, each
    with its unit; long scheme labels as S1, S2, ... with their key."""
    from rich.table import Table

    from jointplay.report.design import (
        YIELD_ALL,
        display,
        evidence_line,
        stop_line,
        verdict_interval,
    )

    table = result.table
    level = f"{100 * result.confidence:g} %"
    ordered = table.sort_values("cost") if len(table) else table
    labels = scheme_labels([str(s) for s in ordered["scheme"]]) if len(table) else {}
    grid = Table(box=None, title="schemes by cost", title_justify="left")
    headers = ["scheme", "cost", "samples", f"{YIELD_ALL}, %", "95 % CI, %", "DPM, 95 % upper"]
    headers.append("verdict")
    for header in headers:
        grid.add_column(header, justify="left" if header in ("scheme", "verdict") else "right")
    required = list(dict.fromkeys(r.response for r in result.requirements))
    values = Table(box=None, title=f"responses at {level}", title_justify="left")
    values.add_column("scheme", justify="left")
    for name in required:
        unit, _ = display(units.get(name, ""))
        values.add_column(f"{name} ({unit or '1'})", justify="right")
    modelled = False
    for _, row in ordered.iterrows():
        label = labels[str(row["scheme"])]
        grid.add_row(
            label,
            f"{row['cost']:.3g}",
            f"{row['samples']:,}",
            f"{row['yield']:.2f}",
            f"{row['yield_low']:.2f}–{row['yield_high']:.2f}",
            f"{row['dpm_high']:,.0f}",
            str(row["verdict"]),
        )
        cells = [label]
        for name in required:
            _, scale = display(units.get(name, ""))
            model = row[f"{name}_at_confidence_basis"] == "normal-model"
            modelled |= model
            cells.append(f"{row[f'{name}_at_confidence'] * scale:.4g}" + (" *" if model else ""))
        values.add_row(*cells)
    console.print(_one_line(whole_headers(grid), 0, 4))
    if required and len(table):
        console.print(_one_line(whole_headers(values), 0))
    for scheme, label in labels.items():
        if label != scheme:
            console.print(f"{label}: {scheme}")
    if len(table):
        stopped = stop_line(result)
        console.print(
            f"verdicts on the {verdict_interval(result)}; samples: what each took"
            + (f"; {stopped}" if stopped else "")
        )
    if modelled:
        console.print(
            f"* normal-model estimate (mean + z·std), not a bound: fewer samples than a "
            f"distribution-free bound at {level} needs; the others are 95 % order-statistic bounds"
        )
    best = result.best_row
    if best is not None:
        regime = f" — {result.lubrication}" if result.lubrication else ""
        line = (
            f"choose {result.best}{regime}: relative cost {best['cost']:.3g}; "
            f"{evidence_line(result, best)}"
        )
        console.print(line)
        for callout in result.drawing:
            console.print(f"  drawing: {callout.text}")
    if best is None:
        console.print(result.verdict)
    elif result.to_decide is not None:
        console.print(f"cheaper, {result.what_decides(SETTING_OPTIONS)}")
    timed = result.what_times(DESIGN_OPTIONS)
    if timed is not None:
        console.print(timed)
    for finding in result.diagnostics:  # one line each, on stderr, as `jointplay tolerance`
        print(f"jointplay: {finding.line(SETTING_OPTIONS)}", file=sys.stderr)
