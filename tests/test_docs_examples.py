"""Every command example of ``docs/*.md`` runs, and what the page promises of it is checked.

Each fenced block holding a command (``jointplay ...``, ``$ jointplay ...``, ``python
benchmarks/...``) must be claimed by exactly one entry of :data:`HANDLERS`, which runs it: as
written, or with a smaller sample count where the page gives the full one and the handler says
why (a design study of thousands of samples cannot run in the test suite), or, for an example
of an error, checking the error line the page prints. Where a page's text or comment gives a
result of the example (a fitted value, a wear life, a row of a table), the handler reads the
figure from the page and compares it with the run, so a page cannot drift from the program.
A new example without a handler fails :func:`test_every_example_block_has_one_handler`.
"""

from __future__ import annotations

import json
import math
import os
import re
import shlex
import signal
import subprocess
import sys
import urllib.request
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest

from jointplay.cli import run

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
#: A page's figures are rounded to two or three digits: 3 % covers that and the last bits a
#: different processor may change in a simulation with impacts.
ROUNDING = 0.03
#: Samples per scheme of a design example run smaller than the page's (each handler says why).
SMALL = 2
COMMAND = re.compile(r"^(\$ )?(jointplay |python benchmarks/)")


@dataclass(frozen=True)
class Block:
    """A fenced block of a docs page that holds commands.

    Attributes:
        page: The page's file name.
        commands: Its commands, continuation lines joined, ``$`` prompts and comments cut.
        comments: Each command's comment (``""`` when none).
        output: Its other lines: what the page shows the commands print.
    """

    page: str
    commands: tuple[str, ...]
    comments: tuple[str, ...]
    output: tuple[str, ...]

    @property
    def id(self) -> str:
        words = re.sub(r"[^\w.=/-]+", "-", self.commands[0].removeprefix("jointplay "))
        return f"{self.page.removesuffix('.md')}:{words.strip('-')[:50]}"


def example_blocks() -> list[Block]:
    found = []
    for page in sorted(DOCS.glob("*.md")):
        text = page.read_text(encoding="utf-8")
        for body in re.findall(r"^ *```\w*\n(.*?)^ *```", text, flags=re.MULTILINE | re.DOTALL):
            commands, comments, output = [], [], []
            for line in re.sub(r"\\\n\s*", " ", body).splitlines():
                line = line.strip()
                if COMMAND.match(line):
                    command, _, comment = line.removeprefix("$ ").partition("  #")
                    commands.append(command.strip())
                    comments.append(comment.strip())
                elif line:
                    output.append(line)
            if commands:
                found.append(Block(page.name, tuple(commands), tuple(comments), tuple(output)))
    return found


def _figure(pattern: str, text: str) -> tuple[str, ...]:
    found = re.search(pattern, text)
    assert found, f"the page no longer says {pattern!r}"
    return found.groups()


