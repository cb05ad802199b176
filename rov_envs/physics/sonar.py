"""Sector sonar on circular obstacles (paper section 4.2.2), exact geometry, numba.

The sonar span S (radians, centred on the heading) is split into q equal sectors, ordered from the
vehicle's right (relative bearing -S/2) to its left (+S/2). Sector i covers relative bearings
[-S/2 + i S/q, -S/2 + (i + 1) S/q]. Each sector reports the shortest distance from the vehicle
position to any obstacle circle's SURFACE lying inside the sector's wedge, capped at ``max_range``
(``max_range`` = nothing seen).

Exact geometry: the distance to a circle's points is unimodal around the circle (smallest at the
radial closest point, distance ``d_c - R``). So the closest circle point inside a wedge is the
radial closest point when its bearing lies in the wedge, otherwise the nearest intersection of the
circle with one of the wedge's two boundary rays (``t = d_c cos(delta) - sqrt(R^2 - d_c^2
sin(delta)^2)`` for a ray at angle delta from the centre direction), or none.
A vehicle inside (or on) an obstacle reads 0 in every sector.
Gaussian range noise, if any, is added by the environment layer.

Obstacles: float64 array (M, 3) of [x, y, radius] (M may be 0).
"""

from __future__ import annotations

import math

from numba import njit

__all__ = [
    "sonar_scan",
    "sonar_scan_n",
    "nearest_surface_distance",
    "nearest_surface_distance_n",
]


@njit(cache=True, inline="always")
def _scan(x, y, cpsi, spsi, obstacles, n_obs, span, max_range, out):
    """Core of ``sonar_scan`` over obstacles[:n_obs]; (cpsi, spsi) = (cos, sin) of the heading."""
    q = out.shape[0]
    for i in range(q):
        out[i] = max_range
    if n_obs == 0:
        return
    half = 0.5 * span
    width = span / q
    # first boundary ray (relative bearing -S/2) and the rotation by one sector width
    c_first = math.cos(half)
    s_first = -math.sin(half)
    c_w = math.cos(width)
    s_w = math.sin(width)
    for k in range(n_obs):
        dx = obstacles[k, 0] - x
        dy = obstacles[k, 1] - y
        rad = obstacles[k, 2]
        dc = math.sqrt(dx * dx + dy * dy)
        near = dc - rad
        if near >= max_range:
            continue
        if near <= 0.0:
            for i in range(q):
                out[i] = 0.0
            return
        # unit direction of the centre in the body frame (relative bearing beta)
        bx = (cpsi * dx + spsi * dy) / dc
        by = (-spsi * dx + cpsi * dy) / dc
        beta = math.atan2(by, bx)
        # sector holding the radial closest point, if any
        i_near = -1
        if -half <= beta <= half:
            i_near = int((beta + half) / width)
            if i_near >= q:
                i_near = q - 1
            if near < out[i_near]:
                out[i_near] = near
        # nearest intersection with each boundary ray (NaN = the ray misses)
        r2 = rad * rad
        rc = c_first
        rs = s_first
        prev = math.nan
        for j in range(q + 1):
            cd = rc * bx + rs * by  # cos(ray - beta)
            sd = rs * bx - rc * by  # sin(ray - beta)
            disc = r2 - dc * dc * sd * sd
            t = math.nan
            if cd > 0.0 and disc >= 0.0:
                t = dc * cd - math.sqrt(disc)
            # sector j - 1 lies between rays j - 1 and j
            if j > 0 and j - 1 != i_near:
                if prev == prev and prev < out[j - 1]:
                    out[j - 1] = prev
                if t == t and t < out[j - 1]:
                    out[j - 1] = t
            prev = t
            rc, rs = rc * c_w - rs * s_w, rs * c_w + rc * s_w


@njit(cache=True)
def _check_scan(obstacles, n_obs, span, max_range, out):
    if obstacles.shape[1] != 3:
        raise ValueError("obstacles must be a float64 array of shape (M, 3) [x, y, radius]")
    if n_obs < 0 or n_obs > obstacles.shape[0]:
        raise ValueError("n_obs must lie in [0, obstacles.shape[0]]")
    if not (span > 0.0 and span <= 2.0 * math.pi):
        raise ValueError("span must be in (0, 2 pi] radians")
    if not (max_range > 0.0 and max_range < math.inf):
        raise ValueError("max_range must be a positive finite distance")
    if out.shape[0] < 1:
        raise ValueError("out must be a float64 array of shape (q,) with q >= 1")


@njit(cache=True)
def sonar_scan(x, y, psi, obstacles, span, max_range, out):
    """Fill ``out`` (q,) with sector distances (m, capped at ``max_range``).

    x, y, psi: vehicle position (m) and heading (rad, CCW from world x); obstacles (M, 3)
    [x, y, radius]; span S in (0, 2 pi]; sectors ordered right (-S/2) to left (+S/2).
    Numba-compiled: callable from Python and from other njit code.
    """
    _check_scan(obstacles, obstacles.shape[0], span, max_range, out)
    _scan(x, y, math.cos(psi), math.sin(psi), obstacles, obstacles.shape[0], span, max_range, out)


@njit(cache=True)
def sonar_scan_n(x, y, psi, obstacles, n_obs, span, max_range, out):
    """``sonar_scan`` over the first ``n_obs`` rows of a padded obstacle array."""
    _check_scan(obstacles, n_obs, span, max_range, out)
    _scan(x, y, math.cos(psi), math.sin(psi), obstacles, n_obs, span, max_range, out)


@njit(cache=True, inline="always")
def _nearest(x, y, obstacles, n_obs):
    best = math.inf
    for k in range(n_obs):
        dx = obstacles[k, 0] - x
        dy = obstacles[k, 1] - y
        d = math.sqrt(dx * dx + dy * dy) - obstacles[k, 2]
        if d < best:
            best = d
    if best < 0.0:
        best = 0.0
    return best


@njit(cache=True)
def nearest_surface_distance(x, y, obstacles):
    """Distance (m) from (x, y) to the nearest obstacle surface (0 inside, inf if none)."""
    if obstacles.shape[1] != 3:
        raise ValueError("obstacles must be a float64 array of shape (M, 3) [x, y, radius]")
    return _nearest(x, y, obstacles, obstacles.shape[0])


@njit(cache=True)
def nearest_surface_distance_n(x, y, obstacles, n_obs):
    """``nearest_surface_distance`` over the first ``n_obs`` rows of a padded obstacle array."""
    if obstacles.shape[1] != 3 or n_obs < 0 or n_obs > obstacles.shape[0]:
        raise ValueError("obstacles must have shape (M, 3) and n_obs lie in [0, M]")
    return _nearest(x, y, obstacles, n_obs)
