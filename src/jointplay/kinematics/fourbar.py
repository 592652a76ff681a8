"""Closed-form kinematics of the four-bar linkage.

Geometry and conventions as in :mod:`jointplay.model.templates`: O2 at the origin, O4 at
(d, 0); crank a (link 2), coupler b (link 3), rocker c (link 4), ground d; angles θ2, θ3, θ4
counter-clockwise from the ground line O2→O4.

Positions: the vector loop a·e(θ2) + b·e(θ3) − c·e(θ4) − d·x̂ = 0 solved through the triangle
A–B–O4 (the geometric form of Freudenstein's equation, e.g. Norton, *Design of Machinery*,
§4.5): with f = |O4 − A| and ψ the direction of A→O4, θ3 = ψ + σ·β where
cos β = (b² + f² − c²)/(2 b f) and σ = ±1 the assembly branch. Velocities and accelerations
follow from the first and second time derivatives of the loop equation, two linear equations
in (ω3, ω4) and (α3, α4) (Norton §6.7, §7.3).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from jointplay.errors import AssemblyError
from jointplay.model.templates import FourBarGeometry

FloatArray = NDArray[np.float64]


def describe(geometry: FourBarGeometry) -> str:
    g = geometry
    return (
        f"crank {g.crank * 1e3:g} mm, coupler {g.coupler * 1e3:g} mm, "
        f"rocker {g.rocker * 1e3:g} mm, ground {g.ground * 1e3:g} mm"
    )


@dataclass(frozen=True)
class GrashofInfo:
    """Grashof classification of a four-bar.

    Attributes:
        kind: ``"crank-rocker"``, ``"double-crank"``, ``"double-rocker"``, ``"rocker-crank"``
            (Grashof, the output turns fully and the input rocks), ``"change-point"``
            (s + l = p + q) or ``"triple-rocker"`` (non-Grashof).
        grashof: s + l <= p + q (some link can turn fully relative to the others).
        crank_rotates: the input (crank) can turn through 360°.
        margin: (p + q) − (s + l), m; positive for a Grashof linkage.
    """

    kind: str
    grashof: bool
    crank_rotates: bool
    margin: float


def grashof(geometry: FourBarGeometry, *, tolerance: float = 1e-12) -> GrashofInfo:
    """Classify the linkage with Grashof's criterion s + l vs p + q (Norton §2.12)."""
    lengths = geometry.lengths
    ordered = sorted(lengths.values())
    s, p, q, l = ordered
    margin = (p + q) - (s + l)
    shortest = min(lengths, key=lambda name: lengths[name])
    if abs(margin) <= tolerance * max(ordered):
        kind = "change-point"
    elif margin < 0:
        kind = "triple-rocker"
    else:
        kind = {
            "crank": "crank-rocker",
            "ground": "double-crank",
            "coupler": "double-rocker",
            "rocker": "rocker-crank",
        }[shortest]
    crank_rotates = margin >= -tolerance * max(ordered) and shortest in ("crank", "ground")
    return GrashofInfo(kind=kind, grashof=margin >= 0, crank_rotates=crank_rotates, margin=margin)


def infeasible_crank_ranges(geometry: FourBarGeometry) -> list[tuple[float, float]]:
    """Crank-angle intervals (rad, within [0, 2π]) in which the linkage cannot be assembled.

    Assembly needs |b − c| <= f <= b + c with f² = a² + d² − 2ad·cos θ2.
    """
    a, b, c, d = geometry.crank, geometry.coupler, geometry.rocker, geometry.ground
    ranges: list[tuple[float, float]] = []
    too_long = (a * a + d * d - (b + c) ** 2) / (2 * a * d)  # need cos θ2 >= too_long
    too_short = (a * a + d * d - (b - c) ** 2) / (2 * a * d)  # need cos θ2 <= too_short
    if too_long > 1 or too_short < -1 or too_long > too_short:
        return [(0.0, 2 * math.pi)]
    if too_long > -1:
        start = math.acos(too_long)
        ranges.append((start, 2 * math.pi - start))
    if too_short < 1:
        end = math.acos(too_short)
        ranges.append((0.0, end))
        ranges.append((2 * math.pi - end, 2 * math.pi))
    return sorted(r for r in ranges if r[1] - r[0] > 1e-12)


