"""Rendering of a tolerance study: report units, number format, the HTML page."""

from __future__ import annotations

import html
import json
import math

import pytest

from jointplay.model.mechanism import Mechanism
from jointplay.report.tolerance import (
    display_scale,
    format_value,
    input_label,
    study_plots,
    write_study,
)
from jointplay.tolerance.analysis import tolerance_study
from jointplay.tolerance.execution import Backend


@pytest.mark.parametrize(
    ("unit", "kind", "expected"),
    [
        ("m", "length", ("mm", 1e3)),
        ("m", "clearance", ("µm", 1e6)),
        ("rad", "", ("deg", 180.0 / math.pi)),
        ("rad/s^2", "", ("rad/s²", 1.0)),
        ("N*m", "", ("N·m", 1.0)),
    ],
)
def test_display_scale_gives_report_units(unit: str, kind: str, expected: tuple) -> None:
    label, factor = display_scale(unit, kind)
    assert label == expected[0]
    assert factor == pytest.approx(expected[1], rel=1e-15)


def test_format_value_scales_to_five_digits_and_marks_missing_values() -> None:
    assert format_value(0.2705123456, 1e3) == "270.51"
    assert format_value(None) == "–"
    assert format_value(math.nan) == "–"
    assert format_value(math.inf, 2.0) == "–"


def test_input_label_is_short() -> None:
    assert input_label("length_crank") == "crank"
    assert input_label("clearance_O2") == "clearance O2"


def test_report_page_is_one_html_report_with_the_tables(paper_fourbar: Mechanism, tmp_path) -> None:
    study = tolerance_study(paper_fourbar, method="rss", backend=Backend("serial"))
    write_study(study, tmp_path, plots=False)
    page = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert page.startswith("<!DOCTYPE html>")
    assert f"<h1>Tolerance study of {paper_fourbar.name}</h1>" in page
    for anchor, heading in (("inputs", "Inputs"), ("responses", "Responses")):
        assert f'<h2 id="{anchor}">{heading}</h2>' in page
    assert '<h2 id="failures">Failures (0)</h2>' in page
    assert page.count("<table>") == 3  # inputs, responses, their definitions
    assert "<td>270.5</td>" in page  # the nominal coupler, mm
    assert "<th>standard deviation</th>" in page  # headers in words
    # every response is defined where it is reported, in the page and in summary.json
    summary = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    definitions = summary["response_definitions"]
    assert list(definitions) == list(study.result.response_names)
    assert all(definitions.values())
    assert "coupler point 'mid'" in definitions["path_deviation_mid"]
    assert html.escape(definitions["path_deviation_mid"]) in page
    assert "sampling_distributions" not in summary  # RSS samples nothing


def test_monte_carlo_report_says_how_inputs_were_sampled(
    paper_fourbar: Mechanism, tmp_path
) -> None:
    study = tolerance_study(paper_fourbar, samples=50, seed=1, backend=Backend("serial"))
    write_study(study, tmp_path, plots=False)
    summary = json.loads((tmp_path / "summary.json").read_text(encoding="utf-8"))
    assert summary["settings"]["truncated_at_limits"] is True
    assert "truncated at their specification limits" in summary["sampling_distributions"]
    page = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert "truncated at their specification limits" in page


def test_figure_format_writes_print_copies_beside_the_embedded_pngs(
    paper_fourbar: Mechanism, tmp_path
) -> None:
    study = tolerance_study(paper_fourbar, samples=50, seed=1, backend=Backend("serial"))
    written = write_study(study, tmp_path, figure_format="svg")
    pngs = sorted(p.stem for p in written if p.suffix == ".png")
    assert pngs == ["histograms", "scatter", "tornado"]
    assert sorted(p.stem for p in written if p.suffix == ".svg") == pngs
    assert all((tmp_path / f"{stem}.svg").read_text().lstrip().startswith("<?xml") for stem in pngs)
    page = (tmp_path / "report.html").read_text(encoding="utf-8")
    assert page.count("<img") == len(pngs)  # the report embeds the PNGs only


def test_the_tolerance_figures_have_no_overlapping_text(paper_fourbar: Mechanism, text_overlaps):
    study = tolerance_study(paper_fourbar, samples=50, seed=1, backend=Backend("serial"))
    study_plots(study)
    assert set(text_overlaps) == {"tornado", "histograms", "scatter"}
    assert not any(text_overlaps.values()), text_overlaps


def test_worker_processes_draw_the_same_images(paper_fourbar: Mechanism) -> None:
    # the command line lends the batch engine's idle workers to the plots: same files, same order
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    study = tolerance_study(paper_fourbar, samples=50, seed=1, backend=Backend("serial"))
    serial = study_plots(study)
    spawn = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(2, mp_context=spawn) as pool:
        parallel = study_plots(study, executor=pool)
    assert list(serial) == ["tornado.png", "histograms.png", "scatter.png"]
    assert list(parallel) == list(serial)
    assert parallel == serial


def test_a_pool_that_is_shut_down_leaves_the_figures_to_this_process(
    paper_fourbar: Mechanism,
) -> None:
    from concurrent.futures import ThreadPoolExecutor

    study = tolerance_study(paper_fourbar, samples=30, seed=2, backend=Backend("serial"))
    pool = ThreadPoolExecutor(1)
    pool.shutdown()
    assert study_plots(study, executor=pool) == study_plots(study)
