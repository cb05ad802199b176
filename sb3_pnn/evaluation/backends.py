"""Where evaluation episodes run: N vehicles stepped together, each (re)started with its seed.

:class:`BatchBackend` runs rov_envs tasks on the natively batched engine
(:class:`rov_envs.sim.engine.RovBatch`, one numba call per step for all vehicles);
:class:`SingleBackend` runs any Gymnasium env id, one ``gymnasium.make`` env per slot, reading
the rov_envs info keys. :func:`make_backend` picks one.
"""

from __future__ import annotations

from typing import Any

import numpy as np


class Backend:
    n: int
    dt: float
    continuous: bool
    observation_space: Any
    action_space: Any

    def reset(self, i: int, seed: int) -> None: ...
    def step(self, actions: np.ndarray, active: np.ndarray) -> dict[str, np.ndarray]: ...
    def observations(self) -> dict[str, np.ndarray]: ...
    def obstacles(self, i: int) -> np.ndarray: ...
    def positions(self) -> np.ndarray: ...
    def start_errors(self) -> tuple[np.ndarray, np.ndarray]: ...


class BatchBackend(Backend):
    """rov_envs' natively batched simulator (one numba call per step for all vehicles)."""

    def __init__(self, task: str, n: int, env_kwargs: dict[str, Any]) -> None:
        from rov_envs.sim.engine import RovBatch

        self.batch = RovBatch(n, task, **env_kwargs)
        self.n = n
        self.dt = float(self.batch.config.dt)
        self.continuous = bool(self.batch.continuous)
        self.sonar_range = float(self.batch.config.sonar_range)
        self.config = self.batch.config
        self.observation_space = self.batch.single_observation_space
        self.action_space = self.batch.single_action_space

    def reset(self, i: int, seed: int) -> None:
        self.batch.reset_index(i, seed=seed)

    def observations(self) -> dict[str, np.ndarray]:
        return self.batch.observations()

    def obstacles(self, i: int) -> np.ndarray:
        return self.batch.vehicle_obstacles(i)

    def positions(self) -> np.ndarray:
        return self.batch.positions()

    def start_errors(self) -> tuple[np.ndarray, np.ndarray]:
        return self.batch.heading_errors(), self.batch.cross_tracks()

    def step(self, actions: np.ndarray, active: np.ndarray) -> dict[str, np.ndarray]:
        if self.continuous:
            actions = np.where(active[:, None], actions, np.array([1.0, 0.0]))
        else:
            actions = np.where(active, actions, 2)
        self.batch.step(actions)
        res = self.batch.step_results()
        return {
            "reward": res["reward"],
            "done": res["terminated"] | res["truncated"],
            "end_reason": res["end_reason"],
            "cross_track": res["cross_track"],
            "heading_error": res["heading_error"],
            "position": self.batch.positions(),
        }


class SingleBackend(Backend):
    """Any Gymnasium env id, one ``gymnasium.make`` env per slot (reads the rov_envs info keys)."""

    def __init__(self, env_id: str, n: int, env_kwargs: dict[str, Any]) -> None:
        import gymnasium as gym

        self.envs = [gym.make(env_id, **env_kwargs) for _ in range(n)]
        self.n = n
        base = self.envs[0].unwrapped
        config = getattr(base, "config", None)
        self.config = config
        self.dt = float(getattr(config, "dt", getattr(base, "dt", 0.2)))
        from gymnasium import spaces

        self.continuous = isinstance(self.envs[0].action_space, spaces.Box)
        self.observation_space = self.envs[0].observation_space
        self.action_space = self.envs[0].action_space
        self._obs: list[dict[str, np.ndarray]] = [{} for _ in range(n)]
        self._info: list[dict[str, Any]] = [{} for _ in range(n)]

    def reset(self, i: int, seed: int) -> None:
        self._obs[i], self._info[i] = self.envs[i].reset(seed=seed)

    def observations(self) -> dict[str, np.ndarray]:
        keys = next(o for o in self._obs if o).keys()
        out = {}
        for k in keys:
            ref = next(o[k] for o in self._obs if o)
            out[k] = np.stack([np.asarray(o[k]) if o else np.zeros_like(ref) for o in self._obs])
        return out

    def obstacles(self, i: int) -> np.ndarray:
        obs = getattr(self.envs[i].unwrapped, "obstacles", np.zeros((0, 3)))
        return np.asarray(obs, dtype=np.float64).reshape(-1, 3)

    def positions(self) -> np.ndarray:
        return np.array([np.asarray(inf.get("position", (np.nan, np.nan))) for inf in self._info])

    def start_errors(self) -> tuple[np.ndarray, np.ndarray]:
        ac = np.array([float(inf.get("heading_error", np.nan)) for inf in self._info])
        g = np.array([float(inf.get("cross_track", np.nan)) for inf in self._info])
        return ac, g

    def step(self, actions: np.ndarray, active: np.ndarray) -> dict[str, np.ndarray]:
        n = self.n
        res = {
            "reward": np.zeros(n),
            "done": np.zeros(n, dtype=bool),
            "end_reason": np.array(["none"] * n, dtype=object),
            "cross_track": np.full(n, np.nan),
            "heading_error": np.full(n, np.nan),
            "position": np.full((n, 2), np.nan),
        }
        for i in np.flatnonzero(active):
            a = actions[i] if self.continuous else int(actions[i])
            obs, r, term, trunc, info = self.envs[i].step(a)
            self._obs[i], self._info[i] = obs, info
            res["reward"][i] = r
            res["done"][i] = term or trunc
            if term or trunc:
                reason = info.get("end_reason")
                if reason is None:
                    reason = "success" if info.get("is_success") else "failure"
                res["end_reason"][i] = reason
            res["cross_track"][i] = info.get("cross_track", np.nan)
            res["heading_error"][i] = info.get("heading_error", np.nan)
            res["position"][i] = info.get("position", (np.nan, np.nan))
        return res


def make_backend(env_id: str, n_envs: int, kwargs: dict[str, Any]) -> Backend:
    """The batched engine for a registered rov_envs task, else one env per slot."""
    import gymnasium as gym

    from rov_envs.sim.tasks import TASKS

    task = (gym.registry[env_id].kwargs or {}).get("task")
    if env_id.startswith("rov_envs/") and task in TASKS:
        return BatchBackend(task, n_envs, kwargs)
    return SingleBackend(env_id, n_envs, kwargs)
