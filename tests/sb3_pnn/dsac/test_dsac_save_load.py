"""save/load round trip: same predictions, optimizers, ent coef and replay buffer; resumes."""

import copy
import json
import zipfile
from pathlib import Path

import numpy as np
import torch as th

from sb3_pnn import DiscreteSAC


def train_small(device: str = "cpu", **kwargs) -> DiscreteSAC:
    model = DiscreteSAC(
        "MlpPolicy",
        "CartPole-v1",
        learning_starts=50,
        batch_size=16,
        buffer_size=2000,
        policy_kwargs=dict(net_arch=[16, 16]),
        seed=1,
        device=device,
        **kwargs,
    )
    model.learn(300)
    return model


def assert_same_optimizer(a: th.optim.Optimizer, b: th.optim.Optimizer) -> None:
    sa, sb = a.state_dict(), b.state_dict()
    assert sa["param_groups"] == sb["param_groups"]
    assert sa["state"].keys() == sb["state"].keys() and len(sa["state"]) > 0
    for key, state in sa["state"].items():
        for name, value in state.items():
            th.testing.assert_close(value, sb["state"][key][name], rtol=0, atol=0)


def test_round_trip_predicts_identically_and_resumes(tmp_path: Path) -> None:
    model = train_small()
    model.save(tmp_path / "dsac.zip")
    model.save_replay_buffer(tmp_path / "buffer.pkl")

    with zipfile.ZipFile(tmp_path / "dsac.zip") as archive:
        saved = json.loads(archive.read("data"))
    assert "_polyak_cache" not in saved  # a cache of tensors, not state to save

    loaded = DiscreteSAC.load(tmp_path / "dsac.zip", env=model.get_env(), device="cpu")
    loaded.load_replay_buffer(tmp_path / "buffer.pkl")

    obs = np.random.default_rng(0).normal(size=(64, 4)).astype(np.float32)
    np.testing.assert_array_equal(
        model.predict(obs, deterministic=True)[0], loaded.predict(obs, deterministic=True)[0]
    )
    for key, value in model.policy.state_dict().items():
        th.testing.assert_close(loaded.policy.state_dict()[key], value, rtol=0, atol=0)
    assert_same_optimizer(model.actor.optimizer, loaded.actor.optimizer)
    assert_same_optimizer(model.critic.optimizer, loaded.critic.optimizer)
    assert_same_optimizer(model.ent_coef_optimizer, loaded.ent_coef_optimizer)
    th.testing.assert_close(loaded.log_ent_coef, model.log_ent_coef, rtol=0, atol=0)
    assert loaded.log_ent_coef.requires_grad
    # An episodic train_freq finishes the episode, so a little over 300 steps
    assert loaded.num_timesteps == model.num_timesteps >= 300
    assert loaded._n_updates == model._n_updates > 0
    assert loaded.target_entropy == model.target_entropy
    assert loaded.replay_buffer.pos == model.replay_buffer.pos
    np.testing.assert_array_equal(
        loaded.replay_buffer.observations, model.replay_buffer.observations
    )
    np.testing.assert_array_equal(loaded.replay_buffer.actions, model.replay_buffer.actions)

    # Training resumes: counters go on, Adam's step count continues, alpha keeps learning
    n_updates = loaded._n_updates
    adam_step = loaded.actor.optimizer.state_dict()["state"][0]["step"].item()
    log_alpha = loaded.log_ent_coef.item()
    start = loaded.num_timesteps
    loaded.learn(200, reset_num_timesteps=False)
    assert loaded.num_timesteps >= start + 200
    assert loaded._n_updates > n_updates
    assert loaded.actor.optimizer.state_dict()["state"][0]["step"].item() > adam_step
    assert loaded.log_ent_coef.item() != log_alpha
    assert (
        loaded.replay_buffer.pos == (model.replay_buffer.pos + loaded.num_timesteps - start) % 2000
    )


def test_round_trip_with_fixed_ent_coef_and_without_env(tmp_path: Path) -> None:
    model = train_small(ent_coef=0.07, target_entropy_ratio=0.5, gradient_steps=3)
    model.save(tmp_path / "fixed.zip")
    loaded = DiscreteSAC.load(tmp_path / "fixed.zip", device="cpu")
    assert loaded.ent_coef_optimizer is None and loaded.log_ent_coef is None
    assert loaded.ent_coef_tensor.item() == np.float32(0.07)
    assert loaded.gradient_steps == 3 and loaded.target_entropy_ratio == 0.5
    obs = np.random.default_rng(1).normal(size=(32, 4)).astype(np.float32)
    np.testing.assert_array_equal(
        model.predict(obs, deterministic=True)[0], loaded.predict(obs, deterministic=True)[0]
    )


def test_polyak_update_averages_the_current_target_into_the_current_critic() -> None:
    model = train_small(tau=0.25)
    # A replaced target (as after policy surgery) is the one averaged from then on
    model.critic_target = model.policy.critic_target = copy.deepcopy(model.policy.critic_target)
    before = [p.detach().clone() for p in model.critic_target.parameters()]
    model.train(gradient_steps=1, batch_size=16)
    critic = list(model.critic.parameters())
    for old, new, online in zip(before, model.critic_target.parameters(), critic, strict=True):
        expected = old * 0.75 + online.detach() * 0.25
        th.testing.assert_close(new.detach(), expected, rtol=1e-6, atol=1e-7)
