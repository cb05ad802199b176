"""a_c from the goal (ObstacleAvoidance) or from the LOS course (every other task), and eq. 21."""

from __future__ import annotations

import math

import gymnasium as gym
import numpy as np
import pytest
from rov_envs_helpers import paper_env

import rov_envs  # noqa: F401
from rov_envs.physics.guidance import DEFAULT_LOOKAHEAD


def _wrap(angle: float) -> float:
    return math.atan2(math.sin(angle), math.cos(angle))


@pytest.mark.parametrize(
    ("task", "kwargs", "reference"),
    [("ObstacleAvoidance", {}, "goal"),
     ("ObstacleAvoidance", {"heading_reference": "path"}, "path"),
     ("PlanningStraight", {}, "path"),
     ("PathFollowingStraight", {"heading_reference": "goal"}, "goal")],
)  # fmt: skip
def test_heading_error_is_measured_from_the_reference(task, kwargs, reference) -> None:
    env = paper_env(f"rov_envs/{task}-v0", start_noise=(3.0, 0.4), **kwargs)
    goal = np.array(env.unwrapped.config.target)
    obs, info = env.reset(seed=5)
    for step in range(40):
        x, y = info["position"]
        psi = info["heading"]
        if reference == "goal":
            expected = _wrap(psi - math.atan2(goal[1] - y, goal[0] - x))
        else:  # the straight line y = 0 with the LOS lookahead of eq. 16
            expected = _wrap(psi + math.atan(y / DEFAULT_LOOKAHEAD))
        assert info["heading_error"] == pytest.approx(expected, abs=1e-9)
        assert obs["path"][0] == pytest.approx(expected / math.pi, abs=1e-6)
        obs, _, terminated, truncated, info = env.step(step % 5)
        if terminated or truncated:
            break


def test_heading_limit_follows_the_reference() -> None:
    """Eq. 21's |a_c| >= pi/2 failure: a start pose off the line, heading away from it, fails
    against the LOS course (5 m lookahead) and not against the goal 60 m ahead."""
    kwargs = {"start_noise": (3.0, 1.2)}
    goal_env = paper_env("rov_envs/ObstacleAvoidance-v0", **kwargs)
    path_env = paper_env("rov_envs/ObstacleAvoidance-v0", heading_reference="path", **kwargs)
    for seed in range(2000):
        _, info = goal_env.reset(seed=seed)
        (x, y), psi = info["position"], info["heading"]
        off_path = abs(_wrap(psi + math.atan(y / DEFAULT_LOOKAHEAD)))
        off_goal = abs(_wrap(psi - math.atan2(-y, 60.0 - x)))
        if off_path > math.pi / 2 + 0.1 and off_goal < math.pi / 2 - 0.1:
            break
    else:
        pytest.fail("no start pose between the two limits in 2000 seeds")
    _, path_info = path_env.reset(seed=seed)
    assert np.allclose(path_info["position"], info["position"])  # the same start pose
    assert goal_env.step(2)[4]["end_reason"] == "none"
    assert path_env.step(2)[4]["end_reason"] == "heading"
    with pytest.raises(ValueError, match="heading_reference='north' is not allowed"):
        paper_env("rov_envs/ObstacleAvoidance-v0", heading_reference="north")


@pytest.mark.parametrize("goal_distance", [None, 25.0])
def test_passing_beside_the_target_is_a_success(goal_distance) -> None:
    """A vehicle that goes straight 3-4 m beside the line reaches the end as a success under the
    goal heading rule: the target's bearing swings past 90 deg on the step that passes it, and
    that step counts as arriving, not as turning away."""
    env = paper_env(
        "rov_envs/PathFollowingStraight-v0",
        length=30.0,
        start_noise=(3.0, 0.0),
        heading_rule="goal",
        goal_distance=goal_distance,
    )
    for seed in range(500):
        _, info = env.reset(seed=seed)
        if 3.0 < abs(info["position"][1]) < 4.0 and info["position"][0] < 1.0:
            break
    else:
        pytest.fail("no start pose 3-4 m beside the line in 500 seeds")
    reasons = []
    for _ in range(200):
        _, _, terminated, truncated, info = env.step(2)  # Go straight
        if terminated or truncated:
            reasons.append(info["end_reason"])
            break
    assert reasons == ["success"]
    assert info["is_success"]


def test_goal_ahead_follows_the_route_past_its_end() -> None:
    """With goal_distance D the "goal" part looks at the route point D m ahead of the closest
    one, the route continued past its end (y = 0 for the straight line), never at the target."""
    env = paper_env(
        "rov_envs/PathFollowingStraight-v0",
        length=30.0,
        start_noise=(2.0, 0.1),
        goal_obs=True,
        goal_distance=25.0,
    )
    obs, info = env.reset(seed=3)
    for _ in range(40):
        (x, y), psi = info["position"], info["heading"]
        expected = _wrap(psi - math.atan2(-y, x + 25.0 - x))  # closest point (x, 0), goal x + 25
        assert obs["goal"][0] == pytest.approx(expected / math.pi, abs=1e-6)
        obs, _, terminated, truncated, info = env.step(2)
        if terminated or truncated:
            break


@pytest.mark.parametrize("task", ["ObstacleAvoidance", "PlanningSine"])
def test_goal_offset_appends_the_distance_from_the_path(task) -> None:
    """goal_offset=True: the goal part is [goal heading deviation / pi, g / d_L]; its first entry
    is the part without the option, on the same episode."""
    plain = gym.make(f"rov_envs/{task}-v0", start_noise=(3.0, 0.4))
    wide = gym.make(f"rov_envs/{task}-v0", start_noise=(3.0, 0.4), goal_offset=True)
    assert wide.observation_space["goal"].shape == (2,)
    assert plain.observation_space["goal"].shape == (1,)
    d_L = wide.unwrapped.config.d_L
    (obs_p, _), (obs_w, info) = plain.reset(seed=3), wide.reset(seed=3)
    for step in range(30):
        assert obs_w["goal"][0] == obs_p["goal"][0]
        assert obs_w["goal"][1] == pytest.approx(info["cross_track"] / d_L, abs=1e-6)
        action = (step // 6) % 5
        obs_p, *_ = plain.step(action)
        obs_w, _, terminated, truncated, info = wide.step(action)
        if terminated or truncated:
            break
    with pytest.raises(ValueError, match="goal_offset"):
        gym.make("rov_envs/PathFollowingStraight-v0", goal_offset=True)
