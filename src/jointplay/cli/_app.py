"""The Typer application object and the error boundary of the ``jointplay`` command.

Command modules register themselves with ``@app.command()`` on the :data:`app` defined here.
:func:`run` turns every :class:`~jointplay.errors.JointplayError` into one line on stderr and
a non-zero exit status; no traceback reaches the user unless ``JOINTPLAY_DEBUG=1``.
"""

from __future__ import annotations

import dataclasses
import os
import re
import signal
import sys
import threading
import warnings
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from typing import Any, NoReturn

import typer

try:  # Typer >= 0.20 vendors its own copy of Click, whose exceptions it raises
    from typer._click import exceptions as click_exceptions
except ImportError:  # pragma: no cover - older Typer uses the click package
    from click import exceptions as click_exceptions  # type: ignore[no-redef]

from jointplay.cli._panels import PANEL_ORDER, option_panel
from jointplay.errors import Interrupted, JointplayError, SettingError, caused_by_interrupt

#: A choice option's type column lists its choices up to this width (``<random|lhs>``);
#: longer lists (``<monte-carlo|worst-case|rss>``) show ``<choice>``, the help naming them.
LONGEST_CHOICES = 14


def _flags_show_no_metavar() -> None:
    """Flags (``--json``, ``--force``, ``--plots/--no-plots``, ``--help``) take no value, so
    the help shows no ``<bool>`` beside them, as Click's own help and rich-click do.

    Typer's Rich help (0.2x) prints a flag's type in the metavar column; plain Click help
    does not (``Option.get_help_record`` skips flags). The column is drawn from
    ``TyperOption.display_type_rich``, which here returns ``None`` for a flag or a counter.
    Older Typer releases have no such method and show no metavar for flags: nothing to do.
    """
    try:
        from typer.core import TyperOption
    except ImportError:  # pragma: no cover - Typer without its own option class
        return
    shown = getattr(TyperOption, "display_type_rich", None)
    if shown is None or getattr(shown, "_flags_hidden", False):
        return

    def display_type_rich(self: Any, ctx: Any) -> str | None:
        if getattr(self, "is_flag", False) or getattr(self, "count", False):
            return None
        text = shown(self, ctx)
        if text and "|" in text and len(text) > LONGEST_CHOICES:  # the help names them
            return "<choice>"
        return text.replace(" range>", ">") if text else text  # the range: with the help

    display_type_rich._flags_hidden = True  # type: ignore[attr-defined]
    TyperOption.display_type_rich = display_type_rich  # type: ignore[method-assign]


def _ranges_beside_the_help() -> None:
    """A number option's range (``--workers``: 1 to 1024) is shown after its help, as its
    default is, not in the type column: there ``<int range> [1<=x<=10000000]`` made the
    column 30 characters wide and left the help of every option of the panel 20 columns.

    Typer's Rich help takes the range from ``_get_number_range_help_str`` for the type
    column; here that returns nothing, and the help's items (``[default: ...]``) get a
    ``[range: ...]`` from the option's ``min`` and ``max``."""
    try:
        from rich.text import Text
        from typer import core, rich_utils
        from typer._display import describe_number_range
    except ImportError:  # pragma: no cover - another Typer: its own layout stays
        return
    helped = getattr(rich_utils, "_get_parameter_help", None)
    if helped is None or getattr(helped, "_with_range", False):
        return

    def get_parameter_help(*, param: Any, ctx: Any, markup_mode: Any) -> Any:
        columns = helped(param=param, ctx=ctx, markup_mode=markup_mode)
        low, high = getattr(param, "min", None), getattr(param, "max", None)
        if (low is not None or high is not None) and hasattr(columns, "renderables"):
            text = describe_number_range(low, high)
            items = columns.renderables
            default = next((t for t in items if str(t).startswith("[default: ")), None)
            if text and default is not None:  # one line: [default: 2; x>=0]
                default.plain = f"{str(default)[:-1]}; {text}]"
            elif text:
                items.append(Text(f"[range: {text}]", style="dim"))
        return columns

    get_parameter_help._with_range = True  # type: ignore[attr-defined]
    rich_utils._get_parameter_help = get_parameter_help
    for kind in (core.TyperOption, core.TyperArgument):
        if hasattr(kind, "_get_number_range_help_str"):
            kind._get_number_range_help_str = lambda self: None  # type: ignore[method-assign]


