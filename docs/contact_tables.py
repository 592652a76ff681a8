"""Regenerate, or check, the tables of numbers in docs/contact.md.

Each table lies between two marker comments in the page::

    <!-- contact-tables: NAME -->
    | ... the table ... |
    <!-- /contact-tables: NAME -->

and is computed here with the package, by running ``jointplay simulate`` in this process
(the command's own reading of the options, its integrator choice and its summary.json), on
the paper four-bar at 200 rpm, steady start, settle 2 + 1 revolution, all four joints at one
clearance. Dry joints run chaotically (docs/contact.md, "What the default gives"): their
table gives statistics over 20 settled revolutions (``revolution_statistics``), not one
trajectory's peaks, which are draws.

Usage (from the repository root, the checkout's sources first on the path)::

    PYTHONPATH=src python docs/contact_tables.py           # rewrite the tables in place
    PYTHONPATH=src python docs/contact_tables.py --check   # exit 1 if a table drifted

``--check`` compares every number of a table with the page's: the deterministic tables to
the digits printed (one unit of the last digit; the step counts within
:data:`STEP_TOLERANCE`), the dry statistics within :data:`DRY_TOLERANCE` (a chaotic
trajectory's statistics move with the platform's round-off). ``tests/docs/test_contact_tables.py`` runs it in check mode. The package does not
import this file.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import re
import sys
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

DOC = Path(__file__).with_name("contact.md")
JOINTS = ("O2", "A", "B", "O4")
#: The clearances of the film tables, µm.
FILM_CLEARANCES = (21.0, 85.0, 130.0)
#: The clearances and film dampings of the linear damper's table (µm, N·s/m).
DAMPER_CLEARANCES = (6.0, 21.0, 60.0)
DAMPINGS = ("1e3", "1e4", "1e5", "1e6", "1e7")
#: The dry statistics' ensemble: runs, and settled revolutions of each (``--ensemble``).
DRY_RUNS = 8
DRY_REVOLUTIONS = 10
#: Relative tolerance of ``--check`` on the dry statistics (chaotic: an ensemble's statistics,
#: not a trajectory, are what carries over between platforms and kernel versions; one
#: trajectory's even dwell in different states: docs/performance.md, "Accuracy of irregular
#: (chaotic) running").
DRY_TOLERANCE = 0.15
#: Relative tolerance of ``--check`` on the integrator's step counts (a column or row named
#: "steps"): the same code takes a few more or fewer steps on another machine, whose round-off
#: differs (NumPy's SIMD paths for the initial state, the C library's functions): 1 991 and
#: 2 576 steps in the page (an AMD EPYC), 2 009 and 2 566 on an Intel Xeon with AVX-512, for
#: the loose fits under the linear damper, every peak the same to its printed digits.
STEP_TOLERANCE = 0.02
FILMS = (("linear", "linear"), ("short-bearing-pi", "`short-bearing-pi`"),
         ("short-bearing-full", "`short-bearing-full`"))  # fmt: skip


def simulate(*options: str) -> dict[str, Any]:
    """summary.json of ``jointplay simulate`` on the paper four-bar with ``options``."""
    from jointplay.cli import run

    with tempfile.TemporaryDirectory(prefix="contact-tables-") as folder:
        out = Path(folder) / "run"
        args = ["simulate", "--preset", "paper-fourbar", "--joints", ",".join(JOINTS),
                "--start", "steady", "--no-plots", "--out", str(out), *options]  # fmt: skip
        printed = io.StringIO()
        with contextlib.redirect_stdout(printed), contextlib.redirect_stderr(printed):
            status = run(args)
        if status != 0:
            raise RuntimeError(f"jointplay {' '.join(args)} failed:\n{printed.getvalue()}")
        summary: dict[str, Any] = json.loads((out / "summary.json").read_text(encoding="utf-8"))
        return summary


class Runs:
    """The simulations the tables share, each run once."""

    def __init__(self) -> None:
        self._done: dict[tuple[str, ...], dict[str, Any]] = {}

    def __call__(self, *options: str) -> dict[str, Any]:
        if options not in self._done:
            self._done[options] = simulate(*options)
        return self._done[options]

    def film(self, clearance_um: float, film: str) -> dict[str, Any]:
        return self("--clearance", f"{clearance_um:g} um", "--film-model", film)

    def dry(self) -> dict[str, Any]:
        return self("--lubrication", "dry", "--revolutions", str(DRY_REVOLUTIONS),
                    "--ensemble", str(DRY_RUNS))  # fmt: skip


def _peaks(summary: dict[str, Any], digits: int = 2) -> str:
    return " / ".join(f"{summary['peaks'][f'F_{j}']['value']:.{digits}f}" for j in JOINTS)


def _nominal(summary: dict[str, Any], digits: int = 2) -> str:
    return " / ".join(f"{summary['nominal_peaks'][f'F_{j}']:.{digits}f}" for j in JOINTS)


def _h_min(summary: dict[str, Any]) -> str:
    """c − max|e| of each joint over the analysed revolutions, µm (negative: the pin sinks
    into its wall by that much)."""
    deepest = summary["cycles"]["deepest_penetration_m"]
    return " / ".join(f"{-deepest[j] * 1e6:.2f}" for j in JOINTS)


def _table(header: Sequence[str], align: Sequence[str], rows: Sequence[Sequence[str]]) -> str:
    lines = ["| " + " | ".join(header) + " |", "| " + " | ".join(align) + " |"]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return "\n".join(lines)


def reynolds_films(runs: Runs) -> str:
    """The three films at three clearances: peaks, h_min, steps."""
    rows = []
    for clearance in FILM_CLEARANCES:
        for film, label in FILMS:
            s = runs.film(clearance, film)
            rows.append([f"{clearance:g} µm", label, _peaks(s), _h_min(s),
                         f"{s['solver']['steps']:,}".replace(",", " ")])  # fmt: skip
    return _table(
        ["clearance", "film", "F_O2 / F_A / F_B / F_O4 peaks (N)",
         "h_min = c − max\\|e\\| (µm; negative: in the wall)", "steps"],
        ["---:", "---", "---", "---", "---:"],
        rows,
    )  # fmt: skip


def mixed_lubrication(runs: Runs) -> str:
    """The π-film at three clearances: peaks against the ideal joints', h_min, regimes."""
    rows = []
    for clearance in FILM_CLEARANCES:
        s = runs.film(clearance, "short-bearing-pi")
        increase = " / ".join(f"{s['increase_percent'][f'F_{j}']:+.2f}" for j in JOINTS)
        regimes = s["film_regimes"]
        full = " / ".join(f"{100 * regimes[j]['full_film']:.0f}" for j in JOINTS)
        rows.append([f"{clearance:g} µm", _peaks(s), f"{increase} %", _h_min(s), full])
    ideal = _nominal(runs.film(FILM_CLEARANCES[0], "short-bearing-pi"))
    return _table(
        ["clearance", "F_O2 / F_A / F_B / F_O4 peaks (N)",
         f"against the ideal joints' {ideal} N", "h_min over the analysed revolution (µm)",
         "full film (% of the analysed revolution)"],
        ["---:", "---", "---", "---", "---"],
        rows,
    )  # fmt: skip


