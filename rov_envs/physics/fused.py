"""One call per control step for N vehicles: dynamics + sonar + LOS guidance (numba).

``advance_observe_batch`` advances every vehicle by one control period (``dynamics``), then fills
its sonar sectors (``sonar``), its nearest obstacle-surface distance and its LOS guidance
(``guidance``: a_c, e, progress). ``observe_batch`` does the observation part alone (for reset).
A single environment can call them with N = 1, which keeps single and batched environments on the
same code path (bit-identical transitions).

Arrays (all float64 unless noted, C-contiguous, written in place):
  states (N, 18)      state layout of ``dynamics``
  cmds (N, 6)         commanded thruster speeds, rev/min
  p (P_SIZE,)         ``BlueROV2Params.to_array()``
  currents (N, 3)     world-frame water velocity, m/s
  obstacles (N, M, 3) per-vehicle obstacle circles [x, y, radius], padded; M may be 0
  n_obstacles (N,)    int64, how many rows of obstacles[i] are real
  sonar_out (N, q)    sector distances (m, capped at max_range); q may be 0 (no sonar)
  nearest_out (N,)    distance to the nearest obstacle surface (inf if none, 0 inside)
  guide_out (N, 3)    [a_c, e, progress]; column 2 is also READ first as the closest-point warm
                      start for the sine path (NaN = global search, e.g. after reset)
Scalars: dt, n_substeps, span, max_range, path_kind (guidance.PATH_STRAIGHT / PATH_SINE),
amplitude, wavelength, lookahead.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rov_envs.physics.dynamics import STATE_DIM, _advance_one
from rov_envs.physics.guidance import los_guidance
from rov_envs.physics.params import P_SIZE
from rov_envs.physics.sonar import _nearest, _scan

__all__ = [
    "advance_observe_batch",
    "observe_batch",
    "advance_observe_batch_kernel",
    "observe_batch_kernel",
]


@njit(cache=True, inline="always")
def _observe_one(
    i, states, obstacles, n_obstacles, span, max_range, sonar_out, nearest_out,
    path_kind, amplitude, wavelength, lookahead, guide_out,
):  # fmt: skip
    x = states[i, 0]
    y = states[i, 1]
    psi = states[i, 5]
    m = n_obstacles[i]
    if m < 0 or m > obstacles.shape[1]:
        raise ValueError("n_obstacles[i] must lie in [0, obstacles.shape[1]]")
    if sonar_out.shape[1] > 0:
        _scan(x, y, psi, obstacles[i], m, span, max_range, sonar_out[i])
    nearest_out[i] = _nearest(x, y, obstacles[i], m)
    los_guidance(path_kind, x, y, psi, amplitude, wavelength, lookahead, guide_out[i])


@njit(cache=True)
def observe_batch_kernel(
    states, obstacles, n_obstacles, span, max_range, sonar_out, nearest_out,
    path_kind, amplitude, wavelength, lookahead, guide_out,
):  # fmt: skip
    """Unchecked numba kernel behind ``observe_batch``."""
    for i in range(states.shape[0]):
        _observe_one(
            i, states, obstacles, n_obstacles, span, max_range, sonar_out, nearest_out,
            path_kind, amplitude, wavelength, lookahead, guide_out,
        )  # fmt: skip


@njit(cache=True)
def advance_observe_batch_kernel(
    states, cmds, p, currents, dt, n_substeps,
    obstacles, n_obstacles, span, max_range, sonar_out, nearest_out,
    path_kind, amplitude, wavelength, lookahead, guide_out,
):  # fmt: skip
    """Unchecked numba kernel behind ``advance_observe_batch``."""
    for i in range(states.shape[0]):
        _advance_one(
            states[i], cmds[i], p, currents[i, 0], currents[i, 1], currents[i, 2],
            dt, n_substeps,
        )  # fmt: skip
        _observe_one(
            i, states, obstacles, n_obstacles, span, max_range, sonar_out, nearest_out,
            path_kind, amplitude, wavelength, lookahead, guide_out,
        )  # fmt: skip


def _check(name: str, a: object, shape: tuple[int, ...], dtype: type = np.float64) -> None:
    if not isinstance(a, np.ndarray) or a.dtype != dtype or a.shape != shape:
        got = f"{a.dtype} {a.shape}" if isinstance(a, np.ndarray) else type(a)
        raise ValueError(f"{name} must be a {np.dtype(dtype)} array of shape {shape}, got {got}")


def _check_observe_args(
    n: int,
    obstacles: np.ndarray,
    n_obstacles: np.ndarray,
    span: float,
    max_range: float,
    sonar_out: np.ndarray,
    nearest_out: np.ndarray,
    path_kind: int,
    wavelength: float,
    lookahead: float,
    guide_out: np.ndarray,
) -> None:
    if not (isinstance(obstacles, np.ndarray) and obstacles.ndim == 3):
        raise ValueError(f"obstacles must be a float64 array of shape ({n}, M, 3)")
    _check("obstacles", obstacles, (n, obstacles.shape[1], 3))
    _check("n_obstacles", n_obstacles, (n,), np.int64)
    if not (isinstance(sonar_out, np.ndarray) and sonar_out.ndim == 2):
        raise ValueError(f"sonar_out must be a float64 array of shape ({n}, q)")
    _check("sonar_out", sonar_out, (n, sonar_out.shape[1]))
    _check("nearest_out", nearest_out, (n,))
    _check("guide_out", guide_out, (n, 3))
    if sonar_out.shape[1] > 0:
        if not (0.0 < span <= 2.0 * np.pi):
            raise ValueError(f"span must be in (0, 2 pi] radians, got {span!r}")
        if not (np.isfinite(max_range) and max_range > 0.0):
            raise ValueError(f"max_range must be a positive finite distance, got {max_range!r}")
    if path_kind not in (0, 1):
        raise ValueError(f"path_kind must be PATH_STRAIGHT (0) or PATH_SINE (1), got {path_kind!r}")
    if not (np.isfinite(wavelength) and wavelength > 0.0):
        raise ValueError(f"wavelength must be a positive finite length, got {wavelength!r}")
    if not (np.isfinite(lookahead) and lookahead > 0.0):
        raise ValueError(f"lookahead must be a positive finite length, got {lookahead!r}")


def observe_batch(
    states: np.ndarray,
    obstacles: np.ndarray,
    n_obstacles: np.ndarray,
    span: float,
    max_range: float,
    sonar_out: np.ndarray,
    nearest_out: np.ndarray,
    path_kind: int,
    amplitude: float,
    wavelength: float,
    lookahead: float,
    guide_out: np.ndarray,
) -> None:
    """Sonar, nearest obstacle distance and LOS guidance for N vehicles (see module doc)."""
    if not (isinstance(states, np.ndarray) and states.ndim == 2):
        raise ValueError(f"states must be a float64 array of shape (N, {STATE_DIM})")
    n = states.shape[0]
    _check("states", states, (n, STATE_DIM))
    _check_observe_args(
        n, obstacles, n_obstacles, span, max_range, sonar_out, nearest_out, path_kind,
        wavelength, lookahead, guide_out,
    )  # fmt: skip
    observe_batch_kernel(
        states, obstacles, n_obstacles, float(span), float(max_range), sonar_out, nearest_out,
        int(path_kind), float(amplitude), float(wavelength), float(lookahead), guide_out,
    )  # fmt: skip


def advance_observe_batch(
    states: np.ndarray,
    cmds: np.ndarray,
    p: np.ndarray,
    currents: np.ndarray,
    dt: float,
    n_substeps: int,
    obstacles: np.ndarray,
    n_obstacles: np.ndarray,
    span: float,
    max_range: float,
    sonar_out: np.ndarray,
    nearest_out: np.ndarray,
    path_kind: int,
    amplitude: float,
    wavelength: float,
    lookahead: float,
    guide_out: np.ndarray,
) -> None:
    """Advance N vehicles one control period, then observe them (see module doc)."""
    if not (isinstance(states, np.ndarray) and states.ndim == 2):
        raise ValueError(f"states must be a float64 array of shape (N, {STATE_DIM})")
    n = states.shape[0]
    _check("states", states, (n, STATE_DIM))
    _check("cmds", cmds, (n, 6))
    _check("p (BlueROV2Params.to_array())", p, (P_SIZE,))
    _check("currents", currents, (n, 3))
    if not (np.isfinite(dt) and dt > 0.0):
        raise ValueError(f"dt must be a positive finite number of seconds, got {dt!r}")
    if int(n_substeps) != n_substeps or n_substeps < 1:
        raise ValueError(f"n_substeps must be an integer >= 1, got {n_substeps!r}")
    _check_observe_args(
        n, obstacles, n_obstacles, span, max_range, sonar_out, nearest_out, path_kind,
        wavelength, lookahead, guide_out,
    )  # fmt: skip
    advance_observe_batch_kernel(
        states, cmds, p, currents, float(dt), int(n_substeps),
        obstacles, n_obstacles, float(span), float(max_range), sonar_out, nearest_out,
        int(path_kind), float(amplitude), float(wavelength), float(lookahead), guide_out,
    )  # fmt: skip
