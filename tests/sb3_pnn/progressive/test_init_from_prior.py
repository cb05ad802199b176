"""``init_from_prior``: the new column starts as a copy of the first prior's column.

Section 3.1 of the paper: "the parameters of the second column are usually initialized with
Theta^(1) or randomly". With the laterals' scale at 0 (ours) a PNN then starts with exactly the
prior's logits and Q-values; the priors stay frozen while the copy learns; the copy survives
save/load (a loaded model does not need the prior files), and bad uses are refused by name.
"""

from __future__ import annotations

import pytest
import torch as th
from progressive_helpers import batch, toy_model

from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy


def _prior(path):
    return DiscreteSAC.load(path, device="cpu").policy


def _pnn(paths, **kwargs):
    kw = dict(
        priors=[paths["pf_dsac"]], net_arch=[16, 16], init_from_prior=True, lateral_scale_init=0.0
    )
    kw.update(kwargs)
    return toy_model(ProgressivePolicy, kw)


def _outputs(policy, obs, keys=None):
    part = obs if keys is None else {k: obs[k] for k in keys}
    x = policy.obs_to_tensor(part)[0]
    with th.no_grad():
        return policy.actor(x), policy.critic(x)


def test_pnn_starts_as_a_copy_of_its_prior(priors):
    model = _pnn(priors, critic_priors=False)
    obs = batch(model.observation_space, 7, seed=5)
    logits, q_values = _outputs(model.policy, obs)
    prior_logits, prior_q = _outputs(_prior(priors["pf_dsac"]), obs, ("path",))
    assert th.allclose(logits, prior_logits, atol=1e-6)
    for q, q_prior in zip(q_values, prior_q, strict=True):
        assert th.allclose(q, q_prior, atol=1e-6)
    # the sonar, which the prior does not see, starts with zero weights in the first layer
    first = model.policy.actor.net.layers[0].weight
    assert th.count_nonzero(first).item() == first.shape[0] * 2  # "path" has 2 features


def test_without_it_the_new_column_starts_at_random(priors):
    model = _pnn(priors, init_from_prior=False)
    obs = batch(model.observation_space, 7, seed=5)
    logits, _ = _outputs(model.policy, obs)
    prior_logits, _ = _outputs(_prior(priors["pf_dsac"]), obs, ("path",))
    assert not th.allclose(logits, prior_logits, atol=1e-3)


def test_the_copy_learns_the_prior_stays_frozen_and_save_load_keeps_it(priors, tmp_path):
    model = _pnn(priors)
    net = model.policy.actor.net
    frozen = {k: v.clone() for k, v in net.priors.state_dict().items()}
    start = net.layers[1].weight.clone()
    model.learn(60)
    assert not th.equal(net.layers[1].weight, start)
    assert all(th.equal(v, net.priors.state_dict()[k]) for k, v in frozen.items())
    model.save(tmp_path / "pnn.zip")
    loaded = DiscreteSAC.load(tmp_path / "pnn.zip", device="cpu")
    assert loaded.policy.init_from_prior is True
    obs = batch(model.observation_space, 7, seed=6)
    assert th.equal(_outputs(loaded.policy, obs)[0], _outputs(model.policy, obs)[0])


def test_spnn_copies_its_path_following_prior(priors):
    model = toy_model(
        SelectivePolicy,
        dict(
            priors=[priors["pf_dsac"], priors["oa_dsac"]],
            net_arch=[16, 16],
            init_from_prior=True,
            start_as_prior=False,  # the copy alone (starting as the prior zeroes the output)
        ),
    )
    pf = _prior(priors["pf_dsac"])
    own = model.policy.actor.net.layers
    assert th.equal(own[1].weight, pf.actor.latent_pi[2].weight)
    assert th.equal(own[2].bias, pf.actor.action_logits.bias)


def test_bad_uses_are_refused_by_name(priors):
    with pytest.raises(ValueError, match="init_from_prior must be True or False, got 'yes'"):
        _pnn(priors, init_from_prior="yes")
    with pytest.raises(ValueError, match=r"hidden widths are \[16, 16\].*hidden widths \[32\]"):
        _pnn(priors, net_arch=[32])
