"""Options and helpers shared by several commands."""

from __future__ import annotations

import re
import shlex
import sys
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import AbstractContextManager, contextmanager, nullcontext
from pathlib import Path
from typing import Annotated, Any, TypeVar, cast

import typer

from jointplay import __version__
from jointplay.cli._app import current_argv
from jointplay.cli._panels import EXECUTION_PANEL, OUTPUT_PANEL, WEAR_PANEL
from jointplay.cli._simulation import declared_option
from jointplay.dynamics.declared import run_setting
from jointplay.errors import ConfigError, Interrupted, PartialInterrupt
from jointplay.io.output import hold_signals, release_signals

PresetOption = Annotated[
    str | None,
    typer.Option(
        "--preset", "-p", help="Named mechanism (jointplay presets; default paper-fourbar)."
    ),
]
ConfigOption = Annotated[
    Path | None,
    typer.Option("--config", "-c", help="TOML mechanism file (see jointplay show)."),
]
RpmOption = Annotated[
    str | None,
    typer.Option(
        "--rpm",
        help="Crank speed with a unit, e.g. '200 rpm' or '20.9 rad/s' (overrides the mechanism's).",
    ),
]
DirectionOption = Annotated[
    str | None,
    typer.Option("--direction", help="Crank direction: ccw or cw (overrides the mechanism's)."),
]
StartAngleOption = Annotated[
    str | None,
    typer.Option(
        "--start-angle",
        help="Crank angle at t = 0 with a unit, e.g. '30 deg' (CCW from the ground line).",
    ),
]

GravityOption = Annotated[
    str | None,
    typer.Option("--gravity", help="off, on (9.80665 m/s² towards -y) or e.g. '9.81 m/s^2'."),
]
OutOption = Annotated[
    Path,
    typer.Option(
        "--out",
        "-o",
        help="Output folder, replaced on success.",
        rich_help_panel=OUTPUT_PANEL,
    ),
]
# Measurement conventions (compare, calibrate): how a file's angles and values are read.
CrankDirectionOption = Annotated[
    str, typer.Option("--crank-direction", help="The rig's crank direction: cw (default) or ccw.")
]
AngleDirectionOption = Annotated[
    str,
    typer.Option(
        "--angle-direction",
        help="Sense in which the file counts crank angles: cw (default) or ccw.",
    ),
]
AngleOriginOption = Annotated[
    str,
    typer.Option(
        "--angle-origin",
        help="Crank position of the file's 0, CCW from the ground line O2->O4, with a unit "
        "(default '0 deg': crank pointing at the rocker pivot O4).",
    ),
]
SpeedPositiveOption = Annotated[
    str,
    typer.Option(
        "--speed-positive",
        help="Rotation that the file's positive values mean: ccw (default) or cw.",
    ),
]
# Archard wear and the running start-up (design, wear).
WearCoefficientOption = Annotated[
    float | None,
    typer.Option(
        "--wear-coefficient", help="Archard k of every joint.", rich_help_panel=WEAR_PANEL
    ),
]
HardnessOption = Annotated[
    str | None,
    typer.Option(
        "--hardness",
        help="Hardness of the softer surface, e.g. '2 GPa'.",
        rich_help_panel=WEAR_PANEL,
    ),
]
SettleOption = Annotated[int, declared_option(run_setting("settle"), min=0)]
#: Figure formats of ``--figure-format`` (PNG is always written; the others beside it).
FIGURE_FORMATS = ("png", "svg", "pdf")
FigureFormatOption = Annotated[
    str,
    typer.Option(
        "--figure-format",
        help="svg or pdf: figures also in it.",
        rich_help_panel=OUTPUT_PANEL,
    ),
]


def progress_shown(ctx: typer.Context, param: typer.CallbackParam, value: bool) -> bool:
    """Whether a command shows its progress bar or spinner: ``--progress`` forces it,
    ``--no-progress`` hides it, and with neither it shows only where stderr is a terminal
    (a log file or a pipe got the bar's last frame as a line of box characters)."""
    source = ctx.get_parameter_source(param.name or "")
    if source is not None and source.name == "DEFAULT":
        return bool(value) and _stderr_is_a_terminal()
    return bool(value)


