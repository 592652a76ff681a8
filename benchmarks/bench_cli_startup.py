"""Start-up cost of the command line (issue: architecture, "fast edges").

Target: ``jointplay --help`` and ``jointplay fit "H8/g7" --size 10mm`` answer in <= 0.5 s,
which needs every command module to import only what describing its options takes (Typer,
Rich, the standard library) and the commands to import NumPy's, SciPy's, Numba's, pandas',
Dask's and pint's stacks only when they run.

Run ``python benchmarks/bench_cli_startup.py``: each command is run in a fresh interpreter
(``python -m jointplay``, as the console script does) ``--repeat`` times after one warm-up
run that fills the operating system's file cache; the best and the median are reported. The
ratios' runs use cached bytecode, as an installed program does (``PYTHONPYCACHEPREFIX`` in
the scratch folder, ``PYTHONDONTWRITEBYTECODE`` unset).

Issue 41 ("a fast command line") adds three ratios to ``jointplay --version`` (the cost of
starting Python, Typer and Rich), each measured in wall time and in CPU time (user + system
of the child, from ``os.wait4``; on a machine shared with other work the CPU ratio is the
fairer one):

==============================================  ======
``jointplay simulate --no-plots --out DIR``      <= 3x
``jointplay simulate --rpm "200 rmp" --out DIR``  <= 1.5x (the error line)
``jointplay simulate --out DIR`` (with plots)    <= 5x
==============================================  ======

``--compare-with SRC`` runs every command also with ``PYTHONPATH=SRC`` (another checkout's
``src``, its Numba caches warm) and prints both side by side; ``--ratios-only`` skips the
table of the light commands.
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

TARGET_S = 0.5

COMMANDS = {
    "jointplay --help": ["--help"],
    "jointplay --version": ["--version"],
    'jointplay fit "H8/g7" --size 10mm': ["fit", "H8/g7", "--size", "10mm"],
    "jointplay general-tolerance c --size 270.5mm": [
        "general-tolerance",
        "c",
        "--size",
        "270.5mm",
    ],
    "jointplay presets": ["presets"],
    "jointplay show paper-fourbar": ["show", "paper-fourbar"],
}

HEAVY = ("numba", "scipy", "pandas", "dask", "matplotlib", "pint")


def _run(arguments: list[str]) -> float:
    start = time.perf_counter()
    subprocess.run(
        [sys.executable, "-m", "jointplay", *arguments],
        check=True,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    return time.perf_counter() - start


def heavy_modules_loaded(arguments: list[str]) -> list[str]:
    """The heavy libraries that running ``jointplay ARGUMENTS`` imports."""
    code = (
        "import sys\n"
        "from jointplay.cli import run\n"
        f"run({arguments!r})\n"
        f"print('HEAVY:' + ','.join(m for m in {HEAVY!r} if m in sys.modules))\n"
    )
    output = subprocess.run(
        [sys.executable, "-c", code], check=True, capture_output=True, text=True
    ).stdout
    line = output.strip().splitlines()[-1].removeprefix("HEAVY:")
    return [name for name in line.split(",") if name]


#: label -> (arguments, ``OUT`` replaced by a fresh folder; the most times ``--version``).
RATIOS = {
    "simulate --no-plots": (["simulate", "--no-plots", "--no-progress", "--out", "OUT"], 3.0),
    'simulate --rpm "200 rmp" (error)': (
        ["simulate", "--rpm", "200 rmp", "--no-progress", "--out", "OUT"],
        1.5,
    ),
    "simulate (with plots)": (["simulate", "--no-progress", "--out", "OUT"], 5.0),
}
REFERENCE = ["--version"]


def _timed(arguments: list[str], source: str | None, scratch: Path) -> tuple[float, float]:
    """(wall s, CPU s: user + system) of ``python -m jointplay ARGUMENTS`` in a fresh
    interpreter, with ``PYTHONPATH=source`` when given; ``OUT`` is a fresh folder."""
    out = scratch / "out"
    shutil.rmtree(out, ignore_errors=True)
    environment = dict(os.environ)
    # As an installed program runs: pip compiles the bytecode when it installs; here the
    # warm-up run writes it, under the scratch folder (nothing is written beside the sources
    # compared). With PYTHONDONTWRITEBYTECODE set, as some environments do, every run
    # compiled the ~100 modules of jointplay it imports from source: ~0.15 s of CPU each.
    environment.pop("PYTHONDONTWRITEBYTECODE", None)
    environment["PYTHONPYCACHEPREFIX"] = str(scratch / "bytecode")
    if source is not None:
        environment["PYTHONPATH"] = source
    command = [sys.executable, "-m", "jointplay", *(a.replace("OUT", str(out)) for a in arguments)]
    start = time.perf_counter()
    child = subprocess.Popen(
        command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=environment
    )
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    child.returncode = os.waitstatus_to_exitcode(status)
    return wall, usage.ru_utime + usage.ru_stime


def _series(
    arguments: list[str], source: str | None, repeat: int, scratch: Path
) -> dict[str, float]:
    _timed(arguments, source, scratch)  # warm the file cache
    runs = [_timed(arguments, source, scratch) for _ in range(repeat)]
    walls, cpus = [w for w, _ in runs], [c for _, c in runs]
    return {
        "wall_best": min(walls),
        "wall_median": statistics.median(walls),
        "cpu_best": min(cpus),
        "cpu_median": statistics.median(cpus),
    }


def ratios(repeat: int, sources: dict[str, str | None]) -> None:
    """The three ratios of issue 41 for each code in ``sources`` (name -> PYTHONPATH)."""
    with tempfile.TemporaryDirectory(prefix="jointplay-bench-") as folder:
        scratch = Path(folder)
        for name, source in sources.items():
            reference = _series(REFERENCE, source, repeat, scratch)
            print(
                f"[{name}] jointplay --version: wall best {reference['wall_best']:.2f} s, "
                f"median {reference['wall_median']:.2f} s; CPU best "
                f"{reference['cpu_best']:.2f} s, median {reference['cpu_median']:.2f} s"
            )
            for label, (arguments, target) in RATIOS.items():
                times = _series(arguments, source, repeat, scratch)
                shown = []
                for kind in ("wall", "cpu"):
                    best = times[f"{kind}_best"] / reference[f"{kind}_best"]
                    median = times[f"{kind}_median"] / reference[f"{kind}_median"]
                    verdict = "meets" if median <= target else "MISSES"
                    shown.append(
                        f"{kind} {times[f'{kind}_best']:.2f}/{times[f'{kind}_median']:.2f} s "
                        f"= {best:.1f}x/{median:.1f}x ({verdict})"
                    )
                print(f"[{name}] {label:<34} (<= {target:g}x; best/median): " + "; ".join(shown))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    parser.add_argument(
        "--compare-with",
        metavar="SRC",
        help="also run every command with PYTHONPATH=SRC (e.g. a checkout of the code before)",
    )
    parser.add_argument(
        "--ratios-only", action="store_true", help="only the three ratios of issue 41"
    )
    args = parser.parse_args()
    print(
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
        f"Python {platform.python_version()}, load {os.getloadavg()[0]:.1f}"
    )
    sources: dict[str, str | None] = {"this": os.environ.get("PYTHONPATH")}
    if args.compare_with:
        sources = {"before": args.compare_with, **sources}
    ratios(args.repeat, sources)
    if args.ratios_only:
        return
    python_only = min(_time_python_start() for _ in range(args.repeat))
    print(f"python -c pass: {python_only * 1e3:.0f} ms (interpreter start-up alone)")
    for label, arguments in COMMANDS.items():
        _run(arguments)  # warm the file cache
        times = [_run(arguments) for _ in range(args.repeat)]
        best, median = min(times), statistics.median(times)
        verdict = "meets" if median <= TARGET_S else "MISSES"
        heavy = heavy_modules_loaded(arguments)
        print(
            f"{label:<48} best {best * 1e3:5.0f} ms, median {median * 1e3:5.0f} ms "
            f"({verdict} {TARGET_S:.1f} s); heavy imports: {', '.join(heavy) or 'none'}"
        )


def _time_python_start() -> float:
    start = time.perf_counter()
    subprocess.run([sys.executable, "-c", "pass"], check=True)
    return time.perf_counter() - start


if __name__ == "__main__":
    main()
