"""The README's code runs: its Python block, and every ``jointplay`` line of its quick tour,
and what a tour line's comment promises is what the program does.

Sample counts are made small (:data:`SMALLER`, said per substitution) so the commands run in
seconds; the lines whose comments promise a result run at the README's full size, and
:data:`CHECKS` reads each promise's numbers from the comment itself and compares them with the
run's ``summary.json`` (within :data:`ROUNDING`): a change of the program's results fails here
until the README says the new ones. Lines that need what a test machine does not have are
skipped with the reason: the GPU backend without JAX, a Dask cluster. The install, test and
development blocks are not run here (``pip install``, ``pytest``, ``.ci/run``): CI runs those
itself.
"""

from __future__ import annotations

import ast
import importlib.util
import json
import re
import shlex
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

import jointplay
from jointplay.cli import run

README = Path(__file__).resolve().parents[1] / "README.md"
DESIGN_PAGE = README.parent / "docs" / "design.md"
#: (pattern, replacement, why): the README's counts, made small for a test.
SMALLER = (
    (r"--samples \d+", "--samples 4", "4 samples: the command's path, not its statistics"),
    (r"samples=200", "samples=4", "the same for the Python study"),
    (r"10_000", "16", "16 batch samples instead of 10 000"),
)  # fmt: skip
#: A comment's figures are rounded to two or three digits: 3 % covers that and the last bits
#: a different processor may change in a simulation with impacts.
ROUNDING = 0.03


def blocks(language: str) -> list[str]:
    """The README's fenced code blocks in ``language``."""
    text = README.read_text(encoding="utf-8")
    return re.findall(rf"^```{language}\n(.*?)^```", text, flags=re.MULTILINE | re.DOTALL)


def smaller(code: str) -> str:
    for pattern, replacement, _ in SMALLER:
        code = re.sub(pattern, replacement, code)
    return code


def tour() -> dict[str, str]:
    """Each ``jointplay`` command of the quick tour (continuation lines joined) and its comment
    (the comment lines below it joined)."""
    block = next(b for b in blocks("bash") if "jointplay show paper-fourbar" in b)
    entries: dict[str, str] = {}
    last = ""
    for line in re.sub(r"\\\n\s*", " ", block).splitlines():
        if line.strip().startswith("#"):  # the comment of the line above goes on
            entries[last] = f"{entries[last]} {line.strip().lstrip('#').strip()}".strip()
            continue
        command, _, comment = line.partition("  #")
        if command.strip().startswith("jointplay "):
            last = command.strip()
            entries[last] = comment.strip()
    return entries


def tour_lines() -> list[str]:
    """Each ``jointplay`` command of the quick tour, continuation lines joined, comments cut."""
    return list(tour())


def _number(pattern: str, comment: str) -> tuple[str, ...]:
    found = re.search(pattern, comment)
    assert found, f"the README's comment no longer says {pattern!r}: {comment!r}"
    return found.groups()


def _summary(folder: Path) -> dict[str, Any]:
    summary: dict[str, Any] = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    return summary


def _warnings(summary: dict[str, Any]) -> list[str]:
    return sorted(d["code"] for d in summary["diagnostics"] if d["level"] == "warning")


def _deepest(summary: dict[str, Any]) -> float:
    """The deepest penetration of any joint over the run, m."""
    return max(summary["solver"]["max_penetration_per_joint_m"].values())