def _help_is_plain_text() -> None:
    """Help texts are read as written: ``pip install 'jointplay[gpu]'``, a ``[wear]`` table.

    With ``rich_markup_mode="rich"`` (what gives the help its panels) Typer reads every help
    text as Rich markup, where ``[gpu]`` or ``[wear]`` is a style tag and silently vanishes.
    jointplay writes no markup in its help, so every help text is escaped
    (:func:`rich.markup.escape`) just before Typer renders it: option help, command
    docstrings and the epilogue alike, those of commands added later included. A paragraph's
    line breaks (a docstring's, at 96 columns) are spaces: the paragraph is wrapped at the
    terminal's width, as Typer already does for the first paragraph and for option help.
    """
    try:
        from typer import rich_utils
    except ImportError:  # pragma: no cover - Typer without Rich help: nothing is markup
        return
    render = getattr(rich_utils, "_make_rich_text", None)
    if render is None or getattr(render, "_escapes_markup", False):
        return
    from rich.markup import escape

    def make_rich_text(*, text: str, style: str = "", markup_mode: Any) -> Any:
        if markup_mode == "rich":
            text = escape(text)
            text = "\n\n".join(
                part if part.startswith("\b") else " ".join(part.split("\n"))
                for part in text.split("\n\n")
            )
        return render(text=text, style=style, markup_mode=markup_mode)

    make_rich_text._escapes_markup = True  # type: ignore[attr-defined]
    rich_utils._make_rich_text = make_rich_text


def _option_names_never_cut() -> None:
    """At 80 columns an option's name is shown whole (``--clearance-limit``, never
    ``--clearance-lim…``), and a long word in its help folds onto the next line instead of
    ending in "…".

    Typer draws each panel of options as a Rich table without declared columns; when the
    table is wider than the terminal, Rich narrows every column that may wrap, the option
    names' too, and cuts what no longer fits. Here the tables Typer creates mark the name
    columns (all but the type and help columns) as not wrapping, so only the type and help
    columns give way, and those fold their long words. A flag's ``--no-`` form is written
    under its name instead of in a column of its own, which left the help of a whole panel
    17 characters narrower for one ``--rare-defects/--no-rare-defects``.
    """
    try:
        from typer import rich_utils
    except ImportError:  # pragma: no cover - Typer without Rich help
        return
    table = getattr(rich_utils, "Table", None)
    if table is None or getattr(table, "_names_never_cut", False):
        return

    class OptionsTable(table):  # type: ignore[misc, valid-type]
        _names_never_cut = True

        def add_row(self, *renderables: Any, **kwargs: Any) -> None:
            if not self.show_header and len(renderables) in (6, 7):  # an options panel's row
                # [required], long, short, --no- long, --no- short, type, help
                first = len(renderables) - 6
                names = [
                    _stacked(renderables[first + k], renderables[first + k + 2]) for k in (0, 1)
                ]
                renderables = (*renderables[:first], *names, *renderables[first + 4 :])
            super().add_row(*renderables, **kwargs)
            if self.show_header or len(self.columns) < 4:  # not an options panel
                return
            for column in self.columns[:-2]:
                column.no_wrap = True
            help_items = getattr(renderables[-1], "renderables", [renderables[-1]])
            for item in [renderables[-2], *help_items]:  # the type, the help and its default
                if hasattr(item, "overflow"):
                    item.overflow = "fold"

    rich_utils.Table = OptionsTable  # type: ignore[misc]


def _stacked(name: Any, negative: Any) -> Any:
    """An option's name with its ``--no-`` form on the line below (Rich texts)."""
    if not str(negative).strip():
        return name
    stacked = name.copy()
    stacked.append("\n")
    stacked.append_text(negative)
    return stacked


