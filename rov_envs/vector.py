"""Natively batched rov_envs: N vehicles stepped by one numba call.

:class:`RovBatch` is the engine (arrays for N vehicles, per-vehicle seeding, the batched kernel);
:class:`RovVectorEnv` exposes it as a Gymnasium ``VectorEnv`` (next-step autoreset, infos as a
dict of arrays), returned by
``gymnasium.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point")``;
:class:`rov_envs.sb3.RovSB3VecEnv` exposes it as a Stable-Baselines3 ``VecEnv``.

Vehicle i seeded with ``s + i`` (``reset(seed=s)``) lives exactly the episodes of a single
``gymnasium.make(id)`` reset with seed ``s + i`` and then reset without a seed after each episode.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium.utils import seeding
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from rov_envs import kernel as K
from rov_envs.config import EnvConfig, make_config
from rov_envs.env import make_spaces
from rov_envs.episode import cfg_array, obstacle_capacity, sample_episode
from rov_envs.physics.dynamics import ADVANCE_WORK_SHAPE, STATE_DIM
from rov_envs.physics.params import BlueROV2Params
from rov_envs.physics.thrusters import ACTION_TABLE
from rov_envs.rewards import END_COLLISION, END_SUCCESS

#: Vehicles from which the batch kernel uses numba's threads (same numbers either way).
PARALLEL_MIN_ENVS = 64


class RovBatch:
    """Arrays and kernels for N vehicles on one task (no autoreset policy of its own)."""

    def __init__(self, num_envs: int, task: str = "PlanningStraight", **kwargs: Any) -> None:
        if isinstance(num_envs, bool) or not isinstance(num_envs, (int, np.integer)):
            raise ValueError(f"num_envs={num_envs!r} is not allowed: expected an int >= 1")
        if num_envs < 1:
            raise ValueError(f"num_envs={num_envs!r} is not allowed: expected an int >= 1")
        self.config: EnvConfig = make_config(task, **kwargs)
        self.num_envs = n = int(num_envs)
        self.single_observation_space, self.single_action_space = make_spaces(self.config)
        c = self.config
        self.has_sonar = c.has_sonar
        self.continuous = c.continuous
        q = c.sonar_sectors if c.has_sonar else 0
        m = obstacle_capacity(c)
        self.params = BlueROV2Params().to_array()
        self.table = np.ascontiguousarray(ACTION_TABLE, dtype=np.float64)
        self.cfg = cfg_array(c)
        self.states = np.zeros((n, STATE_DIM))
        self.cmds = np.zeros((n, 6))
        self.currents = np.tile(np.array([*c.current, 0.0]), (n, 1))
        self.obstacles = np.zeros((n, m, 3))
        self.n_obs = np.zeros(n, dtype=np.int64)
        self.rng = np.zeros(n, dtype=np.uint64)
        self.aux = np.zeros((n, K.A_SIZE))
        self.work = np.zeros((n, *ADVANCE_WORK_SHAPE))
        self.guide = np.zeros((n, 3))
        self.sonar_buf = np.zeros((n, q))
        self.obs_path = np.zeros((n, 2), dtype=np.float32)
        self.obs_sonar = np.zeros((n, q), dtype=np.float32)
        self.out = np.zeros((n, K.O_SIZE))
        self._no_int = np.zeros(n, dtype=np.int64)
        self._no_cont = np.zeros((n, 2))
        self.generators: list[np.random.Generator | None] = [None] * n
        self._kernel = K.step_batch_parallel if n >= PARALLEL_MIN_ENVS else K.step_batch

    def reset_index(self, i: int, seed: int | None = None) -> None:
        """Start a new episode for vehicle i (seeding its generator when ``seed`` is given)."""
        if seed is not None or self.generators[i] is None:
            self.generators[i], _ = seeding.np_random(seed)
        state, obstacles, stream = sample_episode(self.config, self.generators[i])
        self.states[i] = state
        m = obstacles.shape[0]
        self.n_obs[i] = m
        self.obstacles[i, :m] = obstacles
        self.rng[i] = stream
        K.reset_vehicle(
            self.states[i], self.cfg, self.obstacles[i, :m], self.rng, i, self.aux[i],
            self.guide[i], self.sonar_buf[i], self.obs_path[i], self.obs_sonar[i], self.out[i],
        )  # fmt: skip

    def vehicle_obstacles(self, i: int) -> np.ndarray:
        """Vehicle i's current obstacles (M_i, 3) (a copy)."""
        return self.obstacles[i, : self.n_obs[i]].copy()

    def step(self, actions: Any) -> None:
        """Advance every vehicle one control period (results in ``out``, ``obs_*``)."""
        n = self.num_envs
        if self.continuous:
            a = np.asarray(actions, dtype=np.float64)
            if a.shape != (n, 2) or np.isnan(a).any():
                raise ValueError(
                    f"actions of shape {a.shape} are not allowed: expected ({n}, 2) finite floats"
                )
            ai, ac = self._no_int, np.ascontiguousarray(a)
        else:
            ai = np.asarray(actions)
            if ai.shape != (n,) or ai.dtype.kind not in "iu":
                raise ValueError(
                    f"actions={actions!r} are not allowed: expected ({n},) ints in [0, 4]"
                )
            ai = ai.astype(np.int64, copy=False)
            if n and (ai.min() < 0 or ai.max() > 4):
                raise ValueError(f"actions={actions!r} are not allowed: expected ints in [0, 4]")
            ac = self._no_cont
        self._kernel(
            self.states, ai, ac, self.continuous, self.table, self.cmds, self.params,
            self.currents, self.cfg, self.obstacles, self.n_obs, self.rng, self.aux, self.work,
            self.guide, self.sonar_buf, self.obs_path, self.obs_sonar, self.out,
        )  # fmt: skip

    def observations(self) -> dict[str, np.ndarray]:
        if self.has_sonar:
            return {"path": self.obs_path.copy(), "sonar": self.obs_sonar.copy()}
        return {"path": self.obs_path.copy()}

    def infos(self) -> dict[str, np.ndarray]:
        """Per-vehicle info arrays (the single env's info keys, batched)."""
        s, o = self.states, self.out
        return {
            "position": s[:, 0:2].copy(),
            "heading": s[:, 5].copy(),
            "velocity": s[:, (6, 7, 11)],
            "cross_track": o[:, K.O_G].copy(),
            "heading_error": o[:, K.O_AC].copy(),
            "obstacle_distance": o[:, K.O_D].copy(),
            "progress": o[:, K.O_PROG].copy(),
            "collision": o[:, K.O_END] == END_COLLISION,
            "r_c": o[:, K.O_RC].copy(),
            "r_v": o[:, K.O_RV].copy(),
            "r_terminal": o[:, K.O_RT].copy(),
            "end_code": o[:, K.O_END].astype(np.int64),
            "steps": self.aux[:, K.A_STEPS].astype(np.int64),
        }


