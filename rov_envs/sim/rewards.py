"""Rewards and episode endings of the paper, eq. (17)-(21), as numba functions.

The reward of a step is ``r = r_c + r_v + r_terminal`` (eq. 17 plus eq. 21):

* ``r_c`` (eq. 18, straight tasks): ``-|a_c| / 3.14 + |1 - |g| / d_L|``. The paper writes ``g``
  ("the vertical distance from the target path") inside the absolute value; we use the
  non-negative distance ``|g|``, because with a signed ``g`` the term would pay up to 2 for
  drifting to one side of the path and less than 1 for staying on it. The constant 3.14 is the
  paper's, kept literally.
* ``r_c`` (eq. 19, sine tasks): ``-0.175 |a_c| + 0.325 * 2**(2 - |g| / d_L)`` when ``|g| <= 1.8``,
  else ``-0.0875 |a_c| + 0.1625 * 2**(2 - |g| / d_L)`` (the branch tests the distance |g|).
* ``r_c`` (ObstacleAvoidance, not in the paper): progress toward the goal,
  ``(D_{t-1} - D_t) / (U_REF * dt)`` with D the straight-line distance to the goal: about +1 per
  step when heading to the goal at 1 m/s, the same scale as the path terms above.
* ``r_c`` with ``progress_weighted=True`` (NOT in the paper; default off): a positive eq. 18/19
  value is multiplied by the step's advance along the path tangent as a fraction of
  ``U_REF * dt``, clipped to [0, 1] (negative values are paid in full). Eq. 18 pays about +1 per
  step near the path whether the vehicle advances or not; on the planning tasks, where passing an
  obstacle costs eq. 20 penalties, agents then learned to stop short of the obstacles and wait
  for the time limit (DiscreteSAC on PlanningStraight).
  With ``progress_along="course"`` (not in the paper; default ``"path"``) the advance is
  measured along the LOS course (heading minus a_c) instead: along the tangent a vehicle running
  parallel to the path 10 m off is paid about as much as one turning back (0.31 against 0.30 on
  the straight path), along the course the way back is paid in full.
* ``r_v`` (eq. 20): -2 when ``5 < d <= 8``, -4 when ``2 < d <= 5``, else 0, where ``d`` is the
  noise-free distance from the vehicle's centre to the nearest obstacle SURFACE (centre distance
  minus radius): the paper's obstacles are cylinders and its collision test ``d <= 2`` only makes
  sense for a surface distance. The argument ``obstacle_penalty`` (default 1, the paper's)
  weights it; 0 drops the term.
* ``r_terminal`` (eq. 21): -200 once when the episode fails, i.e. when ``|g| >= d_L``,
  ``|a_c| >= pi/2`` or ``d <= 2`` (several at once still give -200). The paper says the vehicle
  "will receive another reward" in those cases, so it is added to ``r_c + r_v`` of that step.
  With ``arrival_gate`` (NOT in the paper's list; default None) an episode whose vehicle passes
  the end of the path farther than the gate from the target point also fails this way
  (``END_MISSED``).
* ``r_terminal`` on success (NOT in the paper; argument ``success_reward``, default +200): eq.
  17-21 pay a positive ``r_c`` (about +1) on every step spent near the path and nothing for
  arriving, so arriving ends a stream of reward and a learner is paid to crawl (DiscreteSAC's
  path-following agents learned to wiggle slowly and time out). A bonus larger
  than the discounted value of loitering (about 1 / (1 - gamma) = 100 at gamma = 0.99) makes
  arriving the better choice; +200 mirrors eq. 21's -200. ``success_reward=0`` restores the
  paper's reward exactly.
"""

from __future__ import annotations

import math

from numba import njit

#: Episode-end codes written by the kernels (``info["end_reason"]`` names them).
END_NONE = 0
END_OFF_PATH = 1  # |g| >= d_L
END_HEADING = 2  # |a_c| >= pi/2
END_COLLISION = 3  # d <= 2
END_SUCCESS = 4  # the target point was reached
END_TIME_LIMIT = 5  # truncated
END_MISSED = 6  # the end of the path reached farther from the target than ``arrival_gate``
END_REASONS = ("none", "off_path", "heading", "collision", "success", "time_limit", "missed_target")

COLLISION_DISTANCE = 2.0
FAILURE_REWARD = -200.0
HALF_PI = 0.5 * math.pi


@njit(cache=True, inline="always")
def reward_straight(a_c: float, g: float, d_L: float) -> float:
    """Eq. (18) with the distance |g| (see the module docstring)."""
    return -abs(a_c) / 3.14 + abs(1.0 - abs(g) / d_L)


@njit(cache=True, inline="always")
def reward_sine(a_c: float, g: float, d_L: float) -> float:
    """Eq. (19)."""
    ag = abs(g)
    if ag <= 1.8:
        return -abs(a_c) * 0.175 + 2.0 ** (2.0 - ag / d_L) * 0.325
    return -abs(a_c) * 0.0875 + 2.0 ** (2.0 - ag / d_L) * 0.1625


@njit(cache=True, inline="always")
def reward_obstacle(d: float) -> float:
    """Eq. (20): r_v from the distance d to the nearest obstacle surface (m)."""
    if 5.0 < d <= 8.0:
        return -2.0
    if 2.0 < d <= 5.0:
        return -4.0
    return 0.0


@njit(cache=True, inline="always")
def failure_code(a_c: float, g: float, d: float, d_L: float) -> int:
    """Eq. (21) conditions: the end code (collision first), or END_NONE."""
    if d <= COLLISION_DISTANCE:
        return END_COLLISION
    if abs(g) >= d_L:
        return END_OFF_PATH
    if abs(a_c) >= HALF_PI:
        return END_HEADING
    return END_NONE
