"""Issue 22's figures for the default contact of the checkout it runs against, so that two
checkouts (the code before a change and after it) can be measured side by side.

Run it with each checkout's sources first on the path, interleaved, e.g.::

    PYTHONPATH=/path/to/old/src python benchmarks/bench_default_contact.py --json old.json
    PYTHONPATH=src python benchmarks/bench_default_contact.py --json new.json

It uses only APIs that both the dry default (before issue 22's lubricated default) and the
lubricated one have: ``ContactModel()`` is whatever default the checkout has. ``--dry`` runs
``steady`` and ``batch`` with ``ContactModel(lubrication="dry")`` instead (issue 40, item 4:
targets ≤ 30 ms per revolution and ≥ 15 samples/s on 2 cores).

- ``steady``: one steady revolution of the paper four-bar at its fits' 21 µm, settle 2 + 1,
  default tolerances; ms per revolution (the integration's wall time over 3), best of 3;
  steps; the settled F_O2 peak. Target: ≤ 15 ms.
- ``batch``: ``simulate_batch`` over 16 samples of all four clearances in 6–21 µm
  (``np.linspace``), settle 2 + 1, the local backend on every core, ``auto`` method; samples
  per second, best of 2 after a warm-up run. Target: ≥ 40 on 2 cores.
- ``study``: ``tolerance_study`` of the paper four-bar, dynamic responses, 200 samples, seed 1,
  with the default contact and with the conventional set (``ifm-conventional``), the
  default first; wall time of each call, their ratio (target ≤ 2), and whether the study's
  own convergence check passes. Each contact first runs a study of a few samples, and the
  convergence check's SciPy import is made before either is timed: the one-time costs
  (loading each contact's compiled kernels; ``scipy.stats``, 2.8 s on the loaded 2-core
  machine) fell on whichever contact ran first (docs/performance.md, issue 39's section).
"""

from __future__ import annotations

import argparse
import json
import os
import time
from typing import Any

import numpy as np

from jointplay.dynamics.batch import BatchSamples, simulate_batch
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import Start, simulate
from jointplay.io.config import load_preset

JOINTS = ("O2", "A", "B", "O4")


def load() -> str:
    return "/".join(f"{x:.2f}" for x in os.getloadavg())


#: The samples of each contact's warm-up study (fewer than the convergence check needs).
WARM_UP = 8

#: The contact measured: ``ContactModel()`` (the checkout's default) unless ``--dry``.
CONTACT: dict[str, Any] = {}


def steady() -> dict[str, Any]:
    mechanism = load_preset("paper-fourbar")
    joints = ContactModel(**CONTACT).joints(mechanism, JOINTS)
    runs = [
        simulate(mechanism, joints, revolutions=1, settle=2, start=Start("steady"))
        for _ in range(4)  # the first loads the compiled kernels
    ]
    best = min(runs[1:], key=lambda r: r.solver_stats["wall_s"])
    return {
        "ms_per_revolution": best.solver_stats["wall_s"] / 3 * 1e3,
        "steps": best.solver_stats["steps"],
        "F_O2_peak": best.peaks["F_O2"]["value"],
    }


def batch() -> dict[str, Any]:
    mechanism = load_preset("paper-fourbar")
    joints = ContactModel(**CONTACT).joints(mechanism, JOINTS)
    samples = BatchSamples(clearances=dict.fromkeys(JOINTS, np.linspace(6e-6, 21e-6, 16)))
    rates, method = [], ""
    for _ in range(3):  # the first loads the compiled kernels
        start = time.perf_counter()
        result = simulate_batch(
            mechanism, joints, samples, revolutions=1, settle=2, start=Start("steady"),
            backend="local",
        )  # fmt: skip
        rates.append(len(samples) / (time.perf_counter() - start))
        method = result.method
    return {"samples_per_s": max(rates[1:]), "method": method}


def study(samples: int) -> dict[str, Any]:
    from jointplay.tolerance.analysis import tolerance_study

    mechanism = load_preset("paper-fourbar")
    out: dict[str, Any] = {}
    contacts = (("default", None), ("conventional", "ifm-conventional"))
    import scipy.stats  # noqa: F401 (the convergence check's, once: see the docstring)

    for _, contact in contacts:  # each contact's compiled kernels loaded before timing
        options = {} if contact is None else {"contact": contact}
        tolerance_study(mechanism, responses="dynamic", samples=WARM_UP, seed=1, **options)
    for name, contact in contacts:
        options = {} if contact is None else {"contact": contact}
        start = time.perf_counter()
        result = tolerance_study(mechanism, responses="dynamic", samples=samples, seed=1, **options)
        check = result.convergence
        out[name] = {
            "wall_s": time.perf_counter() - start,
            "converged": None if check is None else check.finding is None,
            "largest_change_over_spread": None if check is None else check.share,
            "response": None if check is None else check.response,
            "failed": len(result.result.failures),
        }
    out["ratio"] = out["default"]["wall_s"] / out["conventional"]["wall_s"]
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=("steady", "batch", "study"), nargs="*")
    parser.add_argument("--samples", type=int, default=200, help="the study's samples")
    parser.add_argument("--json", help="write the figures here")
    parser.add_argument(
        "--dry", action="store_true", help="steady and batch with dry joints (issue 40, item 4)"
    )
    args = parser.parse_args()
    if args.dry:
        CONTACT["lubrication"] = "dry"
    contact = ContactModel(**CONTACT).describe()["text"]
    figures: dict[str, Any] = {"contact": contact, "load": [load()]}
    for part in args.part or ["steady", "batch", "study"]:
        figures[part] = study(args.samples) if part == "study" else globals()[part]()
        figures["load"].append(load())
        print(part, json.dumps(figures[part]), flush=True)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as file:
            json.dump(figures, file, indent=1)


if __name__ == "__main__":
    main()
