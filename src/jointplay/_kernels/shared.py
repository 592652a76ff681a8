"""The single engine: the lane source compiled for the CPU with the single engine's hooks.

The equations are written once, in :mod:`jointplay._kernels.lanes.source` (and
:mod:`~jointplay._kernels.lanes.source_radau`), in the subset of Python that Numba's CPU and
CUDA targets both compile; the batch lanes take them from :mod:`jointplay._kernels.lanes.cpu`,
the CUDA kernel from its own compilation, and the single engine (:mod:`jointplay._kernels.eom`,
:mod:`~jointplay._kernels.constraints`, :mod:`~jointplay._kernels.contact`,
:mod:`~jointplay._kernels.driver`) from here: the right-hand side, the contact forces and laws,
the film, the quantities, the contact memory and the closed-form Jacobian are the source's.
The sustained-contact mode, which the GPU lanes lack, is the CPU's own
(:mod:`jointplay._kernels.sustained`): its functions fill the source's hooks
(``locked_accelerations``, ``release_fraction``, ``switch_contacts``) and are compiled into
the same namespace, as the CPU lanes compile them.

Compiled by :func:`jointplay._kernels.lanes.build.build` with the single engine's flags
(``error_model="numpy"``: a division by zero gives inf/NaN, the kernels never raise) and
``inline="always"``: Numba inlines each function into its caller (a compiled call that passes
an array costs ~100 ns of reference counting, several times per right-hand side; measured
6–12 % of ``bench_clearance.py``'s times without it). Numba's on-disk cache does not follow
inlined functions: after editing the lane source, clear the caches (the README's
``find src -name "*.nb[ic]" -delete``). The copies are tagged ``_single``, so their cache
entries are never the lanes' (which inline other functions).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numba
import numpy as np

from jointplay._kernels import sustained
from jointplay._kernels.lanes import source
from jointplay._kernels.lanes.build import build, closed
from jointplay._kernels.lanes.projection import project_lapack

__all__ = ["APART", "SHARED", "apart", "compiled", "pick"]

#: The sustained-contact mode's functions, compiled apart (not inlined: they allocate and
#: run only while a joint is locked); and the Reynolds film's force and coefficients (not
#: inlined into every copy of the right-hand side: inlined, they made the single engine's
#: first compilation ~50 % longer, measured 140 s → 217 s on a loaded 2-core machine). The
#: π-film is now the default, so this is one compiled call per joint and right-hand side on
#: the default's hot path: a trade of first compilation against run time not yet measured.
_OWN: dict[str, Callable[..., Any]] = {
    **sustained.OWN,
    "reynolds_force": source.reynolds_force,
    "reynolds_matrix": source.reynolds_matrix,
}

#: The single engine's versions of the source's hooks (the CPU lanes' too): the
#: sustained-contact mode's (accelerations, release control, switches) and the projection
#: with LAPACK's solve.
_HOOKS: dict[str, Callable[..., Any]] = {**sustained.HOOKS, "project": project_lapack}

#: The functions the single engine calls, and every source function they call.
SHARED = closed(
    (
        "rhs",
        "any_film",
        "penetration_and_rate",
        "contact_memory",
        "onset_fraction",
        "impact_rate",
        "jacobian_clear",
        "law_slopes",
        "step3",
        "power",
        "normal_force",
        "friction_force",
        "driver_angle",
        "driver_speed",
        "driver_acceleration",
        "cholesky_solve",
        "all_finite",
        "constraint_residual",
        "project",
        "sustained_on",
        "release_fraction",
        "switch_contacts",
    ),
    {**_OWN, **_HOOKS},
)

#: Each of :data:`SHARED` (the hook and the mode's functions included), compiled, by name.
compiled: dict[str, Any] = build(
    numba.njit(cache=True, error_model="numpy", inline="always"),
    hooks=_HOOKS,
    extras={"np": np},
    only=SHARED,
    own=_OWN,
    decorate_own=numba.njit(cache=True, error_model="numpy"),
    tag="single",
)

#: The roots compiled apart for the cold callers: each a real function (its callees inlined
#: into it) rather than inlined into every caller. Inlined, each of the single engine's entry
#: points compiled its own copy of the whole right-hand side (``evaluate``, ``quantities``,
#: ``jacobian_state`` through ``jacobian_fixed``'s columns, ...), and the first compilation
#: grew with every copy. The integrator's hot hooks (``eom.state_rhs``, ``jacobian_clear``) keep the
#: inlined copies of :data:`compiled`; what runs once per output sample, or once per column of
#: a differenced Jacobian, pays one call instead.
APART = ("rhs", "rhs_and_quantities", "film_components")

_C1 = numba.float64[::1]
_C2 = numba.float64[:, ::1]
_READ = numba.types.Array(numba.float64, 1, "C", readonly=True)
_READ_INT = numba.types.Array(numba.int64, 1, "C", readonly=True)
#: The source's ``rhs`` compiled once for every cold caller: typed up front, since a call
#: passing the literal ``True`` (``eom.evaluate``) and one passing ``False``
#: (``jacobian_fixed``) would otherwise compile two copies (Numba types a literal bool as its
#: own type); writable arrays convert to these read-only types.
_APART_SIGNATURES = {
    "rhs": numba.float64(
        numba.float64, _C1, _READ, _READ_INT, _READ_INT, _C1, _C1, numba.boolean, _C2, _C2, _C1
    ),
}

#: ``jacobian_fixed`` and :data:`APART`, compiled in a namespace of their own (tag
#: ``apart``) where the roots are not inlined; the mode's and the film's own functions are
#: :data:`compiled`'s (one compilation of each).
apart: dict[str, Any] = build(
    numba.njit(cache=True, error_model="numpy", inline="always"),
    hooks=_HOOKS,
    extras={"np": np, **{name: compiled[name] for name in _OWN}},
    only=closed(("jacobian_fixed", *APART), _OWN),
    own={name: getattr(source, name) for name in APART},
    decorate_own=lambda function: numba.njit(
        _APART_SIGNATURES.get(function.__name__), cache=True, error_model="numpy"
    )(function),
    tag="apart",
)


def pick(table: dict[str, Any], names: str) -> tuple[Any, ...]:
    """The compiled functions ``names`` (separated by spaces) of ``table`` (:data:`compiled`
    or :data:`apart`), in that order: a kernel module binds them to module globals, which
    Numba's compiled callers can read (a dict lookup they cannot)."""
    return tuple(table[name] for name in names.split())
