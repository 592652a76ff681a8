"""Rare defects: the probability of a failure region far in the tail, by cross-entropy
importance sampling.

Monte Carlo needs about 3/p failure-free samples to bound a defect rate p (880 000 for 3.4
DPM). Importance sampling draws the inputs from a density shifted towards the failure
region and reweights each sample by the likelihood ratio; the **cross-entropy method**
(Rubinstein 1999, *Methodology and Computing in Applied Probability* 1:127; Rubinstein &
Kroese, *The Cross-Entropy Method*, 2004, §3; for reliability, Kurtz & Song 2013,
*Structural Safety* 42:35) finds that shift by itself, in stages:

1. Work in standard normal space: every input is ``x = F⁻¹(Φ(z))`` of a standard normal
   ``z`` (exact for any input distribution, truncated ones included).
2. Stage ``t``: draw ``n_stage`` points from N(μₜ, I); the excess ``e(z)`` (> 0: a defect) of
   each; the level γₜ = min(0, the (1 − ρ) quantile of e). μₜ₊₁ = the likelihood-ratio
   weighted mean of the points with e ≥ γₜ (the cross-entropy update of a normal's mean).
   Stop once γₜ = 0: the elite points are defects.
3. Final stage, independent of the others: ``n_final`` points from N(μ, I), weights
   w(z) = φ(z)/φ(z − μ) = exp(−μ·z + |μ|²/2); the estimate p̂ = mean(w·1[e > 0]) is unbiased,
   and its 95 % interval p̂ ± 1.96 s/√n (s the sample std of w·1[e > 0]; central limit
   theorem) is what :class:`RareEstimate` reports.

Why this and not subset simulation (Au & Beck 2001): the final stage is plain importance
sampling with a fixed density, so its samples are independent and the interval is the
ordinary one, which the tests check for coverage; subset simulation's Markov chains give
correlated samples whose variance needs an estimated correlation factor. The price: one
mean shift finds one failure region; a response with several separate regions (e.g. two
joints failing for opposite input deviations) is underestimated — the pilot stages' defects
show whether they fall in one region (``RareEstimate.stages``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError

__all__ = ["RareEstimate", "cross_entropy_importance_sampling"]

FloatArray = NDArray[np.float64]

#: z of the two-sided 95 % normal interval.
_Z95 = 1.959963984540054


@dataclass(frozen=True)
class RareEstimate:
    """A defect probability from importance sampling.

    Attributes:
        probability: the estimate p̂ (fraction of parts with a defect).
        interval: its 95 % interval (central limit theorem; the lower bound clipped at 0).
        samples: every evaluation spent, pilot stages included.
        final_samples: evaluations of the final stage, which alone give the estimate.
        defects: defects among the final stage's samples.
        shift: the final sampling density's mean in standard normal space.
        stages: pilot stages run.
        converged: the pilot stages reached the failure region (γ = 0); if not, the estimate
            comes from a density that stops short of it and may be far too low.
    """

    probability: float
    interval: tuple[float, float]
    samples: int
    final_samples: int
    defects: int
    shift: tuple[float, ...]
    stages: int
    converged: bool

    @property
    def dpm(self) -> float:
        """Defects per million."""
        return 1e6 * self.probability

    @property
    def dpm_interval(self) -> tuple[float, float]:
        """The interval in defects per million."""
        return 1e6 * self.interval[0], 1e6 * self.interval[1]

    @property
    def relative_half_width(self) -> float:
        """Half the interval over the estimate (inf without a defect)."""
        if self.probability <= 0.0:
            return math.inf
        return 0.5 * (self.interval[1] - self.interval[0]) / self.probability

    @property
    def reliability_index(self) -> float:
        """|μ| of the final density: the distance of the failure region in σ (for a linear
        response, close to β = −Φ⁻¹(p))."""
        return float(np.linalg.norm(self.shift))

    def as_dict(self) -> dict[str, object]:
        return {
            "method": "cross-entropy importance sampling (Rubinstein & Kroese 2004)",
            "probability": self.probability,
            "interval95": list(self.interval),
            "dpm": self.dpm,
            "dpm_ci95": list(self.dpm_interval),
            "samples": self.samples,
            "final_samples": self.final_samples,
            "defects": self.defects,
            "stages": self.stages,
            "converged": self.converged,
            "reliability_index": self.reliability_index,
        }


def cross_entropy_importance_sampling(
    excess: Callable[[FloatArray], FloatArray],
    dimension: int,
    *,
    seed: int = 0,
    n_stage: int = 1000,
    n_final: int = 10000,
    rho: float = 0.1,
    max_stages: int = 8,
) -> RareEstimate:
    """The probability that ``excess(z) > 0`` for z ~ N(0, I) of ``dimension``.

    Args:
        excess: (n, d) standard normal points → (n,) excess over the limit, > 0 a defect;
            NaN (a failed evaluation) counts as a defect.
        dimension: d, the number of random inputs.
        seed: seed of every stage's draws.
        n_stage: points per pilot stage.
        n_final: points of the final stage.
        rho: share of a pilot stage kept as its elite (0 < ρ < 0.5).
        max_stages: pilot stages at most (the budget is ``max_stages·n_stage + n_final``).
    """
    if dimension < 1 or n_stage < 10 or n_final < 10 or not 0.0 < rho < 0.5 or max_stages < 1:
        raise ConfigError(
            "cross-entropy importance sampling: need dimension >= 1, n_stage and n_final "
            f">= 10, 0 < rho < 0.5, max_stages >= 1; got {dimension}, {n_stage}, {n_final}, "
            f"{rho}, {max_stages}"
        )
    rng = np.random.default_rng(seed)
    mu = np.zeros(dimension)
    spent = 0
    stages = 0
    converged = False
    while stages < max_stages:
        z = mu + rng.standard_normal((n_stage, dimension))
        e = _excess(excess, z)
        spent += n_stage
        stages += 1
        level = min(0.0, float(np.quantile(e, 1.0 - rho, method="higher")))
        elite = e >= level
        w = _weights(z[elite], mu)
        mu = (w[:, None] * z[elite]).sum(axis=0) / w.sum()
        if level == 0.0:
            converged = True
            break
    z = mu + rng.standard_normal((n_final, dimension))
    defect = _excess(excess, z) > 0.0
    y = np.where(defect, _weights(z, mu), 0.0)
    p = float(y.mean())
    half = _Z95 * float(y.std(ddof=1)) / math.sqrt(n_final)
    return RareEstimate(
        probability=p,
        interval=(max(0.0, p - half), p + half),
        samples=spent + n_final,
        final_samples=n_final,
        defects=int(defect.sum()),
        shift=tuple(float(v) for v in mu),
        stages=stages,
        converged=converged,
    )


def _excess(function: Callable[[FloatArray], FloatArray], z: FloatArray) -> FloatArray:
    e = np.asarray(function(z), dtype=float).reshape(len(z))
    return np.where(np.isnan(e), np.inf, e)


def _weights(z: FloatArray, mu: FloatArray) -> FloatArray:
    """Likelihood ratio φ(z)/φ(z − μ) of N(0, I) against N(μ, I)."""
    return np.asarray(np.exp(-z @ mu + 0.5 * float(mu @ mu)), dtype=float)
