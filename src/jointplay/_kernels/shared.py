"""The lane source's functions that the single engine calls, compiled once for the CPU.

The equations are written once, in :mod:`jointplay._kernels.lanes.source` (and
:mod:`~jointplay._kernels.lanes.source_radau`), in the subset of Python that Numba's CPU and
CUDA targets both compile; the batch lanes take them from
:mod:`jointplay._kernels.lanes.cpu` and the CUDA kernel from its own compilation. The single
engine (:mod:`jointplay._kernels.eom`, :mod:`~jointplay._kernels.constraints`,
:mod:`~jointplay._kernels.contact`) takes those below from here, compiled by
:func:`jointplay._kernels.lanes.build.build` with its flags (``error_model="numpy"``: a
division by zero gives inf/NaN, the kernels never raise), so that a law, the driver's motion or
the Schur solve is one piece of code for every engine.
"""

from __future__ import annotations

from typing import Any

import numba

from jointplay._kernels.lanes.build import build

__all__ = ["SHARED", "compiled"]

#: The functions compiled here (a subset closed under the calls among them).
SHARED = (
    "step3", "power", "normal_force", "friction_force", "law_slopes",
    "driver_angle", "driver_speed", "driver_acceleration", "cholesky_solve", "all_finite",
    "interrupt_pending", "onset_fraction", "impact_rate",
)  # fmt: skip

#: Each of :data:`SHARED`, compiled, by name.
#: ``inline="always"``: Numba inlines each into its caller, as the single engine's own helpers
#: are (a compiled call that passes an array costs ~100 ns of reference counting, several
#: times per right-hand side; measured 6–12 % of ``bench_clearance.py``'s times without it).
#: Numba's on-disk cache does not follow inlined functions: after editing the lane source,
#: clear the caches (the README's ``find src -name "*.nb[ic]" -delete``).
compiled: dict[str, Any] = build(
    numba.njit(cache=True, error_model="numpy", inline="always"), only=SHARED
)
