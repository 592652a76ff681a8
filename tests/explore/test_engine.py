"""The engine of ``jointplay explore``: the nominal analysis it keeps is the one ``simulate``
computes, and the view is drawn from the run it was given."""

from __future__ import annotations

import pytest

import jointplay
from jointplay.explore import engine
from jointplay.explore.settings import load_base, parse_query


@pytest.fixture(scope="module")
def base():
    return load_base("paper-fourbar")


def test_a_nominal_table_given_to_simulate_is_used_as_computed() -> None:
    from jointplay.settings.simulation import contact_model

    mechanism = jointplay.load_preset("paper-fourbar")
    joints = contact_model({"method": "ifm-conventional"}, mechanism).joints(mechanism)
    fresh = jointplay.simulate(mechanism, joints, settle=0, nominal=True)
    reused = jointplay.simulate(mechanism, joints, settle=0, nominal=fresh.nominal)
    assert reused.nominal is fresh.nominal
    assert reused.nominal_peaks == fresh.nominal_peaks
    assert reused.increase_percent == fresh.increase_percent


def test_the_nominal_analysis_is_shared_only_where_the_mechanism_is_the_same(base) -> None:
    small = parse_query(base, {"c.A": "5", "contact": "ifm-conventional", "start": "rest"})
    large = parse_query(base, {"c.A": "H8/g7:max", "mu": "0.2"})
    assert engine.nominal_key(base, small) == engine.nominal_key(base, large)
    for other in ({"rpm": "201"}, {"L.crank": "108.1"}):
        assert engine.nominal_key(base, parse_query(base, other)) != engine.nominal_key(base, small)


def test_the_view_of_a_kept_nominal_equals_a_fresh_one(base) -> None:
    engine._NOMINAL.clear()
    first = parse_query(base, {"c.A": "5", "contact": "ifm-conventional", "settle": "0"})
    second = parse_query(base, {"c.A": "50", "contact": "ifm-conventional", "settle": "0"})
    engine.simulate_settings(base, first)  # keeps the nominal analysis
    assert len(engine._NOMINAL) == 1
    kept = engine.view(engine.simulate_settings(base, second))
    engine._NOMINAL.clear()
    fresh = engine.view(engine.simulate_settings(base, second))
    assert kept["nominal_peaks"] == fresh["nominal_peaks"]
    assert kept["increase_percent"] == fresh["increase_percent"]
    assert kept["peaks"] == fresh["peaks"]
    assert kept["orbits"]["A"]["clearance_um"] == pytest.approx(50)


def test_joints_of_their_own_contact_are_simulated_with_it(base) -> None:
    from jointplay.settings.simulation import contact_model

    settings = parse_query(
        base, {"contact.A": "ifm-conventional", "mu.B": "0.02", "settle": "0", "c.O4": "off"}
    )
    run = engine.simulate_settings(base, settings)
    laws = {c.joint: c.law.name for c in run.result.system.clearances}
    assert set(laws) == {"O2", "A", "B"}
    assert laws["A"] != laws["O2"] and laws["B"] == laws["O2"]
    assert "A: the paper's method ifm-conventional" in run.contact
    assert "B: " in run.contact and "coefficient 0.02" in run.contact

    mechanism = run.mechanism
    joints = (
        contact_model({}, mechanism).joints(mechanism, ["O2"])
        + contact_model({"method": "ifm-conventional"}, mechanism).joints(mechanism, ["A"])
        + contact_model({"friction": 0.02}, mechanism).joints(mechanism, ["B"])
    )
    expected = jointplay.simulate(mechanism, joints, settle=0, start=jointplay.Start("steady"))
    assert {k: p["value"] for k, p in run.result.peaks.items()} == pytest.approx(
        {k: p["value"] for k, p in expected.peaks.items()}, rel=1e-12
    )


def test_ended_children_stop_and_no_new_one_starts(tmp_path) -> None:
    """What the server's stopping does to a download's ``jointplay simulate`` (here a process
    that would sleep 60 s): it is stopped at once, and no new one starts."""
    import sys
    import threading
    import time

    from jointplay.errors import ConfigError

    children = engine.Children()
    outcome: list[object] = []

    def run() -> None:
        try:
            outcome.append(
                children.run(
                    [sys.executable, "-c", "import time; time.sleep(60)"], cwd=tmp_path, timeout=90
                )
            )
        except ConfigError as exc:
            outcome.append(exc)

    worker = threading.Thread(target=run, daemon=True)
    worker.start()
    deadline = time.monotonic() + 10
    while children.running == 0 and time.monotonic() < deadline:
        time.sleep(0.01)
    assert children.running == 1
    started = time.monotonic()
    children.end()
    worker.join(10)
    assert time.monotonic() - started < 5 and children.running == 0
    assert len(outcome) == 1 and str(outcome[0]) == engine.STOPPING
    with pytest.raises(ConfigError, match="the server is stopping"):
        children.run([sys.executable, "-c", "pass"], cwd=tmp_path, timeout=10)