def default_gives(runs: Runs) -> str:
    """The default against the ideal joints, the linear damper and the conventional set."""
    default = runs.film(21.0, "short-bearing-pi")
    linear = runs.film(21.0, "linear")
    conventional = runs("--clearance", "21 um", "--method", "ifm-conventional")
    columns = (default, linear, conventional)

    def omega(s: dict[str, Any]) -> str:
        return f"{s['peaks']['omega3']['value']:.3f} rad/s"

    def deepest(s: dict[str, Any]) -> str:
        pen = s["cycles"]["deepest_penetration_m"]
        return " / ".join(f"{pen[j] * 1e6:.2f}" for j in JOINTS) + " µm"

    def regime(s: dict[str, Any]) -> str:
        regimes = s.get("film_regimes") or {}
        if all(regimes.get(j) is None for j in JOINTS):
            return "dry"
        shares = (f"{100 * regimes[j]['full_film']:.0f}" for j in JOINTS)
        return "full film " + " / ".join(shares) + " %"

    return _table(
        ["peak", "ideal joints (`kinematics`)", "physical default (π-film, σ = 1.12 µm)",
         "`--film-model linear` (the default before issue 39)", "`--method ifm-conventional`"],
        ["---", "---", "---", "---", "---"],
        [
            ["F_O2 / F_A / F_B / F_O4", f"{_nominal(default)} N",
             *(f"{_peaks(s)} N" for s in columns)],
            ["\\|ω3\\|", f"{default['nominal_peaks']['omega3']:.3f} rad/s",
             *(omega(s) for s in columns)],
            ["deepest \\|e\\| − c, O2 / A / B / O4 (analysed revolution; negative: the pin "
             "floats)", "—", *(deepest(s) for s in columns)],
            ["full film (share of the analysed revolution, O2 / A / B / O4)", "—",
             *(regime(s) for s in columns)],
            ["steps (settle 2 + 1 revolution)", "—",
             *(f"{s['solver']['steps']:,}".replace(",", " ") for s in columns)],
        ],
    )  # fmt: skip


