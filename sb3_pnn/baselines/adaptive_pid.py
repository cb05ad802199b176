"""Adaptive PID: the PID heading controller plus sonar obstacle avoidance (paper section 4.3).

The paper's "adaptive PID controller with the same parameters as the PID controller but tuned for
the path following with local path planning task" is not specified further; this is our reading:
the same PID law and gains as :class:`~sb3_pnn.baselines.pid.PIDController`, steering to the LOS
heading plus an avoidance offset ``delta`` read from the sonar (a small vector-field-histogram
rule). Avoidance rule, per control step and environment:

1. Sector k (of q, ordered right to left) covers relative bearings ``theta_k +- S/(2q)`` with
   ``theta_k = -S/2 + (k + 1/2) S/q`` and reads the surface distance ``d_k = obs["sonar"][k] * R``
   (``R = sonar_range``, ``S = sonar_span``).
2. A sector with ``d_k < trigger_distance`` blocks every heading within its wedge widened on both
   sides by the clearance angle ``alpha_k = asin(min(1, clearance / d_k))``: the angle at which a
   path passes the reading at ``clearance`` metres. ``alpha_k`` grows as the obstacle nears
   (with clearance 3.5 m: about 17 deg at 12 m, 44 deg at 5 m, 90 deg at <= 3.5 m), so the push
   away grows with it.
3. Candidate headings are the bearings ``-S/2 .. S/2`` in steps of ``S / (4q)``. When the LOS
   heading (bearing ``-a_c``) is blocked, the vehicle steers to the free candidate closest to it:
   ``delta`` = (that bearing) - (LOS bearing), clipped to ``+-max_bias``. Once avoidance has
   turned one way, candidates on the other side of the LOS heading cost an extra 10 rad, so it
   keeps going round the same side until the way is clear (no dithering); between two equally
   close free headings it goes round toward the path (``-sign(g)``, left when on it). If every
   candidate is blocked it turns by ``max_bias`` to the held side (or toward the path).
4. Guard: when ``|a_c| >= heading_guard`` the offset is dropped if it would push ``|a_c|``
   further (``|a_c| >= pi/2`` ends the episode, eq. 21).
5. With the LOS heading free, ``delta = 0``: plain LOS path following resumes.

The PID then runs on ``e = wrap(a_c - delta)`` (eq. 16 with the desired heading ``c_d + delta``).

Defaults: ``max_bias = 1.2`` rad, ``heading_guard = 1.2`` rad, the PID's ``kp = 1.5``,
``ki = 0.05``, ``kd = 0.6``, and per vehicle (:data:`VEHICLE_GAINS`, picked by ``for_env`` from the
env's ``vehicle``; the constructor's defaults are the default vehicle's):

* ``"wu2018"`` (pivots at 1.0-1.4 rad/s): ``trigger_distance = 12`` m, ``clearance = 3.5`` m
  (collision at 2 m, eq. 21, plus 1.5 m margin) and the PID's thresholds ``(0.4, 1.5)`` rad/s,
  ``yaw_rate_full = 0.7`` rad/s, tuned on PlanningStraight-v0 and PlanningSine-v0 with 1 m / 5 deg
  start noise.
* ``"uuv_simulator"`` (turns at 0.16-0.27 rad/s, in circles of about 2 m): it has to start
  avoiding earlier and wider: ``trigger_distance = 18`` m, ``clearance = 4.5`` m, thresholds
  ``(0.2, 0.6)`` rad/s (coarser than the plain PID's (0.05, 0.15)), ``yaw_rate_full = 0.3``
  rad/s, tuned on the six sonar tasks (60 episodes each from seed 1000, 1 m / 5 deg start noise;
  the tuning's figures are in docs/benchmarks.md).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from sb3_pnn.baselines.pid import DEFAULT_DT, DEFAULT_VEHICLE, PIDController
from sb3_pnn.common.checks import check_nonnegative

_M_SIDE = 3

#: The gains that depend on the vehicle preset (module docstring), by the env's ``vehicle``.
VEHICLE_GAINS: dict[str, dict[str, Any]] = {
    "uuv_simulator": {
        "turn_thresholds": (0.2, 0.6),
        "yaw_rate_full": 0.3,
        "trigger_distance": 18.0,
        "clearance": 4.5,
    },
    "wu2018": {
        "turn_thresholds": (0.4, 1.5),
        "yaw_rate_full": 0.7,
        "trigger_distance": 12.0,
        "clearance": 3.5,
    },
}


class AdaptivePIDController(PIDController):
    """PID on the LOS heading deviation plus sonar obstacle avoidance (module docstring).

    Args:
        kp, ki, kd, dt, continuous, turn_thresholds, integral_limit, yaw_rate_full: as
            :class:`~sb3_pnn.baselines.pid.PIDController`.
        trigger_distance: sonar distance (m) below which a sector starts to push the heading away
            (default: the default vehicle's, :data:`VEHICLE_GAINS`).
        max_bias: the largest heading offset from the LOS heading (rad, < pi/2).
        clearance: distance (m) at which the avoidance passes a sonar reading (sets alpha_k;
            default: the default vehicle's).
        heading_guard: |a_c| (rad) beyond which the offset may not push |a_c| further.
        sonar_range: metres per unit of ``obs["sonar"]`` (the env's ``sonar_range``, 25 m default).
        sonar_span: the sonar's angular span S (rad, pi by default), centred ahead.

    Memory per environment: integral, previous error, has-previous flag, avoidance side
    (+1 left, -1 right, 0 none).
    Observations without a "sonar" part are followed like the plain PID.
    """

    memory_size = 4
    vehicle_gains = VEHICLE_GAINS
    #: The avoider's coarser thresholds hold at every control period (measured at 0.5 and 1.0 s).
    long_period_turn_thresholds: dict[str, tuple[float, float]] = {}

    def __init__(
        self,
        kp: float = 1.5,
        ki: float = 0.05,
        kd: float = 0.6,
        dt: float = DEFAULT_DT,
        continuous: bool = False,
        turn_thresholds: tuple[float, float] | None = None,
        integral_limit: float = 0.5,
        yaw_rate_full: float = VEHICLE_GAINS[DEFAULT_VEHICLE]["yaw_rate_full"],
        trigger_distance: float = VEHICLE_GAINS[DEFAULT_VEHICLE]["trigger_distance"],
        max_bias: float = 1.2,
        sonar_range: float = 25.0,
        sonar_span: float = math.pi,
        clearance: float = VEHICLE_GAINS[DEFAULT_VEHICLE]["clearance"],
        heading_guard: float = 1.2,
    ) -> None:
        super().__init__(
            kp=kp,
            ki=ki,
            kd=kd,
            dt=dt,
            continuous=continuous,
            turn_thresholds=turn_thresholds,
            integral_limit=integral_limit,
            yaw_rate_full=yaw_rate_full,
        )
        self.trigger_distance = check_nonnegative(
            "trigger_distance", trigger_distance, allow_zero=False
        )
        self.max_bias = check_nonnegative("max_bias", max_bias)
        if self.max_bias >= math.pi / 2:
            raise ValueError(f"max_bias={max_bias!r} is not allowed: expected a float in [0, pi/2)")
        self.clearance = check_nonnegative("clearance", clearance)
        self.heading_guard = check_nonnegative("heading_guard", heading_guard)
        self.sonar_range = check_nonnegative("sonar_range", sonar_range, allow_zero=False)
        self.sonar_span = check_nonnegative("sonar_span", sonar_span, allow_zero=False)
        if self.sonar_span > 2.0 * math.pi + 1e-12:
            raise ValueError(
                f"sonar_span={sonar_span!r} is not allowed: expected a float in (0, 2 pi]"
            )

    @classmethod
    def env_settings(cls, env: Any) -> dict[str, Any]:
        """dt, continuous, sonar_range and sonar_span from an rov_envs env's config."""
        out = super().env_settings(env)
        config = cls.env_config(env)
        out["sonar_range"] = float(config.sonar_range)
        out["sonar_span"] = float(config.sonar_span)
        return out

    def sector_bearings(self, q: int) -> np.ndarray:
        """Relative bearings (rad) of the q sector centres, right (-S/2) to left (+S/2)."""
        s = self.sonar_span
        return -s / 2.0 + (np.arange(q) + 0.5) * s / q

    def blocked(self, sonar: np.ndarray) -> np.ndarray:
        """(N, C) mask of the candidate bearings (:attr:`candidates`) blocked by the sonar."""
        n, q = sonar.shape
        d = sonar * self.sonar_range
        near = d < self.trigger_distance
        half = 0.5 * self.sonar_span / q
        alpha = np.arcsin(np.clip(self.clearance / np.maximum(d, 1e-9), 0.0, 1.0))
        theta = self.sector_bearings(q)[None, :]
        lo = (theta - half - alpha)[:, :, None]
        hi = (theta + half + alpha)[:, :, None]
        phi = self.candidates(q)[None, None, :]
        return np.any(near[:, :, None] & (phi >= lo) & (phi <= hi), axis=1)

    def candidates(self, q: int) -> np.ndarray:
        """Candidate bearings (rad, relative to the vehicle heading) spanning the sonar."""
        half = 0.5 * self.sonar_span
        return np.linspace(-half, half, 4 * q + 1)

    def _desired_offset(self, obs: dict[str, np.ndarray], mem: np.ndarray) -> np.ndarray:
        n = obs["path"].shape[0]
        if "sonar" not in obs or obs["sonar"].shape[1] == 0:
            mem[:, _M_SIDE] = 0.0
            return np.zeros(n)
        sonar = obs["sonar"]
        q = sonar.shape[1]
        a_c = obs["path"][:, 0] * math.pi
        los = -a_c  # bearing of the LOS heading relative to the vehicle's heading
        phi = self.candidates(q)[None, :]
        blocked = self.blocked(sonar)
        # is the LOS heading itself blocked? (candidate nearest to it)
        idx = np.abs(phi - los[:, None]).argmin(axis=1)
        los_blocked = blocked[np.arange(n), idx] | (np.abs(los) > 0.5 * self.sonar_span)
        active = los_blocked & blocked.any(axis=1)
        dev = phi - los[:, None]  # heading offset from the LOS heading of each candidate
        side = mem[:, _M_SIDE][:, None]
        g = obs["path"][:, 1]
        toward_path = np.where(g > 0, -1.0, 1.0)[:, None]  # left of the path -> turn right
        cost = (
            np.abs(dev)
            + np.where((side != 0) & (np.sign(dev) != side), 10.0, 0.0)
            + np.where(np.sign(dev) != toward_path, 1e-6, 0.0)  # ties: go round toward the path
        )
        cost = np.where(blocked, np.inf, cost)
        all_blocked = ~np.isfinite(cost).any(axis=1)
        best = np.where(all_blocked, 0, cost.argmin(axis=1))
        offset = dev[np.arange(n), best]
        # nowhere free: turn as hard as allowed to the held side (or toward the path)
        fallback = np.where(side[:, 0] != 0, side[:, 0], toward_path[:, 0])
        offset = np.where(all_blocked, fallback * self.max_bias, offset)
        offset = np.clip(offset, -self.max_bias, self.max_bias)
        # guard: never push |a_c| further once it nears pi/2 (that ends the episode, eq. 21)
        guard = (np.abs(a_c) >= self.heading_guard) & (np.sign(offset) == np.sign(a_c))
        offset = np.where(guard, 0.0, offset)
        mem[:, _M_SIDE] = np.where(active, np.where(offset != 0, np.sign(offset), side[:, 0]), 0.0)
        return np.where(active, offset, 0.0)
