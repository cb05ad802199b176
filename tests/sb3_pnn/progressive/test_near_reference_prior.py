"""``near_reference_prior``: a PNN that reads a path-following and an obstacle-avoidance column
is pulled toward the avoidance column's policy near obstacles, toward the path follower's beyond.

With ``reference_prior=0``, ``near_reference_prior=1`` and ``prior_kl_clearance=12.5`` the KL
term's pi_0 is, sample by sample, the avoidance checkpoint's own policy where the nearest
obstacle is within 12.5 m (eq. 15's switch) and the path follower's elsewhere, and every sample
counts; ``near_reference_corridor`` hands samples far off the path back to the path follower;
training with a strong term keeps the policy near the avoidance column on near states; the
choice survives save/load; bad combinations are refused by name.
"""

from __future__ import annotations

import numpy as np
import pytest
import torch as th
import torch.nn.functional as F
from progressive_helpers import (
    NEAR_DISTANCES,
    batch,
    near_far_batch,
    near_reference_pnn,
    obs_tensor,
)

from sb3_pnn import DiscreteSAC

NEAR = NEAR_DISTANCES <= 12.5  # far, near, far, near, near


def _own_log_probs(paths, obs):
    """log pi of the path-following and of the avoidance checkpoint, each on its own parts."""
    pf = DiscreteSAC.load(paths["pf_dsac"], device="cpu").policy
    oa = DiscreteSAC.load(paths["oa_dsac"], device="cpu").policy
    with th.no_grad():
        log_pf = F.log_softmax(pf.actor(obs_tensor(pf, obs, ("path",))), dim=1)
        log_oa = F.log_softmax(oa.actor(obs_tensor(oa, obs)), dim=1)
    return log_pf, log_oa


def test_the_reference_is_the_avoidance_column_near_and_the_path_column_beyond(priors):
    model = near_reference_pnn(priors)
    policy = model.policy
    obs = near_far_batch(model.observation_space)
    obs["path"][:, 1] = 0.1  # well inside the corridor
    _, reference = policy.actor.logits_and_prior_log_probs(obs_tensor(policy, obs))
    log_pf, log_oa = _own_log_probs(priors, obs)
    near = th.as_tensor(NEAR)
    assert th.allclose(reference[near], log_oa[near], atol=1e-6)
    assert th.allclose(reference[~near], log_pf[~near], atol=1e-6)
    assert not th.allclose(log_pf[near], log_oa[near], atol=1e-3)  # the two priors differ
    assert policy.actor.prior_kl_weights(obs_tensor(policy, obs)) is None  # every sample counts
    # without it the near samples are left out of the term, as before
    plain = near_reference_pnn(priors, near_reference_prior=None).policy
    weights = plain.actor.prior_kl_weights(obs_tensor(plain, obs))
    assert th.equal(weights, th.as_tensor(~NEAR, dtype=th.float32))


def test_the_corridor_bound_hands_far_off_samples_back_to_the_path_column(priors):
    model = near_reference_pnn(priors, near_reference_corridor=0.5)
    policy = model.policy
    obs = near_far_batch(model.observation_space)
    obs["path"][:, 1] = np.array([0.1, 0.1, 0.1, 0.7, -0.6], dtype=np.float32)
    _, reference = policy.actor.logits_and_prior_log_probs(obs_tensor(policy, obs))
    log_pf, log_oa = _own_log_probs(priors, obs)
    oa_rows = th.tensor([False, True, False, False, False])  # near and inside 0.5 d_L
    assert th.allclose(reference[oa_rows], log_oa[oa_rows], atol=1e-6)
    assert th.allclose(reference[~oa_rows], log_pf[~oa_rows], atol=1e-6)


def test_a_strong_term_keeps_the_policy_near_the_avoidance_column_near_obstacles(priors):
    """The toy task pays for action 2 only. Trained with a strong KL term, the run whose near
    samples are referred to the avoidance column ends closer to that column's policy on near
    states than the run that leaves them out; the frozen columns keep every bit."""
    space = near_reference_pnn(priors).observation_space
    obs = batch(space, 256, seed=7)
    obs["sonar"] = np.minimum(obs["sonar"], 0.3).astype(np.float32)  # every state within 7.5 m
    _, log_oa = _own_log_probs(priors, obs)
    kls = {}
    for near_prior in (None, 1):
        model = near_reference_pnn(priors, near_reference_prior=near_prior, prior_kl=10.0)
        frozen = {k: v.clone() for k, v in model.policy.state_dict().items() if "priors" in k}
        model.learn(400)
        with th.no_grad():
            log_pi = F.log_softmax(model.policy.actor(obs_tensor(model.policy, obs)), dim=1)
        kls[near_prior] = float((log_pi.exp() * (log_pi - log_oa)).sum(dim=1).mean())
        after = model.policy.state_dict()
        assert all(th.equal(after[k], v) for k, v in frozen.items())
    assert kls[1] < 0.5 * kls[None], kls


def test_the_choice_is_saved_and_earlier_models_are_unchanged(priors, tmp_path):
    model = near_reference_pnn(priors, near_reference_corridor=0.9)
    model.learn(40)
    model.save(tmp_path / "pnn.zip")
    loaded = DiscreteSAC.load(tmp_path / "pnn.zip", device="cpu").policy
    assert (loaded.near_reference_prior, loaded.near_reference_corridor) == (1, 0.9)
    obs = obs_tensor(loaded, near_far_batch(model.observation_space))
    with th.no_grad():
        a = loaded.actor.logits_and_prior_log_probs(obs)
        b = model.policy.actor.logits_and_prior_log_probs(obs)
    assert all(th.equal(x, y) for x, y in zip(a, b, strict=True))
    plain = near_reference_pnn(
        priors, near_reference_prior=None
    ).policy._get_constructor_parameters()
    assert "near_reference_prior" not in plain and "near_reference_corridor" not in plain


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (dict(near_reference_prior=0), r"near_reference_prior=0 needs a reference_prior other"),
        (dict(near_reference_prior=2), r"near_reference_prior=2 is not allowed: expected None"),
        (dict(near_reference_prior=True), r"near_reference_prior=True is not allowed"),
        (dict(prior_kl_clearance=None), r"near_reference_prior=1 needs prior_kl_clearance"),
        (dict(near_reference_corridor=1.5), r"near_reference_corridor must be a fraction of d_L"),
        (
            dict(near_reference_prior=None, near_reference_corridor=0.9),
            r"near_reference_corridor=0.9 needs near_reference_prior",
        ),
    ],
)
def test_bad_combinations_are_refused_by_name(priors, kwargs, message):
    with pytest.raises(ValueError, match=message):
        near_reference_pnn(priors, **kwargs)