def check_full_rotation(geometry: FourBarGeometry) -> None:
    """Raise :class:`AssemblyError` unless the crank can turn through a full revolution."""
    bad = infeasible_crank_ranges(geometry)
    if bad:
        info = grashof(geometry)
        spans = ", ".join(f"{math.degrees(lo):.1f}°–{math.degrees(hi):.1f}°" for lo, hi in bad)
        raise AssemblyError(
            f"four-bar with {describe(geometry)} ({info.kind}) cannot be assembled for crank "
            f"angles {spans}: the crank cannot turn fully. For a crank-rocker the crank must be "
            "the shortest link and shortest + longest <= sum of the other two (Grashof)."
        )


def positions(
    geometry: FourBarGeometry, theta2: ArrayLike, branch: int = 1
) -> tuple[FloatArray, FloatArray]:
    """Coupler and rocker angles θ3, θ4 (rad) for crank angles ``theta2`` (rad).

    Raises:
        AssemblyError: at some crank angle the loop cannot close; the message names the
            lengths and the failing crank angles.
    """
    a, b, c, d = geometry.crank, geometry.coupler, geometry.rocker, geometry.ground
    theta2 = np.asarray(theta2, dtype=float)
    ax, ay = a * np.cos(theta2), a * np.sin(theta2)
    vx, vy = d - ax, -ay
    f = np.hypot(vx, vy)
    cos_beta = (b * b + f * f - c * c) / (2.0 * b * f)
    bad = ~(np.abs(cos_beta) <= 1.0 + 1e-12)
    if np.any(bad):
        angles = np.degrees(np.atleast_1d(theta2)[np.atleast_1d(bad)]) % 360.0
        raise AssemblyError(
            f"four-bar with {describe(geometry)} cannot be assembled at crank angle(s) "
            f"{_angle_list(angles)}; check the lengths (|coupler − rocker| <= |O4 − A| <= "
            "coupler + rocker must hold)"
        )
    beta = np.arccos(np.clip(cos_beta, -1.0, 1.0))
    theta3 = np.arctan2(vy, vx) + branch * beta
    bx, by = ax + b * np.cos(theta3), ay + b * np.sin(theta3)
    theta4 = np.arctan2(by, bx - d)
    return _wrap(theta3), theta4


def velocities(
    geometry: FourBarGeometry,
    theta2: ArrayLike,
    theta3: ArrayLike,
    theta4: ArrayLike,
    omega2: ArrayLike,
) -> tuple[FloatArray, FloatArray]:
    """ω3, ω4 (rad/s) from a·ω2·e⊥(θ2) + b·ω3·e⊥(θ3) − c·ω4·e⊥(θ4) = 0."""
    a, b, c = geometry.crank, geometry.coupler, geometry.rocker
    t2, t3, t4 = (np.asarray(x, dtype=float) for x in (theta2, theta3, theta4))
    w2 = np.asarray(omega2, dtype=float)
    rhs_x, rhs_y = a * w2 * np.sin(t2), -a * w2 * np.cos(t2)
    return _solve_columns(b, t3, c, t4, rhs_x, rhs_y)


def accelerations(
    geometry: FourBarGeometry,
    theta2: ArrayLike,
    theta3: ArrayLike,
    theta4: ArrayLike,
    omega2: ArrayLike,
    omega3: ArrayLike,
    omega4: ArrayLike,
    alpha2: ArrayLike = 0.0,
) -> tuple[FloatArray, FloatArray]:
    """α3, α4 (rad/s²) from the second derivative of the loop equation."""
    a, b, c = geometry.crank, geometry.coupler, geometry.rocker
    t2, t3, t4, w2, w3, w4, al2 = (
        np.asarray(x, dtype=float) for x in (theta2, theta3, theta4, omega2, omega3, omega4, alpha2)
    )
    # −a α2 e⊥(θ2) + a ω2² e(θ2) + b ω3² e(θ3) − c ω4² e(θ4)
    rhs_x = (
        a * al2 * np.sin(t2)
        + a * w2**2 * np.cos(t2)
        + b * w3**2 * np.cos(t3)
        - c * w4**2 * np.cos(t4)
    )
    rhs_y = (
        -a * al2 * np.cos(t2)
        + a * w2**2 * np.sin(t2)
        + b * w3**2 * np.sin(t3)
        - c * w4**2 * np.sin(t4)
    )
    return _solve_columns(b, t3, c, t4, rhs_x, rhs_y)


def _solve_columns(
    b: float, t3: FloatArray, c: float, t4: FloatArray, rhs_x: FloatArray, rhs_y: FloatArray
) -> tuple[FloatArray, FloatArray]:
    # Columns: b·e⊥(θ3) = b(−sin θ3, cos θ3) and −c·e⊥(θ4) = c(sin θ4, −cos θ4); Cramer's rule.
    c1x, c1y = -b * np.sin(t3), b * np.cos(t3)
    c2x, c2y = c * np.sin(t4), -c * np.cos(t4)
    det = c1x * c2y - c1y * c2x  # = −b c sin(θ4 − θ3)
    x1 = (rhs_x * c2y - rhs_y * c2x) / det
    x2 = (c1x * rhs_y - c1y * rhs_x) / det
    return x1, x2


