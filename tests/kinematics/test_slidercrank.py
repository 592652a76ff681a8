"""Slider-crank kinematics against the textbook closed form of the piston motion."""

from __future__ import annotations

import numpy as np
import pytest

from jointplay.errors import AssemblyError
from jointplay.kinematics.analysis import analyse
from jointplay.model.templates import LinkBody, SliderCrankGeometry, slider_crank


def textbook_piston(r: float, l: float, e: float, theta: np.ndarray, w: float):
    """x = r cos θ + sqrt(l² − (r sin θ − e)²) and its exact time derivatives (constant ω)."""
    s = r * np.sin(theta) - e
    root = np.sqrt(l * l - s * s)
    ds = r * np.cos(theta)
    x = r * np.cos(theta) + root
    dx = -r * np.sin(theta) - s * ds / root
    d2x = -r * np.cos(theta) - (ds * ds - s * r * np.sin(theta)) / root - (s * ds) ** 2 / root**3
    return x, dx * w, d2x * w * w


@pytest.mark.parametrize("offset", [0.0, 0.02, -0.015])
@pytest.mark.parametrize("method", ["closed-form", "general"])
def test_piston_motion_matches_textbook(offset: float, method: str) -> None:
    r, l, w = 0.05, 0.12, 523.6
    mechanism = slider_crank(
        SliderCrankGeometry(r, l, offset),
        speed=w,
        bodies={"crank": LinkBody(0.3), "rod": LinkBody(0.21), "slider": LinkBody(0.14)},
    )
    theta = np.radians(np.arange(0, 361, 5.0))
    res = analyse(mechanism, theta, method=method)  # type: ignore[arg-type]
    pos, vel, acc = res.point("slider", "B")
    x, v, a = textbook_piston(r, l, offset, theta, w)
    np.testing.assert_allclose(pos[:, 0], x, rtol=0, atol=1e-12)
    np.testing.assert_allclose(pos[:, 1], offset, atol=1e-12)
    np.testing.assert_allclose(vel[:, 0], v, rtol=1e-10, atol=1e-9)
    np.testing.assert_allclose(acc[:, 0], a, rtol=1e-9, atol=1e-6)
    np.testing.assert_allclose(vel[:, 1], 0, atol=1e-9)


def test_rod_too_short_is_rejected() -> None:
    mechanism = slider_crank(
        SliderCrankGeometry(0.1, 0.12, 0.05),
        speed=10.0,
        bodies={"crank": LinkBody(0.3), "rod": LinkBody(0.21), "slider": LinkBody(0.14)},
    )
    with pytest.raises(AssemblyError, match="cannot turn fully"):
        analyse(mechanism)
