"""Natively batched rov_envs: N vehicles stepped by one numba call.

The engine is :class:`rov_envs.sim.engine.RovBatch` (arrays for N vehicles, per-vehicle random
streams, the batched kernel, autoresets inside the kernel); :class:`RovVectorEnv` exposes it as a
Gymnasium ``VectorEnv`` (next-step autoreset, infos as a dict of arrays), returned by
``gymnasium.make_vec(id, num_envs=N, vectorization_mode="vector_entry_point")``;
:class:`rov_envs.envs.sb3.RovSB3VecEnv` exposes it as a Stable-Baselines3 ``VecEnv``.

Vehicle i seeded with ``s + i`` (``reset(seed=s)``) lives exactly the episodes of a single
``gymnasium.make(id)`` reset with seed ``s + i`` and then reset without a seed after each episode.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from gymnasium.vector import AutoresetMode, VectorEnv
from gymnasium.vector.utils import batch_space

from rov_envs.sim import kernel as K
from rov_envs.sim.engine import RovBatch
from rov_envs.sim.rewards import END_SUCCESS

__all__ = ["RovVectorEnv"]


def _seeds(seed: int | list[int | None] | None, n: int) -> list[int | None]:
    allowed = f"None, an int >= 0 (vehicle i gets seed + i), or a list of {n} such ints or None"
    if seed is None:
        return [None] * n
    if isinstance(seed, (int, np.integer)) and not isinstance(seed, bool):
        seeds: list = [int(seed) + i for i in range(n)]
    elif isinstance(seed, (list, tuple, np.ndarray)):
        seeds = list(seed)
    else:
        raise ValueError(f"seed={seed!r} is not allowed: expected {allowed}")
    if len(seeds) != n or not all(
        s is None or (isinstance(s, (int, np.integer)) and not isinstance(s, bool) and s >= 0)
        for s in seeds
    ):
        raise ValueError(f"seed={seed!r} is not allowed: expected {allowed}")
    return [None if s is None else int(s) for s in seeds]


class RovVectorEnv(VectorEnv):
    """N rov_envs vehicles as one Gymnasium ``VectorEnv`` (see :class:`rov_envs.envs.env.RovEnv`).

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
        #: the BlueROV2 parameter set these vehicles run (``rov_envs.physics.params.VEHICLES``)
        self.vehicle = self.batch.config.vehicle

    def _with_masks(self, info: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        ones = np.ones(self.num_envs, dtype=bool)  # one mask shared by every always-set key
        for key in list(info):
            info["_" + key] = ones
        return info

    def reset(
        self, *, seed: int | list[int | None] | None = None, options: dict | None = None
    ) -> tuple[dict[str, np.ndarray], dict[str, Any]]:
        self.batch.reset_all(_seeds(seed, self.num_envs))
        self.batch.pending[:] = False
        return self.batch.observations(), self._with_masks(self.batch.infos())

    def step(self, actions: Any):
        b = self.batch
        b.step(actions, K.MODE_NEXT_STEP)
        out = b.out
        rewards = out[K.O_R].copy()
        terminated = out[K.O_TERM] != 0.0
        truncated = out[K.O_TRUNC] != 0.0
        info = self._with_masks(b.infos())
        info["is_success"] = out[K.O_END] == END_SUCCESS
        info["_is_success"] = b.pending.copy()  # ended this step (reset on the next one)
        return b.observations(), rewards, terminated, truncated, info

    def to_sb3(self):
        """A Stable-Baselines3 ``VecEnv`` over a fresh engine with the same task and arguments."""
        from rov_envs.envs.sb3 import RovSB3VecEnv

        return RovSB3VecEnv(self.num_envs, self._task, **self._kwargs)
