"""PNN (eq. 13): laterals matter, prior columns stay frozen bit for bit, no optimizer sees them."""

from __future__ import annotations

import copy

import pytest
import torch as th
import torch.nn.functional as F
from progressive_helpers import batch, toy_model
from stable_baselines3.common.preprocessing import preprocess_obs

from sb3_pnn import DiscreteSAC, ProgressivePolicy
from sb3_pnn.progressive.columns import FrozenColumn


def _model(priors, **kwargs):
    kw = dict(priors=[priors["pf_dqn"], priors["oa_dsac"]], net_arch=[32, 24])
    kw.update(kwargs)
    return toy_model(ProgressivePolicy, kw, gradient_steps=2)


def _new_column_alone(net, features):
    h = features
    for i, layer in enumerate(net.layers):
        h = layer(h)
        if i < len(net.layers) - 1:
            h = F.relu(h)
    return h


def test_laterals_change_the_output_and_zeroing_them_restores_the_plain_column(priors):
    model = _model(priors)
    policy = model.policy
    obs, _ = policy.obs_to_tensor(batch(policy.observation_space, 8))
    with th.no_grad():
        logits = policy.actor(obs)
        q = policy.critic(obs)
        saved = {k: v.clone() for k, v in policy.state_dict().items()}
        policy.actor.net.zero_laterals_()
        for q_net in policy.critic.q_networks:
            q_net.zero_laterals_()
        plain = policy.actor(obs)
        features = policy.actor.features_extractor(obs)
        assert not th.allclose(plain, logits)
        assert th.allclose(plain, _new_column_alone(policy.actor.net, features), atol=1e-6)
        assert not th.allclose(policy.critic(obs)[1], q[1])
        policy.load_state_dict(saved)
        assert th.equal(policy.actor(obs), logits)


def test_laterals_reach_every_layer_including_the_output(priors):
    net = _model(priors).policy.actor.net
    # layer 0 has none (input layer); hidden layer 1 and the output layer read both priors
    assert net.sources == [[None, None], [0, 0], [1, 1]]
    assert net.laterals["1_0"].in_features == 16 and net.laterals["1_1"].in_features == 8
    assert net.laterals["2_1"].out_features == 5


def _prior_buffers(policy):
    return {name: t.clone() for name, t in policy.state_dict().items() if ".priors." in name}


def test_priors_frozen_bit_for_bit_and_in_no_optimizer(priors):
    model = _model(priors)
    policy = model.policy
    before = _prior_buffers(policy)
    new_before = {n: p.detach().clone() for n, p in policy.named_parameters()}
    # 2 priors x 3 Linear layers x (W, b) in the actor, 2 critic and 2 target Q-networks
    assert len(before) == 12 * 5
    model.learn(200)
    after = _prior_buffers(policy)
    assert before.keys() == after.keys()
    for name in before:
        assert th.equal(before[name], after[name]), name
    changed = [n for n, p in policy.named_parameters() if not th.equal(p, new_before[n])]
    assert any(n.startswith("actor.net.layers") for n in changed)
    assert any(n.startswith("critic.q_networks") and "laterals" in n for n in changed)
    # Priors are buffers of FrozenColumn modules: no parameter of theirs exists to optimize
    frozen = [m for m in policy.modules() if isinstance(m, FrozenColumn)]
    assert len(frozen) == 1 * 2 + 2 * 2 * 2  # actor, critic and target: 2 priors each
    assert all(len(list(m.parameters())) == 0 for m in frozen)
    assert not any(t.requires_grad for m in frozen for t in m.buffers())
    optimized = {
        id(p)
        for opt in (policy.actor.optimizer, policy.critic.optimizer)
        for g in opt.param_groups
        for p in g["params"]
    }
    prior_tensors = {id(t) for m in frozen for t in m.buffers()}
    assert not optimized & prior_tensors
    trainable = {
        id(p) for p in [*policy.actor.parameters(), *policy.critic.parameters()] if p.requires_grad
    }
    assert optimized == trainable


def test_prior_columns_always_in_eval_mode(priors):
    policy = _model(priors).policy
    policy.set_training_mode(True)
    assert policy.actor.training
    assert all(not m.training for m in policy.modules() if isinstance(m, FrozenColumn))