def _seeds(seed: int | list[int | None] | None, n: int) -> list[int | None]:
    if seed is None:
        return [None] * n
    if isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
        return [int(seed) + i for i in range(n)]
    seeds = list(seed)
    if len(seeds) != n:
        raise ValueError(f"seed={seed!r} is not allowed: expected an int, None or {n} seeds")
    return seeds


class RovVectorEnv(VectorEnv):
    """N rov_envs vehicles as one Gymnasium ``VectorEnv`` (see :class:`rov_envs.env.RovEnv`).

    Autoreset: next-step (Gymnasium's default): the step after a vehicle's episode ends
    returns its reset observation with reward 0 and ``terminated = truncated = False``.
    ``reset(seed=s)`` seeds vehicle i with ``s + i`` (or pass a list of N seeds).
    Infos are a dict of arrays with Gymnasium's ``"_key"`` masks; ``"is_success"`` is set
    (masked) on each vehicle's final step. ``to_sb3()`` wraps the same engine for SB3.

    Arguments: ``num_envs`` and every keyword argument of the single environment.
    """

    metadata = {"render_modes": [], "autoreset_mode": AutoresetMode.NEXT_STEP}

    def __init__(self, num_envs: int = 1, task: str = "PlanningStraight", **kwargs: Any) -> None:
        if kwargs.get("render_mode") is not None:
            raise ValueError(
                f"render_mode={kwargs['render_mode']!r} is not allowed for the batched env: "
                "expected None (render a single env instead)"
            )
        self._task = task
        self._kwargs = dict(kwargs)
        self.batch = RovBatch(num_envs, task, **kwargs)
        self.num_envs = self.batch.num_envs
        self.single_observation_space = self.batch.single_observation_space
        self.single_action_space = self.batch.single_action_space
        self.observation_space = batch_space(self.single_observation_space, self.num_envs)
        self.action_space = batch_space(self.single_action_space, self.num_envs)
        self.render_mode = None
        self.sonar_range = self.batch.config.sonar_range
        self._autoreset = np.zeros(self.num_envs, dtype=bool)
        self._ones = np.ones(self.num_envs, dtype=bool)

    def _with_masks(self, info: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        for key in list(info):
            info["_" + key] = self._ones.copy()
        return info

    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        seeds = _seeds(seed, self.num_envs)
        for i, s in enumerate(seeds):
            self.batch.reset_index(i, s)
        self._autoreset[:] = False
        return self.batch.observations(), self._with_masks(self.batch.infos())

    def step(self, actions: Any):
        b = self.batch
        b.step(actions)
        reset_now = np.flatnonzero(self._autoreset)
        for i in reset_now:
            b.reset_index(int(i))
        out = b.out
        rewards = out[:, K.O_R].copy()
        terminated = out[:, K.O_TERM] != 0.0
        truncated = out[:, K.O_TRUNC] != 0.0
        if reset_now.size:
            rewards[reset_now] = 0.0
            terminated[reset_now] = False
            truncated[reset_now] = False
        done = terminated | truncated
        info = self._with_masks(b.infos())
        info["is_success"] = out[:, K.O_END] == END_SUCCESS
        info["_is_success"] = done
        self._autoreset = done
        return b.observations(), rewards, terminated, truncated, info

    def to_sb3(self):
        """A Stable-Baselines3 ``VecEnv`` over a fresh engine with the same task and arguments."""
        from rov_envs.sb3 import RovSB3VecEnv

        return RovSB3VecEnv(self.num_envs, self._task, **self._kwargs)
