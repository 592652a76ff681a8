"""Fingerprints of the benchmarks' cases, to show that a refactoring of the kernels leaves
their results bit-identical (issue 38: "results bit-identical on the benchmarks' cases").

Run it against two checkouts and compare the lines (``diff``)::

    PYTHONPATH=/path/to/old/src python benchmarks/bit_fingerprint.py > old.txt
    PYTHONPATH=src python benchmarks/bit_fingerprint.py > new.txt
    diff old.txt new.txt

Each line is a case, the SHA-256 (first 16 hex digits) of its raw results — the single
engine's every accepted step ``(t, y)``, the batch engine's peaks, statistics and counters —
and a few readable figures (steps, a peak), so a difference can be told apart from noise
at a glance. The cases are those of ``bench_clearance.py`` (the paper's three IFM sets from
rest, with the paper methods' integrators and with Radau), ``bench_default_contact.py`` (the
lubricated default from the steady start, and the same dry), ``bench_sustained_contact.py``
(the sustained-contact mode), one joint clear beside ideal joints (the constrained
equations), and ``bench_batch.py``'s small batches on both lane methods (and the implicit
one in the sustained-contact mode). ``--quick`` keeps the cases that take under a second
each warm.
"""

from __future__ import annotations

import argparse
import hashlib
from collections.abc import Callable
from typing import Any

import numpy as np
from bench_clearance import PARAMETER_SETS as IFM_SETS  # the same three IFM sets

from jointplay.contact.laws import get_law
from jointplay.dynamics.batch import BatchSamples, simulate_batch
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SolverOptions, Start, simulate
from jointplay.io.config import load_preset

JOINTS = ("O2", "A", "B", "O4")


def digest(*arrays: Any) -> str:
    h = hashlib.sha256()
    for array in arrays:
        h.update(np.ascontiguousarray(np.asarray(array, dtype=np.float64)).tobytes())
    return h.hexdigest()[:16]


def single(name: str, joints: list[ClearanceJoint], **options: Any) -> str:
    mechanism = options.pop("mechanism", None) or load_preset("paper-fourbar")
    result = simulate(mechanism, joints, **options)
    peak = result.peaks.get("F_A", result.peaks.get("omega4", {})).get("value", float("nan"))
    return (
        f"{name:<34} {digest(result.t, result.y)}  steps {result.solver_stats['steps']:>6}"
        f"  F_A/ω4 peak {peak:.12g}"
    )


def batch(name: str, joints: list[ClearanceJoint], n: int, **options: Any) -> str:
    mechanism = load_preset("paper-fourbar")
    rng = np.random.default_rng(99)
    nominal = {"crank": 0.108, "coupler": 0.2705, "rocker": 0.2705, "ground": 0.2794}
    samples = BatchSamples(
        lengths={k: v + rng.uniform(-2e-4, 2e-4, n) for k, v in nominal.items()},
        clearances={j: rng.uniform(6e-6, 21e-6, n) for j in JOINTS},
    )
    result = simulate_batch(mechanism, joints, samples, backend="local", **options)
    counts = result.counters.to_numpy(dtype=float)
    return (
        f"{name:<34} {digest(result.peaks.to_numpy(), result.statistics.to_numpy(), counts)}"
        f"  method {result.method}  steps {int(counts[:, 0].sum()):>7}"
    )


def cases(quick: bool) -> list[Callable[[], str]]:
    mechanism = load_preset("paper-fourbar")
    ifm = {k: [ClearanceJoint(j, 21e-6, 5e-3, get_law("impact", **v)) for j in JOINTS]
           for k, v in IFM_SETS.items()}  # fmt: skip
    rest = {"revolutions": 1, "start": Start("rest")}
    steady = {"revolutions": 1, "settle": 2, "start": Start("steady")}
    default = ContactModel().joints(mechanism, JOINTS)
    dry = ContactModel(film_damping=0).joints(mechanism, JOINTS)
    out: list[Callable[[], str]] = []
    for key, integrator in (("conventional", "dopri5"), ("conventional", "radau"),
                            ("spherical", "rodas4"), ("cylindrical", "rodas4")):  # fmt: skip
        if quick and key == "cylindrical":
            continue
        out.append(lambda k=key, i=integrator: single(
            f"ifm-{k} rest {i}", ifm[k], solver=SolverOptions(integrator=i), **rest
        ))  # fmt: skip
    out += [
        lambda: single("default steady (lubricated)", default, **steady),
        lambda: single("default steady dry", dry, **steady),
        lambda: single(
            "default steady sustained contact",
            ContactModel(sustained_contact=True).joints(mechanism, JOINTS),
            **steady,
        ),
        lambda: single("A clear beside ideal joints", default[1:2], **steady),
        lambda: single("A clear beside ideal dry", dry[1:2], **steady),
        lambda: batch(
            "batch conventional explicit",
            ifm["conventional"],
            8,
            solver=SolverOptions(),
            method="explicit",
        ),
        lambda: batch("batch default implicit", default, 8, settle=1, method="implicit"),
        lambda: batch(
            "batch sustained contact implicit",
            ContactModel(sustained_contact=True).joints(mechanism, JOINTS),
            4,
            settle=1,
            method="implicit",
        ),
    ]
    if not quick:
        out.append(lambda: batch("batch spherical implicit", ifm["spherical"], 8,
                                 method="implicit"))  # fmt: skip
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the cases under ~1 s each")
    args = parser.parse_args()
    for case in cases(args.quick):
        print(case(), flush=True)


if __name__ == "__main__":
    main()
