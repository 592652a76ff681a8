"""Compile the kernels a test run compiles first into Numba's on-disk cache, split in groups:
``python tests/_precompile.py NAME,NAME`` (names of :data:`KERNELS`; ``--list``: the names,
compiling none).

Two kinds: the kernels that importing ``eom`` compiles (``@njit(signature)``: the lane source's
right-hand side compiled apart, ~12 CPU-s) and the single engine's traced lanes
(``traced:<integrator>``, :data:`jointplay._kernels.lanes.cpu.traced`, compiled on first use:
each inlines the whole lane source, the largest compilations of a test run). Under
pytest-xdist every worker would compile them at the same time from a cold cache (a fresh
clone); ``tests/conftest.py`` runs this script on :data:`GROUPS` (disjoint) instead, one
process each, before the workers start: each process leaves the other group's eager kernels
lazy (its ``numba.njit`` drops their signatures) and compiles its own — a traced lane by one
short integration of the paper four-bar — which Numba's cache then holds for the workers. Run
from the controller only; a failure here is ignored (the workers compile as they did, and a
compile error is theirs to report).
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

#: Each kernel with the stem of its cache index file (``<stem>-<line>.pyXY.nbi``): the
#: explicit-signature one that importing ``eom`` compiles (:mod:`jointplay._kernels.shared`
#: builds it for it) and each integrator's traced lane.
KERNELS = {
    "jointplay._kernels.lanes.source.rhs": "source.rhs_apart",
    "traced:radau": "cpu._traced_radau",
    "traced:rodas4": "cpu._traced_rodas4",
    "traced:dopri5": "cpu._traced_dopri5",
}
#: Two disjoint groups of about equal compile time (the implicit lane is the largest).
GROUPS = (
    ("jointplay._kernels.lanes.source.rhs", "traced:radau"),
    ("traced:rodas4", "traced:dopri5"),
)


def _warm(integrator: str) -> None:
    """One short integration by ``integrator``'s traced lane, typed as ``simulate`` calls it."""
    import numpy as np

    from jointplay.dynamics.integrate import integrate_mechanism
    from jointplay.dynamics.setup import ContactModel
    from jointplay.dynamics.simulate import Start, initial_state
    from jointplay.dynamics.system import build_system
    from jointplay.io.config import load_preset

    mechanism = load_preset("paper-fourbar")
    system = build_system(mechanism, ContactModel().joints(mechanism), ramp_time=0.05)
    y0 = initial_state(system, Start("rest"))
    integrate_mechanism(
        system.kernel_args(), 1e-4, y0, method=integrator, rtol=1e-6,
        atol=np.full(y0.shape[0], 1e-6), max_step=1e-4, max_steps=5, throw=False,
    )  # fmt: skip


def main(names: list[str]) -> None:
    import numba

    original = numba.njit
    held: dict[str, tuple[Any, Any]] = {}

    def lazy(*args: Any, **kwargs: Any) -> Any:
        if not args or args[0] is None or callable(args[0]):
            return original(*args, **kwargs)
        signature = args[0]

        def decorate(function: Callable[..., Any]) -> Any:
            dispatcher = original(*args[1:], **kwargs)(function)
            held[f"{function.__module__}.{function.__name__}"] = (dispatcher, signature)
            return dispatcher

        return decorate

    numba.njit = lazy
    try:
        import jointplay._kernels.eom  # noqa: F401  (its eager kernels, held lazy)
    finally:
        numba.njit = original
    from jointplay._kernels.lanes.cpu import traced

    if names == ["--list"]:
        print(*sorted([*held, *(f"traced:{name}" for name in traced)]), sep="\n")
        return
    for name in names:
        if name.startswith("traced:"):
            _warm(name.removeprefix("traced:"))
            continue
        dispatcher, signature = held[name]  # a KeyError: eom changed, this does nothing
        dispatcher.compile(signature)


if __name__ == "__main__":
    main(sys.argv[1].split(","))
