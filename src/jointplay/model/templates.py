"""Four-bar and slider-crank templates built on the general :class:`Mechanism`.

A template is a small frozen geometry object plus a function that turns it into links and
joints. The mechanism remembers its template, so the closed-form kinematics can be used and
tolerance studies can rebuild it with other lengths (:func:`with_lengths`).

Conventions (four-bar): ground pivots O2 at the origin and O4 at (ground, 0), so the ground
line O2→O4 is the global x-axis; link numbers 2 crank, 3 coupler, 4 rocker; joints O2
(ground–crank), A (crank–coupler), B (coupler–rocker), O4 (rocker–ground). Branch +1 puts B
on the left of the directed line A→O4 — for a crank shorter than the ground at crank angle 0,
that is B above the ground line.

Conventions (slider-crank): crank pivot O2 at the origin, the slider's pin B moves on the line
y = offset, parallel to the x-axis; link numbers 2 crank, 3 connecting rod, 4 slider; joints O2,
A (crank–rod), B (rod–slider pin), S (slider–guide). Branch +1 puts the slider at x > x_A.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, replace
from typing import Literal

from jointplay.errors import ConfigError
from jointplay.model.mechanism import (
    GROUND,
    STEEL,
    Driver,
    Ground,
    JointFit,
    LengthTolerance,
    Link,
    Material,
    Mechanism,
    Point,
    PrismaticJoint,
    RevoluteJoint,
)


@dataclass(frozen=True)
class LinkBody:
    """Mass properties of a template bar: mass (kg), in-plane width and thickness (m).

    ``inertia`` (kg·m², about the centre of mass) overrides the bar formula ``m (L² + w²)/12``.
    """

    mass: float | None = None
    width: float = 0.022
    thickness: float | None = 0.010
    inertia: float | None = None


@dataclass(frozen=True)
class FourBarGeometry:
    """Link lengths of a four-bar, m."""

    crank: float
    coupler: float
    rocker: float
    ground: float
    kind: Literal["four-bar"] = "four-bar"

    def __post_init__(self) -> None:
        for name in self.length_names:
            value = getattr(self, name)
            if not value > 0:
                raise ConfigError(f"four-bar: {name} length must be > 0, got {value}")

    length_names = ("crank", "coupler", "rocker", "ground")

    @property
    def lengths(self) -> dict[str, float]:
        return {name: getattr(self, name) for name in self.length_names}


@dataclass(frozen=True)
class SliderCrankGeometry:
    """Crank radius, connecting-rod length and slider offset, m (offset may be negative)."""

    crank: float
    rod: float
    offset: float = 0.0
    kind: Literal["slider-crank"] = "slider-crank"

    def __post_init__(self) -> None:
        for name in ("crank", "rod"):
            if not getattr(self, name) > 0:
                raise ConfigError(
                    f"slider-crank: {name} length must be > 0, got {getattr(self, name)}"
                )

    length_names = ("crank", "rod", "offset")

    @property
    def lengths(self) -> dict[str, float]:
        return {name: getattr(self, name) for name in self.length_names}


Geometry = FourBarGeometry | SliderCrankGeometry


@dataclass(frozen=True)
class TemplateSpec:
    """Everything a template needs besides its geometry (kept so the mechanism can be rebuilt)."""

    geometry: Geometry
    bodies: Mapping[str, LinkBody]
    material: Material
    coupler_points: Mapping[str, Point]
    fits: Mapping[str, JointFit]


def four_bar(
    geometry: FourBarGeometry,
    *,
    speed: float,
    bodies: Mapping[str, LinkBody] | None = None,
    material: Material = STEEL,
    direction: Literal[1, -1] = 1,
    start_angle: float = 0.0,
    gravity: Point = (0.0, 0.0),
    branch: Literal[1, -1] = 1,
    coupler_points: Mapping[str, Point] | None = None,
    fits: Mapping[str, JointFit] | None = None,
    tolerances: tuple[LengthTolerance, ...] = (),
    name: str = "four-bar",
) -> Mechanism:
    """Build a four-bar (see the module docstring for frames, numbering and branch).

    Args:
        geometry: link lengths, m.
        speed: crank speed, rad/s.
        bodies: mass properties per link (``"crank"``, ``"coupler"``, ``"rocker"``); a link
            without an entry gets its mass from ``material`` and a 22 × 10 mm section.
        coupler_points: extra named points on the coupler, in its frame (origin A, x-axis
            towards B), m — e.g. for coupler curves.
        fits: joint manufacturing data by joint name (``O2``, ``A``, ``B``, ``O4``).
    """
    spec = TemplateSpec(
        geometry=geometry,
        bodies=dict(bodies or {}),
        material=material,
        coupler_points=dict(coupler_points or {}),
        fits=dict(fits or {}),
    )
    g = geometry
    links = (
        _bar(spec, "crank", g.crank, "O2", "A"),
        _bar(spec, "coupler", g.coupler, "A", "B", extra=spec.coupler_points),
        _bar(spec, "rocker", g.rocker, "O4", "B"),
    )
    joints = (
        RevoluteJoint("O2", GROUND, "O2", "crank", "O2", fit=spec.fits.get("O2")),
        RevoluteJoint("A", "crank", "A", "coupler", "A", fit=spec.fits.get("A")),
        RevoluteJoint("B", "coupler", "B", "rocker", "B", fit=spec.fits.get("B")),
        RevoluteJoint("O4", GROUND, "O4", "rocker", "O4", fit=spec.fits.get("O4")),
    )
    _check_fit_names(spec.fits, joints)
    return Mechanism(
        name=name,
        ground=Ground({"O2": (0.0, 0.0), "O4": (g.ground, 0.0)}),
        links=links,
        joints=joints,
        driver=Driver("crank", "O2", speed, direction, start_angle),
        gravity=gravity,
        template=spec,
        branch=branch,
        materials={material.name: material},
        tolerances=tolerances,
    )


def slider_crank(
    geometry: SliderCrankGeometry,
    *,
    speed: float,
    bodies: Mapping[str, LinkBody] | None = None,
    material: Material = STEEL,
    direction: Literal[1, -1] = 1,
    start_angle: float = 0.0,
    gravity: Point = (0.0, 0.0),
    branch: Literal[1, -1] = 1,
    coupler_points: Mapping[str, Point] | None = None,
    fits: Mapping[str, JointFit] | None = None,
    tolerances: tuple[LengthTolerance, ...] = (),
    name: str = "slider-crank",
) -> Mechanism:
    """Build an (offset) slider-crank (see the module docstring for frames and numbering).

    ``bodies`` may hold ``"crank"``, ``"rod"`` and ``"slider"``; the slider needs a mass (its
    inertia defaults to that of a 0.05 m square block) — give it in ``bodies["slider"]``.
    ``coupler_points`` are extra points on the connecting rod.
    """
    spec = TemplateSpec(
        geometry=geometry,
        bodies=dict(bodies or {}),
        material=material,
        coupler_points=dict(coupler_points or {}),
        fits=dict(fits or {}),
    )
    g = geometry
    slider_body = spec.bodies.get("slider", LinkBody(mass=None))
    if slider_body.mass is None:
        raise ConfigError(
            "slider-crank: give the slider's mass (bodies['slider'] = LinkBody(mass=...))"
        )
    side = slider_body.width
    slider = Link(
        name="slider",
        points={"B": (0.0, 0.0)},
        mass=slider_body.mass,
        com=(0.0, 0.0),
        inertia=slider_body.inertia or slider_body.mass * 2 * side**2 / 12.0,
        width=side,
        thickness=slider_body.thickness,
        material=material.name,
    )
    links = (
        _bar(spec, "crank", g.crank, "O2", "A"),
        _bar(spec, "rod", g.rod, "A", "B", extra=spec.coupler_points),
        slider,
    )
    joints: tuple[RevoluteJoint | PrismaticJoint, ...] = (
        RevoluteJoint("O2", GROUND, "O2", "crank", "O2", fit=spec.fits.get("O2")),
        RevoluteJoint("A", "crank", "A", "rod", "A", fit=spec.fits.get("A")),
        RevoluteJoint("B", "rod", "B", "slider", "B", fit=spec.fits.get("B")),
        PrismaticJoint("S", GROUND, "S0", "slider", "B", axis_angle=0.0),
    )
    _check_fit_names(spec.fits, joints)
    return Mechanism(
        name=name,
        ground=Ground({"O2": (0.0, 0.0), "S0": (0.0, g.offset)}),
        links=links,
        joints=joints,
        driver=Driver("crank", "O2", speed, direction, start_angle),
        gravity=gravity,
        template=spec,
        branch=branch,
        materials={material.name: material},
        tolerances=tolerances,
    )


_BUILDERS: dict[str, Callable[..., Mechanism]] = {
    "four-bar": four_bar,
    "slider-crank": slider_crank,
}


def with_lengths(mechanism: Mechanism, **lengths: float) -> Mechanism:
    """Rebuild a template mechanism with some lengths changed (m), keeping everything else.

    Masses stay as given (a ±1 mm change moves a bar's mass by well under 1 %); bar inertias
    follow the new length through ``m (L² + w²)/12`` unless they were given explicitly.
    """
    spec = template_of(mechanism)
    unknown = set(lengths) - set(spec.geometry.length_names)
    if unknown:
        raise ConfigError(
            f"{spec.geometry.kind}: unknown length(s) {sorted(unknown)}; "
            f"it has {list(spec.geometry.length_names)}"
        )
    geometry = replace(spec.geometry, **lengths)  # type: ignore[arg-type]
    return rebuild(mechanism, geometry=geometry)


def rebuild(mechanism: Mechanism, **changes: object) -> Mechanism:
    """Rebuild a template mechanism with fields of its :class:`TemplateSpec` replaced."""
    spec = replace(template_of(mechanism), **changes)  # type: ignore[arg-type]
    driver = mechanism.driver
    builder = _BUILDERS[spec.geometry.kind]
    rebuilt = builder(
        spec.geometry,
        speed=driver.speed,
        bodies=spec.bodies,
        material=spec.material,
        direction=driver.direction,
        start_angle=driver.start_angle,
        gravity=mechanism.gravity,
        branch=mechanism.branch,
        coupler_points=spec.coupler_points,
        fits=spec.fits,
        tolerances=mechanism.tolerances,
        name=mechanism.name,
    )
    return replace(  # the declared lubrication is the joints', not the geometry's
        rebuilt,
        lubrication=mechanism.lubrication,
        joint_lubrication=mechanism.joint_lubrication,
    )


def template_of(mechanism: Mechanism) -> TemplateSpec:
    """The mechanism's template, or a ConfigError if it was built without one."""
    if not isinstance(mechanism.template, TemplateSpec):
        raise ConfigError(
            f"Mechanism {mechanism.name!r} was not built from a template (four-bar, slider-crank)"
        )
    return mechanism.template


def _bar(
    spec: TemplateSpec,
    name: str,
    length: float,
    start: str,
    end: str,
    extra: Mapping[str, Point] | None = None,
) -> Link:
    body = spec.bodies.get(name, LinkBody())
    link = Link.bar(
        name,
        length,
        start=start,
        end=end,
        mass=body.mass,
        width=body.width,
        thickness=body.thickness,
        material=spec.material,
        extra_points=extra,
    )
    if body.inertia is not None:
        link = replace(link, inertia=body.inertia)
    return link


def _check_fit_names(fits: Mapping[str, JointFit], joints: tuple[object, ...]) -> None:
    names = {j.name for j in joints}  # type: ignore[attr-defined]
    unknown = set(fits) - names
    if unknown:
        raise ConfigError(
            f"fits given for unknown joint(s) {sorted(unknown)}; joints: {sorted(names)}"
        )


__all__ = [
    "FourBarGeometry",
    "LinkBody",
    "SliderCrankGeometry",
    "TemplateSpec",
    "four_bar",
    "rebuild",
    "slider_crank",
    "template_of",
    "with_lengths",
]
