"""The ``jointplay tolerance`` command."""

from __future__ import annotations

import json
import math

import numpy as np
import pandas as pd
import pytest

from jointplay.cli import run

QUIET = ["--no-progress", "--no-plots", "--workers", "1"]
LENGTHS = ("length_crank", "length_coupler", "length_rocker", "length_ground")


def _summary(folder) -> dict:
    return json.loads((folder / "summary.json").read_text())


def test_spec_limit_is_a_deprecated_alias_of_require(tmp_path, capsys) -> None:
    def limits(*given: str) -> dict:
        out = tmp_path / str(len(list(tmp_path.iterdir())))
        args = ["tolerance", "--samples", "50", "--out", str(out), *QUIET, *given]
        assert run(args) == 0
        return {k: v.get("spec_limits") for k, v in _summary(out)["responses"].items()}

    old = limits("--spec-limit", "rocker_swing=52.3 deg:53 deg")
    assert "--spec-limit is deprecated" in capsys.readouterr().err
    new = limits("--require", "rocker_swing >= 52.3 deg", "--require", "rocker_swing <= 53 deg")
    assert "deprecated" not in capsys.readouterr().err
    assert new == old and new["rocker_swing"]["upper"] == pytest.approx(math.radians(53))


@pytest.mark.parametrize(
    ("given", "message"),
    [
        (["--require", "rocker_swing <= 53 deg @99"], "takes no @confidence"),
        (["--require", "rocker_swing <= 53 deg", "--require", "rocker_swing < 54 deg"],
         "two upper limits on 'rocker_swing'"),
        (["--require", "rocker_swing <= 53 deg", "--spec-limit", "rocker_swing=52 deg:"],
         "both limit 'rocker_swing'"),
        (["--require", "omega9_peak <= 5 rad/s"], "unknown response 'omega9_peak'"),
    ],
)  # fmt: skip
def test_bad_requirements_are_one_line_errors(given, message, tmp_path, capsys) -> None:
    args = ["tolerance", "--method", "worst-case", "--out", str(tmp_path / "x"), *QUIET, *given]
    assert run(args) == 2
    assert message in capsys.readouterr().err


def test_monte_carlo_answers_with_files_and_a_table(tmp_path, capsys) -> None:
    def args(out) -> list[str]:
        return [
            "tolerance", "--preset", "paper-fourbar", "--method", "monte-carlo",
            "--samples", "300", "--seed", "12", "--out", str(out), *QUIET,
            "--require", "rocker_swing >= 52.3 deg", "--require", "rocker_swing <= 53 deg",
            "--require", "omega4_peak <= 13.9 rad/s",
        ]  # fmt: skip

    out = tmp_path / "mc"
    assert run(args(out)) == 0
    printed = capsys.readouterr().out
    assert "rocker_swing (deg)" in printed and "most influential" in printed
    assert f"results written to {out}" in printed
    summary = _summary(out)
    assert summary["method"] == "monte-carlo" and summary["seed"] == 12
    assert summary["provenance"]["command_line"].startswith("jointplay")
    swing = summary["responses"]["rocker_swing"]
    assert swing["spec_limits"]["lower"] == pytest.approx(math.radians(52.3))
    assert swing["cp"] == pytest.approx(math.radians(0.7) / (6 * swing["std"]))
    assert summary["responses"]["omega4_peak"]["spec_limits"] == {"lower": None, "upper": 13.9}
    assert len(pd.read_parquet(out / "samples.parquet")) == 300
    # Same seed, same numbers.
    assert run(args(tmp_path / "again")) == 0
    pd.testing.assert_frame_equal(
        pd.read_parquet(out / "samples.parquet"),
        pd.read_parquet(tmp_path / "again" / "samples.parquet"),
    )


@pytest.mark.parametrize("method", ["worst-case", "rss"])
def test_worst_case_and_rss(tmp_path, method) -> None:
    out = tmp_path / method
    assert run(["tolerance", "--method", method, "--out", str(out), *QUIET]) == 0
    summary = _summary(out)
    assert summary["method"] == method
    assert summary["most_influential"]["alpha4_peak"] == "length_crank"


