"""What every response of a tolerance or design study means, in one sentence each.

Reports and ``summary.json`` files list these beside the numbers, so that a name such as
``path_deviation_mid`` is defined where it is reported. Names follow the response models of
:mod:`jointplay.tolerance.responses` and the design study (:mod:`jointplay.study.design`);
a name with a placeholder (a link number, a joint, a coupler point, a slider) is matched by
pattern. Units are SI (the ``unit`` of each response); angles are measured counter-clockwise
from the ground line O2→O4.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

__all__ = ["RESPONSE_DEFINITIONS", "response_definition", "response_definitions"]

_LINK = {"2": "the crank (link 2)", "3": "the coupler (link 3)", "4": "the rocker (link 4)"}

#: Definitions of the responses with fixed names.
RESPONSE_DEFINITIONS: dict[str, str] = {
    "rocker_swing": ("angle the rocker sweeps between its two limit positions over one crank turn"),
    "transmission_angle_min": (
        "smallest of μ and 180° − μ over one crank turn, μ being the angle between coupler and "
        "rocker (exact: the extremes lie where the crank is collinear with the ground link); "
        "the usual design guideline keeps it at 40° or more"
    ),
    "torque_peak": ("largest |driving torque| on the crank over the analysed revolutions"),
    "rocker_speed_error": (
        "largest deviation of the rocker's angular velocity from the nominal ideal-joint "
        "mechanism's at the same crank angle over the analysed revolution, as a fraction of "
        "the largest ideal value (1 = 100 %)"
    ),
    "joint_force": "largest peak contact force of a pin on its bearing, over all joints",
    "contact_pressure": (
        "largest peak Hertz line-contact pressure over all joints (the force over the "
        "bearing width, conformal cylinders)"
    ),
    "wear_rate": ("fastest Archard growth of a radial clearance over all joints, while running"),
    "life": (
        "running time until the first joint's radial clearance grows past its limit at its "
        "wear rate"
    ),
    "functional_life": (
        "running time until the mechanism's first other requirement (or clearance limit) "
        "fails as it wears, the dynamics re-simulated as its clearances grow; censored at the "
        "hours of its B_p requirement"
    ),
}

#: Definitions by pattern: (regular expression, definition with {groups}).
_PATTERNS: tuple[tuple[str, str], ...] = (
    (r"theta(\d+)_min", "smallest angle of {link} over one crank turn"),
    (r"theta(\d+)_max", "largest angle of {link} over one crank turn"),
    (r"omega(\d+)_peak", "largest |angular velocity| of {link}"),
    (r"alpha(\d+)_peak", "largest |angular acceleration| of {link}"),
    (
        r"path_deviation_(.+)",
        "largest distance, over one crank turn, between coupler point '{0}' and the same "
        "point of the nominal linkage at the same crank angle",
    ),
    (r"F_(.+)_peak", "largest force transmitted by joint {0} (pin on bearing)"),
    (r"wear_rate_(.+)", "Archard growth rate of the radial clearance of joint {0}"),
    (r"(.+)_stroke", "stroke of slider '{0}': the range of its position over one crank turn"),
    (r"(.+)_v_peak", "largest |velocity| of slider '{0}'"),
    (r"(.+)_a_peak", "largest |acceleration| of slider '{0}'"),
)


def response_definition(name: str) -> str:
    """The one-sentence definition of response ``name`` ("" for an unknown name).

    Peaks (``*_peak``) are over one crank turn for the kinematic responses (ideal joints)
    and over the analysed revolutions, after the start-up, for the dynamic ones.
    """
    if name in RESPONSE_DEFINITIONS:
        return RESPONSE_DEFINITIONS[name]
    for pattern, text in _PATTERNS:
        found = re.fullmatch(pattern, name)
        if found:
            group = found.group(1)
            return text.format(group, link=_LINK.get(group, f"link {group}"))
    return ""


def response_definitions(names: Iterable[str]) -> dict[str, str]:
    """``{name: definition}`` for ``names`` (in order; unknown names get "")."""
    return {name: response_definition(name) for name in names}
