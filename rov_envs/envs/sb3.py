"""Stable-Baselines3 ``VecEnv`` over the natively batched rov_envs engine.

SB3 wants same-step autoreset and a list of info dicts: a vehicle whose episode ends is reset in
the same ``step_wait`` call; its info then carries ``"terminal_observation"``,
``"TimeLimit.truncated"``, ``"is_success"`` and an ``"episode"`` record ({"r", "l", "t"}, as
SB3's Monitor writes it, so ``ep_rew_mean`` and ``success_rate`` are logged without a wrapper).
Other steps give empty info dicts unless ``info_keys`` names keys to copy every step (for a vehicle
that has just been reset, those values are already its new episode's).
"""

from __future__ import annotations

import time
from collections.abc import Iterable, Sequence
from typing import Any

import numpy as np
from stable_baselines3.common.vec_env.base_vec_env import VecEnv, VecEnvStepReturn

from rov_envs.sim import kernel as K
from rov_envs.sim.engine import RovBatch
from rov_envs.sim.rewards import END_SUCCESS


def _task_name(task_or_id: str) -> str:
    if task_or_id.startswith("rov_envs/") and task_or_id.endswith("-v0"):
        return task_or_id[len("rov_envs/") : -len("-v0")]
    return task_or_id


class RovSB3VecEnv(VecEnv):
    """N vehicles of one rov_envs task as an SB3 ``VecEnv``.

    Args:
        num_envs: number of vehicles.
        task: a task name (``"PlanningStraight"``) or id (``"rov_envs/PlanningStraight-v0"``).
        info_keys: info keys (of :meth:`rov_envs.sim.engine.RovBatch.infos`) copied into every
            step's info dicts (slower; default none).
        **kwargs: the single environment's keyword arguments.
    """

    def __init__(
        self,
        num_envs: int = 1,
        task: str = "PlanningStraight",
        info_keys: Iterable[str] = (),
        **kwargs: Any,
    ) -> None:
        if kwargs.get("render_mode") is not None:
            raise ValueError(
                f"render_mode={kwargs['render_mode']!r} is not allowed for the batched env: "
                "expected None"
            )
        self.batch = RovBatch(num_envs, _task_name(task), **kwargs)
        self.render_mode = None
        self.sonar_range = self.batch.config.sonar_range
        #: the BlueROV2 parameter set these vehicles run (``rov_envs.physics.params.VEHICLES``)
        self.vehicle = self.batch.config.vehicle
        self.info_keys = tuple(info_keys)
        known = set(self.batch.infos())
        for key in self.info_keys:
            if key not in known:
                raise ValueError(f"info_keys={info_keys!r}: {key!r} is not one of {sorted(known)}")
        super().__init__(
            self.batch.num_envs,
            self.batch.single_observation_space,
            self.batch.single_action_space,
        )
        self._actions: np.ndarray | None = None
        self._ep_return = np.zeros(self.num_envs)
        self._ep_len = np.zeros(self.num_envs, dtype=np.int64)
        self._t0 = time.time()

    def reset(self):
        self.batch.reset_all([self._seeds[i] for i in range(self.num_envs)])
        self._reset_seeds()
        self._reset_options()
        self._ep_return[:] = 0.0
        self._ep_len[:] = 0
        self.reset_infos = [{} for _ in range(self.num_envs)]
        return self.batch.observations()

    def step_async(self, actions: np.ndarray) -> None:
        """Check the actions now (one per vehicle: ``(N,)`` or ``(N, 1)`` ints, or ``(N, 2)``
        floats with ``continuous=True``), so that a wrong shape is named here."""
        a = np.asarray(actions)
        n = self.num_envs
        if self.batch.continuous:
            ok = a.shape == (n, 2)
            expected = f"({n}, 2) floats"
        else:
            ok = a.shape in ((n,), (n, 1)) and a.dtype.kind in "iu"
            expected = f"({n},) ints"
        if not ok:
            raise ValueError(
                f"actions of shape {a.shape} and dtype {a.dtype} are not allowed: expected "
                f"{expected}, one per vehicle"
            )
        self._actions = a

    def step_wait(self) -> VecEnvStepReturn:
        b = self.batch
        actions = self._actions
        if not b.continuous:
            actions = np.asarray(actions).reshape(self.num_envs)
        b.step(actions, K.MODE_SAME_STEP)
        # the kernel has already reset the vehicles that ended (flagged in ``pending``): their
        # final reward and ending are in ``final``, their final observation in ``term_*``
        dones = b.pending.copy()
        ended = np.flatnonzero(dones)
        rewards = b.out[K.O_R].copy()
        rewards[ended] = b.final[K.F_REWARD, ended]
        self._ep_return += rewards
        self._ep_len += 1
        obs = b.observations()
        if self.info_keys:
            full = b.infos()
            infos = [{k: full[k][i] for k in self.info_keys} for i in range(self.num_envs)]
        else:
            infos = [{} for _ in range(self.num_envs)]
        if ended.size:
            final = b.final[:, ended]
            truncated = ((final[K.F_TRUNC] != 0) & (final[K.F_TERM] == 0)).tolist()
            success = (final[K.F_END] == END_SUCCESS).tolist()
            returns = self._ep_return[ended].tolist()
            lengths = self._ep_len[ended].tolist()
            terminal = b.terminal_observations(ended)  # copies: they outlive later steps
            t = round(time.time() - self._t0, 6)
            for j, i in enumerate(ended.tolist()):
                infos[i].update(
                    terminal_observation={k: v[j] for k, v in terminal.items()},
                    is_success=success[j],
                    episode={"r": returns[j], "l": lengths[j], "t": t},
                )
                infos[i]["TimeLimit.truncated"] = truncated[j]
            self._ep_return[ended] = 0.0
            self._ep_len[ended] = 0
        return obs, rewards.astype(np.float32), dones, infos

    def close(self) -> None:
        pass

    # ---- attribute plumbing required by VecEnv ----
    def _indices(self, indices: None | int | Sequence[int]) -> list[int]:
        if indices is None:
            return list(range(self.num_envs))
        if isinstance(indices, int):
            return [indices]
        return list(indices)

    def get_attr(self, attr_name: str, indices: None | int | Sequence[int] = None) -> list[Any]:
        if attr_name == "obstacles":
            return [self.batch.vehicle_obstacles(i) for i in self._indices(indices)]
        value = getattr(
            self.batch.config if hasattr(self.batch.config, attr_name) else self, attr_name
        )
        return [value for _ in self._indices(indices)]

    def set_attr(
        self, attr_name: str, value: Any, indices: None | int | Sequence[int] = None
    ) -> None:
        setattr(self, attr_name, value)

    def env_method(
        self,
        method_name: str,
        *method_args: Any,
        indices: None | int | Sequence[int] = None,
        **method_kwargs: Any,
    ) -> list[Any]:
        method = getattr(self, method_name)
        return [method(*method_args, **method_kwargs) for _ in self._indices(indices)]

    def env_is_wrapped(self, wrapper_class: type, indices: None | int | Sequence[int] = None):
        return [False for _ in self._indices(indices)]