def dry_statistics(runs: Runs) -> str:
    """Dry joints: the per-revolution peaks over an ensemble of runs from start angles
    0.01° apart (``--ensemble``): the mean with its 95 % interval, and the 95th percentile."""
    stats = runs.dry()["ensemble"]["statistics"]
    rows = []
    for name, label, unit, digits in [*((f"F_{j}", f"F_{j}", "N", 1) for j in JOINTS),
                                      ("omega3", "\\|ω3\\|", "rad/s", 3)]:  # fmt: skip
        q = stats[name]
        mean, p95 = q["mean"], q["percentile_95"]
        rows.append([f"{label} ({unit})",
                     f"{mean['value']:.{digits}f} [{mean['low']:.{digits}f}, "
                     f"{mean['high']:.{digits}f}]",
                     _interval(p95, digits)])  # fmt: skip
    return _table(
        [f"`--lubrication dry`, {DRY_RUNS} runs × {DRY_REVOLUTIONS} settled revolutions",
         "mean of the revolutions' peaks [95 %]", "95th percentile [95 %; — unbounded]"],
        ["---", "---:", "---:"],
        rows,
    )  # fmt: skip


def _interval(estimate: dict[str, Any], digits: int) -> str:
    """``value [low, high]``, an unbounded end as —."""
    ends = [f"{estimate[end]:.{digits}f}" if estimate[end] is not None else "—"
            for end in ("low", "high")]  # fmt: skip
    return f"{estimate['value']:.{digits}f} [{ends[0]}, {ends[1]}]"


def film_damping(runs: Runs) -> str:
    """F_O2's settled peak under the linear damper of a fixed c_e, by clearance."""
    rows = []
    for damping in DAMPINGS:
        cells = []
        for clearance in DAMPER_CLEARANCES:
            s = runs("--clearance", f"{clearance:g} um", "--film-damping", f"{damping} N*s/m")
            cells.append(f"{s['peaks']['F_O2']['value']:.2f} N")
        rows.append([damping, *cells])
    ideal = runs("--clearance", "21 um", "--film-damping", "1e5 N*s/m")["nominal_peaks"]["F_O2"]
    rows.append(["ideal joints", *([f"{ideal:.2f} N"] * len(DAMPER_CLEARANCES))])
    return _table(
        ["c_e (N·s/m)", *(f"F_O2 peak at {c:g} µm" for c in DAMPER_CLEARANCES)],
        ["---:", *(["---:"] * len(DAMPER_CLEARANCES))],
        rows,
    )


