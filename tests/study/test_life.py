"""The functional life of one mechanism, checked by hand on stub response models whose wear
rate is known in closed form (no dynamics)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
import pytest

from jointplay.errors import ConfigError
from jointplay.execution.backends import Backend
from jointplay.study.life import (
    Criterion,
    clearance_criteria,
    functional_lives,
)
from jointplay.study.life_result import SIMULATION_FAILED
from jointplay.tolerance.response_base import Evaluation

HOUR = 3600.0
LOCAL = Backend("local")


@dataclass(frozen=True)
class WearStub:
    """Two joints A and B: wear rate a + b·c (m/s) each, a force growing with A's clearance
    (``joint_force = f0 + f1·c_A``, N); fails (NaN) beyond ``breaks`` of clearance A."""

    a: float = 1e-6 / HOUR  # 1 µm/h
    b: float = 0.0  # 1/s
    f0: float = 100.0
    f1: float = 1e6  # N/m: +1 N per µm
    breaks: float = math.inf
    chunk_size: int = 1000

    input_names = ("length_crank", "clearance_A", "clearance_B")
    response_names = ("wear_rate_A", "wear_rate_B", "joint_force", "wear_rate")

    @property
    def units(self) -> dict[str, str]:
        return {"wear_rate_A": "m/s", "wear_rate_B": "m/s", "joint_force": "N", "wear_rate": "m/s"}

    def evaluate(self, x: np.ndarray) -> Evaluation:
        c = x[:, 1:3]
        rates = self.a + self.b * c
        force = self.f0 + self.f1 * c[:, 0]
        values = np.column_stack([rates, force, rates.max(axis=1)])
        ok = c[:, 0] <= self.breaks
        values[~ok] = np.nan
        return Evaluation(values, ok, tuple("" if o else "IntegrationError: stub" for o in ok))

    def describe(self) -> dict[str, str]:
        return {"model": "stub"}


def _x(clearances_a, clearance_b=10e-6):
    c = np.asarray(clearances_a, dtype=float)
    return np.column_stack([np.full(len(c), 0.1), c, np.full(len(c), clearance_b)])


def test_constant_rate_life_is_the_margin_over_the_rate():
    """Hand check: clearance 20 µm growing 1 µm/h to its 50 µm limit lives 30 h; at 35 µm,
    15 h; B (10 µm, limit 100 µm) would last 90 h, so A fails first and is named."""
    lives = functional_lives(
        WearStub(),
        _x([20e-6, 35e-6]),
        clearance_criteria({"A": 50e-6, "B": 100e-6}),
        hours=200 * HOUR,
        first_step=4 * HOUR,
        backend=LOCAL,
    )
    assert lives.life / HOUR == pytest.approx([30.0, 15.0], rel=1e-9)
    assert not lives.censored.any()
    assert lives.failing == ("clearance of A <= 50 µm",) * 2
    # the history ends at the failure, at the limit
    time, clearances = lives.history[0][-1]
    assert time / HOUR == pytest.approx(30.0)
    assert clearances[0] == pytest.approx(50e-6)


def test_a_life_beyond_the_hours_is_censored_there():
    lives = functional_lives(
        WearStub(), _x([20e-6]), clearance_criteria({"A": 50e-6}),
        hours=25 * HOUR, first_step=5 * HOUR, backend=LOCAL,
    )  # fmt: skip
    assert lives.censored.tolist() == [True]
    assert lives.life[0] == pytest.approx(25 * HOUR)
    assert lives.failing == ("",)


def test_a_response_requirement_fails_first_and_is_named():
    """joint_force = 100 N + 1 N/µm·c_A <= 140 N: fails at c_A = 40 µm, i.e. after 20 h from
    20 µm, before the 50 µm clearance limit (30 h)."""
    force = Criterion("joint_force <= 140 N", "joint_force", True, 140.0)
    lives = functional_lives(
        WearStub(), _x([20e-6]), (force, *clearance_criteria({"A": 50e-6})),
        hours=100 * HOUR, first_step=3 * HOUR, backend=LOCAL,
    )  # fmt: skip
    assert lives.life[0] / HOUR == pytest.approx(20.0, rel=1e-9)
    assert lives.failing == ("joint_force <= 140 N",)


def test_a_growing_rate_meets_the_closed_form_within_the_tolerance():
    """dc/dt = a + b·c: c(t) = (c0 + a/b) e^{bt} − a/b, so the life to the limit L is
    ln((L + a/b)/(c0 + a/b))/b. Euler steps with the rate evaluated at each step's start
    would be late by about half the rate's change per step; the rule keeps it within 1 %."""
    a, b = 1e-6 / HOUR, 0.05 / HOUR  # the rate grows 5 % per hour per metre... of clearance
    c0, limit = 20e-6, 200e-6
    exact = math.log((limit + a / b) / (c0 + a / b)) / b
    lives = functional_lives(
        WearStub(a=a, b=b), _x([c0]), clearance_criteria({"A": limit}),
        hours=500 * HOUR, first_step=20 * HOUR, tolerance=0.01, min_step=1.0, backend=LOCAL,
    )  # fmt: skip
    assert lives.life[0] == pytest.approx(exact, rel=0.01)
    loose = functional_lives(
        WearStub(a=a, b=b), _x([c0]), clearance_criteria({"A": limit}),
        hours=500 * HOUR, first_step=20 * HOUR, tolerance=0.2, min_step=1.0, backend=LOCAL,
    )  # fmt: skip
    # the tolerance is what controls it: a loose one errs by more, with fewer simulations
    assert abs(loose.life[0] / exact - 1) > abs(lives.life[0] / exact - 1)
    assert loose.resimulations[0] < lives.resimulations[0]
    assert not lives.floor_steps.any()


