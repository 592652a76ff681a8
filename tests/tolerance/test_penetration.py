"""Non-physical samples: each sample's penetration over its clearance, carried from the
response model to the study, and a warning where pins sink deeper than the clearance.

Fast settings: the paper's four-bar from its steady motion, no start-up revolution left out,
a quarter of a crank turn. The IMPACT stiffness sets the outcome (penetration ∝ k^(-2/3) at
a given load): 1e2 N/mm^1.5 is absurdly soft (every pin sinks 7 to 30 times its clearance),
1e5 N/mm^1.5 leaves the deepest pins near their clearance (some samples beyond it), and
with the fixed 21 µm of the paper's joints it leaves every pin well inside.
"""

from __future__ import annotations

import dataclasses
import json
from typing import ClassVar

import numpy as np
import pandas as pd
import pytest

from _tolerances import CONTRACT_OTHER_RTOL
from jointplay.contact.laws import ContactLaw, get_law
from jointplay.dynamics.batch import BatchSamples, simulate_batch
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.simulate import Start
from jointplay.model.mechanism import Mechanism
from jointplay.report.tolerance import write_study
from jointplay.tolerance.analysis import build_model, tolerance_study
from jointplay.tolerance.execution import Backend, run
from jointplay.tolerance.responses import (
    CheckedModel,
    DynamicResponses,
    Evaluation,
    LinearModel,
    RunningResponses,
    penetration_ratios,
)
from jointplay.tolerance.sampling import sample
from jointplay.tolerance.spec import ToleranceSpec

JOINTS = ("O2", "A", "B", "O4")
FAST = {"settle": 0, "revolutions": 0.25}
LOCAL = Backend("local")


def _impact(k_n_per_mm15: float) -> ContactLaw:
    """The paper's IMPACT law with stiffness ``k`` in N/mm^1.5 (SI inside)."""
    return get_law(
        "impact", stiffness=k_n_per_mm15 * 1000**1.5, exponent=1.5, c_max=1e4, d_max=1e-4
    )


def _batch_penetration(
    mechanism: Mechanism, spec: ToleranceSpec, x: np.ndarray, law: ContactLaw, settle: int = 0
) -> tuple[np.ndarray, np.ndarray]:
    """(pen, clearance), (n, 4) each, m: the batch engine's ``pen_<joint>`` of the samples
    ``x`` run through the public :func:`simulate_batch`, and each sample's clearance."""
    columns = {name: x[:, i] for i, name in enumerate(spec.names)}
    lengths = {n.removeprefix("length_"): v for n, v in columns.items() if n.startswith("length_")}
    fixed = {j.name: j.fit.clearance for j in mechanism.revolute_joints if j.fit is not None}
    clearance = np.stack(
        [columns.get(f"clearance_{j}", np.full(len(x), fixed[j])) for j in JOINTS], axis=1
    )
    joints = [
        ClearanceJoint(j, clearance=21e-6, journal_radius=5e-3, law=law)  # any: samples rule
        for j in JOINTS
    ]
    result = simulate_batch(
        mechanism,
        joints,
        BatchSamples(lengths=lengths, clearances=dict(zip(JOINTS, clearance.T, strict=True))),
        start=Start("steady"),
        method="explicit",
        backend="local",
        revolutions=FAST["revolutions"],
        settle=settle,
    )
    assert result.ok.all()
    return result.statistics[[f"pen_{j}" for j in JOINTS]].to_numpy(), clearance


