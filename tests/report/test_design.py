"""The design and wear report's figures."""

from __future__ import annotations

import math

import numpy as np

from jointplay.dynamics.wear import WearHistory
from jointplay.report.design import wear_plots, wear_profile_figure
from jointplay.report.figures import overlapping_text

JOINTS = ("O2", "A", "B", "O4")


def history() -> WearHistory:
    """A synthetic four-joint wear life: lobed worn profiles of a few µm."""
    theta = (np.arange(360) + 0.5) * 2 * math.pi / 360
    hours = (0.0, 50.0, 100.0)
    return WearHistory(
        rpm=200.0,
        limit=dict.fromkeys(JOINTS, 41e-6),
        hours=hours,
        clearance={j: (21e-6, 22e-6, 23e-6) for j in JOINTS},
        peak_force={j: (40.0, 41.0, 42.0) for j in JOINTS},
        speed_error=(0.01, 0.011, 0.012),
        growth_per_hour={j: (2e-8,) * 3 for j in JOINTS},
        bearing_profile={j: 3e-6 * np.abs(np.cos(k + theta)) ** 8 for k, j in enumerate(JOINTS)},
        journal_profile={j: 5e-6 * np.abs(np.sin(k + theta)) ** 8 for k, j in enumerate(JOINTS)},
        life=dict.fromkeys(JOINTS, 1000.0),
        life_extrapolated=dict.fromkeys(JOINTS, True),
        assumption="synthetic",
    )


def test_the_worn_profiles_have_no_colliding_labels() -> None:
    """Each panel's 0° once met the next panel's 180° (and the depth labels sat among the
    angle labels): the check found three collisions in that layout."""
    from jointplay.report._mpl import pyplot

    fig = wear_profile_figure(history())
    assert overlapping_text(fig) == []
    pyplot().close(fig)


def test_wear_plots_give_both_figures(text_overlaps) -> None:
    images = wear_plots(history())
    assert list(images) == ["wear_history.png", "wear_profiles.png"]
    assert not any(text_overlaps.values()), text_overlaps
