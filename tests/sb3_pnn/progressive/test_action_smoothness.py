"""``action_smoothness``: the actor's loss adds lambda * KL(pi(.|s) || pi(.|s')) over replayed
transitions (CAPS's temporal term for a categorical policy).

The term is exactly lambda times that divergence; it makes a trained policy change less between
consecutive states; it is saved with the model and named only when on; 0 takes the plain pass;
with n-step returns it reads the one-step successor that the Dict buffer samples beside s_t+n.
"""

from __future__ import annotations

import numpy as np
import pytest
import torch as th
import torch.nn.functional as F
from progressive_helpers import actor_loss_inputs, toy_model
from stable_baselines3.common.buffers import DictReplayBuffer

from sb3_pnn import DiscreteSAC, SelectivePolicy
from sb3_pnn.common.buffers import DictNStepReplayBuffer
from sb3_pnn.dsac.dsac import discrete_sac_losses


def _spnn(paths, n_steps: int = 1, replay_buffer_class=None, **kwargs):
    kw = dict(priors=[paths["pf_dsac"], paths["oa_dsac"]], net_arch=[16, 16])
    kw.update(kwargs)
    return toy_model(SelectivePolicy, kw, n_steps=n_steps, replay_buffer_class=replay_buffer_class)


def test_the_term_is_lambda_times_the_kl_to_the_next_states_policy():
    logits, next_logits, q, common = actor_loss_inputs()
    plain = discrete_sac_losses(logits, q, **common).actor_loss
    smooth = discrete_sac_losses(
        logits, q, **common, next_logits=next_logits, action_smoothness=2.0
    ).actor_loss
    p, p_next = F.softmax(logits, dim=1).numpy(), F.softmax(next_logits, dim=1).numpy()
    kl = float(np.mean(np.sum(p * (np.log(p) - np.log(p_next)), axis=1)))
    assert smooth.item() == pytest.approx(plain.item() + 2.0 * kl, rel=1e-5)
    same = discrete_sac_losses(logits, q, **common, next_logits=logits, action_smoothness=2.0)
    assert same.actor_loss.item() == pytest.approx(plain.item(), abs=1e-6)  # KL(p || p) = 0
    off = discrete_sac_losses(logits, q, **common, next_logits=next_logits, action_smoothness=0)
    assert th.equal(off.actor_loss, plain)


def test_the_gradient_reaches_both_states_logits():
    logits = th.randn(4, 5, requires_grad=True)
    next_logits = th.randn(4, 5, requires_grad=True)
    q = (th.zeros(4, 5), th.zeros(4, 5))
    losses = discrete_sac_losses(
        logits, q, th.zeros(4, 1), th.zeros(4, 1), 0.0,
        next_logits=next_logits, action_smoothness=1.0,
    )  # fmt: skip
    losses.actor_loss.backward()
    assert logits.grad.abs().sum() > 0 and next_logits.grad.abs().sum() > 0


def _mean_step_change(model, n: int = 200) -> float:
    """Mean total-variation distance between pi(.|s) and pi(.|s') over replayed transitions."""
    data = model.replay_buffer.sample(n)
    with th.no_grad():
        p = F.softmax(model.actor(data.observations), dim=1)
        p_next = F.softmax(model.actor(data.next_observations), dim=1)
    return float(0.5 * (p - p_next).abs().sum(dim=1).mean())


def test_it_makes_the_policy_change_less_between_consecutive_states(priors):
    """The same run with a strong term changes its action distribution less from one state to
    the next (on the replayed transitions) than without it."""
    change = {}
    for weight in (0.0, 50.0):
        model = _spnn(priors, start_as_prior=False, action_smoothness=weight)
        model.learn(400)
        change[weight] = _mean_step_change(model)
    assert change[50.0] < 0.5 * change[0.0], change


def test_zero_takes_the_plain_path_and_the_weight_is_saved(priors, tmp_path):
    model = _spnn(priors)
    assert model.policy.action_smoothness == 0.0
    assert "action_smoothness" not in model.policy_kwargs  # saved models before it: same kwargs
    model = _spnn(priors, action_smoothness=1.5)
    model.learn(60)
    model.save(tmp_path / "spnn.zip")
    loaded = DiscreteSAC.load(tmp_path / "spnn.zip", device="cpu")
    assert loaded.policy.action_smoothness == 1.5
    assert loaded.policy_kwargs["action_smoothness"] == 1.5


def test_bad_values_are_refused(priors):
    with pytest.raises(ValueError, match="action_smoothness must be a finite number >= 0, got -1"):
        _spnn(priors, action_smoothness=-1)


def test_with_n_step_returns_the_term_reads_the_one_step_successor(priors):
    """With n-step returns the sampled s' is s_t+n; the term compares pi(.|s_t) with
    pi(.|s_t+1), which the Dict n-step buffer then samples beside it (the stored successor)."""
    model = _spnn(priors, action_smoothness=1.0, n_steps=3)
    model.learn(80)
    buffer = model.replay_buffer
    assert isinstance(buffer, DictNStepReplayBuffer) and buffer.step_successors
    rows = np.arange(0, 40, 2)  # one env: the sampled env index is always 0
    data = buffer._get_samples(rows)
    one_step = DictReplayBuffer._get_samples(buffer, rows)
    for key, value in data.step_next_observations.items():
        assert th.equal(value, one_step.next_observations[key])
    assert any(
        not th.equal(data.next_observations[k], data.step_next_observations[k])
        for k in data.next_observations
    )
    refused = pytest.raises(
        ValueError, match=r"action_smoothness=1.0 .* DictReplayBuffer with n_st"
    )
    with refused, pytest.warns(UserWarning, match="n_steps=3. is ignored"):
        _spnn(priors, action_smoothness=1.0, n_steps=3, replay_buffer_class=DictReplayBuffer)
