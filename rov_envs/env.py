"""The single-vehicle Gymnasium environment behind every ``rov_envs/*-v0`` id."""

from __future__ import annotations

from typing import Any

import gymnasium as gym
import numpy as np
from gymnasium import spaces

from rov_envs import kernel as K
from rov_envs.config import EnvConfig, make_config
from rov_envs.episode import cfg_array, sample_episode
from rov_envs.physics.dynamics import ADVANCE_WORK_SHAPE
from rov_envs.physics.params import BlueROV2Params
from rov_envs.physics.thrusters import ACTION_TABLE
from rov_envs.rewards import END_COLLISION, END_REASONS, END_SUCCESS


def make_spaces(config: EnvConfig) -> tuple[spaces.Dict, spaces.Space]:
    """Observation and action spaces of a task (shared with the batched environment)."""
    parts: dict[str, spaces.Space] = {"path": spaces.Box(-1.0, 1.0, (2,), np.float32)}
    if config.has_sonar:
        parts["sonar"] = spaces.Box(0.0, 1.0, (config.sonar_sectors,), np.float32)
    action: spaces.Space
    if config.continuous:
        action = spaces.Box(-1.0, 1.0, (2,), np.float32)
    else:
        action = spaces.Discrete(ACTION_TABLE.shape[0])
    return spaces.Dict(parts), action


