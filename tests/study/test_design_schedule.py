"""The cost-ordered schedule of ``samples="auto"``: a scheme dearer than an open cheaper one
waits (it gets samples once every cheaper one is decided ``fails``, stopped at the most
samples or can no longer be chosen), except in the lanes a block leaves free on a device."""

from __future__ import annotations

import pandas as pd
import pytest

from jointplay.study import design as design_module
from jointplay.study.design import _free_lanes, _plan, design_study
from jointplay.tolerance.execution import Backend

SERIAL = Backend("serial")
#: one fit, four classes: each scheme its own sample stream (a kinematic study shares one per
#: class); by cost v < c < m < f. Class v fails at the first look, c meets at 1 600.
FITS = ["H11/c11"]
CLASSES = ["f", "m", "c", "v"]
REQUIRE = ["omega4_peak <= 13.97 rad/s"]


def _counting(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """The samples of each run of the study's blocks."""
    real = design_module.run
    sizes: list[int] = []

    def run(model, x, **kwargs):
        sizes.append(len(x))
        return real(model, x, **kwargs)

    monkeypatch.setattr(design_module, "run", run)
    return sizes


def test_a_dearer_scheme_waits_while_a_cheaper_one_is_open(paper_fourbar, monkeypatch) -> None:
    sizes = _counting(monkeypatch)
    result = design_study(paper_fourbar, FITS, CLASSES, REQUIRE, backend=SERIAL)
    table = result.table.set_index("scheme")
    assert table["samples"].to_dict() == {"H11/c11 / c": 1600, "H11/c11 / v": 100}
    assert table["verdict"].to_dict() == {"H11/c11 / c": "meets", "H11/c11 / v": "fails"}
    assert result.best == "H11/c11 / c"
    # the dearer classes never ran: a cheaper scheme was open until it was shown to meet
    assert result.settings["not_run"] == [
        {"scheme": "H11/c11 / f", "cost": pytest.approx(22.1, abs=0.5), "stopped": "dearer"},
        {"scheme": "H11/c11 / m", "cost": pytest.approx(21.36, abs=0.01), "stopped": "dearer"},
    ]
    # one scheme per block (no lane is free on the CPU): v's block, then c's sixteen; every
    # scheme at once (the former schedule) ran 4 x 100, then 3 x 100 up to 1 600: 4 900
    assert sizes == [100] * 17 and sum(sizes) == 1700
    assert result.settings["schedule"] == "cost-ordered"
    assert result.settings["runs"][-1]["samples_computed"] == 1700


def test_a_fixed_sample_size_runs_every_scheme(paper_fourbar) -> None:
    result = design_study(paper_fourbar, FITS, CLASSES, REQUIRE, samples=100, backend=SERIAL)
    assert sorted(result.table["samples"]) == [100] * 4 and result.settings["not_run"] == []
    assert result.settings["schedule"] == "every scheme"


def test_a_cheaper_scheme_undecided_at_the_most_samples_lets_the_next_one_run(
    paper_fourbar,
) -> None:
    result = design_study(paper_fourbar, FITS, CLASSES, REQUIRE, max_samples=800, backend=SERIAL)
    table = result.table.set_index("scheme")
    # c is undecided at 800 (800 failure-free samples do not show 99.73 %): m, then f, get
    # their turn, each to 800
    assert table["stopped"].to_dict() == {
        "H11/c11 / c": "max-samples",
        "H11/c11 / f": "max-samples",
        "H11/c11 / m": "max-samples",
        "H11/c11 / v": "decided",
    }
    assert result.settings["not_run"] == [] and result.best is None


def test_free_lanes_only_on_a_device() -> None:
    assert _free_lanes(Backend("cuda")) == 1024
    assert _free_lanes(Backend("gpu", chunk_size=4096)) == 4096
    for cpu in (Backend("serial"), Backend("processes", workers=2), None):
        assert _free_lanes(cpu) == 1


def test_the_plan_fills_free_lanes_in_cost_order() -> None:
    costs = [3.0, 1.0, 2.0, 1.0, 4.0]
    looks = (100, 200, 300)
    key = [0, 1, 2, 3, 4]
    reached = dict.fromkeys(key, 0)
    looked = [0] * 5
    # on the CPU only the cheapest (a tie: both)
    assert _plan(set(key), costs, key, looks, looked, reached, 1) == {1: 100, 3: 100}
    # 400 free lanes: the tie's 200 samples, then schemes 2 and 0 in cost order; 4 waits
    assert _plan(set(key), costs, key, looks, looked, reached, 400) == {
        1: 100, 3: 100, 2: 100, 0: 100,
    }  # fmt: skip
    # a scheme whose stream holds its samples already is judged at no cost
    shared = [0, 1, 1, 1, 4]
    plan = _plan({0, 1, 2, 4}, costs, shared, looks, looked, reached, 1)
    assert plan == {1: 100, 2: 100}
    # a fixed sample size: every open scheme
    assert _plan({0, 4}, costs, key, (50,), looked, reached, None) == {0: 50, 4: 50}


def test_free_lanes_change_the_dearer_schemes_counts_not_the_answer(
    paper_fourbar, monkeypatch
) -> None:
    cpu = design_study(paper_fourbar, FITS, CLASSES, REQUIRE, backend=SERIAL)
    sizes = _counting(monkeypatch)
    monkeypatch.setattr(design_module, "_free_lanes", lambda backend: 1024)
    device = design_study(paper_fourbar, FITS, CLASSES, REQUIRE, backend=SERIAL)
    assert max(sizes) <= 1024 and sizes[0] == 400  # the first block: all four schemes
    assert device.best == cpu.best
    chosen = device.table.set_index("scheme").loc[cpu.best]
    pd.testing.assert_series_equal(chosen, cpu.table.set_index("scheme").loc[cpu.best])
    # m and f rode in the free lanes: samples without delaying the cheapest
    assert (device.table["samples"] > 0).all() and len(device.table) == 4
