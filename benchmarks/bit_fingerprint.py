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
equations), ``bench_batch.py``'s small batches on both lane methods (and the implicit
one in the sustained-contact mode), and the generic :func:`jointplay.integrate` with each of
its methods on a few small ODEs (its every accepted step and counter: backwards, a user
Jacobian, onset retries and an ``after_step`` that changes the state, a failure).
``--quick`` keeps the cases that take under a second each warm.
"""

from __future__ import annotations

import argparse
import hashlib
from collections.abc import Callable
from typing import Any

import numba
import numpy as np
from bench_clearance import PARAMETER_SETS as IFM_SETS  # the same three IFM sets

from jointplay import integrate
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


@numba.njit(cache=True)
def van_der_pol(t: float, y: Any, args: Any) -> Any:
    mu = args[0][0]
    return np.array([y[1], mu * (1 - y[0] ** 2) * y[1] - y[0]])


@numba.njit(cache=True)
def van_der_pol_jacobian(t: float, y: Any, f: Any, args: Any, out: Any) -> bool:
    mu = args[0][0]
    out[0, 0], out[0, 1] = 0.0, 1.0
    out[1, 0], out[1, 1] = -2 * mu * y[0] * y[1] - 1.0, mu * (1 - y[0] ** 2)
    return True


@numba.njit(cache=True)
def forced_decay(t: float, y: Any, args: Any) -> Any:
    return -args[0] * y + np.sin(t)


@numba.njit(cache=True)
def falling(t: float, y: Any, args: Any) -> Any:
    return np.array([y[1], -9.81])


@numba.njit(cache=True)
def land_on_floor(t: float, y: Any, t_new: float, y_new: Any, args: Any) -> float:
    return 0.5 if y[0] > 0.0 and y_new[0] < -1e-3 else 1.0


@numba.njit(cache=True)
def bounce(t: float, y: Any, args: Any) -> bool:
    if y[0] < 0.0:
        y[0], y[1] = -y[0], -0.9 * y[1]
        args[1][0] += 1.0
        return True
    return False


def generic(method: str) -> list[Callable[[], str]]:
    """The generic integrate's cases with ``method``."""
    mu = (np.array([5.0]),)
    calls: dict[str, Callable[[], Any]] = {
        "van der Pol": lambda: integrate(van_der_pol, (0.0, 3.0), [2.0, 0.0], args=mu,
                                         rtol=1e-6, atol=1e-8, method=method),
        "van der Pol backwards": lambda: integrate(
            van_der_pol, (2.5, -1.0), [2.0, 0.0], args=(np.array([1.0]),), rtol=1e-5,
            method=method),
        "van der Pol jacobian": lambda: integrate(
            van_der_pol, (0.3, 2.0), [2.0, 0.0], args=(np.array([10.0]),),
            jac=van_der_pol_jacobian, max_step=0.05, method=method),
        "forced decay": lambda: integrate(
            forced_decay, (1.0, 4.0), [1.0, 2.0, 3.0], args=(np.array([2.0, 30.0, 500.0]),),
            rtol=1e-7, atol=[1e-9, 1e-9, 1e-6], first_step=1e-4, method=method),
        "bounce": lambda: integrate(
            falling, (0.0, 3.0), [1.0, 0.0], args=(np.zeros(1), np.zeros(1)),
            step_check=land_on_floor, after_step=bounce, n_second=1,
            hold_after_failure=True, rtol=1e-6, method=method),
        "out of steps": lambda: integrate(
            van_der_pol, (0.0, 3000.0), [2.0, 0.0], args=(np.array([1000.0]),), max_steps=20,
            throw=False, method=method),
    }  # fmt: skip

    def line(name: str, call: Callable[[], Any]) -> str:
        r = call()
        counts = (r.nfev, r.njev, r.nlu, r.n_steps, r.n_rejected_error, r.n_rejected_newton,
                  r.n_rejected_check)  # fmt: skip
        return (f"integrate {method} {name:<22} {digest(r.t, r.y, counts)}  steps "
                f"{r.n_steps:>6}  {r.status.name}")  # fmt: skip

    return [lambda n=name, c=call: line(n, c) for name, call in calls.items()]


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
    for method in ("radau", "rodas4", "dopri5"):
        out += generic(method)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="the cases under ~1 s each")
    args = parser.parse_args()
    for case in cases(args.quick):
        print(case(), flush=True)


if __name__ == "__main__":
    main()
