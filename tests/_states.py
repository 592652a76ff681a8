"""States near a mechanism's nominal assembly for the kernels' Jacobian and film tests."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

from jointplay.dynamics.simulate import Start, initial_state
from jointplay.dynamics.system import System


def perturbed_states(
    system: System, seed: int, position: float, count: int = 6
) -> list[npt.NDArray[np.float64]]:
    """``count`` states near the nominal assembly: positions off by ``position`` (m; 10× that
    in rad) times a standard normal, rates by ~1 m/s and 10 rad/s, and each joint's contact
    memory v0 either 0 or in 0.01–1 m/s, so that some pins penetrate and some are free."""
    rng = np.random.default_rng(seed)
    y0 = initial_state(system, Start())
    n = system.n_coordinates
    nc = len(system.clearances)
    states = []
    for _ in range(count):
        y = y0.copy()
        y[:n] += np.tile([position, position, 10 * position], n // 3) * rng.standard_normal(n)
        y[n : 2 * n] += np.tile([1.0, 1.0, 10.0], n // 3) * rng.standard_normal(n)
        y[2 * n + 2 :] = np.where(rng.random(nc) < 0.5, 0.0, rng.uniform(0.01, 1.0, nc))
        states.append(y)
    return states
