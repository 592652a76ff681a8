"""``jointplay paper``: the paper's study end to end — the README's main job.

The module imports only Typer and Rich at the top; the study and the report (NumPy, pandas,
SciPy, Numba, matplotlib) are imported when the command runs, so that ``jointplay --help``
stays fast.
"""

from __future__ import annotations

from typing import Annotated

import typer
from rich.console import Console
from rich.progress import (
    BarColumn,
    MofNCompleteColumn,
    Progress,
    TextColumn,
    TimeElapsedColumn,
    TimeRemainingColumn,
)

from jointplay.cli._app import app
from jointplay.cli._common import ForceOption, OutOption, provenance
from jointplay.errors import ConfigError


@app.command("paper")
def paper_command(
    out: OutOption,
    force: ForceOption = False,
    rpm: Annotated[
        float, typer.Option("--rpm", help="Crank speed, rev/min (the paper's 200).")
    ] = 200.0,
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
) -> None:
    """Reproduce the paper's study (Akhadkar et al.) and write OUT/report.html and OUT/results.json.

    ECS contact parameters, the six simulation methods of Table 2, nominal vs actual mechanism
    (tolerance corners), sensitivities, the comparison with the measured rocker speed (Table 7),
    and every quantitative claim of the paper beside jointplay's value.
    """
    from jointplay.io.output import output_dir
    from jointplay.report.paper import write_paper_report
    from jointplay.study.paper import PaperStudyOptions, run_paper_study

    with output_dir(out, force=force) as folder:
        sources = {"both": ("paper", "computed"), "paper": ("paper",), "computed": ("computed",)}
        if ecs_source not in sources:
            raise ConfigError(f"--ecs-source must be both, paper or computed, got {ecs_source!r}")
        if not (revolutions > 0 and rpm > 0):
            raise ConfigError("--revolutions and --rpm must be > 0")
        if experiment_revolutions < 1:
            raise ConfigError(
                f"--experiment-revolutions must be >= 1, got {experiment_revolutions}"
            )
        if workers is not None and workers < 1:
            raise ConfigError(f"--workers must be >= 1, got {workers}")
        if dask_scheduler is not None and workers is not None:
            raise ConfigError("--workers applies to local processes; the Dask cluster has its own")
        options = PaperStudyOptions(
            rpm=rpm,
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
        with Progress(
            TextColumn("[bold]paper study"),
            BarColumn(),
            MofNCompleteColumn(),
            TimeElapsedColumn(),
            TimeRemainingColumn(),
            TextColumn("{task.description}"),
            console=console,
            transient=False,
        ) as progress:
            task = progress.add_task("starting", total=None)

            def report(label: str, done: int, total: int) -> None:
                progress.update(task, completed=done, total=total, description=label)

            study = run_paper_study(options, progress=report)
        record = provenance(
            {"options": {k: getattr(options, k) for k in options.__dataclass_fields__}}
        )
        write_paper_report(study, folder, record)
    typer.echo(f"paper study written to {out}/report.html ({study.wall_s:.0f} s)")
