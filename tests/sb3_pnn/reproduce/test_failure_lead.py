"""The failure-lead diagnostic: which of SPNN's columns led when an episode ended."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
import torch as th

import rov_envs  # noqa: F401  (registers the tasks)
from rov_envs.physics.thrusters import ACTION_NAMES
from sb3_pnn.reproduce.tools.failure_lead import ending_cells, leads, main

SONAR_RANGE = 25.0


class _Gate:
    """Eq. 15's hard switch at 12.5 m on the nearest sonar reading."""

    def gate_weights(self, obs):
        near = float(np.min(obs["sonar"])) * SONAR_RANGE <= 12.5
        return th.tensor([[0.0, 1.0]] if near else [[1.0, 0.0]])


class GoStraight:
    """An SPNN stand-in: a gate, and always "Go straight"."""

    policy = _Gate()

    def predict(self, obs, state=None, episode_start=None, deterministic=True):
        return ACTION_NAMES.index("Go straight"), state


def test_a_collision_is_laid_to_the_avoidance_column_and_a_clear_run_to_the_path_column() -> None:
    """Going straight along PlanningStraight's line runs into the obstacle on it, with the
    avoidance column leading (the obstacle within d_th); without obstacles the path column leads
    every decision to the target."""
    result = leads(GoStraight(), gym.make("rov_envs/PlanningStraight-v0"), 1, 10)
    assert result["endings"] == {("collision", 1): 1}
    assert result["decisions"][0] > 0 and result["decisions"][1] >= 10
    assert ending_cells(result["endings"]) == "collision: path 0, avoid 1"
    clear = leads(GoStraight(), gym.make("rov_envs/PlanningStraight-v0", obstacles=[]), 1, 10)
    assert clear["endings"] == {("success", 0): 1} and clear["decisions"][1] == 0
    straight = ACTION_NAMES.index("Go straight")
    assert clear["actions"][0][straight] == clear["decisions"][0]


def test_bad_arguments_stop_with_a_message(tmp_path, capsys) -> None:
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), "--last", "0"])
    assert stop.value.code == 2
    assert "--last 0 is not allowed: expected a number of decisions >= 1" in (
        capsys.readouterr().err
    )
    with pytest.raises(SystemExit):
        main([str(tmp_path), "--seeds", "0"])
    assert "does not exist" in capsys.readouterr().err


def test_the_actions_come_from_the_policy_that_plays_the_model() -> None:
    """With a playing policy (as the study plays the run), its actions move the vehicle and
    the leader is read from the model's gate; each episode starts with ``episode_start``."""

    class TurnLeft:
        def __init__(self):
            self.starts = []

        def predict(self, obs, state=None, episode_start=None, deterministic=True):
            self.starts.append(bool(episode_start[0]))
            return ACTION_NAMES.index("Turn left 2"), state

    player = TurnLeft()
    env = gym.make("rov_envs/PlanningStraight-v0", obstacles=[])
    result = leads(GoStraight(), env, 2, 10, policy=player)
    assert result["actions"][0][ACTION_NAMES.index("Turn left 2")] == sum(
        result["decisions"].values()
    )
    assert player.starts.count(True) == 2 and player.starts[0]
    assert not any(reason == "success" for reason, _ in result["endings"])  # it circles
