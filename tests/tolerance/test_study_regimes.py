"""The lubrication regimes of a dynamic study (issue 39, item 4): per lubricated joint and
sample, the fractions of the analysed time in full film, mixed and boundary lubrication, the
batch engine's, equal to the single engine's ``simulate`` fractions of the same sample (to
the steps' resolution: tests/dynamics/test_batch_regimes.py); the study's summary and report
give their means and the share of samples that ever left full film."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from jointplay.dynamics.setup import ContactModel
from jointplay.model.mechanism import Mechanism
from jointplay.report.tolerance import write_study
from jointplay.tolerance.analysis import build_model, tolerance_study
from jointplay.tolerance.response_base import regime_check_names, regime_fractions
from jointplay.tolerance.responses import DynamicResponses, sample_checks
from jointplay.tolerance.sampling import sample
from jointplay.tolerance.spec import ToleranceSpec

JOINTS = ("O2", "A", "B", "O4")
FAST = {"settle": 1, "revolutions": 0.5}
#: A thin oil and smooth pins: every joint spends part of the time in mixed lubrication.
THIN = ContactModel(lubricant_viscosity=1e-4, roughness="0.1 um")
#: The batch engine's fractions against the single engine's (tests/dynamics/test_batch_regimes.py).
REGIME_ATOL = 1e-3


def test_regime_fractions_are_means_over_the_successful_samples() -> None:
    names = ("penetration_ratio_A", *regime_check_names(["A", "B"]))
    checks = np.array(
        [
            [0.1, 1.0, 0.0, 0.0, 0.5, 0.5, 0.0],
            [0.2, 0.6, 0.3, 0.1, 0.2, 0.7, 0.1],
            [0.3, 0.2, 0.8, 0.0, 0.0, 0.9, 0.1],  # failed: left out
        ]
    )
    ok = np.array([True, True, False])
    got = regime_fractions(names, checks, ok)
    assert list(got) == ["A", "B"]
    assert got["A"]["full_film_mean"] == pytest.approx(0.8)
    assert got["A"]["mixed_mean"] == pytest.approx(0.15)
    assert got["A"]["boundary_mean"] == pytest.approx(0.05)
    assert (got["A"]["left_full_film"], got["A"]["samples"]) == (1, 2)
    assert got["A"]["left_full_film_share"] == pytest.approx(0.5)
    assert got["B"]["left_full_film"] == 2
    assert regime_fractions(names[:1], checks[:, :1], ok) == {}  # no film: nothing


def test_the_study_reports_the_single_engines_regimes_per_sample(
    paper_fourbar: Mechanism,
) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    model, spec = build_model(paper_fourbar, spec, "dynamic", contact=THIN, **FAST)
    assert isinstance(model, DynamicResponses)
    assert model.lubricated_joints == JOINTS
    assert model.check_names[8:] == regime_check_names(JOINTS)
    x = sample(spec, 3, 7).values
    evaluation = model.evaluate(x)
    assert evaluation.ok.all() and evaluation.checks is not None
    batch = evaluation.checks[:, 8:]
    for i, row in enumerate(x):
        single = sample_checks(model.simulate_one(row), model.lubricated_joints)[8:]
        np.testing.assert_allclose(batch[i], single, rtol=0, atol=REGIME_ATOL, err_msg=str(i))
    assert np.allclose(batch.reshape(3, 4, 3).sum(axis=2), 1.0)
    assert (batch[:, 1::3] > 0.01).any()  # some time in mixed lubrication: worth comparing


def test_the_summary_and_the_report_give_each_joints_regimes(
    paper_fourbar: Mechanism, tmp_path: Path
) -> None:
    study = tolerance_study(
        paper_fourbar, responses="dynamic", contact=THIN, samples=3, seed=7, **FAST
    )
    run = study.result.run
    assert run.checks is not None
    write_study(study, tmp_path, plots=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    regimes = summary["lubrication_regimes"]
    assert "lambda = h_min/sigma >= 3" in regimes["definition"]
    for joint in JOINTS:
        full = run.checks[:, run.check_names.index(f"full_film_{joint}")]
        entry = regimes["joints"][joint]
        assert entry["full_film_mean"] == pytest.approx(full.mean(), rel=1e-12)
        assert entry["left_full_film"] == int(np.sum(full < 1 - 1e-9))
        assert entry["samples"] == 3
    html = (tmp_path / "report.html").read_text()
    assert "Lubrication regimes" in html and "samples that left full film" in html


def test_a_dry_study_reports_no_regimes(paper_fourbar: Mechanism) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    dry = ContactModel(lubrication="dry")
    model, _ = build_model(paper_fourbar, spec, "dynamic", contact=dry, **FAST)
    assert isinstance(model, DynamicResponses)
    assert model.lubricated_joints == ()
    assert not any(name.startswith("full_film_") for name in model.check_names)


def test_the_running_study_reports_each_samples_regimes(paper_fourbar: Mechanism) -> None:
    """The running responses' single engine gives the fractions itself (its
    ``film_regimes``), in the same check columns."""
    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    model, spec = build_model(paper_fourbar, spec, "running", contact=THIN, **FAST)
    assert model.check_names[8:] == regime_check_names(JOINTS)  # type: ignore[attr-defined]
    x = sample(spec, 1, 7).values
    evaluation = model.evaluate(x)
    assert evaluation.ok.all() and evaluation.checks is not None
    regimes = evaluation.checks[0, 8:].reshape(4, 3)
    np.testing.assert_allclose(regimes.sum(axis=1), 1.0, rtol=1e-12)
    dynamic, _ = build_model(paper_fourbar, spec, "dynamic", contact=THIN, **FAST)
    batch = dynamic.evaluate(x).checks
    assert batch is not None
    np.testing.assert_allclose(regimes.ravel(), batch[0, 8:], rtol=0, atol=REGIME_ATOL)
