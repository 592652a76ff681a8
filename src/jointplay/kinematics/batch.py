"""Four-bar kinematics vectorised over many link-length samples × crank angles.

The closed form of :mod:`jointplay.kinematics.fourbar` (the same loop closure, conventions and
assembly branch) written for an (m, 4) array of lengths ``(crank a, coupler b, rocker c,
ground d)`` and a grid of n crank angles given by their cosines and sines, without
trigonometric functions in the inner loop: every angle is carried as its direction cosines.
Results are (m, n) arrays, SI (m, rad/s, rad/s²). Tolerance studies evaluate thousands of
linkages this way (:class:`jointplay.tolerance.responses.FourBarKinematics`).

Lengths that do not let the crank turn fully give NaN or meaningless values; check them
first with :func:`turns_fully`.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "FourBarStates",
    "accelerations",
    "coupler_point",
    "positions",
    "transmission_angle_min",
    "turns_fully",
    "velocities",
]

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


@dataclass(frozen=True)
class FourBarStates:
    """Positions of m four-bars at n crank angles, as direction cosines ((m, n) arrays).

    Attributes:
        c3, s3: cos θ3 and sin θ3 of the coupler.
        c4, s4: cos θ4 and sin θ4 of the rocker.
        ax, ay: crank pin A = a·(cos θ2, sin θ2), m.
    """

    c3: FloatArray
    s3: FloatArray
    c4: FloatArray
    s4: FloatArray
    ax: FloatArray
    ay: FloatArray


def _columns(lengths: FloatArray) -> tuple[FloatArray, ...]:
    """The (m, 1) columns a, b, c, d of the (m, 4) lengths (broadcast against the grid)."""
    return tuple(lengths[:, i : i + 1] for i in range(4))


def positions(
    lengths: FloatArray, c2: FloatArray, s2: FloatArray, branch: int = 1
) -> FourBarStates:
    """Coupler and rocker directions for crank directions ``(c2, s2)`` (Norton §4.5).

    With f = |O4 − A|, e_f = (O4 − A)/f and cos β = (b² + f² − c²)/(2bf), the coupler direction
    e3 is e_f turned by σβ (σ = ``branch``, ±1) and the rocker direction e4 = (A + b e3 − O4)/c:
    the loop closure of :func:`jointplay.kinematics.fourbar.positions`.

    Args:
        lengths: (m, 4) crank, coupler, rocker, ground lengths, m.
        c2, s2: (n,) cosines and sines of the crank angles θ2.
        branch: assembly branch, +1 or −1 (see :mod:`jointplay.model.templates`).
    """
    a, b, c, d = _columns(lengths)
    ax, ay = a * c2, a * s2
    vx, vy = d - ax, -ay
    f2 = vx * vx + vy * vy
    inv_f = 1.0 / np.sqrt(f2)
    cos_b = (b * b - c * c + f2) * inv_f * (0.5 / b)
    sin_b = np.sqrt(np.maximum(1.0 - cos_b * cos_b, 0.0)) * branch
    vx *= inv_f
    vy *= inv_f
    c3 = vx * cos_b - vy * sin_b
    s3 = vy * cos_b + vx * sin_b
    c4 = (ax + b * c3 - d) / c
    s4 = (ay + b * s3) / c
    return FourBarStates(c3, s3, c4, s4, ax, ay)


def velocities(
    lengths: FloatArray, states: FourBarStates, c2: FloatArray, s2: FloatArray, omega2: float
) -> tuple[FloatArray, FloatArray]:
    """ω3, ω4 (rad/s) at constant crank speed ``omega2`` (rad/s) (Norton §6.7).

    ω3 = a ω2 sin(θ4 − θ2) / (b sin(θ3 − θ4)) and ω4 = a ω2 sin(θ3 − θ2) / (c sin(θ3 − θ4)):
    the loop's time derivative dotted with e4 and e3.
    """
    a, b, c, _ = _columns(lengths)
    c3, s3, c4, s4 = states.c3, states.s3, states.c4, states.s4
    inv_s34 = 1.0 / (s3 * c4 - c3 * s4)  # 1 / sin(θ3 − θ4)
    omega3 = (a * omega2 / b) * (s4 * c2 - c4 * s2) * inv_s34
    omega4 = (a * omega2 / c) * (s3 * c2 - c3 * s2) * inv_s34
    return omega3, omega4


def accelerations(
    lengths: FloatArray,
    states: FourBarStates,
    c2: FloatArray,
    s2: FloatArray,
    omega2: float,
    omega3: FloatArray,
    omega4: FloatArray,
) -> tuple[FloatArray, FloatArray]:
    """α3, α4 (rad/s²) at constant crank speed ``omega2`` (α2 = 0; Norton §7.3).

    The loop's second time derivative dotted with e4 and e3; ``omega3`` and ``omega4`` are
    those of :func:`velocities`.
    """
    a, b, c, _ = _columns(lengths)
    c3, s3, c4, s4 = states.c3, states.s3, states.c4, states.s4
    inv_s34 = 1.0 / (s3 * c4 - c3 * s4)
    k = a * omega2 * omega2
    cos34 = c3 * c4 + s3 * s4
    w3sq, w4sq = omega3 * omega3, omega4 * omega4
    alpha3 = -(k * (c2 * c4 + s2 * s4) + b * w3sq * cos34 - c * w4sq) * inv_s34 / b
    alpha4 = -(k * (c2 * c3 + s2 * s3) + b * w3sq - c * w4sq * cos34) * inv_s34 / c
    return alpha3, alpha4


def coupler_point(states: FourBarStates, px: float, py: float) -> tuple[FloatArray, FloatArray]:
    """Position (x, y), m, of the coupler point (px, py) given in the coupler frame.

    The frame has its origin at A and its x-axis towards B.
    """
    c3, s3 = states.c3, states.s3
    return states.ax + px * c3 - py * s3, states.ay + px * s3 + py * c3


def turns_fully(lengths: FloatArray) -> BoolArray:
    """(m,) True where the crank turns through 360°: |b − c| <= |d − a| and d + a <= b + c.

    |O4 − A| ranges over [|d − a|, d + a]; the triangle A–B–O4 closes while it lies in
    [|b − c|, b + c] (the condition of :func:`jointplay.kinematics.fourbar.infeasible_crank_ranges`).
    All lengths must be > 0.
    """
    a, b, c, d = lengths.T
    positive = np.all(lengths > 0, axis=1)
    with np.errstate(invalid="ignore"):
        return np.asarray(
            positive & (np.abs(b - c) <= np.abs(d - a)) & (d + a <= b + c), dtype=bool
        )


def transmission_angle_min(lengths: FloatArray) -> FloatArray:
    """(m,) smallest transmission angle over a crank revolution: min over θ2 of min(μ, π − μ), rad.

    cos μ = (b² + c² − f²)/(2bc) with f = |O4 − A|; |cos μ| is largest at θ2 = 0 or π
    (f = |d − a| or d + a), so the minimum is exact, without a grid.
    """
    a, b, c, d = lengths.T
    cos_0 = (b * b + c * c - (d - a) ** 2) / (2 * b * c)
    cos_pi = (b * b + c * c - (d + a) ** 2) / (2 * b * c)
    largest = np.minimum(np.maximum(np.abs(cos_0), np.abs(cos_pi)), 1.0)
    return np.asarray(np.arccos(largest), dtype=float)