def _options_in_panels() -> None:
    """Every command's help groups its options in the panels of :data:`PANEL_ORDER` (the
    panel of an option without a declared one: :func:`option_panel`), in that order, so a
    long command's help (``design``: 235 lines at 80 columns in one panel) is read by topic
    and each panel's columns are as wide as its own options need."""
    try:
        from typer import core, rich_utils
    except ImportError:  # pragma: no cover - Typer without Rich help
        return
    render = getattr(rich_utils, "rich_format_help", None)
    if render is None or getattr(render, "_in_panels", False):
        return

    def rich_format_help(*, obj: Any, ctx: Any, markup_mode: Any) -> None:
        params = list(getattr(obj, "params", []))
        order = {panel: k for k, panel in enumerate(PANEL_ORDER)}
        panels = [option_panel(p) if isinstance(p, core.TyperOption) else None for p in params]
        saved = [getattr(p, "rich_help_panel", None) for p in params]
        try:
            for param, panel in zip(params, panels, strict=True):
                if panel is not None and panel != "Options":
                    param.rich_help_panel = panel
            obj.params = sorted(  # stable: each panel keeps its options' declared order
                params,
                key=lambda p: (
                    order.get(option_panel(p), len(order))
                    if isinstance(p, core.TyperOption)
                    else -1
                ),
            )
            render(obj=obj, ctx=ctx, markup_mode=markup_mode)
        finally:
            obj.params = params
            for param, panel in zip(params, saved, strict=True):
                param.rich_help_panel = panel

    rich_format_help._in_panels = True  # type: ignore[attr-defined]
    rich_utils.rich_format_help = rich_format_help


#: Option values that read the same by ``int()``/``float()`` as by Pydantic's lax mode.
_PLAIN_INT = re.compile(r"[+-]?[0-9]{1,18}")
_PLAIN_FLOAT = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?")


def _values_read_without_pydantic() -> None:
    """Option values of the plain kinds (text, a flag, a number, a path) are read as Python
    reads them, without importing Pydantic.

    Typer (0.2x) converts every option's value with a Pydantic ``TypeAdapter``, and importing
    Pydantic took ~0.1 s of every command, a third of a mistyped option's error line
    (docs/performance.md, "Command-line start-up, round 3"). Here a value that
    ``str``/``int``/``float``/``pathlib.Path`` read exactly as Pydantic's lax mode does (a
    ``str``; digits; a plain decimal number; a path) is converted directly; every other
    value (``1_0``, ``inf``, a number out of its range, an enum choice, a list) goes to
    Typer's own converter, with its own result or error message.
    tests/cli/test_startup.py compares the two on a table of values."""
    try:
        from pathlib import Path

        from typer import core
        from typer._coercion import RuntimeParam, build_runtime_param
        from typer._param_types import coerce_cli_path
    except ImportError:  # pragma: no cover - another Typer: its own converter stays
        return
    if getattr(core.build_runtime_param, "_plain", False):
        return

    slow = object()

    def plain(converter: Any, value: Any, param: Any, ctx: Any) -> Any:
        kind, info = converter.annotation, converter.parameter_info
        if info.parser is not None or info.clamp:
            return slow
        low, high = info.min, info.max
        number: float
        if kind is str and type(value) is str:
            return value
        if kind is bool and type(value) is bool:
            return value
        if kind is int and type(value) is str and _PLAIN_INT.fullmatch(value):
            number = int(value)
        elif kind is int and type(value) is int:
            number = value
        elif kind is float and type(value) is str and _PLAIN_FLOAT.fullmatch(value):
            number = float(value)
        elif kind is float and type(value) is float:
            number = value
        elif (
            kind is Path
            and info.path_type is None
            and not info.allow_dash
            and type(value) is str
            and value
            and "\0" not in value
        ):
            text: Any = coerce_cli_path(value, info, path_type=None, param=param, ctx=ctx)
            return Path(text)
        else:
            return slow
        if (low is not None and number < low) or (high is not None and number > high):
            return slow  # Typer's message for a number out of range
        return number

    @dataclasses.dataclass(frozen=True)
    class PlainRuntimeParam(RuntimeParam):
        descriptor: Any  # Typer's TypeDescriptor, for its own converter

        def _coerce_value(self, value: Any, param: Any, ctx: Any) -> Any:
            converted = plain(self, value, param, ctx)
            if converted is not slow:
                return converted
            full = build_runtime_param(self.descriptor)  # Pydantic's
            return full._coerce_value(value, param=param, ctx=ctx)

    def build(descriptor: Any) -> Any:
        if descriptor.file_annotation is not None:
            return build_runtime_param(descriptor)
        return PlainRuntimeParam(
            annotation=descriptor.annotation,
            parameter_info=descriptor.parameter_info,
            descriptor=descriptor,
        )

    build._plain = True  # type: ignore[attr-defined]
    core.build_runtime_param = build


