"""The single-vehicle Gymnasium environment behind every ``rov_envs/*-v0`` id."""

from __future__ import annotations

import math
from typing import Any

import gymnasium as gym
import numpy as np

from rov_envs.sim import kernel as K
from rov_envs.sim.config import make_config
from rov_envs.sim.engine import RovBatch
from rov_envs.sim.rewards import END_COLLISION, END_REASONS, END_SUCCESS
from rov_envs.sim.spaces import make_spaces

__all__ = ["RovEnv", "make_spaces"]


def _discrete_action(action: Any) -> int:
    """A Table 1 row index from an int, a numpy integer or a one-element integer array."""
    if isinstance(action, (int, np.integer)) and not isinstance(action, bool):  # kept fast
        if 0 <= action < 5:
            return int(action)
    elif isinstance(action, np.ndarray) and action.ndim <= 1 and action.size == 1:
        # a 0-d array, or SB3's predict on one observation: shape (1,)
        if action.dtype.kind in "iu" and 0 <= action.reshape(()) < 5:
            return int(action.reshape(()))
    raise ValueError(
        f"action={action!r} is not allowed: expected an int in [0, 4] (or a one-element "
        "integer array)"
    )


def _continuous_action(action: Any) -> tuple[float, float]:
    """(surge, yaw) as two finite floats, from any sequence of exactly two numbers."""
    try:
        if len(action) == 2:
            surge, yaw = float(action[0]), float(action[1])
            if math.isfinite(surge) and math.isfinite(yaw):
                return surge, yaw
    except (TypeError, ValueError):
        pass  # refused below
    raise ValueError(f"action={action!r} is not allowed: expected two finite floats")