def check_conventional(line: str, comment: str, folder: Path) -> None:
    """The paper's conventional contact from rest: a law named runs dry (how deep the pins
    sink, the warning, the force peak as the crank starts), and with the lubricant the
    comment names, the film holds the pins near the ideal joints' force."""
    summary = _summary(folder / "conventional")
    assert {j["regime"] for j in summary["lubrication"].values()} == {"dry"}
    depth, clearance = _number(
        r"the pins sink ([\d.]+) µm into ([\d.]+) µm, with a warning", comment
    )
    assert _deepest(summary) == pytest.approx(float(depth) * 1e-6, rel=ROUNDING)
    assert "penetration-exceeds-clearance" in _warnings(summary)
    joints = summary["clearance_joints"]
    assert {j["clearance_m"] for j in joints.values()} == {float(clearance) * 1e-6}
    joint, force = _number(r"F_(\w+) peaks at ([\d.e+]+) N as the crank starts", comment)
    peak = summary["peaks"][f"F_{joint}"]
    assert peak["revolution"] == 1 and peak["crank_deg"] < 1.0
    assert peak["value"] == pytest.approx(float(force), rel=ROUNDING)
    flags, h_min, joint, force, ideal = _number(
        r"with \((--[^)]*)\) the π-film holds them in full film \(h_min ([\d.]+) µm\) and "
        r"F_(\w+) peaks at ([\d.]+) N \(ideal joints ([\d.]+) N\)",
        comment,
    )
    command = [*shlex.split(line)[1:], *flags.split(), "--no-plots"]
    command[command.index("--out") + 1] = str(folder / "oil")
    assert run(command) == 0
    summary = _summary(folder / "oil")
    films = {(j["regime"], j["film_model"]) for j in summary["lubrication"].values()}
    assert films == {("oil", "short-bearing-pi")}
    regimes = summary["film_regimes"].values()
    assert all(r["full_film"] == 1.0 for r in regimes)
    lowest = min(r["h_min_m"] for r in regimes)
    assert lowest == pytest.approx(float(h_min) * 1e-6, rel=ROUNDING)
    assert "penetration-exceeds-clearance" not in _warnings(summary)
    assert summary["peaks"][f"F_{joint}"]["value"] == pytest.approx(float(force), rel=ROUNDING)
    assert summary["nominal_peaks"][f"F_{joint}"] == pytest.approx(float(ideal), rel=ROUNDING)


def check_running(line: str, comment: str, folder: Path) -> None:
    """Steady running: the only warning is the mechanism's transmission angle."""
    summary = _summary(folder / "running")
    (angle,) = _number(
        r"no joint warning \(the paper's transmission angle, ([\d.]+)° < 40°", comment
    )
    assert _warnings(summary) == ["transmission-angle-low"]
    (low,) = [d for d in summary["diagnostics"] if d["code"] == "transmission-angle-low"]
    assert low["value"] == pytest.approx(float(angle), abs=0.05)


def check_wear(line: str, comment: str, folder: Path) -> None:
    """Lubricated, no joint wears: each is in full film throughout, with the smallest film
    thickness the comment gives, and the mechanism has no finite life over the hours run."""
    summary = _summary(folder / "wear")
    (h_min,) = _number(r"full film throughout in all four joints \(h_min ≥ ([\d.]+) µm\)", comment)
    (hours,) = _number(r"no joint wears over (\d+) h", comment)
    no_wear = summary["no_wear"]
    assert set(no_wear) == {"O2", "A", "B", "O4"}
    assert all(why.startswith("full film throughout") for why in no_wear.values())
    assert summary["max_depth_bearing_m"] == {joint: 0.0 for joint in no_wear}
    lowest = min(r["h_min_m"] for runs in summary["film_regimes"].values() for r in runs)
    assert lowest == pytest.approx(float(h_min) * 1e-6, rel=ROUNDING)
    assert summary["mechanism_life_hours"] is None
    assert f'--hours "{hours} h"' in line


def _row(text: str, scheme: str) -> list[str]:
    (row,) = re.findall(rf"^\| {re.escape(scheme)} \|(.*)\|$", text, flags=re.MULTILINE)
    return [cell.strip() for cell in row.split("|")]


