"""DiscreteSAC as an SB3 citizen: Dict observations, several envs, callbacks, TensorBoard, hooks."""

from pathlib import Path
from typing import Any

import gymnasium as gym
import numpy as np
import pytest
from stable_baselines3.common.callbacks import CheckpointCallback, EvalCallback
from stable_baselines3.common.env_util import make_vec_env
from stable_baselines3.common.vec_env import SubprocVecEnv

from sb3_pnn import DiscreteSAC, DiscreteSACPolicy, MultiInputDiscreteSACPolicy


class DictObsEnv(gym.Env):
    """Tiny task with the rov_envs observation layout: reward 1 when the action matches the
    sign of path[0] (0 when negative, 2 when positive), 20 steps per episode."""

    def __init__(self) -> None:
        self.observation_space = gym.spaces.Dict(
            path=gym.spaces.Box(-1, 1, (2,), np.float32),
            sonar=gym.spaces.Box(0, 1, (9,), np.float32),
        )
        self.action_space = gym.spaces.Discrete(5)
        self._t = 0
        self._obs: dict[str, np.ndarray] = {}

    def _new_obs(self) -> dict[str, np.ndarray]:
        self._obs = self.observation_space.sample()
        return self._obs

    def reset(self, *, seed: int | None = None, options: dict | None = None):
        super().reset(seed=seed)
        self.observation_space.seed(seed)
        self._t = 0
        return self._new_obs(), {}

    def step(self, action: int):
        good = 2 if self._obs["path"][0] > 0 else 0
        reward = float(int(action) == good)
        self._t += 1
        truncated = self._t >= 20
        info: dict[str, Any] = {"is_success": True} if truncated else {}
        return self._new_obs(), reward, False, truncated, info


def test_dict_observations_with_multi_input_policy(tmp_path: Path) -> None:
    model = DiscreteSAC(
        "MultiInputPolicy",
        DictObsEnv(),
        buffer_size=1000,
        learning_starts=100,
        batch_size=32,
        policy_kwargs=dict(net_arch=[32]),
        seed=0,
        device="cpu",
    )
    assert isinstance(model.policy, MultiInputDiscreteSACPolicy)
    model.learn(400)
    obs = {"path": np.zeros((3, 2), np.float32), "sonar": np.ones((3, 9), np.float32)}
    actions, _ = model.predict(obs, deterministic=True)
    assert actions.shape == (3,) and set(actions.tolist()) <= set(range(5))
    model.save(tmp_path / "dict.zip")
    loaded = DiscreteSAC.load(tmp_path / "dict.zip", device="cpu")
    np.testing.assert_array_equal(loaded.predict(obs, deterministic=True)[0], actions)


def test_several_envs_with_the_episodic_default_schedule() -> None:
    env = make_vec_env("CartPole-v1", n_envs=3, seed=0)
    model = DiscreteSAC(
        "MlpPolicy",
        env,
        learning_starts=60,
        batch_size=32,
        policy_kwargs=dict(net_arch=[16]),
        seed=0,
    )
    model.learn(300)
    assert model.num_timesteps >= 300
    # 10 gradient steps per rollout, a rollout ending once an episode ends in any env
    assert model._n_updates > 0 and model._n_updates % 10 == 0
    actions, _ = model.predict(env.reset(), deterministic=False)
    assert actions.shape == (3,)


def test_subprocess_vec_env_with_step_schedule() -> None:
    env = make_vec_env(
        "CartPole-v1",
        n_envs=2,
        seed=0,
        vec_env_cls=SubprocVecEnv,
        vec_env_kwargs=dict(start_method="fork"),
    )
    try:
        model = DiscreteSAC(
            "MlpPolicy",
            env,
            learning_starts=50,
            batch_size=32,
            train_freq=4,
            gradient_steps=1,
            policy_kwargs=dict(net_arch=[16]),
        )
        model.learn(200)
        assert model._n_updates > 0
    finally:
        env.close()


def test_callbacks_progress_bar_and_tensorboard(tmp_path: Path) -> None:
    pytest.importorskip("tensorboard")
    from tensorboard.backend.event_processing.event_accumulator import EventAccumulator

    env = make_vec_env("CartPole-v1", n_envs=1, seed=0)
    eval_cb = EvalCallback(
        make_vec_env("CartPole-v1", n_envs=1, seed=1),
        eval_freq=100,
        n_eval_episodes=2,
        log_path=str(tmp_path / "eval"),
        best_model_save_path=str(tmp_path / "best"),
        verbose=0,
    )
    ckpt_cb = CheckpointCallback(
        save_freq=100, save_path=str(tmp_path / "ckpt"), save_replay_buffer=True
    )
    model = DiscreteSAC(
        "MlpPolicy",
        env,
        learning_starts=50,
        batch_size=32,
        policy_kwargs=dict(net_arch=[16]),
        tensorboard_log=str(tmp_path / "tb"),
        seed=0,
    )
    model.learn(250, callback=[eval_cb, ckpt_cb], log_interval=1, progress_bar=True)

    assert (tmp_path / "best" / "best_model.zip").exists()
    assert sorted(p.suffix for p in (tmp_path / "ckpt").iterdir()) == [
        ".pkl",
        ".pkl",
        ".zip",
        ".zip",
    ]
    run_dirs = list((tmp_path / "tb").iterdir())
    assert [d.name for d in run_dirs] == ["DiscreteSAC_1"]
    events = EventAccumulator(str(run_dirs[0]))
    events.Reload()
    tags = set(events.Tags()["scalars"])
    for key in (
        "train/actor_loss",
        "train/critic_loss",
        "train/ent_coef",
        "train/ent_coef_loss",
        "train/entropy",
        "train/learning_rate",
        "rollout/ep_rew_mean",
        "eval/mean_reward",
    ):
        assert key in tags, key
    entropies = [e.value for e in events.Scalars("train/entropy")]
    assert all(0.0 <= h <= np.log(2) + 1e-6 for h in entropies)


class HookedPolicy(DiscreteSACPolicy):
    """Uses the two optional hooks of the Learner API and a critic with frozen layers."""

    def __init__(self, *args, marker: int = 0, **kwargs) -> None:
        self.marker = marker
        super().__init__(*args, **kwargs)

    def make_critic(self, features_extractor=None):
        critic = super().make_critic(features_extractor)
        critic.q_networks[0][0].requires_grad_(False)
        return critic

    def extra_logs(self) -> dict[str, float]:
        return {"marker": float(self.marker)}

    def portable_policy_kwargs(self) -> dict[str, Any]:
        return {"net_arch": self.net_arch, "marker": self.marker + 1}


def test_learner_api_hooks_and_trainable_parameters_only() -> None:
    model = DiscreteSAC(
        HookedPolicy,
        "CartPole-v1",
        learning_starts=20,
        batch_size=16,
        policy_kwargs=dict(net_arch=[8], marker=5),
        seed=0,
    )
    assert model.policy_kwargs == {"net_arch": [8], "marker": 6}
    frozen = model.critic.q_networks[0][0].weight
    frozen_before = frozen.detach().clone()
    optimized = {id(p) for g in model.critic.optimizer.param_groups for p in g["params"]}
    assert id(frozen) not in optimized
    model.learn(100)
    np.testing.assert_array_equal(frozen.detach().numpy(), frozen_before.numpy())
    model.train(gradient_steps=1, batch_size=16)
    assert model.logger.name_to_value["train/marker"] == 5.0
