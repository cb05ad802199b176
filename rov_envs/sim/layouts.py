"""Obstacle layouts drawn afresh each episode from the vehicle's random stream (numba).

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
    start-goal line is always blocked and the policy must actually avoid. It is short and
    sparse enough to be learnt (a first design, 5-8 larger cylinders on a 100 m route, was
    not), while still forcing a detour on every episode.
``uniform`` (PlanningStraightUniform): one obstacle of radius 1.5 m (the paper's size) per 20 m
    station along [30, length - 20] (8 on the 200 m line), x uniform inside its station,
    y uniform in [-12, 12]: obstacles spread evenly along the whole route.
``dense`` (PlanningStraightDense): one obstacle of radius U(1.0, 2.0) m per 10 m along
    [30, length - 20] (15 on the 200 m line), x uniform in the whole stretch and y uniform in
    [-6, 6]: the route is crowded and nearly every obstacle is in the way.
``sine_dense`` (PlanningSineDense): one obstacle of radius U(1.0, 2.0) m per 10 m of x along
    [20, length - 15] (8-9 on the 120 m sinusoid), each placed at a point of the sinusoid and moved
    along its normal by U(-5, 5) m, so the obstacles follow the curve.

``scatter`` (any task, ``layout="scatter"``; training layouts beyond the paper, not an
    evaluation layout): a random field of random density and size around the route: 1-5
    cylinders per 40 m of the route along [START_CLEAR, length - END_CLEAR], each of radius
    U(0.75, 2.5) m, placed at a route point and moved along its normal by U(-10, 10) m. Its
    counts, sizes and spread are its own: none of the ``uniform`` / ``dense`` / ``sine_dense``
    generators' parameters. For the obstacle-avoidance source task the first cylinder blocks
    the start-goal line, as in ``avoidance``.

Obstacles are drawn one at a time, each proposal redrawn until it keeps ``GAP_MIN`` from those
already placed (at most ``MAX_TRIES`` proposals each). The draws come from the vehicle's
splitmix64 stream (:mod:`rov_envs.sim.random_stream`) inside the kernels, so a batched reset costs
no
Python call; :func:`sample_layout` runs the same code from Python (tests, plots).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial

import numpy as np
from numba import njit

from rov_envs.sim.random_stream import stream_seed, uniform

GAP_MIN = 6.0
START_CLEAR = 15.0
END_CLEAR = 12.0
MAX_TRIES = 2000

#: Layout codes read by the kernels (``rov_envs.sim.kernel.C_LAYOUT``); 0 = nothing is drawn.
LAYOUT_FIXED = 0
LAYOUT_CODES: dict[str, int] = {
    "avoidance": 1,
    "uniform": 2,
    "dense": 3,
    "sine_dense": 4,
    "scatter": 5,
}
#: The scatter layout: cylinders per this many metres of route, at most.
SCATTER_STRETCH = 40.0
#: Most obstacles per ``SCATTER_STRETCH`` metres of the scatter layout (at least 1).
SCATTER_MOST = 5


@njit(cache=True, inline="always")
def _propose(kind, rng, ri, k, n, length, amplitude, wavelength):
    """Proposal k of n for layout ``kind``: (x, y, radius)."""
    if kind == 1:  # avoidance
        y_half = 1.5 if k == 0 else 8.0
        x = START_CLEAR + (length - END_CLEAR - START_CLEAR) * uniform(rng, ri)
        return x, -y_half + 2.0 * y_half * uniform(rng, ri), 1.5
    if kind == 2:  # uniform: one per station
        x0 = 30.0
        width = (length - 20.0 - x0) / n
        x = x0 + k * width + width * uniform(rng, ri)
        return x, -12.0 + 24.0 * uniform(rng, ri), 1.5
    if kind == 3:  # dense
        x = 30.0 + (length - 50.0) * uniform(rng, ri)
        y = -6.0 + 12.0 * uniform(rng, ri)
        return x, y, 1.0 + uniform(rng, ri)
    if kind == 5:  # scatter: a route point moved along its normal, the first one on the route
        xs = START_CLEAR + (length - END_CLEAR - START_CLEAR) * uniform(rng, ri)
        off = (-1.5 + 3.0 * uniform(rng, ri)) if k == 0 else (-10.0 + 20.0 * uniform(rng, ri))
        r = 0.75 + 1.75 * uniform(rng, ri)
        if amplitude == 0.0:
            return xs, off, r
        k_w = 2.0 * math.pi / wavelength
        slope = amplitude * k_w * math.cos(k_w * xs)
        norm = math.sqrt(1.0 + slope * slope)
        return xs - off * slope / norm, amplitude * math.sin(k_w * xs) + off / norm, r
    # sine_dense: a point of the sinusoid moved along its normal
    k_w = 2.0 * math.pi / wavelength
    xs = 20.0 + (length - 35.0) * uniform(rng, ri)
    slope = amplitude * k_w * math.cos(k_w * xs)
    norm = math.sqrt(1.0 + slope * slope)
    off = -5.0 + 10.0 * uniform(rng, ri)
    r = 1.0 + uniform(rng, ri)
    return xs - off * slope / norm, amplitude * math.sin(k_w * xs) + off / norm, r


@njit(cache=True, _nrt=False)
def draw_layout(kind, n_max, rng, ri, length, amplitude, wavelength, out):
    """Draw layout ``kind`` (a ``LAYOUT_CODES`` value) into ``out`` (>= n_max, 3); returns M.

    ``n_max``: the layout's count (:func:`max_obstacles`); the avoidance layout draws 2-4.
    """
    n = n_max
    if kind == 1:
        n = 2 + int(3.0 * uniform(rng, ri))
    elif kind == 5:  # between one per stretch and n_max
        stretches = max(1, n_max // SCATTER_MOST)
        n = stretches + int((n_max - stretches + 1) * uniform(rng, ri))
    m = 0
    for k in range(n):
        for _ in range(MAX_TRIES):
            x, y, r = _propose(kind, rng, ri, k, n, length, amplitude, wavelength)
            ok = True
            for j in range(m):
                dx = x - out[j, 0]
                dy = y - out[j, 1]
                if math.sqrt(dx * dx + dy * dy) - r - out[j, 2] < GAP_MIN:
                    ok = False
                    break
            if ok:
                out[m, 0] = x
                out[m, 1] = y
                out[m, 2] = r
                m += 1
                break
        else:  # the band is full: keep what fits (never happens with the default sizes)
            break
    return m


def max_obstacles(layout: str, length: float) -> int:
    """The most obstacles layout ``layout`` places on a path of ``length`` metres."""
    if layout == "avoidance":
        return 4
    if layout == "uniform":
        return max(1, int(round((length - 50.0) / 20.0)))
    if layout == "dense":
        return max(1, int(round((length - 50.0) / 10.0)))
    if layout == "sine_dense":
        return max(1, int(round((length - 35.0) / 10.0)))
    if layout == "scatter":
        stretches = max(1, int(round((length - START_CLEAR - END_CLEAR) / SCATTER_STRETCH)))
        return SCATTER_MOST * stretches
    raise ValueError(f"layout={layout!r} is not allowed: expected one of {sorted(LAYOUT_CODES)}")


def sample_layout(
    layout: str,
    generator: np.random.Generator,
    length: float,
    amplitude: float,
    wavelength: float,
) -> np.ndarray:
    """Draw one layout from Python: (M, 3) array of (x, y, radius), stream seeded from
    ``generator`` (the kernels run the same code on a vehicle's stream)."""
    n_max = max_obstacles(layout, length)
    out = np.zeros((n_max, 3))
    rng = np.array([stream_seed(generator)], dtype=np.uint64)
    m = draw_layout(
        LAYOUT_CODES[layout], n_max, rng, 0, float(length), float(amplitude), float(wavelength), out
    )
    return out[:m].copy()


#: name -> sampler(generator, length, amplitude, wavelength) -> (M, 3) array of (x, y, radius).
LAYOUTS: dict[str, Callable[..., np.ndarray]] = {
    name: partial(sample_layout, name) for name in LAYOUT_CODES
}