class RovEnv(gym.Env):
    """BlueROV2 path following with local path planning (Pan et al. 2025, section 4.2).

    ## Description
    A BlueROV2 (Fossen 6-DOF model, :mod:`rov_envs.physics`) runs at constant depth and follows
    a path (a 200 m line or a 120 m sinusoid) while avoiding cylindrical obstacles seen by a
    sector sonar. World frame: x along the straight path, y to its left, z up; the heading psi
    is counter-clockwise from x, so turning left raises it. Which path, reward and obstacles a
    task uses is in :mod:`rov_envs.tasks`; the README's task table lists them.

    ## Action Space
    ``Discrete(5)``: action i is row i of the paper's Table 1 (thruster speeds T1..T6 in
    rev/min): 0 Turn left 1, 1 Turn left 2, 2 Go straight, 3 Turn right 1, 4 Turn right 2.
    With ``continuous=True``: ``Box(-1, 1, (2,))`` = (surge, yaw), mapped onto the same
    horizontal thrusters by ``rov_envs.physics.thrusters.continuous_to_speeds`` (+yaw turns
    left; values are clipped to [-1, 1]). One step lasts 0.2 s (the physics' control period).

    ## Observation Space
    ``Dict`` with
    * ``"path"``: ``Box(-1, 1, (2,), float32)`` = [a_c / pi, clip(g / d_L, -1, 1)]: the LOS
      heading deviation a_c (eq. 16, wrapped to (-pi, pi]) and the signed cross-track distance
      g (positive = vehicle left of the path).
    * ``"sonar"`` (tasks with obstacles): ``Box(0, 1, (q,), float32)``: the shortest distance
      to an obstacle surface in each of q sectors of the span S centred ahead, ordered from the
      vehicle's right to its left, divided by ``sonar_range`` (1 = nothing within range).

    ## Rewards
    ``r = r_c + r_v + r_terminal``: eq. (18) (straight paths) or eq. (19) (sine) for r_c,
    eq. (20) for r_v, eq. (21) -200 on failure; see :mod:`rov_envs.rewards` for the exact
    reading. ObstacleAvoidance rewards progress toward its goal instead of eq. 18.

    ## Starting State
    At (0, 0) heading along the path's tangent, at rest, thrusters stopped, plus the optional
    Gaussian ``start_noise``. Layouts named in the README are drawn afresh from the seed.

    ## Episode End
    Terminated with -200 when |g| >= d_L, |a_c| >= pi/2 or the distance to an obstacle
    surface d <= 2 m (eq. 21); terminated with success when the closest path point passes the
    end of the path (progress >= length) or the vehicle is within 2 m of the target point;
    truncated at the time limit (default: twice the path's arc length at 1 m/s).
    ``info["is_success"]`` is set on the final step; ``info["end_reason"]`` names the cause.

    ## Arguments
    See :func:`rov_envs.config.make_config`: ``obstacles``, ``current``, ``sonar_noise``,
    ``start_noise``, ``length``, ``amplitude``, ``wavelength``, ``sonar_sectors``,
    ``sonar_span``, ``sonar_range``, ``continuous``, ``max_episode_seconds``, ``render_mode``.
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 5}

    def __init__(self, task: str = "PlanningStraight", **kwargs: Any) -> None:
        self.config = make_config(task, **kwargs)
        self.render_mode = self.config.render_mode
        self.observation_space, self.action_space = make_spaces(self.config)
        self.sonar_range = self.config.sonar_range
        self._continuous = self.config.continuous
        self._has_sonar = self.config.has_sonar
        self._params = BlueROV2Params().to_array()
        self._table = np.ascontiguousarray(ACTION_TABLE, dtype=np.float64)
        self._cfg = cfg_array(self.config)
        self._current = np.array([*self.config.current, 0.0], dtype=np.float64)
        self._state = np.zeros(18, dtype=np.float64)
        self._cmd = np.zeros(6, dtype=np.float64)
        self._obstacles = np.zeros((0, 3), dtype=np.float64)
        self._rng = np.zeros(1, dtype=np.uint64)
        self._aux = np.zeros(K.A_SIZE, dtype=np.float64)
        self._work = np.zeros(ADVANCE_WORK_SHAPE, dtype=np.float64)
        self._guide = np.zeros(3, dtype=np.float64)
        q = self.config.sonar_sectors if self._has_sonar else 0
        self._sonar_buf = np.zeros(q, dtype=np.float64)
        self._obs_path = np.zeros(2, dtype=np.float32)
        self._obs_sonar = np.zeros(q, dtype=np.float32)
        self._out = np.zeros(K.O_SIZE, dtype=np.float64)
        self._trajectory: list[tuple[float, float]] = []
        self._started = False

    # ---- public helpers ----
    @property
    def obstacles(self) -> np.ndarray:
        """The current episode's obstacles, (M, 3) of (x, y, radius) in metres (a copy)."""
        return self._obstacles.copy()

    @property
    def state(self) -> np.ndarray:
        """The full 18-dim physics state (a copy): x y z phi theta psi u v w p q r n1..n6."""
        return self._state.copy()

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
        vals = (float(x), float(y), float(heading))
        if not all(np.isfinite(vals)):
            raise ValueError(f"pose={vals!r} is not allowed: expected finite floats")
        self._state[:] = 0.0
        self._state[0], self._state[1], self._state[5] = vals
        K.reset_vehicle(
            self._state, self._cfg, self._obstacles, self._rng, 0, self._aux, self._guide,
            self._sonar_buf, self._obs_path, self._obs_sonar, self._out,
        )  # fmt: skip
        if self.render_mode:
            self._trajectory.append((vals[0], vals[1]))
        return self._obs()

    # ---- gymnasium API ----
    def _obs(self) -> dict[str, np.ndarray]:
        if self._has_sonar:
            return {"path": self._obs_path.copy(), "sonar": self._obs_sonar.copy()}
        return {"path": self._obs_path.copy()}

    def _info(self) -> dict[str, Any]:
        s = self._state
        o = self._out
        return {
            "position": s[0:2].copy(),
            "heading": float(s[5]),
            "velocity": np.array((s[6], s[7], s[11])),
            "cross_track": float(o[K.O_G]),
            "heading_error": float(o[K.O_AC]),
            "obstacle_distance": float(o[K.O_D]),
            "progress": float(o[K.O_PROG]),
            "collision": bool(o[K.O_END] == END_COLLISION),
            "r_c": float(o[K.O_RC]),
            "r_v": float(o[K.O_RV]),
            "r_terminal": float(o[K.O_RT]),
            "end_reason": END_REASONS[int(o[K.O_END])],
            "steps": int(self._aux[K.A_STEPS]),
        }

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        super().reset(seed=seed)
        state, obstacles, stream = sample_episode(self.config, self.np_random)
        self._state[:] = state
        self._obstacles = np.ascontiguousarray(obstacles, dtype=np.float64)
        self._rng[0] = stream
        K.reset_vehicle(
            self._state, self._cfg, self._obstacles, self._rng, 0, self._aux, self._guide,
            self._sonar_buf, self._obs_path, self._obs_sonar, self._out,
        )  # fmt: skip
        self._started = True
        self._trajectory = [(float(state[0]), float(state[1]))] if self.render_mode else []
        return self._obs(), self._info()

    def step(self, action: Any) -> tuple[dict[str, np.ndarray], float, bool, bool, dict]:
        if not self._started:
            raise RuntimeError("call reset() before step() (and after an episode ended)")
        if self._continuous:
            surge, yaw = float(action[0]), float(action[1])
            if surge != surge or yaw != yaw:
                raise ValueError(f"action={action!r} is not allowed: expected two finite floats")
            a = 0
        else:
            a = int(action)
            if not 0 <= a < 5:
                raise ValueError(f"action={action!r} is not allowed: expected an int in [0, 4]")
            surge = yaw = 0.0
        o = self._out
        K.step_single(
            self._state, a, surge, yaw, self._continuous, self._table, self._cmd, self._params,
            self._current, self._cfg, self._obstacles, self._rng, self._aux, self._work,
            self._guide, self._sonar_buf, self._obs_path, self._obs_sonar, o,
        )  # fmt: skip
        terminated = o[K.O_TERM] != 0.0
        truncated = o[K.O_TRUNC] != 0.0
        info = self._info()
        if terminated or truncated:
            info["is_success"] = bool(o[K.O_END] == END_SUCCESS)
            self._started = False
        if self.render_mode:
            self._trajectory.append((float(self._state[0]), float(self._state[1])))
        return self._obs(), float(o[K.O_R]), bool(terminated), bool(truncated), info

    def render(self) -> np.ndarray | None:
        if self.render_mode != "rgb_array":
            return None
        from rov_envs.render import render_topdown

        return render_topdown(
            self.config,
            self._obstacles,
            self.trajectory,
            self._state,
            self._sonar_buf if self._has_sonar else None,
        )