@pytest.mark.parametrize("clearances", ["sampled", "fixed"])
def test_ratio_is_the_batch_engines_penetration_over_each_samples_clearance(
    paper_fourbar: Mechanism, clearances: str
) -> None:
    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    if clearances == "fixed":
        spec = spec.only("length")  # the joints keep the configured 21 µm
    law = _impact(1e5)
    model, spec = build_model(paper_fourbar, spec, "dynamic", contact=law, **FAST)
    assert isinstance(model, DynamicResponses) and isinstance(model, CheckedModel)
    assert model.check_names == tuple(
        f"{check}_ratio_{j}" for check in ("penetration", "elastic") for j in JOINTS
    )
    assert model.method_choice().method == "explicit"
    x = sample(spec, 6, 4).values
    evaluation = model.evaluate(x)
    pen, clearance = _batch_penetration(paper_fourbar, spec, x, law)
    if clearances == "fixed":
        np.testing.assert_allclose(clearance, 21e-6, rtol=1e-12)  # the fit H8/g7, Ø10
    assert evaluation.checks is not None
    # the same engine on the same lanes: the same bits, up to the division's rounding
    np.testing.assert_allclose(evaluation.checks[:, :4], pen / clearance, rtol=1e-14, atol=0)
    assert (evaluation.checks[:, :4] > 0).all()  # every pin touched its bearing
    # elastic: over Hertz's approach (F / K)^(2/3) at the peak force, K = (4/3) E* sqrt(R)
    forces = evaluation.values[:, [model.response_names.index(f"F_{j}_peak") for j in JOINTS]]
    e_star = 207e9 / (2 * (1 - 0.29**2))  # the paper's steel
    radius = 5e-3 * (5e-3 + clearance) / clearance
    approach = (forces / (4 / 3 * e_star * np.sqrt(radius))) ** (2 / 3)
    np.testing.assert_allclose(evaluation.checks[:, 4:], pen / approach, rtol=1e-12)


def test_running_ratio_is_the_batch_engines_deepest_penetration(
    paper_fourbar: Mechanism,
) -> None:
    """The running model runs on the batch engine (issue 42): without start-up revolutions,
    its checks are the batch engine's deepest penetration over the clearance (the running
    reductions do not move a step), and within 3 % of each sample's own simulation (another
    integrator; the deepest points here are the first impacts, where the two agree to about
    1 %)."""
    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    law = _impact(1e5)
    model, spec = build_model(paper_fourbar, spec, "running", contact=law, **FAST)
    assert isinstance(model, RunningResponses) and model.check_names == model.base.check_names
    assert model.base.method_choice().method == "explicit"  # as _batch_penetration's
    x = sample(spec, 2, 4).values
    evaluation = model.evaluate(x)
    assert evaluation.ok.all() and evaluation.checks is not None
    pen, clearance = _batch_penetration(paper_fourbar, spec, x, law)
    np.testing.assert_allclose(evaluation.checks[:, :4], pen / clearance, rtol=1e-12)
    for i, row in enumerate(x):
        result = model.base.simulate_one(row)
        deepest = result.solver_stats["max_penetration_per_joint_m"]
        single = [c.clearance for c in result.system.clearances]
        expected = [deepest[j] / c for j, c in zip(JOINTS, single, strict=True)]
        np.testing.assert_allclose(evaluation.checks[i, :4], expected, rtol=0.03)


def test_running_model_records_the_engine_that_ran(paper_fourbar: Mechanism) -> None:
    # summary.json's "model" of a running (and design) study says what ran: the batch
    # engine with the running responses in its lanes, its integrator choice; on the single
    # engine (engine="single"), one simulation per sample and no batch method
    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    model, _ = build_model(paper_fourbar, spec, "running", contact=_impact(1e5), **FAST)
    assert isinstance(model, RunningResponses)
    record = model.describe()
    assert "running responses in the same lanes" in record["model"]
    assert record["method"] == model.base.describe()["method"]
    assert "continuous solution" in record["rocker_speed_error"]
    assert record["checks"] == model.base.describe()["checks"]
    record = dataclasses.replace(model, engine="single").describe()
    assert "single-engine" in record["model"] and "batch" not in record["model"]
    assert "method" not in record and "method_reason" not in record
    assert "continuous solution" in record["peaks"]
    assert record["checks"] == model.base.describe()["checks"]