def test_config_with_extended_tolerances_and_distribution_override(tmp_path) -> None:
    from jointplay.io.config import preset_text

    text = preset_text("paper-fourbar").split("# Link-length tolerances")[0]
    text += '[tolerances]\ngeneral = "m"\n\n[tolerances.lengths.crank]\nclass = "c"\ncpk = 1.33\n'
    config = tmp_path / "mine.toml"
    config.write_text(text)

    def args(out) -> list[str]:
        return ["tolerance", "--config", str(config), "--samples", "50", "--out", str(out), *QUIET]

    out = tmp_path / "out"
    assert run(args(out)) == 0
    inputs = _summary(out)["inputs"]
    assert inputs["length_crank"]["source"] == "ISO 2768-1 c"
    assert inputs["length_crank"]["cpk"] == pytest.approx(1.33)
    assert inputs["length_coupler"]["source"] == "ISO 2768-1 m"
    assert run([*args(tmp_path / "tri"), "--distribution", "triangular"]) == 0
    distributions = {v["distribution"] for v in _summary(tmp_path / "tri")["inputs"].values()}
    assert distributions == {"triangular"}


def test_dask_scheduler_option(tmp_path) -> None:
    from distributed import LocalCluster

    out = tmp_path / "dask"
    with LocalCluster(
        n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0"
    ) as cluster:
        args = ["tolerance", "--samples", "100", "--seed", "2", "--out", str(out)]
        args += ["--dask-scheduler", cluster.scheduler_address, "--no-progress", "--no-plots"]
        assert run(args) == 0
    summary = _summary(out)
    assert summary["execution"]["backend"] == "dask"
    local = tmp_path / "local"
    assert run(["tolerance", "--samples", "100", "--seed", "2", "--out", str(local), *QUIET]) == 0
    pd.testing.assert_frame_equal(
        pd.read_parquet(out / "samples.parquet"), pd.read_parquet(local / "samples.parquet")
    )


def test_dynamic_responses_with_contact_options(tmp_path) -> None:
    out = tmp_path / "dyn"
    args = ["tolerance", "--responses", "dynamic", "--samples", "2", "--revolutions", "0.05"]
    args += ["--contact", "impact", "--k", "1e4 N/mm^1.5", "--cmax", "10 N*s/mm"]
    args += ["--depth", "0.1 mm", "--start", "rest", "--out", str(out), *QUIET]
    assert run(args) == 0
    summary = _summary(out)
    assert summary["responses_kind"] == "dynamic"
    law = summary["model"]["contact_law"]
    assert law["stiffness"] == pytest.approx(1e4 * 1000**1.5)
    assert law["c_max"] == pytest.approx(1e4) and law["d_max"] == pytest.approx(1e-4)
    assert "ideal_joints" in summary["responses"]["F_B_peak"]
    assert set(summary["inputs"]) >= {"clearance_O2", "clearance_O4"}


def test_dynamic_study_on_the_local_backend_names_its_method(tmp_path) -> None:
    out = tmp_path / "local"
    args = ["tolerance", "--responses", "dynamic", "--samples", "3", "--settle", "0"]
    args += ["--revolutions", "0.1", "--backend", "local", "--out", str(out)]
    # the conventional set: the explicit method (the default contact runs implicit)
    args += ["--paper-method", "ifm-conventional"]
    assert run([*args, "--no-progress", "--no-plots"]) == 0
    summary = _summary(out)
    assert summary["execution"]["backend"] == "local"
    assert summary["model"]["method"] == "explicit"
    assert "Dormand-Prince" in summary["model"]["method_reason"]
    assert summary["counts"]["ok"] == 3


def test_rtol_tightens_the_batch_engine(tmp_path) -> None:
    """--rtol reaches the integrator: the study records it, and the same samples' peaks move
    (by about the integration error, far less than the samples differ)."""
    peaks = {}
    for rtol in (None, "1e-8"):
        out = tmp_path / f"rtol-{rtol}"
        args = ["tolerance", "--responses", "dynamic", "--samples", "2", "--settle", "0"]
        args += ["--revolutions", "0.1", "--backend", "local", "--out", str(out)]
        args += ["--lubricant-viscosity", "0"]  # dry: the film's located peaks carry ~1e-3
        args += [] if rtol is None else ["--rtol", rtol]
        assert run([*args, "--no-progress", "--no-plots"]) == 0
        assert _summary(out)["model"]["solver"]["rtol"] == (1e-6 if rtol is None else 1e-8)
        peaks[rtol] = pd.read_parquet(out / "samples.parquet")["F_B_peak"].to_numpy()
    moved = np.abs(peaks["1e-8"] / peaks[None] - 1)
    assert (moved > 0).all() and (moved < 1e-3).all()