def test_steps_at_the_smallest_step_are_counted():
    """With a floor above what the tolerance asks, steps are accepted there, counted, and
    the largest estimate kept."""
    a, b = 1e-6 / HOUR, 0.05 / HOUR
    lives = functional_lives(
        WearStub(a=a, b=b), _x([20e-6]), clearance_criteria({"A": 200e-6}),
        hours=500 * HOUR, first_step=20 * HOUR, tolerance=0.01, backend=LOCAL,
    )  # fmt: skip
    assert lives.floor_steps[0] > 0
    assert lives.worst_error[0] > 0.01


def test_a_failed_simulation_ends_the_life_where_it_fails():
    """The stub fails beyond 40 µm at A: the life ends there, named, after the step was
    halved down to the smallest step (a quarter of the first)."""
    lives = functional_lives(
        WearStub(breaks=40e-6), _x([20e-6]), clearance_criteria({"A": 80e-6}),
        hours=100 * HOUR, first_step=4 * HOUR, backend=LOCAL,
    )  # fmt: skip
    assert lives.failing == (SIMULATION_FAILED,)
    # the first state beyond 40 µm, within one smallest step (a quarter of 4 h) of 20 h
    assert 20.0 < lives.life[0] / HOUR <= 21.0


def test_a_mechanism_failing_as_made_has_life_zero():
    lives = functional_lives(
        WearStub(), _x([60e-6, 20e-6]), clearance_criteria({"A": 50e-6}),
        hours=100 * HOUR, first_step=4 * HOUR, backend=LOCAL,
    )  # fmt: skip
    assert lives.life[0] == 0.0
    assert lives.failing[0] == "clearance of A <= 50 µm"
    assert lives.life[1] / HOUR == pytest.approx(30.0)


def test_bad_settings_are_one_line_errors():
    with pytest.raises(ConfigError, match="hours"):
        functional_lives(
            WearStub(), _x([20e-6]), clearance_criteria({"A": 50e-6}),
            hours=0.0, first_step=1.0, backend=LOCAL,
        )  # fmt: skip
    with pytest.raises(ConfigError, match="no response 'torque'"):
        functional_lives(
            WearStub(), _x([20e-6]), (Criterion("torque <= 1 N*m", "torque", True, 1.0),),
            hours=10.0, first_step=1.0, backend=LOCAL,
        )  # fmt: skip