def _stderr_is_a_terminal() -> bool:
    try:
        return bool(sys.stderr.isatty())
    except (AttributeError, ValueError, OSError):  # no stderr, or a closed one
        return False


ProgressOption = Annotated[
    bool,
    typer.Option(
        "--progress/--no-progress",
        help="A progress bar or spinner on stderr (default: if it is a terminal).",
        show_default=False,
        rich_help_panel=OUTPUT_PANEL,
        callback=progress_shown,
    ),
]
ForceOption = Annotated[
    bool,
    typer.Option(
        "--force",
        help="Replace --out jointplay did not write, inside the current, home or a temp folder.",
        rich_help_panel=OUTPUT_PANEL,
    ),
]


def maybe_output_dir(
    out: Path | None, force: bool = False, inputs: Sequence[Path | None] = ()
) -> AbstractContextManager[Path | None]:
    """:func:`jointplay.io.output.output_dir` for ``out`` (``inputs``: the files the run
    reads), or ``None`` without one.

    Enter it before computing, so that an unusable ``--out`` is reported first.
    """
    if out is None:
        return nullcontext(None)
    from jointplay.io.output import output_dir

    return output_dir(out, force=force, inputs=inputs)


def provenance(configuration: Any) -> dict[str, Any]:
    """Version, full resolved configuration and command line, for result files."""
    return {
        "jointplay_version": __version__,
        "python": sys.version.split()[0],
        "command_line": " ".join(shlex.quote(a) for a in ["jointplay", *current_argv]),
        "configuration": configuration,
    }


def choice(text: str, option: str, choices: Iterable[str]) -> str:
    """``text`` lower-cased and stripped, if it is one of ``choices``; else a ConfigError
    naming ``option`` and the allowed values. The one choice parser of the command line."""
    allowed = tuple(choices)
    value = text.strip().lower()
    if value not in allowed:
        raise ConfigError(f"{option} must be one of {', '.join(allowed)}, got {text!r}")
    return value


#: The most samples of a study (and of each scheme of a design): 10 million samples of a
#: dynamic study run for days; a larger number is a typo, refused before memory is asked for.
MAX_SAMPLES = 10_000_000
#: The most local worker processes.
MAX_WORKERS = 1024

WorkersOption = Annotated[
    int | None,
    typer.Option(
        "--workers",
        help="Local worker processes (default: one per CPU).",
        min=1,
        max=MAX_WORKERS,
        rich_help_panel=EXECUTION_PANEL,
    ),
]
DaskSchedulerOption = Annotated[
    str | None,
    typer.Option(
        "--dask-scheduler", help="The Dask cluster's ADDRESS.", rich_help_panel=EXECUTION_PANEL
    ),
]
PlotsOption = Annotated[
    bool,
    typer.Option("--plots/--no-plots", help="Write PNG plots.", rich_help_panel=OUTPUT_PANEL),
]


def check_figure_format(text: str) -> str:
    """The ``--figure-format`` value, checked (before any computation)."""
    return choice(text, "--figure-format", FIGURE_FORMATS)


#: What a first run after install spends compiling the kernels (2-core machine: a fresh
#: `jointplay paper` measured 126 s of start-up and 30 s of compiling with another job running).
COMPILE_NOTICE = (
    "jointplay: compiling the numerical kernels first: once after an install or upgrade, "
    "one to two minutes on a 2-core machine; later runs load them in about a second"
)


def _to_stderr(line: str) -> None:
    print(line, file=sys.stderr)


@contextmanager
def compiling_kernels(
    say: Any = _to_stderr, *, needed: bool = True, kernels: Sequence[str] | None = None
) -> Iterator[bool]:
    """Around a command's first dynamic work: when the kernels it runs are not all cached
    (:func:`jointplay._kernels.compiled_cache_present` of ``kernels``: default the single
    engine's with Radau, :func:`jointplay._kernels.single_engine`; the batch lanes':
    :data:`jointplay._kernels.BATCH_LANES`), ``say`` (a print function; default: a line on
    stderr) tells the user before the work that the kernels are compiled now, and after it
    how long the work took with the compilation. ``needed=False`` (work without dynamics)
    says nothing. Yields whether they are compiled here."""
    from jointplay._kernels import compiled_cache_present, single_engine

    if not needed or compiled_cache_present(single_engine() if kernels is None else kernels):
        yield False
        return
    say(COMPILE_NOTICE)
    started = time.perf_counter()
    yield True
    say(
        f"jointplay: kernels compiled and cached; this step took "
        f"{time.perf_counter() - started:.0f} s with the compilation"
    )