def test_dynamic_worst_case_with_a_paper_method_and_fixed_clearances(tmp_path) -> None:
    out = tmp_path / "ecs"
    args = ["tolerance", "--responses", "dynamic", "--method", "worst-case", "--no-clearances"]
    args += ["--paper-method", "ifm-ecs-spherical", "--ecs-source", "paper"]
    args += ["--revolutions", "0.02", "--corners", "sensitivity", "--out", str(out), *QUIET]
    assert run(args) == 0
    summary = _summary(out)
    # Lengths only; the joints keep the configured 0.021 mm clearance.
    assert set(summary["inputs"]) == set(LENGTHS)
    assert summary["model"]["fixed_clearances_m"] == pytest.approx(
        {"O2": 2.1e-5, "A": 2.1e-5, "B": 2.1e-5, "O4": 2.1e-5}
    )
    # Table 5 (spherical ECS): K = 2500 N/mm, D = 25 N·s/mm.
    law = summary["model"]["contact_law"]
    assert law["name"] == "impact"
    assert law["c_max"] == pytest.approx(25e3)
    assert summary["settings"]["corners"] == "sensitivity"
    evaluated = summary["settings"]["evaluated_corners"]
    assert summary["counts"]["points"] == 1 + 2 * 4 + evaluated  # nominal, ±step per input
    limits = {name: summary["inputs"][name]["limits"] for name in LENGTHS}
    for response in summary["responses"].values():
        for corner in (response["high_corner"], response["low_corner"]):
            for name, value in corner.items():
                assert value == pytest.approx(limits[name][0]) or value == pytest.approx(
                    limits[name][1]
                )


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--spec-limit", "omega4_peak<5"], "RESPONSE=LO:HI"),
        (["--spec-limit", "omega9_peak=:5 rad/s"], "unknown response 'omega9_peak'"),
        (["--spec-limit", "omega4_peak=:5"], "has no unit"),
        (["--spec-limit", "omega4_peak=:5 N"], "cannot be converted"),
        (["--k", "1e4 N/mm^1.5"], "dynamic or running only"),
        (["--rtol", "1e-7"], "--rtol applies to --responses dynamic or running only"),
        (["--responses", "dynamic", "--rtol", "0.5"], "rtol"),
        (
            ["--responses", "dynamic", "--contact", "kelvin-voigt", "--damping", "1 N*s/m"],
            "needs a stiffness",
        ),
        (["--responses", "dynamic", "--contact", "bogus"], "unknown contact law"),
        (
            ["--responses", "dynamic", "--paper-method", "ifm-ecs-spherical", "--k", "1 N/m"],
            "drop --k",
        ),
        (["--responses", "dynamic", "--ecs-source", "paper"], "give --paper-method"),
        (["--dask-scheduler", "tcp://127.0.0.1:1", "--workers", "2"], "--workers applies"),
        (["--backend", "threads"], "--backend must be local, processes, dask, gpu or cuda"),
        (["--backend", "dask"], "give --dask-scheduler"),
        (["--backend", "local", "--workers", "2"], "--workers applies to --backend processes"),
        (["--backend", "gpu"], "--backend gpu runs the dynamics: use it with --responses dynamic"),
        (
            ["--backend", "cuda"],
            "--backend cuda runs the dynamics: use it with --responses dynamic",
        ),
        (["--preset", "nope"], "unknown preset"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(tmp_path, capsys, extra, message) -> None:
    args = ["tolerance", "--samples", "5", "--out", str(tmp_path / "x"), "--no-progress", *extra]
    assert run(args) == 2
    err = capsys.readouterr().err
    assert message in err
    assert err.count("\n") == 1
    assert not (tmp_path / "x").exists()


def test_running_responses_from_the_command_line(tmp_path) -> None:
    out = tmp_path / "running"
    args = ["tolerance", "--responses", "running", "--samples", "2",
            "--spec-limit", "contact_pressure=:400 MPa", "--out", str(out), *QUIET]  # fmt: skip
    assert run(args) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert {"rocker_speed_error", "joint_force", "contact_pressure", "wear_rate"} <= set(
        summary["responses"]
    )
    assert summary["responses"]["contact_pressure"]["out_of_spec_percent"] == 0.0


def test_samples_beyond_the_clearance_get_one_warning_line_per_joint(tmp_path, capsys) -> None:
    """An absurdly soft contact (every pin sinks several times its clearance): one warning
    line per joint on stderr, as `jointplay simulate` prints its diagnostics; a stiff one
    with the paper's 21 µm joints: none."""

    def args(out, *extra: str) -> list[str]:
        return ["tolerance", "--responses", "dynamic", "--samples", "4", "--settle", "0",
                "--revolutions", "0.25", "--backend", "local", "--contact", "impact",
                "--lubricant-viscosity", "0",  # dry pins: a film would hold them
                "--out", str(out), "--no-progress", "--no-plots", *extra]  # fmt: skip

    assert run(args(tmp_path / "soft", "--k", "1e2 N/mm^1.5")) == 0
    err = capsys.readouterr().err
    lines = [line for line in err.splitlines() if "penetration-exceeds-clearance" in line]
    assert len(lines) == 4
    for line, joint in zip(lines, ("O2", "A", "B", "O4"), strict=True):
        assert line.startswith(
            f"jointplay: warning: penetration-exceeds-clearance [{joint}]: 4 of 4 samples "
            f"(100 %): the pin of {joint} penetrates its bearing by up to "
        )
    summary = _summary(tmp_path / "soft")
    clearance = [d for d in summary["diagnostics"] if d["code"] == "penetration-exceeds-clearance"]
    assert [d["count"] for d in clearance] == [4, 4, 4, 4]
    # so soft a contact is not elastic either: one more line per joint
    elastic = [d for d in summary["diagnostics"] if d["code"] == "penetration-exceeds-elastic"]
    assert [d["count"] for d in elastic] == [4, 4, 4, 4]
    frame = pd.read_parquet(tmp_path / "soft" / "samples.parquet")
    assert (frame[[f"penetration_ratio_{j}" for j in ("O2", "A", "B", "O4")]] > 1).all().all()
    # IMPACT 1e5 N/mm^1.5 in the 21 µm joints: inside the clearance, but ~50x softer than
    # the joints' Hertz law: only the elastic check speaks (docs/contact.md)
    assert run(args(tmp_path / "stiff", "--k", "1e5 N/mm^1.5", "--no-clearances")) == 0
    assert "penetration-exceeds-clearance" not in capsys.readouterr().err
    codes = {d["code"] for d in _summary(tmp_path / "stiff")["diagnostics"]}
    assert codes == {"penetration-exceeds-elastic"}


def test_an_interrupt_between_the_study_and_its_writing_keeps_every_sample(
    tmp_path, capsys, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Ctrl-C after the study finished and before its results were written (here: as the
    command reads the study's summary) used to lose every sample; they are now written as
    the partial result (the figures and report missing), beside the complete result of an
    earlier run, which is kept."""
    import os
    import signal

    from jointplay.tolerance.analysis import ToleranceStudyResult

    out = tmp_path / "out"
    args = ["tolerance", "--samples", "40", "--out", str(out), *QUIET]
    assert run(args) == 0
    before = pd.read_parquet(out / "samples.parquet")
    capsys.readouterr()
    summary = ToleranceStudyResult.summary
    calls = []

    def interrupted_once(self):
        if not calls:  # the command's own call, before the writing
            calls.append(1)
            os.kill(os.getpid(), signal.SIGINT)
        return summary(self)

    monkeypatch.setattr(ToleranceStudyResult, "summary", interrupted_once)
    assert run(args) == 130
    beside = tmp_path / "out.interrupted-1"
    assert capsys.readouterr().err.strip().splitlines()[-1] == (
        "jointplay: interrupted; 40 of 40 points finished (the figures and report missing); "
        f"their results were written to {beside} (the more complete result in {out} was kept)"
    )
    pd.testing.assert_frame_equal(pd.read_parquet(out / "samples.parquet"), before)
    pd.testing.assert_frame_equal(pd.read_parquet(beside / "samples.parquet"), before)
    assert not (beside / "report.html").exists()
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler  # nothing left held
