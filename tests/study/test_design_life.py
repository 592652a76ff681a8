"""The design study's life-quantile requirement ``Bp >= X``: its parsing, and its decision as
the yield of "functional life >= X" against 1 − p, on a stub model whose lives are known in
closed form (no dynamics)."""

from __future__ import annotations

import numpy as np
import pytest

from jointplay.errors import ConfigError
from jointplay.execution.backends import Backend
from jointplay.study.requirements import FUNCTIONAL_LIFE, parse_requirement
from jointplay.tolerance.confidence import YieldEstimate, verdict

from .test_life import ConstantWear

HOUR = 3600.0
LOCAL = Backend("local")


@pytest.mark.parametrize(
    ("text", "p", "comparison", "hours"),
    [
        ("B10 >= 2000 h", 0.10, ">=", 2000.0),
        ("B1>=500h", 0.01, ">=", 500.0),
        ("  B50 > 3 d ", 0.50, ">", 72.0),
        ("B0.5 >= 10 h", 0.005, ">=", 10.0),
    ],
)
def test_life_quantile_requirements_parse(text: str, p: float, comparison: str, hours: float):
    r = parse_requirement(text, {})
    assert (r.response, r.comparison, r.unit) == (FUNCTIONAL_LIFE, comparison, "s")
    assert r.quantile == pytest.approx(p)
    assert r.confidence == pytest.approx(1.0 - p)  # the yield target: (100 − p) %
    assert r.limit == pytest.approx(hours * HOUR)
    assert r.text == text.strip()
    assert not r.upper


@pytest.mark.parametrize(
    ("text", "culprit"),
    [
        ("B10 >= 2000", "'B10 >= 2000 h'"),
        ("B120 >= 1 h", "between 0 and 100"),
        ("B0 >= 1 h", "between 0 and 100"),
        ("B >= 1 h", "between 0 and 100"),
        ("B10 <= 2000 h", "write 'B10 >= 2000 h'"),
        ("B10 < 2000 h", "lower bound"),
        ("B10 >= 2000 h @95", "drop the '@95'"),
        ("B10 >= 2000 N", "cannot be converted"),
        ("B10 >= 0 h", "must be > 0"),
        ("B10 >= >= 2000 h", "one comparison only"),
    ],
)
def test_bad_life_quantile_requirements_are_one_line_errors(text: str, culprit: str):
    with pytest.raises(ConfigError) as caught:
        parse_requirement(text, {})
    message = str(caught.value)
    assert "\n" not in message
    assert culprit in message, message
    assert repr(text) in message


def test_the_population_life_refuses_a_life_quantile():
    """``jointplay life`` computes the quantiles: a B_p is no requirement there."""
    from jointplay.io.config import load_preset
    from jointplay.study.life import parse_life_requirements

    with pytest.raises(ConfigError, match="the life is what this study computes"):
        parse_life_requirements(load_preset("paper-fourbar"), ["B10 >= 100 h"])


def _design(requirements, **options):
    from jointplay.io.config import load_preset
    from jointplay.study.design import design_study, schemes
    from jointplay.tolerance.parts import Process, model_inputs

    mechanism = load_preset("paper-fourbar")
    (scheme,) = schemes(mechanism, ["H8/g7"], ["m"])
    spec = scheme.spec(mechanism, Process())
    names, _ = model_inputs(spec.names, np.empty((0, len(spec.names))))
    options = {"samples": 60, "seed": 3, "clearance_limit": 30e-6, **options}
    return design_study(
        mechanism, ["H8/g7"], ["m"], requirements, backend=LOCAL,
        model=ConstantWear(names), **options,
    ), names  # fmt: skip