def test_running_ratio_leaves_out_the_start_up_revolutions(paper_fourbar: Mechanism) -> None:
    """With a start-up revolution left out (as the peaks are), the ratio is the deepest
    penetration of the analysed quarter turn; the start-up's first impacts, deeper, are out."""
    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    model, spec = build_model(
        paper_fourbar, spec, "running", contact=_impact(1e5), settle=1, revolutions=0.25
    )
    assert isinstance(model, RunningResponses)
    result = model.base.simulate_one(sample(spec, 1, 4).values[0])
    ratio = penetration_ratios(result)
    steps = result.steps
    period = paper_fourbar.driver.period
    analysed = steps["t"].to_numpy() >= period * (1 - 1e-9)
    clearance = np.array([c.clearance for c in result.system.clearances])
    deepest = np.array([steps[f"pen_{j}"].to_numpy()[analysed].max() for j in JOINTS])
    np.testing.assert_allclose(ratio, deepest / clearance, rtol=1e-12)
    whole_run = [result.solver_stats["max_penetration_per_joint_m"][j] for j in JOINTS]
    assert (ratio * clearance < np.asarray(whole_run)).all()


@pytest.mark.parametrize(("k", "what"), [(1e2, "absurdly soft"), (1e5, "borderline")])
def test_study_warns_with_the_count_of_samples_beyond_the_clearance(
    paper_fourbar: Mechanism, tmp_path, k: float, what: str
) -> None:
    law = _impact(k)
    study = tolerance_study(
        paper_fourbar, responses="dynamic", contact=law, samples=8, seed=1, backend=LOCAL, **FAST
    )
    pen, clearance = _batch_penetration(paper_fourbar, study.spec, study.result.x, law)
    beyond = pen > clearance  # counted without the study's ratios
    assert beyond.any(), what
    code = "penetration-exceeds-clearance"  # (the elastic check has its own test)
    findings = {d.diagnostic.joint: d for d in study.diagnostics if d.diagnostic.code == code}
    assert set(findings) == {j for c, j in enumerate(JOINTS) if beyond[:, c].any()}
    if what == "absurdly soft":
        assert beyond.all() and set(findings) == set(JOINTS)
    else:
        assert not beyond.all()  # some samples stay inside: the count is a real count
    summary = study.summary()
    records = {r["joint"]: r for r in summary["diagnostics"] if r["code"] == code}
    for c, joint in enumerate(JOINTS):
        if joint not in findings:
            continue
        finding = findings[joint]
        count = int(beyond[:, c].sum())
        worst = int(np.argmax(pen[:, c] / clearance[:, c]))
        ratio = pen[worst, c] / clearance[worst, c]
        d = finding.diagnostic
        assert (d.level, d.code, d.limit) == ("warning", "penetration-exceeds-clearance", 1.0)
        assert (finding.count, finding.out_of, finding.worst_sample) == (count, 8, worst)
        assert d.value == pytest.approx(ratio, rel=1e-12)
        assert finding.worst_inputs == dict(
            zip(study.spec.names, study.result.x[worst], strict=True)
        )
        assert d.message.startswith(
            f"{count} of 8 samples ({100 * count / 8:.3g} %): the pin of {joint} penetrates "
            f"its bearing by up to {ratio:.3g} times the radial clearance"
        )
        assert "not physical" in d.message and "stiffness law" in d.message
        assert records[joint]["count"] == count and records[joint]["share"] == count / 8
        assert records[joint]["worst_sample"] == worst
    # where the user reads it: summary.json, samples.parquet, the report's callout
    write_study(study, tmp_path, plots=False)
    written = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert [r["joint"] for r in written["diagnostics"] if r["code"] == code] == list(findings)
    frame = pd.read_parquet(tmp_path / "samples.parquet")
    for c, joint in enumerate(JOINTS):
        column = frame[f"penetration_ratio_{joint}"].to_numpy()
        np.testing.assert_allclose(column, pen[:, c] / clearance[:, c], rtol=1e-14)
    page = (tmp_path / "report.html").read_text(encoding="utf-8")
    first = next(iter(findings))
    assert f"Warning (penetration-exceeds-clearance, joint {first})" in page
    assert page.index("penetration-exceeds-clearance") < page.index('id="inputs"')  # on top