_values_read_without_pydantic()
_flags_show_no_metavar()
_ranges_beside_the_help()
_help_is_plain_text()
_option_names_never_cut()
_options_in_panels()

app = typer.Typer(
    name="jointplay",
    help="Planar linkages with tolerance stacks and clearance joints: kinematics, contact "
    "dynamics, the Akhadkar et al. paper study and tolerance analysis.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode="rich",
)


def _print_version(value: bool) -> None:
    if value:
        from jointplay import __version__

        print(f"jointplay {__version__}")
        raise typer.Exit()


@app.callback()
def _options(
    version: bool = typer.Option(
        False,
        "--version",
        help="Print the version and exit.",
        callback=_print_version,
        is_eager=True,
    ),
) -> None:
    """Planar linkages with tolerance stacks and clearance joints."""


EXIT_ERROR = 2
EXIT_INTERNAL = 3
EXIT_INTERRUPTED = 130


#: The line printed when a run is interrupted before it could write anything.
NOTHING_KEPT = "jointplay: interrupted; nothing was written (the output folder is as it was)"


def fail(message: str) -> None:
    """Print one error line to stderr (helper for commands that detect bad input themselves)."""
    print(f"jointplay: error: {_one_line(message)}", file=sys.stderr)


#: The arguments of the command being run (for the provenance records of result files).
current_argv: list[str] = []


def _raise_interrupt(signum: int, frame: object) -> None:
    """SIGTERM handler: stop like Ctrl-C, so that every ``finally`` block runs."""
    raise KeyboardInterrupt(f"signal {signum}")


