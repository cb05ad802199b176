"""Target critics move only by Polyak averaging: theta_bar <- (1 - tau) theta_bar + tau theta."""

import torch as th
from stable_baselines3.common.logger import configure

from sb3_pnn import DiscreteSAC


def make_model(**kwargs) -> DiscreteSAC:
    model = DiscreteSAC(
        "MlpPolicy",
        "CartPole-v1",
        learning_starts=0,
        batch_size=8,
        tau=0.1,
        policy_kwargs=dict(net_arch=[8]),
        seed=0,
        device="cpu",
        **kwargs,
    )
    model.set_logger(configure(None, []))
    # Some transitions to sample from
    model.learn(40)
    return model


def snapshot(module: th.nn.Module) -> dict[str, th.Tensor]:
    return {k: v.detach().clone() for k, v in module.state_dict().items()}


def test_target_is_polyak_average_after_each_step() -> None:
    model = make_model()
    target_before = snapshot(model.critic_target)
    critic_before = snapshot(model.critic)
    model.train(gradient_steps=1, batch_size=8)
    critic_after = snapshot(model.critic)
    target_after = snapshot(model.critic_target)
    assert any(not th.equal(critic_before[k], critic_after[k]) for k in critic_after)
    for key, value in target_after.items():
        expected = (1 - 0.1) * target_before[key] + 0.1 * critic_after[key]
        th.testing.assert_close(value, expected, rtol=0, atol=1e-7)
    # The target has no optimizer and no gradient
    assert all(not p.requires_grad for p in model.critic_target.parameters())
    assert all(p.grad is None for p in model.critic_target.parameters())
    optimized = {id(p) for group in model.critic.optimizer.param_groups for p in group["params"]}
    optimized |= {id(p) for group in model.actor.optimizer.param_groups for p in group["params"]}
    assert not optimized & {id(p) for p in model.critic_target.parameters()}


def test_target_update_interval_counts_updates_across_train_calls() -> None:
    model = make_model(target_update_interval=2)
    n_before = model._n_updates
    model._n_updates = 0  # an odd count after the next step: no target update
    start = snapshot(model.critic_target)
    model.train(gradient_steps=1, batch_size=8)
    assert all(th.equal(start[k], v) for k, v in snapshot(model.critic_target).items())
    # The second step (in a separate train() call) is the 2nd update: Polyak step
    model.train(gradient_steps=1, batch_size=8)
    critic_after = snapshot(model.critic)
    for key, value in snapshot(model.critic_target).items():
        th.testing.assert_close(
            value, 0.9 * start[key] + 0.1 * critic_after[key], rtol=0, atol=1e-7
        )
    assert model._n_updates == 2
    assert n_before > 0
