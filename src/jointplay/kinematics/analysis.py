"""Kinematics of a mechanism over a crank cycle, as a frozen result.

:func:`analyse` uses the closed form of the mechanism's template when it has one (four-bar:
:mod:`~jointplay.kinematics.fourbar`, slider-crank: :mod:`~jointplay.kinematics.slidercrank`)
and the general Newton–Raphson solver (:mod:`~jointplay.kinematics.solver`) otherwise, or when
asked to. Both produce the same state arrays, so everything downstream (points, inverse
dynamics, reports) is method-independent.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError
from jointplay.kinematics import fourbar, slidercrank
from jointplay.kinematics import solver as gs
from jointplay.model.flat import FlatModel, flatten
from jointplay.model.mechanism import Mechanism, PrismaticJoint
from jointplay.model.templates import FourBarGeometry, SliderCrankGeometry, TemplateSpec

FloatArray = NDArray[np.float64]
Method = Literal["auto", "closed-form", "general"]


@dataclass(frozen=True)
class KinematicsResult:
    """Positions, velocities and accelerations of every link at each crank angle.

    Attributes:
        mechanism: the analysed mechanism.
        flat: its flat model (all joints ideal).
        crank_angle: (N,) crank angles, rad, counter-clockwise from the ground line.
        q, qd, qdd: (N, 3 nb) centre-of-mass x, y (m) and link angle φ (rad) of each moving
            link, with their first and second time derivatives.
        method: ``"closed-form"`` or ``"general"``.
    """

    mechanism: Mechanism
    flat: FlatModel
    crank_angle: FloatArray
    q: FloatArray
    qd: FloatArray
    qdd: FloatArray
    method: str

    def _index(self, link: str) -> int:
        return self.flat.body_index(link) if link in self.flat.link_names else self._missing(link)

    def _missing(self, link: str) -> int:
        raise ConfigError(f"no moving link {link!r}; links: {list(self.flat.link_names)}")

    def angle(self, link: str) -> FloatArray:
        """Link angle, rad, wrapped to (−π, π]."""
        phi = self.q[:, 3 * self._index(link) + 2]
        return np.arctan2(np.sin(phi), np.cos(phi))

    def omega(self, link: str) -> FloatArray:
        """Angular velocity, rad/s, counter-clockwise positive."""
        return self.qd[:, 3 * self._index(link) + 2]

    def alpha(self, link: str) -> FloatArray:
        """Angular acceleration, rad/s²."""
        return self.qdd[:, 3 * self._index(link) + 2]

    def point(
        self, link: str, point: str | tuple[float, float]
    ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Position, velocity and acceleration (each (N, 2), SI) of a point on ``link``.

        ``point`` is the name of one of the link's points or local coordinates (m) in the
        link frame — any point, e.g. for coupler curves.
        """
        k = self._index(link)
        body = self.mechanism.link(link)
        local = np.array(body.point(point) if isinstance(point, str) else point, dtype=float)
        s = local - np.asarray(body.com)
        phi = self.q[:, 3 * k + 2]
        c, sn = np.cos(phi), np.sin(phi)
        rs = np.column_stack([c * s[0] - sn * s[1], sn * s[0] + c * s[1]])
        perp = np.column_stack([-rs[:, 1], rs[:, 0]])
        w = self.qd[:, 3 * k + 2][:, None]
        al = self.qdd[:, 3 * k + 2][:, None]
        pos = self.q[:, 3 * k : 3 * k + 2] + rs
        vel = self.qd[:, 3 * k : 3 * k + 2] + w * perp
        acc = self.qdd[:, 3 * k : 3 * k + 2] + al * perp - w**2 * rs
        return pos, vel, acc


def cycle_angles(mechanism: Mechanism, step_deg: float = 1.0) -> FloatArray:
    """Crank angles of one revolution in the driving direction from the start angle, inclusive."""
    if not 0 < step_deg <= 90:
        raise ConfigError(f"angle step must be in (0, 90] degrees, got {step_deg}")
    n = round(360.0 / step_deg)
    if not np.isclose(n * step_deg, 360.0):
        raise ConfigError(f"angle step {step_deg}° must divide 360°")
    driver = mechanism.driver
    return driver.start_angle + driver.direction * np.radians(np.arange(n + 1) * step_deg)


