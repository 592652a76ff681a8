"""``jointplay life``: the life distribution of a production population — B10, B50 and the
Weibull life of the mechanisms built to one drawing, each worn until its first requirement
fails through the wear-coupled dynamics.

Import-light: NumPy, SciPy and the dynamics load when the command runs.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import typer
from rich.console import Console

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
    compiling_kernels,
    provenance,
)
from jointplay.cli._panels import (
    RUN_PANEL,
    SAMPLING_PANEL,
    WEAR_PANEL,
)
from jointplay.cli._simulation import (
    NO_CONTACT_OPTIONS,
    ContactValues,
    RtolOption,
    run_settings,
    with_contact_options,
)
from jointplay.cli.tolerance import BackendOption, backend_from_options
from jointplay.errors import ConfigError
from jointplay.settings.mechanism import mechanism_from_options, quantity_option
from jointplay.settings.simulation import check_revolutions, contact_from_options

console = Console(highlight=False, soft_wrap=True)


def parse_share(text: str, option: str, example: str) -> float:
    """A share in % (``"10 %"``, ``"10"``) → a fraction in (0, 1)."""
    value = text.strip()
    number = value.removesuffix("%").strip()
    try:
        share = float(number) / 100.0
    except ValueError:
        share = float("nan")
    if not 0.0 < share < 1.0:
        raise ConfigError(
            f"{option}: expected a share in % between 0 and 100, e.g. {example!r}, got "
            f"{text[:40]!r}"
        )
    return share


@app.command("life")
@with_contact_options()
def life_command(
    out: OutOption,
    hours: Annotated[
        str,
        typer.Option(
            "--hours",
            help="Operating time simulated, e.g. '2000 h'; longer lives are censored there.",
            rich_help_panel=WEAR_PANEL,
        ),
    ],
    preset: PresetOption = None,
    config: ConfigOption = None,
    fit: Annotated[
        list[str] | None,
        typer.Option(
            "--fit",
            help="ISO 286 fit of every pin joint (H8/g7), or of one joint (O2=H7/g6). "
            "Repeatable. Default: the mechanism's own.",
        ),
    ] = None,
    length_class: Annotated[
        str, typer.Option("--class", help="ISO 2768-1 class of the link lengths.")
    ] = "m",
    require: Annotated[
        list[str] | None,
        typer.Option(
            "--require",
            "-r",
            help="What each mechanism must keep meeting: RESPONSE <=|<|>=|> VALUE UNIT, e.g. "
            "'rocker_speed_error <= 2 %'. Repeatable.",
        ),
    ] = None,
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
            help="First step between re-simulations, e.g. '50 h' (default --hours / 10).",
            rich_help_panel=WEAR_PANEL,
        ),
    ] = None,
    fixed_steps: Annotated[
        bool,
        typer.Option(
            "--fixed-steps",
            help="Steps of --update-hours, none rejected (noisy dry wear: same lives).",
            rich_help_panel=WEAR_PANEL,
        ),
    ] = False,
    tolerance: Annotated[
        str,
        typer.Option(
            "--tolerance",
            help="Relative error of each step's clearance growth and of each life.",
            rich_help_panel=WEAR_PANEL,
        ),
    ] = "1 %",
    samples: Annotated[
        str,
        typer.Option(
            "--samples",
            "-n",
            help="Mechanisms: a number, or auto (100, 200, 400, ... until --precision).",
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = "auto",
    max_samples: Annotated[
        int,
        typer.Option(
            "--max-samples",
            help="--samples auto: the most mechanisms.",
            min=1,
            max=MAX_SAMPLES,
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = 2000,
    precision: Annotated[
        str,
        typer.Option(
            "--precision",
            help="--samples auto: B10's 90 % interval half-width, as a share of B10.",
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = "10 %",
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
    cpk: Annotated[
        list[str] | None,
        typer.Option(
            "--cpk",
            help="FEATURE=CPK (hole, pin, length), e.g. hole=1.33. Repeatable.",
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = None,
    seed: Annotated[
        int, typer.Option("--seed", help="Seed.", min=0, rich_help_panel=SAMPLING_PANEL)
    ] = 0,
    truncate: Annotated[
        bool,
        typer.Option(
            "--truncate/--no-truncate",
            help="Normal inputs truncated at their limits.",
            rich_help_panel=SAMPLING_PANEL,
        ),
    ] = True,
    table: Annotated[
        Path | None,
        typer.Option(
            "--table",
            help="TOML file with a [wear] table (replacing the --config file's).",
            rich_help_panel=WEAR_PANEL,
        ),
    ] = None,
    wear_coefficient: WearCoefficientOption = None,
    hardness: HardnessOption = None,
    contact_options: ContactValues = NO_CONTACT_OPTIONS,
    rtol: RtolOption = None,
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
) -> None:
    """Population life: mechanisms as made (as design draws them), each worn through the
    re-simulated dynamics until its first requirement fails; B10 with its interval, the
    censored Weibull fit and which requirement fails first. Files: docs/life.md.
    """
    from jointplay.cli.design import (
        parse_clearance_limit,
        parse_joint_fits,
        parse_process,
        parse_samples,
        read_table,
        wear_settings,
    )
    from jointplay.io.output import output_dir
    from jointplay.report.life import write_life
    from jointplay.study.life import parse_life_requirements, population_life

    mechanism = mechanism_from_options(preset, config, rpm=rpm, gravity=gravity)
    horizon = quantity_option(hours, "s", "--hours", example="h", positive=True)
    first = (
        None
        if update_hours is None
        else quantity_option(update_hours, "s", "--update-hours", example="h", positive=True)
    )
    if first is not None and first > horizon:
        raise ConfigError(
            f"--update-hours {update_hours!r} is longer than --hours {hours!r}; give a first "
            "step within the hours, e.g. a tenth of them"
        )
    share = parse_share(tolerance, "--tolerance", "1 %")
    if share >= 0.5:
        raise ConfigError(
            f"--tolerance: expected a share below 50 %, e.g. '1 %', got {tolerance!r}"
        )
    wanted = parse_share(precision, "--precision", "10 %")
    requirements = parse_life_requirements(mechanism, require or [])
    limit, allowance = parse_clearance_limit(clearance_limit)
    if not requirements and limit is None and allowance is None:
        raise ConfigError(
            "nothing ends a life: give --require (e.g. 'rocker_speed_error <= 2 %') or "
            "--clearance-limit (e.g. '+20 um')"
        )
    scheme_fit = _scheme_fit(mechanism, fit or [], parse_joint_fits)
    count = parse_samples(samples)
    process = parse_process(sampling, distribution, cpk or [])
    check_revolutions(revolutions, settle)
    wear = wear_settings(read_table(table, config), wear_coefficient, hardness)
    where = backend_from_options(backend, workers, dask_scheduler)
    figure_format = check_figure_format(figure_format)
    contact_used = contact_from_options(
        config, mechanism, "--method", preset=preset, **contact_options
    )
    settings = run_settings(contact_used, settle=settle, revolutions=revolutions, rtol=rtol)
    with output_dir(out, force=force, inputs=(config, table)) as folder:
        from jointplay.dynamics.setup import regime_line

        fitted = [j.name for j in mechanism.revolute_joints if j.fit is not None]
        print(regime_line(contact_used, mechanism, fitted))
        say = (lambda line: console.print(f"  {line}", style="dim")) if progress else None
        with compiling_kernels():
            result = population_life(
                mechanism,
                scheme_fit,
                length_class,
                requirements,
                hours=horizon,
                samples=count,
                max_samples=max_samples,
                precision=wanted,
                seed=seed,
                process=process,
                clearance_limit=limit,
                clearance_allowance=allowance,
                wear=wear,
                run_settings=settings,
                first_step=first,
                min_step=(first or horizon / 10.0) if fixed_steps else None,
                tolerance=share,
                truncate=truncate,
                backend=where,
                progress=say,
            )
        write_life(
            result,
            folder,
            plots=plots,
            provenance=provenance(
                {**result.summary()["settings"], "contact": contact_used.describe(mechanism)}
            ),
            figure_format=figure_format,
        )
    console.print(result.headline())
    for line in result.lines():
        console.print(line)
    console.print(f"results written to {out}")


def _scheme_fit(mechanism: Any, texts: list[str], parse_joint_fits: Any) -> Any:
    """``--fit``: one fit for every pin joint, per-joint fits, or the mechanism's own."""
    own = {j.name: j.fit.fit for j in mechanism.revolute_joints if j.fit is not None}
    whole = [t for t in texts if "=" not in t]
    if len(whole) > 1:
        raise ConfigError(
            f"--fit: one fit for every joint, got {len(whole)} ({', '.join(whole)}); name the "
            "others per joint, e.g. --fit H8/g7 --fit O2=H7/g6"
        )
    named = parse_joint_fits([t for t in texts if "=" in t])
    base = dict.fromkeys(own, whole[0]) if whole else dict(own)
    chosen = {**base, **named}
    missing = sorted(j for j, f in chosen.items() if f is None)
    if missing or not chosen:
        raise ConfigError(
            "--fit: no fit for joint(s) "
            f"{', '.join(missing) or '(none with a diameter)'}; give one, e.g. --fit H8/g7"
        )
    return chosen
