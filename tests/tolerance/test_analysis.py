"""The study: response models against the reference kinematics, files written, dynamics."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from jointplay.kinematics import fourbar
from jointplay.model.mechanism import Mechanism
from jointplay.model.templates import FourBarGeometry, with_lengths
from jointplay.report.tolerance import write_study
from jointplay.tolerance.analysis import tolerance_study
from jointplay.tolerance.execution import Backend
from jointplay.tolerance.methods import SpecLimits
from jointplay.tolerance.responses import FourBarKinematics
from jointplay.tolerance.spec import LinkTolerance, ToleranceSpec

SERIAL = Backend("serial")
#: The paper's conventional contact set (fast); the default is the physical contact.
CONVENTIONAL = "ifm-conventional"
LENGTHS = ("length_crank", "length_coupler", "length_rocker", "length_ground")


@pytest.mark.parametrize(
    "lengths",
    [(0.108, 0.2705, 0.2705, 0.2794), (0.05, 0.19, 0.16, 0.20), (0.03, 0.09, 0.07, 0.08)],
)
@pytest.mark.parametrize("branch", [1, -1])
def test_vectorised_fourbar_matches_the_closed_form(lengths, branch) -> None:
    """The trig-free kernel against kinematics/fourbar.py on a 0.01° grid."""
    geometry = FourBarGeometry(*lengths)
    omega2 = -20.944
    model = FourBarKinematics(
        geometry, LENGTHS, omega2, branch=branch, coupler_points={"P": (0.03, 0.02)}
    )
    values = dict(
        zip(model.response_names, model.evaluate(np.array([lengths])).values[0], strict=True)
    )
    theta2 = np.linspace(0, 2 * np.pi, 36_000, endpoint=False)
    t3, t4 = fourbar.positions(geometry, theta2, branch)
    w3, w4 = fourbar.velocities(geometry, theta2, t3, t4, omega2)
    a3, a4 = fourbar.accelerations(geometry, theta2, t3, t4, omega2, w3, w4)
    t3 = np.unwrap(t3)
    # 1° grid + parabolic refinement vs a 0.01° grid: agreement to ~1e-5 relative (the
    # parabola's error) — far below any manufacturing effect.
    rtol = 2e-5
    assert values["omega3_peak"] == pytest.approx(np.abs(w3).max(), rel=rtol)
    assert values["omega4_peak"] == pytest.approx(np.abs(w4).max(), rel=rtol)
    assert values["alpha3_peak"] == pytest.approx(np.abs(a3).max(), rel=rtol)
    assert values["alpha4_peak"] == pytest.approx(np.abs(a4).max(), rel=rtol)
    assert values["theta4_max"] - values["theta4_min"] == pytest.approx(values["rocker_swing"])
    assert values["theta4_min"] == pytest.approx(t4.min(), abs=1e-6)
    assert values["theta4_max"] == pytest.approx(t4.max(), abs=1e-6)
    assert values["theta3_min"] == pytest.approx(t3.min(), abs=1e-6)
    assert values["theta3_max"] == pytest.approx(t3.max(), abs=1e-6)
    mu = fourbar.transmission_angle(geometry, theta2)
    assert values["transmission_angle_min"] == pytest.approx(
        np.minimum(mu, np.pi - mu).min(), abs=1e-9
    )
    assert values["path_deviation_P"] == 0.0


def test_rocker_swing_matches_the_limit_positions(paper_fourbar: Mechanism) -> None:
    model = FourBarKinematics.from_mechanism(paper_fourbar, LENGTHS)
    for lengths in ([0.108, 0.2705, 0.2705, 0.2794], [0.1088, 0.2693, 0.2717, 0.2782]):
        geometry = FourBarGeometry(*lengths)
        extended, folded = fourbar.rocker_limit_positions(geometry)
        swing = abs(extended.rocker_angle - folded.rocker_angle)
        values = model.evaluate(np.array([lengths])).values[0]
        assert values[0] == pytest.approx(swing, abs=1e-6)  # rad; ≈ 0.06 mdeg


def test_path_deviation_is_the_distance_to_the_nominal_point(paper_fourbar: Mechanism) -> None:
    from jointplay.kinematics.analysis import analyse

    model = FourBarKinematics.from_mechanism(paper_fourbar, ("length_crank",))
    angles = np.radians(np.arange(0, 360, 0.01))
    mid = (0.2705 / 2, 0.0)  # the default point: the nominal coupler's mid-point
    nominal = analyse(paper_fourbar, angles).point("coupler", mid)[0]
    changed = analyse(with_lengths(paper_fourbar, crank=0.109), angles).point("coupler", mid)[0]
    deviation = float(np.max(np.hypot(*(nominal - changed).T)))
    value = model.evaluate(np.array([[0.109]])).values[0, -1]
    assert value == pytest.approx(deviation, rel=1e-5)


def test_kinematic_monte_carlo_files(paper_fourbar: Mechanism, tmp_path) -> None:
    limits = {"omega4_peak": SpecLimits(upper=13.85), "rocker_swing": SpecLimits(0.91, 0.925)}
    study = tolerance_study(paper_fourbar, samples=500, seed=4, limits=limits, backend=SERIAL)
    written = write_study(study, tmp_path, provenance={"jointplay_version": "test"})
    assert {p.name for p in written} == {
        "samples.parquet",
        "summary.json",
        "tornado.png",
        "histograms.png",
        "scatter.png",
        "report.html",
    }
    samples = pd.read_parquet(tmp_path / "samples.parquet")
    assert len(samples) == 500
    assert list(samples.columns[:6]) == ["sample", "role", *LENGTHS]
    assert list(samples.columns[-2:]) == ["status", "error"]
    assert (samples["status"] == "ok").all()
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["method"] == "monte-carlo" and summary["seed"] == 4
    assert summary["settings"] == {
        "samples": 500,
        "seed": 4,
        "sampling": "random",
        "truncated_at_limits": True,
    }
    assert summary["counts"] == {"points": 500, "ok": 500, "failed": 0, "not_run": 0}
    assert summary["provenance"] == {"jointplay_version": "test"}
    assert set(summary["inputs"]) == set(LENGTHS)  # kinematics: the lengths only
    omega = summary["responses"]["omega4_peak"]
    assert omega["unit"] == "rad/s"
    assert omega["spec_limits"] == {"lower": None, "upper": 13.85}
    assert omega["out_of_spec_percent"] == pytest.approx(
        100 * np.mean(samples["omega4_peak"] > 13.85)
    )
    assert omega["std"] == pytest.approx(samples["omega4_peak"].std())
    assert sum(omega["contributions"].values()) == pytest.approx(1.0)
    assert summary["most_influential"]["omega4_peak"] == "length_crank"
    for name in ("tornado.png", "histograms.png", "scatter.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    page = (tmp_path / "report.html").read_text()
    assert page.count("data:image/png;base64,") == 3
    assert "omega4_peak" in page and '<td class="text">crank</td>' in page  # inputs by link name


@pytest.mark.parametrize("method", ["worst-case", "rss"])
def test_other_methods_write_their_tables(paper_fourbar: Mechanism, tmp_path, method) -> None:
    study = tolerance_study(paper_fourbar, method=method, backend=SERIAL)
    write_study(study, tmp_path, plots=False)
    samples = pd.read_parquet(tmp_path / "samples.parquet")
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["method"] == method and summary["seed"] is None
    assert samples["role"].iloc[0] == "nominal"
    swing = summary["responses"]["rocker_swing"]
    if method == "worst-case":
        assert len(samples) == 17
        assert swing["minimum"] < swing["nominal"] < swing["maximum"]
        assert set(swing["high_corner"]) == set(LENGTHS)
    else:
        assert len(samples) == 2 + 2 * 4
        assert swing["std"] > 0 and swing["half_range"] > swing["std"]
    assert "data:image/png" not in (tmp_path / "report.html").read_text()


def test_failures_reach_summary_and_samples(paper_fourbar: Mechanism, tmp_path) -> None:
    spec = ToleranceSpec(
        (LinkTolerance.from_deviations("coupler", 0.2705, -0.18, 0.18, distribution="uniform"),)
    )
    study = tolerance_study(paper_fourbar, spec, samples=200, seed=1, backend=SERIAL)
    write_study(study, tmp_path, plots=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    samples = pd.read_parquet(tmp_path / "samples.parquet")
    failed = samples[samples["status"] == "failed"]
    assert summary["counts"]["failed"] == len(failed) > 0
    assert [f["sample"] for f in summary["failures"]] == failed["sample"].tolist()
    first = summary["failures"][0]
    # summary.json rounds its numbers to 12 significant digits (io.output.jsonable)
    assert first["inputs"]["length_coupler"] == pytest.approx(
        failed["length_coupler"].iloc[0], rel=1e-12
    )
    assert "cannot be assembled" in first["error"]
    assert failed["omega4_peak"].isna().all()
    assert "Failures (" in (tmp_path / "report.html").read_text()


def test_slider_crank_uses_the_general_kinematics(slider_crank: Mechanism) -> None:
    spec = ToleranceSpec.from_mechanism(slider_crank, general_class="m")
    assert spec.names == ("length_crank", "length_rod")  # the zero offset has no tolerance
    study = tolerance_study(slider_crank, spec, method="rss", backend=SERIAL)
    stroke = study.summaries["slider_stroke"]
    # The stroke of a centred slider-crank is twice the crank: ∂stroke/∂crank = 2.
    assert stroke.nominal == pytest.approx(2 * 0.05, rel=1e-9)
    assert stroke.sensitivities["length_crank"] == pytest.approx(2.0, rel=1e-6)
    assert stroke.sensitivities["length_rod"] == pytest.approx(0.0, abs=1e-6)


def test_dynamic_study_spreads_peaks_and_forces(paper_fourbar: Mechanism, tmp_path) -> None:
    """Four clearance joints, the paper's IFM, from rest; tiny settings (a short start-up)."""
    study = tolerance_study(
        paper_fourbar,
        responses="dynamic",
        contact=CONVENTIONAL,
        samples=2,
        seed=3,
        start="rest",
        settle=0,
        revolutions=0.05,
        backend=SERIAL,
    )
    assert study.spec.names[4:] == ("clearance_O2", "clearance_A", "clearance_B", "clearance_O4")
    assert study.responses == "dynamic"
    names = set(study.summaries)
    assert {"omega4_peak", "alpha4_peak", "F_O2_peak", "F_B_peak", "torque_peak"} <= names
    frame = study.to_dataframe()
    assert (frame["status"] == "ok").all()
    clearances = frame[[n for n in frame.columns if n.startswith("clearance_")]].to_numpy()
    assert ((clearances >= 2.5e-6) & (clearances <= 21e-6)).all()
    ideal = study.ideal
    assert ideal is not None
    assert ideal["omega4_peak"] == pytest.approx(13.726, rel=1e-3)
    # Impacts at start-up: joint forces far above the ideal-joint forces (paper, Table 6).
    assert study.summaries["F_A_peak"].nominal > 10 * ideal["F_A_peak"]
    assert study.model["contact_law"]["name"] == "impact"
    assert study.model["start"] == "rest"
    write_study(study, tmp_path, plots=False)
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["responses"]["F_A_peak"]["ideal_joints"] == pytest.approx(ideal["F_A_peak"])
    assert math.isfinite(summary["responses"]["omega4_peak"]["mean"])


