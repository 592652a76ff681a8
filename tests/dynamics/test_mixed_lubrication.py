"""The film-to-contact transition in a simulation (docs/contact.md, "The film-to-contact
transition"): the paper four-bar at 21 µm in every joint under the π-film, O2 with a rough
pin and hole (σ = 3 µm: its asperities touch where its film thins to 9 µm), the other joints
smooth (σ = 0: the film alone up to the wall). O2 runs in mixed lubrication, its dry law and
friction carrying the asperities' share; the others in full film, their contact force zero;
the energy balance closes; the regimes reach ``summary.json``."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from jointplay.dynamics.regimes import joint_regime, regime_line
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SimulationResult, SolverOptions, Start, simulate
from jointplay.io.config import load_preset

JOINTS = ("O2", "A", "B", "O4")


@pytest.fixture(scope="module")
def rough_o2() -> SimulationResult:
    mechanism = load_preset("paper-fourbar")
    contact = ContactModel(film_model="short-bearing-pi", roughness=0.0)
    joints = [
        dataclasses.replace(j.with_clearance(21e-6), roughness=3e-6 if j.joint == "O2" else 0.0)
        for j in contact.joints(mechanism)
    ]
    return simulate(
        mechanism, joints, revolutions=0.5, settle=0, start=Start("steady"),
        solver=SolverOptions(rtol=1e-8),
    )  # fmt: skip


def test_two_joints_with_different_roughness_behave_differently(
    rough_o2: SimulationResult,
) -> None:
    """O2's asperities carry load (F_N > 0 where its film is thinner than 3σ = 9 µm), the
    smooth joints' contact force stays 0 (their films never reach the wall)."""
    steps = rough_o2.steps
    assert steps["Fn_O2"].max() > 0.0
    h_o2 = 21e-6 - np.hypot(steps["ex_O2"], steps["ey_O2"])
    assert np.all(steps["Fn_O2"][h_o2 > 9e-6] == 0.0)
    for joint in JOINTS[1:]:
        assert steps[f"Fn_{joint}"].max() == 0.0
    regimes = rough_o2.film_regimes
    assert regimes["O2"] is not None and regimes["O2"].full_film < 1.0
    for joint in JOINTS[1:]:
        regime = regimes[joint]
        assert regime is not None and regime.full_film == 1.0 and regime.h_min > 0


def test_the_energy_balance_closes_in_mixed_lubrication(rough_o2: SimulationResult) -> None:
    """KE + V − W_motor + W_contact constant: the asperities' power (dry law and friction)
    and the film's faded share both in W_contact."""
    assert rough_o2.success
    assert rough_o2.solver_stats["energy_residual"] < 1e-5


def test_the_regimes_reach_the_summary(rough_o2: SimulationResult) -> None:
    summary = rough_o2.summary()["film_regimes"]
    assert set(summary) == set(JOINTS)
    o2 = summary["O2"]
    assert o2["full_film"] + o2["mixed"] + o2["boundary"] == pytest.approx(1.0)
    assert o2["roughness_m"] == 3e-6
    assert o2["thresholds_lambda"] == {"full_film": 3.0, "boundary": 1.0}


def test_the_regime_fractions_count_time_by_lambda() -> None:
    """Half the time at λ = 5, a quarter at λ = 2, a quarter at λ = 0.5 (σ = 1 µm, c = 21 µm):
    fractions 1/2, 1/4, 1/4, h_min the smallest; a dry joint has none."""
    contact = ContactModel(film_model="short-bearing-pi", roughness="1 um")
    joint = contact.joints(load_preset("paper-fourbar"), ["O2"], clearance=21e-6)[0]
    assert joint.roughness == pytest.approx(1e-6)
    t = np.arange(9) * 0.25
    h = np.array([5, 5, 5, 5, 2, 2, 0.5, 0.5, 0.5]) * 1e-6  # by the intervals' midpoints
    regime = joint_regime(joint, t, 21e-6 - h, np.zeros_like(h))
    assert (regime.full_film, regime.mixed, regime.boundary) == pytest.approx((0.5, 0.25, 0.25))
    assert regime.h_min == pytest.approx(0.5e-6)
    assert "full film 50 %" in regime_line("O2", regime)
    assert regime_line("O2", None) == "O2: dry (no lubricant)"


