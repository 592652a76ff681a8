"""Which engine a dynamic design study runs: the batch engine (peaks, every backend, the GPU
included) unless a requirement needs each sample's trajectory (the single engine)."""

from __future__ import annotations

import numpy as np
import pytest

from _tolerances import CONTRACT_OTHER_RTOL, SAME_ALGORITHM_RTOL, contract_rtol
from jointplay.errors import ConfigError
from jointplay.model.mechanism import Mechanism
from jointplay.study.design import design_study, trajectory_requirements
from jointplay.study.requirements import parse_requirement
from jointplay.tolerance.execution import Backend

LOCAL = Backend("local")
#: The paper's conventional set, as before the physical default (these tests compare engines).
SHORT = {
    "settle": 1, "revolutions": 0.5, "samples": 4, "seed": 3, "contact": "ifm-conventional"
}  # fmt: skip
PEAKS = ["omega4_peak", "F_A_peak", "F_B_peak", "joint_force", "contact_pressure"]
#: ω peaks of the two engines at the default tolerances (rtol 1e-6), in design conditions
#: (fits up to H11/c11, a start-up revolution left out): measured against a converged
#: solution (rtol 1e-9) on 24 samples, the batch engine's Dormand–Prince is off by up to
#: 3.4e-5 (8 of 24 beyond 1e-5) and the single engine's Radau by up to 1.3e-5; both converge
#: under refinement (batch at rtol 1e-7: ≤ 2.2e-6). The batch contract's 1e-5
#: (tests/dynamics/test_batch.py) holds on its own cases; here the engines are compared as
#: they run by default, at a bound looser than the contract (the forces keep its 1e-3).
OMEGA_RTOL_LOOSER_THAN_CONTRACT = 5e-5


def _design(mechanism: Mechanism, requirements: list[str], backend: Backend = LOCAL):
    return design_study(
        mechanism, ["H8/g7", "H11/c11"], ["c"], requirements, backend=backend, **SHORT
    )


@pytest.fixture(scope="module")
def both(paper_fourbar: Mechanism):
    """The same samples through the batch engine (a peak requirement) and through the single
    engine (a trajectory requirement added, which every sample meets)."""
    peaks = _design(paper_fourbar, ["joint_force <= 1 kN"])
    trajectories = _design(paper_fourbar, ["joint_force <= 1 kN", "rocker_speed_error <= 100 %"])
    return peaks, trajectories


def test_peak_requirements_run_on_the_batch_engine(both) -> None:
    peaks, trajectories = both
    assert "batch engine" in peaks.settings["model"]["model"]
    # the running responses too, in the same lanes (issue 42; before: one single-engine
    # simulation per sample)
    assert "running responses in the same lanes" in trajectories.settings["model"]["model"]
    assert "rocker_speed_error" not in peaks.samples and "life" not in peaks.samples
    assert "rocker_speed_error" in trajectories.samples


def test_the_two_engines_agree_within_the_integration_tolerance(both) -> None:
    peaks, trajectories = both
    a, b = peaks.samples, trajectories.samples
    assert (a["status"] == "ok").all() and (b["status"] == "ok").all()
    np.testing.assert_array_equal(a["clearance_A"], b["clearance_A"])  # the same samples
    for name in PEAKS:
        omega = name.startswith("omega")
        rtol = OMEGA_RTOL_LOOSER_THAN_CONTRACT if omega else CONTRACT_OTHER_RTOL
        np.testing.assert_allclose(a[name], b[name], rtol=rtol, err_msg=name)
    assert peaks.best == trajectories.best
    np.testing.assert_array_equal(peaks.table["yield"], trajectories.table["yield"])


def test_contact_pressure_is_the_hertz_pressure_of_the_largest_peak_force(
    both, paper_fourbar: Mechanism
) -> None:
    from jointplay.dynamics.diagnostics import line_contact_pressure

    samples = both[0].samples
    steel = paper_fourbar.material_of("crank")
    for _, row in samples.iterrows():
        pressures = [
            line_contact_pressure(
                row[f"F_{j}_peak"],
                paper_fourbar.bearing_width(j),
                5e-3,
                row[f"clearance_{j}"],
                steel,
                steel,
            )
            for j in ("O2", "A", "B", "O4")
        ]
        assert row["contact_pressure"] == pytest.approx(max(pressures), rel=1e-12)
        assert row["joint_force"] == max(row[f"F_{j}_peak"] for j in ("O2", "A", "B", "O4"))