def analyse(
    mechanism: Mechanism,
    crank_angles: FloatArray | None = None,
    *,
    method: Method = "auto",
    q_start: FloatArray | None = None,
) -> KinematicsResult:
    """Kinematics at ``crank_angles`` (rad; default one revolution in 1° steps).

    Args:
        method: ``"closed-form"`` (templates only), ``"general"`` (Newton–Raphson) or
            ``"auto"`` (closed form when available).
        q_start: initial guess for the general solver at the first angle (selects the branch);
            by default the closed form (templates) or the mechanism's ``initial_angles``.
    """
    angles = (
        cycle_angles(mechanism) if crank_angles is None else np.asarray(crank_angles, dtype=float)
    )
    flat = flatten(mechanism)
    spec = mechanism.template if isinstance(mechanism.template, TemplateSpec) else None
    if method == "closed-form" and spec is None:
        raise ConfigError(
            f"mechanism {mechanism.name!r} has no template, so no closed form; use method='general'"
        )
    if method not in ("auto", "closed-form", "general"):
        raise ConfigError(f"unknown kinematics method {method!r}; use auto, closed-form or general")
    check_mobility(mechanism)
    if spec is not None and method != "general":
        q, qd, qdd = _closed_form(mechanism, flat, spec, angles)
        return KinematicsResult(mechanism, flat, angles, q, qd, qdd, "closed-form")
    if q_start is None:
        if spec is not None:
            q_start = _closed_form(mechanism, flat, spec, angles[:1])[0][0]
        else:
            hints = {flat.body_index(k): v for k, v in mechanism.initial_angles.items()}
            hints[flat.body_index(mechanism.driver.link)] = float(angles[0])
            q_start = gs.guess_from_angles(flat, hints)
    q, qd, qdd = gs.solve_cycle(flat, angles, q_start)
    return KinematicsResult(mechanism, flat, angles, q, qd, qdd, "general")


def check_mobility(mechanism: Mechanism) -> None:
    """Raise :class:`~jointplay.errors.AssemblyError` if a template's crank cannot turn fully."""
    spec = mechanism.template
    if isinstance(spec, TemplateSpec):
        if isinstance(spec.geometry, FourBarGeometry):
            fourbar.check_full_rotation(spec.geometry)
        else:
            slidercrank.check_full_rotation(spec.geometry)


def _closed_form(
    mechanism: Mechanism, flat: FlatModel, spec: TemplateSpec, angles: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    omega2 = mechanism.driver.angular_velocity
    n = len(angles)
    phi = np.zeros((n, 3))
    omega = np.zeros((n, 3))
    alpha = np.zeros((n, 3))
    phi[:, 0], omega[:, 0] = angles, omega2
    geometry = spec.geometry
    if isinstance(geometry, FourBarGeometry):
        t3, t4 = fourbar.positions(geometry, angles, mechanism.branch)
        w3, w4 = fourbar.velocities(geometry, angles, t3, t4, omega2)
        a3, a4 = fourbar.accelerations(geometry, angles, t3, t4, omega2, w3, w4)
        phi[:, 1], phi[:, 2] = t3, t4
        omega[:, 1], omega[:, 2] = w3, w4
        alpha[:, 1], alpha[:, 2] = a3, a4
    else:
        assert isinstance(geometry, SliderCrankGeometry)
        t3, _ = slidercrank.positions(geometry, angles, mechanism.branch)
        w3, _ = slidercrank.velocities(geometry, angles, t3, omega2)
        a3, _ = slidercrank.accelerations(geometry, angles, t3, omega2, w3)
        phi[:, 1], omega[:, 1], alpha[:, 1] = t3, w3, a3
        slider_joint = next(j for j in mechanism.joints if isinstance(j, PrismaticJoint))
        phi[:, 2] = slider_joint.axis_angle + slider_joint.relative_angle
    return gs.state_from_angles(flat, phi, omega, alpha)