def status(enabled: bool, text: str) -> AbstractContextManager[Any]:
    """A spinner on stderr saying ``text`` while the block runs (nothing with
    ``--no-progress``)."""
    if not enabled:
        return nullcontext()
    from rich.console import Console

    return Console(stderr=True).status(text)


#: Words of a table's cells up to this length are never split either (``zero-load``,
#: ``overall``); longer ones (a design scheme's ``O2=H7/g6,A=H7/g6,...``) fold.
LONGEST_WHOLE_WORD = 16
#: A cell that is one number (``13.822``, ``-3.963e-06``, ``2338.1``): never split.
_NUMBER = re.compile(r"[-+−]?(\d[\d,]*\.?\d*|\.\d+)([eE][-+]?\d+)?%?")


def whole_headers(table: Any) -> Any:
    """``table`` (a :class:`rich.table.Table`, its rows added) with headers and numbers that
    are never cut: each column at least as wide as the longest word of its header, the
    longest number among its cells and their longest word up to
    :data:`LONGEST_WHOLE_WORD` characters; its cells wrapped at spaces or, where a longer
    word does not fit, folded onto the next line instead of ending in "…". A table that still outgrows the
    terminal is wrapped by the terminal (the consoles print it with ``soft_wrap``), not
    truncated by Rich. Columns declared ``no_wrap`` wrap at spaces too: Rich cut their
    header otherwise (tolerance's "most influential" read "most influenti" at 80 columns)."""
    for column in table.columns:
        words = str(column.header).split()
        cells = [str(getattr(cell, "plain", cell)).strip() for cell in column.cells]
        numbers = [cell for cell in cells if _NUMBER.fullmatch(cell)]
        short = [w for cell in cells for w in cell.split() if len(w) <= LONGEST_WHOLE_WORD]
        column.min_width = max((len(word) for word in [*words, *numbers, *short]), default=0)
        column.overflow = "fold"
        column.no_wrap = False
    return table


_R = TypeVar("_R")


def run_study(compute: Callable[[], _R]) -> tuple[_R, list[str]]:
    """``(compute(), [])``; an interrupt in the study's convergence check, after every point
    or scheme finished (a :class:`~jointplay.errors.PartialInterrupt`), gives its partial
    result and ``["the convergence check"]``, what is missing from it.

    From the study's end SIGINT and SIGTERM are held back
    (:func:`~jointplay.io.output.hold_signals`) until its data files have been written
    (:func:`writing_study`): an interrupt in between is delivered after them instead of
    losing every finished sample."""
    try:
        result = compute()
        hold_signals()
        return result, []
    except PartialInterrupt as stopped:
        hold_signals()
        return cast("_R", stopped.partial), ["the convergence check"]


@contextmanager
def writing_study(finished: tuple[int, int, str], missing: list[str]) -> Iterator[None]:
    """Around the writing of a study's results, whose tables and summary are written first,
    whole: an interrupt there becomes :class:`~jointplay.errors.Interrupted` saying that
    ``finished`` (done, of, what) are kept and ``missing`` and the figures and report are not."""
    try:
        try:
            yield
        finally:
            release_signals()  # what run_study held, if the writing did not take it over
    except KeyboardInterrupt:
        raise Interrupted(*finished, ", ".join([*missing, "the figures and report"])) from None


def study_kept(interrupted: bool, finished: tuple[int, int, str], missing: list[str]) -> None:
    """Raise :class:`~jointplay.errors.Interrupted` for a study written in full that an
    interrupt had cut short (``interrupted``) or that lacks ``missing``."""
    if interrupted or missing:
        raise Interrupted(*finished, ", ".join(missing))
