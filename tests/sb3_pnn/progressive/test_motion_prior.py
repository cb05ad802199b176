"""A prior trained with the "motion" observation part feeds into a planning task that has it."""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest
import torch as th
from stable_baselines3 import DQN

import rov_envs  # noqa: F401  (registers the ids)
from sb3_pnn import DiscreteSAC, ProgressivePolicy
from sb3_pnn.progressive.prior_loading import load_prior


@pytest.fixture(scope="module")
def motion_prior(tmp_path_factory):
    """A tiny DQN on PathFollowingStraight with ``motion_obs=True``: {"motion", "path"}."""
    env = gym.make("rov_envs/PathFollowingStraight-v0", motion_obs=True)
    assert set(env.observation_space.spaces) == {"motion", "path"}
    path = tmp_path_factory.mktemp("motion_prior") / "pf_motion.zip"
    DQN("MultiInputPolicy", env, policy_kwargs=dict(net_arch=[12]), seed=0).save(path)
    return path


def _planning_observations(env: gym.Env, n: int) -> dict[str, np.ndarray]:
    """n real observations of the planning task (random Table 1 actions from a seeded start)."""
    rows = []
    obs, _ = env.reset(seed=3)
    rng = np.random.default_rng(0)
    for _ in range(n):
        obs, _, term, trunc, _ = env.step(int(rng.integers(0, 5)))
        rows.append(obs)
        if term or trunc:
            obs, _ = env.reset()
    return {k: np.stack([r[k] for r in rows]) for k in rows[0]}


def test_motion_prior_gets_exactly_its_parts_from_the_planning_task(motion_prior):
    env = gym.make("rov_envs/PlanningStraight-v0", motion_obs=True)
    assert set(env.observation_space.spaces) == {"motion", "path", "goal", "sonar"}
    model = DiscreteSAC(
        ProgressivePolicy, env, policy_kwargs=dict(priors=[motion_prior], net_arch=[8])
    )
    assert load_prior(motion_prior).spec.obs.keys == ("motion", "path")
    feed = model.policy.actor.feeds[0]
    assert feed.keys == ("motion", "path")  # the prior's own parts, in its own order
    obs = _planning_observations(env, 32)
    assert np.abs(obs["motion"][:, 1]).max() > 0.05  # the vehicle really turned
    tens, _ = model.policy.obs_to_tensor(obs)
    fed = feed(tens)
    assert th.equal(fed, th.cat([tens["motion"], tens["path"]], dim=1))
    # the frozen column computes what the DQN computed on its own observation
    dqn = DQN.load(motion_prior)
    own = dqn.policy.obs_to_tensor({"motion": obs["motion"], "path": obs["path"]})[0]
    col = model.policy.actor.net.priors[0]
    assert th.allclose(col(fed), dqn.q_net(own), atol=1e-6)


def test_motion_prior_is_refused_by_a_task_without_motion(motion_prior):
    env = gym.make("rov_envs/PlanningStraight-v0", motion_obs=False)  # no "motion" part
    with pytest.raises(ValueError, match=r"pf_motion.zip.*key 'motion' is missing"):
        DiscreteSAC(ProgressivePolicy, env, policy_kwargs=dict(priors=[motion_prior]))
