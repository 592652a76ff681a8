"""A fast command line (issue 41): the options of ``simulate`` are read and checked before
the numerical stack is imported, so a mistyped option is one error line without waiting for
SciPy, pandas and Numba (seconds on a loaded machine). No timing here: the speed is measured
by ``benchmarks/bench_cli_startup.py``; these tests check what is imported."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path
from typing import Annotated

import pytest

#: What a command that only reads its options must not import.
HEAVY = ("numba", "scipy", "pandas", "matplotlib", "dask", "pint")

CHECK = """
import sys
from jointplay.cli import run
status = run(sys.argv[1:])
print("STATUS", status)
print("HEAVY", ",".join(m for m in {heavy!r} if m in sys.modules))
"""


def _run(arguments: list[str]) -> tuple[int, list[str], str]:
    """(exit status, heavy modules imported, stderr) of ``jointplay ARGUMENTS`` in a fresh
    interpreter."""
    done = subprocess.run(
        [sys.executable, "-c", CHECK.format(heavy=HEAVY), *arguments],
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    )
    lines = dict(line.split(" ", 1) for line in done.stdout.splitlines() if " " in line)
    heavy = [name for name in lines.get("HEAVY", "").strip().split(",") if name]
    return int(lines["STATUS"]), heavy, done.stderr


@pytest.mark.parametrize(
    ("options", "named"),
    [
        (["--rpm", "200 rmp"], "'rmp' is not defined"),
        (["--clearance", "0.021 mmm"], "--clearance"),
        (["--format", "xls"], "--format"),
        (["--revolutions", "-1"], "--revolutions"),
        (["--sample-deg", "500 deg"], "--sample-deg"),
        (["--max-step", "1 mss"], "--max-step"),
        (["--atol", "2 um"], "--atol"),
        (["--onset-tolerance", "0 um"], "--onset-tolerance"),
    ],
)
def test_a_bad_option_is_one_line_before_the_numerical_stack_loads(
    options: list[str], named: str, tmp_path: Path
) -> None:
    out = tmp_path / "out"
    status, heavy, err = _run(["simulate", *options, "--out", str(out)])
    assert status == 2 and named in err and len(err.strip().splitlines()) == 1, err
    assert heavy == [], f"imported {heavy} before refusing {options}"
    assert not out.exists()


class _Clock:
    """A stand-in for ``time.perf_counter``: every reading is one second after the one
    before, and the stand-ins below move it on by what their work would take. Any interval
    between two readings that the timing line leaves out shows as missing seconds."""

    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        self.now += 1.0
        return self.now


def test_the_paper_timing_line_adds_up(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    """The first paper of a fresh install said '323 s (simulations 166 s, report 15 s)':
    142 s were not accounted for (the imports and compilation before the study, the folder
    after it). Now its parts add up to its total."""
    import re
    import time
    from types import SimpleNamespace

    import jointplay._kernels
    import jointplay.report.paper
    import jointplay.study.paper
    from jointplay.cli import run

    clock = _Clock()
    monkeypatch.setattr(time, "perf_counter", clock)
    monkeypatch.setattr(jointplay._kernels, "compiled_cache_present", lambda *_: False)

    def study(options: object, *, progress: object = None, animation: bool = False) -> object:
        begun = time.perf_counter()
        phases = {"nominal analysis and ECS": 4.0, "kernels": 31.0, "simulations": 166.0}
        clock.now += sum(phases.values()) + 20.0  # 20 s of analyses the phases do not name
        return SimpleNamespace(
            options=options,
            wall_s=time.perf_counter() - begun,
            extra={"kernels_s": 31.0, "phases": phases},
        )

    def report(study: object, folder: Path, record: object, **_: object) -> None:
        clock.now += 15.0

    monkeypatch.setattr(jointplay.study.paper, "run_paper_study", study)
    monkeypatch.setattr(jointplay.report.paper, "write_paper_report", report)
    out = tmp_path / "out"
    assert run(["paper", "--out", str(out), "--no-progress"]) == 0
    line = capsys.readouterr().out.strip().splitlines()[-1]
    found = re.fullmatch(r"paper study written to .* in (\d+) s \((.*)\)", line)
    assert found, line
    parts = {
        name.strip(): int(seconds) for name, seconds in re.findall(r"([^,]+?) (\d+) s", found[2])
    }
    assert sum(parts.values()) == int(found[1]), line
    assert parts["compiling"] == 31 and parts["simulations"] == 166 and parts["report"] >= 15


@pytest.mark.parametrize(
    "parts",
    [
        {"a": 0.4, "b": 0.4, "c": 0.4},
        {"start-up": 3.49, "simulations": 166.51, "report": 14.5, "other": 0.5},
        {"only": 0.2},
        {"x": 10.0, "y": 20.0},
    ],
)
def test_the_rounded_parts_add_up_to_the_rounded_total(parts: dict[str, float]) -> None:
    from jointplay.cli.paper import accounted

    total, shown = accounted(parts)
    assert total == round(sum(parts.values()))
    numbers = [int(n) for n in __import__("re").findall(r"(\d+) s", shown)]
    assert sum(numbers) == total or (total == 0 and numbers == [0]), shown


def test_a_mistyped_unit_loads_not_even_numpy(tmp_path: Path) -> None:
    """Reading the mechanism and its quantities needs no NumPy (about 0.1 s of CPU): the
    error line of ``--rpm "200 rmp"`` costs about what ``--version`` does."""
    status, _, err = _run(["simulate", "--rpm", "200 rmp", "--out", str(tmp_path / "o")])
    assert status == 2 and "'rmp' is not defined" in err
    done = subprocess.run(
        [
            sys.executable,
            "-c",
            "import sys\nfrom jointplay.cli import run\n"
            f"run(['simulate', '--rpm', '200 rmp', '--out', {str(tmp_path / 'o')!r}])\n"
            "print('NUMPY', 'numpy' in sys.modules)",
        ],
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    )
    assert "NUMPY False" in done.stdout, done.stdout


#: Values of each plain kind of option, those read without Pydantic and those left to it
#: (underscores, inf, hexadecimal, a number out of range, an empty path).
OPTION_VALUES = {
    "--text": ["abc", "", " 200 rpm ", "é µ", "-"],
    "--count": ["3", "+3", "-0", "007", " 3", "1_0", "3.0", "1e3", "x", "99999999999999999999"],
    "--workers": ["1", "10", "0", "11", "-1", "5.5"],
    "--ratio": ["1", "1.", ".5", "-2.5e-3", "1E5", "1e400", "inf", "nan", "1_0", "0x10", "a"],
    "--folder": ["out", "a//b/", "./x y", "", "/"],
}


def _plain_options_app() -> object:
    import typer

    app = typer.Typer()

    @app.command()
    def main(
        text: Annotated[str | None, typer.Option("--text")] = None,
        count: Annotated[int | None, typer.Option("--count")] = None,
        workers: Annotated[int, typer.Option("--workers", min=1, max=10)] = 2,
        ratio: Annotated[float | None, typer.Option("--ratio")] = None,
        folder: Annotated[Path | None, typer.Option("--folder")] = None,
        flag: Annotated[bool, typer.Option("--flag/--no-flag")] = False,
    ) -> tuple[object, ...]:
        return (text, count, workers, ratio, folder, flag)

    return app


def _outcome(app: object, arguments: list[str]) -> tuple[str, str]:
    """What ``arguments`` give: the values (their types and reprs) or the error message."""
    try:
        values = app(args=arguments, standalone_mode=False)  # type: ignore[operator]
    except Exception as exc:  # Click's BadParameter and UsageError
        message = exc.format_message() if hasattr(exc, "format_message") else str(exc)
        return "error", message
    return "values", repr([(type(v).__name__, repr(v)) for v in values])


def test_option_values_read_without_pydantic_are_what_pydantic_reads() -> None:
    """Options are converted without Pydantic (~0.1 s of every command's start-up) only
    where int(), float(), str and Path give what Typer's Pydantic converter gives; every
    value of the table gives the same values, or the same error message, both ways."""
    import typer.core
    from typer._coercion import build_runtime_param

    import jointplay.cli  # noqa: F401  (installs the plain converter)

    assert typer.core.build_runtime_param is not build_runtime_param
    plain = typer.core.build_runtime_param
    compared = 0
    for option, values in OPTION_VALUES.items():
        for value in values:
            arguments = [f"{option}={value}", "--flag"]
            typer.core.build_runtime_param = plain
            ours = _outcome(_plain_options_app(), arguments)
            try:
                typer.core.build_runtime_param = build_runtime_param
                typers = _outcome(_plain_options_app(), arguments)
            finally:
                typer.core.build_runtime_param = plain
            assert ours == typers, (option, value)
            compared += 1
    assert compared == sum(len(v) for v in OPTION_VALUES.values())


def test_a_bad_option_imports_no_pydantic(tmp_path: Path) -> None:
    """Typer converts option values with Pydantic; jointplay reads the plain ones itself, so
    neither a command's error line nor its run waits for Pydantic's import."""
    done = subprocess.run(
        [
            sys.executable,
            "-c",
            "import sys\nfrom jointplay.cli import run\n"
            "status = run(['simulate', '--rpm', '200 rmp', '--rtol', '1e-6', '--no-plots', "
            f"'--out', {str(tmp_path / 'o')!r}])\n"
            "print('STATUS', status, 'PYDANTIC', 'pydantic' in sys.modules)",
        ],
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    )
    assert "STATUS 2 PYDANTIC False" in done.stdout, done.stdout + done.stderr


#: What a default ``simulate --no-plots`` (one run of the single engine) must not import:
#: the plotting stack and the report; SciPy's statistics and integrators (its optimizers
#: are: the restitution law's χ is found with ``brentq``); the batch engine's lanes, its
#: process, Dask and JAX back ends.
NOT_FOR_ONE_RUN = (
    "matplotlib",
    "PIL",
    "jointplay.report",
    "scipy.stats",
    "scipy.integrate",
    "jointplay._kernels.batch",
    "jointplay._kernels.jax_batch",
    "jointplay._kernels.lanes.cuda",
    "jointplay._kernels.workers",
    "numba.cuda",
    "dask",
    "jax",
    "multiprocessing",
    "pint",
    "pydantic",
)


def test_a_run_without_plots_loads_only_what_it_runs(tmp_path: Path) -> None:
    """``simulate --no-plots`` runs the single engine once and writes tables and JSON: none
    of :data:`NOT_FOR_ONE_RUN` is imported."""
    out = tmp_path / "out"
    code = (
        "import sys\nfrom jointplay.cli import run\n"
        "status = run(['simulate', '--no-plots', '--no-progress', '--settle', '0', "
        f"'--revolutions', '0.25', '--out', {str(out)!r}])\n"
        "print('STATUS', status)\n"
        f"names = {NOT_FOR_ONE_RUN!r}\n"
        "print('LOADED', ','.join(n for n in names if any(m == n or m.startswith(n + '.') "
        "for m in sys.modules)))\n"
    )
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, timeout=900
    )
    lines = dict(line.split(" ", 1) for line in done.stdout.splitlines() if " " in line)
    assert lines.get("STATUS") == "0", done.stdout + done.stderr
    assert lines["LOADED"].strip() == "", f"a run without plots imported {lines['LOADED']}"
    assert (out / "summary.json").is_file() and not list(out.glob("*.png"))
