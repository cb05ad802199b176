"""``progress_along="course"``: the weighted r_c measures the advance along the LOS course."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from rov_envs_helpers import paper_env

from rov_envs.sim.rewards import reward_sine, reward_straight


@pytest.mark.parametrize(
    ("env_id", "pose", "d_L", "reward"),
    [
        ("rov_envs/PathFollowingStraight-v0", (50.0, 8.0, -0.4), 30.0, reward_straight),
        ("rov_envs/PathFollowingSine-v0", (20.0, 4.0, 0.2), 15.0, reward_sine),
    ],
)
def test_course_weighted_r_c(env_id, pose, d_L, reward) -> None:
    """r_c = eq. 18/19 times the step's advance along the LOS course (heading - a_c, read at
    the step's end) / (1 m/s * dt), clipped to [0, 1]."""
    env = paper_env(env_id, progress_weighted=True, progress_along="course", control_period=0.5)
    env.reset(seed=0)
    env.unwrapped.set_pose(*pose)
    position = np.array(pose[:2])
    weights = []
    for action in (2, 2, 3, 3, 2, 2, 1, 2):
        _, _, _, _, info = env.step(action)
        eq = reward(info["heading_error"], info["cross_track"], d_L)
        course = info["heading"] - info["heading_error"]
        advance = float(np.dot(info["position"] - position, (math.cos(course), math.sin(course))))
        weight = min(1.0, max(0.0, advance / (1.0 * 0.5)))
        assert eq > 0
        assert info["r_c"] == pytest.approx(eq * weight, abs=1e-9)
        position = info["position"]
        weights.append(weight)
    assert max(weights) - min(weights) > 0.05  # the weight does change along the run


def _r_c_after(along: str, heading: float) -> float:
    env = gym.make(
        "rov_envs/PathFollowingStraight-v0", progress_along=along, start_noise=(0.0, 0.0)
    )
    env.reset(seed=1)
    env.unwrapped.set_pose(20.0, 10.0, heading)
    for _ in range(6):  # up to speed
        _, _, _, _, info = env.step(2)
    return float(info["r_c"])


def test_course_pays_the_way_back() -> None:
    """10 m off the straight path: along the tangent, running parallel pays about as much as
    turning back along the LOS course (the offset can be held); along the course the way back
    pays several times more."""
    parallel, back = 0.0, -math.atan2(10.0, 5.0)
    assert _r_c_after("path", back) == pytest.approx(_r_c_after("path", parallel), abs=0.05)
    assert _r_c_after("course", back) > 3 * _r_c_after("course", parallel)


def test_obstacle_avoidance_reward_does_not_read_it() -> None:
    """The obstacle-avoidance task's progress reward is the same either way."""
    rewards = []
    for along in ("path", "course"):
        env = gym.make("rov_envs/ObstacleAvoidance-v0", progress_along=along)
        env.reset(seed=3)
        rewards.append([env.step(a)[1] for a in (2, 2, 1, 3, 2, 0, 4, 2)])
    assert rewards[0] == rewards[1]


@pytest.mark.parametrize("bad", ["los", "", 1, None])
def test_bad_progress_along_refused(bad) -> None:
    with pytest.raises(ValueError, match="progress_along") as err:
        gym.make("rov_envs/PathFollowingStraight-v0", progress_along=bad)
    assert "one of ['path', 'course']" in str(err.value)
