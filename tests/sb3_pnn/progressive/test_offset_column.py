"""An avoidance column that reads its distance from the route (``goal_offset``) inside SPNN."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

import rov_envs  # noqa: F401 - registers the tasks
from sb3_pnn import DiscreteSAC, SelectivePolicy


@pytest.fixture(scope="module")
def columns(tmp_path_factory):
    folder = tmp_path_factory.mktemp("offset_columns")
    out = {}
    for name, env_id, kwargs in (
        ("pf", "rov_envs/PathFollowingSine-v0", {}),
        ("oa", "rov_envs/ObstacleAvoidance-v0", {"goal_offset": True, "corridor": 15.0}),
    ):
        model = DiscreteSAC("MultiInputPolicy", gym.make(env_id, **kwargs), seed=0)
        out[name] = folder / f"{name}.zip"
        model.save(out[name])
    return out


def test_spnn_feeds_the_offset_to_the_column_that_was_trained_with_it(columns) -> None:
    env = gym.make("rov_envs/PlanningSine-v0", goal_offset=True)
    priors = [str(columns["pf"]), str(columns["oa"])]
    spnn = DiscreteSAC(SelectivePolicy, env, policy_kwargs=dict(priors=priors, start_as_prior=True))
    oa = DiscreteSAC.load(columns["oa"])
    obs, _ = env.reset(seed=0)
    # within d_th the SPNN starts as its avoidance column: the same greedy action, from the
    # column's own keys (goal with the offset, sonar, motion) of the planning observation
    env.unwrapped.set_pose(25.0, 13.0, 0.5)
    obs, *_ = env.step(2)
    assert obs["sonar"].min() * env.unwrapped.sonar_range <= 12.5
    own = {k: obs[k] for k in oa.observation_space.spaces}
    assert own["goal"].shape == (2,)
    greedy = spnn.predict(obs, deterministic=True)[0]
    np.testing.assert_array_equal(greedy, oa.predict(own, deterministic=True)[0])


def test_a_planning_task_without_the_offset_is_refused_naming_the_goal_part(columns) -> None:
    with pytest.raises(ValueError, match="goal"):
        DiscreteSAC(
            SelectivePolicy,
            gym.make("rov_envs/PlanningSine-v0"),
            policy_kwargs=dict(priors=[str(columns["pf"]), str(columns["oa"])]),
        )