def test_a_physical_study_warns_of_nothing(paper_fourbar: Mechanism, tmp_path) -> None:
    """The default contact (docs/contact.md), lubricated and dry, in the paper's 21 µm
    joints: inside the clearance and within the elastic check; IMPACT's 1e5 N/mm^1.5, inside the clearance too,
    is ~50 times softer than the joints' Hertz stiffness and is flagged as not elastic."""
    from jointplay.dynamics.setup import ContactModel

    spec = ToleranceSpec.from_mechanism(paper_fourbar).only("length")  # 21 µm joints
    soft = tolerance_study(
        paper_fourbar, spec, responses="dynamic", contact=_impact(1e5), samples=4, seed=2,
        backend=LOCAL, **FAST,
    )  # fmt: skip
    ratios = soft.to_dataframe()[[f"penetration_ratio_{j}" for j in JOINTS]].to_numpy()
    assert ((ratios > 0) & (ratios < 1)).all()
    assert {d.diagnostic.code for d in soft.diagnostics} == {"penetration-exceeds-elastic"}
    dry = tolerance_study(
        paper_fourbar, spec, responses="dynamic", contact=ContactModel(film_damping=0),
        samples=4, seed=2, backend=LOCAL, **FAST,
    )  # fmt: skip
    ratios = dry.to_dataframe()[[f"penetration_ratio_{j}" for j in JOINTS]].to_numpy()
    assert ((ratios > 0) & (ratios < 1)).all()  # every dry pin touches, none sinks through
    assert dry.diagnostics == ()
    study = tolerance_study(
        paper_fourbar, spec, responses="dynamic", contact=ContactModel(), samples=4, seed=2,
        backend=LOCAL, **FAST,
    )  # fmt: skip
    frame = study.to_dataframe()
    ratios = frame[[f"penetration_ratio_{j}" for j in JOINTS]].to_numpy()
    assert (ratios < 0).all()  # lubricated (the π-film): every pin floats in its film
    elastic = frame[[f"elastic_ratio_{j}" for j in JOINTS]].to_numpy()
    touching = ratios > 0  # a floating pin's elastic ratio is not positive (or NaN)
    assert (elastic[touching] < 3).all() and not (elastic[~touching] > 0).any()
    assert study.diagnostics == () and study.summary()["diagnostics"] == []
    write_study(study, tmp_path, plots=False)
    assert "penetration-exceeds-clearance" not in (tmp_path / "report.html").read_text()
    # kinematic studies have no checks: no column, no warning
    kinematic = tolerance_study(paper_fourbar, samples=20, seed=2, backend=LOCAL)
    assert kinematic.result.run.checks is None and kinematic.result.run.check_names == ()
    assert not any(c.startswith("penetration") for c in kinematic.to_dataframe().columns)
    assert kinematic.summary()["diagnostics"] == []


class _Checked:
    """A cheap checked model: response 2x, check 10x; negative inputs fail (NaN checks
    from the model are not trusted: failed samples get NaN whatever the model says)."""

    input_names = ("x",)
    response_names = ("y",)
    check_names = ("ratio",)
    units: ClassVar[dict[str, str]] = {"y": ""}
    chunk_size = 3

    def evaluate(self, x: np.ndarray) -> Evaluation:
        ok = x[:, 0] >= 0
        errors = tuple("" if good else "ValueError: negative" for good in ok)
        return Evaluation(2.0 * x, ok, errors, 10.0 * x)

    def describe(self) -> dict:
        return {}


def test_run_carries_the_checks_in_sample_order() -> None:
    x = np.array([[0.0], [1.0], [-2.0], [3.0], [4.0], [-5.0], [6.0]])  # blocks of 3
    result = run(_Checked(), x, backend=Backend("serial"))
    assert result.check_names == ("ratio",) and result.checks is not None
    np.testing.assert_array_equal(result.checks, np.where(x >= 0, 10.0 * x, np.nan))
    assert result.status.tolist() == [0, 0, 1, 0, 0, 1, 0]
    plain = run(LinearModel(("x",), ((2.0,),)), x, backend=Backend("serial"))
    assert plain.checks is None and plain.check_names == ()


