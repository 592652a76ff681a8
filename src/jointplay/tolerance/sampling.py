"""Seeded sampling of a tolerance specification: a pure function of (spec, n, seed).

Every input draws from its own random stream, ``SeedSequence(seed, spawn_key=(crc32(name),))``
with NumPy's PCG64 generator, so

* the same (spec, n, seed) gives the same samples on every machine and backend (sampling
  happens once, in the calling process; backends only evaluate);
* an input's samples do not change when other inputs are added or removed (common random
  numbers when comparing specifications);
* with ``method="random"`` the first m of n samples are the samples of a run with n = m.

Each stream yields probabilities ``u`` strictly inside (0, 1); the input's inverse CDF
(:meth:`~jointplay.tolerance.spec.Tolerance.ppf`) turns them into values. ``method="lhs"``
stratifies each input into n equal-probability bins, one sample per bin, independently
permuted per input (Latin hypercube sampling; McKay, Beckman & Conover, *Technometrics* 21,
1979).
"""

from __future__ import annotations

import zlib
from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError
from jointplay.tolerance.spec import ToleranceSpec

__all__ = ["SAMPLING_METHODS", "Samples", "check_settings", "sample", "uniforms"]

FloatArray = NDArray[np.float64]
SamplingMethod = Literal["random", "lhs"]

#: Ways of drawing the probabilities.
SAMPLING_METHODS: tuple[str, ...] = ("random", "lhs")

_RESOLUTION = 2.0**-53  # spacing of Generator.random()'s doubles in [0, 1)


@dataclass(frozen=True)
class Samples:
    """Input samples of a study.

    Attributes:
        names: input names (the columns of ``values``).
        values: (n, k) input values, SI.
        seed: the seed they were drawn with.
        method: ``"random"`` or ``"lhs"``.
    """

    names: tuple[str, ...]
    values: FloatArray
    seed: int
    method: str

    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.values.shape[0])


def check_settings(n: int, seed: int, method: str) -> None:
    """Raise :class:`ConfigError` unless n >= 1, seed >= 0 (integers) and ``method`` is known."""
    if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
        raise ConfigError(f"number of samples must be a positive integer, got {n!r}")
    if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
        raise ConfigError(f"seed must be a non-negative integer, got {seed!r}")
    if method not in SAMPLING_METHODS:
        raise ConfigError(
            f"sampling method must be one of {', '.join(SAMPLING_METHODS)}, got {method!r}"
        )


def stream(seed: int, name: str) -> np.random.Generator:
    """The random generator of input ``name`` under ``seed`` (PCG64)."""
    key = zlib.crc32(name.encode("utf-8"))
    return np.random.Generator(np.random.PCG64(np.random.SeedSequence(int(seed), spawn_key=(key,))))


def uniforms(
    names: tuple[str, ...] | list[str], n: int, seed: int, method: SamplingMethod = "random"
) -> FloatArray:
    """(n, k) probabilities strictly inside (0, 1), one column per input name."""
    check_settings(n, seed, method)
    out = np.empty((n, len(names)))
    for column, name in enumerate(names):
        rng = stream(seed, name)
        if method == "random":
            u = rng.random(n) + 0.5 * _RESOLUTION
        else:
            strata = rng.permutation(n)
            u = (strata + rng.random(n) + 0.5 * _RESOLUTION) / n
        out[:, column] = u
    return out


def sample(spec: ToleranceSpec, n: int, seed: int, *, method: SamplingMethod = "random") -> Samples:
    """Draw ``n`` samples of every input of ``spec`` with ``seed``.

    Args:
        spec: the toleranced inputs and their distributions.
        n: number of samples (>= 1).
        seed: non-negative integer seed.
        method: ``"random"`` (independent draws) or ``"lhs"`` (Latin hypercube).

    Returns:
        The samples, one column per input in the order of ``spec.names``.
    """
    if len(spec) == 0:
        raise ConfigError("the tolerance specification has no inputs to sample")
    u = uniforms(spec.names, n, seed, method)
    values = np.column_stack(
        [item.tolerance.ppf(u[:, column]) for column, item in enumerate(spec.inputs)]
    )
    return Samples(spec.names, values, int(seed), method)
