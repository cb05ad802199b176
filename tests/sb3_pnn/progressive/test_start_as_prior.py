"""``start_as_prior``: before any update a progressive network outputs its prior's own output.

The PNN's actor gives the prior's logits and a critic reading a prior's critic that critic's
Q-values; the SPNN gives, per sample, the output of the prior its hard gate selects. Then the
network learns (the own output layer leaves zero), survives save/load, and bad uses are refused.
"""

from __future__ import annotations

import pytest
import torch as th
from progressive_helpers import (
    NEAR_DISTANCES,
    near_far_batch,
    obs_tensor,
    toy_model,
)

from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy
from sb3_pnn.progressive.columns import FrozenColumn, ProgressiveNet


def _prior(path):
    return DiscreteSAC.load(path, device="cpu").policy


def _pnn(paths, **kwargs):
    kw = dict(priors=[paths["pf_dsac"]], net_arch=[16, 16], start_as_prior=True)
    kw.update(kwargs)
    return toy_model(ProgressivePolicy, kw)


def _spnn(paths, **kwargs):
    kw = dict(priors=[paths["pf_dsac"], paths["oa_dsac"]], net_arch=[16, 16], start_as_prior=True)
    kw.update(kwargs)
    return toy_model(SelectivePolicy, kw)


def test_pnn_starts_with_the_priors_logits_and_q_values(priors):
    model = _pnn(priors, lateral_scale_init=0.0)  # ours: hidden laterals start at 0
    prior = _prior(priors["pf_dsac"])
    obs = near_far_batch(model.observation_space)
    with th.no_grad():
        logits = model.policy.actor(obs_tensor(model.policy, obs))
        q_values = model.policy.critic(obs_tensor(model.policy, obs))
        prior_logits = prior.actor(obs_tensor(prior, obs, ("path",)))
        prior_q = prior.critic(obs_tensor(prior, obs, ("path",)))
    assert th.allclose(logits, prior_logits, atol=1e-6)
    for q, q_prior in zip(q_values, prior_q, strict=True):
        assert th.allclose(q, q_prior, atol=1e-6)
    # and the greedy actions are the prior's
    assert th.equal(logits.argmax(dim=1), prior_logits.argmax(dim=1))


def test_without_it_the_new_column_starts_elsewhere(priors):
    model = _pnn(priors, start_as_prior=False)
    prior = _prior(priors["pf_dsac"])
    obs = near_far_batch(model.observation_space)
    with th.no_grad():
        logits = model.policy.actor(obs_tensor(model.policy, obs))
        prior_logits = prior.actor(obs_tensor(prior, obs, ("path",)))
    assert not th.allclose(logits, prior_logits, atol=1e-3)


def test_spnn_starts_with_the_selected_priors_output_per_sample(priors):
    model = _spnn(priors)
    policy = model.policy
    pf, oa = _prior(priors["pf_dsac"]), _prior(priors["oa_dsac"])
    obs = near_far_batch(model.observation_space)
    near = th.as_tensor(NEAR_DISTANCES <= 12.5)
    assert th.equal(policy.gate_weights(obs)[:, 1], near.float())
    with th.no_grad():
        logits = policy.actor(obs_tensor(policy, obs))
        q_values = policy.critic(obs_tensor(policy, obs))
        pf_in, oa_in = obs_tensor(pf, obs, ("path",)), obs_tensor(oa, obs)
        expected = th.where(near[:, None], oa.actor(oa_in), pf.actor(pf_in))
        expected_q = [
            th.where(near[:, None], q_oa, q_pf)
            for q_pf, q_oa in zip(pf.critic(pf_in), oa.critic(oa_in), strict=True)
        ]
    assert th.allclose(logits, expected, atol=1e-6)
    for q, q_expected in zip(q_values, expected_q, strict=True):
        assert th.allclose(q, q_expected, atol=1e-6)


def test_it_learns_from_there_and_survives_save_load(priors, tmp_path):
    model = _pnn(priors, lateral_scale_init=0.0)
    net = model.policy.actor.net
    frozen = {k: v.clone() for k, v in net.priors.state_dict().items()}
    model.learn(60)
    assert net.layers[-1].weight.abs().sum() > 0  # the own output layer left zero
    assert all(th.equal(v, net.priors.state_dict()[k]) for k, v in frozen.items())
    obs = near_far_batch(model.observation_space)
    model.save(tmp_path / "pnn.zip")
    loaded = DiscreteSAC.load(tmp_path / "pnn.zip", device="cpu")
    assert loaded.policy.start_as_prior is True
    with th.no_grad():
        assert th.equal(
            loaded.policy.actor(obs_tensor(loaded.policy, obs)),
            model.policy.actor(obs_tensor(model.policy, obs)),
        )


def test_critics_without_priors_start_at_random_and_the_actor_as_the_prior(priors):
    model = _pnn(priors, critic_priors=False)
    assert all(len(q.priors) == 0 for q in model.policy.critic.q_networks)
    prior = _prior(priors["pf_dsac"])
    obs = near_far_batch(model.observation_space)
    with th.no_grad():
        assert th.allclose(
            model.policy.actor(obs_tensor(model.policy, obs)),
            prior.actor(obs_tensor(prior, obs, ("path",))),
            atol=1e-6,
        )


def test_bad_uses_are_refused_by_name(priors):
    with pytest.raises(ValueError, match="needs exactly one prior for a ProgressivePolicy"):
        _pnn(priors, priors=[priors["pf_dsac"], priors["oa_dsac"]])
    with pytest.raises(ValueError, match="start_as_prior must be True or False, got 'yes'"):
        _pnn(priors, start_as_prior="yes")
    column = FrozenColumn(_pnn(priors).policy.prior_specs[0].actor)  # 5 outputs
    net = ProgressiveNet(4, [8], 5, th.nn.ReLU, [column])  # no output-lateral bias
    with pytest.raises(ValueError, match="output_lateral_bias=True"):
        net.start_as_priors_()
    wide = ProgressiveNet(4, [8], 7, th.nn.ReLU, [column], output_lateral_bias=True)
    with pytest.raises(ValueError, match=r"does not fit this column's output lateral"):
        wide.start_as_priors_()
    with pytest.raises(ValueError, match="multiplier must be > 0"):
        ProgressiveNet(4, [8], 5, th.nn.ReLU, [column], output_lateral_bias=True).start_as_priors_(
            0.0
        )