@contextmanager
def _sigterm_as_interrupt() -> Iterator[None]:
    """While the command runs, SIGTERM raises KeyboardInterrupt (main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _raise_interrupt)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


@contextmanager
def _one_line_warnings() -> Iterator[None]:
    """Python warnings (NumPy's overflow notes, ...) as one ``jointplay: warning:`` line each,
    without the source line; which warnings show is left to the warning filters."""
    previous = warnings.showwarning

    def show(message: Warning | str, category: type[Warning], *args: object, **kw: object) -> None:
        print(
            f"jointplay: warning: {category.__name__}: {_one_line(str(message))}", file=sys.stderr
        )

    warnings.showwarning = show
    try:
        yield
    finally:
        warnings.showwarning = previous


#: The longest message line printed, characters: an error that quotes a huge input (a
#: 10 MB line of a file, a long argument) keeps its start and its end, where the fix is said.
MAX_LINE = 600


def _one_line(text: str) -> str:
    """``text`` on one line, its middle cut where it is longer than :data:`MAX_LINE`."""
    line = " ".join(str(text).split())
    if len(line) <= MAX_LINE:
        return line
    head, tail = MAX_LINE * 2 // 3, MAX_LINE // 3
    return f"{line[:head]} … ({len(line) - head - tail} characters cut) … {line[-tail:]}"


#: Words that a user may write after a flag, meaning "on" or "off".
_FLAG_WORDS = ("true", "false", "yes", "no", "on", "off", "1", "0")


def _command_names() -> set[str]:
    """The names of the registered commands."""
    return {
        command.name or (command.callback.__name__ if command.callback else "")
        for command in app.registered_commands
    }


def _flags_of(ctx: Any) -> dict[str, tuple[str, ...]]:
    """Every flag spelling of the command being parsed (and its parents) → all its spellings."""
    flags: dict[str, tuple[str, ...]] = {}
    while ctx is not None:
        for param in getattr(ctx.command, "params", []):
            if getattr(param, "is_flag", False):
                spellings = (*param.opts, *param.secondary_opts)
                flags.update(dict.fromkeys(spellings, spellings))
        ctx = ctx.parent
    return flags


def _flag_value_hint(argv: list[str], message: str, ctx: Any) -> str:
    """A hint when a flag was given a value (``--json true``, ``--plots=false``), else "".

    Flags follow Click's convention: they take no value; the flag alone turns the feature
    on, and leaving it out (or its ``--no-`` partner, where it has one) turns it off. Click
    reports the stray word as an extra argument or says the option takes no value; the
    hint says what to write instead.
    """
    if "extra argument" not in message and "does not take a value" not in message:
        return ""
    flags = _flags_of(ctx)
    named = re.search(r"Option '(--[\w-]+)' does not take a value", message)
    if named and named[1] not in flags:  # Click names it from the group's context
        flags[named[1]] = (named[1],)
    for previous, word in zip(["", *argv], argv, strict=False):
        name, equals, value = word.partition("=")
        if equals and name in flags and value.lower() in _FLAG_WORDS:
            flag = name
        elif previous in flags and word.lower() in _FLAG_WORDS:
            flag = previous
        else:
            continue
        spellings = flags[flag]
        if len(spellings) > 1:
            return f"; flags take no value: write {' or '.join(spellings)}"
        return f"; flags take no value: write {flag} alone, or leave it out"
    return ""


def run(argv: list[str] | None = None) -> int:
    """Run the CLI with ``argv`` and return the exit status.

    The exit statuses are a contract (README, "Exit codes"): 0 success; 2 bad input or
    environment (unwritable output, unreachable cluster); 3 a bug (with a pointer to
    report it); 130 interrupted (SIGINT or SIGTERM), with one line saying what was kept.
    Every failure is one line on stderr.
    """
    current_argv[:] = list(sys.argv[1:] if argv is None else argv)
    try:
        with _sigterm_as_interrupt(), _one_line_warnings():
            # Without standalone mode Typer returns (rather than raises) the code of
            # typer.Exit and of an interrupted command.
            status = app(args=argv, prog_name="jointplay", standalone_mode=False)
        if isinstance(status, int) and not isinstance(status, bool):
            if status == EXIT_INTERRUPTED:  # Typer turns KeyboardInterrupt into this code
                print(NOTHING_KEPT, file=sys.stderr)
            return status
    except typer.Exit as exc:
        return int(exc.exit_code)
    except click_exceptions.UsageError as exc:
        if type(exc).__name__ == "NoArgsIsHelpError":  # the help was shown: nothing failed
            return 0
        where = exc.ctx.command_path if exc.ctx is not None else "jointplay"
        if where == "jointplay" and current_argv and current_argv[0] in _command_names():
            where = f"jointplay {current_argv[0]}"
        message = _one_line(exc.format_message())
        hint = _flag_value_hint(current_argv, message, exc.ctx)
        if hint:
            message = message.rstrip(".") + hint
        fail(f"{message} (see '{where} --help')")
        return EXIT_ERROR
    except click_exceptions.ClickException as exc:
        fail(_one_line(exc.format_message()))
        return EXIT_ERROR if exc.exit_code in (1, 2) else int(exc.exit_code)
    except Interrupted as exc:
        print(f"jointplay: interrupted; {_one_line(exc.line())}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except (typer.Abort, KeyboardInterrupt):
        print(NOTHING_KEPT, file=sys.stderr)
        return EXIT_INTERRUPTED
    except JointplayError as exc:
        fail(_one_line(str(_with_options(exc))))
        return EXIT_ERROR
    except MemoryError:
        fail("out of memory; ask for less (fewer samples or revolutions, a coarser step)")
        return EXIT_ERROR
    except OSError as exc:
        if os.environ.get("JOINTPLAY_DEBUG"):
            raise
        name = f" {exc.filename!r}" if exc.filename else ""
        fail(f"{exc.strerror or type(exc).__name__}{name}")
        return EXIT_ERROR
    except Exception as exc:
        if caused_by_interrupt(exc):  # Ctrl-C inside compiled code (Numba's SystemError)
            print(NOTHING_KEPT, file=sys.stderr)
            return EXIT_INTERRUPTED
        if os.environ.get("JOINTPLAY_DEBUG"):
            raise
        print(
            f"jointplay: internal error (a bug): {type(exc).__name__}: {_one_line(str(exc))}; "
            "please report it to the jointplay maintainers with the command line and the "
            "traceback that JOINTPLAY_DEBUG=1 prints",
            file=sys.stderr,
        )
        return EXIT_INTERNAL
    return 0


class _UnfailingStream:
    """A text stream whose writes never raise: what cannot be written (a full disk, a closed
    pipe or descriptor) is dropped, so that the exit status stays the one the command chose
    (``jointplay ... 2>/dev/full`` used to exit 1, from the error line it could not write).
    Everything else is the wrapped stream's (``isatty``, ``encoding``, ``fileno``)."""

    def __init__(self, stream: Any) -> None:
        self._stream = stream

    def write(self, text: str) -> int:
        try:
            return int(self._stream.write(text))
        except (OSError, ValueError):  # ValueError: closed, or a character not encodable
            return len(text)

    def writelines(self, lines: Any) -> None:
        for line in lines:
            self.write(line)

    def flush(self) -> None:
        with suppress(OSError, ValueError):
            self._stream.flush()

    def __getattr__(self, name: str) -> Any:
        return getattr(self._stream, name)


def _streams_for_any_terminal() -> None:
    """Start-up of the command line: the exit statuses are the documented ones whatever the
    terminal.

    * stdout and stderr write a character their encoding lacks as an escape (``\\xb5``)
      instead of raising (``PYTHONIOENCODING=ascii`` made the ``µ`` of a table a
      UnicodeEncodeError, exit 3);
    * stderr never raises (:class:`_UnfailingStream`): an error line that cannot be written
      is lost, its exit status is not; a missing stderr (``2>&-``) is a null one, so that
      those lines never land on stdout.
    """
    for stream in (sys.stdout, sys.stderr):
        reconfigure = getattr(stream, "reconfigure", None)
        if reconfigure is not None:
            with suppress(OSError, ValueError):  # a stream that cannot change stays as it is
                reconfigure(errors="backslashreplace")
    if sys.stderr is None:
        sys.stderr = open(os.devnull, "w", encoding="utf-8")  # noqa: SIM115 (for good)
    if not isinstance(sys.stderr, _UnfailingStream):
        sys.stderr = _UnfailingStream(sys.stderr)


def main() -> None:
    """Console-script entry point: :func:`run`, then :func:`leave` (the standard streams
    made safe first: :func:`_streams_for_any_terminal`)."""
    _streams_for_any_terminal()
    leave(run(sys.argv[1:]))


def leave(status: int) -> NoReturn:
    """End the process with ``status`` once the command is done, skipping the interpreter's
    teardown.

    The exit handlers run first (``atexit``: e.g. the batch engine's worker pool is shut
    down) and the standard streams are flushed; every file a command writes is closed by the
    time it returns. What is skipped is the freeing of every module's objects — the compiled
    kernels, the plotting and data libraries — which took ~0.6 s after each command on a
    2-core machine (a tenth of a 1 000-sample dynamic tolerance study) and changes nothing.
    """
    import atexit

    try:
        atexit._run_exitfuncs()
        sys.stdout.flush()
        sys.stderr.flush()
    finally:
        os._exit(status)


def _with_options(error: JointplayError) -> JointplayError:
    """``error``, a :class:`~jointplay.errors.SettingError` calling its settings by their
    command-line options (the layers below know no option)."""
    if isinstance(error, SettingError):
        from jointplay.cli._simulation import SETTING_OPTIONS

        return error.named(SETTING_OPTIONS)
    return error
