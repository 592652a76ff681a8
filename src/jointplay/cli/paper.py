"""``jointplay paper``: the paper's study end to end — the README's main job.

The module imports only Typer and Rich at the top; the study and the report (NumPy, pandas,
SciPy, Numba, matplotlib) are imported when the command runs, so that ``jointplay --help``
stays fast.
"""

from __future__ import annotations

import math
import time
from typing import Annotated

import typer
from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TextColumn,
    TimeElapsedColumn,
)

from jointplay.cli._app import app
from jointplay.cli._common import (
    COMPILE_NOTICE,
    FigureFormatOption,
    ForceOption,
    OutOption,
    ProgressOption,
    check_figure_format,
    provenance,
)
from jointplay.errors import ConfigError
from jointplay.settings.mechanism import crank_speed
from jointplay.settings.simulation import check_revolutions


@app.command("paper")
def paper_command(
    out: OutOption,
    force: ForceOption = False,
    progress_shown: ProgressOption = True,
    rpm: Annotated[
        str,
        typer.Option(
            "--rpm",
            help="Crank speed with a unit, e.g. '200 rpm' (the paper's) or '20.9 rad/s'; "
            "a bare number is refused.",
        ),
    ] = "200 rpm",
    revolutions: Annotated[
        float,
        typer.Option(
            "--revolutions", help="Crank revolutions simulated from rest per method and case."
        ),
    ] = 1.0,
    ecs_source: Annotated[
        str,
        typer.Option(
            "--ecs-source", help="ECS parameters of the ECS methods: both, paper or computed."
        ),
    ] = "both",
    corners: Annotated[
        bool,
        typer.Option(
            "--corners/--no-corners",
            help="Simulate all 16 length-tolerance corners (else only all-upper and all-lower).",
        ),
    ] = True,
    workers: Annotated[
        int | None,
        typer.Option("--workers", help="Local worker processes for the simulations (default 2)."),
    ] = None,
    dask_scheduler: Annotated[
        str | None,
        typer.Option(
            "--dask-scheduler",
            help="Run the simulations on the Dask distributed cluster at ADDRESS "
            "(e.g. tcp://host:8786).",
        ),
    ] = None,
    experiment_revolutions: Annotated[
        int,
        typer.Option(
            "--experiment-revolutions",
            help="Revolutions of the steady runs compared with Table 7 (the last one is used).",
        ),
    ] = 3,
    figure_format: FigureFormatOption = "png",
    animation: Annotated[
        bool,
        typer.Option(
            "--animation/--no-animation",
            help="Embed an animation of the running mechanism (pins' play magnified).",
        ),
    ] = True,
) -> None:
    """Reproduce the paper's study (Akhadkar et al.) and write OUT/report.html and OUT/results.json.

    ECS contact parameters, the six simulation methods of Table 2, nominal vs actual mechanism
    (tolerance corners), sensitivities, the comparison with the measured rocker speed (Table 7),
    and every quantitative claim of the paper beside jointplay's value.
    """
    started = time.perf_counter()
    from jointplay.io.output import output_dir
    from jointplay.report.paper import write_paper_report
    from jointplay.study.paper import PaperStudyOptions, run_paper_study

    with output_dir(out, force=force) as folder:
        sources = {"both": ("paper", "computed"), "paper": ("paper",), "computed": ("computed",)}
        if ecs_source not in sources:
            raise ConfigError(f"--ecs-source must be both, paper or computed, got {ecs_source!r}")
        speed = crank_speed(rpm)
        check_revolutions(revolutions)
        if experiment_revolutions < 1:
            raise ConfigError(
                f"--experiment-revolutions must be >= 1, got {experiment_revolutions}"
            )
        if workers is not None and workers < 1:
            raise ConfigError(f"--workers must be >= 1, got {workers}")
        if dask_scheduler is not None and workers is not None:
            raise ConfigError("--workers applies to local processes; the Dask cluster has its own")
        check_figure_format(figure_format)
        options = PaperStudyOptions(
            rpm=speed * 30.0 / math.pi,
            revolutions=revolutions,
            ecs_sources=sources[ecs_source],
            tolerance_source=sources[ecs_source][0],
            corners=corners,
            workers=2 if workers is None else workers,
            experiment_revolutions=experiment_revolutions,
            scheduler=dask_scheduler,
        )
        options.backend  # noqa: B018 (checks --dask-scheduler before any work)
        console = Console(stderr=True)
        from jointplay._kernels import compiled_cache_present, single_engine

        # the study warms the single engine with its three integrators (never the lanes)
        compiling = not compiled_cache_present(single_engine("radau", "rodas4", "dopri5"))
        if compiling:
            console.print(COMPILE_NOTICE, markup=False, highlight=False)
        with Progress(
            TextColumn("[bold]paper study"),
            BarColumn(bar_width=24),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            TextColumn("{task.description}"),
            console=console,
            transient=False,
            disable=not progress_shown,
        ) as progress:
            task = progress.add_task("starting", total=None)
            steps = {"total": 0}

            def report(label: str, done: int, total: int) -> None:
                # one step more than the study's: writing the report
                steps["total"] = total + 1
                progress.update(task, completed=done, total=total + 1, description=label)

            study_started = time.perf_counter()
            study = run_paper_study(options, progress=report, animation=animation)
            record = provenance(
                {"options": {k: getattr(options, k) for k in options.__dataclass_fields__}}
            )
            progress.update(
                task, description="writing the report: figures, tables and the animation"
            )
            writing = time.perf_counter()
            write_paper_report(study, folder, record, figure_format=figure_format)
            report_s = time.perf_counter() - writing
            progress.update(task, completed=steps["total"], description="done")
    total_s = time.perf_counter() - started
    phases = dict(study.extra.get("phases", {}))
    if "kernels" in phases:
        phases["compiling" if compiling else "loading the kernels"] = phases.pop("kernels")
    parts = {
        "start-up and checks": study_started - started,  # imports, the options, --out
        **phases,
        "report": report_s,
    }
    parts["other"] = total_s - sum(parts.values())  # the folder put in place, bookkeeping
    total, shown = accounted(parts)
    typer.echo(f"paper study written to {out}/report.html in {total} s ({shown})")


def accounted(parts: dict[str, float]) -> tuple[int, str]:
    """The whole seconds of a run whose ``parts`` (s, back to back) make it up, and the parts
    in words, each rounded so that they add up to the rounded total exactly (largest
    remainder): ``(323, "compiling 31 s, simulations 166 s, ..., other 111 s")``. A part
    that rounds to 0 s is left out, unless it is all there is."""
    total = round(sum(parts.values()))
    floors = {name: math.floor(max(seconds, 0.0)) for name, seconds in parts.items()}
    short = total - sum(floors.values())
    by_remainder = sorted(parts, key=lambda name: floors[name] - parts[name])
    for name in by_remainder[: max(short, 0)]:
        floors[name] += 1
    shown = [f"{name} {seconds} s" for name, seconds in floors.items() if seconds]
    return total, ", ".join(shown) or f"{', '.join(parts)}: {total} s"
