"""A callback that trains for a fixed number of EPISODES and records each one.

The paper measures training in episodes (Figures 10, 11, 14). :class:`EpisodeRecorder` stops
``learn()`` once ``n_episodes`` episodes have ended and records, per episode, the return (sum of
the rewards of eq. 17-21), the length in steps, success (``info["is_success"]``) and the end
reason; for the episodes listed in ``record`` it also keeps the trajectory (x, y per step, from
``info["position"]``). One environment (``n_envs == 1``), as in the paper.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from stable_baselines3.common.callbacks import BaseCallback


class EpisodeRecorder(BaseCallback):
    """Stop after ``n_episodes`` episodes; record returns, lengths, successes, trajectories."""

    def __init__(self, n_episodes: int, record: tuple[int, ...] = ()) -> None:
        super().__init__(verbose=0)
        if isinstance(n_episodes, bool) or not isinstance(n_episodes, int) or n_episodes < 1:
            raise ValueError(f"n_episodes={n_episodes!r} is not allowed: expected an integer >= 1")
        self.n_episodes = n_episodes
        self.record = frozenset(record)
        self.returns: list[float] = []
        self.lengths: list[int] = []
        self.successes: list[bool] = []
        self.end_reasons: list[str] = []
        self.trajectories: dict[int, np.ndarray] = {}
        self._ret = 0.0
        self._len = 0
        self._path: list[tuple[float, float]] = []

    def _init_callback(self) -> None:
        if self.training_env.num_envs != 1:
            raise ValueError(
                f"EpisodeRecorder counts the episodes of one environment; got "
                f"{self.training_env.num_envs} environments"
            )

    @property
    def episode(self) -> int:
        """Index of the episode in progress (0-based)."""
        return len(self.returns)

    def _on_step(self) -> bool:
        info: dict[str, Any] = self.locals["infos"][0]
        self._ret += float(self.locals["rewards"][0])
        self._len += 1
        if self.episode in self.record and "position" in info:
            pos = info["position"]
            self._path.append((float(pos[0]), float(pos[1])))
        if bool(self.locals["dones"][0]):
            if self._path:
                self.trajectories[self.episode] = np.asarray(self._path, dtype=np.float64)
            self.returns.append(self._ret)
            self.lengths.append(self._len)
            self.successes.append(bool(info.get("is_success", False)))
            self.end_reasons.append(str(info.get("end_reason", "")))
            self._ret, self._len, self._path = 0.0, 0, []
        return self.episode < self.n_episodes

    def to_dict(self) -> dict[str, Any]:
        """Per-episode records (JSON-able); trajectories are saved separately."""
        return {
            "returns": self.returns,
            "lengths": self.lengths,
            "successes": self.successes,
            "end_reasons": self.end_reasons,
            "recorded_episodes": sorted(self.trajectories),
        }
