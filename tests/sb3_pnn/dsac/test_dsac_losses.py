"""The three discrete-SAC losses against a numpy computation written from the formulas.

A tiny network (one hidden layer of 3 units) and a fixed batch of 4 transitions: the numpy
side runs the networks from their weights, computes the Christodoulou (2019) target, critic,
actor and entropy losses, and compares them with what ``DiscreteSAC.train()`` logs for one
gradient step on that batch.
"""

import math

import numpy as np
import pytest
import torch as th
from stable_baselines3.common.logger import configure
from stable_baselines3.common.type_aliases import ReplayBufferSamples

from sb3_pnn import DiscreteSAC
from sb3_pnn.dsac.dsac import discrete_sac_losses, soft_td_target

GAMMA = 0.9
ENT_INIT = 0.3
RATIO = 0.7


def np_mlp(
    state_dict: dict, prefix: str, x: np.ndarray, hidden: tuple[str, ...], out: str
) -> np.ndarray:
    for name in hidden:
        w = state_dict[f"{prefix}{name}.weight"].numpy().astype(np.float64)
        b = state_dict[f"{prefix}{name}.bias"].numpy().astype(np.float64)
        x = np.maximum(x @ w.T + b, 0.0)
    w = state_dict[f"{prefix}{out}.weight"].numpy().astype(np.float64)
    b = state_dict[f"{prefix}{out}.bias"].numpy().astype(np.float64)
    return x @ w.T + b


def np_log_softmax(x: np.ndarray) -> np.ndarray:
    shifted = x - x.max(axis=1, keepdims=True)
    return shifted - np.log(np.exp(shifted).sum(axis=1, keepdims=True))


def fixed_batch() -> ReplayBufferSamples:
    rng = np.random.default_rng(123)
    obs = rng.normal(size=(4, 4)).astype(np.float32)
    next_obs = rng.normal(size=(4, 4)).astype(np.float32)
    return ReplayBufferSamples(
        observations=th.as_tensor(obs),
        actions=th.tensor([[0], [1], [1], [0]], dtype=th.int64),
        next_observations=th.as_tensor(next_obs),
        dones=th.tensor([[0.0], [0.0], [1.0], [0.0]]),
        rewards=th.tensor([[1.0], [0.5], [-1.0], [2.0]]),
    )


def numpy_losses(state_dict: dict, batch: ReplayBufferSamples, alpha: float) -> dict[str, float]:
    """Independent numpy version of the discrete SAC losses (Christodoulou 2019)."""
    obs = batch.observations.numpy().astype(np.float64)
    next_obs = batch.next_observations.numpy().astype(np.float64)
    actions = batch.actions.numpy().reshape(-1)
    rewards = batch.rewards.numpy().reshape(-1).astype(np.float64)
    dones = batch.dones.numpy().reshape(-1).astype(np.float64)
    rows = np.arange(len(actions))

    def actor(x):
        return np_mlp(state_dict, "actor.", x, ("latent_pi.0",), "action_logits")

    def critic(prefix, i, x):
        return np_mlp(state_dict, f"{prefix}.q_networks.{i}.", x, ("0",), "2")

    # Target: y = r + gamma (1 - d) sum_a' pi(a'|s') [min_i Qbar_i(s', a') - alpha log pi(a'|s')]
    next_logp = np_log_softmax(actor(next_obs))
    next_min_q = np.minimum(
        critic("critic_target", 0, next_obs), critic("critic_target", 1, next_obs)
    )
    next_v = (np.exp(next_logp) * (next_min_q - alpha * next_logp)).sum(axis=1)
    y = rewards + GAMMA * (1.0 - dones) * next_v

    q1, q2 = critic("critic", 0, obs), critic("critic", 1, obs)
    critic_loss = 0.5 * (
        np.mean((q1[rows, actions] - y) ** 2) + np.mean((q2[rows, actions] - y) ** 2)
    )

    logp = np_log_softmax(actor(obs))
    p = np.exp(logp)
    actor_loss = np.mean((p * (alpha * logp - np.minimum(q1, q2))).sum(axis=1))

    entropy = np.mean(-(p * logp).sum(axis=1))
    target_entropy = RATIO * math.log(2)
    ent_coef_loss = -math.log(alpha) * (-entropy + target_entropy)
    return dict(
        critic_loss=critic_loss,
        actor_loss=actor_loss,
        ent_coef_loss=ent_coef_loss,
        entropy=entropy,
        ent_coef=alpha,
    )