def transmission_angle(geometry: FourBarGeometry, theta2: ArrayLike) -> FloatArray:
    """Transmission angle μ ∈ [0, π] between coupler and rocker: cos μ = (b² + c² − f²)/(2bc)."""
    a, b, c, d = geometry.crank, geometry.coupler, geometry.rocker, geometry.ground
    f2 = a * a + d * d - 2 * a * d * np.cos(np.asarray(theta2, dtype=float))
    return np.arccos(np.clip((b * b + c * c - f2) / (2 * b * c), -1.0, 1.0))


#: The usual design guideline for the transmission angle μ: keep it within 40°–140°, i.e. its
#: deviation from 90° below 50°, for smooth running and good force transmission (R. L.
#: Norton, *Design of Machinery*, 5th ed., McGraw-Hill 2012, §3.3 "Limiting Conditions":
#: "keep the minimum transmission angle above about 40 degrees"; the extremes of μ of a
#: four-bar lie where the crank is collinear with the ground link, Norton §4.10). Below it
#: the coupler pushes the output link mostly along the link, not across it: forces in the
#: joints grow and the motion becomes sensitive to clearance and friction.
MIN_TRANSMISSION_ANGLE_DEG = 40.0


def transmission_angle_range(geometry: FourBarGeometry) -> tuple[float, float]:
    """Smallest and largest transmission angle μ over a full crank turn, rad (exact).

    μ grows with the diagonal f = |O4 − A| (cos μ = (b² + c² − f²)/(2bc)), and f runs from
    |d − a| (crank along the ground line, θ2 = 0) to d + a (θ2 = π): the extremes are μ at
    θ2 = 0 and θ2 = π, no grid needed.
    """
    ends = transmission_angle(geometry, np.array([0.0, math.pi]))
    return float(ends.min()), float(ends.max())


def transmission_angle_deviation(geometry: FourBarGeometry) -> float:
    """The worst transmission angle of a crank turn, rad: min over θ2 of min(μ, π − μ)
    (the angle the guideline :data:`MIN_TRANSMISSION_ANGLE_DEG` bounds from below)."""
    low, high = transmission_angle_range(geometry)
    return min(low, math.pi - high)


@dataclass(frozen=True)
class LimitPosition:
    """A rocker limit position (crank and coupler collinear): angles in rad."""

    name: str
    crank_angle: float
    rocker_angle: float


def rocker_limit_positions(
    geometry: FourBarGeometry, branch: int = 1
) -> tuple[LimitPosition, LimitPosition]:
    """The two limit (toggle) positions of the rocker of a crank-rocker.

    The rocker reverses where crank and coupler are collinear: |O2B| = b + a (extended) or
    b − a (folded). The crank is also at a *dead centre* for motion driven from the rocker
    there.
    """
    check_full_rotation(geometry)
    a, b, c, d = geometry.crank, geometry.coupler, geometry.rocker, geometry.ground
    found = []
    for name, reach, offset in (("extended", b + a, 0.0), ("folded", b - a, math.pi)):
        cos_g = (d * d + reach * reach - c * c) / (2 * d * reach)
        gamma = math.acos(max(-1.0, min(1.0, cos_g)))
        best: tuple[float, float, float] | None = None
        for sign in (1.0, -1.0):
            theta2 = (sign * gamma + offset) % (2 * math.pi)
            t3, t4 = positions(geometry, np.array([theta2]), branch)
            bx = a * math.cos(theta2) + b * math.cos(t3[0])
            by = a * math.sin(theta2) + b * math.sin(t3[0])
            error = abs(math.hypot(bx, by) - reach)
            if best is None or error < best[0]:
                best = (error, theta2, float(t4[0]))
        assert best is not None
        found.append(LimitPosition(name, best[1], best[2]))
    return found[0], found[1]


def _wrap(angle: FloatArray) -> FloatArray:
    return np.arctan2(np.sin(angle), np.cos(angle))


def _angle_list(degrees: FloatArray, limit: int = 6) -> str:
    shown = ", ".join(f"{v:.1f}°" for v in degrees[:limit])
    more = f" and {len(degrees) - limit} more" if len(degrees) > limit else ""
    return shown + more
