"""SAC-Multi (paper 4.3): a DiscreteSAC started from a prior's weights, all of them trained."""

from __future__ import annotations

import pytest
import torch as th
from progressive_helpers import ToyRovEnv, batch
from stable_baselines3 import DQN

from sb3_pnn import DiscreteSAC, make_sac_multi


def test_initial_policy_and_q_are_the_priors(priors):
    env = ToyRovEnv()  # {"path", "sonar"}; the prior saw only "path"
    model = make_sac_multi(
        priors["pf_dsac"], env, learning_starts=20, batch_size=16, seed=0, buffer_size=1000
    )
    prior = DiscreteSAC.load(priors["pf_dsac"])
    obs = batch(env.observation_space, 64)
    new_t, _ = model.policy.obs_to_tensor(obs)
    old_t, _ = prior.policy.obs_to_tensor({"path": obs["path"]})
    with th.no_grad():
        assert th.allclose(model.actor(new_t), prior.actor(old_t), atol=1e-6)
        for q_new, q_old in zip(model.critic(new_t), prior.critic(old_t), strict=True):
            assert th.allclose(q_new, q_old, atol=1e-6)
        for q_tgt, q_old in zip(model.critic_target(new_t), prior.critic(old_t), strict=True):
            assert th.allclose(q_tgt, q_old, atol=1e-6)
    first = model.actor.latent_pi[0].weight
    assert th.count_nonzero(first[:, 2:]) == 0  # sonar inputs (after "path") start at zero
    model.learn(80)
    assert th.count_nonzero(model.actor.latent_pi[0].weight[:, 2:]) > 0  # and are trained


def test_dqn_prior_gives_the_same_greedy_action(priors):
    env = ToyRovEnv()
    model = make_sac_multi(priors["pf_dqn"], env)
    dqn = DQN.load(priors["pf_dqn"])
    obs = batch(env.observation_space, 64, seed=1)
    a_new, _ = model.predict(obs, deterministic=True)
    a_old, _ = dqn.predict({"path": obs["path"]}, deterministic=True)
    assert (a_new == a_old).all()
    assert model.policy.net_arch == [16, 12]


def test_refuses_arch_override_and_unfit_env(priors):
    with pytest.raises(ValueError, match="takes net_arch from the prior"):
        make_sac_multi(priors["pf_dsac"], ToyRovEnv(), policy_kwargs=dict(net_arch=[4]))
    with pytest.raises(ValueError, match=r"'path' is missing"):
        make_sac_multi(priors["oa_dsac"], ToyRovEnv(("sonar",)))
