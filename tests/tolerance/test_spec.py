"""Tolerance specifications: the paper's stack, distributions, the [tolerances] table."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointplay.errors import ConfigError, StandardsError
from jointplay.model.mechanism import Mechanism
from jointplay.tolerance.spec import (
    JointTolerance,
    LinkTolerance,
    QuantityTolerance,
    Tolerance,
    ToleranceSpec,
    load_study_spec,
    parse_tolerance_table,
)

MM, UM = 1e-3, 1e-6


def test_paper_preset_carries_class_c_and_h8_g7(paper_fourbar: Mechanism) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    assert spec.names == (
        "length_crank",
        "length_coupler",
        "length_rocker",
        "length_ground",
        "clearance_O2",
        "clearance_A",
        "clearance_B",
        "clearance_O4",
    )
    half = (spec.upper - spec.lower) / 2
    # ISO 2768-1 c: ±0.8 mm for 30-120 mm (crank), ±1.2 mm for 120-400 mm; the paper's ±4.4 mm
    # stack is their sum.
    np.testing.assert_allclose(half[:4] / MM, [0.8, 1.2, 1.2, 1.2], rtol=1e-12)
    assert half[:4].sum() / MM == pytest.approx(4.4)
    # Ø10 H8/g7: radial clearance 2.5 ... 21 µm; nominal = mid-range.
    np.testing.assert_allclose(spec.lower[4:] / UM, 2.5, rtol=1e-9)
    np.testing.assert_allclose(spec.upper[4:] / UM, 21.0, rtol=1e-9)
    np.testing.assert_allclose(spec.nominal[4:] / UM, 11.75, rtol=1e-9)
    assert spec["clearance_A"].journal_radius == pytest.approx(5 * MM)  # type: ignore[union-attr]
    assert spec["clearance_A"].fit == "H8/g7"  # type: ignore[union-attr]
    assert spec["length_crank"].source == "ISO 2768-1 c"


def test_general_class_c_gives_the_presets_explicit_limits(paper_fourbar: Mechanism) -> None:
    explicit = ToleranceSpec.from_mechanism(paper_fourbar, fits=False)
    general = parse_tolerance_table({"general": "c", "fits": False}, paper_fourbar)
    assert general.names == explicit.names
    np.testing.assert_allclose(general.lower, explicit.lower, rtol=1e-12)
    np.testing.assert_allclose(general.upper, explicit.upper, rtol=1e-12)


@pytest.mark.parametrize(
    ("distribution", "std_over_h"),
    [("uniform", 1 / math.sqrt(3)), ("triangular", 1 / math.sqrt(6)), ("normal", 1 / 3)],
)
def test_distribution_moments(distribution: str, std_over_h: float) -> None:
    t = Tolerance((1.0, 3.0), distribution)  # type: ignore[arg-type]
    assert t.mean == pytest.approx(2.0)
    assert t.std == pytest.approx(std_over_h, rel=1e-12)
    assert t.ppf(0.5) == pytest.approx(2.0)
    u = np.linspace(0.001, 0.999, 999)
    values = t.ppf(u)
    assert np.all(np.diff(values) > 0), "the inverse CDF must increase"
    if distribution != "normal":
        assert values.min() >= 1.0 and values.max() <= 3.0


def test_process_shift_and_cpk_set_mean_and_sigma() -> None:
    shifted = Tolerance((-1.0, 1.0), "normal", shift=0.25, cpk=1.5)
    # Cpk = min(USL - mu, mu - LSL) / (3 sigma) = (1 - 0.25) / (3 sigma) = 1.5
    assert shifted.mean == pytest.approx(0.25)
    assert shifted.std == pytest.approx(0.75 / 4.5)
    assert Tolerance((-1.0, 1.0), "uniform", shift=0.1).ppf(0.0) == pytest.approx(-0.9)


def test_truncated_normal_moments_match_a_large_sample() -> None:
    # A clearance range near zero: the normal is truncated at 0 (physical bound).
    t = Tolerance((0.0, 2.0), "normal", shift=-0.9, bounds=(0.0, math.inf))
    values = t.ppf((np.arange(200_000) + 0.5) / 200_000)
    assert values.min() >= 0.0
    # Midpoint quadrature of the inverse CDF: accurate to ~1e-4 relative here.
    assert values.mean() == pytest.approx(t.mean, rel=1e-3)
    assert values.std() == pytest.approx(t.std, rel=1e-3)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"limits": (2.0, 1.0)}, "lower <= upper"),
        ({"limits": (0.0, 1.0), "distribution": "cauchy"}, "distribution must be one of"),
        ({"limits": (0.0, 1.0), "distribution": "uniform", "cpk": 1.33}, "cpk applies"),
        ({"limits": (0.0, 1.0), "cpk": 1.0, "shift": 0.6}, "shift"),
        ({"limits": (0.0, 1.0), "distribution": "uniform", "bounds": (0.2, 5.0)}, "bounds"),
    ],
)
def test_tolerance_validation_names_the_problem(kwargs: dict, message: str) -> None:
    with pytest.raises(ConfigError, match=message):
        Tolerance(**kwargs)


def test_interference_fits_are_refused() -> None:
    with pytest.raises(ConfigError, match="interference fit"):
        JointTolerance.from_fit("A", "H7/s6", 0.010)
    with pytest.raises(StandardsError):
        JointTolerance.from_fit("A", "H8/q7", 0.010)


def test_duplicate_inputs_are_refused() -> None:
    t = LinkTolerance.from_deviations("crank", 0.1, -1e-4, 1e-4)
    with pytest.raises(ConfigError, match="given twice"):
        ToleranceSpec((t, t))
    with pytest.raises(ConfigError, match="letters, digits"):
        QuantityTolerance("a-b", 0.0, Tolerance((0.0, 1.0)))


def test_tolerance_table_reads_every_form(paper_fourbar: Mechanism) -> None:
    table = {
        "distribution": "uniform",
        "lengths": {
            "crank": {"lower": "-0.1 mm", "upper": "0.3 mm", "distribution": "normal"},
            "coupler": {"class": "m", "shift": "0.05 mm"},
            "rocker": {
                "lower": "-1 mm",
                "upper": "1 mm",
                "distribution": "normal",
                "cpk": 1.33,
                "source": "drawing 42",
            },
        },
        "joints": {
            "A": {"fit": "H7/g6"},
            "B": {"clearance_min": "5 um", "clearance_max": "30 um"},
            "O4": {"distribution": "triangular"},
        },
    }
    spec = parse_tolerance_table(table, paper_fourbar)
    assert spec.names == (
        "length_crank",
        "length_coupler",
        "length_rocker",
        "clearance_O2",
        "clearance_A",
        "clearance_B",
        "clearance_O4",
    )
    crank = spec["length_crank"].tolerance
    assert crank.limits == pytest.approx((0.1079, 0.1083))
    assert crank.distribution == "normal"
    coupler = spec["length_coupler"]
    assert coupler.source == "ISO 2768-1 m"
    assert coupler.tolerance.half_width == pytest.approx(0.5 * MM)  # class m, 120-400 mm
    assert coupler.tolerance.distribution == "uniform"
    assert coupler.tolerance.mean == pytest.approx(0.2705 + 0.05 * MM)
    assert spec["length_rocker"].tolerance.cpk == pytest.approx(1.33)
    assert spec["length_rocker"].source == "drawing 42"
    assert spec["clearance_A"].tolerance.limits == pytest.approx((2.5 * UM, 14.5 * UM))
    assert spec["clearance_B"].tolerance.limits == pytest.approx((5 * UM, 30 * UM))
    assert spec["clearance_O4"].tolerance.distribution == "triangular"
    assert spec["clearance_O2"].tolerance.distribution == "uniform"  # the table's default


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"lenghts": {}}, r"unknown key\(s\) \['lenghts'\]"),
        ({"lengths": {"crank": {"lower": "-1 mm", "upper": "1 mm", "tol": 1}}}, "'tol'"),
        ({"lengths": {"slider": {"class": "m"}}}, "unknown length 'slider'"),
        ({"lengths": {"crank": {"class": "m", "lower": "-1 mm"}}}, "not both"),
        ({"lengths": {"crank": {"lower": "-1", "upper": "1 mm"}}}, "has no unit"),
        ({"lengths": {"crank": {"class": "x"}}}, r"tolerances.lengths.crank: .*class"),
        ({"joints": {"C": {"fit": "H7/g6"}}}, "unknown revolute joint 'C'"),
        ({"joints": {"A": {"clearance_min": "1 um"}}}, "both clearance_min and clearance_max"),
        ({"distribution": "gauss"}, "distribution must be one of"),
    ],
)
def test_tolerance_table_errors_name_table_and_key(
    paper_fourbar: Mechanism, table: dict, message: str
) -> None:
    with pytest.raises((ConfigError, StandardsError), match=message):
        parse_tolerance_table(table, paper_fourbar)


def test_config_file_with_extended_tolerances(tmp_path) -> None:
    from jointplay.io.config import preset_text

    text = preset_text("paper-fourbar").split("# Link-length tolerances")[0]
    text += """
