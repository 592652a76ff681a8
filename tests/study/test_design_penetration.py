"""Non-physical samples in the design study: every scheme counts its samples whose pins sink
deeper than the radial clearance, and the study warns once per joint concerned.

Fast settings, as in tests/tolerance/test_penetration.py: the paper's four-bar from its
steady motion, no start-up revolution left out, a quarter of a crank turn, 4 samples of two
schemes. The IMPACT stiffness sets the outcome (penetration ∝ k^(-2/3) at a given load):
1e2 N/mm^1.5 is absurdly soft (every pin sinks 1.2 to 30 times its clearance, whatever the
fit), 1e5 N/mm^1.5 lets the pins of the tight H7/g6 (radial clearance 2.5 to 14.5 µm) pass
their clearance in some samples but not those of the loose H11/c11 (40 to 130 µm), and
1e6 N/mm^1.5 keeps every pin of both inside (ratios below 0.9).
"""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

from jointplay.contact.laws import ContactLaw, get_law
from jointplay.model.mechanism import Mechanism
from jointplay.report.design import write_design
from jointplay.study.design import DesignResult, design_study, design_units
from jointplay.tolerance.execution import Backend

JOINTS = ("O2", "A", "B", "O4")
FAST = {"settle": 0, "revolutions": 0.25}
SERIAL = Backend("serial")
SAMPLES = 4
TIGHT, LOOSE = "H7/g6 / m", "H11/c11 / m"
#: every scheme meets it: the cheapest, the loose fit, is recommended
EASY = ["joint_force <= 1 kN"]
#: 4 failure-free samples show a yield of at least 0.025^(1/4) = 39.8 % (95 %): a level
#: they can decide, so that a scheme is recommended
CONFIDENCE = 0.3
#: The check of this file (the elastic one, penetration-exceeds-elastic, warns beside it for
#: these IMPACT stiffnesses, 5 to 1000 times softer than the joints' Hertz law).
CODE = "penetration-exceeds-clearance"


def _clearance_findings(result: DesignResult) -> list:
    return [f for f in result.diagnostics if f.diagnostic.code == CODE]


def _impact(k_n_per_mm15: float) -> ContactLaw:
    """The paper's IMPACT law with stiffness ``k`` in N/mm^1.5 (SI inside)."""
    return get_law(
        "impact", stiffness=k_n_per_mm15 * 1000**1.5, exponent=1.5, c_max=1e4, d_max=1e-4
    )


def _design(mechanism: Mechanism, k: float, requirements=EASY) -> DesignResult:
    return design_study(
        mechanism, ["H7/g6", "H11/c11"], ["m"], requirements, samples=SAMPLES, seed=0,
        confidence=CONFIDENCE, contact=_impact(k), backend=SERIAL, **FAST,
    )  # fmt: skip


def _beyond(result: DesignResult) -> dict[str, dict[str, np.ndarray]]:
    """scheme -> joint -> which successful samples have ratio > 1, from ``samples`` alone."""
    out: dict[str, dict[str, np.ndarray]] = {}
    for scheme, part in result.samples.groupby("scheme", sort=False):
        ok = (part["status"] == "ok").to_numpy()
        out[str(scheme)] = {
            j: ok & (part[f"penetration_ratio_{j}"].to_numpy() > 1.0) for j in JOINTS
        }
    return out


@pytest.fixture(scope="module")
def soft(paper_fourbar: Mechanism) -> DesignResult:
    return _design(paper_fourbar, 1e2)


@pytest.fixture(scope="module")
def borderline(paper_fourbar: Mechanism) -> DesignResult:
    return _design(paper_fourbar, 1e5)


@pytest.mark.parametrize("what", ["soft", "borderline"])
def test_each_scheme_counts_its_samples_beyond_the_clearance(request, what: str) -> None:
    result: DesignResult = request.getfixturevalue(what)
    beyond = _beyond(result)
    assert result.best == LOOSE and set(beyond) == {TIGHT, LOOSE}
    assert (result.samples["status"] == "ok").all()  # so the largest ratio is of them all
    table = result.table.set_index("scheme")
    samples = result.samples.set_index(["scheme", "sample"])
    for scheme, joints in beyond.items():
        for joint, mask in joints.items():
            ratio = samples.loc[scheme, f"penetration_ratio_{joint}"].to_numpy()
            assert table.loc[scheme, f"penetration_exceeds_{joint}"] == int(mask.sum())
            assert table.loc[scheme, f"penetration_ratio_max_{joint}"] == ratio.max()
    tight = np.array([beyond[TIGHT][j] for j in JOINTS])
    loose = np.array([beyond[LOOSE][j] for j in JOINTS])
    if what == "soft":  # every pin of every sample of either fit
        assert tight.all() and loose.all()
    else:  # the tight fit only, and not in every sample: the count is a real count
        assert tight.any() and not tight.all() and not loose.any()