@dataclass(frozen=True)
class ConstantWear:
    """Any inputs; every joint's clearance grows at ``rate`` (m/s)."""

    input_names: tuple[str, ...]
    rate: float = 1e-6 / HOUR
    chunk_size: int = 100000

    @property
    def joints(self) -> list[str]:
        return [n.removeprefix("clearance_") for n in self.input_names if "clearance_" in n]

    @property
    def response_names(self) -> tuple[str, ...]:
        return tuple(f"wear_rate_{j}" for j in self.joints)

    @property
    def units(self) -> dict[str, str]:
        return dict.fromkeys(self.response_names, "m/s")

    def evaluate(self, x: np.ndarray) -> Evaluation:
        values = np.full((len(x), len(self.response_names)), self.rate)
        return Evaluation(values, np.ones(len(x), bool), ("",) * len(x))

    def describe(self) -> dict[str, str]:
        return {"model": "constant wear"}


def _population(**options):
    from jointplay.io.config import load_preset
    from jointplay.study.design_schemes import schemes
    from jointplay.study.life import population_life
    from jointplay.tolerance.parts import Process, model_inputs

    mechanism = load_preset("paper-fourbar")
    (scheme,) = schemes(mechanism, ["H8/g7"], ["m"])
    spec = scheme.spec(mechanism, Process())
    names, _ = model_inputs(spec.names, np.empty((0, len(spec.names))))
    model = ConstantWear(names)
    result = population_life(
        mechanism, "H8/g7", "m", [], hours=100 * HOUR, clearance_limit=30e-6,
        first_step=10 * HOUR, backend=LOCAL, model=model, **options,
    )  # fmt: skip
    return result, names


def test_population_lives_are_each_mechanisms_margin_over_the_rate():
    """Mechanisms drawn as design draws them (H8/g7, ISO 2768-m), every joint wearing 1 µm/h
    to a 30 µm limit: each life is (30 µm − its largest clearance)/(1 µm/h), its failing
    joint the one with the largest clearance, censored past 100 h."""
    result, names = _population(samples=50, seed=4)
    clearances = result.inputs[:, [i for i, n in enumerate(names) if n.startswith("clearance_")]]
    expected = np.minimum((30e-6 - clearances.max(axis=1)) / 1e-6, 100.0)
    assert result.n == 50
    assert result.lives.life / HOUR == pytest.approx(expected, rel=1e-9)
    joints = [n.removeprefix("clearance_") for n in names if n.startswith("clearance_")]
    worst = [joints[j] for j in clearances.argmax(axis=1)]
    assert [f.split()[2] for f in result.lives.failing] == worst
    # the same seed draws the same parts as the design study
    from jointplay.io.config import load_preset
    from jointplay.study.design_schemes import schemes
    from jointplay.tolerance.methods import truncated_at_limits
    from jointplay.tolerance.parts import Process
    from jointplay.tolerance.sampling import sample

    mechanism = load_preset("paper-fourbar")
    (scheme,) = schemes(mechanism, ["H8/g7"], ["m"])
    drawn = sample(truncated_at_limits(scheme.spec(mechanism, Process())), 50, 4).values
    assert result.features == pytest.approx(drawn)


def test_auto_samples_stop_at_the_precision_or_the_most():
    loose, _ = _population(samples="auto", precision=0.5, max_samples=400)
    assert loose.n == 100
    assert loose.settings["stopped_by"] == "precision"
    tight, _ = _population(samples="auto", precision=0.001, max_samples=200)
    assert tight.n == 200
    assert tight.settings["stopped_by"] == "max-samples"
    assert tight.lives.life[:100] == pytest.approx(loose.lives.life)  # rounds extend the draw


