"""Update time of ``jointplay explore`` (issue 27): the clearance of joint A moved between 5 and
50 µm, the page in headless Chromium.

Targets on a 2-core machine: each update <= 0.3 s with the paper's conventional set
(``ifm-conventional``) and <= 1 s with the physical default contact.

Run ``python benchmarks/bench_explore.py`` (needs ``pip install '.[test]'`` and Debian's
``chromium``). It starts ``jointplay explore --no-browser --port 0``, loads the page with
``?contact=<set>&c.A=5`` and moves joint A's clearance slider to 50, 5, 50, ... µm
``--updates`` times per set, waiting for each view. The page measures each update itself:
from the change to the drawn view (``total``), the part spent on the server (``server``:
reading the settings, the simulation, the view's numbers) and the drawing (``draw``); the
rest is the request and the JSON. The median and the largest are printed.
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import signal
import statistics
import subprocess
import sys

TARGETS_S = {"ifm-conventional": 0.3, "physical": 1.0}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--updates", type=int, default=10, help="updates per contact set")
    parser.add_argument("--chromium", default=shutil.which("chromium") or "chromium")
    args = parser.parse_args()
    from playwright.sync_api import sync_playwright

    server = subprocess.Popen(
        [sys.executable, "-m", "jointplay", "explore", "--no-browser", "--port", "0"],
        stdout=subprocess.PIPE,
        text=True,
        env={**os.environ, "MPLBACKEND": "Agg"},
    )
    assert server.stdout is not None
    line = server.stdout.readline()
    url = line[line.index("http://") :].split()[0]
    print(f"{platform.python_version()} on {os.cpu_count()} CPUs, load {os.getloadavg()[0]:.1f}")
    try:
        with sync_playwright() as driver:
            browser = driver.chromium.launch(executable_path=args.chromium, args=["--no-sandbox"])
            page = browser.new_context(
                viewport={"width": 1400, "height": 1000}, bypass_csp=True
            ).new_page()
            for contact, target in TARGETS_S.items():
                page.goto(f"{url}?contact={contact}&c.A=5")
                views = 1
                wait = "document.body.dataset.views === '{}' && document.body.dataset.state === 'ready'"
                page.wait_for_function(wait.format(views), timeout=120_000)
                rows = []
                for k in range(args.updates):
                    page.fill("#clr-A-range", "50" if k % 2 == 0 else "5")
                    views += 1
                    page.wait_for_function(wait.format(views), timeout=120_000)
                    data = page.evaluate("({...document.body.dataset})")
                    rows.append(
                        [float(data[key]) for key in ("lastUpdateS", "lastServerS", "lastDrawS")]
                    )
                columns = list(zip(*rows, strict=True))
                print(
                    f"{contact:17s} target <= {target:.1f} s  "
                    + "  ".join(
                        f"{name} median {statistics.median(c):.3f} max {max(c):.3f} s"
                        for name, c in zip(("total", "server", "draw"), columns, strict=True)
                    )
                )
            browser.close()
    finally:
        server.send_signal(signal.SIGINT)
        server.wait(30)


if __name__ == "__main__":
    main()
