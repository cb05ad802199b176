"""Thruster allocation and the paper's action table (paper eq. (7), Table 1).

Numbering (see ``params``): T1 front-left, T2 front-right, T3 rear-left, T4 rear-right (horizontal,
vectored 45 deg), T5/T6 vertical. Speeds are in rev/min, as in the paper.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rov_envs.physics.params import MAX_THRUSTER_SPEED, BlueROV2Params

__all__ = [
    "ACTION_NAMES",
    "ACTION_TABLE",
    "N_ACTIONS",
    "allocation_matrix",
    "continuous_pair_speeds",
    "continuous_to_speeds",
    "continuous_to_speeds_into",
    "thrust_from_speeds",
]

ACTION_NAMES: tuple[str, ...] = (
    "Turn left 1",
    "Turn left 2",
    "Go straight",
    "Turn right 1",
    "Turn right 2",
)
"""Names of the discrete actions, action i = row i of Table 1."""

ACTION_TABLE: np.ndarray = np.array(
    [
        [0.0, 6000.0, 0.0, -6000.0, 0.0, 0.0],  # 0 Turn left 1
        [0.0, 8000.0, 0.0, -8000.0, 0.0, 0.0],  # 1 Turn left 2
        [8000.0, 8000.0, -8000.0, -8000.0, 0.0, 0.0],  # 2 Go straight
        [6000.0, 0.0, -6000.0, 0.0, 0.0, 0.0],  # 3 Turn right 1
        [8000.0, 0.0, -8000.0, 0.0, 0.0, 0.0],  # 4 Turn right 2
    ],
    dtype=np.float64,
)
"""Table 1 of the paper, (5, 6) commanded speeds T1..T6 in rev/min (read-only)."""
ACTION_TABLE.setflags(write=False)

N_ACTIONS: int = ACTION_TABLE.shape[0]


def allocation_matrix(params: BlueROV2Params | None = None) -> np.ndarray:
    """The 6x6 allocation matrix T (tau = T f), rows X, Y, Z, K, M, N (body FLU), cols T1..T6."""
    return (params if params is not None else BlueROV2Params()).allocation_matrix()


def thrust_from_speeds(speeds: np.ndarray, params: BlueROV2Params | None = None) -> np.ndarray:
    """Steady thrust forces f = k |n| n (N) for thruster speeds n (rev/min), any leading shape."""
    p = params if params is not None else BlueROV2Params()
    n = np.asarray(speeds, dtype=np.float64)
    return p.thrust_coefficient * np.abs(n) * n


def _check_unit(name: str, value: float) -> float:
    value = float(value)
    if not (math.isfinite(value) and -1.0 <= value <= 1.0):
        raise ValueError(f"{name} must be a finite number in [-1, 1], got {value!r}")
    return value


@njit(cache=True)
def continuous_pair_speeds(surge, yaw, max_speed):
    """(n_left, n_right): the speeds of T1 (= -T3) and T2 (= -T4) for ``continuous_to_speeds``.

    Inputs are clipped to [-1, 1] here (``continuous_to_speeds`` refuses out-of-range values).
    """
    s = min(1.0, max(-1.0, surge))
    y = min(1.0, max(-1.0, yaw))
    left = min(1.0, max(-1.0, s - y))
    right = min(1.0, max(-1.0, s + y))
    n_left = math.copysign(math.sqrt(abs(left)), left) * max_speed
    n_right = math.copysign(math.sqrt(abs(right)), right) * max_speed
    return n_left, n_right


@njit(cache=True)
def continuous_to_speeds_into(surge, yaw, max_speed, out):
    """njit, allocation-free core of ``continuous_to_speeds``: writes T1..T6 into ``out`` (6,).

    Inputs are clipped to [-1, 1] here (``continuous_to_speeds`` refuses out-of-range values).
    """
    n_left, n_right = continuous_pair_speeds(surge, yaw, max_speed)
    out[0] = n_left
    out[1] = n_right
    out[2] = -n_left
    out[3] = -n_right
    out[4] = 0.0
    out[5] = 0.0


def continuous_to_speeds(
    surge: float, yaw: float, max_speed: float = MAX_THRUSTER_SPEED
) -> np.ndarray:
    """Map continuous commands in [-1, 1] onto T1..T6 speeds (rev/min), T5 = T6 = 0.

    Uses the same horizontal thrusters as Table 1. ``surge`` = +1 is "Go straight"
    (T1, T2, T3, T4) = (+, +, -, -) * max_speed; ``yaw`` = +1 turns left (counter-clockwise) like
    "Turn left 2" on the right-hand pair (T2, T4) = (+, -) with the left pair reversed. The two
    are mixed on the thrust (k |n| n) scale, so the body force and moment are linear in the
    commands: thrust fraction of T1/T3 = surge - yaw, of T2/T4 = surge + yaw, each clipped to
    [-1, 1] and turned back into a speed by a signed square root. Thus (surge, yaw) = (1, 0) gives
    exactly "Go straight" and (0.5, 0.5) gives exactly "Turn left 2".
    """
    s = _check_unit("surge", surge)
    y = _check_unit("yaw", yaw)
    if not (math.isfinite(max_speed) and max_speed > 0.0):
        raise ValueError(f"max_speed must be a positive finite speed (rev/min), got {max_speed!r}")
    out = np.empty(6, dtype=np.float64)
    continuous_to_speeds_into(s, y, float(max_speed), out)
    return out