@pytest.mark.parametrize("responses", ["dynamic", "running"])
def test_worker_processes_give_the_local_checks_and_warnings(
    paper_fourbar: Mechanism, responses: str
) -> None:
    """The batch engine's own worker pool (dynamic) and one task per sample on the process
    backend (running, the checks pickled back with the responses): the same bits as here."""
    options = {"responses": responses, "contact": _impact(1e5), "samples": 6, "seed": 1}
    local = tolerance_study(paper_fourbar, backend=LOCAL, **options, **FAST)
    spread = tolerance_study(
        paper_fourbar, backend=Backend("processes", workers=2, chunk_size=4), **options, **FAST
    )
    assert spread.result.run.backend == "processes" and spread.result.run.workers == 2
    assert local.result.run.checks is not None and spread.result.run.checks is not None
    assert np.isfinite(local.result.run.checks).all()
    np.testing.assert_array_equal(local.result.run.checks, spread.result.run.checks)
    assert local.summary()["diagnostics"] == spread.summary()["diagnostics"] != []


def test_concatenated_evaluations_keep_their_checks() -> None:
    model = _Checked()
    parts = [model.evaluate(np.array([[1.0], [-1.0]])), model.evaluate(np.array([[2.0]]))]
    joined = Evaluation.concatenate(parts, 1)
    assert joined.checks is not None
    np.testing.assert_array_equal(joined.checks[:, 0], [10.0, -10.0, 20.0])
    plain = Evaluation(np.ones((1, 1)), np.ones(1, dtype=bool), ("",))
    assert Evaluation.concatenate([parts[0], plain], 1).checks is None
    with pytest.raises(ValueError, match="one row per sample"):
        Evaluation(np.ones((2, 1)), np.ones(2, dtype=bool), ("", ""), np.ones((3, 1)))


@pytest.mark.slow  # JAX compiles the batch for ~8 s
def test_the_gpu_backend_gives_the_cpu_checks_and_warnings(paper_fourbar: Mechanism) -> None:
    """The JAX kernel runs the Numba kernel's explicit method: the deepest penetrations agree
    within the integration accuracy (the contract's CONTRACT_OTHER_RTOL). Not to rounding:
    XLA's and Numba's arithmetic differ in the last bits (elementary functions, order of
    operations), so most lanes agree to ~1e-8 while a lane where those bits flip one step's
    acceptance goes its own way (at the batch engine's tolerances, 3 of 16 random lanes, by up
    to 6e-5; on these 6 samples, 8.1e-5 on the fifth, the others ≤ 4.4e-7: a penetration is a
    difference of positions, so its round-off is relative to the positions, larger than the
    peaks' SAME_ALGORITHM_RTOL)."""
    pytest.importorskip("jax")
    options = {"responses": "dynamic", "contact": _impact(1e5), "samples": 6, "seed": 1}
    local = tolerance_study(paper_fourbar, backend=LOCAL, **options, **FAST)
    gpu = tolerance_study(paper_fourbar, backend=Backend("gpu"), **options, **FAST)
    assert gpu.result.run.backend == "gpu"
    assert local.result.run.checks is not None and gpu.result.run.checks is not None
    np.testing.assert_allclose(
        gpu.result.run.checks, local.result.run.checks, rtol=CONTRACT_OTHER_RTOL
    )
    assert [d.as_dict()["count"] for d in gpu.diagnostics] == [
        d.as_dict()["count"] for d in local.diagnostics
    ]
    clearance = [d for d in gpu.diagnostics if d.diagnostic.code == "penetration-exceeds-clearance"]
    assert [d.diagnostic.joint for d in clearance] == ["O2", "A", "O4"]