@pytest.fixture()
def tiny_model() -> DiscreteSAC:
    model = DiscreteSAC(
        "MlpPolicy",
        "CartPole-v1",
        gamma=GAMMA,
        ent_coef=f"auto_{ENT_INIT}",
        target_entropy_ratio=RATIO,
        policy_kwargs=dict(net_arch=[3]),
        seed=0,
        device="cpu",
    )
    # The target must differ from the critic for the test to see which one is used
    with th.no_grad():
        for param in model.critic_target.parameters():
            param.add_(0.1 * th.randn_like(param))
    model.set_logger(configure(None, []))
    return model


def test_train_step_logs_hand_computed_losses(tiny_model: DiscreteSAC) -> None:
    model = tiny_model
    batch = fixed_batch()
    expected = numpy_losses(
        {k: v.clone() for k, v in model.policy.state_dict().items()}, batch, ENT_INIT
    )
    model.replay_buffer.sample = lambda batch_size, env=None: batch  # type: ignore[method-assign]
    model.train(gradient_steps=1, batch_size=4)
    logged = model.logger.name_to_value
    for key, value in expected.items():
        assert logged[f"train/{key}"] == pytest.approx(value, rel=1e-5, abs=1e-6), key


def test_loss_functions_match_numpy(tiny_model: DiscreteSAC) -> None:
    model = tiny_model
    batch = fixed_batch()
    expected = numpy_losses(model.policy.state_dict(), batch, 0.5)
    log_alpha = th.tensor([math.log(0.5)], requires_grad=True)
    with th.no_grad():
        target = soft_td_target(
            model.actor(batch.next_observations),
            model.critic_target(batch.next_observations),
            batch.rewards,
            batch.dones,
            GAMMA,
            0.5,
        )
    losses = discrete_sac_losses(
        model.actor(batch.observations),
        model.critic(batch.observations),
        target,
        batch.actions,
        ent_coef=0.5,
        log_ent_coef=log_alpha,
        target_entropy=RATIO * math.log(2),
    )
    assert losses.critic_loss.item() == pytest.approx(expected["critic_loss"], rel=1e-5)
    assert losses.actor_loss.item() == pytest.approx(expected["actor_loss"], rel=1e-5)
    assert losses.ent_coef_loss.item() == pytest.approx(expected["ent_coef_loss"], rel=1e-5)
    assert losses.entropy.item() == pytest.approx(expected["entropy"], rel=1e-5)

    # Gradients flow where they should: the actor loss does not reach the critics,
    # the entropy loss only reaches log(alpha)
    losses.actor_loss.backward()
    assert all(p.grad is None for p in model.critic.parameters())
    assert all(p.grad is not None for p in model.actor.parameters())
    losses.ent_coef_loss.backward()
    assert log_alpha.grad is not None
    # d J_alpha / d log(alpha) = E[H] - H_target
    assert log_alpha.grad.item() == pytest.approx(
        expected["entropy"] - RATIO * math.log(2), rel=1e-5
    )


def test_fixed_ent_coef_has_no_entropy_loss() -> None:
    model = DiscreteSAC(
        "MlpPolicy", "CartPole-v1", ent_coef=0.05, policy_kwargs=dict(net_arch=[3]), device="cpu"
    )
    batch = fixed_batch()
    expected = numpy_losses(model.policy.state_dict(), batch, 0.05)
    model.gamma = GAMMA
    model.set_logger(configure(None, []))
    model.replay_buffer.sample = lambda batch_size, env=None: batch  # type: ignore[method-assign]
    model.train(gradient_steps=1, batch_size=4)
    logged = model.logger.name_to_value
    assert "train/ent_coef_loss" not in logged
    assert logged["train/ent_coef"] == pytest.approx(0.05)
    assert logged["train/critic_loss"] == pytest.approx(expected["critic_loss"], rel=1e-5)
    assert logged["train/actor_loss"] == pytest.approx(expected["actor_loss"], rel=1e-5)
