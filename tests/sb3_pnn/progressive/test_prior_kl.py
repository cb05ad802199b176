"""``prior_kl``: the actor's loss adds beta * KL(pi || pi_0), pi_0 the priors' own policy.

pi_0 is the gate-selected prior's policy for the SPNN (per sample) and the prior's for a PNN;
the term is exactly beta times the KL divergence; it pulls a trained policy toward pi_0; it is
saved with the model; beta = 0 takes the plain actor pass.
"""

from __future__ import annotations

import pytest
import torch as th
import torch.nn.functional as F
from progressive_helpers import (
    NEAR_DISTANCES,
    actor_loss_inputs,
    near_far_batch,
    obs_tensor,
    toy_model,
)

from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy
from sb3_pnn.dsac.dsac import discrete_sac_losses
from sb3_pnn.progressive.selective_policy import DEFAULT_PRIOR_KL


def _spnn(paths, **kwargs):
    kw = dict(priors=[paths["pf_dsac"], paths["oa_dsac"]], net_arch=[16, 16])
    kw.update(kwargs)
    return toy_model(SelectivePolicy, kw)


def test_reference_is_the_selected_priors_policy(priors):
    model = _spnn(priors, start_as_prior=False)
    policy = model.policy
    pf = DiscreteSAC.load(priors["pf_dsac"], device="cpu").policy
    oa = DiscreteSAC.load(priors["oa_dsac"], device="cpu").policy
    obs = near_far_batch(model.observation_space)
    near = th.as_tensor(NEAR_DISTANCES <= 12.5)
    logits, reference = policy.actor.logits_and_prior_log_probs(obs_tensor(policy, obs))
    with th.no_grad():
        assert th.equal(logits, policy.actor(obs_tensor(policy, obs)))
        expected = th.where(
            near[:, None],
            F.log_softmax(oa.actor(obs_tensor(oa, obs)), dim=1),
            F.log_softmax(pf.actor(obs_tensor(pf, obs, ("path",))), dim=1),
        )
    assert th.allclose(reference, expected, atol=1e-6)
    assert logits.requires_grad and not reference.requires_grad


def test_pnn_reference_is_its_priors_policy(priors):
    model = toy_model(ProgressivePolicy, dict(priors=[priors["pf_dsac"]], net_arch=[16, 16]))
    pf = DiscreteSAC.load(priors["pf_dsac"], device="cpu").policy
    obs = near_far_batch(model.observation_space)
    _, reference = model.policy.actor.logits_and_prior_log_probs(obs_tensor(model.policy, obs))
    with th.no_grad():
        expected = F.log_softmax(pf.actor(obs_tensor(pf, obs, ("path",))), dim=1)
    assert th.allclose(reference, expected, atol=1e-6)


def test_the_term_is_beta_times_the_kl_divergence():
    logits, other, q, common = actor_loss_inputs()
    reference = F.log_softmax(other, dim=1)
    plain = discrete_sac_losses(logits, q, **common).actor_loss
    with_kl = discrete_sac_losses(
        logits, q, **common, prior_log_probs=reference, prior_kl=3.0
    ).actor_loss
    log_pi = F.log_softmax(logits, dim=1)
    kl = (log_pi.exp() * (log_pi - reference)).sum(dim=1).mean()
    assert with_kl.item() == pytest.approx(plain.item() + 3.0 * kl.item(), rel=1e-6)
    off = discrete_sac_losses(logits, q, **common, prior_log_probs=reference, prior_kl=0.0)
    assert th.equal(off.actor_loss, plain)


def _kl_to_reference(model, obs):
    policy = model.policy
    with th.no_grad():
        logits, reference = policy.actor.logits_and_prior_log_probs(obs_tensor(policy, obs))
        log_pi = F.log_softmax(logits, dim=1)
        return float((log_pi.exp() * (log_pi - reference)).sum(dim=1).mean())


def test_it_pulls_the_policy_toward_the_priors(priors):
    """The toy task pays for action 2 only; the priors do not prefer it. A strong KL term keeps
    the trained policy closer to the priors than the same run without it."""
    obs = near_far_batch(_spnn(priors).observation_space)
    kls = {}
    for beta in (0.0, 10.0):
        model = _spnn(priors, start_as_prior=True, prior_kl=beta)
        model.learn(400)
        kls[beta] = _kl_to_reference(model, obs)
    assert kls[10.0] < 0.5 * kls[0.0], kls


