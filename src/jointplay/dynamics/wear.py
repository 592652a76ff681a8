"""Archard wear of clearance joints, wear life, and the coupled wear–dynamics loop.

Archard's law (Archard, *J. Appl. Phys.* 24:981–988, 1953): the volume worn off the softer of
two sliding surfaces is ``V = k F_N s / H`` with ``k`` the dimensionless wear coefficient,
``F_N`` the normal force (N), ``s`` the sliding distance (m) and ``H`` the hardness of the
softer surface (Pa). Locally, the depth grows as ``dh = (k/H) p ds`` with ``p`` the contact
pressure (Flores, *Mech. Mach. Theory* 44:1211–1222, 2009, eq. 4).

In a clearance joint (docs/contact-laws.md §5) the sliding speed at the contact
point is ``v_T = ė·t + R_J ω_b − R_B ω_a`` (bearing on body a, journal on body b, t = ẑ × n),
the speed friction uses. :func:`cycle_wear` integrates ``(k/H) F_N |v_T|`` over the steady
revolutions of a simulation, on the integrator's own steps (which resolve every impact), and
spreads each increment over the Hertz contact arc (half-width ``b = √(4 F R/(π w E*))``, an
elliptical pressure, Johnson 1985 §4.2) on both the bearing (angle in the bearing body's
frame) and the journal (angle in the journal body's frame). The discrete spread is normalised,
so the depth profile integrated over the surface, ``∫ h(θ) R w dθ``, equals that surface's
worn volume: Archard's ``V`` is what the pair loses, shared half and half between bearing and
journal (:data:`SURFACE_SHARE`). ``k`` and ``H`` follow the joint's materials
(:data:`MATERIAL_WEAR`) unless given.

Geometric assumption of the coupling (:func:`wear_life`): the compiled contact kernel models a
circular bearing and a circular journal, so a worn (non-circular) profile cannot enter it. The
coupling instead updates the *effective radial clearance* of each joint,
``c = c₀ + max_θ h_B(θ) + max_θ h_J(θ)``: the deepest wear of bearing and journal facing each
other (conservative: the play the worn surfaces allow at worst). The dynamics are re-simulated
at that clearance every ``update_hours``, and the worn profiles are kept for the reports.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from jointplay.contact.hertz import conformal_radius, effective_modulus
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.cycles import DEFAULT_SETTLE
from jointplay.dynamics.regimes import JointRegime, full_film_throughout
from jointplay.dynamics.simulate import SimulationResult, SolverOptions, Start, simulate
from jointplay.errors import ConfigError, IntegrationError, SettingError
from jointplay.model.columns import rotating_links
from jointplay.model.mechanism import GROUND, Mechanism

__all__ = [
    "DEFAULT_HARDNESS",
    "DEFAULT_WEAR_COEFFICIENT",
    "PROFILE_BINS",
    "CycleWear",
    "JointWear",
    "OutputSpeedReference",
    "WearHistory",
    "WearSettings",
    "archard_volume",
    "cycle_wear",
    "life_hours",
    "profile_volume",
    "speed_error",
    "wear_from_series",
    "wear_life",
]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class WearData:
    """Archard data of a material sliding on itself, dry.

    Attributes:
        coefficient: dimensionless wear coefficient k.
        hardness: hardness H, Pa.
        source: where the numbers come from, and which material they stand for.
    """

    coefficient: float
    hardness: float
    source: str


#: 1 kgf/mm² in Pa (the unit of the hardness in Archard & Hirst's table).
KGF_PER_MM2 = 9.80665e6

#: Archard data by :attr:`~jointplay.model.mechanism.Material.name`, from Archard & Hirst,
#: *Proc. R. Soc. A* 236:397–410, 1956, Table 1 (reproduced in Hutchings, *Tribology*, 1992,
#: Table 5.3): pairs of like metals, dry, in the same pin-on-ring test. Jointplay's
#: ``"steel"`` (the presets' material) is a mild structural steel — its yield strength is
#: ASTM A36's, and the contact-pressure check uses it — so it wears as mild steel.
#: Lubricated contacts have k = 1e-6 … 1e-9: set the coefficient for them.
MATERIAL_WEAR: Mapping[str, WearData] = {
    "steel": WearData(
        7e-3, 186 * KGF_PER_MM2, "mild steel on mild steel, dry (Archard & Hirst 1956)"
    ),
    "mild-steel": WearData(
        7e-3, 186 * KGF_PER_MM2, "mild steel on mild steel, dry (Archard & Hirst 1956)"
    ),
    "tool-steel": WearData(
        1.3e-4, 850 * KGF_PER_MM2, "hardened tool steel on itself, dry (Archard & Hirst 1956)"
    ),
}
#: The wear coefficient of jointplay's default material, ``"steel"`` (mild steel).
DEFAULT_WEAR_COEFFICIENT = MATERIAL_WEAR["steel"].coefficient
#: The hardness of the same, 186 kgf/mm² ≈ 1.82 GPa.
DEFAULT_HARDNESS = MATERIAL_WEAR["steel"].hardness
#: The share of the Archard volume worn off each of the two surfaces, bearing and journal.
#: Archard's V = k F s / H is the volume the pair loses (the wear debris); jointplay's rule,
#: for a joint whose two surfaces have one hardness H (like materials, as every material of
#: :data:`MATERIAL_WEAR` sliding on itself): they wear alike, half each. (It used to remove
#: the whole V from both, counting the pair's wear twice.)
SURFACE_SHARE = 0.5
#: Angular bins of a worn profile around a bearing or a journal (0.5°).
PROFILE_BINS = 720


@dataclass(frozen=True)
class WearSettings:
    """Archard parameters, with per-joint overrides.

    Attributes:
        coefficient: dimensionless wear coefficient k (``None``: the material's,
            :data:`MATERIAL_WEAR`).
        hardness: hardness H of the softer surface, Pa (``None``: the material's).
        joints: per-joint overrides ``{joint: {"coefficient": k, "hardness": H}}``.
        bins: angular bins of the worn profiles.
    """

    coefficient: float | None = None
    hardness: float | None = None
    joints: Mapping[str, Mapping[str, float]] = field(default_factory=dict)
    bins: int = PROFILE_BINS

    def __post_init__(self) -> None:
        object.__setattr__(self, "joints", {k: dict(v) for k, v in self.joints.items()})
        for name in ("coefficient", "hardness"):
            if getattr(self, name) is not None:
                _check("WearSettings", name, float(getattr(self, name)))
        for joint, values in self.joints.items():
            for key, value in values.items():
                if key not in ("coefficient", "hardness"):
                    raise ConfigError(
                        f"WearSettings: joint {joint!r}: unknown field {key!r}; expected "
                        "coefficient or hardness"
                    )
                _check(f"WearSettings joint {joint!r}", key, float(value))
        if isinstance(self.bins, bool) or not isinstance(self.bins, int) or self.bins < 8:
            raise ConfigError(f"WearSettings: bins must be an integer >= 8, got {self.bins!r}")

    def of(self, joint: str, mechanism: Mechanism | None = None) -> tuple[float, float]:
        """``(k, H)`` of ``joint``: its override, else the settings', else those of the softer
        material of its two links in ``mechanism`` (:data:`MATERIAL_WEAR`; default steel).

        Raises:
            ConfigError: a value is needed from a material that :data:`MATERIAL_WEAR` lacks.
        """
        values = self.joints.get(joint, {})
        k = values.get("coefficient", self.coefficient)
        hardness = values.get("hardness", self.hardness)
        if k is None or hardness is None:
            data = material_wear(mechanism, joint)
            k = data.coefficient if k is None else k
            hardness = data.hardness if hardness is None else hardness
        return float(k), float(hardness)

    def describe(self, mechanism: Mechanism | None = None) -> dict[str, Any]:
        """JSON-ready: the values used and where they come from."""
        joint = next((j.name for j in mechanism.revolute_joints), None) if mechanism else None
        data = material_wear(mechanism, joint) if joint else MATERIAL_WEAR["steel"]
        return {
            "coefficient": data.coefficient if self.coefficient is None else self.coefficient,
            "hardness_Pa": data.hardness if self.hardness is None else self.hardness,
            "source": "given"
            if self.coefficient is not None and self.hardness is not None
            else data.source,
            "joints": dict(self.joints),
        }


def material_wear(mechanism: Mechanism | None, joint: str) -> WearData:
    """The Archard data of ``joint``: those of the softer material of its two links
    (:data:`MATERIAL_WEAR`; without a mechanism, steel's)."""
    if mechanism is None:
        return MATERIAL_WEAR["steel"]
    found = mechanism.joint(joint)
    names = {mechanism.material_of(found.link_a).name, mechanism.material_of(found.link_b).name}
    missing = sorted(n for n in names if n.lower() not in MATERIAL_WEAR)
    if missing:
        raise SettingError(
            "wear of joint {joint!r}: no wear data for material {material!r} (known: "
            "{known}); give the [wear] coefficient and hardness, or {wear_coefficient} and "
            "{hardness}",
            joint=joint,
            material=missing[0],
            known=", ".join(MATERIAL_WEAR),
        )
    return min((MATERIAL_WEAR[n.lower()] for n in names), key=lambda data: data.hardness)


def _check(owner: str, name: str, value: float) -> None:
    if not (math.isfinite(value) and value > 0):
        raise ConfigError(f"{owner}: {name} must be finite and > 0, got {value!r}")


def archard_volume(force: float, sliding: float, coefficient: float, hardness: float) -> float:
    """Archard's worn volume ``V = k F s / H``, m³ (Archard 1953).

    Args:
        force: normal force F, N.
        sliding: sliding distance s, m.
        coefficient: dimensionless wear coefficient k.
        hardness: hardness H of the softer surface, Pa.
    """
    return coefficient * force * sliding / hardness


def profile_volume(depth: FloatArray, radius: float, width: float) -> float:
    """Volume of a worn profile ``∫ h(θ) R w dθ`` (bins of equal angle over 2π), m³."""
    depth = np.asarray(depth, dtype=float)
    return float(depth.sum() * (2.0 * math.pi / len(depth)) * radius * width)


def life_hours(clearance: float, limit: float, rate_per_hour: float) -> float:
    """Hours until a clearance growing at a constant ``rate_per_hour`` (m/h) reaches ``limit``
    (m): ``(limit − c)/rate``; 0 if already past, ``inf`` without wear."""
    if clearance >= limit:
        return 0.0
    if rate_per_hour <= 0.0:
        return math.inf
    return (limit - clearance) / rate_per_hour


@dataclass(frozen=True)
class JointWear:
    """Wear of one clearance joint per crank revolution of the steady motion.

    Attributes:
        joint: joint name.
        clearance: radial clearance simulated, m.
        journal_radius: R_J, m.
        width: bearing width w, m.
        coefficient, hardness: Archard k and H (Pa).
        sliding: sliding distance in contact per revolution, m.
        work: ∫ F_N |v_T| dt per revolution (the Archard load × distance), N·m.
        volume_bearing, volume_journal: worn volume per revolution, m³.
        bearing_profile: wear depth per revolution around the bearing (bearing body frame,
            bins from 0 to 2π), m.
        journal_profile: the same around the journal (journal body frame), m.
        growth_per_revolution: growth of the effective radial clearance per revolution,
            ``max h_B + max h_J``, m.
    """

    joint: str
    clearance: float
    journal_radius: float
    width: float
    coefficient: float
    hardness: float
    sliding: float
    work: float
    volume_bearing: float
    volume_journal: float
    bearing_profile: FloatArray = field(repr=False)
    journal_profile: FloatArray = field(repr=False)
    growth_per_revolution: float

    @property
    def bearing_radius(self) -> float:
        return self.journal_radius + self.clearance

    def per_hour(self, rpm: float) -> float:
        """Growth of the radial clearance per hour at ``rpm`` rev/min, m/h."""
        return self.growth_per_revolution * rpm * 60.0

    def describe(self, rpm: float) -> dict[str, Any]:
        return {
            "clearance_m": self.clearance,
            "sliding_per_rev_m": self.sliding,
            "volume_bearing_per_rev_m3": self.volume_bearing,
            "volume_journal_per_rev_m3": self.volume_journal,
            "depth_bearing_per_rev_m": float(self.bearing_profile.max()),
            "depth_journal_per_rev_m": float(self.journal_profile.max()),
            "clearance_growth_per_rev_m": self.growth_per_revolution,
            "clearance_growth_per_hour_m": self.per_hour(rpm),
            "wear_coefficient": self.coefficient,
            "hardness_Pa": self.hardness,
        }


@dataclass(frozen=True)
class CycleWear:
    """Wear of every clearance joint over the steady revolutions of one simulation.

    Attributes:
        rpm: crank speed, rev/min.
        joints: per-joint wear, in the simulation's clearance-joint order.
    """

    rpm: float
    joints: Mapping[str, JointWear]

    def growth_per_hour(self) -> dict[str, float]:
        """Growth of each joint's radial clearance per hour, m/h."""
        return {name: j.per_hour(self.rpm) for name, j in self.joints.items()}


def _body_angle(steps: Mapping[str, FloatArray], mechanism: Mechanism, body: str) -> FloatArray:
    n = len(steps["t"])
    if body == GROUND:
        return np.zeros(n)
    if body == mechanism.driver.link:
        return np.radians(steps["crank_deg"])
    number = dict(rotating_links(mechanism))[body]
    return np.radians(steps[f"theta{number}_deg"])


def _body_speed(steps: Mapping[str, FloatArray], mechanism: Mechanism, body: str) -> FloatArray:
    n = len(steps["t"])
    if body == GROUND:
        return np.zeros(n)
    if body == mechanism.driver.link:
        return np.gradient(np.unwrap(np.radians(steps["crank_deg"])), steps["t"])
    number = dict(rotating_links(mechanism))[body]
    return np.asarray(steps[f"omega{number}"], dtype=float)


def _spread(
    angles: FloatArray, amounts: FloatArray, half_angles: FloatArray, bins: int
) -> FloatArray:
    """Distribute ``amounts`` (volumes) over ``bins`` equal bins around 2π with an elliptical
    weight of half-angle ``half_angles`` about ``angles``; each amount is conserved exactly
    (its weights are normalised; an arc narrower than a bin falls in the nearest bin)."""
    out = np.zeros(bins)
    touching = amounts > 0.0  # out of contact nothing wears
    angles, amounts, half_angles = angles[touching], amounts[touching], half_angles[touching]
    if len(angles) == 0:
        return out
    width = 2.0 * math.pi / bins
    half = np.maximum(half_angles, width)
    reach = min(math.ceil(float(half.max()) / width) + 1, bins // 2)
    nearest = np.floor(np.mod(angles, 2.0 * math.pi) / width).astype(np.int64) % bins
    offsets = np.arange(-reach, reach + 1)
    index = (nearest[:, None] + offsets[None, :]) % bins
    centres = (nearest[:, None] + offsets[None, :] + 0.5) * width
    diff = np.mod(centres - angles[:, None] + math.pi, 2.0 * math.pi) - math.pi  # in [-π, π)
    weight = np.sqrt(np.clip(1.0 - (diff / half[:, None]) ** 2, 0.0, None))
    total = weight.sum(axis=1, keepdims=True)
    empty = total[:, 0] <= 0.0
    weight[empty, reach] = 1.0
    total[empty] = 1.0
    spread: FloatArray = np.bincount(
        index.ravel(), weights=((weight / total) * amounts[:, None]).ravel(), minlength=bins
    ).astype(np.float64)
    return spread


def wear_from_series(
    t: FloatArray,
    force: FloatArray,
    slip: FloatArray,
    bearing_angle: FloatArray,
    journal_angle: FloatArray,
    *,
    joint: str,
    journal_radius: float,
    clearance: float,
    width: float,
    coefficient: float,
    hardness: float,
    modulus: float,
    revolutions: float = 1.0,
    bins: int = PROFILE_BINS,
) -> JointWear:
    """Archard wear of one joint from time series of its contact (trapezoidal rule).

    Args:
        t: times, s (increasing).
        force: normal contact force F_N ≥ 0, N.
        slip: relative sliding speed at the contact point v_T, m/s.
        bearing_angle, journal_angle: direction of the contact normal in the bearing's and
            the journal's body frame, rad.
        joint: joint name.
        journal_radius: R_J, m; clearance: c = R_B − R_J, m; width: bearing width w, m.
        coefficient, hardness: Archard k and H (Pa).
        modulus: effective modulus E* of the pair, Pa (the Hertz contact arc).
        revolutions: crank revolutions the series covers (results are per revolution).
        bins: angular bins of the profiles.
    """
    t = np.asarray(t, dtype=float)
    force = np.clip(np.asarray(force, dtype=float), 0.0, None)
    speed = np.abs(np.asarray(slip, dtype=float))
    dt = np.diff(t)
    r_j, r_b = journal_radius, journal_radius + clearance
    sliding_rate = np.where(force > 0.0, speed, 0.0)
    power = force * speed  # F_N |v_T|, N·m/s
    sliding = float(np.sum(0.5 * (sliding_rate[1:] + sliding_rate[:-1]) * dt)) / revolutions
    increments = 0.5 * (power[1:] + power[:-1]) * dt  # N·m per step interval
    work = float(increments.sum()) / revolutions
    volumes = coefficient * increments / hardness / revolutions
    f_mid = 0.5 * (force[1:] + force[:-1])
    radius = conformal_radius(r_j, r_b) if r_b > r_j else 1e3
    half_width = np.sqrt(4.0 * (f_mid / width) * radius / (math.pi * modulus))

    def midpoint(angle: FloatArray) -> FloatArray:
        angle = np.asarray(angle, dtype=float)
        return np.mod(np.angle(np.exp(1j * angle[:-1]) + np.exp(1j * angle[1:])), 2 * math.pi)

    active = volumes > 0.0
    vol = SURFACE_SHARE * volumes[active]  # each surface's share of the pair's volume
    bearing_vol = _spread(midpoint(bearing_angle)[active], vol, half_width[active] / r_b, bins)
    journal_vol = _spread(midpoint(journal_angle)[active], vol, half_width[active] / r_j, bins)
    arc = 2.0 * math.pi / bins
    bearing_profile = bearing_vol / (arc * r_b * width)
    journal_profile = journal_vol / (arc * r_j * width)
    return JointWear(
        joint=joint,
        clearance=clearance,
        journal_radius=r_j,
        width=float(width),
        coefficient=coefficient,
        hardness=hardness,
        sliding=sliding,
        work=work,
        volume_bearing=float(vol.sum()),
        volume_journal=float(vol.sum()),
        bearing_profile=bearing_profile,
        journal_profile=journal_profile,
        growth_per_revolution=float(bearing_profile.max() + journal_profile.max()),
    )


def cycle_wear(
    result: SimulationResult,
    settings: WearSettings | None = None,
    *,
    revolutions: float | None = None,
) -> CycleWear:
    """Archard wear per revolution of every clearance joint of a steady simulation.

    Integrates ``(k/H) F_N |v_T|`` over the last ``revolutions`` (default: the analysed ones,
    after the start-up) with the trapezoidal rule on the integrator's steps.

    Raises:
        IntegrationError: the simulation failed.
        ConfigError: a clearance joint without a bearing width (link thickness or pin length).
    """
    settings = settings or WearSettings()
    if not result.success:
        raise IntegrationError(f"wear needs a finished simulation: {result.message}")
    mechanism = result.mechanism
    revs = float(result.revolutions if revolutions is None else revolutions)
    period = mechanism.driver.period
    steps_frame = result.steps
    t_all = steps_frame["t"].to_numpy()
    t_end = float(t_all[-1])
    keep = t_all >= t_end - revs * period - 1e-12
    steps = {name: steps_frame[name].to_numpy()[keep] for name in steps_frame.columns}
    t = steps["t"]
    rpm = mechanism.driver.speed * 30.0 / math.pi
    joints: dict[str, JointWear] = {}
    for clearance in result.system.clearances:
        name = clearance.joint
        joint = mechanism.joint(name)
        width = mechanism.bearing_width(name)
        if width is None:
            raise ConfigError(
                f"wear of joint {name!r}: no bearing width; give its links a thickness or the "
                "pin a pin_length"
            )
        k, hardness = settings.of(name, mechanism)
        r_j = clearance.journal_radius
        r_b = r_j + clearance.clearance
        ex, ey = steps[f"ex_{name}"], steps[f"ey_{name}"]
        dex, dey = steps[f"dex_{name}"], steps[f"dey_{name}"]
        norm = np.hypot(ex, ey)
        safe = np.where(norm > 0, norm, 1.0)
        nx, ny = np.where(norm > 0, ex / safe, 1.0), np.where(norm > 0, ey / safe, 0.0)
        omega_a = _body_speed(steps, mechanism, joint.link_a)
        omega_b = _body_speed(steps, mechanism, joint.link_b)
        material_a = mechanism.material_of(joint.link_a)
        material_b = mechanism.material_of(joint.link_b)
        psi = np.arctan2(ny, nx)
        joints[name] = wear_from_series(
            t,
            np.clip(steps[f"Fn_{name}"], 0.0, None),
            dex * (-ny) + dey * nx + r_j * omega_b - r_b * omega_a,
            psi - _body_angle(steps, mechanism, joint.link_a),
            psi - _body_angle(steps, mechanism, joint.link_b),
            joint=name,
            journal_radius=r_j,
            clearance=clearance.clearance,
            width=float(width),
            coefficient=k,
            hardness=hardness,
            modulus=effective_modulus(
                material_a.youngs_modulus,
                material_a.poisson_ratio,
                material_b.youngs_modulus,
                material_b.poisson_ratio,
            ),
            revolutions=revs,
            bins=settings.bins,
        )
    return CycleWear(rpm, joints)


@dataclass(frozen=True)
class OutputSpeedReference:
    """The ideal-joint angular velocity of the output link (the last rotating link, e.g. the
    rocker) of the nominal mechanism over one crank revolution.

    Attributes:
        link_number: textbook number of the output link (``omega<k>`` column).
        crank: crank angles, rad, increasing over [0, 2π].
        omega: ideal angular velocity there, rad/s.
    """

    link_number: int
    crank: tuple[float, ...]
    omega: tuple[float, ...]

    @classmethod
    def of(cls, mechanism: Mechanism, step_deg: float = 0.5) -> OutputSpeedReference:
        from jointplay.dynamics.nominal import nominal_analysis

        number = rotating_links(mechanism)[-1][1]
        table = nominal_analysis(mechanism, step_deg=step_deg).table
        crank = np.mod(np.radians(table["crank_deg"].to_numpy()), 2 * math.pi)
        order = np.argsort(crank)
        return cls(
            number,
            tuple(map(float, crank[order])),
            tuple(map(float, table[f"omega{number}"].to_numpy()[order])),
        )

    def at(self, crank: FloatArray) -> FloatArray:
        return np.interp(
            np.mod(crank, 2 * math.pi), self.crank, self.omega, period=2 * math.pi
        ).astype(float)

    @property
    def peak(self) -> float:
        return float(np.max(np.abs(self.omega)))


def speed_error(result: SimulationResult, reference: OutputSpeedReference) -> float:
    """The output-link (rocker) speed error of a simulation: the largest
    ``|ω(t) − ω_ideal(θ₂(t))|`` over the analysed revolutions, as a fraction of the largest
    ideal ``|ω|`` (dimensionless; 0.01 = 1 %). Evaluated on the continuous solution at 0.25°
    of crank angle and at every integrator step."""
    mechanism = result.mechanism
    period = mechanism.driver.period
    t_end = float(result.t[-1])
    t0 = t_end - result.revolutions * period
    grid = np.linspace(t0, t_end, max(2, round(result.revolutions * 1440)) + 1)
    values = result.evaluate(grid)
    steps = result.steps
    mask = steps["t"].to_numpy() >= t0
    column = f"omega{reference.link_number}"
    crank = np.concatenate([np.radians(values["crank_deg"]), np.radians(steps["crank_deg"])[mask]])
    omega = np.concatenate([values[column], steps[column].to_numpy()[mask]])
    return float(np.max(np.abs(omega - reference.at(crank))) / reference.peak)


@dataclass(frozen=True)
class WearHistory:
    """The coupled wear–dynamics history of a mechanism.

    Attributes:
        rpm: crank speed, rev/min.
        limit: radial clearance limit per joint, m.
        hours: times of the re-simulations, h.
        clearance: effective radial clearance per joint at those times, m.
        peak_force: peak contact force per joint at those times, N.
        speed_error: output-link speed error at those times (fraction).
        growth_per_hour: clearance growth rate per joint at those times, m/h.
        bearing_profile, journal_profile: final worn depth profiles per joint, m.
        life: hours until each joint's clearance passes its limit (``inf``: never at the
            final rate).
        life_extrapolated: per joint: the life lies beyond the simulated hours, extrapolated
            at the final rate.
        assumption: the geometric assumption of the coupling (module docstring).
        contact_peak: the largest contact (asperity) normal force F_N per joint at those
            times, N: what wears (a film's force does not).
        regimes: the lubrication regimes per joint at those times
            (:mod:`jointplay.dynamics.regimes`; ``None``: a dry joint).
    """

    rpm: float
    limit: Mapping[str, float]
    hours: tuple[float, ...]
    clearance: Mapping[str, tuple[float, ...]]
    peak_force: Mapping[str, tuple[float, ...]]
    speed_error: tuple[float, ...]
    growth_per_hour: Mapping[str, tuple[float, ...]]
    bearing_profile: Mapping[str, FloatArray] = field(repr=False)
    journal_profile: Mapping[str, FloatArray] = field(repr=False)
    life: Mapping[str, float]
    life_extrapolated: Mapping[str, bool]
    assumption: str
    contact_peak: Mapping[str, tuple[float, ...]] = field(default_factory=dict)
    regimes: Mapping[str, tuple[JointRegime | None, ...]] = field(default_factory=dict)

    def no_wear(self, name: str) -> str | None:
        """Why joint ``name`` has no wear life, in one line, or ``None`` (it wears): no
        contact (asperity) force at any re-simulation, and what held it off."""
        if not math.isinf(self.life[name]) or any(self.contact_peak.get(name, (1.0,))):
            return None
        regimes = self.regimes.get(name, ())
        if not regimes or any(r is None for r in regimes):
            return "no contact: the pin never touched its bearing's wall, nothing wears"
        h_min = min(r.h_min for r in regimes if r is not None) * 1e6
        if all(full_film_throughout(r) for r in regimes):
            return f"full film throughout: h_min ≥ {h_min:.2f} µm, no asperity contact"
        mixed = max(1.0 - r.full_film for r in regimes if r is not None) * 100
        return (
            f"no contact force: the film kept the pin off the wall (h_min ≥ {h_min:.2f} µm), "
            f"though thinner than 3σ {mixed:.0f} % of the time; the linear film has no "
            "asperity contact (--film-model short-bearing-pi models it)"
        )

    @property
    def mechanism_life(self) -> float:
        """Hours until the first joint passes its limit."""
        return min(self.life.values()) if self.life else math.inf

    def to_dataframe(self) -> Any:
        import pandas as pd

        columns: dict[str, Any] = {"hours": list(self.hours), "speed_error": self.speed_error}
        for name in self.clearance:
            columns[f"clearance_{name}"] = self.clearance[name]
            columns[f"F_{name}_peak"] = self.peak_force[name]
            columns[f"growth_per_hour_{name}"] = self.growth_per_hour[name]
        return pd.DataFrame(columns)

    def summary(self) -> dict[str, Any]:
        return {
            "rpm": self.rpm,
            "assumption": self.assumption,
            "clearance_limit_m": dict(self.limit),
            "life_hours": {k: (None if math.isinf(v) else v) for k, v in self.life.items()},
            "life_extrapolated": dict(self.life_extrapolated),
            "mechanism_life_hours": None
            if math.isinf(self.mechanism_life)
            else self.mechanism_life,
            "final_clearance_m": {k: v[-1] for k, v in self.clearance.items()},
            "max_depth_bearing_m": {k: float(v.max()) for k, v in self.bearing_profile.items()},
            "max_depth_journal_m": {k: float(v.max()) for k, v in self.journal_profile.items()},
            # what wears: the contact (asperity) force, not the film's; why a joint does not
            "contact_force_peak_N": {k: list(v) for k, v in self.contact_peak.items()},
            "no_wear": {k: self.no_wear(k) for k in self.life},
            "film_regimes": {
                k: [None if r is None else r.describe() for r in v] for k, v in self.regimes.items()
            },
        }


#: The geometric assumption of :func:`wear_life`, for reports.
COUPLING_ASSUMPTION = (
    "circular bearing and journal in the contact kernel; the worn profiles enter the dynamics "
    "through the effective radial clearance c = c0 + max h_bearing + max h_journal "
    "(deepest wear of both surfaces facing each other, conservative)"
)


def wear_life(
    mechanism: Mechanism,
    joints: Sequence[ClearanceJoint],
    *,
    hours: float,
    update_hours: float,
    clearance_limit: Mapping[str, float] | float,
    settings: WearSettings | None = None,
    settle: int = DEFAULT_SETTLE,
    revolutions: float = 1.0,
    solver: SolverOptions | None = None,
    on_update: Any = None,
) -> WearHistory:
    """Wear the joints for ``hours``, re-simulating the steady motion every ``update_hours``.

    Each interval: simulate at the current effective clearances (steady start, ``settle``
    start-up revolutions left out), compute the Archard wear per revolution
    (:func:`cycle_wear`), add it × the revolutions of the interval to the worn profiles, and
    update the effective clearance (:data:`COUPLING_ASSUMPTION`). A joint's life is the time
    its clearance passes its limit (linear within the interval); past ``hours``, it is
    extrapolated at the final rate.

    Args:
        mechanism: the mechanism (crank speed from its driver).
        joints: the clearance joints at their initial clearance.
        hours: operating hours to simulate (> 0).
        update_hours: hours between re-simulations (> 0).
        clearance_limit: radial clearance limit, m, one for all or per joint.
        settings: Archard parameters.
        settle, revolutions, solver: as :func:`~jointplay.dynamics.simulate.simulate`.
        on_update: optional callback ``on_update(hours_done, hours_total)``.

    Raises:
        IntegrationError: a simulation failed.
    """
    settings = settings or WearSettings()
    _check("wear_life", "hours", hours)
    _check("wear_life", "update_hours", update_hours)
    names = [j.joint for j in joints]
    if isinstance(clearance_limit, Mapping):
        missing = [n for n in names if n not in clearance_limit]
        if missing:
            raise ConfigError(f"wear_life: no clearance limit for joint(s) {missing}")
        limit = {n: float(clearance_limit[n]) for n in names}
    else:
        limit = {n: float(clearance_limit) for n in names}
    reference = OutputSpeedReference.of(mechanism)
    rpm = mechanism.driver.speed * 30.0 / math.pi
    revs_per_hour = rpm * 60.0
    c0 = {j.joint: j.clearance for j in joints}
    bearing = {n: np.zeros(settings.bins) for n in names}
    journal = {n: np.zeros(settings.bins) for n in names}
    current = dict(c0)
    times: list[float] = []
    history_c: dict[str, list[float]] = {n: [] for n in names}
    history_f: dict[str, list[float]] = {n: [] for n in names}
    history_g: dict[str, list[float]] = {n: [] for n in names}
    history_n: dict[str, list[float]] = {n: [] for n in names}
    history_r: dict[str, list[JointRegime | None]] = {n: [] for n in names}
    errors: list[float] = []
    life: dict[str, float] = {}
    done = 0.0
    rates: dict[str, float] = {}
    while True:
        state = [j.with_clearance(current[j.joint]) for j in joints]
        result = simulate(
            mechanism,
            state,
            revolutions=revolutions,
            settle=settle,
            start=Start("steady"),
            solver=solver,
            throw=False,
        )
        if not result.success:
            raise IntegrationError(f"wear at {done:g} h: {result.message}")
        wear = cycle_wear(result, settings)
        rates = wear.growth_per_hour()
        regimes = result.film_regimes
        window = result.steps["t"].to_numpy() >= float(result.t[-1]) - revolutions * (
            mechanism.driver.period
        )
        times.append(done)
        errors.append(speed_error(result, reference))
        for n in names:
            history_c[n].append(current[n])
            history_f[n].append(float(result.peaks[f"F_{n}"]["value"]))
            history_g[n].append(rates[n])
            history_n[n].append(float(np.max(result.steps[f"Fn_{n}"].to_numpy()[window])))
            history_r[n].append(regimes[n])
            if n not in life and current[n] >= limit[n]:
                life[n] = done
        if on_update is not None:
            on_update(done, hours)
        if done >= hours - 1e-12 or len(life) == len(names):
            break
        step = min(update_hours, hours - done)
        for n in names:
            joint_wear = wear.joints[n]
            bearing[n] = bearing[n] + joint_wear.bearing_profile * revs_per_hour * step
            journal[n] = journal[n] + joint_wear.journal_profile * revs_per_hour * step
            new = c0[n] + float(bearing[n].max() + journal[n].max())
            if n not in life and new >= limit[n] > current[n]:
                life[n] = done + step * (limit[n] - current[n]) / (new - current[n])
            current[n] = new
        done += step
    extrapolated = {}
    for n in names:
        extrapolated[n] = n not in life
        if n not in life:
            life[n] = done + life_hours(current[n], limit[n], rates.get(n, 0.0))
    return WearHistory(
        rpm=rpm,
        limit=limit,
        hours=tuple(times),
        clearance={n: tuple(v) for n, v in history_c.items()},
        peak_force={n: tuple(v) for n, v in history_f.items()},
        speed_error=tuple(errors),
        growth_per_hour={n: tuple(v) for n, v in history_g.items()},
        bearing_profile=bearing,
        journal_profile=journal,
        life=life,
        life_extrapolated=extrapolated,
        assumption=COUPLING_ASSUMPTION,
        contact_peak={n: tuple(v) for n, v in history_n.items()},
        regimes={n: tuple(v) for n, v in history_r.items()},
    )