def test_mode_switches_leave_the_flags_a_full_walk_would(priors):
    policy = _model(priors).policy
    modules = [*policy.actor.modules(), *policy.critic.modules()]
    for mode in (True, False, True, True, False):
        policy.set_training_mode(mode)
        switched = [m.training for m in modules]
        for m in modules:  # what SB3's recursive nn.Module.train(mode) leaves
            m.training = not mode
        policy.actor.train(mode)
        policy.critic.train(mode)
        assert switched == [m.training for m in modules]
        assert policy.training == mode
        assert not any(m.training for m in policy.critic_target.modules())
    # a frozen column's flag set by hand is put right by the next switch
    frozen = next(m for m in modules if isinstance(m, FrozenColumn))
    frozen.training = True
    policy.set_training_mode(True)
    assert not frozen.training
    # a deep copy switches its own modules (the remembered flags follow the copy)
    twin = copy.deepcopy(policy)
    twin.set_training_mode(False)
    assert not any(m.training for m in [*twin.actor.modules(), *twin.critic.modules()])
    assert policy.actor.training and twin.actor.net.layers[0].training is False


def test_fixed_lateral_scale_is_eq13_exactly(priors):
    policy = _model(priors, learn_lateral_scale=False).policy
    assert "lateral_scale" not in dict(policy.actor.net.named_parameters())
    assert th.equal(policy.actor.net.lateral_scale, th.ones(3, 2))


def test_critics_without_priors_are_plain_columns_and_survive_save_load(priors, tmp_path):
    model = _model(priors, critic_priors=False)
    policy = model.policy
    assert len(policy.actor.net.priors) == 2  # the actor still reads both priors
    obs, _ = policy.obs_to_tensor(batch(policy.observation_space, 8))
    with th.no_grad():
        features = policy.critic.features_extractor(obs)
        for q_net, q in zip(policy.critic.q_networks, policy.critic(obs), strict=True):
            assert len(q_net.priors) == 0 and len(q_net.laterals) == 0
            assert th.allclose(q, _new_column_alone(q_net, features), atol=1e-6)
    model.learn(60)
    model.save(tmp_path / "m.zip")
    loaded = DiscreteSAC.load(tmp_path / "m.zip")
    assert loaded.policy.critic_priors is False
    with th.no_grad():
        assert th.equal(loaded.policy.critic(obs)[0], policy.critic(obs)[0])
        assert th.equal(loaded.policy.actor(obs), policy.actor(obs))


def test_critic_priors_must_be_a_bool(priors):
    with pytest.raises(ValueError, match="critic_priors must be True or False, got 'false'"):
        _model(priors, critic_priors="false")  # a YAML string would otherwise read as True


def _eq13_written_out(net, x, hidden, weights, own_weight):
    """Eq. 13 / 15 term by term, every lateral multiplied by its scale alpha and weight c_j."""
    h, last = x, len(net.layers) - 1
    for i, layer in enumerate(net.layers):
        # own path: nn.Linear when its weight is 1 (one fused op), else tau * W h + b
        z = layer(h) if own_weight == 1.0 else own_weight * F.linear(h, layer.weight) + layer.bias
        for j, src in enumerate(net.sources[i]):
            if src is not None:
                lat = net.lateral_scale[i, j] * net.laterals[f"{i}_{j}"](hidden[j][src])
                z = z + (lat if weights is None else weights[:, j : j + 1] * lat)
        h = net.activation(z) if i < last else z
    return h


@pytest.mark.parametrize("scale", [1.0, 0.5])
@pytest.mark.parametrize("own_weight", [1.0, 0.5])
def test_forward_is_eq13_bit_for_bit(priors, scale, own_weight):
    """The forward pass skips a fixed alpha of exactly 1 and plans its laterals once; its output
    is the written-out formula's, bit for bit, with and without lateral weights c_j(s)."""
    policy = _model(priors, learn_lateral_scale=False, lateral_scale_init=scale).policy
    net = policy.actor.net
    obs, _ = policy.obs_to_tensor(batch(policy.observation_space, 8))
    pre = preprocess_obs(obs, policy.observation_space)
    with th.no_grad():
        x = policy.actor.features_extractor(pre)
        hidden = net.prior_hidden([feed(pre) for feed in policy.actor.feeds])
        weights = th.rand(8, 2, generator=th.Generator().manual_seed(0))
        for c in (None, weights):
            expected = _eq13_written_out(net, x, hidden, c, own_weight)
            assert th.equal(net(x, hidden, c, own_weight), expected)
