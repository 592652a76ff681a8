"""A JSON-ready description of a resolved mechanism (SI), for provenance records."""

from __future__ import annotations

import math
from typing import Any

from jointplay.model.mechanism import Mechanism, RevoluteJoint


def mechanism_summary(mechanism: Mechanism) -> dict[str, Any]:
    """A JSON-ready description of the resolved mechanism (SI), for provenance records."""
    spec = mechanism.template
    out: dict[str, Any] = {
        "name": mechanism.name,
        "template": getattr(getattr(spec, "geometry", None), "kind", "general"),
        "branch": mechanism.branch,
        "gravity_m_s2": list(mechanism.gravity),
        "driver": {
            "link": mechanism.driver.link,
            "speed_rad_s": mechanism.driver.speed,
            "speed_rpm": mechanism.driver.speed * 30.0 / math.pi,
            "direction": "ccw" if mechanism.driver.direction == 1 else "cw",
            "start_angle_deg": math.degrees(mechanism.driver.start_angle),
        },
        "links": {
            link.name: {
                "mass_kg": link.mass,
                "inertia_kg_m2": link.inertia,
                "com_m": list(link.com),
                "points_m": {k: list(v) for k, v in link.points.items()},
            }
            for link in mechanism.links
        },
        "ground_points_m": {k: list(v) for k, v in mechanism.ground.points.items()},
        "joints": {
            joint.name: {
                "type": joint.kind,
                "between": [f"{joint.link_a}.{joint.point_a}", f"{joint.link_b}.{joint.point_b}"],
                **(
                    {"fit": {k: v for k, v in vars(joint.fit).items() if v is not None}}
                    if isinstance(joint, RevoluteJoint) and joint.fit is not None
                    else {}
                ),
            }
            for joint in mechanism.joints
        },
        "tolerances_m": {t.length: [t.lower, t.upper] for t in mechanism.tolerances},
    }
    if spec is not None:
        out["geometry_m"] = spec.geometry.lengths  # type: ignore[attr-defined]
    return out
