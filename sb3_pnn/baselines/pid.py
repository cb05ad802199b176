"""PID heading controller on LOS guidance: the paper's "PID controller" baseline (section 4.3).

The controller acts on the LOS heading deviation ``a_c = c - c_d`` (eq. 16), which every rov_envs
task gives as ``obs["path"][0] * pi``. Because the LOS desired heading ``c_d`` points at a spot
``lookahead`` metres ahead on the path, steering ``a_c`` to zero also removes the cross-track
distance ``g``; the controller needs nothing else.

Control law (one control period ``dt`` per call, per environment):

    e_t   = wrap(a_c)                                      (rad)
    I_t   = clip(I_{t-1} + e_t * dt, -integral_limit, integral_limit)
    D_t   = wrap(e_t - e_{t-1}) / dt                       (0 on the first step of an episode)
    u_t   = -(kp * e_t + ki * I_t + kd * D_t)              (desired yaw rate, rad/s, + = turn left)

``u`` is negative when the vehicle points left of the desired heading (a_c > 0), i.e. it turns
right, and vice versa. It is then quantised to the discrete action space of Table 1:

    |u| <  turn_thresholds[0]                  -> 2 Go straight
    turn_thresholds[0] <= |u| < thresholds[1]  -> 0 Turn left 1  / 3 Turn right 1
    |u| >= turn_thresholds[1]                  -> 1 Turn left 2  / 4 Turn right 2

With ``continuous=True`` the action is ``(surge, yaw) = (1, clip(u / yaw_rate_full, -1, 1))``:
(1, 0) is exactly Go straight and (1, +-1) gives the thrust of Turn left 2 / Turn right 2 (see
``rov_envs.physics.thrusters.continuous_to_speeds``).

Gains that depend on the vehicle (:data:`VEHICLE_GAINS`, picked by :meth:`PIDController.for_env`
from the env's ``vehicle``; the constructor's defaults are those of the environments' default
vehicle, ``"uuv_simulator"``): the turn thresholds and ``yaw_rate_full`` follow how fast Table 1
turns the vehicle. UUV Simulator's BlueROV2 turns at about 0.16 / 0.27 rad/s (Turn 1 / Turn 2):
thresholds ``(0.05, 0.15)`` rad/s, ``yaw_rate_full = 0.3`` rad/s (on PathFollowingSine-v0, 50
episodes from seed 1000: mean |g| 0.11 m against 0.49 m with (0.2, 0.6) and 1.04 m with Wu's
thresholds; continuous mean |a_c| 0.013 rad against 0.031 rad with 0.7). Wu's set pivots at
about 1.0 / 1.4 rad/s: thresholds ``(0.4, 1.5)`` rad/s, ``yaw_rate_full = 0.7`` rad/s (mean |a_c|
0.08 rad on PathFollowingSine-v0 against 0.37 rad with 1.4). The rest is shared (tuned on
PathFollowingStraight-v0 / PathFollowingSine-v0 with 1 m / 5 deg start noise, see the module
tests and ``python -m sb3_pnn.evaluate --model pid``): ``kp = 1.5`` /s, ``ki = 0.05`` /s^2,
``kd = 0.6`` (s/s), ``integral_limit = 0.5`` rad s.

The thresholds above hold up to a 0.5 s control period (:data:`FINE_PERIOD`). At longer periods
one step of Turn 1 swings UUV Simulator's BlueROV2 past the narrow go-straight band, and the
controller chatters between Turn left 1 and Turn right 1 without going straight and runs out
of time: of 60 episodes from seed 2000 (1 m / 5 deg start noise) it ends PathFollowingStraight-v0
on 4 at 0.6 s and on 1 from 0.75 s to 1.0 s, PathFollowingSine-v0 on none from 0.75 s on.
Longer periods therefore take ``(0.15, 0.45)`` rad/s (:data:`LONG_PERIOD_TURN_THRESHOLDS`):
60 / 60 on both tasks at 0.6-1.0 s, mean |g| 0.14 / 0.18 m at 1.0 s (from seed 1000 at 1.0 s:
(0.1, 0.3) ends the line on 5 / 60, (0.15, 0.45) on 60 / 60). Wu's set keeps its thresholds
(30 / 30 episodes from seed 1000 at 1.0 s on both tasks, mean |g| 0.6 m).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from sb3_pnn.common.checks import check_nonnegative

#: The environments' default control period (s): ``rov_envs.sim.config.CONTROL_PERIOD`` (a test
#: checks they agree).
DEFAULT_DT = 1.0
#: Table 1 action indices.
TURN_LEFT_1, TURN_LEFT_2, GO_STRAIGHT, TURN_RIGHT_1, TURN_RIGHT_2 = 0, 1, 2, 3, 4
#: The environments' default vehicle (``rov_envs.physics.params.DEFAULT_VEHICLE``).
DEFAULT_VEHICLE = "uuv_simulator"
#: The gains that depend on the vehicle preset (module docstring), by the env's ``vehicle``.
VEHICLE_GAINS: dict[str, dict[str, Any]] = {
    "uuv_simulator": {"turn_thresholds": (0.05, 0.15), "yaw_rate_full": 0.3},
    "wu2018": {"turn_thresholds": (0.4, 1.5), "yaw_rate_full": 0.7},
}
#: The longest control period (s) at which :data:`VEHICLE_GAINS`' turn thresholds hold.
FINE_PERIOD = 0.5
#: Turn thresholds for control periods longer than :data:`FINE_PERIOD`, by vehicle (module
#: docstring; a vehicle not listed keeps its own).
LONG_PERIOD_TURN_THRESHOLDS: dict[str, tuple[float, float]] = {"uuv_simulator": (0.15, 0.45)}


# memory columns shared by every controller
_M_INTEGRAL = 0
_M_PREV = 1
_M_HAS_PREV = 2


def wrap_to_pi(a: np.ndarray) -> np.ndarray:
    """Wrap angles (rad) to (-pi, pi]."""
    out = np.mod(np.asarray(a, dtype=np.float64) + math.pi, 2.0 * math.pi) - math.pi
    return np.where(out <= -math.pi, out + 2.0 * math.pi, out)


class PIDController:
    """PID on the LOS heading deviation with the SB3 ``predict`` interface (module docstring).

    Args:
        kp, ki, kd: PID gains on ``a_c`` (rad): proportional (1/s), integral (1/s^2),
            derivative (-).
        dt: control period (s) used by the integral and derivative terms (default: the envs'
            default, 1.0 s).
        continuous: emit (surge, yaw) actions for ``continuous=True`` envs instead of Discrete(5).
        turn_thresholds: ``(t1, t2)`` in rad/s: the |u| at which Turn 1 and Turn 2 are chosen
            (default: the default vehicle's, :data:`VEHICLE_GAINS`).
        integral_limit: anti-windup clamp of the integral (rad s).
        yaw_rate_full: the |u| (rad/s) mapped to yaw = +-1 in continuous mode (default: the
            default vehicle's).

    ``predict`` keeps one row of memory per environment (integral, previous error, ...). It is
    reset for the rows where ``episode_start`` is True, by :meth:`reset`, or when the batch size
    changes; a ``state`` passed in (as returned by a previous call) replaces the memory.
    """

    #: Columns of memory per environment.
    memory_size = 3
    #: Vehicle-dependent constructor arguments, by the env's ``vehicle`` (module docstring).
    vehicle_gains: dict[str, dict[str, Any]] = VEHICLE_GAINS
    #: Turn thresholds that replace ``vehicle_gains``' above :data:`FINE_PERIOD`, by vehicle.
    long_period_turn_thresholds: dict[str, tuple[float, float]] = LONG_PERIOD_TURN_THRESHOLDS

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
    ) -> None:
        self.kp = check_nonnegative("kp", kp)
        self.ki = check_nonnegative("ki", ki)
        self.kd = check_nonnegative("kd", kd)
        self.dt = check_nonnegative("dt", dt, allow_zero=False)
        if turn_thresholds is None:  # the default vehicle's, for this control period
            turn_thresholds = self.vehicle_turn_thresholds(DEFAULT_VEHICLE, self.dt)
        if not isinstance(continuous, (bool, np.bool_)):
            raise ValueError(f"continuous={continuous!r} is not allowed: expected True or False")
        self.continuous = bool(continuous)
        try:
            t1, t2 = (float(t) for t in turn_thresholds)
        except (TypeError, ValueError):
            raise ValueError(
                f"turn_thresholds={turn_thresholds!r} is not allowed: expected (t1, t2) floats "
                "with 0 <= t1 <= t2"
            ) from None
        if not (math.isfinite(t1) and math.isfinite(t2) and 0 <= t1 <= t2):
            raise ValueError(
                f"turn_thresholds={turn_thresholds!r} is not allowed: expected (t1, t2) floats "
                "with 0 <= t1 <= t2"
            )
        self.turn_thresholds = (t1, t2)
        self.integral_limit = check_nonnegative("integral_limit", integral_limit)
        self.yaw_rate_full = check_nonnegative("yaw_rate_full", yaw_rate_full, allow_zero=False)
        self._memory = np.zeros((0, self.memory_size))

    # ---- construction from an environment ----
    @staticmethod
    def env_config(env: Any) -> Any:
        """The ``rov_envs.sim.config.EnvConfig`` of an env (single, batched, wrapped) or a
        config."""
        if hasattr(env, "dt") and hasattr(env, "continuous") and hasattr(env, "sonar_range"):
            return env  # already an EnvConfig
        for obj in (getattr(env, "unwrapped", None), env, getattr(env, "batch", None)):
            config = getattr(obj, "config", None)
            if config is not None:
                return config
        raise ValueError(
            f"env={env!r} is not allowed: expected an rov_envs environment (with .config) or "
            "its EnvConfig"
        )

    @classmethod
    def env_settings(cls, env: Any) -> dict[str, Any]:
        """The settings this controller reads from an rov_envs env: ``dt``, ``continuous`` and
        the gains of its ``vehicle`` (:attr:`vehicle_gains`)."""
        config = cls.env_config(env)
        vehicle = getattr(config, "vehicle", DEFAULT_VEHICLE)
        turn_thresholds = cls.vehicle_turn_thresholds(vehicle, float(config.dt))
        return {
            "dt": float(config.dt),
            "continuous": bool(config.continuous),
            **cls.vehicle_gains[vehicle],
            "turn_thresholds": turn_thresholds,
        }

    @classmethod
    def vehicle_turn_thresholds(cls, vehicle: str, dt: float) -> tuple[float, float]:
        """This controller's turn thresholds (rad/s) for ``vehicle`` at a ``dt`` s period."""
        if vehicle not in cls.vehicle_gains:
            raise ValueError(
                f"vehicle={vehicle!r} is not allowed: {cls.__name__} has gains for "
                f"{sorted(cls.vehicle_gains)}"
            )
        if dt > FINE_PERIOD and vehicle in cls.long_period_turn_thresholds:
            return cls.long_period_turn_thresholds[vehicle]
        return cls.vehicle_gains[vehicle]["turn_thresholds"]

    @classmethod
    def for_env(cls, env: Any, **overrides: Any) -> PIDController:
        """A controller configured from ``env.unwrapped.config`` (plus ``overrides``)."""
        return cls(**{**cls.env_settings(env), **overrides})

    # ---- memory ----
    def reset(self) -> None:
        """Forget every environment's memory (call between episodes without episode_start)."""
        self._memory = np.zeros((0, self.memory_size))

    def _prepare_memory(
        self, n: int, state: np.ndarray | None, episode_start: np.ndarray | None
    ) -> np.ndarray:
        if state is not None:
            mem = np.array(state, dtype=np.float64)
            if mem.shape != (n, self.memory_size):
                raise ValueError(
                    f"state of shape {mem.shape} is not allowed: expected ({n}, "
                    f"{self.memory_size}) as returned by predict"
                )
        elif self._memory.shape[0] != n:
            mem = np.zeros((n, self.memory_size))
        else:
            mem = self._memory
        if episode_start is not None:
            starts = np.asarray(episode_start, dtype=bool).reshape(-1)
            if starts.shape != (n,):
                raise ValueError(
                    f"episode_start of shape {starts.shape} is not allowed: expected ({n},)"
                )
            mem[starts] = 0.0
        return mem

    # ---- control ----
    def _pid(self, error: np.ndarray, mem: np.ndarray) -> np.ndarray:
        """Advance the PID memory with ``error`` (N,) and return the yaw-rate command u (N,)."""
        has_prev = mem[:, _M_HAS_PREV] > 0.5
        integral = np.clip(
            mem[:, _M_INTEGRAL] + error * self.dt, -self.integral_limit, self.integral_limit
        )
        deriv = np.where(has_prev, wrap_to_pi(error - mem[:, _M_PREV]) / self.dt, 0.0)
        mem[:, _M_INTEGRAL] = integral
        mem[:, _M_PREV] = error
        mem[:, _M_HAS_PREV] = 1.0
        return -(self.kp * error + self.ki * integral + self.kd * deriv)

    def _desired_offset(self, obs: dict[str, np.ndarray], mem: np.ndarray) -> np.ndarray:
        """Heading offset (rad, + = left of the LOS heading) to steer to; 0 for plain PID."""
        return np.zeros(obs["path"].shape[0])

    def yaw_rate_command(self, obs: dict[str, np.ndarray], mem: np.ndarray) -> np.ndarray:
        """u (N,) for batched observations, advancing ``mem`` in place."""
        a_c = obs["path"][:, 0].astype(np.float64) * math.pi
        offset = self._desired_offset(obs, mem)
        # desired heading c_d + offset => deviation a_c - offset
        return self._pid(wrap_to_pi(a_c - offset), mem)

    def quantise(self, u: np.ndarray) -> np.ndarray:
        """Map yaw-rate commands u (N,) to actions (Discrete indices or (surge, yaw) pairs)."""
        if self.continuous:
            yaw = np.clip(u / self.yaw_rate_full, -1.0, 1.0)
            return np.stack([np.ones_like(yaw), yaw], axis=1).astype(np.float32)
        t1, t2 = self.turn_thresholds
        mag = np.abs(u)
        left = u > 0
        actions = np.full(u.shape, GO_STRAIGHT, dtype=np.int64)
        turn1 = (mag >= t1) & (mag < t2)
        turn2 = mag >= t2
        actions[turn1 & left] = TURN_LEFT_1
        actions[turn1 & ~left] = TURN_RIGHT_1
        actions[turn2 & left] = TURN_LEFT_2
        actions[turn2 & ~left] = TURN_RIGHT_2
        return actions

    def predict(
        self,
        observation: dict[str, np.ndarray] | np.ndarray,
        state: np.ndarray | None = None,
        episode_start: np.ndarray | None = None,
        deterministic: bool = True,
    ) -> tuple[np.ndarray, np.ndarray]:
        """SB3-style prediction for one observation or a batch (``deterministic`` is ignored:
        the controller is deterministic).

        Returns ``(actions, state)``: int64 ``()`` / ``(N,)`` (or float32 ``(2,)`` / ``(N, 2)``
        when continuous) and the (N, memory_size) memory after this step.
        """
        obs, single = self._batch(observation)
        n = obs["path"].shape[0]
        mem = self._prepare_memory(n, state, episode_start)
        u = self.yaw_rate_command(obs, mem)
        self._memory = mem
        actions = self.quantise(u)
        if single:
            actions = actions[0]
        return actions, mem.copy()

    def _batch(self, observation: Any) -> tuple[dict[str, np.ndarray], bool]:
        """Normalise to a dict of (N, k) float arrays; tell whether the input was one obs."""
        if isinstance(observation, dict):
            if "path" not in observation:
                raise ValueError(
                    f"observation with keys {sorted(observation)} is not allowed: expected a "
                    'Dict observation with a "path" part (rov_envs tasks)'
                )
            parts = {k: np.asarray(v, dtype=np.float64) for k, v in observation.items()}
        else:  # a bare "path" array (Box(2) observation)
            parts = {"path": np.asarray(observation, dtype=np.float64)}
        path = parts["path"]
        if path.ndim == 1 and path.shape == (2,):
            single = True
            parts = {k: v.reshape(1, -1) for k, v in parts.items()}
        elif path.ndim == 2 and path.shape[1] == 2:
            single = False
        else:
            raise ValueError(
                f'observation["path"] of shape {path.shape} is not allowed: expected (2,) or (N, 2)'
            )
        n = parts["path"].shape[0]
        for k, v in parts.items():
            if v.ndim != 2 or v.shape[0] != n:
                raise ValueError(
                    f'observation["{k}"] of shape {v.shape} is not allowed: expected {n} rows '
                    'like "path"'
                )
            if not np.all(np.isfinite(v)):
                raise ValueError(f'observation["{k}"] is not allowed: expected finite values')
        return parts, single
