"""``jointplay design --resume`` and ``--max-time``: going on from a result folder."""

from __future__ import annotations

import json

import pandas as pd

from jointplay.cli import run

QUIET = ["--no-progress", "--no-plots", "--workers", "1", "--no-model-sensitivity"]
STUDY = ["design", "--preset", "paper-fourbar", "--fits", "H9/d9,H11/c11", "--classes", "c,v",
         "--require", "omega4_peak <= 100 rad/s"]  # fmt: skip


def _files(folder) -> dict[str, bytes]:
    return {p.name: p.read_bytes() for p in sorted(folder.iterdir()) if p.is_file()}


def test_resume_with_more_samples_gives_the_whole_study_and_says_what_it_merged(
    tmp_path, capsys
) -> None:
    out, whole = tmp_path / "design", tmp_path / "whole"
    assert run([*STUDY, "--max-samples", "800", "--out", str(out), *QUIET]) == 0
    assert "undecided" in capsys.readouterr().out
    assert run([*STUDY, "--resume", "--out", str(out), *QUIET]) == 0
    printed = capsys.readouterr().out
    assert "choose H11/c11 / v" in printed
    assert "resumed: 2 runs merged, 1,600 samples kept" in printed
    assert run([*STUDY, "--out", str(whole), *QUIET]) == 0
    pd.testing.assert_frame_equal(
        pd.read_parquet(out / "design.parquet"), pd.read_parquet(whole / "design.parquet")
    )


def test_a_changed_study_is_refused_in_one_line_and_nothing_is_written(tmp_path, capsys) -> None:
    out = tmp_path / "design"
    assert run([*STUDY, "--max-samples", "200", "--out", str(out), *QUIET]) == 0
    before = _files(out)
    capsys.readouterr()
    changed = [a.replace("100 rad/s", "90 rad/s") for a in STUDY]
    assert run([*changed, "--resume", "--out", str(out), *QUIET]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert "different requirements[0].text: 'omega4_peak <= 100 rad/s' there" in err
    assert _files(out) == before


def test_resume_needs_a_design_result(tmp_path, capsys) -> None:
    assert run([*STUDY, "--resume", "--out", str(tmp_path / "none"), *QUIET]) == 2
    err = capsys.readouterr().err
    assert "--resume:" in err and "holds no design result" in err and err.count("\n") == 1
    assert not (tmp_path / "none").exists()


def test_max_time_stops_with_the_verdicts_reached_and_says_what_would_decide_the_rest(
    tmp_path, capsys
) -> None:
    out = tmp_path / "design"
    assert run([*STUDY, "--max-time", "1 ms", "--out", str(out), *QUIET]) == 0
    printed = capsys.readouterr().out
    # cost-ordered: class v's 2 schemes ran a block, class c's waited (not run)
    assert "stopped: 2 at the time budget, not run: 2 at the time budget" in printed
    assert (
        "stopped at the time budget (0.001 s): 4 scheme(s) undecided (2 not run yet); "
        "--resume with " in printed
    )
    assert "--max-time 0.002 s would allow ~" in printed
    assert run([*STUDY, "--resume", "--out", str(out), *QUIET]) == 0
    assert "choose H11/c11 / v" in capsys.readouterr().out


def test_max_time_needs_a_time(tmp_path, capsys) -> None:
    assert run([*STUDY, "--max-time", "10", "--out", str(tmp_path / "d"), *QUIET]) == 2
    err = capsys.readouterr().err
    assert "--max-time: '10' has no unit" in err and err.count("\n") == 1


def test_every_output_says_what_each_decision_took_and_on_which_interval(tmp_path, capsys) -> None:
    out = tmp_path / "design"
    assert run([*STUDY, "--out", str(out), "--no-progress", "--workers", "1"]) == 0
    printed = capsys.readouterr().out
    assert (
        "verdicts on the 95 % beta-binomial confidence sequence (valid at every look); "
        "samples: what each took; stopped: 2 decided, not run: 2 dearer than a scheme shown to meet"
    ) in printed
    csv = pd.read_csv(out / "design.csv")
    assert (csv["decided_at"] == 1600).all() and (csv["stopped"] == "decided").all()
    assert (csv["verdict_interval"] == "sequential").all()
    assert (csv["verdict_low_pct_omega4_peak <= 100 rad/s"] >= 99.73).all()
    summary = json.loads((out / "summary.json").read_text())
    record = summary["schemes"][0]["requirements"][0]
    # decided on the sequence (at or above 99.73 %), wider than the exact interval reported
    assert 0.9973 <= record["verdict_interval"][0] < record["yield_ci95"][0]
    assert summary["settings"]["verdict_rule"] == "sequential"
    report = (out / "report.html").read_text()
    assert "95 % beta-binomial confidence sequence (valid at every look)" in report
    assert (
        "stopped: 2 decided, not run: 2 dearer than a scheme shown to meet" in report
        and "looks every 100 up to 4,000" in report
    )


def test_an_interrupted_design_is_kept_as_partial_and_resumed_to_the_whole_answer(
    tmp_path, capsys, monkeypatch
) -> None:
    """Interrupted in its 8th block (of 16), the study keeps its samples in a folder marked
    partial (its samples of the most it could take), and --resume gives the whole run's table."""
    import dataclasses

    from jointplay.io.output import MARKER
    from jointplay.study import design as design_module
    from jointplay.tolerance.execution import NOT_RUN

    real, calls = design_module.run, {"n": 0}

    def interrupted_run(model, x, **kwargs):
        outcome = real(model, x, **kwargs)
        calls["n"] += 1
        if calls["n"] != 8:
            return outcome
        status = outcome.status.copy()
        status[len(x) // 2 :] = NOT_RUN
        return dataclasses.replace(outcome, status=status, interrupted=True)

    out, whole = tmp_path / "design", tmp_path / "whole"
    with monkeypatch.context() as patch:
        patch.setattr(design_module, "run", interrupted_run)
        assert run([*STUDY, "--out", str(out), *QUIET]) == 130
    err = capsys.readouterr().err.strip().splitlines()[-1]
    # cost-ordered: class v's 8th block not kept (its 2 schemes at 700; class c, dearer,
    # waits), of 4 x 4 000
    assert err == (
        f"jointplay: interrupted; 1400 of 16000 samples finished; their results were "
        f"written to {out}"
    )
    assert json.loads((out / MARKER).read_text())["complete"] < 1.0
    assert run([*STUDY, "--resume", "--out", str(out), *QUIET]) == 0
    assert "resumed: 2 runs merged" in capsys.readouterr().out
    assert run([*STUDY, "--out", str(whole), *QUIET]) == 0
    pd.testing.assert_frame_equal(
        pd.read_parquet(out / "design.parquet"), pd.read_parquet(whole / "design.parquet")
    )