def test_simulate_prints_and_writes_the_regimes(tmp_path, capsys) -> None:
    """``jointplay simulate --film-model short-bearing-pi --roughness "3 um"``: one regime line
    per joint after the run, the same fractions in summary.json."""
    import json
    import re

    from jointplay.cli import run

    out = tmp_path / "run"
    status = run(
        ["simulate", "--revolutions", "0.5", "--settle", "0", "--film-model",
         "short-bearing-pi", "--roughness", "3 um", "--no-plots", "--out", str(out)]
    )  # fmt: skip
    text = capsys.readouterr().out
    assert status == 0, text
    summary = json.loads((out / "summary.json").read_text(encoding="utf-8"))
    for name in JOINTS:
        regime = summary["film_regimes"][name]
        assert regime["roughness_m"] == pytest.approx(3e-6)
        line = re.search(rf"^  {name}: full film (\d+) %, mixed (\d+) %, boundary (\d+) %", text,
                         flags=re.MULTILINE)  # fmt: skip
        assert line, text
        assert int(line.group(1)) == round(100 * regime["full_film"])


def test_the_batch_engine_runs_the_transition_as_the_single_engine() -> None:
    """The CPU backends' implicit lanes and the single engine give the same settled peaks with
    a rough O2 (σ = 3 µm) in mixed lubrication at 21 µm, and the lanes take each joint's σ:
    both report O2's deepest wall penetration |e| − c alike; the rough O2's asperity
    interference δ_a = |e| − (c − 3σ) is > 0 (its asperities touch), the smooth one's
    wall penetration < 0 (it floats)."""
    from jointplay.dynamics.batch import BatchSamples, simulate_batch

    mechanism = load_preset("paper-fourbar")
    contact = ContactModel(film_model="short-bearing-pi", roughness=0.0)
    smooth = [j.with_clearance(21e-6) for j in contact.joints(mechanism)]
    rough = [dataclasses.replace(j, roughness=3e-6) if j.joint == "O2" else j for j in smooth]
    samples = BatchSamples(clearances={j: np.array([21e-6]) for j in JOINTS})
    peaks: dict[str, float] = {}
    for name, joints in (("smooth", smooth), ("rough", rough)):
        single = simulate(mechanism, joints, revolutions=1, settle=2, start=Start("steady"))
        batch = simulate_batch(mechanism, joints, samples, backend="local", revolutions=1,
                               settle=2)  # fmt: skip
        assert batch.method == "implicit"
        for joint in JOINTS:
            peak = single.peaks[f"F_{joint}"]["value"]
            assert batch.peaks[f"F_{joint}"].iloc[0] == pytest.approx(peak, rel=1e-4)
        window = single.steps["t"] >= single.t[-1] - mechanism.driver.period
        deepest = float(single.steps["pen_O2"][window].max())
        assert batch.statistics["pen_O2"].iloc[0] == pytest.approx(deepest, rel=1e-2)
        peaks[name] = deepest
        assert single.steps["contact_O2"][window].any() == (name == "rough")
    assert peaks["rough"] + 3 * 3e-6 > 0 > peaks["smooth"]


def test_a_bad_roughness_is_one_clear_line(tmp_path, capsys) -> None:
    """``--roughness`` takes a length from 0 to 100 µm; anything else is refused in one line
    naming the option, exit status 2, nothing written."""
    from jointplay.cli import run

    for bad in ("-1 um", "2 m", "rough"):
        out = tmp_path / "run"
        assert run(["simulate", "--roughness", bad, "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and "--roughness" in err, err
        assert not out.exists()


def test_the_reported_penetration_is_the_walls() -> None:
    """Under the default π-film the kernels' δ is the asperities' (|e| − (c − 3σ)); every
    output still reports the wall's |e| − c (the asperities' is 3σ larger)."""
    mechanism = load_preset("paper-fourbar")
    joints = ContactModel().joints(mechanism, ["O2"])
    result = simulate(mechanism, joints, revolutions=0.1, settle=0, start=Start("steady"))
    steps = result.steps
    wall = steps["e_O2"] - joints[0].clearance
    assert np.allclose(steps["pen_O2"], wall, rtol=0, atol=1e-12)
    assert joints[0].roughness > 0 and (steps["pen_O2"] < 0).all()
