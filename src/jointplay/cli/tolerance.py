"""``jointplay tolerance``: how the tolerance stack and the joint clearances spread the responses.

Import-light: NumPy, SciPy, pandas, Numba and Dask load when the command runs, not when the
CLI starts (``jointplay --help``).
"""

from __future__ import annotations

import sys
from enum import StrEnum
from typing import TYPE_CHECKING, Annotated, Any

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
    OutOption,
    PlotsOption,
    PresetOption,
    ProgressOption,
    RpmOption,
    WorkersOption,
    check_figure_format,
    compiling_kernels,
    provenance,
    run_study,
    study_kept,
    whole_headers,
    writing_study,
)
from jointplay.cli._panels import EXECUTION_PANEL
from jointplay.cli._simulation import (
    NO_CONTACT_OPTIONS,
    SETTING_OPTIONS,
    ContactValues,
    RtolOption,
    run_settings,
    with_contact_options,
)
from jointplay.errors import ConfigError
from jointplay.settings.mechanism import crank_speed, parse_gravity
from jointplay.settings.simulation import check_revolutions, contact_from_options
from jointplay.units import parse_quantity

if TYPE_CHECKING:
    from jointplay.execution.backends import Backend
    from jointplay.tolerance.analysis import ToleranceStudyResult
    from jointplay.tolerance.methods import SpecLimits

console = Console(highlight=False, soft_wrap=True)
#: Width of tables when the output is not a terminal (files, pipes, tests).
REPORT_WIDTH = 140


class Method(StrEnum):
    """Tolerance analysis methods."""

    monte_carlo = "monte-carlo"
    worst_case = "worst-case"
    rss = "rss"


class Responses(StrEnum):
    """Response sets."""

    kinematic = "kinematic"
    dynamic = "dynamic"
    running = "running"


class Sampling(StrEnum):
    """Monte Carlo sampling."""

    random = "random"
    lhs = "lhs"


class StartMode(StrEnum):
    """Start of the motion in dynamic studies."""

    steady = "steady"
    rest = "rest"
    impulsive = "impulsive"


class Distribution(StrEnum):
    """Distribution of every toleranced quantity."""

    uniform = "uniform"
    normal = "normal"
    triangular = "triangular"


#: ``--backend``: where the samples run (shared with ``jointplay design``).
BackendOption = Annotated[
    str,
    typer.Option(
        "--backend",
        help="local, processes (default), dask or gpu (pip install 'jointplay[gpu]').",
        rich_help_panel=EXECUTION_PANEL,
    ),
]


def backend_from_options(kind: str, workers: int | None, dask_scheduler: str | None) -> Backend:
    """The execution backend of ``--backend``, ``--workers`` and ``--dask-scheduler``.

    ``--dask-scheduler`` alone means ``--backend dask``; ``serial`` is another name of
    ``local``; ``--workers`` applies to local processes only.
    """
    from jointplay.execution.backends import ALIASES, BACKENDS, Backend

    kind = kind.strip().lower()
    if kind not in (*BACKENDS, *ALIASES):
        raise ConfigError(
            f"--backend must be {', '.join(BACKENDS[:-1])} or {BACKENDS[-1]}, got {kind!r}"
        )
    if dask_scheduler is not None and kind == "processes":
        kind = "dask"
    if kind == "dask":
        if dask_scheduler is None:
            raise ConfigError("--backend dask needs the scheduler's address: give --dask-scheduler")
        if workers is not None:
            raise ConfigError("--workers applies to local processes; the Dask cluster has its own")
        try:
            return Backend.dask(dask_scheduler)
        except ConfigError as error:  # the address is the one setting it checks here
            raise ConfigError(f"--dask-scheduler: {error}") from None
    if dask_scheduler is not None:
        raise ConfigError(f"--dask-scheduler applies to --backend dask, not {kind}")
    if workers is not None and kind != "processes":
        raise ConfigError(f"--workers applies to --backend processes, not {kind}")
    return Backend(kind, workers=workers)  # type: ignore[arg-type]


class CornerMode(StrEnum):
    """Worst-case corners."""

    auto = "auto"
    all = "all"
    sensitivity = "sensitivity"


