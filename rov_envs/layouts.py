"""Obstacle layouts drawn afresh each episode from the environment's random generator.

The paper gives coordinates only for PlanningStraight and PlanningSine. The other layouts are
designed here to fit the task names, and all of them are kept solvable by construction:

* every obstacle is a cylinder (x, y, radius); the vehicle collides when its distance to an
  obstacle SURFACE is <= 2 m (eq. 21), so a passage between two surfaces must be wider than 4 m;
  every generator keeps the surface-to-surface gap between any two obstacles >= ``GAP_MIN`` (6 m),
  so the vehicle can pass between any pair with 1 m to spare on each side;
* obstacles stay inside a lateral band well inside the corridor |g| < d_L, so there is always
  room to go around a cluster on either side;
* the start (0, 0) and the target point are kept clear: obstacles are drawn only between
  ``START_CLEAR`` metres after the start and ``END_CLEAR`` metres before the end of the path.

Layouts (``length`` is the path length along x; counts scale with it):

``avoidance`` (ObstacleAvoidance): 2-4 cylinders of the paper's radius 1.5 m with x in
    [15, length - 12] and y in [-8, 8]; the first is drawn with |y| <= 1.5 so the straight
    start-goal line is always blocked and the policy must actually avoid. (A first design with
    5-8 cylinders of up to 2.5 m on a 100 m route was never solved by DiscreteSAC in 800
    episodes under the paper's update schedule, and the adaptive PID managed 57 %, so the source
    task for SPNN's avoidance column carried no skill; this one is short and sparse enough to be
    learnt, while still forcing a detour on every episode.)
``uniform`` (PlanningStraightUniform): one obstacle of radius 1.5 m (the paper's size) per 20 m
    station along [30, length - 20] (8 on the 200 m line), x uniform inside its station,
    y uniform in [-12, 12]: obstacles spread evenly along the whole route.
``dense`` (PlanningStraightDense): one obstacle of radius U(1.0, 2.0) m per 10 m along
    [30, length - 20] (15 on the 200 m line), x uniform in the whole stretch and y uniform in
    [-6, 6]: the route is crowded and nearly every obstacle is in the way.
``sine_dense`` (PlanningSineDense): one obstacle of radius U(1.0, 2.0) m per 10 m of x along
    [20, length - 15] (8-9 on the 120 m sinusoid), each placed at a point of the sinusoid and moved
    along its normal by U(-5, 5) m, so the obstacles follow the curve.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

GAP_MIN = 6.0
START_CLEAR = 15.0
END_CLEAR = 12.0
_MAX_TRIES = 2000


def _accept(obs: list[tuple[float, float, float]], x: float, y: float, r: float) -> bool:
    for ox, oy, orad in obs:
        if math.hypot(x - ox, y - oy) - r - orad < GAP_MIN:
            return False
    return True


def _draw(
    rng: np.random.Generator,
    n: int,
    propose: Callable[[np.random.Generator, int], tuple[float, float, float]],
) -> np.ndarray:
    """Draw ``n`` obstacles one by one with ``propose(rng, k)``, rejecting too-close ones."""
    obs: list[tuple[float, float, float]] = []
    for k in range(n):
        for _ in range(_MAX_TRIES):
            x, y, r = propose(rng, k)
            if _accept(obs, x, y, r):
                obs.append((x, y, r))
                break
        else:  # the band is full: keep what fits (never happens with the default sizes)
            break
    return np.asarray(obs, dtype=np.float64).reshape(-1, 3)


def avoidance(rng: np.random.Generator, length: float, amplitude: float, wavelength: float):
    n = int(rng.integers(2, 5))
    x0, x1 = START_CLEAR, length - END_CLEAR

    def propose(g: np.random.Generator, k: int):
        y_half = 1.5 if k == 0 else 8.0
        return (float(g.uniform(x0, x1)), float(g.uniform(-y_half, y_half)), 1.5)

    return _draw(rng, n, propose)


def uniform(rng: np.random.Generator, length: float, amplitude: float, wavelength: float):
    x0, x1 = 30.0, length - 20.0
    n = max(1, int(round((x1 - x0) / 20.0)))
    width = (x1 - x0) / n

    def propose(g: np.random.Generator, k: int):
        return (
            float(g.uniform(x0 + k * width, x0 + (k + 1) * width)),
            float(g.uniform(-12.0, 12.0)),
            1.5,
        )

    return _draw(rng, n, propose)


def dense(rng: np.random.Generator, length: float, amplitude: float, wavelength: float):
    x0, x1 = 30.0, length - 20.0
    n = max(1, int(round((x1 - x0) / 10.0)))

    def propose(g: np.random.Generator, k: int):
        return (
            float(g.uniform(x0, x1)),
            float(g.uniform(-6.0, 6.0)),
            float(g.uniform(1.0, 2.0)),
        )

    return _draw(rng, n, propose)


def sine_dense(rng: np.random.Generator, length: float, amplitude: float, wavelength: float):
    x0, x1 = 20.0, length - 15.0
    n = max(1, int(round((x1 - x0) / 10.0)))
    k_w = 2.0 * math.pi / wavelength

    def propose(g: np.random.Generator, k: int):
        xs = float(g.uniform(x0, x1))
        slope = amplitude * k_w * math.cos(k_w * xs)
        norm = math.hypot(1.0, slope)
        off = float(g.uniform(-5.0, 5.0))
        return (
            xs - off * slope / norm,
            amplitude * math.sin(k_w * xs) + off / norm,
            float(g.uniform(1.0, 2.0)),
        )

    return _draw(rng, n, propose)


#: name -> generator(rng, length, amplitude, wavelength) -> (M, 3) array of (x, y, radius).
LAYOUTS: dict[str, Callable[..., np.ndarray]] = {
    "avoidance": avoidance,
    "uniform": uniform,
    "dense": dense,
    "sine_dense": sine_dense,
}

#: The most obstacles a generator can return for a given path length (for batch buffers).


def max_obstacles(layout: str, length: float) -> int:
    if layout == "avoidance":
        return 4
    if layout == "uniform":
        return max(1, int(round((length - 50.0) / 20.0)))
    if layout == "dense":
        return max(1, int(round((length - 50.0) / 10.0)))
    if layout == "sine_dense":
        return max(1, int(round((length - 35.0) / 10.0)))
    raise ValueError(f"layout: unknown layout {layout!r}; expected one of {sorted(LAYOUTS)}")
