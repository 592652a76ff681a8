"""Closed-form kinematics of the (offset) slider-crank.

Conventions as in :mod:`jointplay.model.templates`: crank r (link 2) about O2 at the origin,
connecting rod l (link 3), slider pin B on the line y = e (offset). From the loop
r·e(θ2) + l·e(θ3) = (x_B, e):  sin θ3 = (e − r sin θ2)/l and
x_B = r cos θ2 + σ·sqrt(l² − (e − r sin θ2)²) with σ = ±1 the assembly branch
(Norton, *Design of Machinery*, §4.6 and §6.7, §7.3).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray

from jointplay.errors import AssemblyError
from jointplay.model.templates import SliderCrankGeometry

FloatArray = NDArray[np.float64]


def describe(geometry: SliderCrankGeometry) -> str:
    return (
        f"crank {geometry.crank * 1e3:g} mm, rod {geometry.rod * 1e3:g} mm, "
        f"offset {geometry.offset * 1e3:g} mm"
    )


def check_full_rotation(geometry: SliderCrankGeometry) -> None:
    """The crank turns fully iff r + |e| < l (the rod can always reach the slider line)."""
    r, l, e = geometry.crank, geometry.rod, geometry.offset
    if r + abs(e) >= l:
        limit = math.asin(max(-1.0, min(1.0, (e + l) / r))) if r > 0 else 0.0
        raise AssemblyError(
            f"slider-crank with {describe(geometry)} cannot turn fully: crank + |offset| must be "
            f"less than the rod (fails near crank angle {math.degrees(limit):.1f}°)"
        )


def positions(
    geometry: SliderCrankGeometry, theta2: ArrayLike, branch: int = 1
) -> tuple[FloatArray, FloatArray]:
    """Rod angle θ3 (rad) and slider position x_B (m) for crank angles θ2 (rad)."""
    r, l, e = geometry.crank, geometry.rod, geometry.offset
    theta2 = np.asarray(theta2, dtype=float)
    height = e - r * np.sin(theta2)
    reach2 = l * l - height * height
    if np.any(reach2 < -1e-15):
        bad = np.degrees(np.atleast_1d(theta2)[np.atleast_1d(reach2 < 0)]) % 360
        raise AssemblyError(
            f"slider-crank with {describe(geometry)} cannot be assembled at crank angle(s) "
            + ", ".join(f"{v:.1f}°" for v in bad[:6])
        )
    run = branch * np.sqrt(np.maximum(reach2, 0.0))
    x_b = r * np.cos(theta2) + run
    theta3 = np.arctan2(height, run)
    return theta3, x_b


def velocities(
    geometry: SliderCrankGeometry, theta2: ArrayLike, theta3: ArrayLike, omega2: ArrayLike
) -> tuple[FloatArray, FloatArray]:
    """ω3 (rad/s) and slider velocity (m/s)."""
    r, l = geometry.crank, geometry.rod
    t2, t3, w2 = (np.asarray(x, dtype=float) for x in (theta2, theta3, omega2))
    omega3 = -r * w2 * np.cos(t2) / (l * np.cos(t3))
    v_b = -r * w2 * np.sin(t2) - l * omega3 * np.sin(t3)
    return omega3, v_b


def accelerations(
    geometry: SliderCrankGeometry,
    theta2: ArrayLike,
    theta3: ArrayLike,
    omega2: ArrayLike,
    omega3: ArrayLike,
    alpha2: ArrayLike = 0.0,
) -> tuple[FloatArray, FloatArray]:
    """α3 (rad/s²) and slider acceleration (m/s²)."""
    r, l = geometry.crank, geometry.rod
    t2, t3, w2, w3, a2 = (
        np.asarray(x, dtype=float) for x in (theta2, theta3, omega2, omega3, alpha2)
    )
    alpha3 = (r * w2**2 * np.sin(t2) - r * a2 * np.cos(t2) + l * w3**2 * np.sin(t3)) / (
        l * np.cos(t3)
    )
    a_b = (
        -r * a2 * np.sin(t2)
        - r * w2**2 * np.cos(t2)
        - l * alpha3 * np.sin(t3)
        - l * w3**2 * np.cos(t3)
    )
    return alpha3, a_b
