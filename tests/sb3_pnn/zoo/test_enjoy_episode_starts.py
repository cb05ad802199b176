"""``enjoy`` tells a played policy where each episode starts (the wrappers that play SPNN as the
study does, SwitchMemory and NoReversal, forget their memory there), and wraps as asked."""

from __future__ import annotations

import argparse

import gymnasium as gym
import numpy as np
import pytest

import rov_envs  # noqa: F401  (registers the tasks)
from sb3_pnn.evaluation.no_reversal import NoReversal
from sb3_pnn.zoo.errors import ZooUsageError
from sb3_pnn.zoo.play import _run, played_as_asked


class TurnsLeftThenRight:
    """Plays "Turn left 2" (action 1) on an episode's first step, "Turn right 1" (3) after:
    NoReversal plays "Go straight" (2) for the first right turn after the left one, and an
    episode's left turn is never held against the right turn that ended the episode before."""

    action_space = gym.spaces.Discrete(5)

    def __init__(self) -> None:
        self.starts: list[bool] = []

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        start = bool(np.asarray(episode_start).reshape(-1)[0])
        self.starts.append(start)
        return np.int64(1 if start else 3), state


def _args(**changes) -> argparse.Namespace:
    args = dict(stochastic=False, record=None, n_timesteps=12, seed=3, verbose=0)
    args.update(switch_memory=None, no_reversal=False)
    args.update(changes)
    return argparse.Namespace(**args)


def test_each_episode_starts_with_episode_start_true() -> None:
    env = gym.make("rov_envs/PathFollowingStraight-v0", max_episode_seconds=3)
    policy = TurnsLeftThenRight()
    _run(policy, env, _args())
    # 3 s at the 1.0 s control period: episodes of 3 steps, 12 steps in all
    assert policy.starts == [True, False, False] * 4


def test_no_reversal_forgets_at_each_episode_start() -> None:
    env = gym.make("rov_envs/PathFollowingStraight-v0", max_episode_seconds=3)
    policy = TurnsLeftThenRight()
    played = played_as_asked(policy, _args(no_reversal=True))
    assert isinstance(played, NoReversal)
    actions: list[int] = []
    predict = played.predict

    def record(obs, state=None, episode_start=None, deterministic=True):
        action, state = predict(obs, state, episode_start, deterministic)
        actions.append(int(action))
        return action, state

    played.predict = record  # type: ignore[method-assign]
    _run(played, env, _args())
    assert actions == [1, 2, 3] * 4


def test_switch_memory_refuses_a_policy_without_spnn_gate() -> None:
    with pytest.raises(ZooUsageError, match=r"--switch-memory 10\.0: SwitchMemory needs an SPNN"):
        played_as_asked(TurnsLeftThenRight(), _args(switch_memory=10.0))
