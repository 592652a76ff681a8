"""Peaks located on the continuous solution: analytic maxima, never below the known values."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from jointplay.dynamics.peaks import locate_peaks


def _signal(times: np.ndarray) -> dict[str, np.ndarray]:
    # A smooth signal with a known maximum 2.0 at t = 0.3 and minimum -1.5 at t = 1.1.
    return {
        "bump": 2.0 * np.exp(-(((times - 0.3) / 0.05) ** 2))
        - 1.5 * np.exp(-(((times - 1.1) / 0.08) ** 2)),
        "sine": np.sin(2 * np.pi * times),
    }


def test_coarse_steps_give_the_analytic_maxima() -> None:
    t = np.linspace(0.0, 2.0, 37)  # steps that miss both extrema
    peaks = locate_peaks(t, _signal(t), _signal, [(0.0, 1.0), (1.0, 2.0)])
    # A smooth maximum is flat: 1e-11 relative in the value is 1e-7 in time here.
    assert peaks["bump"][0].value == pytest.approx(2.0, rel=1e-11)
    assert peaks["bump"][0].t == pytest.approx(0.3, abs=1e-6)
    assert peaks["bump"][1].signed_value == pytest.approx(-1.5, rel=1e-11)
    assert peaks["bump"][1].t == pytest.approx(1.1, abs=1e-6)
    assert peaks["sine"][0].value == pytest.approx(1.0, rel=1e-11)
    assert np.max(np.abs(_signal(t)["bump"])) < 1.99  # the steps alone would be too low


@settings(max_examples=30, deadline=None)
@given(st.integers(8, 200), st.integers(2, 4))
def test_never_below_a_step_or_a_sample(n: int, windows: int) -> None:
    steps = np.unique(np.concatenate([[0.0, 2.0], np.random.default_rng(n).uniform(0, 2, n)]))
    samples = np.linspace(0.0, 2.0, 721)  # a sampled output, as --sample-deg gives
    t = np.unique(np.concatenate([steps, samples]))
    edges = np.linspace(0.0, 2.0, windows + 1)
    peaks = locate_peaks(t, _signal(t), _signal, list(itertools.pairwise(edges)))
    for name in ("bump", "sine"):
        for w in range(windows):
            inside = (t >= edges[w]) & (t <= edges[w + 1])
            assert peaks[name][w].value >= np.max(np.abs(_signal(t)[name][inside]))
            assert edges[w] <= peaks[name][w].t <= edges[w + 1]