def test_dynamic_studies_default_to_the_running_mechanism(paper_fourbar: Mechanism) -> None:
    """Steady start, two start-up revolutions left out: the forces are the running ones, a
    few per cent above the ideal joints' (not the kilonewton start-up impacts)."""
    study = tolerance_study(
        paper_fourbar, responses="dynamic", contact=CONVENTIONAL, samples=2, seed=3,
        backend=SERIAL,
    )  # fmt: skip
    assert (study.model["start"], study.model["settle_revolutions"]) == ("steady", 2)
    ideal = study.ideal
    assert ideal is not None
    for joint in ("O2", "A", "B", "O4"):
        peak = study.summaries[f"F_{joint}_peak"].nominal
        assert ideal[f"F_{joint}_peak"] < peak < 1.2 * ideal[f"F_{joint}_peak"]


def test_running_responses_add_speed_error_force_pressure_and_wear(
    paper_fourbar: Mechanism,
) -> None:
    """responses="running": the dynamic peaks and the design study's running responses, so a
    tolerance study knows contact pressure and wear rate too."""
    study = tolerance_study(
        paper_fourbar, responses="running", contact=CONVENTIONAL, samples=2, seed=3,
        backend=SERIAL,
    )  # fmt: skip
    names = set(study.summaries)
    assert {
        "F_A_peak",
        "rocker_speed_error",
        "joint_force",
        "contact_pressure",
        "wear_rate",
    } <= names
    assert {f"wear_rate_{j}" for j in ("O2", "A", "B", "O4")} <= names
    summary = study.summaries
    # The largest joint force is the largest of the per-joint peaks, sample by sample.
    frame = study.to_dataframe()
    peaks = frame[[f"F_{j}_peak" for j in ("O2", "A", "B", "O4")]].max(axis=1)
    assert (frame["joint_force"] == peaks).all()
    assert (frame["wear_rate"] > 0).all() and (frame["contact_pressure"] > 0).all()
    assert 0 < summary["rocker_speed_error"].nominal < 0.05  # a few % on the running mechanism
    assert study.ideal is not None and "F_A_peak" in study.ideal


