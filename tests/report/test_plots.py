"""`jointplay simulate`'s figures: start-up and analysed revolutions apart, the slider drawn,
orbits to scale; and the ECS figures' print copies."""

from __future__ import annotations

import numpy as np
import pytest

from jointplay.dynamics.setup import clearance_joints
from jointplay.dynamics.simulate import Start, simulate
from jointplay.io.config import load_preset
from jointplay.report.plots import _panels, simulation_figures


def test_panels_split_the_start_up_from_the_analysed_revolutions() -> None:
    crank = np.linspace(0.0, 1080.0, 1001)
    (label_a, startup), (label_b, analysed) = _panels(crank, 720.0)
    assert "start-up" in label_a and label_b == "analysed"
    assert np.array_equal(startup, crank < 720.0) and np.array_equal(analysed, ~startup)
    # no settling revolutions but a start from rest: the first 30° apart
    (_, early), (_, later) = _panels(crank, 0.0)
    assert crank[early].max() <= 30.0 and crank[later].min() > 30.0
    # nothing known about the start: one panel over everything
    ((label, everything),) = _panels(crank, None)
    assert label == "" and everything.all()


@pytest.fixture(scope="module")
def slider_run():
    """A slider-crank with clearance at its piston pin: one settling revolution, a quarter
    analysed (a fraction of a second)."""
    mechanism = load_preset("flores-slider-crank")
    joints = clearance_joints(mechanism, ["B"], clearance=0.5e-3)
    return simulate(
        mechanism, joints, revolutions=0.25, settle=1, start=Start("steady"), nominal=True
    )


def test_simulation_figures_draw_the_slider_and_the_orbit(slider_run, tmp_path) -> None:
    written = simulation_figures(slider_run, tmp_path, "slider-crank", figure_format="svg")
    names = {p.name for p in written}
    assert {"angular_velocity.png", "joint_forces.png", "journal_orbits.png"} <= names
    assert {"slider_x.png", "slider_v.png", "slider_a.png"} <= names
    assert all((tmp_path / n).with_suffix(".svg").stat().st_size > 0 for n in names)
    # each line is thinned: no SVG path carries the integrator's every step
    svg = (tmp_path / "slider_v.svg").read_text()
    assert svg.count(" L ") < 3 * 1000 * 4 + 100
