"""``arrival_gate``: the end of the path counts as arrival only near the target point."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest

from rov_envs.sim.config import make_config
from rov_envs.sim.rewards import FAILURE_REWARD


def _finish(env_id: str, offset: float, **kwargs):
    """Run straight ahead from ``offset`` m beside the path, 8 m before its end, to the end of
    the episode; the last step's reward and info."""
    env = gym.make(env_id, start_noise=(0.0, 0.0), **kwargs)
    env.reset(seed=0)
    config = env.unwrapped.config
    x_end, y_end = config.target
    env.unwrapped.set_pose(x_end - 8.0, y_end + offset, 0.0)
    for _ in range(40):
        _, reward, terminated, truncated, info = env.step(2)
        if terminated or truncated:
            return reward, terminated, info
    raise AssertionError("the episode did not end within 40 steps")


@pytest.mark.parametrize("offset", [3.0, 8.0])
def test_without_a_gate_the_end_of_the_path_is_a_success_anywhere(offset) -> None:
    _, terminated, info = _finish("rov_envs/PathFollowingStraight-v0", offset)
    assert terminated and info["end_reason"] == "success" and info["is_success"]


def test_a_gate_fails_an_end_passed_farther_off_than_it() -> None:
    """8 m off with a 5 m gate: a failure with eq. 21's reward; 3 m off: still a success."""
    reward, terminated, info = _finish("rov_envs/PathFollowingStraight-v0", 8.0, arrival_gate=5.0)
    assert terminated and info["end_reason"] == "missed_target" and not info["is_success"]
    assert reward == pytest.approx(FAILURE_REWARD + info["r_c"] + info["r_v"])
    assert abs(info["cross_track"]) > 5.0
    _, _, near = _finish("rov_envs/PathFollowingStraight-v0", 3.0, arrival_gate=5.0)
    assert near["end_reason"] == "success" and near["is_success"]


def test_the_gate_reads_the_distance_to_the_sine_path_target() -> None:
    """On the sinusoid the target is (length, A sin(k length)); the gate measures from it."""
    _, _, far = _finish("rov_envs/PlanningSine-v0", 7.0, arrival_gate=5.0)
    assert far["end_reason"] == "missed_target"
    _, _, near = _finish("rov_envs/PlanningSine-v0", 1.0, arrival_gate=5.0)
    assert near["end_reason"] == "success"
    target = make_config("PlanningSine").target
    assert math.hypot(*(np.asarray(near["position"]) - target)) <= 5.0


@pytest.mark.parametrize("bad", [1.0, 101.0, "5", math.nan])
def test_a_bad_gate_is_refused_with_its_value(bad) -> None:
    with pytest.raises(ValueError, match="arrival_gate=.* is not allowed: expected a float in"):
        make_config("PlanningStraight", arrival_gate=bad)