[tolerances]
distribution = "uniform"

[tolerances.lengths.crank]
lower = "-0.8 mm"
upper = "0.8 mm"
source = "ISO 2768-1 c"
shift = "0.2 mm"

[tolerances.lengths.ground]
class = "c"

[tolerances.joints.O2]
clearance_min = "10 um"
clearance_max = "40 um"
"""
    path = tmp_path / "mine.toml"
    path.write_text(text)
    mechanism, spec = load_study_spec(config=path)
    # The mechanism records every length tolerance, the class entries included.
    assert [t.length for t in mechanism.tolerances] == ["crank", "ground"]
    assert mechanism.tolerances[1].upper == pytest.approx(1.2 * MM)
    assert spec.names[:2] == ("length_crank", "length_ground")
    assert spec["length_crank"].tolerance.mean == pytest.approx(0.108 + 0.2 * MM)
    assert spec["clearance_O2"].tolerance.limits == pytest.approx((10 * UM, 40 * UM))
    assert spec["clearance_A"].tolerance.distribution == "uniform"


def test_with_distribution_and_only(paper_fourbar: Mechanism) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar).with_distribution("triangular")
    assert {t.tolerance.distribution for t in spec.inputs} == {"triangular"}
    assert spec.only("clearance").names == (
        "clearance_O2",
        "clearance_A",
        "clearance_B",
        "clearance_O4",
    )
    described = spec.describe()["length_crank"]
    assert described["limits"] == pytest.approx([0.1072, 0.1088])
    assert described["distribution"] == "triangular"
