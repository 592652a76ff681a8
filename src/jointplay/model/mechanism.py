"""What a planar mechanism is: rigid links, joints, the ground and a driver.

The description is general: any number of rigid links connected by revolute and prismatic
joints, one of them driven at constant speed. The four-bar and slider-crank templates
(:mod:`jointplay.model.templates`) build on it. All quantities are SI (m, kg, kg·m², rad, rad/s).

Link frames: each link has its own frame; its named points (joint centres, coupler points)
and its centre of mass are given in that frame. A link's *angle* is the angle of its frame's
x-axis, counter-clockwise from the global x-axis. The ground's frame is the global frame.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any, Literal

from jointplay.errors import ConfigError
from jointplay.model.lubricants import grade_viscosity, grade_words, parse_grade

Point = tuple[float, float]
GROUND = "ground"

#: Largest magnitude of the gravitational acceleration a mechanism takes, m/s²: about 100 g,
#: ten times a centrifuge test rig's 10 g; beyond it a value is a slip of the unit
#: ("9.81 km/s^2") or of the exponent, not a mechanism (Earth's: 9.80665 m/s²).
MAX_GRAVITY = 1000.0
#: Largest crank start angle either way, rad: two turns (±720°). Every crank position lies
#: within one turn; two leave room for writing it either way (-90° or 270°, 450°). Beyond,
#: it is a typo, and far beyond the angle's float loses the position (at 1e17 rad one step
#: of the float is 16 rad, more than two turns).
MAX_START_ANGLE = 4.0 * math.pi


def check_gravity(gravity: Point, field: str, given: object = None) -> Point:
    """``gravity`` (m/s², a vector) if its magnitude is at most :data:`MAX_GRAVITY`.

    Args:
        gravity: the vector, m/s².
        field: what the message names (``"--gravity"``, ``"mechanism.gravity"``).
        given: the value as written, shown in the message (default: the magnitude).

    Raises:
        ConfigError: one line: the bound, why, and the value.
    """
    magnitude = math.hypot(*gravity)
    if not magnitude <= MAX_GRAVITY:
        shown = repr(given) if given is not None else f"{magnitude:.6g} m/s²"
        raise ConfigError(
            f"{field} must be at most {MAX_GRAVITY:g} m/s² (about 100 g; Earth's is 9.81 "
            f"m/s²), got {shown}; check the unit and the exponent"
        )
    return gravity


def check_start_angle(angle: float, field: str, given: object = None) -> float:
    """``angle`` (rad) if finite and within ±:data:`MAX_START_ANGLE` (two turns).

    Raises:
        ConfigError: one line: the range, why, and the value.
    """
    if not (math.isfinite(angle) and abs(angle) <= MAX_START_ANGLE):
        shown = repr(given) if given is not None else f"{math.degrees(angle):.6g}°"
        raise ConfigError(
            f"{field} must lie within ±720° (two turns; every crank position is within one), "
            f"got {shown}; write it within one turn, e.g. '30 deg'"
        )
    return angle


class FrozenMap(dict[str, Any]):
    """A read-only dict: the mappings inside frozen model objects (picklable, unlike
    ``types.MappingProxyType``, so mechanisms can be sent to worker processes)."""

    def _readonly(self, *args: object, **kwargs: object) -> None:
        raise TypeError("this mapping belongs to a frozen model object and cannot be changed")

    __setitem__ = __delitem__ = clear = pop = popitem = setdefault = update = _readonly  # type: ignore[assignment]
    __ior__ = _readonly  # type: ignore[assignment]

    def __reduce__(self) -> tuple[type, tuple[dict[str, Any]]]:
        return (FrozenMap, (dict(self),))

    def __hash__(self) -> int:  # type: ignore[override]
        return hash(tuple(sorted(self.items())))


def _positive(owner: str, name: str, value: float, *, allow_zero: bool = False) -> None:
    ok = value >= 0.0 if allow_zero else value > 0.0
    if not (math.isfinite(value) and ok):
        bound = ">= 0" if allow_zero else "> 0"
        raise ConfigError(f"{owner}: {name} must be finite and {bound}, got {value!r}")


@dataclass(frozen=True)
class Material:
    """An isotropic linear-elastic material.

    Attributes:
        name: identifier, e.g. ``"steel"``.
        density: kg/m³.
        youngs_modulus: Young's modulus E in Pa.
        poisson_ratio: Poisson's ratio ν, in [0, 0.5).
        yield_strength: tensile yield strength Y in Pa (``None``: unknown).
        allowable_contact_pressure: largest Hertz contact pressure the designer accepts, Pa
            (``None``: the onset of yield, :data:`YIELD_ONSET_FACTOR` × Y; see
            :attr:`contact_pressure_limit`).
    """

    name: str
    density: float
    youngs_modulus: float
    poisson_ratio: float
    yield_strength: float | None = None
    allowable_contact_pressure: float | None = None

    def __post_init__(self) -> None:
        owner = f"Material {self.name!r}"
        _positive(owner, "density", self.density)
        _positive(owner, "youngs_modulus", self.youngs_modulus)
        if not 0.0 <= self.poisson_ratio < 0.5:
            raise ConfigError(
                f"{owner}: poisson_ratio must lie in [0, 0.5), got {self.poisson_ratio}"
            )
        if self.yield_strength is not None:
            _positive(owner, "yield_strength", self.yield_strength)
        if self.allowable_contact_pressure is not None:
            _positive(owner, "allowable_contact_pressure", self.allowable_contact_pressure)

    @property
    def contact_pressure_limit(self) -> float | None:
        """The allowable Hertz contact pressure p0, Pa: the given value, else the onset of
        yield under line contact, p0 = 1.79 Y (von Mises; Johnson, *Contact Mechanics*,
        1985, §4.2), else ``None``."""
        if self.allowable_contact_pressure is not None:
            return self.allowable_contact_pressure
        if self.yield_strength is not None:
            return YIELD_ONSET_FACTOR * self.yield_strength
        return None


#: Hertz line contact of elastic cylinders first yields (von Mises) below the surface when
#: the peak pressure reaches p0 = 1.79 Y (Johnson, *Contact Mechanics*, 1985, §4.2(b)).
YIELD_ONSET_FACTOR = 1.79

#: Steel as in the paper's Table 1 (ρ = 7801 kg/m³, ν = 0.29, E = 2.07e5 N/mm²). The paper
#: names no grade; the yield strength is the minimum of ASTM A36 structural steel, 250 MPa
#: (a conservative default: the allowable contact pressure is then 1.79 × 250 = 448 MPa;
#: hardened pins allow several times more; set ``yield_strength`` or
#: ``allowable_contact_pressure`` in the ``[material]`` table).
STEEL = Material(
    "steel", density=7801.0, youngs_modulus=207e9, poisson_ratio=0.29, yield_strength=250e6
)


@dataclass(frozen=True)
class Link:
    """A rigid moving link.

    Attributes:
        name: unique identifier.
        points: named points in the link frame, m (joint centres, coupler points).
        mass: kg.
        com: centre of mass in the link frame, m.
        inertia: moment of inertia about the centre of mass, perpendicular to the plane, kg·m².
        width: in-plane width of a bar, m (informational; used when the inertia was computed).
        thickness: out-of-plane thickness of a bar, m (informational).
        material: name of the link's material, if known.
    """

    name: str
    points: Mapping[str, Point]
    mass: float
    com: Point
    inertia: float
    width: float | None = None
    thickness: float | None = None
    material: str | None = None

    def __post_init__(self) -> None:
        owner = f"Link {self.name!r}"
        if not self.name or self.name == GROUND:
            raise ConfigError(f"{owner}: a moving link needs a name other than {GROUND!r}")
        _positive(owner, "mass", self.mass)
        _positive(owner, "inertia", self.inertia)
        if len(self.points) == 0:
            raise ConfigError(f"{owner}: needs at least one named point")
        object.__setattr__(self, "points", FrozenMap(_check_points(owner, self.points)))
        object.__setattr__(self, "com", _point(owner, "com", self.com))

    @classmethod
    def bar(
        cls,
        name: str,
        length: float,
        *,
        start: str,
        end: str,
        mass: float | None = None,
        width: float,
        thickness: float | None = None,
        material: Material | None = None,
        extra_points: Mapping[str, Point] | None = None,
    ) -> Link:
        """A straight bar of ``length`` from point ``start`` (frame origin) to ``end`` on the x-axis.

        The centre of mass is at mid-length and the centroidal inertia that of a rectangle,
        ``m (L² + w²) / 12`` with in-plane width ``w``. Without ``mass``, the mass is
        ``ρ L w t`` from the material and thickness.
        """
        _positive(f"Link {name!r}", "length", length)
        _positive(f"Link {name!r}", "width", width)
        if mass is None:
            if material is None or thickness is None:
                raise ConfigError(
                    f"Link {name!r}: give its mass, or a material and thickness to compute it"
                )
            mass = material.density * length * width * thickness
        points = {start: (0.0, 0.0), end: (length, 0.0), **(extra_points or {})}
        return cls(
            name=name,
            points=points,
            mass=mass,
            com=(length / 2.0, 0.0),
            inertia=mass * (length**2 + width**2) / 12.0,
            width=width,
            thickness=thickness,
            material=material.name if material else None,
        )

    def point(self, name: str) -> Point:
        try:
            return self.points[name]
        except KeyError:
            raise ConfigError(
                f"Link {self.name!r} has no point {name!r}; it has {sorted(self.points)}"
            ) from None


@dataclass(frozen=True)
class Ground:
    """The fixed frame: its named points are global coordinates, m."""

    points: Mapping[str, Point]

    def __post_init__(self) -> None:
        object.__setattr__(self, "points", FrozenMap(_check_points("ground", self.points)))

    name = GROUND

    def point(self, name: str) -> Point:
        try:
            return self.points[name]
        except KeyError:
            raise ConfigError(
                f"ground has no point {name!r}; it has {sorted(self.points)}"
            ) from None


@dataclass(frozen=True)
class JointFit:
    """Manufacturing data of a pin joint (used by the clearance and tolerance analyses).

    Attributes:
        diameter: nominal diameter, m.
        fit: ISO 286 fit designation, e.g. ``"H8/g7"``.
        pin_length: engaged length of the pin, m.
        pin_mass: mass of the pin, kg (enters the ECS load estimate, paper eq. 13).
        clearance: radial clearance to simulate, m (``None``: ideal joint).
    """

    diameter: float
    fit: str | None = None
    pin_length: float | None = None
    pin_mass: float | None = None
    clearance: float | None = None

    def __post_init__(self) -> None:
        _positive("JointFit", "diameter", self.diameter)
        if self.pin_length is not None:
            _positive("JointFit", "pin_length", self.pin_length)
        if self.pin_mass is not None:
            _positive("JointFit", "pin_mass", self.pin_mass)
        if self.clearance is not None:
            _positive("JointFit", "clearance", self.clearance, allow_zero=True)


#: The lubrication regimes a pin joint may be declared in (docs/contact.md, "Lubrication,
#: declared per joint"): dry steel on steel, an oil film, or a grease (whose film is its base
#: oil's).
REGIMES = ("dry", "oil", "grease")


@dataclass(frozen=True)
class Lubrication:
    """How a pin joint is lubricated: its regime and its lubricant's viscosity.

    Attributes:
        regime: ``"dry"``, ``"oil"`` or ``"grease"`` (:data:`REGIMES`).
        grade: the lubricant's ISO 3448 viscosity grade (``46`` for ISO VG 46), or ``None``;
            a grade sets :attr:`viscosity` to its value at 40 °C
            (:func:`jointplay.model.lubricants.grade_viscosity`).
        viscosity: the dynamic viscosity of the oil (of a grease's base oil) at the joint's
            working temperature, Pa·s (> 0); ``None`` for ``dry``. An ``oil`` declared
            without one takes the default lubricant's
            (:data:`jointplay.dynamics.setup.DEFAULT_VISCOSITY`); a grease needs its base
            oil's.
    """

    regime: str
    viscosity: float | None = None
    grade: int | None = None

    def __post_init__(self) -> None:
        if self.regime not in REGIMES:
            raise ConfigError(
                f"lubrication must be one of {', '.join(REGIMES)}, got {self.regime!r}"
            )
        if self.grade is not None:
            self._take_grade()
        if self.viscosity is None:
            if self.regime == "grease":
                raise ConfigError(
                    "lubrication 'grease' needs its base oil's viscosity, e.g. '0.15 Pa*s'"
                )
            return
        value = self.viscosity
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(f"the lubricant's viscosity must be a number in Pa*s, got {value!r}")
        if self.regime == "dry":
            raise ConfigError(
                "a dry joint has no lubricant: drop its viscosity, or declare it 'oil' or 'grease'"
            )
        if not (math.isfinite(value) and value > 0):
            raise ConfigError(
                f"the lubricant's viscosity must be > 0 Pa*s (a dry joint: 'dry'), got {value!r}"
            )
        object.__setattr__(self, "viscosity", float(value))

    def _take_grade(self) -> None:
        """An ISO VG ``grade`` (:mod:`jointplay.model.lubricants`) names the viscosity at
        40 °C: refuse it on a dry joint or beside another viscosity."""
        grade = parse_grade(self.grade)
        if self.regime == "dry":
            raise ConfigError(
                "a dry joint has no lubricant: drop its ISO VG grade, or declare it 'oil' or "
                "'grease'"
            )
        viscosity = grade_viscosity(grade)
        if self.viscosity is not None and self.viscosity != viscosity:
            raise ConfigError(
                f"give the lubricant's ISO VG grade or its viscosity, not both (ISO VG {grade} "
                f"is {viscosity:#.2g} Pa*s at 40 °C; got {self.viscosity!r} too)"
            )
        object.__setattr__(self, "grade", grade)
        object.__setattr__(self, "viscosity", viscosity)

    @property
    def lubricated(self) -> bool:
        """The joint runs in a film (oil or grease)."""
        return self.regime != "dry"

    def words(self) -> str:
        """The regime in words: ``dry``, ``oil 0.05 Pa*s``, ``grease (base oil 0.15 Pa*s)``,
        ``oil ISO VG 46 (0.040 Pa*s at 40 °C)``."""
        if self.regime == "dry":
            return "dry"
        if self.grade is not None:
            base = "grease, base oil" if self.regime == "grease" else "oil"
            return f"{base} {grade_words(self.grade)}"
        if self.regime == "grease":
            return f"grease (base oil {self.viscosity:g} Pa*s)"
        return "oil" if self.viscosity is None else f"oil {self.viscosity:g} Pa*s"


@dataclass(frozen=True)
class RevoluteJoint:
    """A pin joint: point ``point_a`` of ``link_a`` coincides with ``point_b`` of ``link_b``.

    With clearance, ``link_a`` carries the bearing (hole) and ``link_b`` the journal (pin).
    """

    name: str
    link_a: str
    point_a: str
    link_b: str
    point_b: str
    fit: JointFit | None = None
    kind: Literal["revolute"] = "revolute"

    def __post_init__(self) -> None:
        if self.link_a == self.link_b:
            raise ConfigError(f"Joint {self.name!r}: connects {self.link_a!r} to itself")


@dataclass(frozen=True)
class PrismaticJoint:
    """A slider: ``point_b`` of ``link_b`` moves along a line fixed in ``link_a``.

    The line passes through ``point_a`` of ``link_a`` with direction ``axis_angle`` (rad, in
    ``link_a``'s frame); ``link_b`` keeps the relative angle it has in the reference
    configuration (its frame x-axis along the line unless ``relative_angle`` says otherwise).
    """

    name: str
    link_a: str
    point_a: str
    link_b: str
    point_b: str
    axis_angle: float = 0.0
    relative_angle: float = 0.0
    kind: Literal["prismatic"] = "prismatic"

    def __post_init__(self) -> None:
        if self.link_a == self.link_b:
            raise ConfigError(f"Joint {self.name!r}: connects {self.link_a!r} to itself")


Joint = RevoluteJoint | PrismaticJoint


@dataclass(frozen=True)
class Driver:
    """The input: ``link`` turns about its ground joint ``joint`` at constant angular speed.

    Attributes:
        link: the driven link (crank).
        joint: the revolute joint between crank and ground.
        speed: magnitude of the angular speed, rad/s (> 0).
        direction: +1 counter-clockwise, -1 clockwise.
        start_angle: crank angle at t = 0, rad, counter-clockwise from the global x-axis.
    """

    link: str
    joint: str
    speed: float
    direction: Literal[1, -1] = 1
    start_angle: float = 0.0

    def __post_init__(self) -> None:
        _positive("Driver", "speed", self.speed)
        check_start_angle(self.start_angle, "Driver: start_angle")
        if self.direction not in (1, -1):
            raise ConfigError(
                f"Driver: direction must be +1 (ccw) or -1 (cw), got {self.direction}"
            )

    @property
    def angular_velocity(self) -> float:
        """Signed crank angular velocity, rad/s (counter-clockwise positive)."""
        return self.direction * self.speed

    @property
    def period(self) -> float:
        """Time of one crank revolution, s."""
        return 2.0 * math.pi / self.speed


@dataclass(frozen=True)
class LengthTolerance:
    """Limit deviations of a template length (e.g. the crank), m; ``lower <= 0 <= upper`` usually."""

    length: str
    lower: float
    upper: float
    source: str = ""

    def __post_init__(self) -> None:
        if not self.lower <= self.upper:
            raise ConfigError(
                f"Tolerance on {self.length!r}: lower deviation {self.lower} exceeds upper {self.upper}"
            )


@dataclass(frozen=True)
class Mechanism:
    """A planar mechanism with one driven link.

    Attributes:
        name: identifier (e.g. the preset name).
        ground: the fixed frame and its points.
        links: the moving links; their order defines their numbers (the first is link 2, the
            ground being link 1, as in the textbook four-bar numbering).
        joints: revolute and prismatic joints.
        driver: the constant-speed input.
        gravity: gravitational acceleration vector, m/s² (``(0, 0)``: off, the default).
        template: the template geometry this mechanism was built from, if any (enables the
            closed-form kinematics and changing lengths for tolerance studies).
        branch: assembly branch, +1 or -1; for templates +1 is the default branch documented
            by the template.
        materials: materials by name.
        tolerances: limit deviations of template lengths (data for tolerance studies).
        initial_angles: rough angles (rad) of links to start the general position solver
            from, for mechanisms without a template.
        lubrication: the lubrication of every joint that declares none (``None``: the
            contact's default, docs/contact.md, "Lubrication, declared per joint").
        joint_lubrication: the declared lubrication of single revolute joints, by name.
    """

    name: str
    ground: Ground
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    driver: Driver
    gravity: Point = (0.0, 0.0)
    template: object | None = None
    branch: Literal[1, -1] = 1
    materials: Mapping[str, Material] = field(default_factory=dict)
    tolerances: tuple[LengthTolerance, ...] = ()
    initial_angles: Mapping[str, float] = field(default_factory=dict)
    lubrication: Lubrication | None = None
    joint_lubrication: Mapping[str, Lubrication] = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "materials", FrozenMap(dict(self.materials)))
        object.__setattr__(self, "joint_lubrication", FrozenMap(dict(self.joint_lubrication)))
        object.__setattr__(self, "initial_angles", FrozenMap(dict(self.initial_angles)))
        object.__setattr__(self, "gravity", _point("Mechanism", "gravity", self.gravity))
        check_gravity(self.gravity, "Mechanism: gravity")
        names = [link.name for link in self.links]
        if len(set(names)) != len(names):
            raise ConfigError(f"Mechanism {self.name!r}: duplicate link names in {names}")
        if not self.links:
            raise ConfigError(f"Mechanism {self.name!r}: needs at least one moving link")
        joint_names = [joint.name for joint in self.joints]
        if len(set(joint_names)) != len(joint_names):
            raise ConfigError(f"Mechanism {self.name!r}: duplicate joint names in {joint_names}")
        for joint in self.joints:
            for link_name, point_name in (
                (joint.link_a, joint.point_a),
                (joint.link_b, joint.point_b),
            ):
                self.body(link_name).point(
                    point_name
                )  # raises a ConfigError naming what is missing
        if self.branch not in (1, -1):
            raise ConfigError(f"Mechanism {self.name!r}: branch must be +1 or -1")
        driver_joint = self.joint(self.driver.joint)
        if not isinstance(driver_joint, RevoluteJoint) or {
            driver_joint.link_a,
            driver_joint.link_b,
        } != {
            GROUND,
            self.driver.link,
        }:
            raise ConfigError(
                f"Driver: joint {self.driver.joint!r} must be a revolute joint between the ground "
                f"and the driven link {self.driver.link!r}"
            )
        revolute = [j.name for j in self.joints if isinstance(j, RevoluteJoint)]
        for declared in self.joint_lubrication:
            if declared not in revolute:
                raise ConfigError(
                    f"lubrication.joints: no revolute joint {declared!r} in {self.name!r}; its "
                    f"revolute joints: {', '.join(revolute)}"
                )
        if self.degrees_of_freedom != 1:
            raise ConfigError(
                f"Mechanism {self.name!r} has {self.degrees_of_freedom} degrees of freedom "
                "(Gruebler); jointplay drives single-degree-of-freedom mechanisms"
            )

    def lubrication_of(self, joint: str) -> Lubrication | None:
        """The declared lubrication of joint ``joint``: its own, else the mechanism's
        (``None``: none declared)."""
        return self.joint_lubrication.get(joint, self.lubrication)

    @property
    def degrees_of_freedom(self) -> int:
        """Gruebler–Kutzbach mobility: 3 (n − 1) − 2 j (each revolute/prismatic joint removes 2)."""
        return 3 * len(self.links) - 2 * len(self.joints)

    def link(self, name: str) -> Link:
        for link in self.links:
            if link.name == name:
                return link
        raise ConfigError(
            f"Mechanism {self.name!r} has no link {name!r}; links: {[lk.name for lk in self.links]}"
        )

    def body(self, name: str) -> Link | Ground:
        return self.ground if name == GROUND else self.link(name)

    def joint(self, name: str) -> Joint:
        for joint in self.joints:
            if joint.name == name:
                return joint
        raise ConfigError(
            f"Mechanism {self.name!r} has no joint {name!r}; joints: {[j.name for j in self.joints]}"
        )

    def material_of(self, body: str) -> Material:
        """The material of a link (the ground, or a link without one: the mechanism's first
        material, else :data:`STEEL`)."""
        if body != GROUND:
            name = self.link(body).material
            if name is not None and name in self.materials:
                return self.materials[name]
        return next(iter(self.materials.values()), STEEL)

    def bearing_width(self, joint_name: str) -> float | None:
        """The length of the contact line in a pin joint, m: the thinner of its moving links
        (the bore the pin bears on), else the pin's engaged length, else ``None``."""
        joint = self.joint(joint_name)
        thicknesses = [
            thickness
            for name in (joint.link_a, joint.link_b)
            if name != GROUND and (thickness := self.link(name).thickness) is not None
        ]
        if thicknesses:
            return min(thicknesses)
        fit = joint.fit if isinstance(joint, RevoluteJoint) else None
        return fit.pin_length if fit is not None else None

    @property
    def revolute_joints(self) -> tuple[RevoluteJoint, ...]:
        return tuple(j for j in self.joints if isinstance(j, RevoluteJoint))

    def link_number(self, name: str) -> int:
        """Textbook link number: ground 1, then the moving links from 2 in their order."""
        if name == GROUND:
            return 1
        return 2 + [link.name for link in self.links].index(name)

    def with_driver(self, **changes: object) -> Mechanism:
        """A copy with driver fields replaced (``speed``, ``direction``, ``start_angle``)."""
        return replace(self, driver=replace(self.driver, **changes))  # type: ignore[arg-type]

    def with_gravity(self, gravity: Point) -> Mechanism:
        return replace(self, gravity=gravity)

    def with_joint_fits(self, fits: Mapping[str, JointFit]) -> Mechanism:
        """A copy whose revolute joints named in ``fits`` get that fit data."""
        for name in fits:
            if not isinstance(self.joint(name), RevoluteJoint):
                raise ConfigError(f"Joint {name!r} is not a revolute joint; it cannot take a fit")
        joints = tuple(
            replace(j, fit=fits[j.name]) if j.name in fits and isinstance(j, RevoluteJoint) else j
            for j in self.joints
        )
        return replace(self, joints=joints)


def _point(owner: str, name: str, value: object) -> Point:
    try:
        x, y = value  # type: ignore[misc]
        point = (float(x), float(y))  # type: ignore[has-type]
    except (TypeError, ValueError):
        raise ConfigError(
            f"{owner}: {name} must be a pair of numbers (x, y), got {value!r}"
        ) from None
    if not all(math.isfinite(v) for v in point):
        raise ConfigError(f"{owner}: {name} must be finite, got {value!r}")
    return point


def _check_points(owner: str, points: Mapping[str, object]) -> dict[str, Point]:
    return {str(name): _point(owner, f"point {name!r}", value) for name, value in points.items()}
