"""Sampling as parts are made: each hole and each pin drawn within its own ISO 286 zone.

A pin joint's radial clearance is half the difference of two diameters made by two processes:
the bearing's hole (Ø D + EI … D + ES) and the pin (Ø d + ei … d + es). :func:`fit_features`
gives one toleranced input per feature, ``hole_<joint>`` and ``pin_<joint>`` (diameters, m),
each with its own distribution (normal ±3σ at its limits, uniform, or a normal of process
capability Cpk, σ = half-band / (3 Cpk), centred: Cp = Cpk); :func:`model_inputs` turns the
sampled diameters into the radial clearances the dynamics take,
``clearance_<joint> = (hole − pin)/2``.

Drawn independently, the clearance's spread is the root sum of squares of the two features'
(for H8/f7 at Ø10, normal ±3σ: σ_c = √(3.67² + 2.50²)/2 µm = 2.22 µm), not the fit's
worst-case band at ±3σ (σ_c = (ES − ei − EI + es)/12 = 3.08 µm, 1.39× wider), which was
the old sampling (``"band"``: the radial clearance itself normal between the fit's smallest
and largest clearance; :meth:`jointplay.study.design.Scheme.spec`). Link lengths are one
feature each already (ISO 2768-1 class, ``length_<name>``); a Cpk for lengths applies to them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError
from jointplay.tolerance import iso286
from jointplay.tolerance.spec import DISTRIBUTIONS, Distribution, QuantityTolerance, Tolerance

__all__ = ["FEATURES", "SAMPLINGS", "Process", "fit_features", "model_inputs"]

FloatArray = NDArray[np.float64]
Sampling = Literal["parts", "band"]

#: How clearances are sampled: ``parts`` (hole and pin apart) or ``band`` (the fit's band).
SAMPLINGS: tuple[str, ...] = ("parts", "band")
#: The features a process capability may be given for.
FEATURES: tuple[str, ...] = ("hole", "pin", "length")


@dataclass(frozen=True)
class Process:
    """How the parts are made.

    Attributes:
        sampling: ``"parts"`` (hole and pin diameters apart, the clearance their difference)
            or ``"band"`` (the radial clearance normal/uniform over the fit's band).
        distribution: ``"normal"`` (±3σ at the limits, or from ``cpk``), ``"uniform"`` or
            ``"triangular"``, for every feature.
        cpk: process capability Cpk > 0 per feature (``hole``, ``pin``, ``length``), centred
            processes (Cp = Cpk); normal only. Features without one: ±3σ at the limits.
    """

    sampling: Sampling = "parts"
    distribution: Distribution = "normal"
    cpk: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "cpk", dict(self.cpk))
        if self.sampling not in SAMPLINGS:
            raise ConfigError(
                f"sampling must be one of {', '.join(SAMPLINGS)}, got {self.sampling!r}"
            )
        if self.distribution not in DISTRIBUTIONS:
            raise ConfigError(
                f"distribution must be one of {', '.join(DISTRIBUTIONS)}, got {self.distribution!r}"
            )
        for feature, value in self.cpk.items():
            if feature not in FEATURES:
                raise ConfigError(
                    f"Cpk for unknown feature {feature!r}; expected {', '.join(FEATURES)}"
                )
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"Cpk of {feature} must be > 0, got {value!r}")
        if self.cpk and self.distribution != "normal":
            raise ConfigError(f"a Cpk needs normal features, not {self.distribution}")
        if self.sampling == "band" and {"hole", "pin"} & set(self.cpk):
            raise ConfigError("a hole or pin Cpk needs sampling 'parts' (the band has no features)")

    def tolerance(self, feature: str, limits: tuple[float, float]) -> Tolerance:
        """The distribution of one feature between ``limits`` (m, ≥ 0)."""
        return Tolerance(
            limits, self.distribution, cpk=self.cpk.get(feature), bounds=(0.0, math.inf)
        )

    def describe(self) -> dict[str, object]:
        return {"sampling": self.sampling, "distribution": self.distribution, "cpk": self.cpk}


def fit_features(
    joint: str, fit: str, diameter: float, process: Process
) -> tuple[QuantityTolerance, QuantityTolerance]:
    """The hole and pin of ``joint`` (diameters ``hole_<joint>``, ``pin_<joint>``, m) in the
    ISO 286 zones of ``fit`` at nominal ``diameter`` (m)."""
    result = iso286.fit(fit, diameter)
    hole, pin = result.hole, result.shaft
    return (
        QuantityTolerance(
            f"hole_{joint}",
            diameter,
            process.tolerance("hole", (hole.min_size, hole.max_size)),
            unit="m",
            source=f"ISO 286 Ø{diameter * 1e3:g} {hole.designation}",
        ),
        QuantityTolerance(
            f"pin_{joint}",
            diameter,
            process.tolerance("pin", (pin.min_size, pin.max_size)),
            unit="m",
            source=f"ISO 286 Ø{diameter * 1e3:g} {pin.designation}",
        ),
    )


def model_inputs(names: Sequence[str], values: FloatArray) -> tuple[tuple[str, ...], FloatArray]:
    """Sampled features → the dynamics' inputs: every ``hole_<J>``/``pin_<J>`` pair becomes
    ``clearance_<J>`` = (hole − pin)/2, in the position of the hole; the others pass.

    Args:
        names: the sampled inputs' names.
        values: (n, k) their values, SI.
    """
    names = list(names)
    out_names: list[str] = []
    columns: list[FloatArray] = []
    for i, name in enumerate(names):
        if name.startswith("pin_"):
            continue
        if name.startswith("hole_"):
            joint = name.removeprefix("hole_")
            pin = names.index(f"pin_{joint}")
            out_names.append(f"clearance_{joint}")
            columns.append(0.5 * (values[:, i] - values[:, pin]))
        else:
            out_names.append(name)
            columns.append(values[:, i])
    return tuple(out_names), np.column_stack(columns) if columns else values[:, :0]
