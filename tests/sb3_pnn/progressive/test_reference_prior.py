"""``reference_prior``: a PNN that reads several priors (eq. 13 with every earlier column)
starts as, and is pulled toward, one of them.

With ``priors=[path_following, obstacle_avoidance]`` and ``reference_prior=0`` the actor starts
with the path follower's logits (the avoidance column's output lateral at zero, so it can learn
from there), the KL term's pi_0 is the path follower's policy (not the mean of the two), the
avoidance column's features reach the output once it learns, the choice survives save/load, and
a bad index is refused by name.
"""

from __future__ import annotations

import pytest
import torch as th
import torch.nn.functional as F
from progressive_helpers import near_far_batch, obs_tensor, two_column_pnn

from sb3_pnn import DiscreteSAC

_pnn = two_column_pnn


def _pf(paths):
    return DiscreteSAC.load(paths["pf_dsac"], device="cpu").policy


def test_it_starts_as_the_reference_prior_and_is_pulled_toward_it(priors):
    model = _pnn(priors)
    policy, pf = model.policy, _pf(priors)
    obs = near_far_batch(model.observation_space)
    logits, reference = policy.actor.logits_and_prior_log_probs(obs_tensor(policy, obs))
    with th.no_grad():
        pf_logits = pf.actor(obs_tensor(pf, obs, ("path",)))
        pf_q = pf.critic(obs_tensor(pf, obs, ("path",)))
        q_values = policy.critic(obs_tensor(policy, obs))
    assert th.allclose(logits, pf_logits, atol=1e-6)
    assert th.allclose(reference, F.log_softmax(pf_logits, dim=1), atol=1e-6)
    for q, q_pf in zip(q_values, pf_q, strict=True):
        assert th.allclose(q, q_pf, atol=1e-6)
    # both priors feed the new column: the avoidance column's output lateral starts at zero
    net = policy.actor.net
    last = len(net.layers) - 1
    oa_output = net.laterals[f"{last}_1"]
    assert len(net.priors) == 2
    assert oa_output.weight.abs().sum() == 0 and oa_output.bias.abs().sum() == 0


def test_the_avoidance_column_learns_to_feed_the_output_and_the_choice_is_saved(priors, tmp_path):
    model = _pnn(priors)
    net = model.policy.actor.net
    frozen = {k: v.clone() for k, v in net.priors.state_dict().items()}
    model.learn(80)
    last = len(net.layers) - 1
    assert net.laterals[f"{last}_1"].weight.abs().sum() > 0
    assert all(th.equal(v, net.priors.state_dict()[k]) for k, v in frozen.items())
    model.save(tmp_path / "pnn.zip")
    loaded = DiscreteSAC.load(tmp_path / "pnn.zip", device="cpu")
    assert loaded.policy.reference_prior == 0
    obs = near_far_batch(model.observation_space)
    with th.no_grad():
        a = loaded.policy.actor.logits_and_prior_log_probs(obs_tensor(loaded.policy, obs))
        b = model.policy.actor.logits_and_prior_log_probs(obs_tensor(model.policy, obs))
    assert all(th.equal(x, y) for x, y in zip(a, b, strict=True))


def test_without_it_the_pnn_still_refuses_to_start_as_two_priors(priors):
    with pytest.raises(ValueError, match="needs exactly one prior for a ProgressivePolicy"):
        _pnn(priors, reference_prior=None)


@pytest.mark.parametrize("bad", [2, -1, True, 0.0, "0"])
def test_a_bad_index_is_refused_by_name(priors, bad):
    with pytest.raises(ValueError, match=r"reference_prior=.* is not allowed: expected None or"):
        _pnn(priors, reference_prior=bad)
