"""Statistics across seeds: learning-curve bands and episodes-to-criterion (Figure 10, report).

* :func:`mean_ci` - mean and two-sided 95 % Student-t confidence interval of the mean across
  seeds (the paper's "0.95 confidence interval" shaded in Figure 10); with one seed the band is
  the mean itself.
* :func:`smooth` - trailing moving average of a per-episode series (window ``w``).
* :func:`episodes_to_first_success` and :func:`episodes_to_threshold` - per run: the index of
  the first successful training episode, and of the first episode at which the moving average
  of the return reaches a threshold; None when never reached within the budget.
* :func:`success_interval` - a success rate pooled over runs with an interval that also covers
  the spread between seeds (episodes of one run are not independent draws: a run that never
  learned fails all of its 50 evaluation episodes).
* :func:`difference_ci` - the difference of two set-ups' mean per-run values with a Welch
  interval: training runs, not episodes, are the independent draws when two set-ups are compared.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from scipy import stats as _st

#: Moving-average window (episodes) for curves and the return threshold.
SMOOTH_WINDOW = 10


def mean_ci(values: Sequence[float], level: float = 0.95) -> tuple[float, float, float]:
    """(mean, low, high) of the mean of ``values`` with a Student-t interval."""
    arr = np.asarray([v for v in values if v is not None and math.isfinite(v)], dtype=np.float64)
    if arr.size == 0:
        return math.nan, math.nan, math.nan
    mean = float(arr.mean())
    if arr.size == 1:
        return mean, mean, mean
    half = float(_st.t.ppf(0.5 + level / 2, arr.size - 1) * arr.std(ddof=1) / math.sqrt(arr.size))
    return mean, mean - half, mean + half


def difference_ci(
    a: Sequence[float], b: Sequence[float], level: float = 0.95
) -> tuple[float, float, float]:
    """(mean(b) - mean(a), low, high) with a two-sided Welch-Satterthwaite t interval; each value
    one training run's rate. The bounds are NaN unless both sides have two runs or more (one run
    says nothing about how much runs of the same set-up differ)."""
    xa = np.asarray(a, dtype=np.float64)
    xb = np.asarray(b, dtype=np.float64)
    if xa.size == 0 or xb.size == 0:
        return math.nan, math.nan, math.nan
    diff = float(xb.mean() - xa.mean())
    if xa.size < 2 or xb.size < 2:
        return diff, math.nan, math.nan
    va, vb = xa.var(ddof=1) / xa.size, xb.var(ddof=1) / xb.size
    se = math.sqrt(va + vb)
    if se == 0.0:
        return diff, diff, diff
    dof = (va + vb) ** 2 / (va**2 / (xa.size - 1) + vb**2 / (xb.size - 1))
    half = float(_st.t.ppf(0.5 + level / 2, dof)) * se
    return diff, diff - half, diff + half


def curve_band(curves: Sequence[Sequence[float]], level: float = 0.95) -> np.ndarray:
    """(3, T) mean / low / high per episode over the runs' curves, cut to the shortest."""
    if not curves:
        return np.zeros((3, 0))
    n = min(len(c) for c in curves)
    data = np.asarray([list(c)[:n] for c in curves], dtype=np.float64)
    mean = data.mean(axis=0)
    if data.shape[0] == 1:
        return np.stack([mean, mean, mean])
    half = _st.t.ppf(0.5 + level / 2, data.shape[0] - 1) * data.std(axis=0, ddof=1)
    half = half / math.sqrt(data.shape[0])
    return np.stack([mean, mean - half, mean + half])


def smooth(series: Sequence[float], w: int = SMOOTH_WINDOW) -> np.ndarray:
    """Trailing moving average (the first ``w - 1`` points average what exists so far)."""
    arr = np.asarray(series, dtype=np.float64)
    if arr.size == 0:
        return arr
    csum = np.cumsum(arr)
    out = np.empty_like(arr)
    for i in range(arr.size):
        lo = max(0, i - w + 1)
        out[i] = (csum[i] - (csum[lo - 1] if lo > 0 else 0.0)) / (i - lo + 1)
    return out


def episodes_to_first_success(successes: Sequence[bool]) -> int | None:
    """Index of the first successful episode, or None."""
    for i, ok in enumerate(successes):
        if ok:
            return i
    return None


def episodes_to_threshold(
    returns: Sequence[float], threshold: float, w: int = SMOOTH_WINDOW
) -> int | None:
    """First episode index where the ``w``-episode moving average of the return >= threshold."""
    if len(returns) < w:
        w = max(1, len(returns))
    avg = smooth(returns, w)
    for i in range(w - 1, len(avg)):
        if avg[i] >= threshold:
            return i
    return None


def success_interval(per_run: Sequence[tuple[int, int]]) -> tuple[float, float, float]:
    """(rate, low, high): successes pooled over runs, each run given as ``(successes, episodes)``.

    The interval is the hull of two 95 % intervals: the Wilson interval of the pooled episodes
    (right when the runs are alike) and the Student-t interval of the mean of the per-run rates,
    clipped to [0, 1] (right when whole runs succeed or fail, as ours do: per-seed rates of 0 %
    and 100 % in one cell are common). With one run it is the Wilson interval.
    """
    from sb3_pnn.evaluation import wilson_interval

    runs = [(int(k), int(n)) for k, n in per_run if n > 0]
    if not runs:
        return math.nan, math.nan, math.nan
    k = sum(r[0] for r in runs)
    n = sum(r[1] for r in runs)
    lo, hi = wilson_interval(k, n)
    if len(runs) > 1:
        _, t_lo, t_hi = mean_ci([rk / rn for rk, rn in runs])
        lo, hi = min(lo, max(0.0, t_lo)), max(hi, min(1.0, t_hi))
    return k / n, lo, hi


def summarize_reached(values: Sequence[int | None], budget: int) -> dict[str, object]:
    """Reached-count, and mean/CI over the seeds that reached (None = not within budget)."""
    reached = [v for v in values if v is not None]
    mean, lo, hi = mean_ci(reached)
    return {
        "reached": len(reached),
        "runs": len(values),
        "mean": mean,
        "ci95": (lo, hi),
        "budget": budget,
        "values": list(values),
    }
