"""n-step returns for dictionary observations, which SB3's ``NStepReplayBuffer`` does not take.

The planning tasks observe a ``Dict`` (path, goal, sonar, motion), and SB3 2.9 refuses
``n_steps > 1`` there ("N-step returns are not supported for Dict observation spaces yet").
:class:`DictNStepReplayBuffer` stores transitions as ``DictReplayBuffer`` does and, when
sampled, returns for each transition (s_t, a_t) the n-step return

    R_t = sum_{k < m} gamma^k r_{t+k},  s' = s_{t+m},  discount gamma^m,

where m <= n stops at the first step that ends the episode (terminal or truncated), as SB3's
``NStepReplayBuffer`` does for flat observations (:func:`n_step_window`; gamma^m is computed in
float64 and rounded to float32, where SB3 computes it in float32, so the last bit may differ).
``DiscreteSAC`` picks this buffer by itself for a
``Dict`` observation space with ``n_steps > 1``; the critic target then reads
``y = R_t + (1 - done) gamma^m V(s')`` (``soft_td_target`` with the sample's discounts).

With ``step_successors`` set, a sample also carries the one-step successor s_{t+1} of each s_t
(:class:`DictNStepReplayBufferSamples`), which a loss comparing consecutive states reads (the
actor's temporal smoothness term, ``ProgressivePolicy(action_smoothness=...)``).
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
import torch as th
from stable_baselines3.common.buffers import DictReplayBuffer
from stable_baselines3.common.type_aliases import DictReplayBufferSamples, TensorDict


class DictNStepReplayBufferSamples(NamedTuple):
    """SB3's ``DictReplayBufferSamples`` and the one-step successors s_{t+1}."""

    observations: TensorDict
    actions: th.Tensor
    next_observations: TensorDict
    dones: th.Tensor
    rewards: th.Tensor
    discounts: th.Tensor | None
    step_next_observations: TensorDict


def n_step_window(
    buffer: DictReplayBuffer,
    batch_inds: np.ndarray,
    env_indices: np.ndarray,
    n_steps: int,
    gamma: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """For sampled rows ``batch_inds`` of environments ``env_indices``: the n-step returns
    (B, 1), the bootstrap discounts gamma^m (B, 1), the rows of s' (B,) and the terminal flags
    of s' (B, 1; 0 where the window ended by truncation or by the length n).

    The newest stored row is treated as an episode end while sampling, so that no window reads
    past it into older transitions of a buffer that has wrapped around."""
    newest = buffer.pos - 1
    saved = buffer.timeouts[newest].copy()
    buffer.timeouts[newest] = np.logical_or(saved, np.logical_not(buffer.dones[newest]))
    try:
        rows = (batch_inds[:, None] + np.arange(n_steps)[None, :]) % buffer.buffer_size
        envs = env_indices[:, None]
        rewards = buffer.rewards[rows, envs]
        ends = np.logical_or(buffer.dones[rows, envs], buffer.timeouts[rows, envs])
        last = np.where(ends.any(axis=1), ends.argmax(axis=1), n_steps - 1)
        inside = np.arange(n_steps)[None, :] <= last[:, None]
        powers = gamma ** np.arange(n_steps, dtype=np.float32)[None, :]
        returns = (rewards * powers * inside).sum(axis=1, keepdims=True)
        discounts = gamma ** inside.sum(axis=1, keepdims=True)  # gamma^m in float64
        next_rows = (batch_inds + last) % buffer.buffer_size
        dones = buffer.dones[next_rows, env_indices][:, None].astype(np.float32)
        truncated = buffer.timeouts[next_rows, env_indices][:, None].astype(np.float32)
    finally:
        buffer.timeouts[newest] = saved
    return (
        returns.astype(np.float32),
        discounts.astype(np.float32),
        next_rows,
        dones * (1.0 - truncated),
    )


class DictNStepReplayBuffer(DictReplayBuffer):
    """``DictReplayBuffer`` that samples n-step returns (see the module docstring).

    :param n_steps: the return's length n (>= 1; 1 samples one-step transitions)
    :param gamma: the discount of the return and of the bootstrap

    :attr:`step_successors` (default False): samples also carry s_{t+1} (module docstring).
    """

    step_successors: bool = False

    def __init__(self, *args: Any, n_steps: int = 3, gamma: float = 0.99, **kwargs: Any) -> None:
        if not (
            isinstance(n_steps, (int, np.integer))
            and not isinstance(n_steps, bool)
            and n_steps >= 1
        ):
            raise ValueError(f"n_steps must be an integer >= 1, got {n_steps!r}")
        if not (isinstance(gamma, (int, float)) and 0.0 <= gamma <= 1.0):
            raise ValueError(f"gamma must be in [0, 1], got {gamma!r}")
        super().__init__(*args, **kwargs)
        if self.optimize_memory_usage:
            raise ValueError("DictNStepReplayBuffer does not take optimize_memory_usage=True")
        self.n_steps, self.gamma = int(n_steps), float(gamma)

    def _get_samples(  # type: ignore[override]
        self, batch_inds: np.ndarray, env: Any = None
    ) -> DictReplayBufferSamples | DictNStepReplayBufferSamples:
        # numpy's global generator, as SB3's buffers (seeded by the algorithm's set_random_seed)
        env_indices = np.random.randint(0, high=self.n_envs, size=(len(batch_inds),))  # noqa: NPY002
        returns, discounts, next_rows, dones = n_step_window(
            self, batch_inds, env_indices, self.n_steps, self.gamma
        )
        obs = self._normalize_obs(
            {key: o[batch_inds, env_indices, :] for key, o in self.observations.items()}, env
        )
        next_obs = self._normalize_obs(
            {key: o[next_rows, env_indices, :] for key, o in self.next_observations.items()}, env
        )
        assert isinstance(obs, dict) and isinstance(next_obs, dict)
        samples = DictReplayBufferSamples(
            observations={key: self.to_torch(o) for key, o in obs.items()},
            actions=self.to_torch(self.actions[batch_inds, env_indices]),
            next_observations={key: self.to_torch(o) for key, o in next_obs.items()},
            dones=self.to_torch(dones),
            rewards=self.to_torch(self._normalize_reward(returns, env)),
            discounts=self.to_torch(discounts),
        )
        if not self.step_successors:
            return samples
        step_next = self._normalize_obs(
            {key: o[batch_inds, env_indices, :] for key, o in self.next_observations.items()}, env
        )
        assert isinstance(step_next, dict)
        return DictNStepReplayBufferSamples(
            *samples, step_next_observations={k: self.to_torch(o) for k, o in step_next.items()}
        )
