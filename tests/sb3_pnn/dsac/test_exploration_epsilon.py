"""``exploration_epsilon``: training actions replaced by uniform draws with probability epsilon.

The share of replaced actions matches epsilon, nothing changes at 0 or in ``predict``, the value
is saved, a checkpoint from before the option trains without it, and a bad value is refused.
"""

from __future__ import annotations

import gymnasium as gym
import numpy as np
import pytest

from sb3_pnn import DiscreteSAC


def _model(epsilon: float, **kwargs) -> DiscreteSAC:
    return DiscreteSAC(
        "MlpPolicy",
        gym.make("CartPole-v1"),
        exploration_epsilon=epsilon,
        learning_starts=0,
        gradient_steps=0,
        buffer_size=5000,
        policy_kwargs={"net_arch": [8]},
        seed=0,
        **kwargs,
    )


@pytest.mark.parametrize("epsilon", [0.0, 0.5])
def test_the_share_of_uniform_actions_is_epsilon(epsilon, monkeypatch):
    """With a policy that always picks action 0, action 1 appears on epsilon / 2 of the steps
    (a uniform draw over two actions)."""
    model = _model(epsilon)
    monkeypatch.setattr(model, "predict", lambda obs, **kw: (np.zeros(1, dtype=np.int64), None))
    model.learn(2000)
    actions = model.replay_buffer.actions[: model.replay_buffer.pos].ravel()
    assert actions.mean() == pytest.approx(epsilon / 2, abs=0.04)


def test_predict_is_unchanged_and_the_value_is_saved(tmp_path):
    model = _model(0.3)
    obs = np.zeros(4, dtype=np.float32)
    before = [model.predict(obs, deterministic=True)[0] for _ in range(5)]
    assert len({int(a) for a in before}) == 1  # no draws in predict
    model.save(tmp_path / "m.zip")
    assert DiscreteSAC.load(tmp_path / "m.zip", device="cpu").exploration_epsilon == 0.3


def test_a_checkpoint_from_before_the_option_reads_zero():
    meta = {"version": 2, "hyperparameters": {"n_steps": 1}}
    assert DiscreteSAC.upgrade_checkpoint(meta)["hyperparameters"]["exploration_epsilon"] == 0.0


@pytest.mark.parametrize("bad", [-0.1, 1.0, True, "0.1"])
def test_bad_values_are_refused(bad):
    with pytest.raises(ValueError, match=f"exploration_epsilon must be in \\[0, 1\\), got {bad!r}"):
        _model(bad)
