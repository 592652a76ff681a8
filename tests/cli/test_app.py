"""The command line's edges: --version, python -m jointplay, and light start-up.

Start-up *time* is a benchmark (benchmarks/bench_cli_startup.py); what the tests pin down is
its cause: the quick commands must not import the numerical stack at all.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys

import pytest

from jointplay import __version__
from jointplay.cli import run

HEAVY = ("numba", "scipy", "pandas", "dask", "distributed", "matplotlib", "pint")


def test_version(capsys) -> None:
    assert run(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"jointplay {__version__}"


def test_python_dash_m_runs_the_command_line() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "jointplay", "--version"], capture_output=True, text=True
    )
    assert done.returncode == 0
    assert done.stdout.strip() == f"jointplay {__version__}"


def test_the_entry_point_ends_with_the_status_after_exit_handlers_and_flushed_output() -> None:
    # main() skips the interpreter's teardown (cli._app.leave): the status must still come
    # out, the atexit handlers (the worker pool's shutdown) still run, and buffered output
    # still reaches the pipe
    script = (
        "import atexit, sys\n"
        "atexit.register(lambda: print('handler ran'))\n"
        "from jointplay.cli._app import leave\n"
        "sys.stdout.write('x' * 100000)\n"
        "leave(3)\n"
    )
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True)
    assert done.returncode == 3
    assert done.stdout == "x" * 100000 + "handler ran\n"


def test_the_console_script_module_is_light_for_spawned_workers() -> None:
    # a worker process started with "spawn" re-runs its parent's script, which imports the
    # console script's module: that must not load the command line (Typer, Rich, commands)
    from importlib.metadata import entry_points

    (script,) = [e for e in entry_points(group="console_scripts") if e.name == "jointplay"]
    module = script.value.partition(":")[0]
    code = f"import sys, {module}; print(sorted(m for m in sys.modules if m.startswith(('jointplay.cli', 'typer', 'rich'))))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[]"


def test_python_dash_m_returns_the_usage_error_status() -> None:
    done = subprocess.run(
        [sys.executable, "-m", "jointplay", "simulate", "--no-such-option"],
        capture_output=True,
        text=True,
    )
    assert done.returncode == 2
    assert "--no-such-option" in done.stderr


@pytest.mark.parametrize(
    "arguments",
    [
        ["--help"],
        ["simulate", "--help"],
        ["fit", "H8/g7", "--size", "10mm"],
        ["general-tolerance", "c", "--size", "270.5mm"],
        ["presets"],
        ["show", "paper-fourbar"],
    ],
    ids=" ".join,
)
def test_quick_commands_do_not_import_the_numerical_stack(arguments: list[str]) -> None:
    code = (
        "import sys\n"
        "from jointplay.cli import run\n"
        f"status = run({arguments!r})\n"
        f"print(status, ','.join(m for m in {HEAVY!r} if m in sys.modules))\n"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    status, _, loaded = done.stdout.strip().splitlines()[-1].partition(" ")
    assert status == "0", done.stderr
    assert loaded == "", f"{' '.join(arguments)} imported {loaded}"


@pytest.mark.parametrize("arguments", [["--help"], ["fit", "--help"], ["kinematics", "--help"]])
def test_flags_show_no_metavar(arguments: list[str], capsys: pytest.CaptureFixture[str]) -> None:
    """Flags take no value, so their help line shows none (Click's own convention)."""
    assert run(arguments) == 0
    text = capsys.readouterr().out
    assert "<bool>" not in text
    assert "--help" in text
    assert "<str>" in text or arguments == ["--help"]  # options with values keep theirs


@pytest.mark.parametrize(
    ("arguments", "hint"),
    [
        (["fit", "H8/g7", "--size", "10mm", "--json", "true"], "write --json alone"),
        (["fit", "H8/g7", "--size", "10mm", "--json=true"], "write --json alone"),
        (["kinematics", "--plots", "false", "-o", "x"], "write --plots or --no-plots"),
    ],
)
def test_a_flag_given_a_value_is_refused_with_a_hint(
    arguments: list[str], hint: str, capsys: pytest.CaptureFixture[str]
) -> None:
    assert run(arguments) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "flags take no value" in err and hint in err
    assert f"see 'jointplay {arguments[0]} --help'" in err


def test_an_extra_argument_that_follows_no_flag_gets_no_flag_hint(
    capsys: pytest.CaptureFixture[str],
) -> None:
    assert run(["fit", "H8/g7", "--size", "10mm", "2"]) == 2
    assert "flags take no value" not in capsys.readouterr().err


@pytest.mark.parametrize(
    ("text", "unit", "expected"),
    [
        ("200 rpm", "rad/s", 200 * math.pi / 30),
        ("20.9 rad/s", "rad/s", 20.9),
        ("600 h", "s", 600 * 3600.0),
        ("1 deg", "rad", math.pi / 180),
    ],
)
def test_quantity_options_convert_to_si(text: str, unit: str, expected: float) -> None:
    from jointplay.settings.mechanism import quantity_option

    assert quantity_option(text, unit, "--x", example="u") == pytest.approx(expected, rel=1e-15)


def test_quantity_options_refuse_bare_numbers_and_show_the_form() -> None:
    from jointplay.errors import ConfigError
    from jointplay.settings.mechanism import crank_speed, quantity_option

    with pytest.raises(
        ConfigError,
        match=re.escape("--hours: '600' has no unit; write it with one, e.g. \"600 h\""),
    ):
        quantity_option("600", "s", "--hours", example="h")
    with pytest.raises(
        ConfigError,
        match=re.escape("--rpm: '200' has no unit; write it with one, e.g. \"200 rpm\""),
    ):
        crank_speed("200")
    with pytest.raises(ConfigError, match="--step must be positive"):
        quantity_option("-1 deg", "rad", "--step", example="deg", positive=True)
    assert crank_speed("200 rpm") == pytest.approx(200 * math.pi / 30, rel=1e-15)


# --- help that renders ------------------------------------------------------------------------

HELP_COLUMNS = 80  # the narrowest terminal the help is written for


def command_names() -> list[str]:
    import typer.main

    from jointplay.cli import app

    return sorted(typer.main.get_command(app).commands)  # type: ignore[attr-defined]


def help_at_80(arguments: list[str], capsys: pytest.CaptureFixture[str], monkeypatch) -> str:
    monkeypatch.setenv("COLUMNS", str(HELP_COLUMNS))
    monkeypatch.delenv("TERMINAL_WIDTH", raising=False)
    assert run([*arguments, "--help"]) == 0
    return capsys.readouterr().out


@pytest.mark.parametrize("name", command_names())
def test_every_help_shows_its_brackets_and_whole_option_names_at_80_columns(
    name: str, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """Every ``[...]`` a help text was written with (``jointplay[gpu]``, ``[wear]``) is shown,
    not read as a Rich style tag, and every option's name is shown whole in its column."""
    import typer.main

    from jointplay.cli import app

    command = typer.main.get_command(app).commands[name]  # type: ignore[attr-defined]
    text = help_at_80([name], capsys, monkeypatch)
    assert max(len(line) for line in text.splitlines()) <= HELP_COLUMNS
    assert "…" not in text  # nothing cut: long words fold
    squashed = re.sub(r"[\s│]", "", text)  # a folded word reads whole again
    shown = [p for p in command.params if not getattr(p, "hidden", False)]
    written = [command.help or "", *[getattr(p, "help", None) or "" for p in shown]]
    brackets = {b for help_text in written for b in re.findall(r"\[[^\]\s]+\]", help_text)}
    for bracket in brackets:
        assert bracket in squashed, f"{name} --help lost {bracket}"
    assert "\\[" not in squashed, f"{name} --help shows an escape"  # escaped twice: '\\[wear]'
    names = re.findall(r"^│\s+(?:\*\s+)?(--[\w,-]+)", text, flags=re.MULTILINE)
    listed = {option for joined in names for option in joined.split(",")}
    secondary = set(re.findall(r"\s(--no-[\w-]+)\s", text))
    for param in shown:
        for option in (*param.opts, *param.secondary_opts):
            if option.startswith("--"):
                assert option in listed | secondary, f"{name} --help cut {option}"


def test_the_bracket_check_can_fail(capsys, monkeypatch) -> None:
    """Read as Rich markup, ``[gpu]`` vanishes: the check above would see it missing."""
    from rich.console import Console

    console = Console(width=HELP_COLUMNS, file=__import__("io").StringIO())
    console.print("pip install 'jointplay[gpu]'")
    assert "[gpu]" not in console.file.getvalue()  # type: ignore[attr-defined]


@pytest.mark.parametrize("cached", [True, False])
def test_a_first_run_says_it_compiles_the_kernels_and_how_long_it_took(
    cached: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    import jointplay._kernels
    from jointplay.cli._common import COMPILE_NOTICE, compiling_kernels

    monkeypatch.setattr(jointplay._kernels, "compiled_cache_present", lambda *_: cached)
    said: list[str] = []
    with compiling_kernels(said.append) as compiling:
        assert said == ([] if cached else [COMPILE_NOTICE])  # before the work
    assert compiling is not cached
    with compiling_kernels(said.append, needed=False) as compiling:  # no dynamics: no word
        assert not compiling
    if cached:
        assert said == []
    else:
        assert re.fullmatch(r"jointplay: kernels compiled and cached; this step took \d+ s "
                            r"with the compilation", said[-1])  # fmt: skip


@pytest.mark.parametrize("name", command_names())
def test_every_command_that_shows_progress_can_hide_it(name: str) -> None:
    """A command whose module draws a spinner or a progress bar takes --no-progress."""
    import inspect

    import typer.main

    from jointplay.cli import app

    command = typer.main.get_command(app).commands[name]  # type: ignore[attr-defined]
    source = inspect.getsource(inspect.getmodule(command.callback))  # type: ignore[arg-type]
    shows = bool(re.search(r"\bstatus\(|\bProgress\(|progress=", source))
    spellings = {o for p in command.params for o in (*p.opts, *p.secondary_opts)}
    assert not shows or "--no-progress" in spellings, f"{name} shows progress"


def test_console_tables_never_cut_a_header() -> None:
    """A design-like table at 80 columns: every word of every header is printed whole (Rich
    alone cut 'joint_force' to 'joint_fo…')."""
    import io

    from rich.console import Console
    from rich.table import Table

    from jointplay.cli._common import whole_headers

    headers = ["scheme", "cost", "yield %", "joint_force @99.73% (N)",
               "rocker_speed_error @99.73% (%)", "contact_pressure @99.73% (MPa)", "meets all"]  # fmt: skip

    def printed(fix: bool) -> str:
        table = Table(*headers, box=None)
        table.add_row(
            "O2=H7/g6,A=H7/g6,B=H7/g6,O4=H7/g6 c", "1.23", "99.5", "140", "2", "300", "yes"
        )
        console = Console(width=80, file=io.StringIO(), soft_wrap=True)
        console.print(whole_headers(table) if fix else table)
        return console.file.getvalue()  # type: ignore[attr-defined]

    words = {word for header in headers for word in header.split()}
    assert "…" in printed(fix=False)  # the check can fail
    text = printed(fix=True)
    assert "…" not in text
    assert all(word in text.split() for word in words)


def test_a_table_never_splits_a_number_nor_cuts_a_declared_no_wrap_header() -> None:
    """At 80 columns Rich folded numbers across lines ("4825." over ".8") and cut headers
    ("nomi…"; a no_wrap column's, "most influenti", where the console crops); whole_headers
    keeps them whole, and the table within 80 columns by wrapping the text cells."""
    import io

    from rich.console import Console
    from rich.table import Table

    from jointplay.cli._common import whole_headers

    headers = ["response", "nominal", "mean", "std", "min", "max", "ideal joints",
               "most influential"]  # fmt: skip
    rows = [["omega3_peak (rad/s)", "13.8365", "13.822", "0.0605", "13.597", "14.057",
             "13.726", "crank 62 %"],
            ["alpha3_peak (rad/s²)", "5330.54", "4825.8", "1455", "1044.4", "8328.4",
             "411.02", "clearance A 88 %"]]  # fmt: skip

    def printed(fix: bool) -> str:
        table = Table(box=None)
        for header in headers:
            table.add_column(header, no_wrap=header in ("response", "most influential"))
        for row in rows:
            table.add_row(*row)
        console = Console(width=80, file=io.StringIO(), soft_wrap=True)
        console.print(whole_headers(table) if fix else table)
        return console.file.getvalue()  # type: ignore[attr-defined]

    numbers = {cell for row in rows for cell in row[1:-1]}
    before = printed(fix=False).split()
    assert not numbers <= set(before) and "nomi…" in before  # the check can fail
    after = printed(fix=True)
    assert all(word in after.split() for header in headers for word in header.split())
    assert numbers <= set(after.split())
    assert max(len(line) for line in after.splitlines()) <= 80  # and it still fits


def test_the_ecs_tables_keep_every_header_and_number_whole_at_80_columns(monkeypatch) -> None:
    """A command's console tables on an 80-column terminal (ecs: six tables of up to 11
    columns): no "…", and every number of the same tables printed 200 wide is there whole."""
    import io

    from rich.console import Console

    import jointplay.cli.ecs as ecs

    def shown(width: int) -> list[str]:
        console = Console(width=width, file=io.StringIO(), force_terminal=True,
                          color_system=None, soft_wrap=True, highlight=False)  # fmt: skip
        monkeypatch.setattr(ecs, "console", console)
        assert run(["ecs"]) == 0
        return re.sub(r"\x1b\[[0-9;]*m", "", console.file.getvalue()).split()  # type: ignore[attr-defined]

    narrow, wide = shown(80), shown(200)
    assert not any("…" in word for word in narrow)
    numbers = {w for w in wide if re.fullmatch(r"-?\d[\d.]*(e[-+]\d+)?", w)}
    assert len(numbers) > 30
    assert numbers <= set(narrow), sorted(numbers - set(narrow))


#: The longest help a command may print at 80 columns (issue 25: design's first, 235 lines
#: in one panel, fits the terminal's scroll-back of one screenful or two).
MOST_HELP_LINES = 120


def test_design_help_is_grouped_in_panels_and_short(capsys, monkeypatch) -> None:
    """design's options are grouped by topic, in the panels' order, and its help at 80
    columns is at most MOST_HELP_LINES lines; the same options in one panel take more (the
    control: the count can fail)."""
    from typer import rich_utils

    from jointplay.cli._app import PANEL_ORDER

    text = help_at_80(["design"], capsys, monkeypatch)
    titles = re.findall(r"^╭─ (.+?) ─", text, flags=re.MULTILINE)
    assert titles == [t for t in PANEL_ORDER if t in titles]  # in the one order
    for panel in ("Requirements", "Sampling", "Contact", "The dynamic run", "Wear and cost",
                  "Execution", "Output"):  # fmt: skip
        assert panel in titles
    assert len(text.splitlines()) <= MOST_HELP_LINES
    monkeypatch.setattr(rich_utils, "_RICH_HELP_PANEL_NAME", "no_such_attribute")
    monkeypatch.setattr("jointplay.cli._app.option_panel", lambda param: "Options")
    one_panel = help_at_80(["design"], capsys, monkeypatch)
    assert "─ Sampling ─" not in one_panel
    assert len(one_panel.splitlines()) > MOST_HELP_LINES


@pytest.mark.parametrize("name", command_names())
def test_every_help_fits_and_keeps_the_panel_order(
    name: str, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    text = help_at_80([name], capsys, monkeypatch)
    from jointplay.cli._app import PANEL_ORDER

    titles = re.findall(r"^╭─ (.+?) ─", text, flags=re.MULTILINE)
    known = [t for t in titles if t in PANEL_ORDER]
    assert known == [t for t in PANEL_ORDER if t in known]
    assert len(text.splitlines()) <= MOST_HELP_LINES, f"{name} --help is too long"


def test_one_option_sits_in_one_panel_on_every_command() -> None:
    """One grammar: an option that several commands take (--settle, --contact, --out,
    --require, ...) is listed under the same panel title on each. ``--method`` names two
    things (a contact method; tolerance's sampling method) and is the one exception."""
    import typer.main

    from jointplay.cli import app
    from jointplay.cli._panels import OPTION_PANELS, option_panel

    panels: dict[str, set[str]] = {}
    for command in typer.main.get_command(app).commands.values():  # type: ignore[attr-defined]
        for param in command.params:
            for option in param.opts:
                if option.startswith("--") and option != "--method":
                    panels.setdefault(option, set()).add(option_panel(param))
    split = {option: found for option, found in panels.items() if len(found) > 1}
    assert not split, f"options in more than one panel: {split}"
    assert {panels[o].pop() for o in ("--settle", "--contact", "--require", "--out")} == {
        "The dynamic run", "Contact", "Requirements", "Output"}  # fmt: skip
    assert all(option in panels for option in OPTION_PANELS), "a panel for no option"


def test_a_number_range_is_shown_with_the_help(capsys, monkeypatch) -> None:
    """``--workers``'s bounds are read beside its help, not in a 30-character type column."""
    text = help_at_80(["design"], capsys, monkeypatch)
    assert "1<=x<=1024" in re.sub(r"[\s│]", "", text)
    assert "<int range>" not in text and "<int>" in text


@pytest.mark.parametrize("name", command_names())
def test_a_choice_shown_as_choice_is_named_in_its_help(name: str) -> None:
    """A choice option whose choices are too many for the type column (``<choice>``) names
    every one of them in its help text."""
    import typer.main

    from jointplay.cli import app
    from jointplay.cli._app import LONGEST_CHOICES

    command = typer.main.get_command(app).commands[name]  # type: ignore[attr-defined]
    for param in command.params:
        listed = param.display_type(None) if hasattr(param, "display_type") else None
        if listed and "|" in listed and len(listed) > LONGEST_CHOICES:
            assert param.display_type_rich(None) == "<choice>"
            for choice in listed.strip("<>").split("|"):
                assert choice in (getattr(param, "help", None) or ""), (param.opts, choice)