def _e(value: float) -> str:
    """``value`` as the page writes it: ``2.05e11``."""
    mantissa, exponent = f"{value:.2e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def liu_stiffness(runs: Runs) -> str:
    """Liu's law fitted as the default contact fits it, against Hertz's, by clearance."""
    from jointplay.contact.stiffness import HertzStiffness
    from jointplay.dynamics.setup import ContactModel
    from jointplay.io.config import load_preset

    mechanism = load_preset("paper-fourbar")
    rows = []
    for clearance in (2.5e-6, 6.5e-6, 11.75e-6, 21e-6):
        joint = ContactModel().joints(mechanism, ["A"], clearance=clearance)[0]
        k, n = joint.law.penalty, joint.law.exponent
        geometry = joint.stiffness_from
        hertz = HertzStiffness(
            bearing_radius=joint.journal_radius + clearance, pin_radius=joint.journal_radius,
            length=geometry.length, bearing_youngs_modulus=geometry.bearing_youngs_modulus,
            bearing_poisson_ratio=geometry.bearing_poisson_ratio,
            pin_youngs_modulus=geometry.pin_youngs_modulus,
            pin_poisson_ratio=geometry.pin_poisson_ratio,
        ).stiffness  # fmt: skip
        rows.append([f"{clearance * 1e6:g} µm", _e(k), f"{n:.3f}", f"{k * 1e-6**n:.0f} N",
                     _e(hertz), f"{hertz * 1e-6**1.5:.0f} N"])  # fmt: skip
    return _table(
        ["radial clearance ΔR", "k (N/m^n)", "n", "F at δ = 1 µm", "Hertz K (N/m^1.5)",
         "Hertz F at 1 µm"],
        ["---", "---", "---", "---", "---", "---"],
        rows,
    )  # fmt: skip


#: The tables, by marker name: what computes each, and whether it is a chaotic statistic.
TABLES: dict[str, tuple[Callable[[Runs], str], bool]] = {
    "liu-stiffness": (liu_stiffness, False),
    "film-damping": (film_damping, False),
    "reynolds-films": (reynolds_films, False),
    "mixed-lubrication": (mixed_lubrication, False),
    "default-gives": (default_gives, False),
    "dry-statistics": (dry_statistics, True),
}

_NUMBER = re.compile(r"[-+−]?\d[\d ]*(?:\.\d+)?(?:e[-+]?\d+)?")


def _block(text: str, name: str) -> re.Match[str]:
    pattern = re.compile(
        rf"(<!-- contact-tables: {re.escape(name)} -->\n)(.*?)(\n<!-- /contact-tables: "
        rf"{re.escape(name)} -->)",
        re.S,
    )
    found = pattern.search(text)
    if found is None:
        raise SystemExit(f"{DOC}: no markers for the table {name!r}")
    return found


def _numbers(text: str) -> tuple[list[float], list[float], str]:
    """The numbers of ``text``, one unit of each one's last printed digit (``1.48e11``:
    1e9), and the text without them."""
    values, units = [], []
    for match in _NUMBER.finditer(text):
        token = match.group().replace(" ", "").replace("−", "-")
        values.append(float(token))
        mantissa, _, exponent = token.partition("e")
        decimals = len(mantissa.split(".")[1]) if "." in mantissa else 0
        units.append(10.0 ** (int(exponent or 0) - decimals))
    return values, units, _NUMBER.sub("#", text)


#: An interval's unbounded end in a table (``_interval``).
_UNBOUNDED = re.compile(r"(?<=[\[ ])—(?=[\],])")


def drifted(written: str, computed: str, statistic: bool) -> list[str]:
    """How ``written`` (the page's table) differs from ``computed``: its words, or a number
    beyond one unit of its last digit (a statistic: beyond :data:`DRY_TOLERANCE`; an
    interval's end unbounded on one side and bounded on the other is no drift there: whether
    the ensemble's order statistics reach a quantile's upper bound changes from one machine's
    round-off to another's, as every chaotic run does)."""
    if statistic:
        written, computed = _bounded_alike(written, computed)
    old, old_units, old_words = _numbers(written)
    new, _, new_words = _numbers(computed)
    if old_words != new_words or len(old) != len(new):
        return ["the table's layout or words differ"]
    out = []
    for a, b, unit, count in zip(old, new, old_units, _counts(written), strict=True):
        if statistic:
            allowed = DRY_TOLERANCE * max(abs(a), abs(b))
        elif count:
            allowed = STEP_TOLERANCE * max(abs(a), abs(b))
        else:
            allowed = unit * 1.001
        if abs(a - b) > allowed:
            out.append(f"{a:g} in the page, {b:g} computed")
    return out