def test_dynamic_study_gives_the_same_samples_and_bits_on_every_cpu_backend(
    paper_fourbar: Mechanism,
) -> None:
    """Sampling happens before dispatch and the batch engine's lanes are independent: the
    same seed gives the same samples and the same responses in this process (threads) and on
    worker processes, in any block size."""
    options = {
        "responses": "dynamic", "contact": CONVENTIONAL, "samples": 6, "seed": 8, "settle": 0,
        "revolutions": 0.2,
    }  # fmt: skip
    local = tolerance_study(paper_fourbar, backend=Backend("local"), **options)
    spread = tolerance_study(
        paper_fourbar, backend=Backend("processes", workers=2, chunk_size=4), **options
    )
    assert spread.result.run.backend == "processes" and spread.result.run.workers == 2
    np.testing.assert_array_equal(local.result.x, spread.result.x)
    np.testing.assert_array_equal(local.result.run.values, spread.result.run.values)
    assert local.model["method"] == "explicit" and "Dormand" in local.model["method_reason"]


def test_dynamic_studies_default_to_the_physical_contact(paper_fourbar: Mechanism) -> None:
    """No contact given: the physical default ``ContactModel()``, as every command (Liu
    stiffness from each joint's geometry, Hunt–Crossley e = 0.8, friction 0.1); the paper's
    conventional IFM set is one argument away."""
    from jointplay.dynamics.setup import ContactModel
    from jointplay.tolerance.analysis import build_model

    spec = ToleranceSpec.from_mechanism(paper_fourbar)
    default, _ = build_model(paper_fourbar, spec, "dynamic")
    physical, _ = build_model(paper_fourbar, spec, "dynamic", contact=ContactModel())
    assert default.describe() == physical.describe()
    described = default.describe()
    assert described["contact_law"]["name"] == "restitution"
    assert set(described["stiffness_from_geometry"]) == {"O2", "A", "B", "O4"}
    assert {rule["law"] for rule in described["stiffness_from_geometry"].values()} == {"liu"}
    assert described["friction"] is not None and described["friction"]["mu"] == 0.1
    conventional, _ = build_model(paper_fourbar, spec, "dynamic", contact=CONVENTIONAL)
    described = conventional.describe()
    assert described["contact_law"]["name"] == "impact" and described["friction"] is None
    assert described["stiffness_from_geometry"] == {}
