"""Statistics across seeds and the report's verdicts."""

from __future__ import annotations

import math

import numpy as np
import pytest

from sb3_pnn.evaluation import wilson_interval
from sb3_pnn.reproduce.reporting.report import _below_half, _compare
from sb3_pnn.reproduce.reporting.stats import (
    curve_band,
    difference_ci,
    episodes_to_first_success,
    episodes_to_threshold,
    mean_ci,
    smooth,
    success_interval,
)


def test_mean_ci_matches_student_t() -> None:
    mean, lo, hi = mean_ci([1.0, 2.0, 3.0, 4.0, 5.0])
    assert mean == 3.0
    # t_{0.975, 4} = 2.776; sd = 1.5811; half = 2.776 * 1.5811 / sqrt(5) = 1.963
    assert hi - mean == pytest.approx(1.963, abs=1e-3)
    assert mean - lo == pytest.approx(hi - mean)
    assert mean_ci([7.0]) == (7.0, 7.0, 7.0)
    assert all(math.isnan(v) for v in mean_ci([]))


def test_difference_ci_is_welchs_interval() -> None:
    """Two equal-sized groups with equal variances: Welch's dof is 2(n-1) and the half-width
    t_{0.975, 8} * sqrt(2 s^2 / n) (s^2 = 2.5, n = 5: 2.306 * 1 = 2.306)."""
    diff, lo, hi = difference_ci([1.0, 2.0, 3.0, 4.0, 5.0], [3.0, 4.0, 5.0, 6.0, 7.0])
    assert diff == 2.0
    assert hi - diff == pytest.approx(2.306, abs=1e-3)
    assert diff - lo == pytest.approx(hi - diff)
    # unequal spreads (one side constant): the interval comes from the other side alone
    diff, lo, hi = difference_ci([0.5, 0.5, 0.5], [0.0, 1.0, 0.2, 0.8])
    assert diff == pytest.approx(0.0)
    assert hi - diff == pytest.approx(mean_ci([0.0, 1.0, 0.2, 0.8])[2] - 0.5)
    assert difference_ci([0.4], [0.6, 0.8])[0] == pytest.approx(0.3)
    assert all(math.isnan(v) for v in difference_ci([0.4], [0.6, 0.8])[1:])
    assert difference_ci([0.5, 0.5], [0.7, 0.7]) == pytest.approx((0.2, 0.2, 0.2))
    assert all(math.isnan(v) for v in difference_ci([], [0.6]))


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


def test_success_interval_covers_the_spread_between_seeds() -> None:
    # one run: the Wilson interval of its episodes
    assert success_interval([(8, 10)]) == pytest.approx((0.8, *wilson_interval(8, 10)))
    # alike runs: the per-seed t-interval is a point, so the pooled Wilson interval remains
    rate, lo, hi = success_interval([(25, 50)] * 3)
    assert (lo, hi) == pytest.approx(wilson_interval(75, 150)) and rate == 0.5
    # whole runs succeed or fail: the pooled Wilson interval [0.40, 0.60] would claim far too much
    rate, lo, hi = success_interval([(50, 50), (0, 50)])
    assert rate == 0.5 and (lo, hi) == (0.0, 1.0)
    # five seeds 100 100 100 26 100 (the study's PNN on PlanningStraight): mean 0.852, sd 0.331,
    # t_{0.975, 4} * sd / sqrt(5) = 0.411 -> [0.441, 1] after clipping
    rate, lo, hi = success_interval([(50, 50)] * 3 + [(13, 50), (50, 50)])
    assert rate == pytest.approx(0.852) and lo == pytest.approx(0.441, abs=1e-3) and hi == 1.0
    assert all(math.isnan(v) for v in success_interval([]))


def test_verdicts_do_not_call_seed_noise_a_difference() -> None:
    # pooled 36 % against 19 % over 250 episodes each: Wilson intervals apart, seeds not
    a = [(3, 50), (37, 50), (16, 50), (4, 50), (30, 50)]
    b = [(0, 50), (19, 50), (8, 50), (15, 50), (5, 50)]

    def pooled(runs):
        return (sum(k for k, _ in runs), sum(n for _, n in runs))

    assert _compare(
        (0.36, wilson_interval(*pooled(a))), (0.188, wilson_interval(*pooled(b)))
    ).startswith("agrees (intervals apart)")

    def seed_aware(runs):
        rate, lo, hi = success_interval(runs)
        return rate, (lo, hi)

    assert "intervals overlap" in _compare(seed_aware(a), seed_aware(b))


def test_the_heading_end_is_explained_by_the_set_ups_heading_rule() -> None:
    from sb3_pnn.reproduce.reporting.report import end_reasons

    assert "goal's bearing" in end_reasons("goal")["heading"]
    assert "path direction" in end_reasons("path")["heading"]
