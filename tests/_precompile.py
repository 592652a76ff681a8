"""Compile some of :mod:`jointplay._kernels.eom`'s explicit-signature kernels into Numba's
on-disk cache, and only those: ``python tests/_precompile.py NAME,NAME`` (names of
:data:`KERNELS`; ``--list``: the kernels held, compiling none).

Importing ``eom`` compiles its explicit-signature kernels (``@njit(signature)``, :data:`KERNELS`)
one after the other, ~120-150 CPU-s from a cold cache. Under pytest-xdist every worker imports it
while collecting, so from a cold cache (a fresh clone) each worker compiled all of them at the
same time. ``tests/conftest.py`` runs this script twice instead, before the workers start,
on :data:`GROUPS` (disjoint): each process leaves the other group's kernels lazy (its
``numba.njit`` drops their signatures), compiles its own with the same signature, which
Numba's cache then holds for the workers' import. Run from the controller only; a failure
here is ignored (the workers compile as they did, and a compile error is theirs to report).
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from typing import Any

#: The explicit-signature kernels that importing ``eom`` compiles (its own four, and the lane
#: source's right-hand side compiled apart, which :mod:`jointplay._kernels.shared` builds for
#: it), each with the stem of its cache index file (``<stem>-<line>.pyXY.nbi``).
KERNELS = {
    "jointplay._kernels.eom.after_step": "eom.after_step",
    "jointplay._kernels.eom.step_check": "eom.step_check",
    "jointplay._kernels.eom.state_rhs": "eom.state_rhs",
    "jointplay._kernels.eom.jacobian_state": "eom.jacobian_state",
    "jointplay._kernels.lanes.source.rhs": "source.rhs_apart",
}
#: Two disjoint groups of about equal compile time (measured from a cold cache, CPU-s, each
#: with the callees it compiles first: after_step 55, step_check 5, the source's rhs apart
#: ~12; jacobian_state 41-51, state_rhs 21-24).
GROUPS = tuple(
    tuple(f"jointplay._kernels.{name}" for name in group)
    for group in (
        ("eom.after_step", "eom.step_check", "lanes.source.rhs"),
        ("eom.jacobian_state", "eom.state_rhs"),
    )
)


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
    if names == ["--list"]:
        print(*sorted(held), sep="\n")
        return
    for name in names:
        dispatcher, signature = held[name]  # a KeyError: eom changed, this does nothing
        dispatcher.compile(signature)


if __name__ == "__main__":
    main(sys.argv[1].split(","))
