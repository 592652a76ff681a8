"""The [tolerances] table of a configuration file: every form, errors naming table and key."""

from __future__ import annotations

import numpy as np
import pytest

from jointplay.errors import ConfigError, StandardsError
from jointplay.io.config import load_study_spec
from jointplay.io.tolerances import parse_tolerance_table
from jointplay.model.mechanism import Mechanism
from jointplay.tolerance.spec import ToleranceSpec

MM, UM = 1e-3, 1e-6


def test_general_class_c_gives_the_presets_explicit_limits(paper_fourbar: Mechanism) -> None:
    explicit = ToleranceSpec.from_mechanism(paper_fourbar, fits=False)
    general = parse_tolerance_table({"general": "c", "fits": False}, paper_fourbar)
    assert general.names == explicit.names
    np.testing.assert_allclose(general.lower, explicit.lower, rtol=1e-12)
    np.testing.assert_allclose(general.upper, explicit.upper, rtol=1e-12)


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
        (
            {"lenghts": {}},
            r"unknown key 'lenghts' \(did you mean 'lengths'\?\); allowed keys: distribution, fits, general, joints, lengths",
        ),
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
