"""The README's code runs: its Python block, and every ``jointplay`` line of its quick tour.

Sample counts and run lengths are made small (:data:`SMALLER`, said per substitution) so the
commands run in seconds; what each line does is otherwise the README's. Lines that need what
a test machine does not have are skipped with the reason: the GPU backend without JAX, a
Dask cluster. The install, test and development blocks are not run here (``pip install``,
``pytest``, ``.ci/run``): CI runs those itself.
"""

from __future__ import annotations

import ast
import importlib.util
import re
import shlex
from pathlib import Path

import pytest

import jointplay
from jointplay.cli import run

README = Path(__file__).resolve().parents[1] / "README.md"
#: (pattern, replacement, why): the README's counts, made small for a test.
SMALLER = (
    (r"--samples \d+", "--samples 4", "4 samples: the command's path, not its statistics"),
    (r"samples=200", "samples=4", "the same for the Python study"),
    (r"10_000", "16", "16 batch samples instead of 10 000"),
    (r"--revolutions 20\b", "--revolutions 1", "one analysed revolution"),
    (r'--hours "600 h" --update-hours "50 h"', '--hours "100 h" --update-hours "50 h"', "two wear updates"),
)  # fmt: skip


def blocks(language: str) -> list[str]:
    """The README's fenced code blocks in ``language``."""
    text = README.read_text(encoding="utf-8")
    return re.findall(rf"^```{language}\n(.*?)^```", text, flags=re.MULTILINE | re.DOTALL)


def smaller(code: str) -> str:
    for pattern, replacement, _ in SMALLER:
        code = re.sub(pattern, replacement, code)
    return code


def tour_lines() -> list[str]:
    """Each ``jointplay`` command of the quick tour, continuation lines joined, comments cut."""
    tour = next(b for b in blocks("bash") if "jointplay show paper-fourbar" in b)
    joined = re.sub(r"\\\n\s*", " ", tour)
    lines = [line.split("  #")[0].strip() for line in joined.splitlines()]
    return [line for line in lines if line.startswith("jointplay ")]


def test_every_name_the_readme_imports_from_the_top_is_there() -> None:
    names = [
        alias.name
        for block in blocks("python")
        for node in ast.walk(ast.parse(block))
        if isinstance(node, ast.ImportFrom) and node.module == "jointplay"
        for alias in node.names
    ]
    assert names  # the README does import from the top
    for name in names:
        assert getattr(jointplay, name) is not None, name


@pytest.mark.slow
def test_the_python_block_runs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(tmp_path)
    (code,) = blocks("python")
    exec(compile(smaller(code), str(README), "exec"), {"__name__": "readme"})


@pytest.mark.slow
@pytest.mark.parametrize("line", tour_lines())
def test_each_quick_tour_line_runs(
    line: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]
) -> None:
    if "--dask-scheduler" in line:
        pytest.skip("needs a Dask cluster at tcp://scheduler:8786")
    if "--backend gpu" in line and importlib.util.find_spec("jax") is None:
        pytest.skip("the GPU backend needs JAX (pip install 'jointplay[gpu]')")
    monkeypatch.chdir(tmp_path)
    if "--config my.toml" in line:  # the tour's first line writes it
        assert run(["show", "paper-fourbar"]) == 0
        (tmp_path / "my.toml").write_text(capsys.readouterr().out, encoding="utf-8")
    command, _, redirect = smaller(line).partition(" > ")
    status = run(shlex.split(command)[1:])
    output = capsys.readouterr()
    assert status == 0, output.err[-2000:]
    if redirect:
        (tmp_path / redirect.strip()).write_text(output.out, encoding="utf-8")
