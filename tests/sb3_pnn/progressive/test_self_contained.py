"""A trained PNN/SPNN model loads and predicts identically without its prior checkpoints."""

from __future__ import annotations

import shutil

import pytest
import torch as th
from progressive_helpers import ToyRovEnv, batch

from sb3_pnn import DiscreteSAC, ProgressivePolicy, SelectivePolicy


@pytest.mark.parametrize(
    "policy_class, names, extra",
    [
        (ProgressivePolicy, ["pf_dqn", "box_dqn"], {}),
        (SelectivePolicy, ["pf_dsac", "oa_dsac"], {"gate": "learned"}),
    ],
)
def test_save_load_without_prior_files(priors, tmp_path, policy_class, names, extra):
    paths = []
    for name in names:  # private copies, deleted before loading
        shutil.copy(priors[name], tmp_path / f"{name}.zip")
        paths.append(str(tmp_path / f"{name}.zip"))
    model = DiscreteSAC(
        policy_class,
        ToyRovEnv(),
        policy_kwargs=dict(priors=paths, net_arch=[16, 8], **extra),
        learning_starts=20,
        buffer_size=1000,
        batch_size=16,
        seed=0,
    )
    model.learn(60)
    model.save(tmp_path / "model.zip")
    for p in paths:
        (tmp_path / p).unlink()

    loaded = DiscreteSAC.load(tmp_path / "model.zip")
    assert type(loaded.policy) is policy_class
    assert "priors" not in loaded.policy_kwargs and len(loaded.policy_kwargs["prior_specs"]) == 2
    obs = batch(model.observation_space, 32, seed=5)
    a1, _ = model.predict(obs, deterministic=True)
    a2, _ = loaded.predict(obs, deterministic=True)
    assert (a1 == a2).all()
    t1, _ = model.policy.obs_to_tensor(obs)
    with th.no_grad():
        assert th.equal(model.actor(t1), loaded.actor(t1))
        for q1, q2 in zip(model.critic(t1), loaded.critic(t1), strict=True):
            assert th.equal(q1, q2)
    for k, v in model.policy.state_dict().items():
        assert th.equal(v, loaded.policy.state_dict()[k]), k
    loaded.set_env(ToyRovEnv())
    loaded.learn(40)  # training goes on from the loaded model
