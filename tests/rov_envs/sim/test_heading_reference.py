"""a_c from the goal (ObstacleAvoidance) or from the LOS course (every other task), and eq. 21."""

from __future__ import annotations

import math

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
