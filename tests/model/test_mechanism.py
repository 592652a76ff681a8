"""Validation of the mechanism model: every bad input names what is wrong."""

from __future__ import annotations

import math
from dataclasses import replace

import pytest

from jointplay.errors import ConfigError
from jointplay.model.mechanism import Driver, JointFit, Link, Material, RevoluteJoint
from jointplay.model.templates import FourBarGeometry, LinkBody, four_bar, template_of, with_lengths


def test_bar_inertia_is_that_of_a_rectangle() -> None:
    link = Link.bar("coupler", 0.2705, start="A", end="B", mass=0.26, width=0.022)
    assert link.inertia == pytest.approx(0.26 * (0.2705**2 + 0.022**2) / 12, rel=1e-15)
    assert link.com == (0.2705 / 2, 0.0)


def test_bar_mass_from_material() -> None:
    steel = Material("steel", 7801.0, 207e9, 0.29)
    link = Link.bar("x", 0.1, start="P", end="Q", width=0.02, thickness=0.01, material=steel)
    assert link.mass == pytest.approx(7801 * 0.1 * 0.02 * 0.01)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"mass": -1.0}, "mass"),
        ({"inertia": 0.0}, "inertia"),
        ({"points": {}}, "at least one"),
        ({"name": "ground"}, "ground"),
        ({"com": (1.0, math.nan)}, "com"),
    ],
)
def test_link_validation(kwargs: dict, message: str) -> None:
    base = {"name": "bar", "points": {"A": (0, 0)}, "mass": 1.0, "com": (0, 0), "inertia": 1.0}
    with pytest.raises(ConfigError, match=message):
        Link(**{**base, **kwargs})


def test_material_and_fit_validation() -> None:
    with pytest.raises(ConfigError, match="poisson_ratio"):
        Material("x", 1.0, 1.0, 0.6)
    with pytest.raises(ConfigError, match="clearance"):
        JointFit(diameter=0.01, clearance=-1e-6)
    with pytest.raises(ConfigError, match="speed"):
        Driver("crank", "O2", speed=0.0)


def test_mechanism_rejects_wrong_mobility(paper_fourbar) -> None:
    extra = RevoluteJoint("X", "crank", "A", "rocker", "B")
    with pytest.raises(ConfigError, match="degrees of freedom"):
        replace(paper_fourbar, joints=(*paper_fourbar.joints, extra))


def test_mechanism_rejects_unknown_points_and_links(paper_fourbar) -> None:
    bad = RevoluteJoint("A", "crank", "Z", "coupler", "A")
    with pytest.raises(ConfigError, match="no point 'Z'"):
        replace(paper_fourbar, joints=(paper_fourbar.joints[0], bad, *paper_fourbar.joints[2:]))
    with pytest.raises(ConfigError, match="no link"):
        paper_fourbar.link("slider")


def test_driver_must_be_on_a_ground_joint(paper_fourbar) -> None:
    with pytest.raises(ConfigError, match="revolute joint between the ground"):
        replace(paper_fourbar, driver=Driver("crank", "A", speed=1.0))


def test_with_lengths_rebuilds_and_keeps_the_rest(paper_fourbar) -> None:
    longer = with_lengths(paper_fourbar, crank=0.1088, ground=0.2782)
    geometry = template_of(longer).geometry
    assert isinstance(geometry, FourBarGeometry)
    assert geometry.crank == 0.1088 and geometry.ground == 0.2782 and geometry.coupler == 0.2705
    assert longer.link("crank").mass == paper_fourbar.link("crank").mass
    assert longer.link("crank").point("A") == (0.1088, 0.0)
    assert longer.driver == paper_fourbar.driver
    assert longer.joint("O2").fit == paper_fourbar.joint("O2").fit
    with pytest.raises(ConfigError, match="unknown length"):
        with_lengths(paper_fourbar, slider=0.1)


def test_four_bar_builder_rejects_fits_of_unknown_joints() -> None:
    with pytest.raises(ConfigError, match="unknown joint"):
        four_bar(
            FourBarGeometry(0.1, 0.3, 0.3, 0.3),
            speed=1.0,
            bodies={"crank": LinkBody(1.0)},
            fits={"Q": JointFit(0.01)},
        )


def test_the_model_bounds_gravity_and_the_start_angle(paper_fourbar) -> None:
    """The Python API as the options and the configuration: |g| <= 1000 m/s², the start
    angle within two turns either way (both were taken at 1e300)."""
    with pytest.raises(ConfigError, match=r"Driver: start_angle must lie within ±720°"):
        Driver("crank", "O2", 20.0, 1, 1e300)
    with pytest.raises(ConfigError, match="within ±720°"):
        Driver("crank", "O2", 20.0, 1, -4.0 * math.pi - 1e-9)
    assert Driver("crank", "O2", 20.0, 1, -4.0 * math.pi).start_angle == -4.0 * math.pi
    with pytest.raises(ConfigError, match=r"Mechanism: gravity must be at most 1000 m/s²"):
        paper_fourbar.with_gravity((0.0, -1e300))
    with pytest.raises(ConfigError, match="at most 1000 m/s²"):
        paper_fourbar.with_gravity((800.0, -800.0))  # 1131 m/s² in all
    assert paper_fourbar.with_gravity((0.0, -1000.0)).gravity == (0.0, -1000.0)
