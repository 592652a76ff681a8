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


def test_simulation_figures_draw_the_slider_and_the_orbit(
    slider_run, tmp_path, text_overlaps
) -> None:
    written = simulation_figures(slider_run, tmp_path, "slider-crank", figure_format="svg")
    assert text_overlaps and not any(text_overlaps.values()), text_overlaps
    names = {p.name for p in written}
    assert {"angular_velocity.png", "joint_forces.png", "journal_orbits.png"} <= names
    assert {"slider_x.png", "slider_v.png", "slider_a.png"} <= names
    assert all((tmp_path / n).with_suffix(".svg").stat().st_size > 0 for n in names)
    # each line is thinned: no SVG path carries the integrator's every step
    svg = (tmp_path / "slider_v.svg").read_text()
    assert svg.count(" L ") < 3 * 1000 * 4 + 100


def test_a_crank_angle_axis_reads_per_revolution() -> None:
    """Revolutions 3 and 4 of a run started at 0°: ticks 0-360 within each, and the
    revolutions named on the top edge, not 720-1080."""
    from jointplay.report._mpl import pyplot
    from jointplay.report.plots import revolution_axis

    plt = pyplot()
    fig, ax = plt.subplots()
    ax.plot([720.0, 1440.0], [0.0, 1.0])
    revolution_axis(ax, 0.0, 720.0, 1440.0)
    fig.canvas.draw()
    shown = [x for x in ax.get_xticks() if 720.0 <= x <= 1440.0]
    labels = [ax.xaxis.get_major_formatter()(x) for x in shown]
    assert labels and all(0 <= int(text) <= 360 for text in labels), labels
    assert labels[0] == "0" and labels[-1] == "360"
    names = [t.get_text() for t in ax.child_axes[0].get_xticklabels()]
    assert names == ["revolution 3", "revolution 4"]
    plt.close(fig)
