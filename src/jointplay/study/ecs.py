"""The ECS method on a whole mechanism: loads from its nominal cycle, a crank-speed sweep, and
the simulator parameters it gives (the paper's eqs. 9–13 applied as in its "ECS approach").

:func:`ecs_analysis` runs the nominal (ideal-joint) analysis of a mechanism, takes each joint's
contact load from it (eq. 13, or the ideal reaction) and applies the per-joint formulas of
:mod:`jointplay.contact.ecs`; :func:`ecs_parameters` turns the result, or the paper's published
Tables 4–5 (:mod:`jointplay.study.published`), into IMPACT and Restitution-Method parameters;
:func:`ecs_sweep` repeats the analysis over crank speed with the hysteresis comparison of the
paper's Fig. 6 discussion. Everything is SI. The conventions and the comparison are explained
in ``docs/ecs.md``.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np
import pandas as pd

from jointplay.contact.ecs import (
    CONTACT_TYPES,
    MM,
    EcsConventions,
    EcsEstimate,
    EcsJoint,
    JointLoad,
    comparison_factors,
    contact_type,
    ecs_hysteresis_factor,
    eq13_load,
    estimate_joint,
    impact_velocity_estimate,
)
from jointplay.contact.laws import FloatArray, ImpactLaw, RestitutionLaw
from jointplay.contact.restitution import effective_restitution
from jointplay.dynamics.nominal import NominalResult, nominal_analysis
from jointplay.errors import ConfigError
from jointplay.model.mechanism import GROUND, Mechanism, RevoluteJoint
from jointplay.study.published import PAPER_PUBLISHED

# --- one crank speed --------------------------------------------------------------------------


@dataclass(frozen=True)
class EcsResult:
    """ECS of a mechanism at one crank speed: per joint and overall.

    Attributes:
        mechanism: mechanism name.
        crank_speed: rad/s.
        conventions: the conventions used.
        joints: one entry per revolute joint with fit data, in the mechanism's order.
        overall_joint: the joint with the largest load (ties: the first); its estimates are
            the mechanism's ECS values, as the paper's single K, δ, D per contact type.
        impact_velocity: v0 for the hysteresis comparison, m/s.
        impact_velocity_source: ``"estimated"`` or ``"given"``.
    """

    mechanism: str
    crank_speed: float
    conventions: EcsConventions
    joints: tuple[EcsJoint, ...]
    overall_joint: str
    impact_velocity: float
    impact_velocity_source: str

    @property
    def crank_speed_rpm(self) -> float:
        """Crank speed, rev/min."""
        return self.crank_speed * 30.0 / math.pi

    @property
    def overall(self) -> EcsJoint:
        """The joint with the largest load."""
        return self.joint(self.overall_joint)

    def joint(self, name: str) -> EcsJoint:
        """The entry of joint ``name``."""
        for entry in self.joints:
            if entry.load.joint == name:
                return entry
        raise ConfigError(
            f"no ECS entry for joint {name!r}; joints: {[j.load.joint for j in self.joints]}"
        )

    def estimate(self, contact: str) -> EcsEstimate:
        """The mechanism's (overall) estimate for ``contact``."""
        return self.overall.estimate(contact)

    def hysteresis_factor(self, contact: str) -> float:
        """χ_ECS = (D/K) v0/δ of the overall estimate (docs/ecs.md), dimensionless."""
        est = self.estimate(contact)
        return ecs_hysteresis_factor(
            self.conventions.damping_ratio, self.impact_velocity, est.penetration
        )

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready record: conventions, loads, estimates (SI and paper units)."""
        joints = []
        for entry in self.joints:
            load = entry.load
            joints.append(
                {
                    "joint": load.joint,
                    "load": {
                        "source": load.source,
                        "load_N": load.load,
                        "at_crank_deg": load.crank_deg,
                        "alpha_link": load.alpha_link,
                        "alpha_max_rad_s2": load.alpha_max,
                        "tangential_acceleration_m_s2": load.tangential_acceleration,
                        "pin_radius_m": load.pin_radius,
                        "bearing_radius_m": load.bearing_radius,
                        "clearance_m": load.clearance,
                        "pin_mass_kg": load.pin_mass,
                        "contact_length_m": load.length,
                        "bearing_material": load.bearing_material.name,
                        "pin_material": load.pin_material.name,
                    },
                    "spherical": entry.spherical.as_dict(),
                    "cylindrical": entry.cylindrical.as_dict(),
                }
            )
        return {
            "mechanism": self.mechanism,
            "crank_speed_rad_s": self.crank_speed,
            "crank_speed_rpm": self.crank_speed_rpm,
            "conventions": self.conventions.as_dict(),
            "overall_joint": self.overall_joint,
            "overall": {c: self.estimate(c).as_dict() for c in CONTACT_TYPES},
            "joints": joints,
            "hysteresis": {
                "impact_velocity_m_s": self.impact_velocity,
                "impact_velocity_source": self.impact_velocity_source,
                "chi_ecs": {c: self.hysteresis_factor(c) for c in CONTACT_TYPES},
            },
        }


def _contact_length(mechanism: Mechanism, joint: RevoluteJoint, convention: str | float) -> float:
    if not isinstance(convention, str):
        return float(convention)
    assert joint.fit is not None
    if convention == "link-thickness":
        width = mechanism.bearing_width(joint.name)
        if width is None:
            raise ConfigError(
                f"joint {joint.name!r}: neither link has a thickness and the fit has no "
                "pin_length; give the links a thickness, or use contact_length='pin-length' "
                "with a pin_length, or a length in m"
            )
        return width
    if joint.fit.pin_length is None:
        raise ConfigError(
            f"joint {joint.name!r}: contact_length='pin-length' needs JointFit.pin_length; set "
            f"joints.{joint.name}.pin_length or use contact_length='link-thickness'"
        )
    return joint.fit.pin_length


def _alpha(nominal: NominalResult, body: str) -> FloatArray:
    if body == GROUND:
        return np.zeros_like(nominal.kinematics.crank_angle)
    return np.asarray(nominal.kinematics.alpha(body), dtype=np.float64)


def _joint_load(
    mechanism: Mechanism,
    joint: RevoluteJoint,
    nominal: NominalResult,
    conventions: EcsConventions,
) -> JointLoad:
    fit = joint.fit
    assert fit is not None
    crank_deg = nominal.table["crank_deg"].to_numpy()
    pin_radius = fit.diameter / 2.0
    clearance = fit.clearance or 0.0
    candidates = {
        "max": (joint.link_a, joint.link_b),
        "pin": (joint.link_b,),
        "bearing": (joint.link_a,),
    }[conventions.alpha_link]
    best_link, best_alpha, best_index = "", 0.0, 0
    for body in candidates:
        alpha = np.abs(_alpha(nominal, body))
        index = int(np.argmax(alpha))
        if alpha[index] > best_alpha:
            best_link, best_alpha, best_index = body, float(alpha[index]), index
    if conventions.load == "eq13":
        if fit.pin_mass is None:
            raise ConfigError(
                f"joint {joint.name!r}: eq. 13 needs the pin mass; set joints.{joint.name}."
                "pin_mass in the configuration, or use the 'reaction' load"
            )
        load = float(eq13_load(best_alpha, pin_radius, fit.pin_mass))
        index = best_index
    else:
        reaction = nominal.dynamics.joint_force(joint.name)
        index = int(np.argmax(reaction))
        load = float(reaction[index])
    return JointLoad(
        joint=joint.name,
        source=conventions.load,
        load=load,
        crank_deg=float(crank_deg[index]),
        alpha_link=best_link,
        alpha_max=best_alpha,
        tangential_acceleration=best_alpha * pin_radius,
        pin_radius=pin_radius,
        bearing_radius=pin_radius + clearance,
        clearance=clearance,
        pin_mass=fit.pin_mass if fit.pin_mass is not None else math.nan,
        length=_contact_length(mechanism, joint, conventions.contact_length),
        bearing_material=mechanism.material_of(joint.link_a),
        pin_material=mechanism.material_of(joint.link_b),
    )


def ecs_analysis(
    mechanism: Mechanism,
    conventions: EcsConventions | None = None,
    *,
    nominal: NominalResult | None = None,
    step_deg: float = 1.0,
) -> EcsResult:
    """The ECS method on ``mechanism`` at its crank speed (paper eqs. 9–13).

    Args:
        mechanism: the nominal mechanism; every revolute joint with a
            :class:`~jointplay.model.mechanism.JointFit` gets an estimate.
        conventions: the open choices (defaults: :class:`~jointplay.contact.ecs.EcsConventions`).
        nominal: a precomputed :func:`~jointplay.dynamics.nominal.nominal_analysis` of
            ``mechanism`` (computed here if ``None``).
        step_deg: crank-angle step of the nominal cycle, deg (1° as the paper's analysis).

    Returns:
        An :class:`EcsResult`.

    Raises:
        ConfigError: no revolute joint with fit data, a fit lacking what the conventions need,
            or an invalid convention.
    """
    conventions = conventions or EcsConventions()
    joints = [j for j in mechanism.revolute_joints if j.fit is not None]
    if not joints:
        raise ConfigError(
            f"mechanism {mechanism.name!r}: no revolute joint has fit data (diameter, clearance, "
            "pin_mass); add a [joints.NAME] table to the configuration"
        )
    if nominal is None:
        nominal = nominal_analysis(mechanism, step_deg=step_deg)
    entries = tuple(
        estimate_joint(_joint_load(mechanism, j, nominal, conventions), conventions) for j in joints
    )
    overall = max(entries, key=lambda e: e.load.load).load.joint
    if conventions.impact_velocity is not None:
        v0, v0_source = conventions.impact_velocity, "given"
    else:
        driver = max(entries, key=lambda e: e.load.tangential_acceleration).load
        v0 = impact_velocity_estimate(driver.tangential_acceleration, driver.clearance)
        v0_source = "estimated"
    return EcsResult(
        mechanism=mechanism.name,
        crank_speed=mechanism.driver.speed,
        conventions=conventions,
        joints=entries,
        overall_joint=overall,
        impact_velocity=v0,
        impact_velocity_source=v0_source,
    )


# --- what the simulator needs -----------------------------------------------------------------


@dataclass(frozen=True)
class EcsParameters:
    """Contact parameters for the simulator from the ECS method, and how they were derived.

    IMPACT (IFM, paper eqs. 1–3): ``F = k δ^e + STEP(δ, 0, 0, d_max, c_max) δ̇``.
    Restitution (RM, eq. 8 surrogate): penalty ``p`` (linear), restitution chosen by the user.

    Attributes:
        contact: ``"spherical"`` or ``"cylindrical"``.
        source: ``"computed"`` or ``"paper"``.
        stiffness: IMPACT k, N/m^e (SI; see ``EcsConventions.ifm_stiffness``).
        exponent: IMPACT e.
        c_max: IMPACT maximum damping = D, N·s/m.
        d_max: IMPACT full-damping penetration = δ, m.
        penalty: RM penalty p = K, N/m (exponent 1).
        ecs_stiffness: the linear ECS K, N/m.
        ecs_penetration: the ECS δ, m.
        ecs_damping: the ECS D, N·s/m.
        derivation: JSON-ready record of sources, conventions and intermediate values.
    """

    contact: str
    source: str
    stiffness: float
    exponent: float
    c_max: float
    d_max: float
    penalty: float
    ecs_stiffness: float
    ecs_penetration: float
    ecs_damping: float
    derivation: Mapping[str, Any] = field(default_factory=dict)

    def impact_law(self) -> ImpactLaw:
        """The IMPACT law with these parameters."""
        return ImpactLaw(
            stiffness=self.stiffness, exponent=self.exponent, c_max=self.c_max, d_max=self.d_max
        )

    def restitution_law(self, restitution: float = 0.8) -> RestitutionLaw:
        """The RM surrogate with penalty p = K (exponent 1) and coefficient ``restitution``."""
        return RestitutionLaw(penalty=self.penalty, restitution=restitution, exponent=1.0)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: SI values, the same in the paper's units, and the derivation."""
        e = self.exponent
        return {
            "contact": self.contact,
            "source": self.source,
            "impact": {
                "stiffness_N_per_m^e": self.stiffness,
                "stiffness_N_per_mm^e": self.stiffness * MM**e,
                "exponent": e,
                "c_max_N_s_per_m": self.c_max,
                "c_max_N_s_per_mm": self.c_max * MM,
                "d_max_m": self.d_max,
                "d_max_mm": self.d_max / MM,
            },
            "restitution_method": {
                "penalty_N_per_m": self.penalty,
                "penalty_N_per_mm": self.penalty * MM,
            },
            "derivation": dict(self.derivation),
        }


def ecs_parameters(
    mechanism: Mechanism,
    contact: str = "spherical",
    source: str = "computed",
    conventions: EcsConventions | None = None,
    *,
    result: EcsResult | None = None,
) -> EcsParameters:
    """IMPACT and RM parameters from the ECS method (``"computed"``) or the paper (``"paper"``).

    Args:
        mechanism: the nominal mechanism (its crank speed sets the computed load).
        contact: ``"spherical"`` (eqs. 9–10, Table 5) or ``"cylindrical"`` (eqs. 11–12,
            Table 4).
        source: ``"computed"`` (:func:`ecs_analysis`) or ``"paper"``
            (:data:`~jointplay.study.published.PAPER_PUBLISHED`, estimated by the paper at
            200 RPM for its own mechanism).
        conventions: the open choices, including how K becomes the IMPACT stiffness.
        result: a precomputed :func:`ecs_analysis` of ``mechanism`` with these conventions.

    Returns:
        :class:`EcsParameters` (SI) with a derivation record.

    Raises:
        ConfigError: unknown contact or source, an unusable estimate (zero load, K or δ not
            positive), or ``ifm_stiffness="matched"`` with the paper's values (no load is
            published).
    """
    contact = contact_type(contact)
    conventions = conventions or EcsConventions()
    if source not in ("computed", "paper"):
        raise ConfigError(f"unknown ECS source {source!r}; use 'computed' or 'paper'")
    record: dict[str, Any] = {"contact": contact, "source": source}
    if source == "paper":
        published = PAPER_PUBLISHED[contact]
        k_lin, delta = published.stiffness, published.penetration
        damping = published.damping
        load = math.nan
        record["published"] = published.as_dict()
        rpm = mechanism.driver.speed * 30.0 / math.pi
        if not math.isclose(rpm, published.crank_speed_rpm, rel_tol=1e-6):
            record["warning"] = (
                f"the published values are for {published.crank_speed_rpm:g} RPM; the mechanism "
                f"runs at {rpm:.6g} RPM"
            )
        record["damping"] = "D as published (D/K = 0.01 s)"
    else:
        result = result or ecs_analysis(mechanism, conventions)
        est = result.estimate(contact)
        if not est.ok:
            raise ConfigError(
                f"ECS {contact} estimate at joint {est.joint!r} is unusable: {est.message}"
            )
        k_lin, delta, damping, load = est.stiffness, est.penetration, est.damping, est.load
        record["estimate"] = est.as_dict()
        record["conventions"] = conventions.as_dict()
        record["damping"] = f"D = {conventions.damping_ratio:g} s x K"
    mode = conventions.ifm_stiffness
    if mode == "paper":
        exponent = conventions.ifm_exponent
        stiffness = k_lin * MM ** (1.0 - exponent)
        record["ifm_stiffness"] = (
            f"paper: K = {k_lin * MM:.6g} N/mm kept as the number and read as N/mm^{exponent:g}"
            f" => k = {stiffness:.6g} N/m^{exponent:g} (a unit leap, not physics)"
        )
    elif mode == "linear":
        exponent, stiffness = 1.0, k_lin
        record["ifm_stiffness"] = f"linear: k = K = {k_lin:.6g} N/m, exponent 1"
    else:
        if source == "paper":
            raise ConfigError(
                "ifm_stiffness='matched' needs the contact load, which the paper does not "
                "publish; use source='computed' or ifm_stiffness='paper'/'linear'"
            )
        exponent = conventions.ifm_exponent
        stiffness = load / delta**exponent
        record["ifm_stiffness"] = (
            f"matched: k = F / delta^{exponent:g} = {load:.6g} N / ({delta:.6g} m)^{exponent:g}"
        )
    record["impact"] = "c_max = D, d_max = delta"
    record["restitution_method"] = "penalty p = K (linear, N/m)"
    return EcsParameters(
        contact=contact,
        source=source,
        stiffness=stiffness,
        exponent=exponent,
        c_max=damping,
        d_max=delta,
        penalty=k_lin,
        ecs_stiffness=k_lin,
        ecs_penetration=delta,
        ecs_damping=damping,
        derivation=MappingProxyType(record),
    )


# --- crank-speed sweep and the hysteresis comparison ------------------------------------------


@dataclass(frozen=True)
class EcsSweep:
    """K, δ, D and the hysteresis comparison over crank speed (SI).

    Attributes:
        mechanism: mechanism name.
        conventions: the conventions used.
        restitution: e of the comparison models.
        chi_models: χ(e) of each comparison model at ``restitution``
            (:func:`~jointplay.contact.ecs.comparison_factors`), dimensionless; the same values
            fill the table's ``chi_{model}`` columns.
        results: the :class:`EcsResult` at each speed.
        table: one row per speed. Columns: ``rpm``, ``load_N``, ``load_joint``,
            ``impact_velocity_m_s``; per contact c: ``K_{c}_N_per_m``, ``delta_{c}_m``,
            ``D_{c}_N_s_per_m``, ``chi_ecs_{c}``, ``e_eff_ecs_{c}`` (restitution of one
            impact with χ_ECS) and ``c_eq_{model}_{c}_N_s_per_m`` (χ(e) K δ/v0); per model
            ``chi_{model}``.
    """

    mechanism: str
    conventions: EcsConventions
    restitution: float
    chi_models: Mapping[str, float]
    results: tuple[EcsResult, ...]
    table: pd.DataFrame

    def paper_units_table(self) -> pd.DataFrame:
        """The table with K in N/mm, δ in mm and damping in N·s/mm (columns renamed)."""
        out = self.table.copy()
        names = {}
        for column in out.columns:
            if column.endswith("_N_per_m") or column.endswith("_N_s_per_m"):
                out[column] = out[column] * MM
                names[column] = column + "m"
            elif column.startswith("delta_") and column.endswith("_m"):
                out[column] = out[column] / MM
                names[column] = column + "m"
        return out.rename(columns=names)


def ecs_sweep(
    mechanism: Mechanism,
    speeds_rpm: Iterable[float],
    conventions: EcsConventions | None = None,
    *,
    restitution: float = 0.8,
    step_deg: float = 1.0,
) -> EcsSweep:
    """ECS values and hysteresis factors over crank speed (the paper's Fig. 6 discussion).

    Each speed runs the nominal analysis of ``mechanism`` with that constant crank speed.
    What is compared is defined in docs/ecs.md ("Hysteresis damping factor").

    Args:
        mechanism: the nominal mechanism.
        speeds_rpm: crank speeds, rev/min (each > 0).
        conventions: the open choices.
        restitution: e of the comparison models LN, HC, Flores, Hu–Guo.
        step_deg: crank-angle step of each nominal cycle, deg.

    Raises:
        ConfigError: no speed, a speed not positive, or e outside (0, 1].
    """
    conventions = conventions or EcsConventions()
    speeds = [float(s) for s in speeds_rpm]
    if not speeds:
        raise ConfigError("ecs_sweep: give at least one crank speed")
    for speed in speeds:
        if not (math.isfinite(speed) and speed > 0.0):
            raise ConfigError(f"ecs_sweep: crank speed must be finite and > 0 rpm, got {speed!r}")
    chi_models = comparison_factors(restitution)
    rows = []
    results = []
    for rpm in speeds:
        result = ecs_analysis(
            mechanism.with_driver(speed=rpm * math.pi / 30.0), conventions, step_deg=step_deg
        )
        results.append(result)
        v0 = result.impact_velocity
        row: dict[str, Any] = {
            "rpm": rpm,
            "load_N": result.overall.load.load,
            "load_joint": result.overall_joint,
            "impact_velocity_m_s": v0,
        }
        for contact in CONTACT_TYPES:
            est = result.estimate(contact)
            chi = result.hysteresis_factor(contact)
            row[f"K_{contact}_N_per_m"] = est.stiffness
            row[f"delta_{contact}_m"] = est.penetration
            row[f"D_{contact}_N_s_per_m"] = est.damping
            row[f"chi_ecs_{contact}"] = chi
            row[f"e_eff_ecs_{contact}"] = (
                effective_restitution(chi) if math.isfinite(chi) else math.nan
            )
            for name, chi_model in chi_models.items():
                row[f"c_eq_{name}_{contact}_N_s_per_m"] = (
                    chi_model * est.stiffness * est.penetration / v0 if v0 > 0 else math.nan
                )
        for name, chi_model in chi_models.items():
            row[f"chi_{name}"] = chi_model
        rows.append(row)
    return EcsSweep(
        mechanism=mechanism.name,
        conventions=conventions,
        restitution=float(restitution),
        chi_models=MappingProxyType(chi_models),
        results=tuple(results),
        table=pd.DataFrame(rows),
    )