@app.command("tolerance")
@with_contact_options(
    renamed={
        "method": (
            "--paper-method",
            "Dynamic: simulate's --method (a contact method of the paper's Table 2; here "
            "--method is the tolerance method).",
        )
    }
)
def tolerance_command(
    out: OutOption,
    force: ForceOption = False,
    preset: PresetOption = None,
    config: ConfigOption = None,
    method: Annotated[
        Method, typer.Option("--method", help="monte-carlo, worst-case (corners) or rss.")
    ] = Method.monte_carlo,
    samples: Annotated[
        int, typer.Option("--samples", "-n", help="Monte Carlo samples.", min=1, max=MAX_SAMPLES)
    ] = 1000,
    seed: Annotated[
        int, typer.Option("--seed", help="Seed: the same seed gives the same samples.", min=0)
    ] = 0,
    sampling: Annotated[
        Sampling, typer.Option("--sampling", help="Monte Carlo: random or lhs (Latin hypercube).")
    ] = Sampling.random,
    responses: Annotated[
        Responses,
        typer.Option(
            "--responses",
            help="kinematic (ideal joints), dynamic (clearance joints: peaks) or running "
            "(dynamic plus the running responses, docs/cli.md).",
        ),
    ] = Responses.kinematic,
    distribution: Annotated[
        Distribution | None,
        typer.Option(
            "--distribution",
            help="uniform, normal or triangular, for every toleranced quantity (default: the "
            "configuration's).",
        ),
    ] = None,
    clearances: Annotated[
        bool,
        typer.Option(
            "--clearances/--no-clearances",
            help="Dynamic: clearances drawn within their fits (off: as configured).",
        ),
    ] = True,
    contact_options: ContactValues = NO_CONTACT_OPTIONS,
    rtol: RtolOption = None,
    start: Annotated[
        StartMode,
        typer.Option(
            "--start",
            help="Dynamic: steady (the nominal motion), rest (the paper's start-up) or impulsive.",
        ),
    ] = StartMode.steady,
    settle: Annotated[
        int,
        typer.Option(
            "--settle",
            help="Dynamic: start-up revolutions left out (--start rest --settle 0: the "
            "paper's start-up peaks).",
        ),
    ] = 2,
    revolutions: Annotated[
        float,
        typer.Option("--revolutions", help="Dynamic: analysed revolutions after --settle."),
    ] = 1.0,
    rpm: RpmOption = None,
    gravity: GravityOption = None,
    corners: Annotated[
        CornerMode,
        typer.Option(
            "--corners",
            help="Worst case: all 2^k corners, sensitivity-sign ones or auto (all for <= 10 "
            "inputs).",
        ),
    ] = CornerMode.auto,
    fd_step: Annotated[
        float,
        typer.Option(
            "--fd-step",
            help="RSS, sensitivity corners: difference step, share of a half-width.",
        ),
    ] = 0.5,
    require: Annotated[
        list[str] | None,
        typer.Option(
            "--require",
            "-r",
            help="RESPONSE <=|<|>=|> VALUE [UNIT], e.g. 'omega4_peak <= 16 rad/s' (a lower "
            "and an upper one: two spec limits). Repeatable.",
        ),
    ] = None,
    spec_limit: Annotated[
        list[str] | None,
        typer.Option(
            "--spec-limit",
            help="Deprecated: use --require. RESPONSE=LO:HI with units, e.g. "
            "'omega4_peak=:16 rad/s'.",
        ),
    ] = None,
    backend: BackendOption = "processes",
    workers: WorkersOption = None,
    dask_scheduler: DaskSchedulerOption = None,
    plots: PlotsOption = True,
    progress: ProgressOption = True,
    figure_format: FigureFormatOption = "png",
) -> None:
    """Tolerance study: spread of the responses, out-of-spec share and what matters most.

    Writes DIR/report.html, samples.parquet, summary.json and plots; what each holds:
    docs/cli.md.
    """
    if responses is Responses.dynamic and method is Method.monte_carlo:
        # the batch engine's worker processes start first, so that their start-up overlaps
        # this command's imports and set-up (a second of a 1 000-sample study here)
        from jointplay.tolerance.execution import start_batch_workers
        from jointplay.tolerance.responses import DynamicResponses

        where = backend_from_options(backend, workers, dask_scheduler)
        start_batch_workers(where, samples, DynamicResponses.seconds_per_sample)
    from jointplay.execution.pool import running_pool
    from jointplay.io.config import load_study_spec
    from jointplay.io.output import output_dir
    from jointplay.report.tolerance import write_study
    from jointplay.tolerance.analysis import response_units, tolerance_study
    from jointplay.tolerance.methods import MonteCarlo, Rss, ToleranceMethod, WorstCase

    figure_format = check_figure_format(figure_format)
    with output_dir(out, force=force, inputs=(config,)) as folder:
        mechanism, spec = load_study_spec(preset, config)
        _check_lengths(spec)
        if rpm is not None:
            mechanism = mechanism.with_driver(speed=crank_speed(rpm))
        if gravity is not None:
            mechanism = mechanism.with_gravity(parse_gravity(gravity))
        if distribution is not None:
            spec = spec.with_distribution(distribution.value)
        dynamic = responses is not Responses.kinematic
        if dynamic and not clearances:
            spec = spec.only("length")
        check_revolutions(revolutions, settle)
        law = None
        if dynamic:
            from jointplay.dynamics.setup import regime_line

            law = contact_from_options(
                config, mechanism, "--paper-method", preset=preset, **contact_options
            )
            fitted = [j.name for j in mechanism.revolute_joints if j.fit is not None]
            print(regime_line(law, mechanism, fitted))
        elif any(v is not None for v in contact_options.values()):
            raise ConfigError("contact options apply to --responses dynamic or running only")
        if rtol is not None and not dynamic:
            raise ConfigError("--rtol applies to --responses dynamic or running only")
        where = backend_from_options(backend, workers, dask_scheduler)
        if where.on_device and not dynamic:
            raise ConfigError(
                f"--backend {where.kind} runs the dynamics: use it with --responses dynamic"
            )
        run = (
            None
            if law is None
            else run_settings(
                law, start=start.value, settle=settle, revolutions=revolutions, rtol=rtol
            )
        )
        units = response_units(mechanism, spec, responses.value, run_settings=run)
        limits = parse_spec_limits(spec_limit or [], units)
        if spec_limit:  # after parsing: a malformed one is still one error line
            print(
                "jointplay: warning: --spec-limit is deprecated and will be removed; write "
                "--require 'RESPONSE <= VALUE UNIT' (and >= for a lower limit), as in design",
                file=sys.stderr,
            )
        for name, limit in limits_from_requirements(require or [], units).items():
            if name in limits:
                raise ConfigError(f"--require and --spec-limit both limit {name!r}: give one")
            limits[name] = limit
        analysis: ToleranceMethod
        if method is Method.monte_carlo:
            analysis = MonteCarlo(samples=samples, seed=seed, sampling=sampling.value)
        elif method is Method.rss:
            analysis = Rss(fd_step=fd_step)
        else:
            analysis = WorstCase(corners=corners.value, fd_step=fd_step)

        def compute() -> ToleranceStudyResult:
            with compiling_kernels(needed=dynamic, kernels=BATCH_LANES):
                return tolerance_study(
                    mechanism,
                    spec,
                    method=analysis,
                    responses=responses.value,
                    limits=limits,
                    run_settings=run,
                    backend=where,
                    progress=progress,
                )

        study, missing = run_study(compute)
        summary = study.summary()
        counts = summary["counts"]
        finished = (counts["ok"] + counts["failed"], counts["points"], "points")
        with writing_study(finished, missing):
            write_study(
                study,
                folder,
                plots=plots,
                provenance=provenance(summary["configuration"]),
                figure_format=figure_format,
                executor=running_pool(),  # the batch engine's idle workers draw plots too
            )
        _print(study)
        if study.model.get("contact"):
            console.print(f"contact: {study.model['contact']}")
        study_kept(study.interrupted, finished, missing)
    console.print(f"results written to {out}")


