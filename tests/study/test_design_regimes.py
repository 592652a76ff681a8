"""A dynamic design reports its lubricated joints' regimes (issue 39, item 4): per scheme
and joint, the mean fractions of the analysed time in full film, mixed and boundary
lubrication over its successful samples and how many samples ever left full film, from the
samples' own fractions (``samples.parquet``); the report shows the chosen scheme's."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from jointplay.dynamics.setup import ContactModel
from jointplay.model.mechanism import Mechanism
from jointplay.report.design import write_design
from jointplay.study.design import design_study, design_units
from jointplay.tolerance.execution import Backend

JOINTS = ("O2", "A", "B", "O4")
FAST = {"settle": 1, "revolutions": 0.5, "samples": 3, "seed": 3, "backend": Backend("serial")}
#: A thin oil and smooth pins: the joints spend part of the time in mixed lubrication.
THIN = ContactModel(lubricant_viscosity=1e-4, roughness="0.1 um")


def test_each_scheme_reports_its_joints_regimes(paper_fourbar: Mechanism, tmp_path: Path) -> None:
    result = design_study(
        paper_fourbar, ["H8/g7", "H7/g6"], ["m"], ["joint_force <= 1 kN"], contact=THIN,
        confidence=0.1, responses="dynamic", **FAST,
    )  # fmt: skip
    assert len(result.table) == 2
    for _, row in result.table.iterrows():
        samples = result.samples[result.samples["scheme"] == row["scheme"]]
        ok = samples["status"] == "ok"
        for joint in JOINTS:
            full = samples[f"full_film_{joint}"][ok].to_numpy()
            for regime in ("full_film", "mixed", "boundary"):
                column = samples[f"{regime}_{joint}"][ok].to_numpy()
                assert row[f"{regime}_mean_{joint}"] == pytest.approx(column.mean(), rel=1e-12)
            assert row[f"left_full_film_{joint}"] == int(np.sum(full < 1 - 1e-9))
    assert (result.table[[f"mixed_mean_{j}" for j in JOINTS]].to_numpy() > 0.01).any()
    write_design(result, tmp_path, design_units(paper_fourbar, "dynamic"), plots=False)
    html = (tmp_path / "report.html").read_text()
    assert "Lubrication regimes" in html and "samples that left full film" in html
    scheme = json.loads((tmp_path / "summary.json").read_text())["schemes"][0]
    assert 0 <= scheme["full_film_mean_O2"] <= 1 and "left_full_film_O2" in scheme


def test_a_dry_design_has_no_regime_columns(paper_fourbar: Mechanism) -> None:
    result = design_study(
        paper_fourbar, ["H8/g7"], ["m"], ["joint_force <= 1 kN"],
        contact=ContactModel(lubrication="dry"), confidence=0.1, responses="dynamic",
        **{**FAST, "samples": 1, "settle": 0, "revolutions": 0.25},
    )  # fmt: skip
    assert not [c for c in result.table.columns if "full_film" in str(c)]
