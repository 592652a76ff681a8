"""What every batch kernel shares: the result type :class:`BatchKernelOutput` (one row per
lane) and the peak rule's constants.

The contract of ``run_batch`` (arguments, orders and units of the outputs, the peak rule: the
module docstring of :mod:`jointplay._kernels.batch`) is shared by the CPU engine
(:func:`jointplay._kernels.batch.run_batch`), the CUDA lanes
(:func:`jointplay._kernels.lanes.cuda.run_batch`) and the JAX backend
(:func:`jointplay._kernels.jax_batch.run_batch`, :mod:`jointplay._kernels.jax.integrate`);
what they share lives here, below all three, so that none of them imports another for it.
NumPy and the lanes' source (plain Python) only at import: no kernel is compiled.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import numpy.typing as npt

from jointplay._kernels.lanes import source

#: The peak rule's margin and the DOPRI5 tableau (Hairer, Nørsett & Wanner, Solving ODEs I,
#: Table II.5.2) with its dense output, as the lanes' source holds them
#: (:mod:`jointplay._kernels.lanes.source`).
REFINE_MARGIN = source.REFINE_MARGIN
#: Interior points of a refined step, as fractions of the step.
REFINE_POINTS = np.arange(1, source.N_REFINE + 1) / 8.0
#: Dense output (SciPy's ``RK45.P``, 7 × 4): y(t + θh) = y + h Σ_j k_j Σ_m P[j, m] θ^(m+1).
DENSE = np.reshape(np.array(source.DENSE), (7, 4))


class BatchKernelOutput(NamedTuple):
    """What a batch kernel's ``run_batch`` returns, per lane (the orders and units: the
    module docstring of :mod:`jointplay._kernels.batch`)."""

    peaks: npt.NDArray[np.float64]
    stats: npt.NDArray[np.float64]
    status: npt.NDArray[np.int64]
    t_reached: npt.NDArray[np.float64]
    n_steps: npt.NDArray[np.int64]
    n_rejected: npt.NDArray[np.int64]
    n_rhs: npt.NDArray[np.int64]