def test_an_interrupted_block_keeps_no_life(monkeypatch: pytest.MonkeyPatch):
    """Samples not run because of an interrupt are not failed simulations: the interrupt
    goes on, no life is made of them."""
    from jointplay.study import life as module

    real = module.run

    def interrupted(model, x, **options):
        outcome = real(model, x, **options)
        return dataclasses.replace(outcome, interrupted=True)

    monkeypatch.setattr(module, "run", interrupted)
    with pytest.raises(KeyboardInterrupt):
        functional_lives(
            WearStub(), _x([20e-6]), clearance_criteria({"A": 50e-6}),
            hours=100 * HOUR, first_step=4 * HOUR, backend=LOCAL,
        )  # fmt: skip


@dataclass(frozen=True)
class CountingStub(WearStub):
    """:class:`WearStub` that counts the rows it simulates (in ``rows``)."""

    rows: list[int] = dataclasses.field(default_factory=list)

    def evaluate(self, x: np.ndarray) -> Evaluation:
        self.rows.append(len(x))
        return super().evaluate(x)


def test_the_as_made_run_is_reused_not_repeated():
    """A caller that already ran the mechanisms as made (the design study's samples) hands
    the run over: the lives are the same bit for bit, and the as-made rows are not simulated
    again (two mechanisms: two rows fewer)."""
    from jointplay.tolerance.execution import run

    x = _x([20e-6, 35e-6])
    criteria = clearance_criteria({"A": 50e-6, "B": 100e-6})
    options = {"hours": 200 * HOUR, "first_step": 4 * HOUR, "backend": LOCAL}
    fresh = CountingStub(b=0.02 / HOUR)
    alone = functional_lives(fresh, x, criteria, **options)
    reused = CountingStub(b=0.02 / HOUR)
    as_made = run(reused, x, backend=LOCAL)
    reused.rows.clear()
    given = functional_lives(reused, x, criteria, as_made=as_made, **options)
    assert given.life.tolist() == alone.life.tolist()
    assert given.resimulations.tolist() == alone.resimulations.tolist()
    assert sum(reused.rows) == sum(fresh.rows) - 2
    with pytest.raises(ConfigError, match="as_made"):
        functional_lives(reused, x[:1], criteria, as_made=as_made, **options)


@dataclass(frozen=True)
class CountingWear(ConstantWear):
    """:class:`ConstantWear` that counts the rows it simulates (in ``rows``)."""

    rows: list[int] = dataclasses.field(default_factory=list)

    def evaluate(self, x: np.ndarray) -> Evaluation:
        self.rows.append(len(x))
        return super().evaluate(x)


def test_design_b_p_simulates_each_sample_as_made_once():
    """``design --require "B10 >= X"``: the design's run of its samples is each life's start
    (before, every sample was simulated as made twice: once for the design, once again as
    its life began). Constant wear to 30 µm, steps of X/4 from the start: each sample's rows
    are its simulations per life, nothing more."""
    from jointplay.io.config import load_preset
    from jointplay.study.design import design_study, schemes
    from jointplay.tolerance.parts import Process, model_inputs

    mechanism = load_preset("paper-fourbar")
    (scheme,) = schemes(mechanism, ["H8/g7"], ["m"])
    spec = scheme.spec(mechanism, Process())
    names, _ = model_inputs(spec.names, np.empty((0, len(spec.names))))
    model = CountingWear(names)
    result = design_study(
        mechanism, ["H8/g7"], ["m"], ["B10 >= 8 h"], samples=20, seed=3,
        clearance_limit=30e-6, life_step=2 * HOUR, backend=LOCAL, model=model,
    )  # fmt: skip
    simulations = result.settings["functional_life"]["simulations"]
    assert sum(model.rows) == simulations