def _jointplay(command: str, capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    """Run a ``jointplay`` command line in this process: status, stdout, stderr."""
    status = run(shlex.split(command)[1:])
    output = capsys.readouterr()
    return status, output.out, output.err


def _ok(command: str, capsys: pytest.CaptureFixture[str]) -> str:
    status, out, err = _jointplay(command, capsys)
    assert status == 0, (command, err[-2000:])
    return out


def _samples(command: str, count: int) -> str:
    """``command`` with ``--samples count`` (replacing the page's count, or ``auto``)."""
    if "--samples" in command:
        return re.sub(r"--samples \S+", f"--samples {count}", command)
    return f"{command} --samples {count}"


def _summary(folder: Path) -> dict[str, Any]:
    summary: dict[str, Any] = json.loads((folder / "summary.json").read_text(encoding="utf-8"))
    return summary


# --- docs/calibration.md ------------------------------------------------------------------


def _measurement_files(folder: Path) -> None:
    """The quick start's files: two runs of rocker speeds (Table 7, and the same motion at
    300 RPM, its speeds 1.5 times as high) and one of the crank pivot's force."""
    from jointplay.dynamics.nominal import nominal_analysis
    from jointplay.io.config import load_preset

    table = (ROOT / "src/jointplay/data/paper_table7_rocker_speed.csv").read_text(encoding="utf-8")
    rows = [line.split(",") for line in table.splitlines() if line and not line.startswith("#")]
    for name, factor in (("run200.csv", 1.0), ("run300.csv", 1.5)):  # two columns: angle, speed
        lines = ["crank_deg,omega4", *(f"{row[0]},{factor * float(row[2]):g}" for row in rows[1:])]
        (folder / name).write_text("\n".join(lines) + "\n", encoding="utf-8")
    nominal = nominal_analysis(load_preset("paper-fourbar")).table
    every = nominal[nominal["crank_deg"] % 30 == 0]
    forces = [
        "crank_deg,F_O2",
        *(f"{a:g},{f:.6g}" for a, f in zip(every["crank_deg"], every["F_O2"], strict=True)),
    ]
    (folder / "forces.csv").write_text("\n".join(forces) + "\n", encoding="utf-8")


@pytest.mark.slow
def calibration_quick_start(block: Block, folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The six commands as one session in one folder (the last simulates the calibrated
    configuration an earlier one wrote); each fits what its comment or options say."""
    _measurement_files(folder)
    for command, comment in zip(block.commands, block.comments, strict=True):
        out = _ok(command, capsys)
        words = shlex.split(command)
        if words[1] != "calibrate":
            continue
        if "--json" in words:
            assert set(json.loads(out)["parameters"]) == {"crank-speed", "phase"}
        elif "--out" in words:
            assert (folder / words[words.index("--out") + 1] / "calibrated.toml").is_file()
        if "crank speed and phase" in comment:
            assert re.search(r"^ crank-speed ", out, re.M) and re.search(r"^ phase ", out, re.M)
    assert (folder / "sim" / "summary.json").is_file()


def test_calibrate_json_prints_what_the_page_shows(capsys: pytest.CaptureFixture[str]) -> None:
    """docs/calibration.md's ``--json`` output: the default fit (Table 7, crank speed and
    phase), its crank speed, interval and RMS errors as printed there (two decimals)."""
    text = (DOCS / "calibration.md").read_text(encoding="utf-8")
    (shown,) = re.findall(r"^```json\n(.*?)^```", text, flags=re.MULTILINE | re.DOTALL)
    page = json.loads(shown)
    printed = json.loads(_ok("jointplay calibrate --json", capsys))
    assert set(printed) == set(page)
    speed, expected = printed["parameters"]["crank-speed"], page["parameters"]["crank-speed"]
    assert expected["unit"] == speed["unit"]
    for key in ("value", "stderr"):
        assert speed[key] == pytest.approx(expected[key], abs=0.005 + 1e-9)
    assert speed["ci95"] == pytest.approx(expected["ci95"], abs=0.005 + 1e-9)
    for key in ("rms_before", "rms_after"):
        assert printed[key] == pytest.approx(page[key], abs=0.005 + 1e-9)
    assert printed["warnings"] == page["warnings"]


# --- docs/cli.md ----------------------------------------------------------------------------


def fails_with_the_line_shown(
    block: Block, folder: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """An example of bad input: exit status 2 and exactly the error line the page shows."""
    ((command,), (line,)) = block.commands, block.output
    status, _, err = _jointplay(command, capsys)
    assert status == 2
    assert " ".join(err.split()) == " ".join(line.split())


# --- docs/design.md -------------------------------------------------------------------------


@pytest.mark.slow
def design_synopsis(block: Block, folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The page's first example: the design study with 2 samples per scheme instead of
    ``--samples auto`` (20 schemes until each is decided: far too long for a test; the
    smaller run takes the same path; the page gives no result of it), the wear study as
    written (its life is not given either)."""
    design, wear = block.commands
    _ok(_samples(f"{design} --no-plots".replace("DIR", str(folder / "design")), SMALL), capsys)
    _ok(wear.replace("DIR", str(folder / "wear")), capsys)
    assert set(_summary(folder / "wear")["life_hours"]) == {"O2", "A", "B", "O4"}


def _row(text: str, scheme: str) -> list[str]:
    (row,) = re.findall(rf"^\| {re.escape(scheme)} \|(.*)\|$", text, flags=re.MULTILINE)
    return [cell.strip() for cell in row.split("|")]


@pytest.mark.slow
def design_table(block: Block, folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The README's design example, whose 50 samples per scheme the page tabulates: one
    scheme run at the full 50 samples (the same seed serves every scheme, so a scheme's
    samples do not depend on the others), its cost, yield, joint force and speed error
    against the table's lubricated column."""
    (command,) = block.commands
    text = (DOCS / "design.md").read_text(encoding="utf-8")
    cost, lubricated = _row(text, "H11/c11 / m")[:2]
    yield_, force, error = _figure(r"([\d.]+) %, ([\d.]+) N / ([\d.]+) %", lubricated)
    one = command.replace('"H7/g6,H8/f7,H8/g7,H11/c11"', "H11/c11").replace("m,c", "m")
    assert "--samples 50" in one and one != command
    _ok(one.replace("--out design", f"--no-plots --out {folder / 'design'}"), capsys)
    (scheme,) = _summary(folder / "design")["schemes"]
    assert scheme["cost"] == pytest.approx(float(cost), abs=0.05)
    assert scheme["samples"] == 50 and scheme["yield"] == pytest.approx(float(yield_), abs=0.5)
    assert scheme["joint_force_at_confidence"] == pytest.approx(float(force), rel=ROUNDING)
    error_percent = 100 * scheme["rocker_speed_error_at_confidence"]
    assert error_percent == pytest.approx(float(error), rel=ROUNDING)


def design_quick_tour(block: Block, folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The quick tour's design is the README's line, word for word: it runs once, at its full
    size, in ``tests/test_readme.py::test_each_quick_tour_line_runs[design-design]``, whose
    check (``check_design``) compares every row of this page's table and its model-sensitivity
    line with that run (the study took about 2 minutes, run twice before)."""
    from test_readme import tour

    (command,) = block.commands
    (line,) = (line for line in tour() if line.startswith("jointplay design "))
    assert shlex.split(command) == shlex.split(line)


@pytest.mark.slow
def design_smaller(block: Block, folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """A design example whose full run takes tens of minutes to hours (the page gives its
    time): 2 samples per scheme, the same command otherwise; the page's verdicts, which need
    thousands of samples, are not checked."""
    (command,) = block.commands
    command = command.replace("DIR", str(folder / "out"))
    if "--out" not in command:
        command += f" --out {folder / 'out'}"
    _ok(_samples(f"{command} --no-plots", SMALL), capsys)


@pytest.mark.slow
def wear_lives(block: Block, folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The worked answer's wear runs: the life each comment gives (``inf``: never worn out)."""
    for command, comment in zip(block.commands, block.comments, strict=True):
        out = folder / f"wear-{len(list(folder.iterdir()))}"
        _ok(command.replace("--out DIR", f"--no-plots --out {out}"), capsys)
        summary = _summary(out)
        (life,) = _figure(r"life ([\d.,]+|inf) h", comment)
        found = summary["mechanism_life_hours"]
        found = math.inf if found is None else found
        assert found == pytest.approx(float(life.replace(",", "")), rel=ROUNDING)
        for joint, hours in re.findall(r"(\w+) ([\d.,]+) h", comment.split(";")[-1]):
            assert summary["life_hours"][joint] == pytest.approx(
                float(hours.replace(",", "")), rel=ROUNDING
            )


@pytest.mark.slow
def design_life_quantile(block: Block, folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The B_p example at its full 20 samples (~58 CPU-s: its figures are of the full run):
    the failures before the hours, the verdict and the share's interval its comment gives,
    and the simulations per life the text after it gives."""
    (command,) = block.commands
    comment = " ".join(block.output)
    out = folder / "b10"
    printed = _ok(command.replace("--out design-b10", f"--no-progress --out {out}"), capsys)
    failures, samples = _figure(r"(\d+) of (\d+) samples fail before", comment)
    low, high = _figure(r"outliving it is ([\d.]+)–([\d.]+) %", comment)
    (scheme,) = _summary(out)["schemes"]
    (judged,) = scheme["requirements"]
    assert judged["requirement"] == "B10 >= 6 h"
    assert judged["samples"] == int(samples)
    # a life near the 6 h mark crosses it with the machine's round-off (dry wear is chaotic:
    # 2 of 20 on the page's machine, 1 of 20 on an Intel Xeon with AVX-512, as the page says)
    assert abs(judged["failures"] - int(failures)) <= 1
    assert judged["verdict"] in comment
    if judged["failures"] == int(failures):
        assert 100 * judged["verdict_interval"][0] == pytest.approx(float(low), abs=0.05)
        assert 100 * judged["verdict_interval"][1] == pytest.approx(float(high), abs=0.05)
    else:  # the exact (Clopper-Pearson) 95 % interval of the share outliving it
        from scipy.stats import beta

        n, kept = judged["samples"], judged["samples"] - judged["failures"]
        exact = [beta.ppf(0.025, kept, n - kept + 1), beta.ppf(0.975, kept + 1, n - kept)]
        assert judged["verdict_interval"] == pytest.approx(exact, rel=1e-9)
    page = (DOCS / "design.md").read_text(encoding="utf-8")
    (per_life,) = _figure(r"([\d.]+) per life\*\*", page)
    lives = _summary(out)["settings"]["functional_life"]["simulations"] / int(samples)
    assert lives == pytest.approx(float(per_life), rel=0.1)
    assert "life: B10 >= 6 h: " in printed


# --- docs/life.md ---------------------------------------------------------------------------


@pytest.mark.slow
def life_synopsis(block: Block, folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The population life with 2 mechanisms instead of the page's 20 (the command's path,
    not its statistics: 20 take minutes): its first-screen answer is the summary's headline,
    and every mechanism has its life."""
    (command,) = block.commands
    out = folder / "life"
    printed = _ok(
        _samples(command, SMALL).replace("--out DIR", f"--no-plots --no-progress --out {out}"),
        capsys,
    )
    summary = _summary(out)
    assert summary["headline"] in printed
    assert summary["mechanisms"] == SMALL
    assert summary["failures"] + summary["censored"] == SMALL


# --- docs/explore.md ------------------------------------------------------------------------


def explore_serves(block: Block, folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The server with a configuration file on a free port answers the page it names; the
    plain ``jointplay explore`` is that server on port 8765 with a browser opened, which a test
    cannot do beside other test sessions (a fixed port); ``pip install`` is the test extra."""
    command = next(c for c in block.commands if "--port 0" in c)
    pytest.importorskip("uvicorn")
    (folder / "my.toml").write_text(_ok("jointplay show paper-fourbar", capsys), encoding="utf-8")
    process = subprocess.Popen(
        [sys.executable, "-m", "jointplay", *shlex.split(command)[1:]],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=folder,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
    )
    try:
        assert process.stdout is not None
        line = process.stdout.readline()
        assert "http://" in line, (line, process.stderr.read() if process.stderr else "")
        url = line[line.index("http://") :].split()[0]
        with urllib.request.urlopen(url, timeout=60) as page:
            assert page.status == 200
    finally:
        process.send_signal(signal.SIGINT)
        process.communicate(timeout=60)


# --- docs/performance.md --------------------------------------------------------------------


@pytest.mark.slow
def benchmark_without_baseline(
    block: Block, folder: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """The kernel-only benchmark runs; the one with the SciPy baseline takes about 4 minutes,
    as the page says, and is run on demand, never in the suite."""
    command = next(c for c in block.commands if "--no-baseline" in c)
    done = subprocess.run(
        [sys.executable, *shlex.split(command)[1:]],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=False,
        env={**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)},
        timeout=600,
    )
    assert done.returncode == 0, done.stderr[-2000:]


#: (page, a string only its block holds, the handler): one per example block.
Handler = Callable[[Block, Path, pytest.CaptureFixture[str]], None]
HANDLERS: tuple[tuple[str, str, Handler], ...] = (
    ("calibration.md", "jointplay calibrate --column mbd_printed --json", calibration_quick_start),
    ("cli.md", "jointplay fit H8/g7 --size 10mm --json true", fails_with_the_line_shown),
    ("cli.md", "jointplay kinematics --rpm 200 --out k", fails_with_the_line_shown),
    ("cli.md", 'jointplay kinematics --rpm "200,5 rpm" --out k', fails_with_the_line_shown),
    ("design.md", '--require "life >= 100 h" --clearance-limit "+20 um" --confidence 99.73', design_synopsis),
    ("design.md", '--require "rocker_speed_error <= 3 %" --samples 50 --out design', design_table),
    ("design.md", 'jointplay design --preset paper-fourbar --require "joint_force <= 150 N"', design_smaller),
    ("design.md", '--fits "H9/d9,H11/c11"', design_smaller),
    ("design.md", '--require "life >= 200 h" --clearance-limit "+20 um" --wear-coefficient 1e-6 --samples 200', design_smaller),
    ("design.md", "jointplay wear --preset paper-fourbar --fit H8/g7", wear_lives),
    ("design.md", '--require "B10 >= 6 h"', design_life_quantile),
    ("design.md", '--require "rocker_speed_error <= 3 %" --confidence 95 --out design', design_quick_tour),
    ("explore.md", "jointplay explore --config my.toml --port 0 --no-browser", explore_serves),
    ("life.md", "jointplay life --fit H8/g7 --clearance-limit", life_synopsis),
    ("performance.md", "python benchmarks/bench_clearance.py --no-baseline", benchmark_without_baseline),
)  # fmt: skip


def _handlers(block: Block) -> list[Handler]:
    return [
        h for page, s, h in HANDLERS if page == block.page and any(s in c for c in block.commands)
    ]


def test_every_example_block_has_one_handler() -> None:
    blocks = example_blocks()
    assert [b.id for b in blocks if len(_handlers(b)) != 1] == []
    claimed = {(page, s) for page, s, _ in HANDLERS}
    used = {
        (p, s)
        for p, s, _ in HANDLERS
        for b in blocks
        if b.page == p and any(s in c for c in b.commands)
    }
    assert claimed == used  # no handler for an example that is gone


def _marks(block: Block) -> list[pytest.MarkDecorator]:
    handlers = _handlers(block)
    return list(getattr(handlers[0], "pytestmark", [])) if len(handlers) == 1 else []


@pytest.mark.parametrize(
    "block", [pytest.param(b, id=b.id, marks=_marks(b)) for b in example_blocks()]
)
def test_each_docs_example_runs(
    block: Block,
    tmp_path: Path,
    monkeypatch: pytest.MonkeyPatch,
    capsys: pytest.CaptureFixture[str],
) -> None:
    monkeypatch.chdir(tmp_path)
    (handler,) = _handlers(block)
    handler(block, tmp_path, capsys)
