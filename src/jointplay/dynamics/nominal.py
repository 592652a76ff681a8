"""The nominal (ideal-joint) analysis of a mechanism over one crank revolution.

Kinematics plus inverse dynamics, tabulated one row per crank degree with the documented
columns, and a summary of ranges, extremes and the linkage's classification.

Column conventions: ``crank_deg`` is the crank angle in degrees counter-clockwise from the
ground line, unwrapped from the start angle (a clockwise crank counts down);
``theta{k}_deg`` link angles (deg, counter-clockwise from the ground line); ``omega{k}``
(rad/s, counter-clockwise positive); ``alpha{k}`` (rad/s²); ``F_{joint}`` the magnitude of the
joint reaction (N); ``torque`` the motor torque on the crank (N·m, counter-clockwise positive).
Sliders add ``{link}_x``, ``{link}_v``, ``{link}_a`` (m, m/s, m/s², along the guide) and
prismatic joints ``M_{joint}`` (the constraint couple, N·m). Extra named points on a link add
``{point}_x``, ``{point}_y`` (m).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd

from jointplay.dynamics.inverse import InverseDynamicsResult, inverse_dynamics
from jointplay.kinematics import fourbar, slidercrank
from jointplay.kinematics.analysis import KinematicsResult, analyse, cycle_angles
from jointplay.model.columns import rotating_links, sliders
from jointplay.model.mechanism import Mechanism
from jointplay.model.summary import mechanism_summary
from jointplay.model.templates import FourBarGeometry, SliderCrankGeometry, TemplateSpec


@dataclass(frozen=True)
class NominalResult:
    """Kinematics and inverse dynamics of the ideal mechanism over one revolution."""

    kinematics: KinematicsResult
    dynamics: InverseDynamicsResult
    table: pd.DataFrame
    summary: dict[str, Any]


def nominal_analysis(
    mechanism: Mechanism, *, step_deg: float = 1.0, method: str = "auto"
) -> NominalResult:
    """Analyse ``mechanism`` with ideal joints at ``step_deg`` crank-angle steps over 360°."""
    kin = analyse(mechanism, cycle_angles(mechanism, step_deg), method=method)  # type: ignore[arg-type]
    dyn = inverse_dynamics(kin)
    table = kinematics_table(kin, dyn)
    return NominalResult(kin, dyn, table, summarize(kin, dyn, table))


def kinematics_table(kin: KinematicsResult, dyn: InverseDynamicsResult) -> pd.DataFrame:
    """One row per analysed crank angle with the documented columns (see the module docstring)."""
    mechanism = kin.mechanism
    columns: dict[str, np.ndarray] = {"crank_deg": np.degrees(kin.crank_angle)}
    numbers = dict(rotating_links(mechanism))
    rotating = list(numbers)
    for name in rotating:
        angle = np.unwrap(kin.q[:, 3 * kin.flat.body_index(name) + 2])
        angle += (
            2
            * math.pi
            * np.round((np.arctan2(np.sin(angle[0]), np.cos(angle[0])) - angle[0]) / (2 * math.pi))
        )
        columns[f"theta{numbers[name]}_deg"] = np.degrees(angle)
    for name in rotating:
        columns[f"omega{numbers[name]}"] = kin.omega(name)
    for name in rotating:
        columns[f"alpha{numbers[name]}"] = kin.alpha(name)
    for joint in sliders(mechanism):
        origin = np.array(mechanism.ground.point(joint.point_a))
        axis = np.array([math.cos(joint.axis_angle), math.sin(joint.axis_angle)])
        pos, vel, acc = kin.point(joint.link_b, joint.point_b)
        columns[f"{joint.link_b}_x"] = (pos - origin) @ axis
        columns[f"{joint.link_b}_v"] = vel @ axis
        columns[f"{joint.link_b}_a"] = acc @ axis
    for link in mechanism.links:
        joint_points = {j.point_a for j in mechanism.joints if j.link_a == link.name} | {
            j.point_b for j in mechanism.joints if j.link_b == link.name
        }
        for point in link.points:
            if point not in joint_points:
                pos, _, _ = kin.point(link.name, point)
                columns[f"{point}_x"], columns[f"{point}_y"] = pos[:, 0], pos[:, 1]
    for j, name in enumerate(dyn.joint_names):
        columns[f"F_{name}"] = dyn.magnitude[:, j]
    for prismatic in sliders(mechanism):
        columns[f"M_{prismatic.name}"] = dyn.couple[:, dyn.joint_names.index(prismatic.name)]
    columns["torque"] = dyn.torque
    return pd.DataFrame(columns)


def column_extremes(table: pd.DataFrame) -> dict[str, dict[str, float]]:
    """min / max / largest |value| of every column, with the crank angle where each occurs."""
    out = {}
    crank = table["crank_deg"].to_numpy()
    for column in table.columns:
        if column == "crank_deg":
            continue
        values = table[column].to_numpy()
        i_min, i_max, i_abs = (
            int(np.argmin(values)),
            int(np.argmax(values)),
            int(np.argmax(np.abs(values))),
        )
        out[column] = {
            "min": float(values[i_min]),
            "min_at_crank_deg": float(crank[i_min]),
            "max": float(values[i_max]),
            "max_at_crank_deg": float(crank[i_max]),
            "peak_abs": float(abs(values[i_abs])),
            "peak_abs_at_crank_deg": float(crank[i_abs]),
        }
    return out


def summarize(
    kin: KinematicsResult, dyn: InverseDynamicsResult, table: pd.DataFrame
) -> dict[str, Any]:
    """Ranges and extremes of every column, classification and the template's key figures."""
    mechanism = kin.mechanism
    force_columns = [c for c in table.columns if c.startswith("F_")]
    forces = table[force_columns].to_numpy()
    i, j = np.unravel_index(np.argmax(forces), forces.shape)
    summary: dict[str, Any] = {
        "mechanism": mechanism.name,
        "crank_speed_rpm": mechanism.driver.speed * 30 / math.pi,
        "crank_direction": "ccw" if mechanism.driver.direction == 1 else "cw",
        "gravity_m_s2": list(mechanism.gravity),
        "kinematics_method": kin.method,
        "rows": len(table),
        "largest_joint_force": {
            "joint": force_columns[j].removeprefix("F_"),
            "value_N": float(forces[i, j]),
            "crank_deg": float(table["crank_deg"].iloc[i]),
        },
        "peak_torque_Nm": float(np.max(np.abs(dyn.torque))),
        "columns": column_extremes(table),
    }
    spec = mechanism.template
    if isinstance(spec, TemplateSpec) and isinstance(spec.geometry, FourBarGeometry):
        summary.update(_fourbar_figures(spec.geometry, mechanism, kin))
    elif isinstance(spec, TemplateSpec) and isinstance(spec.geometry, SliderCrankGeometry):
        x = table["slider_x"].to_numpy()
        summary["slider_stroke_m"] = float(x.max() - x.min())
        slidercrank.check_full_rotation(spec.geometry)
    summary["configuration"] = mechanism_summary(mechanism)
    return summary


def _fourbar_figures(
    geometry: FourBarGeometry, mechanism: Mechanism, kin: KinematicsResult
) -> dict[str, Any]:
    info = fourbar.grashof(geometry)
    mu = np.degrees(fourbar.transmission_angle(geometry, kin.crank_angle))
    figures: dict[str, Any] = {
        "grashof": {"class": info.kind, "grashof": info.grashof, "margin_mm": info.margin * 1e3},
        "transmission_angle_deg": {"min": float(mu.min()), "max": float(mu.max())},
    }
    if info.kind == "crank-rocker":
        limits = fourbar.rocker_limit_positions(geometry, mechanism.branch)
        swing = abs(math.degrees(limits[0].rocker_angle - limits[1].rocker_angle))
        figures["rocker_swing_deg"] = swing
        figures["rocker_limit_positions"] = [
            {
                "name": lp.name,
                "crank_deg": math.degrees(lp.crank_angle),
                "rocker_deg": math.degrees(lp.rocker_angle),
            }
            for lp in limits
        ]
        figures["dead_centres"] = (
            "none for the crank as input (Grashof crank-rocker); driven from the rocker, the "
            "limit positions are dead centres"
        )
    return figures