def check_design(line: str, comment: str, folder: Path) -> None:
    """The design decides on its first run: the scheme the comment names is the one chosen
    (every requirement shown to meet at the confidence asked). The same run is the example
    of docs/design.md's "The quick tour's design" (its handler in tests/test_docs_examples.py
    checks that the page's command is this line): every row of the page's table — cost, the
    samples its verdict took, the speed-error failures, the interval the verdict was decided
    on, the verdict — and the model-sensitivity line the page and the README describe (the
    choice does not hold with the joints dry) are this run's, so the study runs once."""
    summary = _summary(folder / "design")
    (scheme,) = _number(r"chooses (\S+ / \w+)", comment)
    assert summary["best"] == scheme, summary["verdict"]
    assert f"shown to meet every requirement: {scheme} " in summary["verdict"]
    page = DESIGN_PAGE.read_text(encoding="utf-8")
    text = page.split("## The quick tour's design")[1].split("\n## ")[0]
    schemes = summary["schemes"]
    # the page's table lists exactly the schemes that ran (cost-ordered: the dearer ones wait)
    listed = re.findall(r"^\| (H\S+ / \w+) \|", text, flags=re.MULTILINE)
    assert sorted(listed) == sorted(row["scheme"] for row in schemes)
    not_run = summary["settings"]["not_run"]
    (chosen_cost,) = (row["cost"] for row in schemes if row["scheme"] == scheme)
    assert not_run and all(r["cost"] >= chosen_cost for r in not_run)
    assert f"not run: {len(not_run)} dearer than a scheme shown to meet" in " ".join(text.split())
    for r in not_run:
        assert r["scheme"] in text, r["scheme"]
    for row in schemes:
        cost, samples, failures, interval, verdict = _row(text, row["scheme"])
        (speed,) = (r for r in row["requirements"] if r["requirement"].startswith("rocker"))
        low, high = (float(v) for v in interval.split("–"))
        assert row["cost"] == pytest.approx(float(cost), abs=0.05)
        assert row["samples"] == int(samples) and speed["failures"] == int(failures)
        assert 100 * speed["verdict_interval"][0] == pytest.approx(low, abs=0.005)
        assert 100 * speed["verdict_interval"][1] == pytest.approx(high, abs=0.005)
        assert row["verdict"] == verdict.strip("*")
    assert "The model-sensitivity line says the choice **does not hold with the joints dry**" in (
        " ".join(text.split())
    )
    assert "the choice does not hold with the joints dry (the model-sensitivity line)" in " ".join(
        README.read_text(encoding="utf-8").split()
    )
    sensitivity = summary["model_sensitivity"]
    assert sensitivity["scheme"] == scheme and not sensitivity["holds"]
    (dry,) = (r for r in sensitivity["rows"] if r["parameter"] == "lubrication")
    assert dry["value"] == "dry" and not dry["meets_every_requirement"]


#: The tour lines whose comments promise a result, by their ``--out``: the check of each.
CHECKS: dict[str, Callable[[str, str, Path], None]] = {
    "conventional": check_conventional,
    "design": check_design,
    "running": check_running,
    "wear": check_wear,
}
#: Comments that describe the command rather than promise a result.
DESCRIPTIONS = (
    "edit lengths, masses, joints, tolerances",
    "a law named runs dry unless a lubricant is named",
)


def _out(line: str) -> str:
    found = re.search(r"--out (\S+)", line)
    return found.group(1) if found else ""


def test_every_promise_of_the_tour_is_checked() -> None:
    promised = {
        _out(line) for line, comment in tour().items() if comment not in ("", *DESCRIPTIONS)
    }
    assert promised == set(CHECKS)
    # the checked lines run at the README's size
    assert all(smaller(line) == line for line in tour() if _out(line) in CHECKS)


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
@pytest.mark.parametrize(
    "line", tour_lines(), ids=lambda line: "-".join(filter(None, (line.split()[1], _out(line))))
)
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
    check = CHECKS.get(_out(line))
    if check is not None:
        check(line, tour()[line], tmp_path)