def _check_lengths(spec: Any) -> None:
    """Toleranced lengths must stay positive and plausible over their whole range."""
    from jointplay.io.config import MAX_LENGTH

    for item in spec.inputs:
        if getattr(item, "kind", None) != "length":
            continue
        low, high = item.tolerance.lower, item.tolerance.upper
        if not (low > 0 and high <= MAX_LENGTH):
            raise ConfigError(
                f"tolerances.lengths.{item.length}: the limits {low * 1e3:g} to {high * 1e3:g} mm "
                f"of a {item.nominal * 1e3:g} mm length are impossible geometry (a length stays "
                f"positive and below {MAX_LENGTH:g} m); check the deviations"
            )


def limits_from_requirements(texts: list[str], units: dict[str, str]) -> dict[str, SpecLimits]:
    """``--require`` texts (design's grammar, :func:`~jointplay.study.requirements.
    parse_requirement`) to spec limits: ``<=``/``<`` give the upper limit, ``>=``/``>`` the
    lower (both inclusive, as spec limits are); no ``@confidence`` (a tolerance study
    reports the share out of spec instead)."""
    from jointplay.study.requirements import parse_requirement
    from jointplay.tolerance.methods import SpecLimits

    bounds: dict[str, dict[str, float]] = {}
    for text in texts:
        requirement = parse_requirement(text, units)
        if requirement.confidence is not None:
            raise ConfigError(
                f"--require {text!r}: a tolerance study takes no @confidence (it reports the "
                "share out of spec); leave it out"
            )
        side = "upper" if requirement.upper else "lower"
        limits = bounds.setdefault(requirement.response, {})
        if side in limits:
            raise ConfigError(f"--require: two {side} limits on {requirement.response!r}")
        limits[side] = requirement.limit
    return {
        name: SpecLimits(limits.get("lower"), limits.get("upper"))
        for name, limits in bounds.items()
    }


