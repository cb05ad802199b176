"""Statistics across seeds and the report's verdicts."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sb3_pnn.evaluation import wilson_interval
from sb3_pnn.reproduce.report import _below_half, _compare
from sb3_pnn.reproduce.stats import (
    curve_band,
    episodes_to_first_success,
    episodes_to_threshold,
    mean_ci,
    smooth,
)


def test_mean_ci_matches_student_t() -> None:
    mean, lo, hi = mean_ci([1.0, 2.0, 3.0, 4.0, 5.0])
    assert mean == 3.0
    # t_{0.975, 4} = 2.776; sd = 1.5811; half = 2.776 * 1.5811 / sqrt(5) = 1.963
    assert hi - mean == pytest.approx(1.963, abs=1e-3)
    assert mean - lo == pytest.approx(hi - mean)
    assert mean_ci([7.0]) == (7.0, 7.0, 7.0)
    assert all(math.isnan(v) for v in mean_ci([]))


def test_curve_band_and_smooth() -> None:
    band = curve_band([[0, 2, 4], [2, 4, 6, 8]])
    assert band.shape == (3, 3)  # cut to the shortest run
    np.testing.assert_allclose(band[0], [1, 3, 5])
    assert np.all(band[1] < band[0]) and np.all(band[2] > band[0])
    np.testing.assert_allclose(smooth([0, 10, 20, 30], w=2), [0, 5, 15, 25])


def test_episodes_to_criteria() -> None:
    assert episodes_to_first_success([False, False, True, True]) == 2
    assert episodes_to_first_success([False]) is None
    returns = [0] * 10 + [100] * 10
    assert episodes_to_threshold(returns, 50, w=4) == 11  # mean of eps 8..11 = 50
    assert episodes_to_threshold(returns, 101, w=4) is None


def test_verdicts_follow_the_wilson_intervals() -> None:
    def rate(k: int, n: int):
        return k / n, wilson_interval(k, n)

    assert _compare(rate(98, 100), rate(60, 100)).startswith("agrees (intervals apart)")
    assert _compare(rate(60, 100), rate(98, 100)).startswith("does NOT agree")
    assert "intervals overlap" in _compare(rate(9, 10), rate(8, 10))
    assert _compare(rate(0, 2), rate(0, 2)).startswith("inconclusive")
    assert _below_half(rate(11, 100)).startswith("agrees")
    assert _below_half(rate(96, 100)).startswith("does NOT agree")
    assert _below_half(rate(1, 2)).startswith("inconclusive")