@pytest.mark.parametrize("what", ["soft", "borderline"])
def test_one_warning_per_joint_beyond_the_clearance_names_the_worst_scheme(
    request, what: str
) -> None:
    result: DesignResult = request.getfixturevalue(what)
    beyond = _beyond(result)
    frame = result.samples
    ok = (frame["status"] == "ok").to_numpy()
    concerned = [j for j in JOINTS if any(beyond[s][j].any() for s in beyond)]
    findings = {f.diagnostic.joint: f for f in _clearance_findings(result)}
    assert list(findings) == concerned and concerned
    inputs = [c for c in frame.columns if c.startswith(("length_", "clearance_"))]
    for joint, finding in findings.items():
        count = sum(int(beyond[s][joint].sum()) for s in beyond)
        schemes = sum(1 for s in beyond if beyond[s][joint].any())
        ratio = np.where(ok, frame[f"penetration_ratio_{joint}"].to_numpy(), np.nan)
        worst = int(np.nanargmax(ratio))
        d = finding.diagnostic
        assert (d.level, d.code, d.limit) == ("warning", "penetration-exceeds-clearance", 1.0)
        assert d.value == ratio[worst] > 1.0
        assert (finding.count, finding.out_of) == (count, 2 * SAMPLES)
        assert (finding.schemes, finding.out_of_schemes) == (schemes, 2)
        assert finding.worst_scheme == frame["scheme"].iloc[worst]
        assert finding.worst_sample == frame["sample"].iloc[worst]
        assert finding.worst_inputs == {n: frame[n].iloc[worst] for n in inputs}
        assert finding.best == LOOSE
        assert finding.best_count == int(beyond[LOOSE][joint].sum())
        assert d.message.startswith(
            f"{count} of {2 * SAMPLES} samples ({100 * count / (2 * SAMPLES):.3g} %) in "
            f"{schemes} of 2 schemes: the pin of {joint} penetrates its bearing by up to "
            f"{d.value:.3g} times the radial clearance (scheme {finding.worst_scheme}, sample "
            f"{finding.worst_sample}; "
        )
        assert "not physical" in d.message and "stiffness law" in d.message
        if what == "soft":  # the recommended scheme is concerned, and the warning says so
            assert finding.best_concerned and finding.best_count == SAMPLES
            assert f"the recommended scheme {LOOSE} is concerned ({SAMPLES} of its " in d.message
        else:
            assert not finding.best_concerned
            assert f"the recommended scheme {LOOSE} is not concerned" in d.message
            assert finding.worst_scheme == TIGHT


def test_without_a_recommended_scheme_the_warning_names_none(paper_fourbar) -> None:
    result = _design(paper_fourbar, 1e2, ["joint_force <= 1 N"])
    assert result.best is None and result.binding == "joint_force <= 1 N"
    assert len(_clearance_findings(result)) == len(JOINTS)
    for finding in result.diagnostics:
        assert finding.best is None and not finding.best_concerned
        assert "recommended" not in finding.diagnostic.message


def test_a_stiff_contact_warns_of_nothing_beyond_the_clearance(paper_fourbar, tmp_path) -> None:
    result = _design(paper_fourbar, 1e6)
    ratios = result.samples[[f"penetration_ratio_{j}" for j in JOINTS]].to_numpy()
    assert ((ratios > 0) & (ratios < 1)).all()
    assert _clearance_findings(result) == []
    assert [r for r in result.summary()["diagnostics"] if r["code"] == CODE] == []
    for joint in JOINTS:
        assert (result.table[f"penetration_exceeds_{joint}"] == 0).all()
    write_design(result, tmp_path, design_units(paper_fourbar, "dynamic"), plots=False)
    assert "penetration-exceeds-clearance" not in (tmp_path / "report.html").read_text()
    written = json.loads((tmp_path / "summary.json").read_text())["diagnostics"]
    assert [r for r in written if r["code"] == CODE] == []


def test_kinematic_designs_have_no_checks(paper_fourbar) -> None:
    result = design_study(
        paper_fourbar, ["H7/g6"], ["m"], ["omega4_peak <= 100 rad/s"], samples=4,
        backend=SERIAL,
    )  # fmt: skip
    assert result.responses == "kinematic" and result.diagnostics == ()
    assert not any(c.startswith("penetration") for c in result.table.columns)
    assert not any(c.startswith("penetration") for c in result.samples.columns)
    assert result.summary()["diagnostics"] == []


def test_the_warning_is_where_the_user_reads_it(soft: DesignResult, tmp_path) -> None:
    """summary.json's diagnostics, the per-scheme columns of design.parquet and .csv, the
    per-sample ratios of samples.parquet and a callout under the report's verdict."""
    write_design(soft, tmp_path, design_units(soft.mechanism, "dynamic"), plots=False)
    written = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    records = [r for r in written["diagnostics"] if r["code"] == CODE]
    assert [r["joint"] for r in records] == list(JOINTS)
    record = records[0]
    finding = _clearance_findings(soft)[0]
    assert record["count"] == finding.count and record["worst_scheme"] == finding.worst_scheme
    assert record["best"] == LOOSE and record["best_concerned"] is True
    assert record["share"] == 1.0
    assert record["value"] == pytest.approx(finding.diagnostic.value, rel=1e-9)  # JSON: 12 digits
    # the other keys are those of a study without warnings
    assert set(written) - {"provenance"} == set(soft.summary())
    table = pd.read_parquet(tmp_path / "design.parquet")
    for joint in JOINTS:
        assert table[f"penetration_exceeds_{joint}"].tolist() == [SAMPLES, SAMPLES]
        assert (table[f"penetration_ratio_max_{joint}"] > 1).all()
    assert "penetration_exceeds_O2" in pd.read_csv(tmp_path / "design.csv")
    frame = pd.read_parquet(tmp_path / "samples.parquet")
    np.testing.assert_array_equal(
        frame["penetration_ratio_A"].to_numpy(), soft.samples["penetration_ratio_A"].to_numpy()
    )
    page = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert "Warning (penetration-exceeds-clearance, joint O2)" in page
    assert page.index("penetration-exceeds-clearance") < page.index("Schemes by cost")
    assert "samples beyond the clearance in O4" in page
