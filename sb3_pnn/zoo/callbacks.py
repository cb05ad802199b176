"""TensorBoard scalars for the rov_envs tasks, beside SB3's own keys.

SB3 already records ``rollout/success_rate`` from ``info["is_success"]`` at the end of each
episode. This callback adds the route-keeping figures the paper plots (Figures 12-19):

* ``rollout/abs_cross_track_mean``: mean over the last ``window`` episodes of each episode's mean
  |g|, the distance from the target route in metres (``info["cross_track"]``);
* ``rollout/abs_heading_error_mean``: the same for |a_c|, eq. (16), in radians
  (``info["heading_error"]``);
* ``rollout/success_rate_rov``: success share over the last ``window`` episodes, counted here
  too so that it is present even when SB3's buffer is not dumped (e.g. ``--log-interval -2``).

SPNN's gate column shares are logged by DiscreteSAC itself (``train/<name>`` from the policy's
``extra_logs()``).
"""

from __future__ import annotations

from collections import deque

import numpy as np
from stable_baselines3.common.callbacks import BaseCallback

INFO_KEYS = {"cross_track": "abs_cross_track_mean", "heading_error": "abs_heading_error_mean"}


class RovMetricsCallback(BaseCallback):
    """Records per-episode route metrics under ``rollout/`` (see the module docstring)."""

    def __init__(self, window: int = 100, verbose: int = 0) -> None:
        super().__init__(verbose)
        if window < 1:
            raise ValueError(f"window must be >= 1, got {window}")
        self.window = window
        self._episodes = {key: deque(maxlen=window) for key in INFO_KEYS}
        self._successes: deque[float] = deque(maxlen=window)
        self._sums: dict[str, np.ndarray] = {}
        self._counts: dict[str, np.ndarray] = {}

    def _init_callback(self) -> None:
        n_envs = self.training_env.num_envs
        self._sums = {key: np.zeros(n_envs) for key in INFO_KEYS}
        self._counts = {key: np.zeros(n_envs, dtype=np.int64) for key in INFO_KEYS}

    def _on_step(self) -> bool:
        infos = self.locals.get("infos", [])
        dones = self.locals.get("dones", np.zeros(len(infos), dtype=bool))
        ended = False
        for index, info in enumerate(infos):
            for key in INFO_KEYS:
                value = info.get(key)
                if value is not None:
                    self._sums[key][index] += abs(float(value))
                    self._counts[key][index] += 1
            if dones[index]:
                ended = True
                for key in INFO_KEYS:
                    if self._counts[key][index] > 0:
                        mean = self._sums[key][index] / self._counts[key][index]
                        self._episodes[key].append(mean)
                    self._sums[key][index] = 0.0
                    self._counts[key][index] = 0
                if info.get("is_success") is not None:
                    self._successes.append(float(bool(info["is_success"])))
        if ended:
            for key, name in INFO_KEYS.items():
                if self._episodes[key]:
                    self.logger.record(f"rollout/{name}", float(np.mean(self._episodes[key])))
            if self._successes:
                self.logger.record("rollout/success_rate_rov", float(np.mean(self._successes)))
        return True