def test_trajectory_requirements_are_named(paper_fourbar: Mechanism) -> None:
    units = {"joint_force": "N", "rocker_speed_error": "1", "wear_rate_A": "m/s", "life": "s"}
    parsed = [
        parse_requirement(text, units)
        for text in ("joint_force <= 1 kN", "rocker_speed_error <= 2 %", "wear_rate_A <= 1 m/s",
                     "life >= 10 h")
    ]  # fmt: skip
    assert trajectory_requirements(parsed) == [r.text for r in parsed[1:]]
    with pytest.raises(
        ConfigError,
        match=r"gpu backend \(JAX\) computes no running responses: 'rocker_speed_error <= 2 %'",
    ):
        _design(paper_fourbar, ["rocker_speed_error <= 2 %"], Backend("gpu"))


@pytest.mark.slow  # JAX compiles the batch for ~10 s
def test_a_peak_design_runs_on_the_gpu_backend(both, paper_fourbar: Mechanism) -> None:
    """The same algorithm as the local batch engine. On these samples (holes and pins as
    made, seed 3) one sample's adaptive step sequence differs between the two kernels (a
    step accepted by one and rejected by the other, through round-off), which moves its
    peaks by up to 4e-7: within the accuracy contract, not round-off
    (tests/_tolerances.py). On samples whose step sequences coincide (the fits' bands, the
    samples this test was first written on) the engines agree to round-off (1e-10)."""
    pytest.importorskip("jax")
    from jointplay.tolerance.parts import Process

    on_gpu = _design(paper_fourbar, ["joint_force <= 1 kN"], Backend("gpu"))
    assert on_gpu.settings["execution"]["backend"] == "gpu"
    for name in PEAKS:  # one lane's acceptance tipped by round-off: the contract
        np.testing.assert_allclose(
            on_gpu.samples[name], both[0].samples[name], rtol=contract_rtol(name), err_msg=name
        )
    band = Process(sampling="band")
    local, gpu = (
        design_study(
            paper_fourbar,
            ["H8/g7", "H11/c11"],
            ["c"],
            ["joint_force <= 1 kN"],
            backend=where,
            process=band,
            **SHORT,
        )
        for where in (LOCAL, Backend("gpu"))
    )
    for name in PEAKS:  # the same steps: round-off apart (measured ≤ 1.4e-10)
        np.testing.assert_allclose(
            gpu.samples[name], local.samples[name], rtol=SAME_ALGORITHM_RTOL, err_msg=name
        )


def test_an_unconverged_design_says_so(paper_fourbar: Mechanism, tmp_path) -> None:
    """Integrated coarsely (rtol 1e-3), the peaks move by a large share of their spread when
    the tolerances are tightened: the design warns, in summary.json and in the report, beside
    the penetration warnings."""
    from jointplay.dynamics.simulate import SolverOptions
    from jointplay.report.design import write_design
    from jointplay.study.design import design_units

    result = design_study(
        paper_fourbar, ["H8/g7"], ["c"], ["joint_force <= 1 kN"], samples=40, seed=1,
        settle=0, revolutions=1.0, backend=LOCAL, solver=SolverOptions(rtol=1e-3),
        contact="ifm-conventional",
    )  # fmt: skip
    check = result.convergence
    assert check is not None and check.share > check.limit and check.finding is not None
    assert result.diagnostics[-1] is check.finding
    summary = result.summary()
    assert summary["convergence_check"]["converged"] is False
    assert summary["diagnostics"][-1]["code"] == "peaks-not-converged"
    write_design(result, tmp_path, design_units(paper_fourbar, "dynamic"), plots=False)
    assert "Warning (peaks-not-converged)" in (tmp_path / "report.html").read_text()


def test_a_design_judged_on_its_statistics_says_so(
    paper_fourbar: Mechanism, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Where the convergence check judged the statistics (irregular samples) and found them
    converged, its ``statistics-converged`` note is among the design's diagnostics: a dry
    design that passes is not silent about the rule that judged it (the note alone, before,
    reached only summary.json)."""
    import jointplay.study.design as design_module
    from jointplay.dynamics.diagnostics import Diagnostic
    from jointplay.tolerance.analysis import ConvergenceCheck, StudyDiagnostic

    said = Diagnostic("info", "statistics-converged", None, 0.0, 0.0, "judged on statistics")
    note = StudyDiagnostic(said, count=8, out_of=8, worst_sample=0, worst_inputs={})
    check = ConvergenceCheck(8, 100.0, "F_A_peak", 1.8, 0.1, None, rule="statistics", note=note)
    monkeypatch.setattr(design_module, "convergence_finding", lambda *args: check)
    result = design_study(
        paper_fourbar, ["H8/g7"], ["c"], ["joint_force <= 1 kN"], samples=4, seed=1,
        settle=0, revolutions=0.2, backend=LOCAL,
    )  # fmt: skip
    assert result.convergence is check
    assert result.diagnostics[-1] is note