class RovEnv(gym.Env):
    """BlueROV2 path following with local path planning (Pan et al. 2025, section 4.2).

    ## Description
    A BlueROV2 (Fossen 6-DOF model, :mod:`rov_envs.physics`; ``vehicle="uuv_simulator"``, the
    default, is UUV Simulator's parameter set that the paper ran in Gazebo, ``vehicle="wu2018"``
    Wu's 2018 set, see ``rov_envs.physics.params``) runs at constant depth and follows
    a path (a 200 m line or a 120 m sinusoid) while avoiding cylindrical obstacles seen by a
    sector sonar. World frame: x along the straight path, y to its left, z up; the heading psi
    is counter-clockwise from x, so turning left raises it. Which path, reward and obstacles a
    task uses is in :mod:`rov_envs.sim.tasks`; the README's task table lists them.

    ## Action Space
    ``Discrete(5)``: action i is row i of the paper's Table 1 (thruster speeds T1..T6 in
    rev/min): 0 Turn left 1, 1 Turn left 2, 2 Go straight, 3 Turn right 1, 4 Turn right 2.
    With ``continuous=True``: ``Box(-1, 1, (2,))`` = (surge, yaw), mapped onto the same
    horizontal thrusters by ``rov_envs.physics.thrusters.continuous_to_speeds`` (+yaw turns
    left; values are clipped to [-1, 1]). One step lasts ``control_period`` seconds (default 1.0 s).

    ## Observation Space
    ``Dict`` with
    * ``"path"``: ``Box(-1, 1, (2,), float32)`` = [a_c / pi, clip(g / d_L, -1, 1)]: the LOS
      heading deviation a_c (eq. 16, wrapped to (-pi, pi]) and the signed cross-track distance
      g (positive = vehicle left of the path); with ``heading_reference="goal"`` a_c is taken
      from the bearing to the target point instead. Not on ObstacleAvoidance by default.
    * ``"goal"`` (ObstacleAvoidance and the planning tasks by default): ``Box(-1, 1, (1,),
      float32)`` = [heading deviation from the bearing to the goal / pi], the goal being the
      route point ``goal_distance`` metres ahead of the closest one (or the target point).
    * ``"sonar"`` (tasks with obstacles): ``Box(0, 1, (q,), float32)``: the shortest distance
      to an obstacle surface in each of q sectors of the span S centred ahead, ordered from the
      vehicle's right to its left, divided by ``sonar_range`` (1 = nothing within range).
    * ``"motion"`` (any task; ``motion_obs=True`` by default):
      ``Box([-3, -2], [3, 2], (2,), float32)`` = [v, r]: the body-frame sway velocity v (m/s,
      over ground, + = to the left) and yaw rate r (rad/s, + = turning left), as the vehicle's
      state holds them after the step, clipped to the bounds
      (``rov_envs.sim.kernel.MOTION_SWAY_LIMIT``, ``MOTION_YAW_RATE_LIMIT``).

    ## Rewards
    ``r = r_c + r_v + r_terminal``: eq. (18) (straight paths) or eq. (19) (sine) for r_c,
    eq. (20) for r_v, eq. (21) -200 on failure; see :mod:`rov_envs.sim.rewards` for the exact
    reading. ObstacleAvoidance rewards progress toward its goal instead of eq. 18.

    ## Starting State
    At (0, 0) heading along the path's tangent, at rest, thrusters stopped, plus a Gaussian
    ``start_noise`` (default 1 m and 5 deg std; ``(0, 0)`` for the paper's exact start).
    Layouts named in the README are drawn afresh from the seed.

    ## Episode End
    Terminated with -200 when |g| >= d_L, the heading rule's deviation reaches pi/2 (|a_c| as
    eq. 21, or on the planning tasks the deviation from the goal's bearing: ``heading_rule``)
    or the distance to an obstacle surface d <= 2 m (eq. 21); terminated with success when the
    closest path point passes the end of the path (progress >= length) or the vehicle is within
    2 m of the target point;
    truncated at the time limit (default: twice the path's arc length at 1 m/s).
    ``info["is_success"]`` is set on the final step; ``info["end_reason"]`` names the cause.

    ## Arguments
    Every keyword argument, with its type, default and meaning, is a field of
    :class:`rov_envs.sim.config.EnvConfig` (documented there, once for all tasks and for the
    batched environments). A bad value raises ``ValueError`` naming it and what is allowed.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 5}

    def __init__(self, task: str = "PlanningStraight", **kwargs: Any) -> None:
        self.config = make_config(task, **kwargs)
        self.render_mode = self.config.render_mode
        self.observation_space, self.action_space = make_spaces(self.config)
        self.sonar_range = self.config.sonar_range
        #: the BlueROV2 parameter set this env runs (``rov_envs.physics.params.VEHICLES``)
        self.vehicle = self.config.vehicle
        self._batch = RovBatch(1, config=self.config)
        self._continuous = self.config.continuous
        self._has_sonar = self.config.has_sonar
        self._action = np.zeros(1, dtype=np.int64)
        self._cont = np.zeros((1, 2))
        self._trajectory: list[tuple[float, float]] = []
        self._started = False

    # ---- public helpers ----
    @property
    def obstacles(self) -> np.ndarray:
        """The current episode's obstacles, (M, 3) of (x, y, radius) in metres (a copy)."""
        return self._batch.vehicle_obstacles(0)

    @property
    def state(self) -> np.ndarray:
        """The full 18-dim physics state (a copy): x y z phi theta psi u v w p q r n1..n6."""
        return self._batch.state(0)

    @property
    def trajectory(self) -> np.ndarray:
        """(T, 2) positions of this episode so far (recorded only with a render_mode)."""
        return np.asarray(self._trajectory, dtype=np.float64).reshape(-1, 2)

    def set_pose(self, x: float, y: float, heading: float) -> dict[str, np.ndarray]:
        """Put the vehicle at rest at (x, y) with ``heading`` (rad) and observe it there.

        For tests and scripted scenarios: keeps the episode's obstacles, clears the step
        counter, returns the new observation. Call after ``reset``.
        """
        if not self._started:
            raise RuntimeError("call reset() before set_pose()")
        self._batch.set_pose(0, x, y, heading)
        if self.render_mode:
            self._trajectory.append((float(x), float(y)))
        return self._obs()

    # ---- gymnasium API ----
    def _obs(self) -> dict[str, np.ndarray]:
        return self._batch.observation(0)

    def _info(self) -> dict[str, Any]:
        o = self._batch.out[:, 0]
        return {
            "position": np.array((o[K.O_X], o[K.O_Y])),
            "heading": float(o[K.O_PSI]),
            "velocity": np.array((o[K.O_U], o[K.O_V], o[K.O_YAW_RATE])),
            "cross_track": float(o[K.O_G]),
            "heading_error": float(o[K.O_AC]),
            "obstacle_distance": float(o[K.O_D]),
            "progress": float(o[K.O_PROG]),
            "collision": bool(o[K.O_END] == END_COLLISION),
            "r_c": float(o[K.O_RC]),
            "r_v": float(o[K.O_RV]),
            "r_terminal": float(o[K.O_RT]),
            "end_reason": END_REASONS[int(o[K.O_END])],
            "steps": int(o[K.O_STEPS]),
        }

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        super().reset(seed=seed)
        b = self._batch
        if seed is not None or not b.seeded[0]:
            b.seed_stream(0, self.np_random)
        b.reset_index(0)
        self._started = True
        if self.render_mode:
            self._trajectory = [(float(b.out[K.O_X, 0]), float(b.out[K.O_Y, 0]))]
        return self._obs(), self._info()

    def step(self, action: Any) -> tuple[dict[str, np.ndarray], float, bool, bool, dict]:
        if not self._started:
            raise RuntimeError("call reset() before step() (and after an episode ended)")
        if self._continuous:
            self._cont[0] = _continuous_action(action)
        else:
            self._action[0] = _discrete_action(action)
        b = self._batch
        K.step_batch(K.MODE_PLAIN, 1, self._action, self._cont, self._continuous, *b.step_arrays)
        b.after_kernel_step(K.MODE_PLAIN)
        o = b.out[:, 0]
        terminated = o[K.O_TERM] != 0.0
        truncated = o[K.O_TRUNC] != 0.0
        info = self._info()
        if terminated or truncated:
            info["is_success"] = bool(o[K.O_END] == END_SUCCESS)
            self._started = False
        if self.render_mode:
            self._trajectory.append((float(o[K.O_X]), float(o[K.O_Y])))
        return self._obs(), float(o[K.O_R]), bool(terminated), bool(truncated), info

    def render(self) -> np.ndarray | None:
        if self.render_mode != "rgb_array":
            return None
        from rov_envs.render.frames import render_topdown

        return render_topdown(
            self.config,
            self.obstacles,
            self.trajectory,
            self.state,
            self._batch.sonar_raw[0] if self._has_sonar else None,
        )