@dataclass(frozen=True)
class NoisyWear(ConstantWear):
    """Every joint's rate 1 µm/h times a factor in [0.8, 1.2) that depends on the clearances
    alone (a fixed pseudo-random function of them): the noise of one simulated revolution
    of the dry paper four-bar, which no shorter step removes."""

    def evaluate(self, x: np.ndarray) -> Evaluation:
        evaluation = super().evaluate(x)
        phase = np.sin(1e7 * x.sum(axis=1)) * 43758.5453
        factor = 0.8 + 0.4 * (phase - np.floor(phase))
        return dataclasses.replace(evaluation, values=evaluation.values * factor[:, None])


def test_fixed_steps_give_the_same_lives_without_the_rejected_tries():
    """Where the rate's noise defeats the step control (every estimate far above 1 %), each
    life is walked at the smallest step anyway, after rejected tries from the first step down
    to it. Starting at the smallest step (``min_step`` = ``first_step``) gives the same lives
    bit for bit with those tries saved (as on the dry paper four-bar, 40 of 40 lives: 6.65 →
    4.6 simulations a life)."""
    from jointplay.io.config import load_preset
    from jointplay.study.design_schemes import schemes
    from jointplay.study.life import population_life
    from jointplay.tolerance.parts import Process, model_inputs

    mechanism = load_preset("paper-fourbar")
    (scheme,) = schemes(mechanism, ["H8/g7"], ["m"])
    spec = scheme.spec(mechanism, Process())
    names, _ = model_inputs(spec.names, np.empty((0, len(spec.names))))
    options = {"hours": 100 * HOUR, "clearance_limit": 30e-6, "samples": 30, "backend": LOCAL}
    model = NoisyWear(names)
    controlled = population_life(
        mechanism, "H8/g7", "m", [], first_step=8 * HOUR, model=model, **options
    )
    fixed = population_life(
        mechanism, "H8/g7", "m", [], first_step=2 * HOUR, min_step=2 * HOUR, model=model,
        **options,
    )  # fmt: skip
    # the mechanisms whose every accepted step sat at the floor (2 h between the history's
    # times, the crossing apart): where a step's noise happened to be small the control let
    # the next one grow, and those lives differ
    walked = [
        bool(np.allclose(np.diff([t for t, _ in history[:-1]]), 2 * HOUR))
        for history in controlled.lives.history
    ]
    assert sum(walked) >= 20
    assert fixed.lives.life[walked].tolist() == controlled.lives.life[walked].tolist()
    saved = controlled.lives.resimulations - fixed.lives.resimulations
    assert saved[walked].min() >= 1
    assert fixed.settings["min_step_s"] == 2 * HOUR


def test_a_quantile_beyond_the_hours_reads_as_a_bound_not_as_words():
    """The order-statistic B10 of 20 lives of which one failed lies beyond the hours: the
    line says "> 6 h" with the interval's ends, never "> the hours"; with too few samples
    to bound it at all, it says so instead of printing [0–∞ h]."""
    from jointplay.study.life_result import quantile_text
    from jointplay.study.weibull import empirical_quantile

    hours = 6 * 3600.0
    lives = np.full(20, hours)
    censored = np.ones(20, dtype=bool)
    lives[0], censored[0] = 2.5 * 3600.0, False
    q = empirical_quantile(lives, censored, 0.10)
    assert math.isinf(q.value)  # the 2nd of 20 lives outlived the hours
    text = quantile_text(q, hours)
    assert text.startswith("> 6 h [")
    assert "the hours" not in text
    few = empirical_quantile(lives[:3], censored[:3], 0.10)
    assert few.low == 0.0 and math.isinf(few.high)
    assert f"not bounded by {100 * few.level:g} % order statistics" in quantile_text(few, hours)
    finite = empirical_quantile(np.arange(1, 101) * 360.0, np.zeros(100, bool), 0.5)
    assert quantile_text(finite, hours) == (
        f"= {finite.value / 3600:.3g} h [{finite.low / 3600:.3g}–{finite.high / 3600:.3g} h]"
    )