def test_b_p_is_the_yield_of_the_life_at_x_against_one_minus_p():
    """Every joint wears 1 µm/h to a 30 µm limit: each sample's life is (30 µm − its largest
    clearance)/(1 µm/h). ``B10 >= X`` fails in the samples that live less than X, and its
    verdict is the yield verdict of those failures against 90 %, at every X: meets where
    few live less, fails where most do; the lives beyond X are censored at X."""
    probe, names = _design(["B10 >= 1000 h"])
    frame = probe.samples
    clearance = frame[[n for n in names if n.startswith("clearance_")]].to_numpy()
    lives = (30e-6 - clearance.max(axis=1)) / 1e-6  # h
    assert frame[FUNCTIONAL_LIFE].to_numpy() / HOUR == pytest.approx(np.maximum(lives, 0.0))
    seen = set()
    for x in np.quantile(lives, [0.01, 0.08, 0.5]):
        text = f"B10 >= {x:.6g} h"
        result, _ = _design([text], life_step=x * HOUR / 4)
        row = result.table.iloc[0]
        life = result.samples[FUNCTIONAL_LIFE].to_numpy() / HOUR
        failures = int(np.sum(lives < float(f"{x:.6g}")))
        assert row[f"failures_{text}"] == failures
        expected = verdict(YieldEstimate(failures, 60), 0.90).name
        assert row[f"verdict_{text}"] == expected
        censored = result.samples[f"{FUNCTIONAL_LIFE}_censored"].to_numpy()
        assert censored.sum() == 60 - failures
        assert life[censored] == pytest.approx(float(f"{x:.6g}"))
        seen.add(expected)
    assert {"meets", "fails"} <= seen
    assert result.settings["functional_life"]["simulations"] > 60


def test_the_other_requirements_end_a_life():
    """``wear_rate_A <= …`` is met by every sample (1 µm/h): the clearance limit ends the lives
    as before; a ``wear_rate_A`` limit below 1 µm/h ends every life at once (life 0)."""
    met, _ = _design(["B10 >= 5 h", "wear_rate_A <= 2 um/h"], samples=10)
    assert (met.samples[f"{FUNCTIONAL_LIFE}_failing"].str.startswith("clearance of ")
            | met.samples[f"{FUNCTIONAL_LIFE}_censored"]).all()  # fmt: skip
    missed, _ = _design(["B10 >= 5 h", "wear_rate_A <= 0.5 um/h"], samples=10)
    assert (missed.samples[FUNCTIONAL_LIFE] == 0).all()
    assert set(missed.samples[f"{FUNCTIONAL_LIFE}_failing"]) == {"wear_rate_A <= 0.5 um/h"}
    assert missed.table.iloc[0]["verdict_B10 >= 5 h"] == "fails"


@pytest.mark.parametrize(
    ("requirements", "options", "culprit"),
    [
        (["B10 >= 100 h"], {"clearance_limit": None}, "nothing ends a life"),
        (["B10 >= 100 h"], {"life_step": 200 * HOUR}, "--update-hours"),
    ],
)
def test_a_b_p_design_that_cannot_run_is_refused(requirements, options, culprit):
    with pytest.raises(ConfigError, match=culprit):
        _design(requirements, **options)


def test_a_resumed_b_p_design_keeps_its_lives(tmp_path, monkeypatch: pytest.MonkeyPatch):
    """--resume: the lives of the kept samples are read back, not re-simulated; the resumed
    study's table is the uninterrupted one's."""
    import json

    import pandas as pd

    from jointplay.io.output import json_text
    from jointplay.study import design as module
    from jointplay.study.design import Earlier

    whole, _ = _design(["B10 >= 8 h"], samples=40)
    first, _ = _design(["B10 >= 8 h"], samples=20)
    path = tmp_path / "samples.parquet"
    first.samples.to_parquet(path, index=False)
    settings = json.loads(json_text(first.summary()))["settings"]
    kept = Earlier(str(tmp_path), settings, pd.read_parquet(path))
    lived = []
    real = module.functional_lives

    def counted(model, x, *args, **options):
        lived.append(len(x))
        return real(model, x, *args, **options)

    monkeypatch.setattr(module, "functional_lives", counted)
    resumed, _ = _design(["B10 >= 8 h"], samples=40, resume=kept)
    assert lived == [20]  # only the new samples' lives
    columns = ["samples", "failures_B10 >= 8 h", "verdict_B10 >= 8 h", "yield_B10 >= 8 h"]
    assert resumed.table[columns].equals(whole.table[columns])
    assert resumed.samples[FUNCTIONAL_LIFE].to_numpy() == pytest.approx(
        whole.samples[FUNCTIONAL_LIFE].to_numpy()
    )