def parse_spec_limits(texts: list[str], units: dict[str, str]) -> dict[str, SpecLimits]:
    """``RESPONSE=LO:HI`` strings (quantities with units; one side may be empty) to SI limits."""
    from jointplay.tolerance.methods import SpecLimits

    limits: dict[str, SpecLimits] = {}
    for text in texts:
        name, sep, rest = text.partition("=")
        name = name.strip()
        if not sep or ":" not in rest:
            raise ConfigError(
                f"--spec-limit {text!r}: write RESPONSE=LO:HI with units, e.g. "
                "'omega4_peak=:16 rad/s' or 'rocker_swing=52 deg:53.5 deg'"
            )
        if name not in units:
            raise ConfigError(
                f"--spec-limit: unknown response {name!r}; responses: {', '.join(units)}"
            )
        if name in limits:
            raise ConfigError(f"--spec-limit: {name!r} given twice")
        low_text, high_text = (part.strip() for part in rest.split(":", 1))
        field = f"--spec-limit {name}"
        limits[name] = SpecLimits(
            parse_quantity(low_text, units[name], field=field) if low_text else None,
            parse_quantity(high_text, units[name], field=field) if high_text else None,
        )
    return limits


def _print(study: ToleranceStudyResult) -> None:
    from rich.table import Table

    from jointplay.report.tolerance import display_scale, format_value, input_label

    result = study.result
    method = result.method
    headers = ["response", "nominal"]
    if method == "monte-carlo":
        headers += ["mean", "std", "min", "max"]
    elif method == "worst-case":
        headers += ["low", "high"]
    else:
        headers += ["mean", "std", "± RSS"]
    if study.ideal is not None:
        headers.append("ideal joints")
    has_limits = any(s.limits is not None for s in result.summaries.values())
    if has_limits:
        headers += ["out of spec %", "Cpk"]
    headers.append("most influential")
    table = Table(box=None)
    for header in headers:
        left = header in ("response", "most influential")
        table.add_column(header, justify="left" if left else "right", no_wrap=left)
    for name, item in result.summaries.items():
        unit, scale = display_scale(item.unit)
        row = [f"{name} ({unit})", format_value(item.nominal, scale)]
        if method == "monte-carlo":
            row += [
                format_value(v, scale) for v in (item.mean, item.std, item.minimum, item.maximum)
            ]
        elif method == "worst-case":
            row += [format_value(item.minimum, scale), format_value(item.maximum, scale)]
        else:
            row += [format_value(v, scale) for v in (item.mean, item.std, item.half_range)]
        if study.ideal is not None:
            row.append(format_value(study.ideal.get(name), scale))
        if has_limits:
            row += [format_value(item.out_of_spec_percent), format_value(item.cpk)]
        top = item.most_influential
        row.append(f"{input_label(top)} {100 * item.contributions[top]:.0f} %" if top else "–")
        table.add_row(*row)
    wide = console if console.is_terminal else Console(highlight=False, width=REPORT_WIDTH)
    wide.print(whole_headers(table))
    for name, item in result.summaries.items():
        if item.note:
            console.print(f"note on {name}: {item.note}")
    failures = result.failures
    if failures:
        console.print(
            f"{len(failures)} point(s) failed (listed in summary.json and samples.parquet):"
        )
        for failure in failures[:5]:
            inputs = ", ".join(f"{k} = {v:.6g}" for k, v in failure.inputs.items())
            console.print(f"  #{failure.index} ({inputs}): {failure.error}")
        if len(failures) > 5:
            console.print(f"  … and {len(failures) - 5} more")
    for finding in study.diagnostics:  # one line each, on stderr, as `jointplay simulate`
        print(f"jointplay: {finding.line(SETTING_OPTIONS)}", file=sys.stderr)
