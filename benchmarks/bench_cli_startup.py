"""Start-up cost of the command line (issue: architecture, "fast edges").

Target: ``jointplay --help`` and ``jointplay fit "H8/g7" --size 10mm`` answer in <= 0.5 s,
which needs every command module to import only what describing its options takes (Typer,
Rich, the standard library) and the commands to import NumPy's, SciPy's, Numba's, pandas',
Dask's and pint's stacks only when they run.

Run ``python benchmarks/bench_cli_startup.py``: each command is run in a fresh interpreter
(``python -m jointplay``, as the console script does) ``--repeat`` times after one warm-up
run that fills the operating system's file cache; the best and the median are reported.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import subprocess
import sys
import time

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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7)
    args = parser.parse_args()
    print(
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
        f"Python {platform.python_version()}"
    )
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
