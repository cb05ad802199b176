"""Each prior column gets exactly the observation it was trained on (the feeding rule)."""

from __future__ import annotations

import numpy as np
import pytest
import torch as th
from gymnasium import spaces
from progressive_helpers import PATH, SONAR, ToyRovEnv, batch
from stable_baselines3 import DQN

from sb3_pnn import DiscreteSAC, ProgressivePolicy
from sb3_pnn.progressive.obs_spec import match_prior_obs, obs_spec_from_space
from sb3_pnn.progressive.prior_loading import load_prior


def test_dict_prior_gets_its_keys_in_its_order():
    prior = obs_spec_from_space(spaces.Dict({"path": PATH, "sonar": SONAR}))
    new = obs_spec_from_space(
        spaces.Dict({"aaa": spaces.Box(0, 1, (3,)), "path": PATH, "sonar": SONAR})
    )
    feed = match_prior_obs(prior, new)
    assert feed.keys == ("path", "sonar")
    obs = {"aaa": th.zeros(2, 3), "path": th.ones(2, 2), "sonar": th.full((2, 9), 0.5)}
    assert th.equal(feed(obs), th.cat([obs["path"], obs["sonar"]], dim=1))


def test_box_prior_from_dict_key_or_box():
    prior = obs_spec_from_space(PATH)
    assert match_prior_obs(
        prior, obs_spec_from_space(spaces.Dict({"path": PATH, "sonar": SONAR}))
    ).keys == ("path",)
    assert match_prior_obs(prior, obs_spec_from_space(PATH)).keys == (None,)


@pytest.mark.parametrize(
    "new_space, why",
    [
        (spaces.Dict({"sonar": SONAR}), "key 'path' is missing"),
        (spaces.Dict({"path": spaces.Box(-1, 1, (3,), np.float32)}), "key 'path' is Box"),
        (spaces.Dict({"path": spaces.Box(-2, 2, (2,), np.float32)}), "key 'path' is Box"),
        (spaces.Box(-1, 1, (2,), np.float32), "expects a Dict"),
    ],
)
def test_unfit_dict_prior_names_both_spaces(new_space, why):
    prior = obs_spec_from_space(spaces.Dict({"path": PATH}))
    with pytest.raises(ValueError, match=why) as err:
        match_prior_obs(prior, obs_spec_from_space(new_space), "prior pf.zip")
    msg = str(err.value)
    assert "pf.zip" in msg and "Prior observation space: Dict('path'" in msg
    assert "new observation space: " in msg


def test_unfit_box_prior_names_both_spaces():
    prior = obs_spec_from_space(spaces.Box(0, 1, (9,), np.float32))
    new = obs_spec_from_space(spaces.Dict({"a": SONAR, "b": SONAR}))
    with pytest.raises(ValueError, match=r"several keys \(\['a', 'b'\]\).*Box\(0.0, 1.0, \(9,\)"):
        match_prior_obs(prior, new)


def test_policy_refuses_unfit_prior_checkpoint(priors):
    env = ToyRovEnv(("sonar",))  # the path-following prior needs "path"
    with pytest.raises(
        ValueError, match=r"pf_dqn.zip.*'path' is missing.*Dict\('path'.*Dict\('sonar'"
    ):
        DiscreteSAC(ProgressivePolicy, env, policy_kwargs=dict(priors=[priors["pf_dqn"]]))


def test_prior_column_reproduces_the_checkpoint(priors):
    """The frozen column, fed from a {"path", "sonar"} observation, computes what the path-only
    DQN computed on its own observation."""
    env = ToyRovEnv()
    model = DiscreteSAC(
        ProgressivePolicy, env, policy_kwargs=dict(priors=[priors["pf_dqn"]], net_arch=[8])
    )
    dqn = DQN.load(priors["pf_dqn"])
    obs = batch(env.observation_space, 16)
    tens, _ = model.policy.obs_to_tensor(obs)
    col = model.policy.actor.net.priors[0]
    fed = model.policy.actor.feeds[0](tens)
    q_dqn = dqn.q_net(dqn.policy.obs_to_tensor({"path": obs["path"]})[0])
    assert th.allclose(col(fed), q_dqn, atol=1e-6)
    assert load_prior(priors["pf_dqn"]).spec.obs.keys == ("path",)