#: A table's cell separator (not an escaped ``\\|``).
_CELL = re.compile(r"(?<!\\)\|")


def _counts(table: str) -> list[bool]:
    """For each number of ``table`` (in :func:`_numbers`' order), whether it is a step count:
    in the column headed "steps" or the row whose first cell starts with "steps"."""
    lines = table.splitlines()
    header = [cell.strip() for cell in _CELL.split(lines[0])] if lines else []
    flags = []
    for number, line in enumerate(lines):
        cells = _CELL.split(line)
        row = len(cells) > 1 and cells[1].strip().startswith("steps")
        for k, cell in enumerate(cells):
            count = number > 0 and k >= 2 and (row or (k < len(header) and header[k] == "steps"))
            flags += [count] * len(_NUMBER.findall(cell))
    return flags


def _bounded_alike(written: str, computed: str) -> tuple[str, str]:
    """``written`` and ``computed`` with each interval end that is unbounded (—) in one of
    them unbounded in both (their cells matched in order, line by line)."""
    lines = []
    for a, b in zip(written.splitlines(), computed.splitlines(), strict=False):
        ends_a = [m.start() for m in _UNBOUNDED.finditer(a)]
        ends_b = [m.start() for m in _UNBOUNDED.finditer(b)]
        if ends_a == ends_b:
            lines.append((a, b))
            continue
        cells_a, cells_b = a.split("|"), b.split("|")
        if len(cells_a) != len(cells_b):
            lines.append((a, b))
            continue
        for k, (x, y) in enumerate(zip(cells_a, cells_b, strict=True)):
            xs, ys = _interval_ends(x), _interval_ends(y)
            if xs is None or ys is None:
                continue
            ends = ["—" if "—" in (u, v) else None for u, v in zip(xs, ys, strict=True)]
            cells_a[k] = _with_ends(x, xs, ends)
            cells_b[k] = _with_ends(y, ys, ends)
        lines.append(("|".join(cells_a), "|".join(cells_b)))
    return "\n".join(a for a, _ in lines), "\n".join(b for _, b in lines)


_ENDS = re.compile(r"\[([^,\]]+), ([^\]]+)\]")


def _interval_ends(cell: str) -> list[str] | None:
    found = _ENDS.search(cell)
    return [found.group(1), found.group(2)] if found else None


def _with_ends(cell: str, ends: list[str], unbounded: list[str | None]) -> str:
    low, high = (u or e for u, e in zip(unbounded, ends, strict=True))
    return _ENDS.sub(f"[{low}, {high}]", cell, count=1)


#: The simulations of this process, shared by every call (the test checks the page and a
#: tampered copy of it with one set of runs).
RUNS = Runs()


def check(text: str, names: Sequence[str] | None = None) -> list[str]:
    """Where the tables ``names`` (default: all) of the page ``text`` drifted from the
    computed ones, one line each (empty: none)."""
    failures = []
    for name in names or TABLES:
        compute, statistic = TABLES[name]
        failures += [
            f"{name}: {line}"
            for line in drifted(_block(text, name).group(2), compute(RUNS), statistic)
        ]
    return failures


def regenerate(text: str, names: Sequence[str] | None = None) -> str:
    """The page ``text`` with the tables ``names`` (default: all) computed afresh."""
    for name in names or TABLES:
        found = _block(text, name)
        text = text[: found.start(2)] + TABLES[name][0](RUNS) + text[found.end(2) :]
    return text


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare, do not write")
    parser.add_argument("--only", nargs="*", choices=sorted(TABLES), help="these tables only")
    args = parser.parse_args(argv)
    text = DOC.read_text(encoding="utf-8")
    if not args.check:
        DOC.write_text(regenerate(text, args.only), encoding="utf-8")
        return 0
    failures = check(text, args.only)
    for line in failures:
        print(f"docs/contact.md drifted: {line}", file=sys.stderr)
    if failures:
        print("regenerate: PYTHONPATH=src python docs/contact_tables.py", file=sys.stderr)
    return 1 if failures else 0


if __name__ == "__main__":
    raise SystemExit(main())
