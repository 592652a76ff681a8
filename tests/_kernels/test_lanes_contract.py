"""What the batch backends share (:mod:`jointplay._kernels.lanes.contract`): run_batch's
input checks, its output arrays and a failed lane's NaNs, written once for the CPU engine
(:func:`jointplay._kernels.batch.run_batch`) and the CUDA lanes
(:func:`jointplay._kernels.lanes.cuda.run_batch`)."""

from __future__ import annotations

import numpy as np
import pytest

from jointplay._kernels import ids
from jointplay._kernels.lanes.contract import finished, lane_inputs, lane_outputs
from jointplay.errors import ConfigError


def test_the_inputs_broadcast_each_lanes_window_and_step() -> None:
    y0, settle, end, step, atol = lane_inputs(
        [[1.0, 2.0, 3.0]] * 2, 0.5, [1.0, 2.0], 1e-3, [1e-6] * 3, np.zeros((2, 4)), 3,
        ValueError,
    )  # fmt: skip
    assert y0.shape == (2, 3) and y0.flags.c_contiguous
    assert settle.tolist() == [0.5, 0.5] and end.tolist() == [1.0, 2.0]
    assert step.tolist() == [1e-3, 1e-3] and atol.shape == (3,)


@pytest.mark.parametrize("error", [ValueError, ConfigError])
@pytest.mark.parametrize(
    ("y0", "atol", "rows"),
    [([[1.0, 2.0]], [1e-6] * 3, 1), ([[1.0, 2.0, 3.0]], [1e-6] * 2, 1),
     ([[1.0, 2.0, 3.0]], [1e-6] * 3, 2)],
)  # fmt: skip
def test_a_shape_that_does_not_fit_raises_the_backends_error(
    error: type[Exception], y0: list[list[float]], atol: list[float], rows: int
) -> None:
    with pytest.raises(error, match=r"run_batch: y0 must be \(n, 3\) and atol \(3,\)"):
        lane_inputs(y0, 0.0, 1.0, 1e-3, atol, np.zeros((rows, 4)), 3, error)


def test_a_lane_that_did_not_succeed_has_nan_peaks_and_statistics() -> None:
    peaks, stats, status, t_reached, counts = lane_outputs(3, 2, 4)
    assert np.isnan(peaks).all() and np.isnan(stats).all()
    assert (status == ids.STATUS_RUNNING).all() and not t_reached.any() and not counts.any()
    peaks[:] = 1.0
    stats[:] = 2.0
    status[:] = [ids.STATUS_SUCCESS, ids.STATUS_NON_FINITE, ids.STATUS_SUCCESS]
    counts[:] = [[5, 1, 40], [6, 2, 50], [7, 3, 60]]
    out = finished(peaks, stats, status, t_reached, counts)
    assert np.isnan(out.peaks[1]).all() and np.isnan(out.stats[1]).all()
    assert (out.peaks[[0, 2]] == 1.0).all() and (out.stats[[0, 2]] == 2.0).all()
    assert out.n_steps.tolist() == [5, 6, 7] and out.n_rejected.tolist() == [1, 2, 3]
    assert out.n_rhs.tolist() == [40, 50, 60]