def test_zero_takes_the_plain_path_and_the_weight_is_saved(priors, tmp_path, monkeypatch):
    """beta = 0 (the paper) trains through the plain actor pass: the reference policy is
    never computed, so the updates are the same operations as before the option existed."""
    assert _spnn(priors).policy.prior_kl == DEFAULT_PRIOR_KL == 1.0  # the recommended set-up
    model = _spnn(priors, prior_kl=0.0)
    assert model.policy.prior_kl == 0.0

    def refuse(*args, **kwargs):
        raise AssertionError("the reference policy was computed with prior_kl = 0")

    monkeypatch.setattr(model.policy.actor, "logits_and_prior_log_probs", refuse)
    model.learn(60)
    model = _spnn(priors, prior_kl=2.5)
    model.save(tmp_path / "spnn.zip")
    assert DiscreteSAC.load(tmp_path / "spnn.zip", device="cpu").policy.prior_kl == 2.5
    with pytest.raises(ValueError, match="prior_kl must be a finite number >= 0, got -1"):
        _spnn(priors, prior_kl=-1)


def _pnn(paths, **kwargs):
    kw = dict(priors=[paths["pf_dsac"]], net_arch=[16, 16], prior_kl=1.0)
    kw.update(kwargs)
    return toy_model(ProgressivePolicy, kw)


def test_clearance_weighs_only_the_samples_with_no_obstacle_near(priors, tmp_path):
    """prior_kl_clearance = c: the KL term's weight is 1 where the nearest obstacle is farther
    than c metres, 0 where it is nearer; the term is beta * mean(w * KL); the clearance is saved
    with the model; without it every sample weighs 1 (and the SPNN never names it)."""
    model = _pnn(priors, prior_kl_clearance=12.5)
    obs = near_far_batch(model.observation_space)
    weights = model.policy.actor.prior_kl_weights(obs_tensor(model.policy, obs))
    assert weights.tolist() == (NEAR_DISTANCES > 12.5).astype(float).tolist()

    gen = th.Generator().manual_seed(1)
    logits = th.randn(len(NEAR_DISTANCES), 5, generator=gen)
    reference = F.log_softmax(th.randn(len(NEAR_DISTANCES), 5, generator=gen), dim=1)
    q = (th.zeros_like(logits), th.zeros_like(logits))
    common = dict(target_q_values=th.zeros(5, 1), actions=th.zeros(5, 1), ent_coef=0.2)
    plain = discrete_sac_losses(logits, q, **common).actor_loss
    weighted = discrete_sac_losses(
        logits, q, **common, prior_log_probs=reference, prior_kl=2.0, prior_kl_weights=weights
    ).actor_loss
    log_pi = F.log_softmax(logits, dim=1)
    per_sample = (log_pi.exp() * (log_pi - reference)).sum(dim=1)
    expected = plain + 2.0 * (per_sample * weights).mean()
    assert weighted.item() == pytest.approx(expected.item(), rel=1e-6)

    model.learn(60)  # the weighted term trains
    model.save(tmp_path / "pnn.zip")
    loaded = DiscreteSAC.load(tmp_path / "pnn.zip", device="cpu").policy
    assert loaded.prior_kl_clearance == 12.5
    assert th.equal(loaded.actor.prior_kl_weights(obs_tensor(loaded, obs)), weights)
    assert _pnn(priors).policy.actor.prior_kl_weights(obs_tensor(model.policy, obs)) is None
    assert "prior_kl_clearance" not in _spnn(priors).policy._get_constructor_parameters()


@pytest.mark.parametrize("bad", [0.0, -3.0, float("nan"), "far"])
def test_bad_clearance_is_refused(priors, bad):
    with pytest.raises(ValueError, match=r"prior_kl_clearance must be a distance > 0"):
        _pnn(priors, prior_kl_clearance=bad)


def test_clearance_needs_a_sonar_observation():
    """The clearance reads the nearest obstacle from the ``sonar`` key; an observation without
    one is refused by name before any network is built."""
    from gymnasium import spaces

    from sb3_pnn.progressive.progressive_policy import _checked_clearance

    box = spaces.Box(-1.0, 1.0, (3,))
    with pytest.raises(ValueError, match=r"prior_kl_clearance=12.5 reads .*'sonar'.*lacks"):
        _checked_clearance(12.5, box)
    with pytest.raises(ValueError, match=r"lacks"):
        _checked_clearance(12.5, spaces.Dict({"path": box}))
    assert _checked_clearance(None, box) is None
    assert _checked_clearance(8, spaces.Dict({"sonar": box})) == 8.0
