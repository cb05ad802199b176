"""The pace diagnostic: how a policy's decisions split near and away from obstacles."""

from __future__ import annotations

import json

import gymnasium as gym
import numpy as np
import pytest

import rov_envs  # noqa: F401  (registers the tasks)
from rov_envs.physics.thrusters import ACTION_NAMES
from sb3_pnn.reproduce.tools.obstacle_pace import main, pace, row


class Constant:
    """A policy that always plays one action."""

    def __init__(self, name: str) -> None:
        self.action = ACTION_NAMES.index(name)

    def predict(self, obs, deterministic=True):
        return self.action, None


def test_go_straight_is_faster_than_a_turn_and_classes_follow_the_sonar() -> None:
    """On the obstacle-free path every decision is "beyond d_th"; "Go straight" (four horizontal
    thrusters) moves the vehicle faster than "Turn left 1" (two of them)."""
    env = gym.make("rov_envs/PlanningStraight-v0", obstacles=[], max_episode_seconds=30.0)
    straight = pace(Constant("Go straight"), env, 1, 12.5)
    turn = pace(Constant("Turn left 1"), env, 1, 12.5)
    assert not straight["speeds"]["near"] and not turn["speeds"]["near"]
    assert straight["counts"]["far"][ACTION_NAMES.index("Go straight")] == 30  # 30 s / 1.0 s
    assert np.mean(straight["speeds"]["far"][-20:]) > 1.5 * np.mean(turn["speeds"]["far"][-20:])
    assert "| 0 % | 0 % | - | 100 % | 100 % |" in row("x", straight)
    with_obstacles = pace(
        Constant("Go straight"), gym.make("rov_envs/PlanningStraight-v0"), 1, 12.5
    )
    assert with_obstacles["speeds"]["near"]  # the task's obstacles come within d_th


def test_a_pid_run_is_replayed_and_a_column_cannot_be_drawn(tmp_path, capsys) -> None:
    run = tmp_path / "runs" / "adaptive_pid-straight"
    run.mkdir(parents=True)
    (run / "manifest.json").write_text(json.dumps({"agent": "adaptive_pid"}))
    (run / "eval.json").write_text(json.dumps({"original": {"env_kwargs": {"obstacles": []}}}))
    assert main([str(tmp_path), "--agent", "adaptive_pid", "--episodes", "1"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[2].startswith("| 0 | success 1 | 0 % |")
    with pytest.raises(SystemExit) as stop:
        main([str(tmp_path), "--agent", "oa", "--drawn"])
    assert stop.value.code == 2
    assert "--drawn replays a planning task; --agent oa is a source column" in (
        capsys.readouterr().err
    )
    with pytest.raises(SystemExit):
        main([str(tmp_path), "--agent", "spn"])
    assert "holds no run of --agent 'spn' on the straight path: expected a study" in (
        capsys.readouterr().err
    )
